#pragma once
/// @file raster_mesh.h
/// The preview's instant picture as triangles (CPU side, no OpenGL): every patch of the traced mesh
/// flat-coloured by its first-shot radiance, and every emissive shape with its emitted radiance.
///
/// With a first-shot table, a diffuse patch j shows on each side of its plane
///     L = ρ/π · E_side(j),   E_side(j) = Σ_{samples i on that side} emission_i · r_ij,
/// which is what the path integrator adds at a camera-visible patch with --primary patch (for
/// glossy patches the raster keeps the diffuse part only). Without a table (or with it switched
/// off) patches show their albedo under a headlight: ρ·|cos θ| to the viewing direction.
///
/// Textures: a patch of a material with an albedo (base-colour) texture carries texture
/// coordinates per vertex (the KHR transform already applied: it is affine, so interpolating the
/// transformed corners is exact) and the factor ρ_factor / ρ̄_patch, so that the GPU shows
///     L(x) = flat colour · ρ_factor · texel(x) / ρ̄_patch = flat colour · ρ(x) / ρ̄_patch,
/// the texture's detail on the patch's mean (a diffuse side's radiance is ∝ its albedo).
/// A cut-out patch carries its alpha texture coordinates and its batch the alpha rule (RasterCutout): the GPU
/// discards the fragments where the surface is absent. Shading normals are not drawn: a patch side is flat.
/// An emitter with an emission texture is a textured batch too: texScale = the emission factor, so it shows
/// factor × texel per point.
#include <cstdint>
#include <memory>
#include <vector>

#include "common/materials/texture.h"
#include "common/util/math.h"
#include "render/integrators/integrator.h"
#include "render/scene/render_scene.h"

namespace firstshot {

/// One vertex of a raster triangle.
struct RasterVertex {
  Vec3 position{0.0f};
  Vec3 normal{0.0f, 0.0f, 1.0f};  ///< the patch's geometric normal (front side)
  Color front{0.0f};              ///< radiance (or headlight base colour) seen from the front side
  Color back{0.0f};               ///< ... and from the back side
  float headlight = 0.0f;         ///< 1: multiply by |cos| to the viewing direction; 0: show as is
  Vec2 uv{0.0f};                  ///< texture coordinates after the texture's transform (textured batches)
  Color texScale{1.0f};           ///< ρ_factor / ρ̄_patch per channel (textured batches; 0 where ρ̄ is 0)
  Vec2 alphaUv{0.0f};             ///< alpha texture coordinates after its transform (cut-out batches)
};

/// How a cut-out batch's fragments are kept (common/patches/patch_cutouts.h): where alpha = factor × the alpha
/// texture (bilinear, its wrap modes; the mean where the shape has no texture coordinates) reaches the cut-off
/// (mask), or with probability alpha by a hash of the pixel (blend: a screen-door dither).
struct RasterCutout {
  std::shared_ptr<const Texture> alpha;  ///< null: alpha is @c mean everywhere
  AlphaMode mode = AlphaMode::Mask;
  float cutoff = 0.5f, factor = 1.0f, mean = 1.0f;
};

/// A run of consecutive triangles drawn with one albedo texture, or none.
struct RasterBatch {
  uint32_t first = 0;   ///< first vertex in RasterMesh::triangles
  uint32_t count = 0;   ///< vertices
  int texture = -1;     ///< index into RasterMesh::textures; -1: untextured (flat colours as they are)
  int cutout = -1;      ///< index into RasterMesh::cutouts; -1: opaque
};

struct RasterMesh {
  std::vector<RasterVertex> triangles;  ///< three vertices per triangle
  std::vector<RasterBatch> batches;     ///< the triangles in order, split where the texture changes
  std::vector<std::shared_ptr<const Texture>> textures;  ///< the albedo textures the batches use, each once
  std::vector<RasterCutout> cutouts;    ///< the cut-outs the batches use, one per (material, with texture or not)
  std::vector<Vec3> edges;              ///< patch outlines, two points per line segment
  Vec3 lo{0.0f}, hi{0.0f};              ///< bounds of all vertices
  bool firstShot = false;               ///< coloured by the first-shot table
};

/// Builds the instant picture of @p scene: first-shot radiance when @p useFirstShot and the scene
/// has a table, headlight shading otherwise. Emissive shapes show their radiance on the front.
/// Patches of albedo-textured materials (with texture coordinates) get textured batches, cut-out patches cut-out
/// batches.
RasterMesh buildRasterMesh(const RenderScene& scene, bool useFirstShot);

/// Per patch j, the first-shot irradiance from samples in front of (index 2j) and behind (2j + 1)
/// its plane (the split PathIntegrator uses). Empty without a table.
std::vector<Color> sideIrradiance(const RenderScene& scene);

/// Line segments (two points each) drawing every record as a circle of its radius in its
/// tangent plane, with @p segments segments per circle.
std::vector<Vec3> recordCircles(const std::vector<IntegratorRecord>& records, int segments = 16);

}  // namespace firstshot
