#pragma once
// What an option's scope (option_table.h) means for a pipeline, and how an option given to
// a pipeline that ignores it is said rather than silently dropped (`run --pipeline grid
// --front-cycle 4`); a sweep runs cells that differ only in such options once.
#include <string>
#include <vector>

#include "option_table.h"
#include "registry/pipeline_kinds.h"

namespace cdb {

// Whether the pipeline `kind` acts on options of `scope`.
bool scope_covers(OptionScope scope, const PipelineKind& kind);
// "front pipelines only", for messages.
const char* scope_words(OptionScope scope);

// "--front-cycle, --restructure-quality do not apply to grid (front pipelines only;
// restructuring pipelines only: c)": the flags (at least one), the pipelines that ignore
// them, and their scopes' words, each once. The one phrasing of run's and verify's
// warnings and the sweep's merged cells.
std::string not_applying_text(const std::vector<std::string>& flags, const std::vector<std::string>& pipelines);

// For each pipeline of `pipelines` (known names) that ignores some of the `given` flags, one
// line: "--front-cycle, --restructure-quality do not apply to grid (...): ignored there".
std::vector<std::string> ignored_option_warnings(const std::vector<std::string>& given,
                                                 const std::vector<std::string>& pipelines);

}  // namespace cdb
