// Compiled instead of cuda_backend.cu when the build found no CUDA compiler.
#include "cdbench/core/error.h"
#include "registry/pipeline_kinds.h"

namespace cdb {

std::unique_ptr<Pipeline> make_cuda_pipeline(const PipelineConfig&) {
  fail("--device cuda: this cdbench was built without CUDA (no nvcc found at configure time)");
}

}  // namespace cdb
