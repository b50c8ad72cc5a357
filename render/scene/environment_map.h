#pragma once
/// @file environment_map.h
/// An environment map: radiance arriving from infinitely far away, from a latitude-longitude
/// (equirectangular) image, with a scale and a rotation about the up axis, importance-sampled by a piecewise-
/// constant 2D density (common/sampling/distribution_2d.h). The render scene's infinite light is one (render/scene/sky_light.h).
///
/// Mapping (scene frame, y up): a direction d, first rotated by −rotation about y, has θ = acos(d.y) from the zenith
/// and φ = atan2(d.x, −d.z); the texel is column ⌊(0.5 + φ/2π)·W⌋, row ⌊θ/π · H⌋ (row 0 at the top, the zenith),
/// so the image's centre is seen looking along −z and its right quarter along +x. Radiance is the texel's value
/// (piecewise constant, the same cells the density uses, so the estimator's weights L/pdf are exactly those of
/// the density). Texel (i, j) is drawn with probability ∝ luminance × sin θ_j (its solid angle), and the density
/// of a direction is p(u, v) / (2π² sin θ).
#include <string>
#include <vector>

#include "common/sampling/distribution_2d.h"
#include "common/util/math.h"

namespace firstshot {

class EnvironmentMap {
 public:
  /// @param texels width × height linear RGB radiances, W/(m² sr), row-major, top row first (before @p scale)
  EnvironmentMap(std::vector<Color> texels, int width, int height, float scale = 1.0f, double rotationDeg = 0.0);
  /// Reads an OpenEXR or PNG lat-long image (render/output/image_io.h; R, G, B channels).
  /// @throws InputError naming @p path when it cannot be read or is not 2:1-ish RGB
  static EnvironmentMap load(const std::string& path, float scale = 1.0f, double rotationDeg = 0.0);

  /// Radiance arriving from direction @p dir (unit, pointing away from the receiver towards the sky).
  Color radiance(const Vec3& dir) const;
  /// Draws a direction from @p u; sets @p dir and @p pdf (solid angle density) and returns its radiance.
  /// pdf is 0 (and the radiance 0) only for a map that is black everywhere.
  Color sample(const Vec2& u, Vec3& dir, float& pdf) const;
  /// Solid angle density with which sample() draws @p dir.
  float pdf(const Vec3& dir) const;

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  Vec2d toUv(const Vec3& dir) const;
  Vec3 fromUv(const Vec2d& uv) const;
  const Color& texel(const Vec2d& uv) const;

  std::vector<Color> texels_;
  int width_, height_;
  double cosRot_, sinRot_;
  Distribution2D distribution_;
};

}  // namespace firstshot
