#pragma once
// The options a command ran with, as JSON for the results file: every option of the
// command, the value given or else its default (numbers as numbers), so a new option is
// recorded without code.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace cdb {

nlohmann::json options_json(const CLI::App& command);
// The long flags given on the command line ("--front-cycle"), in the command's order.
std::vector<std::string> given_flags(const CLI::App& command);

}  // namespace cdb
