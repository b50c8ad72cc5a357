// The patch of a traced face that holds a point (render/scene/patch_locator.h).
#include "render/scene/patch_locator.h"

#include <algorithm>
#include <cmath>

#include "common/patches/patch_faces.h"

namespace firstshot {

namespace {

int largestAxis(const Vec3& n) {
  const Vec3 a = glm::abs(n);
  return a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
}

template <typename V3>
auto drop(const V3& p, int axis) {
  using V2 = glm::vec<2, typename V3::value_type>;
  return axis == 0 ? V2(p.y, p.z) : axis == 1 ? V2(p.z, p.x) : V2(p.x, p.y);
}

template <typename V2>
auto cross2(V2 a, V2 b) { return a.x * b.y - a.y * b.x; }

constexpr double kCellTolerance = 1e-3;  ///< how far (in cells) a patch's corner may stray from its cell
constexpr int kMaxSplits = 16;           ///< a refinement deeper than this is taken as no refinement

/// One split of a cell's coordinates: the child (0–3) that holds @p x, and @p x in that child's own coordinates. A
/// quad's children are its quarters; a triangle's the three at its corners (0: at (0, 0), 1: at (1, 0), 2: at (0, 1))
/// and the middle one, whose coordinates run from (½, ½).
inline int splitChild(bool triangle, Vec2& x) {
  int c;
  if (!triangle) {
    c = int(x.x > 0.5f) + 2 * int(x.y > 0.5f);
    x = 2.0f * x - Vec2(float(c & 1), float(c >> 1));
  } else if (x.x > 0.5f) {
    c = 1, x = Vec2(2.0f * x.x - 1.0f, 2.0f * x.y);
  } else if (x.y > 0.5f) {
    c = 2, x = Vec2(2.0f * x.x, 2.0f * x.y - 1.0f);
  } else if (x.x + x.y < 0.5f) {
    c = 0, x = 2.0f * x;
  } else {
    c = 3, x = Vec2(1.0f) - 2.0f * x;
  }
  return c;
}

}  // namespace

std::unique_ptr<const PatchLocator> PatchLocator::build(const SceneDesc& scene, const PatchMesh& patches) {
  auto loc = std::unique_ptr<PatchLocator>(new PatchLocator());
  PatchLocator& l = *loc;
  l.faces_ = buildPatches(scene, kFacesAsTheyAre);
  const uint32_t nf = l.faces_.size(), np = patches.size();
  if (nf == 0 || np >= kQuadtree || double(np) < kMinPatchesPerFace * double(nf)) return nullptr;
  // Face mesh entry of face f of shape s: every face of a non-emissive shape is one polygon, in order.
  std::vector<uint32_t> shapeStart(scene.shapes.size() + 1, 0), faceShape(nf), faceIndex(nf);
  uint32_t k = 0;
  for (size_t s = 0; s < scene.shapes.size(); ++s) {
    shapeStart[s] = k;
    if (scene.materials[size_t(scene.shapes[s].material)].isEmissive()) continue;
    for (uint32_t f = 0; f < scene.shapes[s].faces.size() && k < nf; ++f, ++k) faceShape[k] = uint32_t(s), faceIndex[k] = f;
    if (k < shapeStart[s] + scene.shapes[s].faces.size()) return nullptr;
  }
  if (k != nf) return nullptr;
  const std::vector<uint32_t> faceInShape = mapPatchesToFaces(scene, patches, [](const Patch&) { return true; });
  std::vector<uint32_t> faceOf(np);
  l.faceStart_.assign(size_t(nf) + 1, 0);
  for (uint32_t j = 0; j < np; ++j) {
    const Patch& p = patches.patches[j];
    if (faceInShape[j] == kNoFace || scene.materials[p.material].isEmissive()) return nullptr;
    faceOf[j] = shapeStart[p.shape] + faceInShape[j];
    if (faceOf[j] >= nf) return nullptr;
    ++l.faceStart_[faceOf[j] + 1];
  }
  for (uint32_t f = 0; f < nf; ++f) {
    if (l.faceStart_[f + 1] == 0) return nullptr;  // a face no patch covers
    l.faceStart_[f + 1] += l.faceStart_[f];
  }
  // The patches must tile each face: on its plane, and their areas its area (a hole would be traced as a surface).
  std::vector<double> faceArea(nf, 0.0);
  for (uint32_t j = 0; j < np; ++j) {
    const Patch& p = patches.patches[j];
    const Patch& face = l.faces_.patches[faceOf[j]];
    const double size = std::sqrt(face.area) + 1e-30;
    for (uint32_t i = 0; i < p.count; ++i)
      if (std::abs(glm::dot(Vec3d(p.v[i]) - Vec3d(face.v[0]), Vec3d(face.normal))) > 1e-4 * size) return nullptr;
    faceArea[faceOf[j]] += p.area;
  }
  for (uint32_t f = 0; f < nf; ++f)
    if (std::abs(faceArea[f] - l.faces_.patches[f].area) > 1e-4 * l.faces_.patches[f].area) return nullptr;
  l.facePatches_.resize(np);
  std::vector<uint32_t> next(l.faceStart_.begin(), l.faceStart_.end() - 1);
  for (uint32_t j = 0; j < np; ++j) l.facePatches_[next[faceOf[j]]++] = j;

  // Each patch flattened into its face's plane.
  l.grids_.resize(nf);
  for (uint32_t f = 0; f < nf; ++f) l.grids_[f].axis = uint8_t(largestAxis(l.faces_.patches[f].normal));
  l.flat_.resize(np);
  for (uint32_t j = 0; j < np; ++j) {
    const Patch& p = patches.patches[j];
    const int axis = l.grids_[faceOf[j]].axis;
    Flat& fl = l.flat_[j];
    fl.count = p.count;
    float area = 0.0f;
    for (uint32_t i = 0; i < 4; ++i) fl.q[i] = drop(p.v[std::min(i, p.count - 1)], axis);
    for (uint32_t i = 0; i < p.count; ++i) area += cross2(fl.q[i], fl.q[(i + 1) % p.count]);
    fl.sign = area >= 0.0f ? 1.0f : -1.0f;
  }
  l.nodes_.emplace_back();  // node 0 is a placeholder: no entry refers to it
  for (uint32_t f = 0; f < nf; ++f) {
    const ShapeDesc& shape = scene.shapes[faceShape[f]];
    if (l.fillGrid(f, shape, shape.faces[faceIndex[f]], patches.patchSize)) {
      ++l.gridFaces_;
      continue;
    }
    Grid& g = l.grids_[f];  // one cell: the face's patches in one quadtree
    g.kind = Kind::Whole;
    g.cellBase = uint32_t(l.cells_.size());
    std::vector<uint32_t> items(l.patchesOf(f), l.patchesOf(f) + l.patchCount(f));
    l.cells_.push_back(items.size() == 1 ? items[0] : l.quadtree(items));
  }
  return loc;
}

void PatchLocator::box(uint32_t j, Vec2& lo, Vec2& hi) const {
  lo = hi = flat_[j].q[0];
  for (uint32_t i = 1; i < flat_[j].count; ++i) lo = glm::min(lo, flat_[j].q[i]), hi = glm::max(hi, flat_[j].q[i]);
}

double PatchLocator::flatArea(uint32_t j) const {
  double a = 0.0;
  for (uint32_t i = 0; i < flat_[j].count; ++i) a += cross2(Vec2d(flat_[j].q[i]), Vec2d(flat_[j].q[(i + 1) % flat_[j].count]));
  return std::abs(a);
}

Vec2 PatchLocator::center(uint32_t j) const {
  Vec2 c(0.0f);
  for (uint32_t k = 0; k < flat_[j].count; ++k) c += flat_[j].q[k];
  return c / float(flat_[j].count);
}

bool PatchLocator::fillGrid(uint32_t face, const ShapeDesc& shape, const Face& sf, double patchSize) {
  if (!(patchSize > 0.0)) return false;
  Grid& g = grids_[face];
  Vec3d v[4];
  for (int i = 0; i < sf.count; ++i) v[i] = shape.vertices[sf.v[i]];
  double cn = 1, cm = 1;
  polygonCells(v, sf.count, patchSize, cn, cm);
  const uint32_t count = patchCount(face);
  const double slots = sf.count == 4 ? cn * cm : 2.0 * cn * cn;
  if (slots > 2.0 * double(count) + 8.0) return false;  // not this mesh's grid
  g.n = uint32_t(cn), g.m = uint32_t(cm);
  g.od = drop(v[0], g.axis);
  g.e = drop(v[1], g.axis) - g.od;
  g.f = drop(sf.count == 3 ? v[2] : v[3], g.axis) - g.od;
  g.g = sf.count == 3 ? Vec2d(0.0) : drop(v[2], g.axis) - g.od - g.e - g.f;
  g.kind = sf.count == 3 ? Kind::Triangle
           : glm::length(g.g) <= 1e-9 * (glm::length(g.e) + glm::length(g.f)) ? Kind::Parallelogram
                                                                               : Kind::Bilinear;
  const double det = cross2(g.e, g.f);
  if (!(std::abs(det) > 0.0)) return false;
  g.o = Vec2(g.od);
  g.m0 = Vec2(Vec2d(g.f.y, -g.f.x) / det);
  g.m1 = Vec2(Vec2d(-g.e.y, g.e.x) / det);
  // Each patch in the cell of its centre, every corner within that cell.
  std::vector<std::vector<uint32_t>> inCell(static_cast<size_t>(slots));
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t j = patchesOf(face)[i];
    Vec2 local;
    const uint32_t cell = cellOf(g, gridCoords(g, center(j)), local);
    const bool triangle = g.kind == Kind::Triangle, upper = triangle && (cell & 1u);
    const uint32_t ci = (triangle ? cell / 2 : cell) % g.n, cj = (triangle ? cell / 2 : cell) / g.n;
    for (uint32_t k = 0; k < flat_[j].count; ++k) {
      const Vec2d x = Vec2d(gridCoords(g, flat_[j].q[k])) * Vec2d(g.n, g.m) - Vec2d(ci, cj);
      if (x.x < -kCellTolerance || x.y < -kCellTolerance || x.x > 1 + kCellTolerance || x.y > 1 + kCellTolerance)
        return false;
      if (triangle && (upper ? x.x + x.y < 1 - kCellTolerance : x.x + x.y > 1 + kCellTolerance)) return false;
    }
    inCell[cell].push_back(j);
  }
  auto used = [&](uint32_t c) {  // a triangle's grid has k² cells in 2k² slots
    const uint32_t i = (c / 2) % g.n, j = (c / 2) / g.n;
    return g.kind != Kind::Triangle || i + j + (c & 1u) < g.n;
  };
  for (uint32_t c = 0; c < inCell.size(); ++c)
    if (used(c) && inCell[c].empty()) return false;  // a cell no patch covers: not this mesh's grid
  g.cellBase = uint32_t(cells_.size());
  cells_.resize(cells_.size() + inCell.size(), 0);
  for (uint32_t c = 0; c < inCell.size(); ++c) {
    if (!used(c)) continue;
    uint32_t entry = inCell[c].size() == 1 ? inCell[c][0] : refinement(g, inCell[c]);
    if (entry == kTag) entry = quadtree(inCell[c]);
    else if (inCell[c].size() > 1) ++refinedCells_;
    cells_[g.cellBase + c] = entry;
  }
  return true;
}

uint32_t PatchLocator::refinement(const Grid& g, const std::vector<uint32_t>& items) {
  const bool triangle = g.kind == Kind::Triangle;
  double cellArea = 0.0;
  for (uint32_t j : items) cellArea += flatArea(j);  // areas in the face's projection: their ratios are the same
  const size_t firstSplit = splits_.size();
  auto fail = [&] {
    splits_.resize(firstSplit);
    return kTag;
  };
  constexpr uint32_t kEmpty = 0xffffffffu;
  splits_.push_back({kEmpty, kEmpty, kEmpty, kEmpty});
  // Each patch at the depth its area tells (a quarter a split), down the path of its centre.
  for (uint32_t j : items) {
    const double splits = 0.5 * std::log2(cellArea / flatArea(j));
    const int depth = int(std::lround(splits));
    if (depth < 1 || depth > kMaxSplits || std::abs(splits - depth) > 0.25) return fail();
    Vec2 x;
    cellOf(g, gridCoords(g, center(j)), x);
    uint32_t node = uint32_t(firstSplit);
    for (int d = 0; d < depth; ++d) {
      const int c = splitChild(triangle, x);
      uint32_t& child = splits_[node][size_t(c)];
      if (d + 1 == depth) {
        if (child != kEmpty) return fail();  // two patches in one place, or a patch over a split
        child = j;
      } else {
        if (child == kEmpty) {
          child = kSplit | uint32_t(splits_.size());
          splits_.push_back({kEmpty, kEmpty, kEmpty, kEmpty});  // invalidates `child`, written already
        } else if ((child & kTag) != kSplit) {
          return fail();
        }
        node = splits_[node][size_t(c)] & ~kTag;
      }
    }
  }
  for (size_t s = firstSplit; s < splits_.size(); ++s)
    for (uint32_t c : splits_[s])
      if (c == kEmpty) return fail();  // a hole: not the refinement's tiling
  // Every corner of every patch, pulled a little towards its centre, must lead to it.
  const uint32_t root = kSplit | uint32_t(firstSplit);
  for (uint32_t j : items)
    for (uint32_t k = 0; k < flat_[j].count; ++k) {
      Vec2 x;
      cellOf(g, gridCoords(g, center(j) + 0.98f * (flat_[j].q[k] - center(j))), x);
      if (descend(root, triangle, x) != j) return fail();
    }
  return root;
}

Vec2 PatchLocator::gridCoords(const Grid& g, Vec2 q) {
  if (g.kind != Kind::Bilinear) {
    const Vec2 h = q - g.o;
    return Vec2(glm::dot(g.m0, h), glm::dot(g.m1, h));
  }
  // q = o + s e + t f + s t g: t solves k2 t² + k1 t + k0 = 0 (cross both sides with e + t g), then s.
  const Vec2d h = Vec2d(q) - g.od;
  const double k2 = cross2(g.g, g.f), k1 = cross2(g.e, g.f) + cross2(h, g.g), k0 = cross2(h, g.e);
  double t;
  if (std::abs(k2) <= 1e-12 * std::abs(cross2(g.e, g.f))) {
    t = -k0 / k1;
  } else {
    const double w = std::sqrt(std::max(0.0, k1 * k1 - 4.0 * k0 * k2));
    const double r = -0.5 * (k1 + std::copysign(w, k1));
    const double t0 = r / k2, t1 = r != 0.0 ? k0 / r : t0;
    auto off = [](double x) { return std::max(0.0, std::max(-x, x - 1.0)); };
    t = off(t0) <= off(t1) ? t0 : t1;
  }
  const Vec2d d = g.e + t * g.g, r = h - t * g.f;
  const double s = std::abs(d.x) >= std::abs(d.y) ? r.x / d.x : r.y / d.y;
  return Vec2(float(s), float(t));
}

uint32_t PatchLocator::cellOf(const Grid& g, Vec2 st, Vec2& local) {
  const float x = st.x * float(g.n), y = st.y * float(g.m);
  auto clampCell = [](float v, uint32_t n) {  // NaN (a degenerate ray) to cell 0
    const float c = std::floor(v);
    return c >= 0.0f ? (c < float(n - 1) ? uint32_t(c) : n - 1) : 0u;
  };
  uint32_t j = clampCell(y, g.m), i = clampCell(x, g.n);
  if (g.kind != Kind::Triangle) {
    local = Vec2(x - float(i), y - float(j));
    return j * g.n + i;
  }
  if (i + j >= g.n) i = g.n - 1 - j;  // beyond the long edge by a rounding
  const Vec2 l(x - float(i), y - float(j));
  const bool upper = l.x + l.y > 1.0f && i + j + 1 < g.n;
  // The upper cell's corners (1, 0), (1, 1), (0, 1) of the pair's square as its corners 0, 1, 2.
  local = upper ? Vec2(l.x + l.y - 1.0f, 1.0f - l.x) : l;
  return 2 * (j * g.n + i) + uint32_t(upper);
}

uint32_t PatchLocator::descend(uint32_t entry, bool triangle, Vec2 local) const {
  while ((entry & kTag) == kSplit) entry = splits_[entry & ~kTag][size_t(splitChild(triangle, local))];
  return entry;
}

uint32_t PatchLocator::quadtree(std::vector<uint32_t>& items) {
  Vec2 lo, hi, blo, bhi;
  box(items[0], lo, hi);
  for (uint32_t j : items) box(j, blo, bhi), lo = glm::min(lo, blo), hi = glm::max(hi, bhi);
  const uint32_t root = uint32_t(nodes_.size());
  nodes_.emplace_back();
  buildNode(root, items, lo, hi, 0);
  return kQuadtree | root;
}

void PatchLocator::buildNode(uint32_t slot, std::vector<uint32_t>& items, Vec2 lo, Vec2 hi, int depth) {
  auto leaf = [&] {
    nodes_[slot].first = uint32_t(leafPatches_.size());
    nodes_[slot].count = uint32_t(items.size());
    leafPatches_.insert(leafPatches_.end(), items.begin(), items.end());
  };
  if (items.size() <= kLeafPatches || depth >= kMaxDepth) return leaf();
  const Vec2 mid = 0.5f * (lo + hi);
  const float tol = 1e-5f * std::max(hi.x - lo.x, hi.y - lo.y);
  std::vector<uint32_t> quadrant[4];
  for (uint32_t j : items) {
    Vec2 blo, bhi;
    box(j, blo, bhi);
    for (int q = 0; q < 4; ++q) {
      const bool x = (q & 1) ? bhi.x >= mid.x - tol : blo.x <= mid.x + tol;
      const bool y = (q & 2) ? bhi.y >= mid.y - tol : blo.y <= mid.y + tol;
      if (x && y) quadrant[q].push_back(j);
    }
  }
  if (std::all_of(quadrant, quadrant + 4, [&](const std::vector<uint32_t>& v) { return v.size() == items.size(); }))
    return leaf();  // every box spans the split: no quadrant is smaller
  const uint32_t child = uint32_t(nodes_.size());
  nodes_.resize(nodes_.size() + 4);
  nodes_[slot].mid = mid;
  nodes_[slot].child = child;
  for (uint32_t q = 0; q < 4; ++q) {
    const Vec2 qlo((q & 1) ? mid.x : lo.x, (q & 2) ? mid.y : lo.y);
    const Vec2 qhi((q & 1) ? hi.x : mid.x, (q & 2) ? hi.y : mid.y);
    buildNode(child + q, quadrant[q], qlo, qhi, depth + 1);
  }
}

float PatchLocator::outsideOf(const Flat& fl, Vec2 p) {
  float worst = 0.0f;
  for (uint32_t i = 0; i < fl.count; ++i) {
    const Vec2 a = fl.q[i], e = fl.q[(i + 1) % fl.count] - a;
    const float c = fl.sign * cross2(e, p - a);
    if (c < 0.0f) {
      const float len = glm::length(e);
      if (len > 0.0f) worst = std::max(worst, -c / len);
    }
  }
  return worst;
}

uint32_t PatchLocator::quadtreeLeaf(uint32_t face, uint32_t root, Vec2 q) const {
  const Node* node = &nodes_[root];
  while (node->child != 0) node = &nodes_[node->child + uint32_t(q.x > node->mid.x) + 2u * uint32_t(q.y > node->mid.y)];
  // A point in a quadrant no patch reaches (beyond a triangle's long edge, by a rounding): the leaf is empty, and the
  // face's patches are all asked.
  const bool empty = node->count == 0;
  const uint32_t* list = empty ? patchesOf(face) : &leafPatches_[node->first];
  const uint32_t count = empty ? patchCount(face) : node->count;
  uint32_t best = list[0];
  float bestOutside = INFINITY;
  for (uint32_t i = 0; i < count; ++i) {
    const float d = outsideOf(flat_[list[i]], q);
    if (d < bestOutside) {
      best = list[i], bestOutside = d;
      if (d == 0.0f) break;
    }
  }
  return best;
}

uint32_t PatchLocator::locate(uint32_t face, const Vec3& p) const {
  const Grid& g = grids_[face];
  const Vec2 q = drop(p, g.axis);
  Vec2 local(0.0f);
  const uint32_t entry = g.kind == Kind::Whole ? cells_[g.cellBase] : cells_[g.cellBase + cellOf(g, gridCoords(g, q), local)];
  switch (entry & kTag) {
    case kSplit: return descend(entry, g.kind == Kind::Triangle, local);
    case kQuadtree: return quadtreeLeaf(face, entry & ~kTag, q);
    default: return entry;
  }
}

}  // namespace firstshot
