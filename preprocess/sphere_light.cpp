// An emissive sphere as isotropic light samples inside it (sphere_light.h).
#include "preprocess/sphere_light.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "common/scene/scene_shapes.h"
#include "preprocess/light_tessellation.h"

namespace firstshot {

namespace {

/// Whether C·(h/d)² ≤ tolerance for a sphere of diameter @p h at distance @p d (the vertex rule's bound).
bool farEnough(double h, double d, double tolerance) { return kVertexRuleErrorConstant * h * h <= tolerance * d * d; }

/// The twelve vertices of an icosahedron on the unit sphere: (0, ±1, ±φ) and its cyclic permutations.
std::array<Vec3d, 12> icosahedron() {
  const double phi = (1 + std::sqrt(5.0)) / 2, s = 1 / std::sqrt(1 + phi * phi);
  std::array<Vec3d, 12> v;
  int k = 0;
  for (double a : {-1.0, 1.0})
    for (double b : {-phi, phi}) {
      v[k++] = s * Vec3d(0, a, b);
      v[k++] = s * Vec3d(a, b, 0);
      v[k++] = s * Vec3d(b, 0, a);
    }
  return v;
}

/// The irradiance per unit radiance (W/m² per W/(m² sr)) that isotropic samples at @p samples' positions,
/// sharing the intensity A/4 of a sphere of area @p area equally, give point @p x of unit normal @p n, unoccluded.
double samplesIrradiance(const std::vector<LightSample>& samples, double area, const Vec3d& x, const Vec3d& n) {
  double e = 0;
  for (const LightSample& s : samples) {
    const Vec3d d = Vec3d(s.position) - x;
    const double l2 = glm::dot(d, d), cosX = glm::dot(d, n);
    if (l2 > 0 && cosX > 0) e += cosX / (l2 * std::sqrt(l2));
  }
  return e * area / 4 / double(samples.size());
}

}  // namespace

std::optional<SphereLightFit> fitSphereLight(const SceneDesc& scene, uint32_t lightIndex, double tolerance) {
  const LightDesc& light = scene.lights[lightIndex];
  if (light.type != LightType::Area) return std::nullopt;
  const ShapeDesc& shape = scene.shapes[light.shape];
  if (shape.type != ShapeType::Sphere || scene.materials[shape.material].emissionTexture || shape.vertices.size() < 4 ||
      shape.faces.empty())
    return std::nullopt;
  SphereLightFit fit;
  for (const Vec3d& v : shape.vertices) fit.centre += v;
  fit.centre /= double(shape.vertices.size());
  double lo = std::numeric_limits<double>::infinity(), hi = 0, sum = 0;
  for (const Vec3d& v : shape.vertices) {
    const double r = glm::length(v - fit.centre);
    lo = std::min(lo, r), hi = std::max(hi, r), sum += r;
  }
  fit.radius = sum / double(shape.vertices.size());
  if (!(fit.radius > 0) || hi - lo > 1e-3 * fit.radius) return std::nullopt;  // an ellipsoid, or not round
  for (const Face& f : shape.faces) {
    const Vec3d a = shape.vertices[f.v[0]], b = shape.vertices[f.v[1]], c = shape.vertices[f.v[2]];
    if (!(glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0 - fit.centre) > 0)) return std::nullopt;  // inward
    fit.area += shapes::faceArea(shape, f);
  }
  fit.distance = std::numeric_limits<double>::infinity();
  std::vector<double> nearPlanes;  // the faces within r of the sphere: their planes' distances to the centre
  for (const ShapeDesc& s : scene.shapes) {
    if (scene.materials[s.material].isEmissive()) continue;
    for (const Face& f : s.faces) {
      Vec3d poly[4], mid(0.0);
      for (int k = 0; k < f.count; ++k) poly[k] = s.vertices[f.v[k]], mid += poly[k];
      mid /= double(f.count);
      double reach = 0;  // the face's bounding sphere about its vertices' mean
      for (int k = 0; k < f.count; ++k) reach = std::max(reach, glm::length(poly[k] - mid));
      if (glm::length(mid - fit.centre) - reach - fit.radius >= std::max(fit.distance, fit.radius)) continue;  // far
      const double d = std::max(0.0, pointPolygonDistance(fit.centre, poly, f.count) - fit.radius);
      fit.distance = std::min(fit.distance, d);
      if (d >= fit.radius) continue;
      const Vec3d n = glm::cross(poly[1] - poly[0], poly[2] - poly[0]);
      const double len = glm::length(n);
      const double offset = len > 0 ? std::abs(glm::dot(n / len, fit.centre - poly[0])) : 0.0;
      nearPlanes.push_back(offset);
      if (offset >= fit.radius) continue;
      // The plane cuts the sphere: the face comes nearest it on an edge (the foot of the perpendicular
      // from the centre lies inside the sphere, so not on a face that misses it).
      const Vec3d toward = glm::dot(n, fit.centre - poly[0]) > 0 ? n / len : -n / len;
      for (int k = 0; k < f.count; ++k) {
        const Vec3d a = poly[k], e = poly[(k + 1) % f.count] - a;
        const double t = std::clamp(glm::dot(fit.centre - a, e) / std::max(glm::dot(e, e), 1e-300), 0.0, 1.0);
        fit.cutPoints.push_back({a + t * e, toward});
      }
    }
  }
  fit.shell = std::min(fit.radius * std::sqrt(3.0) / 2,
                       (fit.radius + fit.distance) * std::pow(tolerance / kShellErrorConstant, 1.0 / 6.0));
  fit.cutsShell = fit.distance <= 0;
  for (double offset : nearPlanes) fit.cutsShell |= offset < fit.shell;
  return fit;
}

double sphereIrradiance(const SphereLightFit& fit, const Vec3d& x, const Vec3d& n) {
  constexpr int kPoints = 4096;
  const double golden = kPi * (3 - std::sqrt(5.0));
  double sum = 0;
  for (int i = 0; i < kPoints; ++i) {
    const double z = 1 - (i + 0.5) * 2 / kPoints, rho = std::sqrt(1 - z * z);
    const Vec3d u(rho * std::cos(golden * i), rho * std::sin(golden * i), z);
    const Vec3d d = fit.centre + fit.radius * u - x;
    const double l2 = glm::dot(d, d), l = std::sqrt(l2);
    const double cosX = glm::dot(d, n) / l, cosY = -glm::dot(d, u) / l;
    if (cosX > 0 && cosY > 0) sum += cosX * cosY / l2;
  }
  return sum * 4 * kPi * fit.radius * fit.radius / kPoints;
}

std::vector<LightSample> sphereLightSamples(const SceneDesc& scene, uint32_t lightIndex, double tolerance,
                                            double surfaceTolerance) {
  const std::optional<SphereLightFit> fit = fitSphereLight(scene, lightIndex, tolerance);
  if (!fit || fit->cutsShell) return {};
  const Color power = scene.materials[scene.shapes[scene.lights[lightIndex].shape].material].emission *
                      static_cast<float>(kPi * fit->area);
  std::vector<LightSample> out;
  LightSample s;
  s.kind = LightSampleKind::Point;
  s.light = lightIndex;
  if (farEnough(2 * fit->radius, fit->distance, tolerance)) {
    s.position = Vec3(fit->centre), s.emission = power;
    out.push_back(s);
  } else {
    s.emission = power / 12.0f;
    for (const Vec3d& u : icosahedron()) {
      s.position = Vec3(fit->centre + fit->shell * u);
      out.push_back(s);
    }
  }
  for (const auto& [x, n] : fit->cutPoints) {  // where part of the sphere is under the horizon
    const double exact = sphereIrradiance(*fit, x, n);
    if (exact > 0 && std::abs(samplesIrradiance(out, fit->area, x, n) - exact) > surfaceTolerance * exact) return {};
  }
  return out;
}

}  // namespace firstshot
