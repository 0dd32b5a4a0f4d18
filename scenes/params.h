#pragma once
// Generator parameters from a scene descriptor's "params" object. Remembers which keys were
// read so that leftovers (typos) can be rejected by finish().
#include <cmath>
#include <cstdint>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace cdb::scene {

class Params {
 public:
  Params(std::string generator, const nlohmann::json& j) : generator_(std::move(generator)), j_(j) {
    if (!j_.is_null() && !j_.is_object()) fail(where("") + "parameters must be a JSON object");
  }
  double number(const char* key, double fallback) {
    used_.insert(key);
    if (j_.is_null() || !j_.contains(key)) return fallback;
    if (!j_[key].is_number()) fail(where(key) + "must be a number");
    return j_[key].get<double>();
  }
  uint64_t count(const char* key, uint64_t fallback) {
    const double v = number(key, double(fallback));
    if (v < 0 || v != std::floor(v)) fail(where(key) + "must be a non-negative integer");
    return uint64_t(v);
  }
  // A count that must lie in [lo, hi].
  uint32_t count_in(const char* key, uint64_t fallback, uint64_t lo, uint64_t hi) {
    const uint64_t v = count(key, fallback);
    if (v < lo || v > hi)
      fail(where(key) + "must be between " + std::to_string(lo) + " and " + std::to_string(hi));
    return uint32_t(v);
  }
  std::string text(const char* key, const std::string& fallback) {
    used_.insert(key);
    if (j_.is_null() || !j_.contains(key)) return fallback;
    if (!j_[key].is_string()) fail(where(key) + "must be a string");
    return j_[key].get<std::string>();
  }
  void finish() const {
    if (j_.is_null()) return;
    for (auto it = j_.begin(); it != j_.end(); ++it)
      if (!used_.count(it.key())) fail(where(it.key()) + "unknown parameter");
  }

 private:
  std::string where(const std::string& key) const {
    return "generator '" + generator_ + "'" + (key.empty() ? "" : ", parameter '" + key + "'") + ": ";
  }
  std::string generator_;
  const nlohmann::json& j_;
  std::set<std::string> used_;
};

}  // namespace cdb::scene
