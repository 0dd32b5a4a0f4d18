#pragma once
// `cdbench scenes list|info|generate`: the scenes, their sizes and motion, and their
// frames written as OBJ files.
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace cdb {

struct ScenesOptions {
  std::string scenes_dir;
  std::string scene;
  std::vector<std::string> sets;  // generator overrides, key=value
  bool json = false;              // info: JSON instead of text
  std::string out_dir;            // generate
  bool overwrite = false;         // generate: replace the frames an earlier generation left in out_dir
};

struct ScenesCommand {
  CLI::App* list = nullptr;
  CLI::App* info = nullptr;
  CLI::App* generate = nullptr;
};

ScenesCommand add_scenes_command(CLI::App& app, ScenesOptions& s);

int scenes_list(const ScenesOptions& s);
int scenes_info(const ScenesOptions& s);
int scenes_generate(const ScenesOptions& s);

}  // namespace cdb
