#include "preprocess/occlusion_cull.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "preprocess/view.h"

namespace firstshot {
namespace {

/// Spreads the low 21 bits of @p x three apart (for 63-bit Morton codes).
uint64_t spread3(uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

/// Shapes with more faces than this (imported meshes) lend none: trying them all would cost more
/// than the ray tests they could save.
constexpr size_t kMaxFacesPerShape = 64;

}  // namespace

OcclusionCull::OcclusionCull(const SceneDesc& scene, const PatchMesh& mesh, uint32_t clusterSize) : mesh_(mesh) {
  faces_.resize(scene.shapes.size());
  for (size_t s = 0; s < scene.shapes.size(); ++s) {
    const ShapeDesc& shape = scene.shapes[s];
    if (scene.materials[shape.material].isEmissive() || shape.faces.size() > kMaxFacesPerShape ||
        scene.materials[shape.material].type == MaterialType::ThinGlass ||  // a pane hides nothing
        scene.materials[shape.material].isCutout())  // nor does a face with holes (a cut-out)
      continue;
    for (const firstshot::Face& f : shape.faces) {
      Face F;
      F.count = f.count;
      for (int k = 0; k < f.count; ++k) F.v[k] = shape.vertices[f.v[k]], F.centroid += F.v[k] / double(f.count);
      for (int k = 0; k < f.count; ++k) F.n += glm::cross(F.v[k], F.v[(k + 1) % f.count]);
      const double len = glm::length(F.n);
      if (!(len > 0)) continue;
      F.n /= len;
      F.d = glm::dot(F.n, F.v[0]);
      faces_[s].push_back(F);
    }
  }
  // Clusters: consecutive patches in Morton order of their centroids.
  if (mesh.size() == 0) return;
  Bounds3d b;
  for (const Patch& p : mesh.patches) b.extend(Vec3d(p.centroid));
  const Vec3d lo = b.lo, ext = glm::max(b.hi - b.lo, Vec3d(1e-30));
  const double scale = std::max({ext.x, ext.y, ext.z});
  margin_ = 1e-6 * std::max(scale, 1e-30);
  std::vector<uint64_t> key(mesh.size());
  for (uint32_t j = 0; j < mesh.size(); ++j) {
    const Vec3d u = (Vec3d(mesh.patches[j].centroid) - lo) / scale * double((1 << 21) - 1);
    key[j] = spread3(uint64_t(u.x)) | spread3(uint64_t(u.y)) << 1 | spread3(uint64_t(u.z)) << 2;
  }
  order_.resize(mesh.size());
  std::iota(order_.begin(), order_.end(), 0u);
  std::stable_sort(order_.begin(), order_.end(), [&](uint32_t a, uint32_t c) { return key[a] < key[c]; });
  for (uint32_t first = 0; first < mesh.size(); first += clusterSize) {
    Cluster c;
    c.first = first, c.count = std::min(clusterSize, mesh.size() - first);
    Bounds3d cb;
    for (uint32_t k = first; k < first + c.count; ++k) {
      const Patch& p = mesh.patches[order_[k]];
      for (uint32_t v = 0; v < p.count; ++v) cb.extend(Vec3d(p.v[v]));
    }
    c.centre = cb.centre();
    for (uint32_t k = first; k < first + c.count; ++k) {
      const Patch& p = mesh.patches[order_[k]];
      for (uint32_t v = 0; v < p.count; ++v) c.radius = std::max(c.radius, glm::length(Vec3d(p.v[v]) - c.centre));
    }
    c.radius = c.radius * (1 + 1e-6) + margin_;
    clusters_.push_back(c);
  }
}

void OcclusionCull::visible(const Vec3d& eye, const std::vector<uint32_t>& shown, std::vector<uint32_t>& out) const {
  std::vector<uint8_t> seen(faces_.size(), 0);
  std::vector<uint32_t> shapes;
  for (uint32_t id : shown) {
    const uint32_t s = mesh_.patches[id].shape;
    if (s < seen.size() && !seen[s]) seen[s] = 1, shapes.push_back(s);
  }
  // The candidate faces, with their edge planes through the eye (unit normals, inward).
  struct Wedge {
    Vec3d n{0.0};
    double d = 0, side = 0;  ///< plane; the eye's signed distance to it
    Vec3d edge[4];
    int count = 0;
  };
  std::vector<Wedge> wedges;
  for (uint32_t s : shapes)
    for (const Face& F : faces_[s]) {
      Wedge w;
      w.n = F.n, w.d = F.d, w.side = glm::dot(F.n, eye) - F.d;
      if (!(std::abs(w.side) > margin_)) continue;  // eye in (or at) the face's plane: it hides nothing
      w.count = F.count;
      bool ok = true;
      for (int k = 0; k < F.count && ok; ++k) {
        Vec3d e = glm::cross(F.v[k] - eye, F.v[(k + 1) % F.count] - eye);
        const double len = glm::length(e);
        ok = len > 0;
        if (!ok) break;
        e /= len;
        if (glm::dot(e, F.centroid - eye) < 0) e = -e;
        w.edge[k] = e;
      }
      if (ok) wedges.push_back(w);
    }
  size_t hint = 0;
  for (const Cluster& c : clusters_) {
    const Vec3d r = c.centre - eye;
    // Margin: the patches' float vertices and the rays' own tolerance (1e-5 of the way, coverage.h).
    const double m = c.radius + 1e-4 * glm::length(r) + margin_;
    bool hidden = false;
    for (size_t t = 0; t < wedges.size() && !hidden; ++t) {
      const Wedge& w = wedges[(hint + t) % wedges.size()];
      const double sc = glm::dot(w.n, c.centre) - w.d;
      if (!(w.side > 0 ? sc < -m : sc > m)) continue;  // not wholly beyond the face's plane
      bool inside = true;
      for (int k = 0; k < w.count && inside; ++k) inside = glm::dot(w.edge[k], r) >= m;
      if (inside) hidden = true, hint = (hint + t) % wedges.size();
    }
    if (!hidden) out.insert(out.end(), order_.begin() + c.first, order_.begin() + c.first + c.count);
  }
}

}  // namespace firstshot
