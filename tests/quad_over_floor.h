#pragma once
/// @file quad_over_floor.h
/// The scene of the material-key tests (test_rough_glass.cpp, test_thin_glass.cpp): a quad of one
/// material over a diffuse floor, parsed and validated as a file of a given name.
#include <string>

#include "common/formats/json/scene_json.h"
#include "common/scene/scene_desc.h"

namespace firstshot::test {

/// A 2 × 2 quad at y = 1 of the material @p name, given as JSON @p material, over a 2 × 2 floor of
/// albedo 0.5 at y = 0; parsed as the file @p file (the name errors quote).
inline SceneDesc quadOverFloor(const std::string& name, const std::string& material, const std::string& file) {
  SceneDesc s = parseSceneJson(R"({"materials": {"floor": {"type": "diffuse", "albedo": 0.5}, ")" + name + R"(": )" +
                                   material + R"(},
    "shapes": [{"type": "quad", "material": ")" + name + R"(", "vertices": [[-1, 1, -1], [-1, 1, 1], [1, 1, 1], [1, 1, -1]]},
               {"type": "quad", "material": "floor", "vertices": [[-1, 0, -1], [-1, 0, 1], [1, 0, 1], [1, 0, -1]]}]})",
                               file);
  validateScene(s);
  return s;
}

}  // namespace firstshot::test
