#include "cli_params.h"

namespace cdb {

nlohmann::json options_json(const CLI::App& command) {
  nlohmann::json j = nlohmann::json::object();
  for (const CLI::Option* opt : command.get_options()) {
    if (opt->get_lnames().empty() || opt->get_lnames()[0] == "help") continue;
    const std::string& name = opt->get_lnames()[0];
    const bool flag = opt->get_expected_max() == 0;
    if (flag) {
      j[name] = opt->count() > 0;
    } else if (opt->count() > 0) {
      const auto& given = opt->results();
      j[name] = given.size() == 1 ? nlohmann::json(given[0]) : nlohmann::json(given);
    } else {
      j[name] = opt->get_default_str();
    }
  }
  return j;
}

}  // namespace cdb
