#pragma once
// A scene's identity in results: its name plus the generator parameters a run overrode
// (`--set`), e.g. `funnel[res=24]`, so runs of one descriptor at other sizes never share a
// heading, a table row group or a plot.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace cdb {

// `name` alone without overrides, else `name[k1=v1,k2=v2]` with the keys sorted and string
// values unquoted.
std::string scene_label(const std::string& name, const nlohmann::json& overrides);

// `--set key=value` arguments as an object: values parsed as JSON where they are (numbers,
// booleans), else kept as strings. Throws on an argument without `key=`.
nlohmann::json parse_set_overrides(const std::vector<std::string>& sets);

}  // namespace cdb
