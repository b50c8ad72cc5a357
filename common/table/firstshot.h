#pragma once
/// @file firstshot.h
/// The first-shot table: the contract between firstshot-preprocess and firstshot-render.
///
/// For every patch j and light sample i the factor r_ij is such that the patch-averaged irradiance
/// that sample i delivers to patch j is E_ij = emission_i · r_ij, and the first-shot radiance
/// reflected at x on patch j towards ω is  Σ_i emission_i · r_ij · f_r(ω'_i, x, ω),
/// with ω'_i the direction from x to the sample (for directional lights, against the light's direction).
/// The average is over the patch's exposed part (docs/firstshot-format.md, "Buried parts"); the
/// renderer spreads it over the patch by the exact per-point term (render/firstshot/lighting.h).
/// Units of emission and r_ij by kind (docs/firstshot-format.md, "What it holds"):
///   Point, Spot:  emission = power Φ [W],        r_ij = Σ_p δω_p·I(p)/Φ / A_j      [1/m²]
///   Directional:  emission = irradiance E⊥ [W/m²], r_ij = Σ_p δA⊥_p / A_j           [1]
///   AreaVertex:   emission = radiance Le [W/m²sr], r_ij = (S_i/3)/A_j · Σ_p δω_p cosθL [sr]
#include <cstdint>
#include <string>
#include <vector>

#include "common/patches/patches.h"
#include "common/scene/scene_desc.h"
#include "common/table/luminaire.h"
#include "common/util/math.h"

namespace firstshot {

enum class LightSampleKind : uint32_t { Point = 0, Spot = 1, Directional = 2, AreaVertex = 3 };

/// One light sample: a point light, a spot, a directional light, or one vertex of a tessellated area light.
struct LightSample {
  LightSampleKind kind = LightSampleKind::Point;
  uint32_t light = 0;     ///< index into SceneDesc::lights
  Vec3 position{0.0f};    ///< world position (directional: unused)
  Vec3 normal{0, -1, 0};  ///< area: light normal; spot: axis; directional: direction the light travels
  Color emission{0.0f};   ///< Φ, E⊥ or Le by kind (see the file comment)
  float weight = 1.0f;    ///< area vertex: S_i/3 in m² (already inside r_ij); otherwise 1
};

// FirstShotSettings, the preprocess settings that change the factors (the SETT section, hashed into
// the header), is defined in common/scene/scene_desc.h: the scene's settings block is one (SettingsDesc).

/// The whole table, as read from or written to a .fsd file.
struct FirstShotTable {
  uint64_t sceneHash = 0;
  FirstShotSettings settings;           ///< as resolved (preprocess/preprocessor.h resolveSettings): patchSize > 0, 0 < minPatchSize ≤ patchSize
  PatchMesh mesh;                       ///< the patches the factors refer to
  std::vector<LightSample> samples;
  std::vector<uint32_t> replacedLights; ///< indices into SceneDesc::lights of the small lights
  /// Distance of an area vertex's window eye from the light's plane, along its normal, m
  /// (preprocess/window.h, areaLightEyeOffset): part of the analytic factors' closed form, which the
  /// file's grouped factors are recomputed from (common/table/firstshot_groups.h).
  double areaEyeOffset = 0;
  /// CSR over patches: the factors of patch j are [rowStart[j], rowStart[j+1]).
  std::vector<uint64_t> rowStart;       ///< size mesh.size()+1
  std::vector<uint32_t> sampleIndex;    ///< light sample of each factor
  std::vector<float> factor;            ///< r_ij
  /// Optional, per factor: the visible fraction V_ij recovered from r_ij for point lights and area
  /// vertices (common/table/firstshot_groups.h, recoveredVisible; −1 for other kinds), filled by
  /// readFirstShot while it expands the grouped factors. Empty: the renderer recovers it itself, to
  /// the same values.
  std::vector<float> visible;
  /// The luminaires (common/table/luminaire.h): their boxes, lights and exit distributions. Their lights are not in
  /// replacedLights: the renderer samples their exit patches instead.
  std::vector<Luminaire> luminaires;

  size_t nonZeros() const { return factor.size(); }
  /// True if SceneDesc::lights[l] is replaced by this table.
  bool replaces(uint32_t l) const;
  /// Patch-averaged irradiance on patch j (Σ_i emission_i r_ij), W/m².
  Color irradiance(uint32_t j) const;
  /// The same per side of each patch's plane: element 2j from samples in front of patch j (the normal
  /// side), 2j+1 from samples behind it. A patch is planar, so every point of it sees a sample on the
  /// same side; diffuse reflection then needs one lookup per hit.
  std::vector<Color> sideIrradiance() const;
};

/// Writes the table atomically (temp file, then rename). @throws std::runtime_error on I/O failure.
void writeFirstShot(const std::string& path, const FirstShotTable& table);

/// Reads and verifies a table: magic, version, end marker, checksum (common/util/binary_file.h), then every section's
/// size and contents. If @p expectedSceneHash is non-zero
/// it must match the file's scene hash. @throws InputError naming the file and the section at fault.
FirstShotTable readFirstShot(const std::string& path, uint64_t expectedSceneHash = 0);

}  // namespace firstshot
