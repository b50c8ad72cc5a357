#pragma once
/// @file math.h
/// Small value types on GLM used everywhere: single precision for geometry and colour,
/// double precision where sums must be exact (areas, form factors).
#ifndef GLM_FORCE_XYZW_ONLY  // set for every target by common/CMakeLists.txt
#define GLM_FORCE_XYZW_ONLY
#endif
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

#include <cmath>
#include <cstdint>

namespace firstshot {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec4 = glm::vec4;
using Vec2d = glm::dvec2;
using Vec3d = glm::dvec3;
using Mat4d = glm::dmat4;
/// Linear RGB radiometric quantity (radiance, power, irradiance or reflectance).
using Color = glm::vec3;

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInvPi = 1.0 / kPi;
inline constexpr float kPiF = static_cast<float>(kPi);
inline constexpr float kInvPiF = static_cast<float>(kInvPi);

/// True when every component is finite.
template <int N, typename T, glm::qualifier Q>
inline bool isFinite(const glm::vec<N, T, Q>& v) {
  for (int i = 0; i < N; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

/// Luminance-like scalar of an RGB value (Rec. 709 weights).
inline float luminance(const Color& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
inline float maxComponent(const Color& c) { return std::max(c.x, std::max(c.y, c.z)); }

/// Orthonormal frame around a unit normal (z axis = n); converts between world and local space.
/// @tparam T float (Frame: shading, sampling) or double (Framed: the preprocessor's cameras)
template <typename T>
struct BasicFrame {
  using Vec = glm::vec<3, T, glm::defaultp>;
  Vec s, t, n;
  BasicFrame() : s(1, 0, 0), t(0, 1, 0), n(0, 0, 1) {}
  /// Builds a frame from a unit normal (Duff et al. 2017, branchless).
  explicit BasicFrame(const Vec& normal) : n(normal) {
    const T sign = std::copysign(T(1), n.z);
    const T a = T(-1) / (sign + n.z);
    const T b = n.x * n.y * a;
    s = Vec(T(1) + sign * n.x * n.x * a, sign * b, -sign * n.x);
    t = Vec(b, sign + n.y * n.y * a, -n.y);
  }
  Vec toLocal(const Vec& v) const { return {glm::dot(v, s), glm::dot(v, t), glm::dot(v, n)}; }
  Vec toWorld(const Vec& v) const { return s * v.x + t * v.y + n * v.z; }
};

using Frame = BasicFrame<float>;
using Framed = BasicFrame<double>;

}  // namespace firstshot
