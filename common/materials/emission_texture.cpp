// Emission that varies over a surface: the radiance at a point of a textured emitter (common/materials/emission_texture.h).
#include "common/materials/emission_texture.h"

#include "common/materials/texture.h"
#include "common/patches/patch_faces.h"

namespace firstshot {

bool emitsPerPoint(const MaterialDesc& m, const ShapeDesc& s) { return m.emissionTexture && s.hasUv(); }

Color emissionAt(const MaterialDesc& m, const Vec2& uv) { return m.emissionFactor * m.emissionTexture->lookup(uv); }

Vec2 faceUvAt(const ShapeDesc& s, size_t f, const Vec3d& p) {
  return faceTriangle(s, s.faces[f], p).interpolate<Vec2>([&](int k) { return s.cornerUv(f, k); });
}

Color meanEmissionOverTriangle(const MaterialDesc& m, const Vec2& uv0, const Vec2& uv1, const Vec2& uv2, int n) {
  Color sum(0.0f);
  forEachSubTriangleCentroid(n, [&](float b, float c) {
    sum += emissionAt(m, uv0 + b * (uv1 - uv0) + c * (uv2 - uv0));
  });
  return sum / float(n * n);
}

}  // namespace firstshot
