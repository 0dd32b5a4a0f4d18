#pragma once
// Generator parameters from a scene descriptor's "params" object. Remembers which keys were
// read, with their defaults, ranges and values: leftovers (typos) are rejected by finish(),
// naming the keys there are, and `scenes info` lists them (described()).
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cdbench/core/error.h"
#include "scenes/generators/generator_parameter.h"

namespace cdb::scene {

// A parameter's value refused (unknown, out of range, of the wrong type), naming the key:
// the loader tells a value given on the command line (--set, a usage error) from one in a
// descriptor's file (bad data).
struct ParameterError : Error {
  ParameterError(const std::string& message, std::string parameter) : Error(message), key(std::move(parameter)) {}
  std::string key;
};

// The largest count a JSON number (a double) holds exactly: 2^53.
inline constexpr uint64_t kLargestExactCount = uint64_t(1) << 53;

class Params {
 public:
  Params(std::string generator, const nlohmann::json& j) : generator_(std::move(generator)), j_(j) {
    if (!j_.is_null() && !j_.is_object()) fail(where("") + "parameters must be a JSON object");
  }
  double number(const char* key, double fallback) {
    const double v = read_number(key, fallback);
    note(key, "number", format(fallback), "", format(v));
    return v;
  }
  // A whole number in [lo, hi] (hi below 2^53, where doubles stop holding every integer):
  // never wrapped into a narrower type.
  uint64_t count_in(const char* key, uint64_t fallback, uint64_t lo, uint64_t hi) {
    const double d = read_number(key, double(fallback));
    if (d < 0 || d != std::floor(d)) fail(where(key) + "must be a whole number >= 0, not " + format(d), key);
    if (d < double(lo) || d > double(hi))
      fail(where(key) + format(d) + " is out of range: must be between " + std::to_string(lo) + " and " +
               std::to_string(hi),
           key);
    const uint64_t v = uint64_t(d);
    note(key, "integer", std::to_string(fallback), std::to_string(lo) + ".." + std::to_string(hi), std::to_string(v));
    return v;
  }
  // A count that fits the 32-bit fields of the scene (frames, resolutions, indices).
  uint32_t count32(const char* key, uint32_t fallback, uint32_t lo, uint32_t hi) {
    return uint32_t(count_in(key, fallback, lo, hi));
  }
  std::string text(const char* key, const std::string& fallback) {
    used_.insert(key);
    std::string v = fallback;
    if (!j_.is_null() && j_.contains(key)) {
      if (!j_[key].is_string()) fail(where(key) + "must be a string", key);
      v = j_[key].get<std::string>();
    }
    note(key, "text", fallback, "", v);
    return v;
  }
  void finish() const {
    if (j_.is_null()) return;
    for (auto it = j_.begin(); it != j_.end(); ++it)
      if (!used_.count(it.key())) fail(where(it.key()) + "unknown parameter (known: " + known() + ")", it.key());
  }
  // Every parameter read so far, in reading order.
  const std::vector<GeneratorParameter>& described() const { return described_; }

 private:
  [[noreturn]] void fail(const std::string& message, const std::string& key = "") const {
    throw ParameterError(message, key);
  }
  std::string where(const std::string& key) const {
    return "generator '" + generator_ + "'" + (key.empty() ? "" : ", parameter '" + key + "'") + ": ";
  }
  double read_number(const char* key, double fallback) {
    used_.insert(key);
    if (j_.is_null() || !j_.contains(key)) return fallback;
    if (!j_[key].is_number()) fail(where(key) + "must be a number", key);
    const double v = j_[key].get<double>();
    if (!std::isfinite(v)) fail(where(key) + "must be finite", key);
    return v;
  }
  static std::string format(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.10g", v);
    return text;
  }
  // The last reading of a key describes it (a helper may read it, then a caller narrow it).
  void note(const std::string& key, const char* kind, std::string fallback, std::string range, std::string value) {
    for (auto& d : described_)
      if (d.key == key) {
        d = {key, kind, std::move(fallback), std::move(range), std::move(value)};
        return;
      }
    described_.push_back({key, kind, std::move(fallback), std::move(range), std::move(value)});
  }
  std::string known() const {
    std::string list;
    for (const auto& d : described_) list += (list.empty() ? "" : ", ") + d.key;
    return list;
  }
  std::string generator_;
  const nlohmann::json& j_;
  std::set<std::string> used_;
  std::vector<GeneratorParameter> described_;
};

}  // namespace cdb::scene
