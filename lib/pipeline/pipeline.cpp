#include "pipeline/pipeline.h"

#include "core/error.h"

namespace cdb {

const std::vector<std::string>& pipeline_names() {
  static const std::vector<std::string> names = {
      "bvh",         "unordered", "static", "periodic", "restructure", "reference", "a",
      "b",           "c",         "radix-order", "sweep", "hash", "grid", "brute"};
  return names;
}

const char* box_precision_name(BoxPrecision p) {
  return p == BoxPrecision::q16 ? "q16" : p == BoxPrecision::fp64 ? "fp64" : "fp32";
}

BoxPrecision parse_box_precision(const std::string& name) {
  if (name == "fp32") return BoxPrecision::fp32;
  if (name == "fp64") return BoxPrecision::fp64;
  if (name == "q16") return BoxPrecision::q16;
  fail("unknown box precision '" + name + "' (known: fp32, fp64, q16)");
}

const char* preserve_warp_name(PreserveWarp w) {
  return w == PreserveWarp::on ? "on" : w == PreserveWarp::off ? "off" : "auto";
}

PreserveWarp parse_preserve_warp(const std::string& name) {
  if (name == "auto") return PreserveWarp::automatic;
  if (name == "on") return PreserveWarp::on;
  if (name == "off") return PreserveWarp::off;
  fail("unknown preserve warp sharing '" + name + "' (known: auto, on, off)");
}

bool config_conservative(const PipelineConfig& config) {
  // The baselines and the per-frame rebuild never keep stale boxes.
  for (const char* n : {"sweep", "hash", "grid", "brute", "reference"})
    if (config.name == n) return true;
  return config.refit_every <= 1;
}

std::unique_ptr<Pipeline> make_pipeline(const PipelineConfig& config) {
  bool known = false;
  for (const auto& n : pipeline_names()) known = known || n == config.name;
  if (!known) {
    std::string list;
    for (const auto& n : pipeline_names()) list += (list.empty() ? "" : ", ") + n;
    fail("unknown pipeline '" + config.name + "' (known: " + list + ")");
  }
  std::unique_ptr<Pipeline> p;
  if (config.device == "cpu")
    p = make_host_pipeline(config);
  else if (config.device == "cuda")
    p = make_cuda_pipeline(config);
  else
    fail("unknown device '" + config.device + "' (known: cuda, cpu)");
  if (!p) fail("pipeline '" + config.name + "' is not available on " + config.device);
  return p;
}

}  // namespace cdb
