#include "version_text.h"

#include "cdbench/core/build_info.h"

namespace cdb {

std::string version_text() {
  const BuildInfo& b = build_info();
  const std::string cuda = *b.cuda_compiler ? std::string("nvcc ") + b.cuda_compiler : "none (built without CUDA: cpu only)";
  return std::string("cdbench ") + CDBENCH_VERSION + "\ncommit  " + b.git_sha + "\ncuda    " + cuda + "\nbuild   " +
         b.build_type + ", " + b.cxx_compiler;
}

}  // namespace cdb
