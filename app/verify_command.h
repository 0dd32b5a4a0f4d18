#pragma once
// `cdbench verify`: pipelines against the exact oracle, frame by frame, and against the
// scene's double geometry; and any program's pairs, read from files, against the same
// oracle (docs/extending.md "Checking an outside method").
#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>
#include <vector>

#include "options.h"

namespace cdb {

struct VerifyOptions {
  // Empty: all but the oracle, or none with --pairs or --write-pairs.
  std::vector<std::string> pipelines;
  size_t brute_limit = 30000;
  std::string pairs_dir;        // an outside method's pairs, one file a frame (io/pairs_file.h)
  std::string write_pairs_dir;  // where to write the oracle's pairs, one file a frame
  std::string pairs_format = "txt";  // of the files --write-pairs writes: txt or bin
};

CLI::App* add_verify_command(CLI::App& app, CommonOptions& o, VerifyOptions& v);

int verify_command(const CommonOptions& o, const VerifyOptions& v);

}  // namespace cdb
