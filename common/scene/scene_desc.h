#pragma once
/// @file scene_desc.h
/// The scene as plain data: parsed once from a file, validated, then only read. Geometry is already
/// resolved to world-space polygons (metres, right-handed, y up); names keep the place in the input
/// file so that later stages can still report errors precisely.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/materials/conductor_fresnel.h"
#include "common/materials/microfacet_model.h"
#include "common/util/math.h"

namespace firstshot {

/// Pbr is the glTF 2.0 metallic-roughness model (common/materials/bsdf.h, MetallicRoughnessBRDF); ThinGlass a window
/// pane that transmits without displacing the ray (common/materials/thin_glass.h).
enum class MaterialType : uint8_t { Diffuse, Glossy, Mirror, Dielectric, Pbr, ThinGlass };

struct Texture;  // common/materials/texture.h

/// How a material's alpha (coverage) is used (glTF's alphaMode): opaque ignores it; mask makes the
/// surface absent where alpha < the cut-off (leaves, fences, grilles, perforated shades); blend lets a ray pass a
/// point with probability 1 − alpha (stochastic transparency, decided by a hash of the ray and the hit).
enum class AlphaMode : uint8_t { Opaque, Mask, Blend };

/// A surface material. Emission makes the surface an area light (one-sided, front face).
struct MaterialDesc {
  std::string name;
  MaterialType type = MaterialType::Diffuse;
  Color albedo{0.0f};    ///< diffuse reflectance (diffuse, and the diffuse part of glossy); pbr: the base colour
  Color specular{0.0f};  ///< glossy: the lobe's albedo bound (ks = specular·(n+1)/2π, see makeBSDF); mirror: reflectance
  float exponent = 1.0f; ///< glossy: Phong exponent n
  float ior = 1.5f;      ///< dielectric, pbr, thin glass: index of refraction (outside is 1)
  float metallic = 1.0f;  ///< pbr: metalness ∈ [0, 1] (glTF's default 1)
  float roughness = 1.0f; ///< pbr: perceptual roughness ∈ [0, 1] (GGX α = roughness², common/materials/microfacet.h)
  Color transmittance{1.0f};  ///< dielectric: tint of refracted light; thin glass: the pane's transmittance at normal incidence
  float glassRoughness = 0.0f;  ///< dielectric, thin glass: perceptual roughness ∈ [0, 1] (0 smooth; > 0 frosted glass)
  /// Mirror and pbr: a conductor's Fresnel (common/materials/conductor_fresnel.h). Set, the mirror reflects specular × F(|cos θ|)
  /// and the pbr material's metal part has the Fresnel base colour × F(c) (a tint times the metal's exact Fresnel, as
  /// Mitsuba's conductors) instead of the same reflectance at every angle (mirror) or Schlick's from F0 = base colour
  /// (pbr). Unset: those, as for every material that does not ask for it.
  std::optional<ConductorFresnel> conductor;
  /// Pbr: the specular lobe's microfacet distribution (GGX, glTF's; Beckmann where a scene file asks for it).
  MicrofacetModel microfacet = MicrofacetModel::Ggx;
  Color emission{0.0f};  ///< emitted radiance, W/(m² sr)
  /// Diffuse and glossy: a base-colour texture; at a point with texture coordinates uv the diffuse reflectance
  /// is albedo × texture.lookup(uv) (albedo is then the factor, 1 by default; render/scene/surface_texture.h).
  /// Null: none. Shared, immutable once loaded.
  std::shared_ptr<const Texture> albedoTexture;
  /// Pbr: a metallic-roughness texture, glTF's layout (roughness in G, metallic in B, linear values); at a point
  /// the metallic and roughness are the factors above × the texture there. Null: none.
  std::shared_ptr<const Texture> metallicRoughnessTexture;
  // Alpha cut-outs (docs/scene-format.md, "Cut-outs"; common/patches/patch_cutouts.h) ---------------------
  AlphaMode alphaMode = AlphaMode::Opaque;
  float alphaCutoff = 0.5f;  ///< mask: the surface exists where alpha ≥ this (glTF's default 0.5)
  float alpha = 1.0f;        ///< the alpha factor: alpha at a point is this × the alpha texture there
  /// The alpha texture: its image's alpha channel, or its first channel (linear) when it has none; may be the
  /// base-colour texture itself (its A channel). Null: alpha is the factor alone.
  std::shared_ptr<const Texture> alphaTexture;
  /// Whether some points of the surface may be absent (a mask or blend alpha mode).
  bool isCutout() const { return alphaMode != AlphaMode::Opaque; }
  // ----------------------------------------------------------------------------------------------------------
  // --- Shading normals ---
  /// A tangent-space normal map (glTF's normalTexture: +x along u, +y up the image, linear texels in [0, 1] mapped
  /// to 2t − 1), read through the shape's texture coordinates; null: none. The shading normal at a point is the
  /// texel's direction in the tangent frame of the interpolated normal (render/scene/shading_normals.h).
  std::shared_ptr<const Texture> normalTexture;
  float normalScale = 1.0f;  ///< glTF's normalTexture.scale: multiplies the texel's x and y (after 2t − 1)
  // --- Emission per point (common/materials/emission_texture.h) ---
  /// An emission texture (sRGB-decoded): on a shape with texture coordinates the radiance at a point is
  /// emissionFactor × the texel there, and `emission` is its mean over the surface (what the light's power is
  /// taken from). Null: `emission` everywhere.
  std::shared_ptr<const Texture> emissionTexture;
  Color emissionFactor{0.0f};  ///< W/(m² sr): what the emission texture's texels multiply
  /// Whether any property varies over the surface (a texture to look up per point).
  bool hasTextures() const { return albedoTexture || metallicRoughnessTexture; }
  bool isEmissive() const { return maxComponent(emission) > 0.0f; }
};

/// Whether a light is replaced by first-shot ("small") or stays in the renderer ("large").
enum class SmallOverride : uint8_t { Auto, Small, Large };

enum class LightType : uint8_t { Point, Spot, Directional, Area };

struct IesData;  // common/lights/ies.h

/// A light. Area lights point at the emissive shape they come from.
struct LightDesc {
  std::string name;          ///< where it was defined, e.g. "lights[2]" or "shapes[5]"
  LightType type = LightType::Point;
  Vec3d position{0.0};       ///< point, spot
  Vec3d direction{0, -1, 0}; ///< spot: axis (IES: photometric axis); directional: direction light travels in (unit)
  Color power{0.0f};         ///< point, spot: total emitted power, W (whatever unit the scene gave)
  Color irradiance{0.0f};    ///< directional: irradiance on a plane facing the light, W/m²
  double innerAngleDeg = 30; ///< spot: full intensity inside this half-angle
  double outerAngleDeg = 45; ///< spot: zero intensity outside this half-angle (smoothstep between)
  /// An IES light ("type": "ies") is a spot whose profile is this photometric table instead of the
  /// cone (common/lights/emission_profile.h); the angles above are then unused.
  std::shared_ptr<const IesData> ies;
  Vec3d iesReference{0.0};   ///< IES: C0 half-plane (type C) or up (types A, B); zero: the default
  int shape = -1;            ///< area: index into SceneDesc::shapes
  SmallOverride small = SmallOverride::Auto;
  /// The luminaire it belongs to (the scene's "luminaire" key; common/table/luminaire.h): lights and shapes of one name form
  /// one luminaire, whose box bounds them. Empty: none named (the preprocessor may still detect one). An area light
  /// takes its shape's. Never set on a directional light.
  std::string luminaire;
};

enum class ShapeType : uint8_t { Quad, Box, Sphere, Mesh };

/// A polygon of a shape: 3 or 4 vertex indices, counter-clockwise seen from the front (normal side).
struct Face {
  uint32_t v[4] = {0, 0, 0, 0};
  uint8_t count = 3;
};

/// A shape, resolved to world-space polygons. Quads are planar (non-planar input quads are split).
struct ShapeDesc {
  std::string name;        ///< e.g. "shapes[3]" plus the user's name if given
  ShapeType type = ShapeType::Quad;
  int material = 0;        ///< index into SceneDesc::materials
  std::string sourceFile;  ///< mesh: the file the triangles came from
  std::vector<Vec3d> vertices;
  std::vector<Face> faces;
  /// Texture coordinates per face corner, (u, v) as glTF defines them (u right, v down from the image's top
  /// edge; OBJ's vt is flipped to this): uv[4·f + k] for corner k of faces[f], unused corners (0, 0). Empty:
  /// the shape has none. Per corner rather than per vertex because mesh vertices are welded by position
  /// (common/formats/assets/mesh_import.cpp), and a texture seam gives one position two coordinates.
  std::vector<Vec2> uv;
  // --- Shading normals ---
  /// Unit shading normals per face corner, world space, as uv: normals[4·f + k] (unused corners 0). Empty: the
  /// shape is shaded flat (its geometric normals; the built-in shapes, and meshes without normals in their file).
  /// Their side does not decide the front: a face's winding does, and normals that point behind it are turned.
  std::vector<Vec3> normals;
  bool hasNormals() const { return !normals.empty(); }
  /// The shading normal of corner @p k of faces[@p f] (hasNormals() must hold).
  Vec3 cornerNormal(size_t f, int k) const { return normals[4 * f + size_t(k)]; }
  // --- Tangent frames from the file (glTF's TANGENT) ---
  /// The file's tangent frame per face corner, world space, as normals: tangents[4·f + k] (xyz of glTF's TANGENT,
  /// along which a normal map's +x points) and bitangents[4·f + k] (its w × NORMAL × TANGENT, the map's +y), both
  /// transformed as surface vectors (by the shape's matrix, not the inverse transpose). 0 at a corner without one.
  /// Empty: the shape has none, and normal maps use the frame generated per triangle (render/scene/shading_normals.h).
  std::vector<Vec3> tangents, bitangents;
  bool hasTangents() const { return !tangents.empty(); }
  SmallOverride small = SmallOverride::Auto;  ///< for emissive shapes
  /// The luminaire the shape belongs to (the scene's "luminaire" key): its bounds are part of that luminaire's box
  /// (a bowl, a shade, a glass envelope, or the emitter itself). Empty: none.
  std::string luminaire;

  bool hasUv() const { return !uv.empty(); }
  /// The texture coordinates of corner @p k of faces[@p f] (hasUv() must hold).
  Vec2 cornerUv(size_t f, int k) const { return uv[4 * f + size_t(k)]; }
};

/// The image axis whose field of view a scene fixes (common/scene/camera_fov.h): the vertical one (JSON's fov_y), the
/// horizontal one, the diagonal, or the smaller or larger of width and height (Mitsuba's `fov_axis`).
enum class FovAxis : uint8_t { Y, X, Diagonal, Smaller, Larger };

/// Pinhole camera.
struct CameraDesc {
  Vec3d position{0, 1, 3};
  Vec3d lookAt{0, 1, 0};
  Vec3d up{0, 1, 0};
  double fovYDeg = 45;  ///< vertical field of view at width × height, degrees
  int width = 512, height = 512;
  /// The axis whose field of view the scene gave: a new resolution (resizeCamera, firstshot-render's --width and
  /// --height) keeps the field on this axis and recomputes fovYDeg from it. Y for JSON scenes and assets.
  FovAxis fovAxis = FovAxis::Y;
  bool given = false;   ///< false when framed automatically
};

/// The preprocessor's settings: the ones that change a first-shot table's factors. One struct from the
/// scene file to the table: the scene's `settings` block fills it (SettingsDesc below, docs/scene-format.md),
/// firstshot-preprocess's command line overrides it and its automatic values are resolved, both in one
/// function (preprocess/preprocessor.h, resolveSettings), and the .fsd keeps it as resolved (its SETT
/// section and settings hash, common/table/firstshot.h). Each field means the same everywhere; a 0 that says
/// "automatic" below is replaced by its value in resolveSettings (common/patches/patch_size.h, resolvePatchSizes),
/// so a table holds the sizes its factors were made with.
struct FirstShotSettings {
  uint32_t resolution = 256;       ///< R: pixels across a full cube face of the item buffers, even (scene: item_buffer_resolution)
  std::string window = "hemicube"; ///< the window at area-light vertices: hemicube | tetra
  std::string backend = "gl";      ///< item buffers: gl | embree | auto (per light sample, preprocess/preprocessor.cpp autoBackend); command line only
  double patchSize = 0;            ///< longest patch edge of the coarse mesh adaptive refinement starts from, m; 0: automatic, from the scene's faces (common/patches/patch_size.h)
  double minPatchSize = 0;         ///< smallest patch edge refinement may reach, m; 0: patchSize/kDefaultRefineRatio; ≥ patchSize: a uniform mesh (taken as patchSize)
  double refineTolerance = 0.02;   ///< split a patch whose shadow-edge measure exceeds this fraction of its irradiance (docs/firstshot-format.md)
  double lightPatchSize = 0;       ///< longest edge of an area light's tessellation, m; 0: automatic from lightTolerance (stays 0: a rule, not a length)
  double lightTolerance = 0.01;    ///< automatic light tessellation: relative error of the vertex rule at the nearest receiver
  double smallLightMaxSolidAngle = 1.0;  ///< sr: an "auto" area light is small up to this solid angle; see docs/scene-format.md
  std::string estimator = "analytic";  ///< analytic: closed form × visible fraction (preprocess/coverage.h) | pixels: Σ pixel weights; command line only
  uint64_t rotationSeed = 0;       ///< 0: windows aligned with the light frame; else a random rotation per sample; command line only (--seed)
  /// A hash of every field, written into the .fsd's header (common/table/firstshot.cpp).
  uint64_t hash() const;
};

/// The scene file's `settings` block: the preprocessor's settings (FirstShotSettings, whose fields it
/// reads as they are: scene.settings.patchSize is the table's patchSize before resolving) and the
/// renderer's. Command-line options override them: firstshot-preprocess's in resolveSettings,
/// firstshot-render's in render/cli/render_command.cpp.
struct SettingsDesc : FirstShotSettings {
  int spp = 64;                    ///< samples per pixel
  uint64_t seed = 1;               ///< the renderer's random seed (not the preprocessor's rotationSeed)
  int maxDepth = 16;               ///< longest path, in bounces
};

struct SkyDesc;          // common/scene/sky_desc.h
struct EnvironmentDesc;  // common/scene/sky_desc.h

/// The whole scene.
struct SceneDesc {
  std::string file;  ///< the file it was read from
  CameraDesc camera;
  std::vector<MaterialDesc> materials;
  std::vector<ShapeDesc> shapes;
  std::vector<LightDesc> lights;  ///< including one Area entry per emissive shape
  SettingsDesc settings;
  /// Daylight (common/scene/sky_desc.h): a sky model or an environment map, at most one, lighting the scene from
  /// infinitely far away (a large light of the renderer, never replaced by first-shot). Null: none. The sun is a
  /// directional light in @c lights.
  std::shared_ptr<const SkyDesc> sky;
  std::shared_ptr<const EnvironmentDesc> environment;

  /// Index of a material by name, or -1.
  int findMaterial(const std::string& name) const;
  /// Axis-aligned bounds of all shape vertices and positional lights.
  void bounds(Vec3d& lo, Vec3d& hi) const;
};

/// Checks a parsed scene (finite numbers, ranges, degenerate geometry, emitter area) and fills in
/// derived data (area lights for emissive shapes, camera framing). @throws InputError.
void validateScene(SceneDesc& scene);

/// A stable 64-bit content hash of everything in the scene that changes results.
uint64_t hashScene(const SceneDesc& scene);

}  // namespace firstshot
