// Splitting surfaces into patches.
#include "common/patches/patches.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/core.h>

#include "common/scene/scene_shapes.h"
#include "common/util/error.h"
#include "common/util/hash.h"
#include "common/util/memory_limit.h"

namespace firstshot {

double PatchMesh::totalArea() const {
  double sum = 0;
  for (const auto& p : patches) sum += p.area;
  return sum;
}

namespace {

/// Area, normal and centroid of a planar polygon given in double precision.
void polygonGeometry(Patch& p, const Vec3d* v) {
  const Vec3d a(v[0]);
  Vec3d cross(0.0), centroid(0.0);
  double area = 0;
  for (uint32_t i = 1; i + 1 < p.count; ++i) {
    const Vec3d b(v[i]), c(v[i + 1]);
    const Vec3d n = glm::cross(b - a, c - a);
    const double ai = 0.5 * glm::length(n);
    cross += n;
    area += ai;
    centroid += ai * (a + b + c) / 3.0;
  }
  p.area = area;
  const double len = glm::length(cross);
  p.normal = len > 0 ? Vec3(cross / len) : Vec3(0, 0, 1);
  p.centroid = area > 0 ? Vec3(centroid / area) : Vec3(a);
}

}  // namespace

void computePatchGeometry(Patch& p, const Vec3d* exact) { polygonGeometry(p, exact); }

void computePatchGeometry(Patch& p) {
  Vec3d v[4];
  for (uint32_t i = 0; i < p.count; ++i) v[i] = Vec3d(p.v[i]);
  polygonGeometry(p, v);
}

namespace {

/// Pieces an edge of @p len is cut into (in double: no overflow for any input).
double edgeCells(double len, double maxEdge) { return std::max(1.0, std::ceil(len / maxEdge * (1 - 1e-12))); }

}  // namespace

void polygonCells(const Vec3d* v, int count, double maxEdge, double& n, double& m) {
  if (count == 4) {
    n = edgeCells(std::max(glm::length(v[1] - v[0]), glm::length(v[2] - v[3])), maxEdge);
    m = edgeCells(std::max(glm::length(v[3] - v[0]), glm::length(v[2] - v[1])), maxEdge);
  } else {
    n = m = edgeCells(std::max({glm::length(v[1] - v[0]), glm::length(v[2] - v[1]), glm::length(v[0] - v[2])}), maxEdge);
  }
}

double subdivisionCount(const Vec3d* v, int count, double maxEdge) {
  double n, m;
  polygonCells(v, count, maxEdge, n, m);
  return n * m;  // a quad's n×m grid, a triangle's k² similar triangles
}

void subdividePolygon(const Vec3d* v, int count, double maxEdge, std::vector<std::vector<Vec3d>>& out) {
  double cn, cm;
  polygonCells(v, count, maxEdge, cn, cm);
  if (cn * cm > double(std::numeric_limits<uint32_t>::max()) || std::max(cn, cm) > double(std::numeric_limits<int>::max()))
    throw std::length_error("subdividePolygon: more than 2^32-1 pieces (check subdivisionCount first)");
  if (count == 4) {
    const int n = static_cast<int>(cn), m = static_cast<int>(cm);
    auto at = [&](int i, int k) {
      const double s = double(i) / n, t = double(k) / m;
      return (1 - t) * ((1 - s) * v[0] + s * v[1]) + t * ((1 - s) * v[3] + s * v[2]);
    };
    for (int k = 0; k < m; ++k)
      for (int i = 0; i < n; ++i) out.push_back({at(i, k), at(i + 1, k), at(i + 1, k + 1), at(i, k + 1)});
    return;
  }
  const int k = static_cast<int>(cn);
  auto at = [&](int i, int j) { return v[0] + (double(i) / k) * (v[1] - v[0]) + (double(j) / k) * (v[2] - v[0]); };
  for (int j = 0; j < k; ++j)
    for (int i = 0; i + j < k; ++i) {
      out.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
      if (i + j + 1 < k) out.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    }
}

void forEachPatchPolygon(const SceneDesc& scene, double patchSize,
                         const std::function<void(uint32_t, const std::vector<Vec3d>&)>& visit) {
  // Count first (arithmetic only), so that a patch size far too small is an error, not an allocation.
  const double total = countPatchPolygons(scene, patchSize);
  if (total > double(std::numeric_limits<uint32_t>::max()))
    throw InputError(scene.file, "settings.patch_size",
                     fmt::format("{:.3g} patches, more than the 2^32-1 patch IDs allow: raise it", total));
  requireMemory(total * double(sizeof(Patch)), scene.file, "settings.patch_size",
                fmt::format("{:.3g} patches", total), "raise it");
  std::vector<std::vector<Vec3d>> polys;
  for (size_t si = 0; si < scene.shapes.size(); ++si) {
    const ShapeDesc& s = scene.shapes[si];
    if (scene.materials[s.material].isEmissive()) continue;
    for (const Face& f : s.faces) {
      Vec3d v[4];
      for (int i = 0; i < f.count; ++i) v[i] = s.vertices[f.v[i]];
      polys.clear();
      subdividePolygon(v, f.count, patchSize, polys);
      for (const auto& poly : polys) visit(static_cast<uint32_t>(si), poly);
    }
  }
}

double countPatchPolygons(const SceneDesc& scene, double patchSize) {
  double total = 0;
  for (const ShapeDesc& s : scene.shapes) {
    if (scene.materials[s.material].isEmissive()) continue;
    for (const Face& f : s.faces) {
      Vec3d v[4];
      for (int i = 0; i < f.count; ++i) v[i] = s.vertices[f.v[i]];
      total += subdivisionCount(v, f.count, patchSize);
    }
  }
  return total;
}

PatchMesh buildPatches(const SceneDesc& scene, double patchSize) {
  PatchMesh mesh;
  mesh.patchSize = patchSize;
  forEachPatchPolygon(scene, patchSize, [&](uint32_t shape, const std::vector<Vec3d>& poly) {
    Patch p;
    p.count = static_cast<uint32_t>(poly.size());
    for (size_t i = 0; i < poly.size(); ++i) p.v[i] = Vec3(poly[i]);
    if (p.count == 3) p.v[3] = p.v[2];
    p.material = static_cast<uint32_t>(scene.shapes[shape].material);
    p.shape = shape;
    polygonGeometry(p, poly.data());  // exact sub-polygon, before rounding to float
    mesh.patches.push_back(p);
  });
  return mesh;
}

double shapeArea(const ShapeDesc& shape) {
  double a = 0;
  for (const auto& f : shape.faces) a += shapes::faceArea(shape, f);
  return a;
}

uint64_t hashPatches(const PatchMesh& mesh) {
  Hasher h;
  h.add<uint64_t>(mesh.patches.size()).add(mesh.patchSize);
  for (const auto& p : mesh.patches) {
    h.bytes(p.v, sizeof(p.v)).add(p.count).add(p.material).add(p.shape);
    h.add(p.normal).add(p.centroid).add(p.area);
  }
  return h.value();
}

}  // namespace firstshot
