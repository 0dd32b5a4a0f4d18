#include "core/error.h"
#include "exec/host_exec.h"
#include "pipeline/broad_phase.h"

namespace cdb {

std::unique_ptr<Pipeline> make_host_pipeline(const PipelineConfig& config) {
  return make_broad_phase<HostExec, HostPhaseTimer>(config);
}

}  // namespace cdb
