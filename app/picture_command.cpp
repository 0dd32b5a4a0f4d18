#include "picture_command.h"

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cdbench/core/error.h"
#include "cdbench/geometry/frame_source.h"
#include "cdbench/narrow/contacts.h"
#include "exit_codes.h"
#include "number_checks.h"
#include "harness/picture/frame_picture.h"
#include "harness/picture/png_writer.h"
#include "output_path.h"
#include "path_checks.h"
#include "harness/measure/query_pairs.h"

namespace cdb {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

CLI::App* add_picture_command(CLI::App& app, CommonOptions& o, PictureOptions& p) {
  auto* picture = app.add_subcommand(
      "picture", "draw one frame as a PNG, the triangles in its pairs red-orange");
  picture
      ->add_option("--pipeline", p.pipeline,
                   "the pipeline whose pairs are marked: one of " + pipeline_list() +
                       "; the default is exact and takes seconds on the host for a million triangles")
      ->group(kPipelineGroup)
      ->capture_default_str();
  add_common(picture, o);
  // A picture runs its pipeline on one frame, --frame K (and the one before it for swept
  // boxes): the options of a range of frames and of what a pipeline does over it do not apply.
  for (const char* name : {"--frames", "--front-cycle", "--rebuild-every", "--refit-every"})
    picture->remove_option(picture->get_option(name));
  picture->add_option("--frame", p.frame, "the frame to draw, 0-based")->group(kSceneGroup)->capture_default_str();
  picture->add_option("--out", p.out, "the PNG file to write (replaced when it exists)")
      ->check(non_empty_path())
      ->group(kOutputGroup)
      ->capture_default_str();
  picture
      ->add_option("--view", p.view,
                   "where the picture looks from: x, y or z (from that axis's positive side; y from above) or iso "
                   "(from the +x +y +z corner); orthographic, the scene fitted into the picture")
      ->check(CLI::IsMember({"x", "y", "z", "iso"}))
      ->group(kOutputGroup)
      ->capture_default_str();
  picture
      ->add_option("--mark", p.mark,
                   "what is marked: pairs (the triangles in the pipeline's pairs) or contacts (those of its pairs "
                   "whose triangles lie within --contact-distance and share no vertex, by the exact narrow phase)")
      ->check(CLI::IsMember({"pairs", "contacts"}))
      ->group(kOutputGroup)
      ->capture_default_str();
  picture
      ->add_option("--contact-distance", p.contact_distance,
                   "with --mark contacts: how close two triangles are to count as in contact (0: touching or "
                   "intersecting); the pairs come from boxes grown by --box-margin, so give at least this")
      ->check(finite_at_least(0))
      ->group(kOutputGroup)
      ->capture_default_str();
  picture->add_option("--size", p.size, "the picture's width and height in pixels")
      ->check(CLI::Range(16u, 16384u))
      ->group(kOutputGroup)
      ->capture_default_str();
  return picture;
}

int picture_command(const CommonOptions& o, const PictureOptions& p) {
  const auto start = std::chrono::steady_clock::now();
  const std::string device = resolve_device(o.device);
  std::unique_ptr<Pipeline> pipeline = std::move(make_pipelines(o, {p.pipeline}, device).front());
  const PictureView view = parse_picture_view(p.view);
  // Before the scene loads; an existing file is replaced: a picture is made again in seconds.
  check_replaced_output(p.out, "frame.png");

  Scene scene = load_scene(o);
  const Topology& topo = scene.source->topology();
  const uint32_t frames = scene.source->num_frames();
  if (p.frame >= frames)
    fail_usage("--frame " + std::to_string(p.frame) + ": scene " + scene.name + " has " + std::to_string(frames) +
               " frame" + (frames == 1 ? "" : "s") + " (0 to " + std::to_string(frames - 1) + ")");
  // Swept boxes span the interval from the frame before (the first frame's are its own),
  // read first: a simulated scene steps forward from it.
  std::vector<vec3d> previous, positions;
  if (o.config.boxes.swept && p.frame > 0) scene.source->positions(p.frame - 1, previous);
  scene.source->positions(p.frame, positions);
  const double load_s = seconds_since(start);

  const auto pairs_start = std::chrono::steady_clock::now();
  pipeline->set_topology(topo);
  if (!previous.empty()) pipeline->run_frame(previous);
  pipeline->run_frame(positions);
  const std::vector<PrimPair> pairs = pipeline->sorted_pairs();
  std::vector<PrimPair> contacts;
  if (p.mark == "contacts") {
    std::vector<vec3f> corners;
    round_to_float(positions, corners);
    contacts = contacts_apart_from_neighbours(topo.faces, corners, pairs, p.contact_distance);
  }
  const std::vector<uint8_t> marked = faces_in_pairs(p.mark == "contacts" ? contacts : pairs, topo.faces.size());
  const double pairs_s = seconds_since(pairs_start);

  const auto draw_start = std::chrono::steady_clock::now();
  const RgbImage image = frame_picture(topo, positions, marked, view, p.size);
  const double draw_s = seconds_since(draw_start);
  const auto write_start = std::chrono::steady_clock::now();
  write_png(p.out, image);
  const double write_s = seconds_since(write_start);

  size_t marked_faces = 0;
  for (uint8_t m : marked) marked_faces += m;
  const QueryPairCounter queries(topo);
  std::string by_query;
  if (queries.active()) {
    const QueryPairs q = queries.count(pairs);
    by_query = " (" + std::to_string(q.self) + " self, " + std::to_string(q.inter) + " inter)";
  }
  std::printf("picture: %s, %ux%u pixels, view %s\n", p.out.c_str(), p.size, p.size, p.view.c_str());
  const size_t objects = topo.objects.empty() ? 1 : topo.objects.size();
  std::printf("  scene     %s frame %u (of %u), %zu triangles, %zu object%s\n", scene.name.c_str(), p.frame, frames,
              topo.faces.size(), objects, objects == 1 ? "" : "s");
  if (p.mark == "contacts")
    std::printf("  marked    %zu triangles (red-orange) in %zu contacts within %g (sharing no vertex) of %zu pairs%s "
                "of pipeline %s on %s\n",
                marked_faces, contacts.size(), double(p.contact_distance), pairs.size(), by_query.c_str(),
                p.pipeline.c_str(), device.c_str());
  else
    std::printf("  marked    %zu triangles (red-orange) in %zu pairs%s of pipeline %s on %s%s\n", marked_faces,
                pairs.size(), by_query.c_str(), p.pipeline.c_str(), device.c_str(),
                o.config.skip_adjacent ? "" : "; triangles sharing a vertex are pairs too (--skip-adjacent: not)");
  std::printf("  time      %.2f s: scene and frame %.2f s, pairs %.2f s, drawing %.2f s, PNG %.2f s\n",
              seconds_since(start), load_s, pairs_s, draw_s, write_s);
  return kExitOk;
}

}  // namespace cdb
