#pragma once
/// @file hidden_lights_scenes.h
/// Scenes whose light hides (BDPT with a table, luminaires): a bulb in an open metal bowl, a filament in a clear
/// glass envelope, a point light in a box open towards the camera, in a small furnished room; and their first-shot
/// table with the luminaires found.
#include <string>

#include "common/scene/scene_desc.h"
#include "preprocess/preprocessor.h"
#include "render/scene/render_scene.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

namespace firstshot::test {

/// A 2 m × 1.5 m × 2 m room with a table (32×24, max depth 6); @p materials and @p shapes add the lamp's (JSON members).
inline SceneDesc hiddenLightsRoom(const std::string& materials, const std::string& shapes) {
  return test::sceneFromJson(R"({"materials": {"wall": {"type": "diffuse", "albedo": 0.7},
      "floor": {"type": "diffuse", "albedo": [0.5, 0.4, 0.3]}, "table": {"type": "diffuse", "albedo": [0.6, 0.6, 0.55]}, )" +
                             materials + R"(},
    "shapes": [{"type": "box", "material": "wall", "min": [0,0,0], "max": [2,1.5,2], "flip_normals": true},
               {"type": "quad", "material": "floor", "vertices": [[0,0.001,0],[0,0.001,2],[2,0.001,2],[2,0.001,0]]},
               {"type": "box", "material": "table", "min": [0.2,0,1.1], "max": [0.9,0.5,1.7]}, )" +
                             shapes + R"(],
    "camera": {"position": [1.9, 0.9, 1.9], "look_at": [0.6, 0.6, 0.5], "fov_y": 70, "resolution": [32, 24]},
    "settings": {"patch_size": 0.4, "max_depth": 6}})");
}

/// A bulb (r = 3 cm) in an open metal bowl (pbr, roughness 0.5, 24 cm × 24 cm × 10 cm) at 0.9 m.
inline SceneDesc bowlLamp() {
  return hiddenLightsRoom(R"("bowl": {"type": "pbr", "base_color": [0.8, 0.75, 0.7], "metallic": 1, "roughness": 0.5},
                 "bulb": {"type": "diffuse", "emission": 60})",
              R"({"type": "quad", "material": "bowl", "vertices": [[1.28,0.9,0.88],[1.52,0.9,0.88],[1.52,0.9,1.12],[1.28,0.9,1.12]]},
                 {"type": "quad", "material": "bowl", "vertices": [[1.28,0.9,0.88],[1.28,0.9,1.12],[1.28,1.0,1.12],[1.28,1.0,0.88]]},
                 {"type": "quad", "material": "bowl", "vertices": [[1.52,0.9,0.88],[1.52,1.0,0.88],[1.52,1.0,1.12],[1.52,0.9,1.12]]},
                 {"type": "quad", "material": "bowl", "vertices": [[1.28,0.9,0.88],[1.28,1.0,0.88],[1.52,1.0,0.88],[1.52,0.9,0.88]]},
                 {"type": "quad", "material": "bowl", "vertices": [[1.28,0.9,1.12],[1.52,0.9,1.12],[1.52,1.0,1.12],[1.28,1.0,1.12]]},
                 {"type": "sphere", "material": "bulb", "center": [1.4, 0.94, 1.0], "radius": 0.03, "subdivisions": 2})");
}

/// A filament (r = 8 cm, so that the path tracer's BSDF samples find it) inside a clear glass envelope (r = 20 cm,
/// ior 1.5) hanging at 1.1 m; with @p roughness > 0 a frosted one (rough glass).
inline SceneDesc glassBulb(double roughness = 0) {
  return hiddenLightsRoom(R"("glass": {"type": "dielectric", "ior": 1.5, "roughness": )" + std::to_string(roughness) +
                              R"(}, "filament": {"type": "diffuse", "emission": 12})",
              R"({"type": "sphere", "material": "glass", "center": [1.2, 1.1, 1.0], "radius": 0.2, "subdivisions": 3, "smooth": true},
                 {"type": "sphere", "material": "filament", "center": [1.2, 1.1, 1.0], "radius": 0.08, "subdivisions": 2})");
}

/// A point light (2 W) in a 30 cm box of grey diffuse walls whose face towards the camera is open, on a stand in the
/// hidden-lights room; the camera looks into the opening from 0.8 m. With @p areaLight a diffuse sphere of 2 cm
/// radius (emission 100 W/(m² sr), ≈ 1.6 W) instead: an area light a record's rays meet by chance. With @p glassBall
/// a clear glass ball (r = 12 cm, ior 1.5) 0.6 m in front of the opening, outside the box, in the light that leaves
/// it, and the camera on the far side of the room looking past the ball at what it focuses on the wall behind it.
inline SceneDesc openBox(bool areaLight = false, bool glassBall = false) {
  const std::string box =
      R"({"type": "quad", "material": "shade", "vertices": [[1.0,0.8,0.6],[1.3,0.8,0.6],[1.3,0.8,0.9],[1.0,0.8,0.9]]},
         {"type": "quad", "material": "shade", "vertices": [[1.0,1.1,0.6],[1.0,1.1,0.9],[1.3,1.1,0.9],[1.3,1.1,0.6]]},
         {"type": "quad", "material": "shade", "vertices": [[1.0,0.8,0.6],[1.0,0.8,0.9],[1.0,1.1,0.9],[1.0,1.1,0.6]]},
         {"type": "quad", "material": "shade", "vertices": [[1.3,0.8,0.6],[1.3,1.1,0.6],[1.3,1.1,0.9],[1.3,0.8,0.9]]},
         {"type": "quad", "material": "shade", "vertices": [[1.0,0.8,0.6],[1.0,1.1,0.6],[1.3,1.1,0.6],[1.3,0.8,0.6]]})";
  const std::string shade = std::string(R"("shade": {"type": "diffuse", "albedo": 0.6})") +
                            (glassBall ? R"(, "glass": {"type": "dielectric", "ior": 1.5})" : "");
  const std::string shapes =
      box + (glassBall ? R"(, {"type": "sphere", "material": "glass", "center": [1.15, 0.7, 1.3], "radius": 0.12,
                               "subdivisions": 4, "smooth": true})"
                       : "");
  SceneDesc d =
      areaLight ? hiddenLightsRoom(shade + R"(, "bulb": {"type": "diffuse", "emission": 100})",
                                   shapes + R"(, {"type": "sphere", "material": "bulb", "center": [1.15, 0.95, 0.7],
                                              "radius": 0.02, "subdivisions": 2})")
                : hiddenLightsRoom(shade, shapes + R"(], "lights": [{"type": "point", "position": [1.15, 0.95, 0.7], "power": 2})");
  d.camera.position = glassBall ? Vec3d(0.5, 0.9, 0.4) : Vec3d(1.35, 1.05, 1.6);
  d.camera.lookAt = glassBall ? Vec3d(1.15, 0.3, 2.0) : Vec3d(1.15, 0.95, 0.75);
  d.camera.fovYDeg = 60;
  return d;
}

/// @p d with its first-shot table (Embree item buffers, R = 64, luminaires found at the defaults with 2^19
/// particles each).
inline RenderScene withLuminaireTable(const SceneDesc& d) {
  PreprocessOptions po = defaultOptions(d);
  po.settings.backend = "embree", po.settings.resolution = 64, po.quiet = true;
  po.luminaires.particles = 1u << 19;
  return RenderScene(d, preprocessScene(d, po));
}

}  // namespace firstshot::test
