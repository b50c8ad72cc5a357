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
#include <cstdint>
#include <vector>

#include "common/math.h"
#include "render/integrators/integrator.h"
#include "render/scene/render_scene.h"

namespace fs {

/// One vertex of a raster triangle.
struct RasterVertex {
  Vec3 position{0.0f};
  Vec3 normal{0.0f, 0.0f, 1.0f};  ///< the patch's geometric normal (front side)
  Color front{0.0f};              ///< radiance (or headlight base colour) seen from the front side
  Color back{0.0f};               ///< ... and from the back side
  float headlight = 0.0f;         ///< 1: multiply by |cos| to the viewing direction; 0: show as is
};

struct RasterMesh {
  std::vector<RasterVertex> triangles;  ///< three vertices per triangle
  std::vector<Vec3> edges;              ///< patch outlines, two points per line segment
  Vec3 lo{0.0f}, hi{0.0f};              ///< bounds of all vertices
  bool firstShot = false;               ///< coloured by the first-shot table
};

/// Builds the instant picture of @p scene: first-shot radiance when @p useFirstShot and the scene
/// has a table, headlight shading otherwise. Emissive shapes show their radiance on the front.
RasterMesh buildRasterMesh(const RenderScene& scene, bool useFirstShot);

/// Per patch j, the first-shot irradiance from samples in front of (index 2j) and behind (2j + 1)
/// its plane (the split PathIntegrator uses). Empty without a table.
std::vector<Color> sideIrradiance(const RenderScene& scene);

/// Line segments (two points each) drawing every record as a circle of its radius in its
/// tangent plane, with @p segments segments per circle.
std::vector<Vec3> recordCircles(const std::vector<IntegratorRecord>& records, int segments = 16);

}  // namespace fs
