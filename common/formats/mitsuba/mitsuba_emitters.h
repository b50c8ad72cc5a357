#pragma once
/// @file mitsuba_emitters.h
/// The top-level `<emitter>` elements of a Mitsuba scene → SceneDesc (docs/scene-format.md, "Mitsuba 3 XML scenes",
/// *Emitters*): `point`, `spot` and `directional` become lights; Mitsuba 0.6's daylight (`sunsky`, `sky`, `sun`)
/// becomes a Preetham sky (common/lights/sky_models.h) scaled to Mitsuba's brightness (common/formats/mitsuba/mitsuba_daylight.h) and a
/// directional sun; `envmap` and `constant` become the scene's environment. Area emitters belong to shapes
/// (common/formats/mitsuba/scene_mitsuba.cpp).
#include <filesystem>
#include <functional>
#include <string>

#include <pugixml.hpp>

#include "common/formats/mitsuba/mitsuba_xml.h"
#include "common/scene/scene_desc.h"

namespace firstshot::mitsuba {

/// Resolves a file name of the scene (relative to its folder or a `<path>`).
using FileResolver = std::function<std::filesystem::path(const std::string&)>;

/// Reads the emitter @p node into @p scene. @throws InputError naming the element and its line.
void readEmitter(Document& doc, pugi::xml_node node, SceneDesc& scene, const FileResolver& resolve);

}  // namespace firstshot::mitsuba
