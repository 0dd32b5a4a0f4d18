#include "cdbench/exec/host_exec.h"
#include "registry/pipeline_factory.h"

namespace cdb {

std::unique_ptr<Pipeline> make_host_pipeline(const PipelineConfig& config) {
  return make_pipeline_on<HostExec, HostPhaseTimer>(config);
}

}  // namespace cdb
