#include "preprocess/coverage.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/lights/form_factors.h"

namespace firstshot {
namespace {

using analytic::clipPolygonToPlane;

/// A polygon clipped to the near plane and projected onto a view's image plane.
struct Projected {
  Vec2d q[8];
  int n = 0;
  double sign = 1;  ///< orientation, so that "inside" means the same side of every edge
  int i0 = 0, i1 = -1, j0 = 0, j1 = -1;  ///< pixel index range whose centres may fall inside
};

/// Projects the convex planar polygon @p poly, clipped to depth ≥ @p near; false if nothing is left.
bool project(const View& view, const Vec3d* poly, int count, double near, Projected& out) {
  Vec3d clipped[8];
  const bool persp = view.projection == Projection::Perspective;
  const int n = clipPolygonToPlane(poly, count, view.eye, view.forward, persp ? near : 0.0, clipped);
  if (n < 3) return false;
  Vec2d lo(1e300), hi(-1e300);
  for (int i = 0; i < n; ++i) {
    const Vec3d r = clipped[i] - view.eye;
    const double z = persp ? glm::dot(r, view.forward) : 1.0;
    out.q[i] = Vec2d(glm::dot(r, view.right) / z, glm::dot(r, view.up) / z);
    lo = glm::min(lo, out.q[i]), hi = glm::max(hi, out.q[i]);
  }
  out.n = n;
  double area2 = 0;
  for (int i = 0; i < n; ++i) area2 += out.q[i].x * out.q[(i + 1) % n].y - out.q[(i + 1) % n].x * out.q[i].y;
  if (area2 == 0) return false;
  out.sign = area2 > 0 ? 1.0 : -1.0;
  const double du = (view.planeMax.x - view.planeMin.x) / view.width, dv = (view.planeMax.y - view.planeMin.y) / view.height;
  out.i0 = std::max(0, int(std::floor((lo.x - view.planeMin.x) / du - 0.5)));
  out.i1 = std::min(view.width - 1, int(std::ceil((hi.x - view.planeMin.x) / du - 0.5)));
  out.j0 = std::max(0, int(std::floor((view.planeMax.y - hi.y) / dv - 0.5)));
  out.j1 = std::min(view.height - 1, int(std::ceil((view.planeMax.y - lo.y) / dv - 0.5)));
  return out.i0 <= out.i1 && out.j0 <= out.j1;  // else beside the view: no pixel centre to visit
}

/// Calls fn(i, j, w) for every pixel centre (i, j) of @p view with weight w > 0 that falls inside the
/// convex planar polygon @p poly clipped to depth ≥ @p near.
template <typename Fn>
void forEachCentre(const View& view, const std::vector<double>& weights, const Vec3d* poly, int count, double near, Fn fn) {
  Projected pr;
  if (!project(view, poly, count, near, pr)) return;
  const int n = pr.n;
  const double sign = pr.sign;
  Vec2d ea[8], eb[8];
  for (int e = 0; e < n; ++e) ea[e] = pr.q[e], eb[e] = pr.q[(e + 1) % n];
  // The inside test, in exactly this floating-point form. Each edge's test is monotone in the centre's
  // x (every operation is), so a row's centres inside form one run of pixels: found from the edges'
  // crossings, widened by a pixel each side and grown while the test holds beyond its ends, then
  // every pixel of it is tested as before. Same centres as testing the whole bounding box.
  auto inside = [&](const Vec2d& c) {
    for (int e = 0; e < n; ++e) {
      const Vec2d a = ea[e], b = eb[e];
      if (!(sign * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)) >= 0)) return false;
    }
    return true;
  };
  const double du = (view.planeMax.x - view.planeMin.x) / view.width;
  // View::pixelCentre()'s own expressions, the y one hoisted out of the row.
  const double spanX = view.planeMax.x - view.planeMin.x;
  auto centre = [&](int i, double cy) { return Vec2d(view.planeMin.x + (i + 0.5) * spanX / view.width, cy); };
  for (int j = pr.j0; j <= pr.j1; ++j) {
    const double cy = view.pixelCentre(0, j).y;
    double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    for (int e = 0; e < n; ++e) {
      const Vec2d a = ea[e], b = eb[e];
      const double dy = b.y - a.y;
      if (dy == 0) continue;  // independent of x: tested per pixel below
      const double x = a.x + (b.x - a.x) * (cy - a.y) / dy;
      if (!std::isfinite(x)) continue;
      if (-sign * dy > 0) lo = std::max(lo, x);
      else hi = std::min(hi, x);
    }
    int i0 = pr.i0, i1 = pr.i1;
    if (lo > -std::numeric_limits<double>::infinity())
      i0 = std::max(i0, int(std::max(-1e9, std::min(1e9, std::ceil((lo - view.planeMin.x) / du - 0.5)))) - 1);
    if (hi < std::numeric_limits<double>::infinity())
      i1 = std::min(i1, int(std::max(-1e9, std::min(1e9, std::floor((hi - view.planeMin.x) / du - 0.5)))) + 1);
    if (i0 > i1) {
      i0 = std::min(std::max(i0, pr.i0), pr.i1), i1 = i0;  // a one-pixel probe; grows below if inside
    }
    while (i0 > pr.i0 && inside(centre(i0, cy))) --i0;
    while (i1 < pr.i1 && inside(centre(i1, cy))) ++i1;
    // The run's ends, tested inwards; the test holds for every centre between them.
    while (i0 <= i1 && !inside(centre(i0, cy))) ++i0;
    while (i1 > i0 && !inside(centre(i1, cy))) --i1;
    const double* w = weights.data() + size_t(j) * view.width;
    for (int i = i0; i <= i1; ++i)
      if (w[i] > 0) fn(i, j, w[i], centre(i, cy));
  }
}

/// A patch's plane and edges in double precision, for exact ray tests.
struct ExactPolygon {
  Vec3d v[4];
  Vec3d n{0.0};  ///< Newell normal (not unit), orientation of the vertex order
  int count = 0;
  ExactPolygon() = default;
  explicit ExactPolygon(const Patch& p) : count(int(p.count)) {
    for (int k = 0; k < count; ++k) v[k] = Vec3d(p.v[k]);
    for (int k = 0; k < count; ++k) n += glm::cross(v[k], v[(k + 1) % count]);
  }
  /// Ray parameter where o + t·d meets the plane (+inf if parallel).
  double planeDepth(const Vec3d& o, const Vec3d& d) const {
    const double den = glm::dot(d, n);
    return den != 0 ? glm::dot(v[0] - o, n) / den : std::numeric_limits<double>::infinity();
  }
  /// True if the point @p x of the plane lies inside the polygon or on its boundary.
  bool contains(const Vec3d& x) const {
    for (int k = 0; k < count; ++k)
      if (glm::dot(glm::cross(v[(k + 1) % count] - v[k], x - v[k]), n) < 0) return false;
    return true;
  }
};

/// A candidate occluder of one patchCoverage() call.
struct Candidate {
  ExactPolygon polygon;
  /// False when no vertex lies on the eye's side of the patch's plane: then no point of the candidate
  /// is in front of the patch along any ray from the eye (the coplanar neighbours of a mesh, the
  /// surfaces behind it), and the ray test is skipped.
  bool inFront = true;
};

/// The candidate occluders one patchCoverage() call meets, built once each (a patch's neighbours
/// recur at most of its border pixels).
class PolygonCache {
 public:
  /// @p self: the patch whose coverage is taken, seen from @p view.
  PolygonCache(const PatchMesh& mesh, const ExactPolygon& self, const View& view) : mesh_(mesh), self_(self) {
    const double side = view.projection == Projection::Perspective ? glm::dot(view.eye - self.v[0], self.n)
                                                                    : -glm::dot(view.forward, self.n);
    eyeSide_ = side > 0 ? 1.0 : side < 0 ? -1.0 : 0.0;
  }
  double eyeSide() const { return eyeSide_; }
  const Candidate& get(uint32_t id) {
    for (int k = 0; k < n_; ++k)
      if (ids_[k] == id) return polys_[k];
    const int k = n_ < kSize ? n_++ : (next_++ % kSize);
    ids_[k] = id;
    Candidate& c = polys_[k];
    c.polygon = ExactPolygon(mesh_.patches[id]);
    c.inFront = eyeSide_ == 0;
    for (int v = 0; v < c.polygon.count && !c.inFront; ++v)
      c.inFront = eyeSide_ * glm::dot(c.polygon.v[v] - self_.v[0], self_.n) > 0;
    return c;
  }

 private:
  static constexpr int kSize = 16;
  const PatchMesh& mesh_;
  const ExactPolygon& self_;
  double eyeSide_ = 0;  ///< sign of the eye's side of the patch's plane (0: in the plane)
  uint32_t ids_[kSize];
  Candidate polys_[kSize];
  int n_ = 0, next_ = 0;
};

/// True if a patch seen at pixel (i, j) of @p view or one of its 8 neighbours, other than @p patch,
/// is hit by the ray o + t·d strictly before depth @p tSelf (and not before @p near).
bool occludedNear(const View& view, const std::vector<uint32_t>& ids, const PatchMesh& mesh, uint32_t patch, int i, int j,
                  const Vec3d& o, const Vec3d& d, double tSelf, double near, PolygonCache& polygons,
                  const PatchCutouts* cutouts) {
  // Depth tolerance: planes of neighbours rebuilt from float vertices agree to ~1e-7 relative.
  constexpr double kRelativeTolerance = 1e-6;
  const double tMax = tSelf - kRelativeTolerance * std::abs(tSelf);
  uint32_t cand[9];
  int nc = 0;
  for (int y = std::max(0, j - 1); y <= std::min(view.height - 1, j + 1); ++y)
    for (int x = std::max(0, i - 1); x <= std::min(view.width - 1, i + 1); ++x) {
      const uint32_t id = ids[size_t(y) * view.width + x];
      if (id == patch || id >= mesh.size()) continue;
      bool seen = false;
      for (int c = 0; c < nc && !seen; ++c) seen = cand[c] == id;
      if (seen) continue;
      cand[nc++] = id;
      const Candidate& c = polygons.get(id);
      if (!c.inFront) continue;
      const ExactPolygon& other = c.polygon;
      const double t = other.planeDepth(o, d);
      if (t >= near && t < tMax && other.contains(o + t * d) &&
          (!cutouts || cutouts->exists(id, o + t * d, cutoutKey(Vec3(o), Vec3(d), id))))
        return true;
    }
  return false;
}

}  // namespace

void markProjection(const View& view, const Patch& patch, double near, int margin, std::vector<uint8_t>& mask) {
  Vec3d poly[4];
  for (uint32_t k = 0; k < patch.count; ++k) poly[k] = Vec3d(patch.v[k]);
  Projected pr;
  if (!project(view, poly, int(patch.count), near, pr)) return;
  const int i0 = std::max(0, pr.i0 - margin), i1 = std::min(view.width - 1, pr.i1 + margin);
  const int j0 = std::max(0, pr.j0 - margin), j1 = std::min(view.height - 1, pr.j1 + margin);
  for (int j = j0; j <= j1; ++j) std::fill_n(mask.begin() + size_t(j) * view.width + i0, std::max(0, i1 - i0 + 1), uint8_t(1));
}

double coveredWeight(const View& view, const std::vector<double>& weights, const Vec3d* poly, int count, double near,
                     size_t& pixels) {
  pixels = 0;
  double sum = 0;
  forEachCentre(view, weights, poly, count, near, [&](int, int, double w, const Vec2d&) { sum += w, ++pixels; });
  return sum;
}

PatchCoverage patchCoverage(const View& view, const std::vector<double>& weights, const std::vector<uint32_t>& ids,
                            const PatchMesh& mesh, uint32_t patch, double near, const ExposureQuery* exposure,
                            const PatchCutouts* cutouts) {
  PatchCoverage r;
  const Patch& p = mesh.patches[patch];
  Vec3d poly[4];
  for (uint32_t k = 0; k < p.count; ++k) poly[k] = Vec3d(p.v[k]);
  const ExactPolygon self(p);
  PolygonCache polygons(mesh, self, view);
  const uint32_t n = mesh.size();
  const bool persp = view.projection == Projection::Perspective;
  // clean(x, j): column x of rows j − 1 … j + 1 shows no other patch; each column once per row
  // (memoized under a key of this call and the row, so nothing is cleared between calls).
  thread_local std::vector<uint64_t> columnKey;
  thread_local std::vector<uint8_t> columnClean;
  thread_local uint64_t call = 0;  // < 2³², so keys of different calls never coincide
  if (++call >> 32 || columnKey.size() < size_t(view.width))
    call = 1, columnKey.assign(std::max(columnKey.size(), size_t(view.width)), 0), columnClean.resize(columnKey.size());
  auto clean = [&](int x, int j) {
    const uint64_t key = (call << 32) | uint32_t(j);
    if (columnKey[x] != key) {
      bool c = true;
      for (int y = std::max(0, j - 1); y <= std::min(view.height - 1, j + 1); ++y) {
        const uint32_t id = ids[size_t(y) * view.width + x];
        c = c && (id == patch || id >= n);
      }
      columnKey[x] = key, columnClean[x] = c;
    }
    return columnClean[x] != 0;
  };
  forEachCentre(view, weights, poly, int(p.count), near, [&](int i, int j, double w, const Vec2d& uv) {
    // No other patch shows at this pixel or its 8 neighbours: nothing to propose as an occluder,
    // so the centre is visible (what occludedNear() would find, without computing the ray).
    const bool clear = clean(std::max(0, i - 1), j) && clean(i, j) && clean(std::min(view.width - 1, i + 1), j);
    const bool selfCut = cutouts && cutouts->cutout(patch);
    if (clear && !exposure && !selfCut) {
      r.expected += w, ++r.pixels, r.visible += w;
      return;
    }
    // View::pixelOrigin() and pixelDirection() at the centre already computed.
    const Vec3d o = persp ? view.eye : view.eye + uv.x * view.right + uv.y * view.up;
    const Vec3d d = persp ? view.forward + uv.x * view.right + uv.y * view.up : view.forward;
    const double t = self.planeDepth(o, d);
    if (exposure && exposure->buried(o + t * d)) return;
    if (selfCut && cutouts->coverage(patch, o + t * d) == 0.0f) return;  // a mask's hole (a blend's points all count)
    r.expected += w, ++r.pixels;
    if (clear || !occludedNear(view, ids, mesh, patch, i, j, o, d, t, near, polygons, cutouts)) r.visible += w;
  });
  return r;
}

bool pointVisibilityRay(const std::vector<View>& views, const std::vector<std::vector<double>>& weights, const Vec3d& x,
                        double near, Vec3d& origin) {
  for (size_t v = 0; v < views.size(); ++v) {
    const View& view = views[v];
    const bool persp = view.projection == Projection::Perspective;
    const Vec3d r = x - view.eye;
    const double z = glm::dot(r, view.forward);
    if (persp ? !(z >= near) : !(z > 0)) continue;
    const double u = glm::dot(r, view.right) / (persp ? z : 1.0), w = glm::dot(r, view.up) / (persp ? z : 1.0);
    if (u < view.planeMin.x || u >= view.planeMax.x || w <= view.planeMin.y || w > view.planeMax.y) continue;
    const int i = std::min(view.width - 1, int((u - view.planeMin.x) / (view.planeMax.x - view.planeMin.x) * view.width));
    const int j = std::min(view.height - 1, int((view.planeMax.y - w) / (view.planeMax.y - view.planeMin.y) * view.height));
    if (!(weights[v][size_t(j) * view.width + i] > 0)) continue;
    origin = persp ? view.eye : view.eye + u * view.right + w * view.up;
    return true;
  }
  return false;
}

double unoccludedProjectedArea(const Vec3d& direction, const Vec3d* poly, int count) {
  return analytic::polygonProjectedArea(direction, poly, count);
}

// ---- For the GPU reduction (preprocess/gl/gl_reduce.h) ----

bool coverageSetup(const View& view, const Patch& patch, double near, CoverageSetup& out) {
  Vec3d poly[4];
  for (uint32_t k = 0; k < patch.count; ++k) poly[k] = Vec3d(patch.v[k]);
  Projected pr;
  if (!project(view, poly, int(patch.count), near, pr)) return false;
  std::copy(pr.q, pr.q + pr.n, out.q);
  out.n = pr.n, out.sign = pr.sign, out.i0 = pr.i0, out.i1 = pr.i1, out.j0 = pr.j0, out.j1 = pr.j1;
  const ExactPolygon self(patch);
  static const PatchMesh none;
  const PolygonCache polygons(none, self, view);  // its eye side, as patchCoverage() takes it
  out.eyeSide = polygons.eyeSide();
  return true;
}

Vec3d exactNormal(const Patch& patch) { return ExactPolygon(patch).n; }

}  // namespace firstshot
