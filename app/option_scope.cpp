#include "option_scope.h"

namespace cdb {
namespace {

struct ScopedOption {
  const char* flag;
  OptionScope scope;
};

// Every option of app/options.cpp that not every pipeline acts on. The others (scene,
// device, frames, boxes, margins, precision, --skip-adjacent, --phase-timing,
// --dependent-launch) act on all of them.
constexpr ScopedOption kScopedOptions[] = {
    {"--rebuild-every", OptionScope::hierarchy},
    {"--refit-every", OptionScope::hierarchy},
    {"--morton-bits", OptionScope::hierarchy},
    {"--refit-levels", OptionScope::hierarchy},
    {"--refit-top-leaves", OptionScope::hierarchy},
    {"--front-cycle", OptionScope::fronts},
    {"--cuda-graph", OptionScope::fronts},
    {"--preserve-warp", OptionScope::fronts},
    {"--update-warp", OptionScope::fronts},
    {"--preserve-bound", OptionScope::fronts},
    {"--order-updates", OptionScope::fronts},
    {"--update-in-place", OptionScope::fronts},
    {"--compact-share", OptionScope::fronts},
    {"--rebuild-degraded", OptionScope::fronts},
    {"--rebuild-ahead", OptionScope::fronts},
    {"--rebuild-growth", OptionScope::fronts},
    {"--regenerate", OptionScope::fronts},
    {"--update-probe", OptionScope::fronts},
    {"--restructure-quality", OptionScope::restructure},
    {"--restructure-min-leaves", OptionScope::restructure},
    {"--restructure-max-fraction", OptionScope::restructure},
    {"--threshold-refit", OptionScope::restructure},
    {"--threshold-build", OptionScope::restructure},
    {"--restructure-price", OptionScope::restructure},
};

}  // namespace

OptionScope option_scope(const std::string& flag) {
  for (const ScopedOption& o : kScopedOptions)
    if (flag == o.flag) return o.scope;
  return OptionScope::every;
}

bool scope_covers(OptionScope scope, const PipelineKind& kind) {
  const FrontStrategy* front = std::get_if<FrontStrategy>(&kind.builds);
  switch (scope) {
    case OptionScope::every: return true;
    case OptionScope::hierarchy: return front || std::get<BaselineMethod>(kind.builds) == BaselineMethod::bvh;
    case OptionScope::fronts: return front != nullptr;
    case OptionScope::restructure: return front && front->restructure;
  }
  return true;
}

const char* scope_words(OptionScope scope) {
  switch (scope) {
    case OptionScope::every: return "every pipeline";
    case OptionScope::hierarchy: return "BVH pipelines only: the front pipelines and bvh";
    case OptionScope::fronts: return "front pipelines only";
    case OptionScope::restructure: return "restructuring pipelines only: c";
  }
  return "";
}

std::vector<std::string> ignored_option_warnings(const std::vector<std::string>& given,
                                                 const std::vector<std::string>& pipelines) {
  std::vector<std::string> lines;
  for (const std::string& name : pipelines) {
    const PipelineKind* kind = find_pipeline_kind(name);
    if (!kind) continue;
    std::string flags, scopes;
    size_t count = 0;
    for (const std::string& flag : given) {
      const OptionScope scope = option_scope(flag);
      if (scope_covers(scope, *kind)) continue;
      flags += (count++ ? ", " : "") + flag;
      const std::string words = scope_words(scope);
      if (scopes.find(words) == std::string::npos) scopes += (scopes.empty() ? "" : "; ") + words;
    }
    if (count)
      lines.push_back(flags + (count > 1 ? " do" : " does") + " not apply to " + name + " (" + scopes +
                      "): ignored there");
  }
  return lines;
}

}  // namespace cdb
