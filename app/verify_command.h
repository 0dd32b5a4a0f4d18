#pragma once
// `cdbench verify`: pipelines against the exact oracle, frame by frame, and against the
// scene's double geometry.
#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>
#include <vector>

#include "options.h"

namespace cdb {

struct VerifyOptions {
  std::vector<std::string> pipelines;  // empty: all but the oracle
  size_t brute_limit = 30000;
};

CLI::App* add_verify_command(CLI::App& app, CommonOptions& o, VerifyOptions& v);

int verify_command(const CommonOptions& o, const VerifyOptions& v);

}  // namespace cdb
