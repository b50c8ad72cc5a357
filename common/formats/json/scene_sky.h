#pragma once
/// @file scene_sky.h
/// The JSON scene format's daylight keys (docs/scene-format.md "Sky, sun and environment"):
/// - "sky": a CIE overcast, CIE clear or Perez sky → SceneDesc::sky (common/scene/sky_desc.h);
/// - "sun", inside "sky" or at the top level: the sun's place in the sky from a direction or from a latitude,
///   longitude, time zone, date and time (common/lights/sun_position.h), and its irradiance, given or (Perez) the model's
///   direct part → a directional LightDesc named after the key, appended to SceneDesc::lights (so first-shot
///   replaces it like any directional light);
/// - "environment": a lat-long image file, scale and rotation → SceneDesc::environment.
/// Sky and environment exclude each other.
#include "common/formats/json/scene_json_reader.h"
#include "common/scene/scene_desc.h"

namespace firstshot {

/// Reads the keys above from the scene's @p root object into @p scene (after its lights were read).
/// @throws InputError naming the file and the key.
void parseDaylight(const SceneJsonReader& r, const Json& root, SceneDesc& scene);

}  // namespace firstshot
