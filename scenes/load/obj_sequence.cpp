#include "scenes/load/obj_sequence.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "cdbench/core/error.h"
#include "scenes/load/input_files.h"
#include "scenes/load/obj_reader.h"

namespace cdb {

size_t read_mesh_file(const std::filesystem::path& file, Topology& topology,
                      std::vector<vec3d>& positions, int64_t frame) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    fail(file.string() + ": " + (ec ? ec.message() : std::string("no such file")));
  if (lower_extension(file) == ".obj") return read_obj_file(file, topology, positions, frame);
  Assimp::Importer importer;
  // Read as is, count the polygons, then triangulate them only: no vertex joining, no
  // degenerate removal, no reordering, so the file's faces keep their order.
  const aiScene* raw = importer.ReadFile(file.string(), 0);
  if (!raw) fail(file.string() + ": cannot read mesh: " + importer.GetErrorString());
  size_t polygons = 0;
  for (unsigned m = 0; m < raw->mNumMeshes; ++m)
    for (unsigned f = 0; f < raw->mMeshes[m]->mNumFaces; ++f) polygons += raw->mMeshes[m]->mFaces[f].mNumIndices > 3;
  const aiScene* scene = importer.ApplyPostProcessing(aiProcess_Triangulate);
  if (!scene) fail(file.string() + ": cannot triangulate mesh: " + importer.GetErrorString());
  if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) fail(file.string() + ": incomplete mesh file");
  topology.faces.clear();
  positions.clear();
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    const uint32_t base = uint32_t(positions.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v)
      positions.push_back({mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z});
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines carry no triangle
      topology.faces.push_back(
          {base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
    }
  }
  topology.num_vertices = uint32_t(positions.size());
  // assimp reads some garbage as an empty mesh; a mesh file without triangles is an error.
  if (topology.faces.empty()) fail(file.string() + ": no triangles in this file (malformed or empty mesh)");
  return polygons;
}

namespace {

class MeshSequence final : public FrameSource {
 public:
  explicit MeshSequence(const std::filesystem::path& dir) : dir_(dir) {
    files_ = frame_files(dir, [](const std::filesystem::path& p) { return lower_extension(p) == ".obj"; });
    if (files_.empty()) fail(dir.string() + ": no .obj frames in this directory");
    std::vector<vec3d> positions;
    const size_t polygons = read_mesh_file(files_[0], topology_, positions, 0);
    if (polygons)
      std::fprintf(stderr, "cdbench: %s: %zu polygon faces triangulated (%zu triangles in all)\n",
                   files_[0].string().c_str(), polygons, topology_.faces.size());
    check_frame(positions, topology_, files_[0].string(), 0);
    // Every frame is read once here, so a bad frame stops the program before the first
    // one is timed rather than after the frames before it ran (the files are read again
    // as the frames are asked for: keeping them all would cost frames x vertices x 24 bytes).
    for (uint32_t k = 1; k < files_.size(); ++k) this->positions(k, positions);
    opened_ = true;
  }
  const Topology& topology() const override { return topology_; }
  uint32_t num_frames() const override { return uint32_t(files_.size()); }
  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    Topology t;
    read_mesh_file(files_.at(k), t, out, k);
    const std::string where = files_[k].string();
    // Every frame matched frame 0 when the scene was opened, so a frame that does not now
    // was rewritten since (frame 0 itself too): said so, not as frame 0 against frame 0.
    if (opened_) {
      const bool same_counts = t.faces.size() == topology_.faces.size() && t.num_vertices == topology_.num_vertices;
      const std::string now =
          same_counts ? "other faces than it had"
                      : std::to_string(t.faces.size()) + " triangles and " + std::to_string(t.num_vertices) +
                            " vertices, the scene " + std::to_string(topology_.faces.size()) + " and " +
                            std::to_string(topology_.num_vertices);
      if (!same_counts || std::memcmp(t.faces.data(), topology_.faces.data(), t.faces.size() * sizeof(Tri)) != 0)
        fail(where + ": frame " + std::to_string(k) + " changed after the scene was opened: it has " + now +
             " when the scene was opened; the frame files were replaced while they were read: write them before "
             "the run starts");
    }
    if (t.faces.size() != topology_.faces.size())
      fail(where + ": frame " + std::to_string(k) + " has " + std::to_string(t.faces.size()) +
           " triangles, frame 0 has " + std::to_string(topology_.faces.size()) +
           " (topology must stay fixed)");
    check_same_faces(t.faces, where, k);
    check_frame(out, topology_, where, k);
  }
  std::string describe() const override {
    return "mesh sequence " + dir_.string() + ": " + std::to_string(files_.size()) + " frames";
  }

 private:
  // Frame 0's faces are the ones every frame is computed with, so a frame listing other
  // faces would silently be run with frame 0's: refused, naming the first face that differs.
  void check_same_faces(const std::vector<Tri>& faces, const std::string& where, uint32_t k) const {
    const std::vector<Tri>& first = topology_.faces;
    if (std::memcmp(faces.data(), first.data(), faces.size() * sizeof(Tri)) == 0) return;
    size_t i = 0;
    while (faces[i].v0 == first[i].v0 && faces[i].v1 == first[i].v1 && faces[i].v2 == first[i].v2) ++i;
    const auto corners = [](const Tri& t) {
      return std::to_string(t.v0 + 1) + " " + std::to_string(t.v1 + 1) + " " + std::to_string(t.v2 + 1);
    };
    fail(where + ": frame " + std::to_string(k) + ": face " + std::to_string(i + 1) + " has vertices " +
         corners(faces[i]) + ", frame 0's face " + std::to_string(i + 1) + " has " + corners(first[i]) +
         " (1-based, as OBJ counts; the faces must stay fixed, only positions may change)");
  }

  std::filesystem::path dir_;
  std::vector<std::filesystem::path> files_;
  Topology topology_;
  bool opened_ = false;  // every frame checked against frame 0
};

}  // namespace

std::unique_ptr<FrameSource> open_mesh_sequence(const std::filesystem::path& dir) {
  return std::make_unique<MeshSequence>(dir);
}

void write_obj_sequence(const FrameSource& source, const std::filesystem::path& out_dir) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) fail(out_dir.string() + ": cannot create directory: " + ec.message());
  const Topology& topology = source.topology();
  std::vector<vec3d> positions;
  for (uint32_t k = 0; k < source.num_frames(); ++k) {
    source.positions(k, positions);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04u.obj", k);
    const std::filesystem::path file = out_dir / name;
    std::unique_ptr<FILE, int (*)(FILE*)> out(std::fopen(file.c_str(), "w"), std::fclose);
    if (!out) fail(file.string() + ": cannot open for writing: " + std::strerror(errno));
    errno = 0;
    // %.17g: seventeen significant digits read back to the same double.
    for (const vec3d& p : positions) std::fprintf(out.get(), "v %.17g %.17g %.17g\n", p.x, p.y, p.z);
    for (const Tri& t : topology.faces) std::fprintf(out.get(), "f %u %u %u\n", t.v0 + 1, t.v1 + 1, t.v2 + 1);
    // A cut-off frame would read as one with fewer vertices: removed, not left behind.
    const bool failed = std::ferror(out.get()) | (std::fclose(out.release()) != 0);
    if (failed) {
      const int error = errno;
      std::filesystem::remove(file, ec);
      fail(file.string() + ": write failed" + (error ? std::string(": ") + std::strerror(error) : "") +
           " (the partial frame removed)");
    }
  }
}

}  // namespace cdb
