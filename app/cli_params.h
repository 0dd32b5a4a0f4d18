#pragma once
// The options a command ran with, as JSON for the results file: every option of the
// command, the value given or else its default (numbers as numbers), so a new option is
// recorded without code.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace cdb {

nlohmann::json options_json(const CLI::App& command);

}  // namespace cdb
