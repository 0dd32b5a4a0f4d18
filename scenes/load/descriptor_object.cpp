#include "scenes/load/descriptor_object.h"

#include <algorithm>
#include <cmath>

#include "cdbench/core/error.h"

namespace cdb {

namespace {

// Directories of data the scenes read from Debian packages, the package and the option of
// scripts/install-deps.sh that installs it.
struct PackagedData {
  const char* dir;
  const char* package;
  const char* flag;
};
constexpr PackagedData kPackagedData[] = {
    {"/usr/share/assimp/models", "assimp-testmodels", "--scenes"},
    {"/usr/share/glmark2", "glmark2-data", "--scenes-extra"},
    {"/usr/share/doc/libcgal-dev", "libcgal-demo", "--scenes-extra"},
};

}  // namespace

std::string package_hint(const std::filesystem::path& file) {
  for (const PackagedData& d : kPackagedData)
    if (file.string().rfind(d.dir, 0) == 0)
      return std::string(" (it ships with the Debian package ") + d.package + ": run scripts/install-deps.sh " +
             d.flag + ")";
  return "";
}

DescriptorObject::DescriptorObject(const nlohmann::json& j, std::string where,
                                   const std::vector<std::string>& known)
    : j_(j), where_(std::move(where)) {
  std::string list;
  for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
  if (!j_.is_object()) fail(where_ + ": must be an object with " + list);
  for (auto it = j_.begin(); it != j_.end(); ++it)
    if (std::find(known.begin(), known.end(), it.key()) == known.end())
      fail(at(it.key()) + ": unknown key (" + list + ")");
}

DescriptorObject DescriptorObject::object(const char* key, const std::vector<std::string>& known) const {
  return DescriptorObject(j_.at(key), at(key), known);
}

std::string DescriptorObject::text(const char* key) const {
  if (!has(key) || !j_[key].is_string()) fail(at(key) + ": must be a string");
  return j_[key].get<std::string>();
}

bool DescriptorObject::flag(const char* key, bool fallback) const {
  if (!has(key)) return fallback;
  if (!j_[key].is_boolean()) fail(at(key) + ": must be true or false");
  return j_[key].get<bool>();
}

double DescriptorObject::number(const char* key, double fallback) const {
  if (!has(key)) return fallback;
  if (!j_[key].is_number() || !std::isfinite(j_[key].get<double>())) fail(at(key) + ": must be a number");
  return j_[key].get<double>();
}

double DescriptorObject::positive(const char* key, double fallback) const {
  const double v = number(key, fallback);
  // 1e-320 is positive, but a rate's reciprocal (a time step) overflows to infinity.
  if (!(v > 0) || !std::isfinite(1 / v)) fail(at(key) + ": must be a positive number (at least 1e-300)");
  return v;
}

uint32_t DescriptorObject::count(const char* key, uint32_t fallback, uint32_t lo, uint32_t hi) const {
  if (!has(key)) return fallback;
  const auto& v = j_[key];
  // Overrides from the command line arrive as signed integers; the value decides.
  if (!v.is_number_integer() || v.get<int64_t>() < int64_t(lo) || v.get<int64_t>() > int64_t(hi))
    fail(at(key) + ": must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
  return v.get<uint32_t>();
}

std::array<double, 3> DescriptorObject::vec3(const char* key, std::array<double, 3> fallback) const {
  if (!has(key)) return fallback;
  const auto& v = j_[key];
  if (!v.is_array() || v.size() != 3) fail(at(key) + ": must be [x, y, z]");
  std::array<double, 3> out;
  for (int i = 0; i < 3; ++i) {
    if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
      fail(at(key) + "/" + std::to_string(i) + ": must be a number");
    out[i] = v[i].get<double>();
  }
  return out;
}

std::filesystem::path DescriptorObject::existing_file(const char* key,
                                                      const std::filesystem::path& descriptor_dir) const {
  if (!has(key) || !j_[key].is_string()) fail(at(key) + ": must be a string (a file)");
  std::filesystem::path file = j_[key].get<std::string>();
  if (file.is_relative()) file = descriptor_dir / file;
  if (!std::filesystem::exists(file)) fail(at(key) + ": " + file.string() + ": no such file" + package_hint(file));
  return file;
}

namespace {

// The containers the parser is inside of, outermost first, so a duplicate key can be
// named by its path ("/parts/1/motion").
struct JsonLevel {
  bool object = false;
  std::vector<std::string> keys;  // seen in this object so far
  size_t index = 0;               // elements of this array so far
};

std::string json_path(const std::vector<JsonLevel>& levels) {
  std::string path;
  for (size_t i = 0; i + 1 < levels.size(); ++i)
    path += "/" + (levels[i].object ? levels[i].keys.back() : std::to_string(levels[i].index));
  return path.empty() ? "/" : path;
}

}  // namespace

nlohmann::json parse_json_file(std::istream& in, const std::string& where) {
  using nlohmann::json;
  std::vector<JsonLevel> levels;
  std::string duplicate;
  const auto element_done = [&levels] {
    if (!levels.empty() && !levels.back().object) ++levels.back().index;
  };
  const json::parser_callback_t callback = [&](int, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start: levels.push_back({true, {}, 0}); break;
      case json::parse_event_t::array_start: levels.push_back({false, {}, 0}); break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        levels.pop_back();
        element_done();
        break;
      case json::parse_event_t::key: {
        const std::string key = parsed.get<std::string>();
        std::vector<std::string>& keys = levels.back().keys;
        if (duplicate.empty() && std::find(keys.begin(), keys.end(), key) != keys.end())
          duplicate = "key \"" + key + "\" appears twice in the object at " + json_path(levels) +
                      " (JSON readers keep only one of the two): remove one";
        keys.push_back(key);
        break;
      }
      case json::parse_event_t::value: element_done(); break;
    }
    return true;
  };
  json j;
  try {
    j = json::parse(in, callback);
  } catch (const json::exception& e) {
    // "[json.exception.parse_error.101] parse error at line 3, column 5: syntax error
    // while parsing object - ..." without the bracketed code; 406 is a number beyond
    // double's range ("1e400").
    const std::string what = e.what();
    const size_t close = what.find("] ");
    fail(where + ": malformed JSON: " + (close == std::string::npos ? what : what.substr(close + 2)) +
         (e.id == 406 ? " (beyond the range of a double, about 1.8e308)" : ""));
  }
  if (!duplicate.empty()) fail(where + ": " + duplicate);
  return j;
}

}  // namespace cdb
