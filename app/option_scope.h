#pragma once
// Which pipelines an option of run and verify acts on: one table (option_scope.cpp), so an
// option given to a pipeline that ignores it is said rather than silently dropped
// (`run --pipeline grid --front-cycle 4`), and a sweep runs cells that differ only in such
// options once.
#include <string>
#include <vector>

#include "registry/pipeline_kinds.h"

namespace cdb {

enum class OptionScope {
  every,        // every pipeline: the scene, the boxes, the measurement
  hierarchy,    // pipelines that refit or rebuild a BVH: the front pipelines and bvh
  fronts,       // the front pipelines (a, b, c and their orderings)
  restructure,  // the front pipelines that restructure (c)
};

// The scope of an option by its flag ("--front-cycle"); every for options outside the table.
OptionScope option_scope(const std::string& flag);
// Whether the pipeline `kind` acts on options of `scope`.
bool scope_covers(OptionScope scope, const PipelineKind& kind);
// "front pipelines only", for messages.
const char* scope_words(OptionScope scope);

// For each pipeline of `pipelines` (known names) that ignores some of the `given` flags, one
// line: "--front-cycle, --restructure-quality do not apply to grid (...): ignored there".
std::vector<std::string> ignored_option_warnings(const std::vector<std::string>& given,
                                                 const std::vector<std::string>& pipelines);

}  // namespace cdb
