#include "io/descriptor_object.h"

#include <cmath>

#include "core/error.h"

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
  for (auto it = j_.begin(); it != j_.end(); ++it) {
    bool ok = false;
    for (const std::string& k : known) ok = ok || it.key() == k;
    if (!ok) fail(at(it.key()) + ": unknown key (" + list + ")");
  }
}

std::string DescriptorObject::at(const std::string& key) const {
  // The root's `where` is "file: ", so its keys read "file: /key".
  return where_ + "/" + key;
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
  if (!(v > 0)) fail(at(key) + ": must be a positive number");
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

}  // namespace cdb
