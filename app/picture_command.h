#pragma once
// `cdbench picture`: a PNG picture of one frame of a scene with the triangles of its pair
// set marked, for a user to see that frames loaded as meant (harness/picture/ draws it).
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

#include "options.h"

namespace cdb {

struct PictureOptions {
  uint32_t frame = 0;
  std::string out = "frame.png";
  std::string view = "iso";
  uint32_t size = 1024;  // pixels, width and height
  // An exact pipeline, run on the host in seconds for a million triangles: the pairs of
  // the float boxes, as the oracle has them (verify checks it).
  std::string pipeline = "sweep";
  // --mark: pairs (the pipeline's pair set) or contacts (those of its pairs whose triangles
  // lie within contact_distance and share no vertex, by the exact narrow phase).
  std::string mark = "pairs";
  float contact_distance = 0.0f;
};

CLI::App* add_picture_command(CLI::App& app, CommonOptions& o, PictureOptions& p);

int picture_command(const CommonOptions& o, const PictureOptions& p);

}  // namespace cdb
