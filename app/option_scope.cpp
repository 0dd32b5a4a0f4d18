#include "option_scope.h"

#include "join_words.h"

namespace cdb {

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

std::string not_applying_text(const std::vector<std::string>& flags, const std::vector<std::string>& pipelines) {
  std::string scopes;
  for (const std::string& flag : flags) {
    const std::string words = scope_words(option_scope(flag));
    if (scopes.find(words) == std::string::npos) scopes += (scopes.empty() ? "" : "; ") + words;
  }
  return join_words(flags, ", ") + (flags.size() > 1 ? " do" : " does") + " not apply to " + join_words(pipelines, ", ") +
         " (" + scopes + ")";
}

std::vector<std::string> ignored_option_warnings(const std::vector<std::string>& given,
                                                 const std::vector<std::string>& pipelines) {
  std::vector<std::string> lines;
  for (const std::string& name : pipelines) {
    const PipelineKind* kind = find_pipeline_kind(name);
    if (!kind) continue;
    std::vector<std::string> ignored;
    for (const std::string& flag : given)
      if (!scope_covers(option_scope(flag), *kind)) ignored.push_back(flag);
    if (!ignored.empty()) lines.push_back(not_applying_text(ignored, {name}) + ": ignored there");
  }
  return lines;
}

}  // namespace cdb
