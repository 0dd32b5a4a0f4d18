#pragma once

namespace cdb {

// What this binary was built from; printed by every run and stored with its results.
struct BuildInfo {
  const char* git_sha;
  const char* cxx_compiler;
  const char* cuda_compiler;  // empty when built without CUDA
  const char* build_type;
};

const BuildInfo& build_info();

}  // namespace cdb
