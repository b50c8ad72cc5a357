#pragma once
/// @file emission_texture.h
/// Emission that varies over a surface: a material's emission texture (glTF's emissiveTexture, the JSON's
/// `emission_texture`) read per point through the shape's texture coordinates. The radiance at a point is
/// MaterialDesc::emissionFactor × the texel there (bilinear, with its wrap modes and transform; sRGB-decoded);
/// MaterialDesc::emission stays the surface's mean radiance, so that everything that needs a light's power (which
/// light to choose, the small-light rule, the preview) reads it as before. The renderer's LightSet
/// (render/scene/light_set.h) and the preprocessor's light tessellation (preprocess/light_tessellation.h) are the two
/// users; both read the radiance through the functions below, so they agree point by point.
#include <cstddef>

#include "common/scene/scene_desc.h"
#include "common/util/math.h"

namespace firstshot {

/// Whether shape @p s of material @p m emits per point: @p m has an emission texture and @p s texture coordinates
/// (a shape without them emits @p m.emission, the mean, everywhere).
bool emitsPerPoint(const MaterialDesc& m, const ShapeDesc& s);

/// Emitted radiance (W/(m² sr)) at texture coordinates @p uv of material @p m, which has an emission texture.
Color emissionAt(const MaterialDesc& m, const Vec2& uv);

/// The texture coordinates at point @p p of face @p f of @p s (which has them): the face's triangle that holds p (a
/// quad is cut along v0–v2, as everywhere) and p's barycentric coordinates in it, p projected onto its plane.
Vec2 faceUvAt(const ShapeDesc& s, size_t f, const Vec3d& p);

/// Calls @p f(β, γ) at the centroids of the @p n² congruent sub-triangles of a triangle (β, γ: barycentric
/// coordinates of its vertices 1 and 2), each standing for 1/n² of its area: a midpoint rule.
template <typename F>
void forEachSubTriangleCentroid(int n, const F& f) {
  const float inv = 1.0f / float(n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      f((float(i) + 1.0f / 3.0f) * inv, (float(j) + 1.0f / 3.0f) * inv);                   // upright
      if (i + j + 1 < n) f((float(i) + 2.0f / 3.0f) * inv, (float(j) + 2.0f / 3.0f) * inv);  // inverted
    }
}

/// The mean of emissionAt over the triangle of texture coordinates @p uv0, @p uv1, @p uv2 (a midpoint rule on
/// @p n² congruent sub-triangles: exact for a texture that is constant on each).
Color meanEmissionOverTriangle(const MaterialDesc& m, const Vec2& uv0, const Vec2& uv1, const Vec2& uv2, int n = 16);

}  // namespace firstshot
