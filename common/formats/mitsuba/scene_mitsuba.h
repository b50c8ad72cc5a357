#pragma once
/// @file scene_mitsuba.h
/// Mitsuba 3 XML scenes read directly (pugixml) into SceneDesc: shapes, bsdfs, emitters, the
/// perspective sensor and the render settings they carry. The mapping of each plugin and what is
/// approximated or refused: docs/scene-format.md, "Mitsuba 3 XML scenes".
#include <string>

#include "common/scene/scene_desc.h"

namespace firstshot {

/// Loads the Mitsuba scene file @p path (not yet validated: loadScene calls validateScene).
/// @throws InputError naming the file, the element path and its line.
SceneDesc loadSceneMitsuba(const std::string& path);

/// Parses a Mitsuba scene from @p text; @p path names it in messages and resolves relative mesh files.
/// Approximations are printed once per kind on stderr, unused properties as one count line.
SceneDesc parseSceneMitsuba(const std::string& text, const std::string& path);

}  // namespace firstshot
