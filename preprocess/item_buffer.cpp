#include "preprocess/item_buffer.h"

#include <stdexcept>

namespace firstshot {

void ItemGeometry::addTriangle(const Vec3& a, const Vec3& b, const Vec3& c, uint32_t patchId) {
  if (patchId == kNoPatch) throw std::invalid_argument("ItemGeometry: patch ID 0xFFFFFFFF is reserved for background");
  positions.push_back(a);
  positions.push_back(b);
  positions.push_back(c);
  patchIds.push_back(patchId);
  for (const Vec3& p : {a, b, c}) bounds.extend(Vec3d(p));
}

ItemGeometry ItemGeometry::fromPatches(const PatchMesh& mesh, const std::vector<uint8_t>& seeThrough) {
  ItemGeometry g;
  size_t tris = 0;
  for (const Patch& p : mesh.patches) tris += p.count == 4 ? 2 : 1;
  g.positions.reserve(3 * tris);
  g.patchIds.reserve(tris);
  for (uint32_t id = 0; id < mesh.size(); ++id) {
    const Patch& p = mesh.patches[id];
    if (!seeThrough.empty() && seeThrough[p.material]) continue;
    g.addTriangle(p.v[0], p.v[1], p.v[2], id);
    if (p.count == 4) g.addTriangle(p.v[0], p.v[2], p.v[3], id);
  }
  return g;
}

double itemBufferNear(const Bounds3d& sceneBounds, double relative) {
  const double d = sceneBounds.diagonal();
  return relative * (d > 0 ? d : 1.0);
}

}  // namespace firstshot
