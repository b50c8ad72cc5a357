#pragma once
/// @file ies_util.h
/// IES LM-63 test files written from a formula, and scenes around an IES light (tests/test_ies*.cpp).
#include <fmt/core.h>

#include <functional>
#include <string>
#include <vector>

#include "tests/test_util.h"

namespace firstshot::test {

/// Angles lo, lo + step, …, hi (degrees).
inline std::vector<double> angleRange(double lo, double hi, double step) {
  std::vector<double> a;
  for (int k = 0; lo + k * step <= hi + 1e-9; ++k) a.push_back(lo + k * step);
  return a;
}

/// LM-63-2002 text of photometric type @p type (1 C, 2 B, 3 A) with intensity @p I(v, h) in cd at
/// vertical angles @p v and horizontal angles @p h, written with candela multiplier @p multiplier
/// (values divided by it) and @p lumens per lamp (−1: absolute).
inline std::string iesText(int type, const std::vector<double>& v, const std::vector<double>& h,
                           const std::function<double(double, double)>& I, double multiplier = 1, double lumens = -1) {
  std::string s = "IESNA:LM-63-2002\n[TEST] firstshot test file\n[MANUFAC] none\nTILT=NONE\n";
  s += fmt::format("1 {} {} {} {} {} 2 0.1 0.1 0.05\n1.0 1.0 20\n", lumens, multiplier, v.size(), h.size(), type);
  for (double x : v) s += fmt::format("{} ", x);
  s += "\n";
  for (double x : h) s += fmt::format("{} ", x);
  s += "\n";
  for (double y : h) {
    for (size_t k = 0; k < v.size(); ++k) s += fmt::format("{:.17g}{}", I(v[k], y) / multiplier, k % 10 == 9 ? "\n" : " ");
    s += "\n";
  }
  return s;
}

/// Writes @p text to a fresh temporary file @p name and returns its path.
inline std::string writeIes(const std::string& name, const std::string& text) {
  const std::string path = tempDir() + "/" + name;
  writeText(path, text);
  return path;
}

/// A 2 × 1.5 × 2 m room (albedo 0.6, inward normals) with a box on the floor, and IES light @p light
/// (the JSON object of one light) inside; the camera looks across the room (32 × 24).
inline std::string iesRoom(const std::string& light, int maxDepth = 4) {
  return fmt::format(R"({{"materials": {{"white": {{"type": "diffuse", "albedo": 0.6}},
      "red": {{"type": "diffuse", "albedo": [0.7, 0.2, 0.1]}}}},
    "shapes": [{{"type": "box", "material": "white", "min": [0,0,0], "max": [2,1.5,2], "flip_normals": true}},
               {{"type": "box", "material": "red", "min": [0.5,0,0.6], "max": [1.0,0.4,1.1]}}],
    "lights": [{}],
    "camera": {{"position": [1.7, 1.0, 0.1], "look_at": [0.8, 0.3, 1.3], "fov_y": 75, "resolution": [32, 24]}},
    "settings": {{"patch_size": 0.25, "max_depth": {}}}}})",
                     light, maxDepth);
}

}  // namespace firstshot::test
