#pragma once
// One JSON object of a scene descriptor, read field by field: keys outside the known list
// are rejected up front, every value is checked for type and range, and every message names
// the descriptor and the JSON path ("scenes/x.json: /parts/1/motion/velocity: ...").
#include <array>
#include <cstdint>
#include <filesystem>
#include <istream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace cdb {

class DescriptorObject {
 public:
  // `where` is "file: /path/to/object" ("file: " for the root). Fails unless `j` is an
  // object whose keys are all in `known`.
  DescriptorObject(const nlohmann::json& j, std::string where, const std::vector<std::string>& known);

  bool has(const char* key) const { return j_.contains(key); }
  const nlohmann::json& raw(const char* key) const { return j_.at(key); }
  // "file: /path/key": the prefix of every message about `key` (the root's `where` is
  // "file: ", so its keys read "file: /key").
  std::string at(const std::string& key) const { return where_ + "/" + key; }
  const std::string& where() const { return where_; }
  DescriptorObject object(const char* key, const std::vector<std::string>& known) const;

  std::string text(const char* key) const;  // required
  bool flag(const char* key, bool fallback) const;
  double number(const char* key, double fallback) const;
  double positive(const char* key, double fallback) const;
  uint32_t count(const char* key, uint32_t fallback, uint32_t lo, uint32_t hi) const;
  std::array<double, 3> vec3(const char* key, std::array<double, 3> fallback) const;
  // A file named by a string, relative to the descriptor's directory; it must exist. A file
  // under a directory a Debian package provides names the package and the set-up flag.
  std::filesystem::path existing_file(const char* key, const std::filesystem::path& descriptor_dir) const;

 private:
  const nlohmann::json& j_;
  std::string where_;
};

// Parses a JSON document for a file the user writes (a scene descriptor, a sweep file),
// `where` naming it. Refuses, in words rather than the parser's own text: malformed JSON
// (with line and column), text that is not UTF-8, and a key given twice in one object
// (a parser keeps one of the two silently), naming the key and its JSON path.
nlohmann::json parse_json_file(std::istream& in, const std::string& where);

// Where a missing file under `file`'s directory comes from: " (it ships with the Debian
// package P: run scripts/install-deps.sh --flag)", or "" for files no package provides.
std::string package_hint(const std::filesystem::path& file);

}  // namespace cdb
