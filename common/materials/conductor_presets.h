#pragma once
/// @file conductor_presets.h
/// Named conductors: Mitsuba's `material` presets as RGB η, k (relative to vacuum), reduced from the measured
/// spectral optical constants Mitsuba ships for each name by Mitsuba's own RGB reduction (scripts/conductor_presets.py
/// states the source and the reduction; docs/scene-format.md lists the names).
#include <optional>
#include <string>
#include <string_view>

#include "common/materials/conductor_fresnel.h"

namespace firstshot {

/// The conductor named @p name (case as Mitsuba spells it: "Au", "Cu_palik", "a-C"), or "none", the ideal mirror
/// (η = 0, k = 1: F = 1 at every angle); nullopt for a name not in the table.
std::optional<ConductorFresnel> conductorPreset(std::string_view name);

/// The names conductorPreset knows, comma-separated, for error messages.
std::string conductorPresetNames();

}  // namespace firstshot
