// One light sample's factors: window, item buffers, analytic estimator (preprocess/sample_shot.h).
#include "preprocess/sample_shot.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "common/lights/spot_integral.h"
#include "common/table/firstshot_groups.h"
#include "preprocess/coverage.h"
#include "preprocess/embree_item_buffer.h"
#include "preprocess/gl/gl_reduce.h"
#include "preprocess/profile.h"

namespace firstshot {

namespace {

/// Fewer pixel centres than this inside a patch and the fraction is taken at points on it instead.
constexpr size_t kMinPixelsForAnalytic = 4;

/// Which side of patch @p p sample @p s lights: 0 the normal's side, 1 the other.
int litSide(const SampleSetup& s, const Patch& p) {
  const Vec3d n(p.normal);
  const double side = s.kind == LightSampleKind::Directional ? -glm::dot(s.axis, n) : glm::dot(s.position - Vec3d(p.centroid), n);
  return side >= 0 ? 0 : 1;
}

/// The closed-form integral of the window weight over the whole patch (no occlusion); for points and
/// area vertices the one the reader recomputes grouped factors from (common/table/firstshot_groups.h).
double unoccludedIntegral(const SampleSetup& s, const Patch& p) {
  switch (s.kind) {
    case LightSampleKind::Point:
    case LightSampleKind::AreaVertex: return analyticIntegral(*s.sample, s.eyeOffset, p);
    case LightSampleKind::Directional: {
      Vec3d poly[4];
      for (uint32_t k = 0; k < p.count; ++k) poly[k] = Vec3d(p.v[k]);
      return unoccludedProjectedArea(s.axis, poly, int(p.count));
    }
    case LightSampleKind::Spot: return spotPatchIntegral(*s.sample, s.profile, p, litSide(s, p));  // numerical
  }
  return 0.0;
}

/// Points on a patch where its visible fraction is tested, each with its share of the patch's area:
/// the centroid and, if @p spread, the midpoints between the centroid and each vertex (equal shares);
/// or, if @p strata > 0, the centres of a strata × strata grid on each triangle of the patch mapped
/// area-preservingly onto it (shares by the triangle's area).
struct PatchPoint {
  Vec3d x;
  double share;
};

/// The grid sides of stratified points: 16 per triangle, then 256 on a patch they find partly lit
/// (a shadow edge parallel to the grid leaves up to 1/32 of the patch wrong at 16).
constexpr int kStrata = 4, kFineStrata = 16;
/// Points tested along each edge of a patch the coarse grid finds all lit or all dark.
constexpr int kEdgePoints = 8;

void patchPoints(const Patch& p, bool spread, int strata, std::vector<PatchPoint>& out) {
  out.clear();
  const Vec3d c(p.centroid);
  if (strata <= 0) {
    for (uint32_t k = spread ? 0 : p.count; k <= p.count; ++k) out.push_back({k == p.count ? c : 0.5 * (c + Vec3d(p.v[k])), 1.0});
    return;
  }
  for (uint32_t t = 0; t + 2 < p.count; ++t) {
    const Vec3d a(p.v[0]), b(p.v[t + 1]), d(p.v[t + 2]);
    const double share = 0.5 * glm::length(glm::cross(b - a, d - a)) / (strata * strata);
    for (int i = 0; i < strata; ++i)
      for (int j = 0; j < strata; ++j) {
        const double su = std::sqrt((i + 0.5) / strata), v = (j + 0.5) / strata;  // uniform over the triangle
        out.push_back({a + su * (1.0 - v) * (b - a) + su * v * (d - a), share});
      }
  }
}

/// Visible fraction of a patch from points on it (for patches covering too few pixel centres; see
/// patchPoints). −1 if none is in a view.
double pointVisibleFraction(const std::vector<View>& views, const SampleSetup& s, const EmbreeItemBuffer& rays,
                            double near, const PatchMesh& mesh, uint32_t patch, bool spread,
                            const ExposureQuery* exposure, bool stratified = false) {
  const Patch& p = mesh.patches[patch];
  // 1 visible, 0 hidden, −1 not tested (buried, in a mask's hole, or outside every view); the rays of a batch of
  // points are traced together (in packets: a directional light's are parallel).
  thread_local std::vector<Vec3d> origins, directions;
  thread_local std::vector<size_t> traced;
  thread_local std::vector<uint8_t> occluded;
  const auto visibleAt = [&](const std::vector<Vec3d>& xs, std::vector<int>& out) {
    out.assign(xs.size(), -1);
    origins.clear(), directions.clear(), traced.clear();
    for (size_t k = 0; k < xs.size(); ++k) {
      const Vec3d& x = xs[k];
      if (exposure && exposure->buried(x)) continue;
      if (rays.cutouts() && rays.cutouts()->coverage(patch, x) == 0.0f) continue;
      Vec3d o;
      if (!pointVisibilityRay(views, *s.weights, x, near, o)) continue;
      origins.push_back(o), directions.push_back(x - o), traced.push_back(k);
    }
    occluded.resize(traced.size());
    rays.occluded(origins.data(), directions.data(), kPointRayEnd, traced.size(), occluded.data());
    for (size_t i = 0; i < traced.size(); ++i) out[traced[i]] = occluded[i] ? 0 : 1;
  };
  thread_local std::vector<PatchPoint> points;
  thread_local std::vector<Vec3d> xs;
  thread_local std::vector<int> seenAt;
  const auto fraction = [&](int strata) {
    patchPoints(p, spread, strata, points);
    xs.clear();
    for (const PatchPoint& q : points) xs.push_back(q.x);
    visibleAt(xs, seenAt);
    double seen = 0, visible = 0;
    for (size_t k = 0; k < points.size(); ++k)
      if (seenAt[k] >= 0) seen += points[k].share, visible += seenAt[k] * points[k].share;
    return seen > 0 ? visible / seen : -1.0;
  };
  const double f = fraction(stratified ? kStrata : 0);
  if (!stratified || f < 0) return f;
  if (f > 0 && f < 1) return fraction(kFineStrata);
  // All lit or all dark: a lit sliver along an edge, or a shadow's, can fall between the grid's
  // points, so a ring just inside the boundary is walked too (kEdgePoints along each edge), a
  // sixteenth of the way in: the exact rays of a window over a whole scene skip their last 10⁻⁵
  // (2 mm of a 200 m one), and a point on the edge would see past the wall it meets.
  const Vec3d c(p.centroid);
  thread_local std::vector<Vec3d> ring;
  thread_local std::vector<int> ringSeen;
  ring.clear();
  for (uint32_t k = 0; k < p.count; ++k) {
    const Vec3d a(p.v[k]), b(p.v[(k + 1) % p.count]);
    for (int i = 0; i < kEdgePoints; ++i) {
      const Vec3d e = a + (i + 0.5) / kEdgePoints * (b - a);
      ring.push_back(e + (c - e) / 16.0);
    }
  }
  visibleAt(ring, ringSeen);
  for (const int v : ringSeen) {
    if (v < 0 || v == int(f)) continue;
    // The patch is partly lit: a sliver the fine grid misses too is less than one of its points'
    // share, so it takes half of one.
    const double fine = fraction(kFineStrata);
    const double half = 0.5 / (kFineStrata * kFineStrata * (p.count - 2));
    return fine == 0 ? half : fine == 1 ? 1 - half : fine;
  }
  return f;
}

/// The analytic estimator's visible fraction (preprocess/coverage.h; the factor is closed form × fraction), the fraction
/// decided in exact geometry at the pixel centres inside the patch, or at a few points on it when
/// fewer than kMinPixelsForAnalytic centres fall inside; a partly visible patch takes it over its
/// exposed part only (preprocess/exposure.h). @p touched: the patch shows in the item buffer.
/// @p exposure is required (it also lends its ray caster to the point tests). ≤ 0: no light.
/// @p computed: the coverage without exposure, computed on the GPU (null: here); @p needIds brings
/// @p ids to the CPU before the exposed part's coverage reads them.
double visibleFraction(const SampleSetup& s, const std::vector<View>& views, const std::vector<std::vector<uint32_t>>& ids,
                        double near, const PatchMesh& mesh, uint32_t patch, bool touched, ExposureCache* exposure,
                        const PatchCoverage* computed, const std::function<void()>& needIds) {
  auto coverage = [&](const ExposureQuery* mask) {
    PatchCoverage total;
    for (size_t v = 0; v < views.size(); ++v) {
      const PatchCoverage c = patchCoverage(views[v], (*s.weights)[v], ids[v], mesh, patch, near, mask,
                                            exposure->rays().cutouts());
      total.expected += c.expected, total.visible += c.visible, total.pixels += c.pixels;
    }
    return total;
  };
  ExposureQuery query;
  auto getMask = [&] {
    if (query.mask) return;
    query.cache = exposure, query.patch = patch, query.side = litSide(s, mesh.patches[patch]);
    query.mask = &exposure->mask(patch, query.side);
  };
  double fraction = -1;
  if (touched) {
    profile::Scope coverageTime(profile::Coverage);
    PatchCoverage total = computed ? *computed : coverage(nullptr);
    if (total.visible < total.expected && total.visible > 0) {  // partly visible: buried?
      coverageTime.stop();
      {
        profile::Scope exposureTime(profile::Exposure);
        getMask();
      }
      profile::Scope again(profile::CoverageExposed);
      if (query.mask->partial) needIds(), total = coverage(&query);
    }
    if (total.pixels >= kMinPixelsForAnalytic && total.expected > 0)
      fraction = std::min(1.0, total.visible / total.expected);
  }
  if (fraction < 0) {
    // 5 points; a patch that shows nowhere (occluded, or smaller than a pixel) is decided by its
    // centroid unless that lies outside the window.
    // A directional light's patches are tested at 16 points per triangle: its window spans the whole
    // scene, so a ground plane 200 m wide makes its pixels a metre wide, and one point would light
    // or darken a whole patch that a window's shadow crosses.
    profile::Scope pointTime(profile::PointTests);
    const bool stratified = s.kind == LightSampleKind::Directional;
    fraction = pointVisibleFraction(views, s, exposure->rays(), near, mesh, patch, touched, nullptr, stratified);
    if (fraction < 0 && !touched) fraction = pointVisibleFraction(views, s, exposure->rays(), near, mesh, patch, true, nullptr);
    if (fraction > 0 && fraction < 1) {
      pointTime.stop();
      {
        profile::Scope exposureTime(profile::Exposure);
        getMask();
      }
      profile::Scope again(profile::PointTests);
      if (query.mask->partial) fraction = pointVisibleFraction(views, s, exposure->rays(), near, mesh, patch, touched, &query, stratified);
    }
  }
  return fraction;
}

}  // namespace

/// r_ij of a patch with visible fraction @p fraction > 0 (closed-form kinds): the closed form times the
/// fraction, computed as the .fsd reader recomputes grouped factors (0 if the patch gets nothing).
float analyticPatchFactor(const SampleSetup& s, const Patch& p, double fraction) {
  const double U = unoccludedIntegral(s, p);
  return fraction * U > 0 ? analyticFactor(s.scale, fraction, U, p.area) : 0.0f;
}

/// Renders one sample's views and returns its non-zero factors over @p task's patches, sorted by
/// patch (sample_shot.h).
std::vector<Entry> renderSample(ItemBufferRenderer* renderer, const SampleSetup& s, const PatchMesh& mesh, const Task& task,
                                bool needVisible, ShotScratch& scratch, ExposureCache* exposure,
                                const OcclusionCull* cull, const Keeping& keeping) {
  std::vector<double>& acc = scratch.acc;
  std::vector<uint32_t>& touched = scratch.touched;
  std::vector<std::vector<uint32_t>>& idsPerView = scratch.ids;
  Framed frame(s.axis);
  if (s.rotation != 0) {  // turn the window about its axis: decorrelates aliasing between samples
    const double c = std::cos(s.rotation), sn = std::sin(s.rotation);
    const Vec3d a = frame.s, b = frame.t;
    frame.s = c * a + sn * b, frame.t = -sn * a + c * b;
  }
  const std::vector<View> views = placeWindow(*s.window, s.position, frame, s.eyeOffset);
  idsPerView.resize(views.size());
  const bool masked = !task.patches.empty();
  KeptItemBuffers* kept = keeping.buffers;
  const bool fromKept = masked && kept && keeping.first && kept->at(keeping.level - 1);
  if (fromKept) {
    profile::Scope keptTime(profile::Kept);
    kept->followSplit(views, mesh, *keeping.first);
    kept->unpack(idsPerView);
  } else if (masked && kept) {
    kept->clear();  // behind the mesh: of no further use
  }
  const double near = fromKept ? kept->nearPlane() : masked ? exposure->rays().nearPlane() : renderer->nearPlane();
  if (masked) {  // only the task's patches are accumulated
    if (scratch.inTask.size() != mesh.size()) scratch.inTask.assign(mesh.size(), 0);
    for (uint32_t id : task.patches) scratch.inTask[id] = 1;
  }
  // ---- GPU reduction: item buffers stay in GPU memory, only per-patch sums come back ----
  GLReduce* gpu = masked ? nullptr : GLReduce::forRenderer(renderer, mesh, scratch.glReduce, scratch.gpu);
  bool idsHere = !gpu;  // else read back only where the CPU reads them (kept buffers, exposed parts)
  const std::function<void()> needIds = [&] {
    if (!idsHere) gpu->readBack(idsPerView), idsHere = true;
  };
  if (gpu) {
    gpu->touch(views, *s.weights, touched, acc);
    if (kept && keeping.maxBytes > 0) needIds();
  }
  std::vector<uint8_t> mask;
  for (size_t v = 0; !gpu && v < views.size(); ++v) {
    std::vector<uint32_t>& ids = idsPerView[v];
    if (masked && !fromKept) {
      profile::Scope renderTime(profile::Render);
      mask.assign(views[v].pixelCount(), 0);
      for (uint32_t id : task.patches) markProjection(views[v], mesh.patches[id], near, 2, mask);
      exposure->rays().renderMasked(views[v], mask, ids);
    } else if (!masked) {
      renderer->render(views[v], ids);
    }
    profile::Scope accumulateTime(profile::Accumulate);
    const std::vector<double>& w = (*s.weights)[v];
    if (fromKept) {  // by runs
      kept->forEachRun(v, [&](uint32_t id, size_t begin, size_t end) {
        if (id == kNoPatch || !scratch.inTask[id]) return;
        double sum = 0;
        for (size_t p = begin; p < end; ++p) sum += w[p];
        if (sum == 0.0) return;
        if (acc[id] == 0.0) touched.push_back(id);
        acc[id] += sum;
      });
      continue;
    }
    for (size_t p = 0; p < ids.size(); ++p) {
      const uint32_t id = ids[p];
      if (id == kNoPatch || w[p] == 0.0 || (masked && !scratch.inTask[id])) continue;
      if (acc[id] == 0.0) touched.push_back(id);
      acc[id] += w[p];
    }
  }
  if (masked)
    for (uint32_t id : task.patches) scratch.inTask[id] = 0;
  if (!masked && kept && keeping.maxBytes > 0) {
    profile::Scope keptTime(profile::Kept);
    kept->keep(views, idsPerView, near, keeping.maxBytes);
  }
  std::sort(touched.begin(), touched.end());
  std::vector<Entry> out;
  out.reserve(touched.size());
  auto emit = [&](uint32_t id, float factor, double fraction) {
    if (factor > 0) out.push_back({id, factor, static_cast<float>(fraction)});
  };
  if (gpu && (s.analytic || needVisible)) gpu->coverage(views, touched, near, scratch.coverage);
  auto fraction = [&](uint32_t id, bool shown) {
    const PatchCoverage* computed =
        gpu && shown ? &scratch.coverage[size_t(std::lower_bound(touched.begin(), touched.end(), id) - touched.begin())] : nullptr;
    return visibleFraction(s, views, idsPerView, near, mesh, id, shown, exposure, computed, needIds);
  };
  auto inTask = [&](uint32_t id) {
    return task.patches.empty() || std::binary_search(task.patches.begin(), task.patches.end(), id);
  };
  if (!s.analytic) {
    for (uint32_t id : touched)
      if (inTask(id) && acc[id] > 0)
        emit(id, static_cast<float>(s.scale * acc[id] / mesh.patches[id].area),
             needVisible ? std::max(0.0, fraction(id, true)) : -1.0);
  } else {
    // Every patch: those that show in the item buffer, and those too small to hold a pixel centre
    // (missing them would lose their light, since their neighbours get only their own exact share).
    auto visit = [&](uint32_t id) {
      const bool shown = std::binary_search(touched.begin(), touched.end(), id);
      const double f = fraction(id, shown);
      if (f > 0) {
        profile::Scope integralTime(profile::Integral);
        emit(id, analyticPatchFactor(s, mesh.patches[id], f), f);
      }
    };
    const bool oneEye = std::all_of(views.begin(), views.end(), [&](const View& v) {
      return v.projection == Projection::Perspective && v.eye == views[0].eye;
    });
    if (task.patches.empty() && cull && oneEye) {
      // The same, less the clusters of unseen patches proven hidden behind a face of the scene (which
      // their point tests would find occluded): preprocess/occlusion_cull.h.
      std::vector<uint32_t>& candidates = scratch.candidates;
      candidates.assign(touched.begin(), touched.end());
      cull->visible(views[0].eye, touched, candidates);
      std::sort(candidates.begin(), candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      for (uint32_t id : candidates) visit(id);
    } else if (task.patches.empty()) {
      for (uint32_t id = 0; id < mesh.size(); ++id) visit(id);
    } else {
      for (uint32_t id : task.patches) visit(id);
    }
  }
  for (uint32_t id : touched) acc[id] = 0.0;
  touched.clear();
  return out;
}

}  // namespace firstshot
