#include "preprocess/light_tessellation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/core.h>

#include "common/lights/form_factors.h"
#include "common/materials/emission_texture.h"
#include "common/patches/patches.h"
#include "common/table/firstshot.h"
#include "common/util/error.h"
#include "common/util/memory_limit.h"
#include "preprocess/light_clusters.h"

namespace firstshot {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Distance (m) between segments [p0, p1] and [q0, q1] (closest points, clamped; parallel segments
/// handled by clamping the first parameter).
double segmentSegmentDistance(const Vec3d& p0, const Vec3d& p1, const Vec3d& q0, const Vec3d& q1) {
  const Vec3d u = p1 - p0, v = q1 - q0, w = p0 - q0;
  const double a = glm::dot(u, u), b = glm::dot(u, v), c = glm::dot(v, v), d = glm::dot(u, w), e = glm::dot(v, w);
  const double den = a * c - b * b;
  double s = 0;
  if (a > 0 && den > 1e-14 * a * c) s = std::clamp((b * e - c * d) / den, 0.0, 1.0);
  double t = c > 0 ? (b * s + e) / c : 0.0;
  if (t < 0 || t > 1) {  // clamp t, then recompute s for the clamped t
    t = std::clamp(t, 0.0, 1.0);
    s = a > 0 ? std::clamp((b * t - d) / a, 0.0, 1.0) : 0.0;
  }
  return glm::length((p0 + s * u) - (q0 + t * v));
}

/// Distance (m) from @p p to segment [a, b].
double pointSegmentDistance(const Vec3d& p, const Vec3d& a, const Vec3d& b) {
  const Vec3d ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

/// Newell normal of a planar polygon: length = 2 × area.
Vec3d polygonNormal(const Vec3d* v, int n) {
  Vec3d s(0.0);
  for (int i = 1; i + 1 < n; ++i) s += glm::cross(v[i] - v[0], v[i + 1] - v[0]);
  return s;
}

/// Largest distance (m) between two vertices of a polygon: its diameter.
double diameter(const Vec3d* v, int n) {
  double h = 0;
  for (int i = 0; i < n; ++i)
    for (int k = i + 1; k < n; ++k) h = std::max(h, glm::length(v[i] - v[k]));
  return h;
}

/// Diameter bound (m) of a shape: the diagonal of its vertices' bounding box.
double shapeDiameter(const ShapeDesc& s) {
  Vec3d lo(kInf), hi(-kInf);
  for (const Vec3d& p : s.vertices) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return s.vertices.empty() ? 0.0 : glm::length(hi - lo);
}

Vec3d centroidOf(const Vec3d* v, int n) {
  Vec3d c(0.0);
  for (int i = 0; i < n; ++i) c += v[i];
  return c / double(n);
}

double radiusAbout(const Vec3d& c, const Vec3d* v, int n) {
  double r = 0;
  for (int i = 0; i < n; ++i) r = std::max(r, glm::length(v[i] - c));
  return r;
}

/// Accumulates triangles into vertex samples, merging vertices with identical coordinates.
class SampleBuilder {
 public:
  /// The cells added next lie in face @p f of shape @p s of material @p m; when it emits per point
  /// (common/materials/emission_texture.h), each vertex accumulates ∫ Le φ_i dA over its triangles.
  void setFace(const MaterialDesc& m, const ShapeDesc& s, size_t f) {
    textured_ = emitsPerPoint(m, s) ? &m : nullptr;
    shape_ = &s, face_ = f;
  }
  /// Adds a triangle or quad (fanned from its first vertex, as two triangles).
  void addCell(const Vec3d* v, int count) {
    for (int k = 1; k + 1 < count; ++k) addTriangle(v[0], v[k], v[k + 1]);
  }
  LightTessellation finish() {
    for (size_t i = 0; i < out_.positions.size(); ++i) {
      out_.weights[i] = out_.weights[i] / 3.0;
      out_.normals[i] = glm::normalize(out_.normals[i]);
      if (!emissionSum_.empty()) out_.emission.push_back(Color(emissionSum_[i] / out_.weights[i]));
    }
    return std::move(out_);
  }

 private:
  void addTriangle(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const Vec3d n = glm::cross(b - a, c - a);
    const double area = 0.5 * glm::length(n);
    for (const Vec3d& p : {a, b, c}) {
      const size_t i = vertex(p);
      out_.weights[i] += area;  // divided by 3 at the end
      out_.normals[i] += n;     // |n| = 2·area: area-weighted
    }
    out_.triangles.push_back({a, b, c});
    if (textured_) addEmission(a, b, c, area);
  }
  /// Adds ∫ Le φ dA over triangle (@p a, @p b, @p c) of @p area m² to its vertices' sums (a midpoint rule on
  /// 16² sub-triangles, φ the vertex's barycentric coordinate).
  void addEmission(const Vec3d& a, const Vec3d& b, const Vec3d& c, double area) {
    if (emissionSum_.size() < out_.positions.size()) emissionSum_.resize(out_.positions.size(), Vec3d(0.0));
    constexpr int kSubdivisions = 16;
    const double w = area / double(kSubdivisions * kSubdivisions);
    const size_t ia = vertex(a), ib = vertex(b), ic = vertex(c);
    forEachSubTriangleCentroid(kSubdivisions, [&](float beta, float gamma) {
      const Vec3d p = a + double(beta) * (b - a) + double(gamma) * (c - a);
      const Vec3d le = w * Vec3d(emissionAt(*textured_, faceUvAt(*shape_, face_, p)));
      emissionSum_[ia] += (1.0 - double(beta) - double(gamma)) * le;
      emissionSum_[ib] += double(beta) * le;
      emissionSum_[ic] += double(gamma) * le;
    });
  }
  size_t vertex(const Vec3d& p) {
    auto [it, inserted] = index_.emplace(std::array<double, 3>{p.x, p.y, p.z}, out_.positions.size());
    if (inserted) {
      out_.positions.push_back(p);
      out_.weights.push_back(0.0);
      out_.normals.push_back(Vec3d(0.0));
    }
    return it->second;
  }
  std::map<std::array<double, 3>, size_t> index_;
  LightTessellation out_;
  const MaterialDesc* textured_ = nullptr;  ///< the material of the current face when it emits per point
  const ShapeDesc* shape_ = nullptr;
  size_t face_ = 0;
  std::vector<Vec3d> emissionSum_;  ///< by vertex: ∫ Le φ_i dA (textured emitters only)
};

/// Recursive 4-way refinement of one cell against the bound C·(h/d)² ≤ tolerance.
struct Refiner {
  const LightReceivers& receivers;
  double scale;    ///< √(C/tolerance): split while h·scale > d
  double minSize;  ///< floor on the cell diameter, m
  SampleBuilder& out;

  void refine(const Vec3d* v, int count) const {
    const double h = diameter(v, count);
    if (h <= minSize * (1 + 1e-9) || h * scale <= receivers.distance(v, count)) {
      out.addCell(v, count);
      return;
    }
    if (count == 4) {
      const Vec3d m01 = 0.5 * (v[0] + v[1]), m12 = 0.5 * (v[1] + v[2]), m23 = 0.5 * (v[2] + v[3]), m30 = 0.5 * (v[3] + v[0]);
      const Vec3d c = 0.5 * (m01 + m23);  // the bilinear centre
      const Vec3d kids[4][4] = {{v[0], m01, c, m30}, {m01, v[1], m12, c}, {c, m12, v[2], m23}, {m30, c, m23, v[3]}};
      for (const auto& k : kids) refine(k, 4);
      return;
    }
    const Vec3d m01 = 0.5 * (v[0] + v[1]), m12 = 0.5 * (v[1] + v[2]), m20 = 0.5 * (v[2] + v[0]);
    const Vec3d kids[4][3] = {{v[0], m01, m20}, {m01, v[1], m12}, {m20, m12, v[2]}, {m01, m12, m20}};
    for (const auto& k : kids) refine(k, 3);
  }
};

/// Automatic tessellation of one face (see tessellateAreaLight), no cell split below (diameter)/@p floorRatio.
void tessellateFace(const SceneDesc& scene, const Vec3d* v, int count, double tolerance, double floorRatio, SampleBuilder& out) {
  const LightReceivers receivers(scene, centroidOf(v, count), polygonNormal(v, count));
  const double scale = std::sqrt(kVertexRuleErrorConstant / tolerance);
  const double size = diameter(v, count);
  // First grid: cells that meet the bound at the face's own distance, or size/8 across when closer.
  const double cell = std::max(receivers.distance(v, count) / scale, size / std::min(double(kLightGridMaxCells), floorRatio));
  std::vector<std::vector<Vec3d>> grid;
  subdividePolygon(v, count, count == 4 ? cell / std::sqrt(2.0) : cell, grid);
  const Refiner refiner{receivers, scale, size / floorRatio, out};
  for (const auto& g : grid) refiner.refine(g.data(), static_cast<int>(g.size()));
}

/// The automatic tessellation of @p shape with the floor at 1/@p floorRatio of a face's diameter.
LightTessellation automaticTessellation(const SceneDesc& scene, const ShapeDesc& shape, double tolerance, double floorRatio) {
  // An emissive mesh: its small faces are cells as they are (one receiver scan per face would cost
  // faces × scene faces), the large ones cut as a single face is; then the samples are merged.
  const bool mesh = shape.faces.size() > kLightMeshFaces;
  const double span = shapeDiameter(shape);
  SampleBuilder out;
  for (size_t k = 0; k < shape.faces.size(); ++k) {
    const Face& f = shape.faces[k];
    out.setFace(scene.materials[size_t(shape.material)], shape, k);
    Vec3d v[4];
    for (int i = 0; i < f.count; ++i) v[i] = shape.vertices[f.v[i]];
    if (mesh && diameter(v, f.count) <= span / kLightGridMaxCells)
      out.addCell(v, f.count);
    else
      tessellateFace(scene, v, f.count, tolerance, floorRatio, out);
  }
  return mesh ? clusterLightSamples(scene, out.finish(), tolerance, span / floorRatio) : out.finish();
}

}  // namespace

double pointPolygonDistance(const Vec3d& p, const Vec3d* poly, int count) {
  const Vec3d n = polygonNormal(poly, count);
  const double len = glm::length(n);
  if (len > 0) {
    const Vec3d nh = n / len;
    bool inside = true;
    for (int i = 0; i < count && inside; ++i)
      inside = glm::dot(glm::cross(poly[(i + 1) % count] - poly[i], p - poly[i]), nh) >= 0;
    if (inside) return std::abs(glm::dot(p - poly[0], nh));
  }
  double d = kInf;
  for (int i = 0; i < count; ++i) d = std::min(d, pointSegmentDistance(p, poly[i], poly[(i + 1) % count]));
  return d;
}

double polygonPolygonDistance(const Vec3d* a, int na, const Vec3d* b, int nb) {
  double d = kInf;
  for (int i = 0; i < na; ++i) d = std::min(d, pointPolygonDistance(a[i], b, nb));
  for (int k = 0; k < nb; ++k) d = std::min(d, pointPolygonDistance(b[k], a, na));
  for (int i = 0; i < na; ++i)
    for (int k = 0; k < nb; ++k) d = std::min(d, segmentSegmentDistance(a[i], a[(i + 1) % na], b[k], b[(k + 1) % nb]));
  return d;
}

LightReceivers::LightReceivers(const SceneDesc& scene, const Vec3d& origin, const Vec3d& normal) {
  const Vec3d nh = glm::normalize(normal);
  for (const ShapeDesc& s : scene.shapes) {
    if (scene.materials[s.material].isEmissive()) continue;
    for (const Face& f : s.faces) {
      Vec3d in[4];
      for (int i = 0; i < f.count; ++i) in[i] = s.vertices[f.v[i]];
      Poly p;
      p.count = analytic::clipPolygonToPlane(in, f.count, origin, nh, 0.0, p.v.data());
      if (p.count < 3) continue;
      double height = 0;
      for (int i = 0; i < p.count; ++i) height = std::max(height, glm::dot(p.v[i] - origin, nh));
      if (height <= 1e-9 * diameter(p.v.data(), p.count)) continue;  // in the light's plane: receives nothing
      p.centre = centroidOf(p.v.data(), p.count);
      p.radius = radiusAbout(p.centre, p.v.data(), p.count);
      polys_.push_back(p);
    }
  }
  // Nearest first, so that the bounding-sphere test below skips most polygons.
  auto bound = [&](const Poly& p) { return glm::length(p.centre - origin) - p.radius; };
  std::stable_sort(polys_.begin(), polys_.end(), [&](const Poly& a, const Poly& b) { return bound(a) < bound(b); });
}

double LightReceivers::distance(const Vec3d* poly, int count) const {
  const Vec3d c = centroidOf(poly, count);
  const double r = radiusAbout(c, poly, count);
  double best = kInf;
  for (const Poly& p : polys_) {
    if (glm::length(p.centre - c) - p.radius - r >= best) continue;
    best = std::min(best, polygonPolygonDistance(poly, count, p.v.data(), p.count));
  }
  return best;
}

void reportRelaxed(const SceneDesc& scene, int shapeIndex, const LightTessellation& t, double asked, size_t budget) {
  if (t.tolerance > asked || t.floorRatio < kLightMinSizeRatio)
    fmt::print(stderr, "{}: {}: {} light samples at light_tolerance {:g}, none split below 1/{:g} of a face (the budget is {}; "
               "{:g} asked)\n", scene.file, scene.shapes[shapeIndex].name, t.positions.size(), t.tolerance, t.floorRatio, budget,
               asked);
}

LightTessellation tessellateAreaLight(const SceneDesc& scene, int shapeIndex, double lightPatchSize, double tolerance,
                                      size_t budget, bool quiet) {
  const ShapeDesc& shape = scene.shapes[shapeIndex];
  if (lightPatchSize <= 0) {
    // Within the budget: the tolerance doubled twice, then the floor raised to 1/8 of a face (the
    // first grid's cells), the tolerance doubled twice more, the floor raised to the whole face.
    constexpr std::pair<double, double> kSteps[] = {{64, 1}, {64, 2}, {64, 4}, {32, 4}, {16, 4}, {8, 4},
                                                    {8, 8}, {8, 16}, {4, 16}, {2, 16}, {1, 16}};
    static_assert(kSteps[0].first == kLightMinSizeRatio);
    for (const auto& [ratio, relax] : kSteps) {
      LightTessellation t = automaticTessellation(scene, shape, relax * tolerance, ratio);
      t.floorRatio = ratio, t.tolerance = relax * tolerance;
      if (t.positions.size() <= budget || ratio == 1) {
        if (!quiet) reportRelaxed(scene, shapeIndex, t, tolerance, budget);
        return t;
      }
    }
  }
  // Uniform. A light_patch_size far too small is an error, not an allocation.
  double cells = 0;
  for (const Face& f : shape.faces) {
    Vec3d v[4];
    for (int i = 0; i < f.count; ++i) v[i] = shape.vertices[f.v[i]];
    cells += subdivisionCount(v, f.count, lightPatchSize);
  }
  if (cells > double(std::numeric_limits<uint32_t>::max()))
    throw InputError(scene.file, "settings.light_patch_size", shape.name + " would be cut into more than 2^32-1 cells: raise it");
  requireMemory(cells * double(sizeof(LightSample)), scene.file, "settings.light_patch_size",
                "the light samples of " + shape.name, "raise it");
  SampleBuilder out;
  std::vector<std::vector<Vec3d>> polys;
  for (size_t k = 0; k < shape.faces.size(); ++k) {
    const Face& f = shape.faces[k];
    out.setFace(scene.materials[size_t(shape.material)], shape, k);
    Vec3d v[4];
    for (int i = 0; i < f.count; ++i) v[i] = shape.vertices[f.v[i]];
    polys.clear();
    subdividePolygon(v, f.count, lightPatchSize, polys);
    for (const auto& p : polys) out.addCell(p.data(), static_cast<int>(p.size()));
  }
  return out.finish();
}

VertexRuleError vertexRuleError(const ShapeDesc& light, const LightTessellation& t,
                                const std::vector<std::pair<Vec3d, Vec3d>>& points) {
  const Face& f = light.faces.at(0);
  Vec3d poly[4];
  for (int i = 0; i < f.count; ++i) poly[i] = light.vertices[f.v[i]];
  const Vec3d front = glm::cross(poly[1] - poly[0], poly[2] - poly[0]);
  VertexRuleError worst;
  for (const auto& [x, n] : points) {
    if (glm::dot(x - poly[0], front) <= 0) continue;
    const double exact = analytic::polygonCosineSolidAngle(x, n, poly, f.count);
    if (exact <= 1e-12) continue;
    double rule = 0, facing = 0;
    for (size_t i = 0; i < t.positions.size(); ++i) {
      const Vec3d r = t.positions[i] - x;
      const double d = glm::length(r), cosL = std::max(0.0, -glm::dot(t.normals[i], r) / d);
      rule += t.weights[i] * std::max(0.0, glm::dot(n, r) / d) * cosL / (d * d);
      facing += t.weights[i] * cosL / (d * d);
    }
    bool cut = false;
    for (int i = 0; i < f.count; ++i) cut = cut || glm::dot(n, poly[i] - x) <= 0;
    if (cut)
      worst.cut = std::max(worst.cut, std::abs(rule - exact) / facing);
    else
      worst.uncut = std::max(worst.uncut, std::abs(rule - exact) / exact);
  }
  return worst;
}

}  // namespace firstshot
