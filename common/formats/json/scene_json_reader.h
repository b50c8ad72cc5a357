#pragma once
/// @file scene_json_reader.h
/// Typed reads out of the JSON scene format's nodes (docs/scene-format.md) that raise InputError naming the file and
/// the node's JSON path: shared by the parts of the parser (common/formats/json/scene_json.cpp, common/formats/json/scene_sky.cpp).
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <set>
#include <string>

#include "common/scene/scene_desc.h"
#include "common/util/error.h"
#include "common/util/math.h"

namespace firstshot {

using Json = nlohmann::ordered_json;

/// Reads typed values out of JSON nodes, raising InputError with the node's path.
class SceneJsonReader {
 public:
  explicit SceneJsonReader(std::string file) : file_(std::move(file)) {}
  [[noreturn]] void fail(const std::string& where, const std::string& msg) const { throw InputError(file_, where, msg); }

  void keys(const Json& j, const std::string& where, std::initializer_list<const char*> allowed) const {
    if (!j.is_object()) fail(where, "expected an object");
    const std::set<std::string> ok(allowed.begin(), allowed.end());
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (!ok.count(it.key())) {
        std::string list;
        for (const auto& k : ok) list += (list.empty() ? "" : ", ") + k;
        fail(where, "unknown key \"" + it.key() + "\" (allowed: " + list + ")");
      }
    }
  }
  const Json& need(const Json& j, const std::string& where, const char* key) const {
    if (!j.contains(key)) fail(where, std::string("missing key \"") + key + "\"");
    return j.at(key);
  }
  double number(const Json& j, const std::string& where) const {
    if (!j.is_number()) fail(where, "expected a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(where, "value is not finite (NaN or Inf)");
    return v;
  }
  double nonNegative(const Json& j, const std::string& where) const {
    const double v = number(j, where);
    if (v < 0) fail(where, "must not be negative (got " + std::to_string(v) + ")");
    return v;
  }
  double positive(const Json& j, const std::string& where) const {
    const double v = number(j, where);
    if (!(v > 0)) fail(where, "must be positive (got " + std::to_string(v) + ")");
    return v;
  }
  int64_t integer(const Json& j, const std::string& where, int64_t lo, int64_t hi) const {
    if (!j.is_number_integer()) fail(where, "expected an integer");
    const int64_t v = j.get<int64_t>();
    if (v < lo || v > hi) fail(where, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  }
  Vec3d vec3(const Json& j, const std::string& where) const {
    if (!j.is_array() || j.size() != 3) fail(where, "expected an array of 3 numbers");
    return {number(j[0], where + "[0]"), number(j[1], where + "[1]"), number(j[2], where + "[2]")};
  }
  Color color(const Json& j, const std::string& where) const {
    if (j.is_number()) {
      const double v = nonNegative(j, where);
      return Color(static_cast<float>(v));
    }
    if (!j.is_array() || j.size() != 3) fail(where, "expected an RGB array of 3 numbers (or one number)");
    Color c;
    for (int i = 0; i < 3; ++i) c[i] = static_cast<float>(nonNegative(j[i], where + "[" + std::to_string(i) + "]"));
    return c;
  }
  std::string string(const Json& j, const std::string& where) const {
    if (!j.is_string()) fail(where, "expected a string");
    return j.get<std::string>();
  }
  bool boolean(const Json& j, const std::string& where) const {
    if (!j.is_boolean()) fail(where, "expected true or false");
    return j.get<bool>();
  }
  SmallOverride small(const Json& j, const std::string& where) const {
    if (j.is_boolean()) return j.get<bool>() ? SmallOverride::Small : SmallOverride::Large;
    if (j.is_string() && j.get<std::string>() == "auto") return SmallOverride::Auto;
    fail(where, "expected true, false or \"auto\"");
  }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

}  // namespace firstshot
