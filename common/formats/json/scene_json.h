#pragma once
/// @file scene_json.h
/// The JSON scene format (docs/scene-format.md) → SceneDesc; scene_json.cpp.

#include <string>

#include "common/scene/scene_desc.h"

namespace firstshot {

/// Loads a JSON scene from text; @p path is used for messages and to resolve relative mesh files.
SceneDesc parseSceneJson(const std::string& text, const std::string& path);

}  // namespace firstshot
