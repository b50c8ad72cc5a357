#pragma once
/// @file load_scene.h
/// A scene file of any format → SceneDesc, by its extension: JSON (formats/json/), Mitsuba XML
/// (formats/mitsuba/), an asset (formats/assets/); then validated (validateScene).

#include <string>

#include "common/scene/scene_desc.h"

namespace firstshot {

/// Loads a scene: .json (docs/scene-format.md), a Mitsuba 3 .xml (common/formats/mitsuba/scene_mitsuba.h) or .obj/.gltf/.glb/.ply directly.
/// @throws InputError naming the file and element for any bad input.
SceneDesc loadScene(const std::string& path);

}  // namespace firstshot
