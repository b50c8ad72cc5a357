#pragma once
/// @file shaded_room.h
/// A test scene shared by the patch-NEE tests of the path tracer and the irradiance cache: a
/// 4 × 3 × 4 m room lit only by a point light inside an open-topped shade under the ceiling. The
/// camera sees no bulb, most shadow rays to it are blocked, and the lit patches (the ceiling above
/// the shade, the shade's inside) are small and bright. Plus the small, quick first-shot table
/// those tests use.
#include <string>

#include "common/scene/scene_desc.h"
#include "preprocess/preprocessor.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

namespace firstshot::test {

/// The shaded-light room with a square camera of @p resolution pixels.
inline SceneDesc shadedLightRoom(int resolution) {
  const std::string r = std::to_string(resolution);
  return sceneFromJson(R"({
  "materials": {"wall": {"type": "diffuse", "albedo": 0.7}, "shade": {"type": "diffuse", "albedo": 0.5}},
  "shapes": [
    {"type": "box", "min": [0, 0, 0], "max": [4, 3, 4], "material": "wall", "flip_normals": true},
    {"type": "quad", "material": "shade", "vertices": [[1.7, 2.2, 1.7], [2.3, 2.2, 1.7], [2.3, 2.2, 2.3], [1.7, 2.2, 2.3]]},
    {"type": "quad", "material": "shade", "vertices": [[1.7, 2.2, 1.7], [1.7, 2.7, 1.7], [2.3, 2.7, 1.7], [2.3, 2.2, 1.7]]},
    {"type": "quad", "material": "shade", "vertices": [[1.7, 2.2, 2.3], [2.3, 2.2, 2.3], [2.3, 2.7, 2.3], [1.7, 2.7, 2.3]]},
    {"type": "quad", "material": "shade", "vertices": [[1.7, 2.2, 1.7], [1.7, 2.2, 2.3], [1.7, 2.7, 2.3], [1.7, 2.7, 1.7]]},
    {"type": "quad", "material": "shade", "vertices": [[2.3, 2.2, 1.7], [2.3, 2.7, 1.7], [2.3, 2.7, 2.3], [2.3, 2.2, 2.3]]}
  ],
  "lights": [{"type": "point", "position": [2, 2.45, 2], "power": 60}],
  "camera": {"position": [3.6, 1.0, 0.4], "look_at": [1.2, 1.6, 3.6], "fov_y": 70, "resolution": [)" +
                       r + ", " + r + R"(]},
  "settings": {"patch_size": 0.25, "max_depth": 6}
})");
}

/// A quick first-shot table: Embree item buffers at R = 128, area lights cut at 0.05 m, the
/// scene's patch size unless @p patchSize > 0.
inline FirstShotTable quickTable(const SceneDesc& desc, double patchSize = 0) {
  PreprocessOptions po = defaultOptions(desc);
  po.settings.backend = "embree";
  po.settings.resolution = 128;
  if (patchSize > 0) po.settings.patchSize = patchSize;
  po.settings.lightPatchSize = 0.05;
  po.quiet = true;
  po.luminaires.mode = "off";  // the shaded light replaced by the table, as these tests mean (not a luminaire)
  return preprocessScene(desc, po);
}

}  // namespace firstshot::test
