#include "cli_params.h"

namespace cdb {
namespace {

// An option's text as JSON: a number where the text is one (so readers compare 0.001 with
// 0.0010 and sort sizes numerically), else the text as given.
nlohmann::json typed_value(const std::string& text) {
  if (nlohmann::json::accept(text)) {
    nlohmann::json v = nlohmann::json::parse(text);
    if (v.is_number()) return v;
  }
  return text;
}

}  // namespace

nlohmann::json options_json(const CLI::App& command) {
  nlohmann::json j = nlohmann::json::object();
  for (const CLI::Option* opt : command.get_options()) {
    if (opt->get_lnames().empty() || opt->get_lnames()[0] == "help") continue;
    const std::string& name = opt->get_lnames()[0];
    const bool flag = opt->get_expected_max() == 0;
    // Repeatable options (--set) are arrays however often they were given.
    const bool repeatable = opt->get_expected_max() > 1;
    if (flag) {
      j[name] = opt->count() > 0;
    } else if (repeatable) {
      nlohmann::json values = nlohmann::json::array();
      for (const auto& g : opt->results()) values.push_back(typed_value(g));
      j[name] = values;
    } else if (opt->count() > 0) {
      j[name] = typed_value(opt->results().front());
    } else {
      j[name] = typed_value(opt->get_default_str());
    }
  }
  return j;
}

std::vector<std::string> given_flags(const CLI::App& command) {
  std::vector<std::string> flags;
  for (const CLI::Option* opt : command.get_options())
    if (opt->count() > 0 && !opt->get_lnames().empty()) flags.push_back("--" + opt->get_lnames()[0]);
  return flags;
}

}  // namespace cdb
