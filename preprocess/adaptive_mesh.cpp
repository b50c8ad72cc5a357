// The patch mesh as a forest of quadtrees (adaptive refinement).
#include "preprocess/adaptive_mesh.h"

#include <algorithm>
#include <limits>
#include <string>

#include "common/util/error.h"
#include "common/util/memory_limit.h"

namespace firstshot {

AdaptiveMesh::AdaptiveMesh(const SceneDesc& scene, double patchSize) : file_(scene.file) {
  mesh_.patchSize = patchSize;
  forEachPatchPolygon(scene, patchSize, [&](uint32_t shape, const std::vector<Vec3d>& poly) {
    Leaf l;
    l.count = static_cast<uint32_t>(poly.size());
    for (size_t i = 0; i < poly.size(); ++i) l.v[i] = poly[i];
    if (l.count == 3) l.v[3] = l.v[2];
    l.material = static_cast<uint32_t>(scene.shapes[shape].material);
    l.shape = shape;
    leaves_.push_back(l);
  });
  rebuild();
}

void AdaptiveMesh::rebuild() {
  mesh_.patches.clear();
  mesh_.patches.reserve(leaves_.size());
  for (const Leaf& l : leaves_) {
    Patch p;
    p.count = l.count;
    for (uint32_t i = 0; i < 4; ++i) p.v[i] = Vec3(l.v[i]);
    p.material = l.material;
    p.shape = l.shape;
    computePatchGeometry(p, l.v);  // exact polygon, before rounding to float
    mesh_.patches.push_back(p);
  }
}

bool AdaptiveMesh::splittable(uint32_t patch, double minEdge) const {
  const Leaf& l = leaves_[patch];
  double longest = 0;
  for (uint32_t i = 0; i < l.count; ++i) longest = std::max(longest, glm::length(l.v[(i + 1) % l.count] - l.v[i]));
  return 0.5 * longest >= minEdge * (1 - 1e-9);
}

void AdaptiveMesh::children(const Vec3d* v, int count, std::vector<std::vector<Vec3d>>& out) {
  auto mid = [&](int a, int b) { return 0.5 * (v[a] + v[b]); };
  if (count == 4) {
    const Vec3d m01 = mid(0, 1), m12 = mid(1, 2), m23 = mid(2, 3), m30 = mid(3, 0);
    const Vec3d c = 0.25 * (v[0] + v[1] + v[2] + v[3]);
    out.push_back({v[0], m01, c, m30});
    out.push_back({m01, v[1], m12, c});
    out.push_back({c, m12, v[2], m23});
    out.push_back({m30, c, m23, v[3]});
    return;
  }
  const Vec3d m01 = mid(0, 1), m12 = mid(1, 2), m20 = mid(2, 0);
  out.push_back({v[0], m01, m20});
  out.push_back({m01, v[1], m12});
  out.push_back({m20, m12, v[2]});
  out.push_back({m01, m12, m20});
}

AdaptiveMesh::SplitLines AdaptiveMesh::splitLines(const Patch* c) {
  SplitLines l;
  auto v = [&](int child, int k) { return Vec3d(c[child].v[k]); };
  if (c[0].count == 4) {  // c0 = {v0, m01, centre, m30}, c1 = {m01, v1, m12, centre}, c2 = {centre, m12, v2, m23}
    l.count = 2;
    l.a[0] = v(0, 3), l.b[0] = v(1, 2), l.ref[0] = v(0, 0);  // m30–m12: v0's side holds c0 and c1
    l.a[1] = v(0, 1), l.b[1] = v(2, 3), l.ref[1] = v(0, 0);  // m01–m23: v0's side holds c0 and c3
    return l;
  }
  l.count = 3;  // c0 = {v0, m01, m20}, c1 = {m01, v1, m12}, c2 = {m20, m12, v2}, c3 the middle
  l.a[0] = v(0, 1), l.b[0] = v(0, 2), l.ref[0] = v(0, 0);
  l.a[1] = v(1, 0), l.b[1] = v(1, 2), l.ref[1] = v(1, 1);
  l.a[2] = v(2, 0), l.b[2] = v(2, 1), l.ref[2] = v(2, 2);
  return l;
}

int AdaptiveMesh::childOf(int lineCount, unsigned inside) {
  if (lineCount == 2) {
    const bool top = inside & 1u, left = inside & 2u;
    return top ? (left ? 0 : 1) : (left ? 3 : 2);
  }
  for (int k = 0; k < 3; ++k)
    if (inside & (1u << k)) return k;
  return 3;
}

std::vector<uint32_t> AdaptiveMesh::split(const std::vector<uint8_t>& flags) {
  size_t count = 0;
  for (size_t j = 0; j < leaves_.size(); ++j) count += flags[j] ? 4 : 1;
  if (count > std::numeric_limits<uint32_t>::max())
    throw InputError(file_, "settings.min_patch_size", "refinement would make more than 2^32-1 patches: raise it");
  requireMemory(double(count) * double(sizeof(Leaf) + sizeof(Patch)), file_, "settings.min_patch_size",
                std::to_string(count) + " refined patches", "raise it");
  std::vector<uint32_t> first(leaves_.size() + 1);
  std::vector<Leaf> next;
  next.reserve(count);
  std::vector<std::vector<Vec3d>> polys;
  for (size_t j = 0; j < leaves_.size(); ++j) {
    first[j] = static_cast<uint32_t>(next.size());
    const Leaf& l = leaves_[j];
    if (!flags[j]) {
      next.push_back(l);
      continue;
    }
    polys.clear();
    children(l.v, int(l.count), polys);
    for (const auto& poly : polys) {
      Leaf c = l;
      for (size_t i = 0; i < poly.size(); ++i) c.v[i] = poly[i];
      if (c.count == 3) c.v[3] = c.v[2];
      next.push_back(c);
    }
  }
  first.back() = static_cast<uint32_t>(next.size());
  leaves_ = std::move(next);
  rebuild();
  return first;
}

}  // namespace firstshot
