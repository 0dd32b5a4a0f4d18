#include "scenes/load/scene_label.h"

#include "cdbench/core/error.h"

namespace cdb {

std::string scene_label(const std::string& name, const nlohmann::json& overrides) {
  if (!overrides.is_object() || overrides.empty()) return name;
  std::string label = name + "[";
  // nlohmann::json objects iterate in key order, so the label does not depend on the order
  // the options were given in.
  for (auto it = overrides.begin(); it != overrides.end(); ++it)
    label += (it == overrides.begin() ? "" : ",") + it.key() + "=" +
             (it.value().is_string() ? it.value().get<std::string>() : it.value().dump());
  return label + "]";
}

nlohmann::json parse_set_overrides(const std::vector<std::string>& sets) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& kv : sets) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) fail_usage("--set " + kv + ": expected key=value");
    const std::string key = kv.substr(0, eq), value = kv.substr(eq + 1);
    j[key] = nlohmann::json::accept(value) ? nlohmann::json::parse(value) : nlohmann::json(value);
  }
  return j;
}

}  // namespace cdb
