#pragma once
// A pipeline configuration as JSON, every field (defaults too), for the results file.
#include <nlohmann/json.hpp>

#include "cdbench/pipeline/pipeline.h"

namespace cdb {

nlohmann::json to_json(const PipelineConfig& config);

}  // namespace cdb
