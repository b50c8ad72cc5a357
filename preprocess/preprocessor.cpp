// Driving the item buffers over all light samples and gathering the factors into a CSR table.
#include "preprocess/preprocessor.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <thread>

#include "common/firstshot_groups.h"
#include "common/lights.h"
#include "common/patches.h"
#include "common/progress.h"
#include "common/rng.h"
#include "preprocess/coverage.h"
#include "preprocess/embree_item_buffer.h"
#include "preprocess/exposure.h"
#include "preprocess/gl_item_buffer.h"
#include "preprocess/light_samples.h"
#include "preprocess/window.h"

namespace fs {

PreprocessOptions defaultOptions(const SceneDesc& scene) {
  PreprocessOptions o;
  o.settings.resolution = static_cast<uint32_t>(scene.settings.itemBufferResolution);
  o.settings.window = scene.settings.window;
  o.settings.patchSize = scene.settings.patchSize;
  o.settings.minPatchSize = scene.settings.minPatchSize > 0 ? scene.settings.minPatchSize
                                                             : scene.settings.patchSize / kDefaultRefineRatio;
  o.settings.refineTolerance = scene.settings.refineTolerance;
  o.settings.lightPatchSize = scene.settings.lightPatchSize;
  o.settings.lightTolerance = scene.settings.lightTolerance;
  o.settings.smallLightMaxSolidAngle = scene.settings.smallLightMaxSolidAngle;
  return o;
}

namespace {

/// How one light sample is rendered: which window, where, and the scale from Σ weights to r_ij·A_j.
struct SampleSetup {
  const LightSample* sample = nullptr;
  const Window* window = nullptr;
  const std::vector<std::vector<double>>* weights = nullptr;  ///< the window's, or a spot's profiled copy
  Vec3d position{0.0};
  Vec3d axis{0, 0, 1};
  double rotation = 0;  ///< radians about the axis (settings.rotationSeed)
  double eyeOffset = 0;
  double scale = 1;
  LightSampleKind kind = LightSampleKind::Point;
  bool analytic = true;  ///< closed form × visible fraction (preprocess/coverage.h)
};

/// Fewer pixel centres than this inside a patch and the fraction is taken at points on it instead.
constexpr size_t kMinPixelsForAnalytic = 4;

/// The closed-form integral of the window weight over the whole patch (no occlusion); for points and
/// area vertices the one the reader recomputes grouped factors from (common/firstshot_groups.h).
double unoccludedIntegral(const SampleSetup& s, const Patch& p) {
  switch (s.kind) {
    case LightSampleKind::Point:
    case LightSampleKind::AreaVertex: return analyticIntegral(*s.sample, s.eyeOffset, p);
    case LightSampleKind::Directional: {
      Vec3d poly[4];
      for (uint32_t k = 0; k < p.count; ++k) poly[k] = Vec3d(p.v[k]);
      return unoccludedProjectedArea(s.axis, poly, int(p.count));
    }
    case LightSampleKind::Spot: break;  // no closed form for the profile
  }
  return 0.0;
}

/// Visible fraction of a patch from points on it (for patches covering too few pixel centres): its
/// centroid and, if @p spread, the midpoints between the centroid and each vertex. −1 if none is in a view.
double pointVisibleFraction(const std::vector<View>& views, const SampleSetup& s, const EmbreeItemBuffer& rays,
                            double near, const PatchMesh& mesh, uint32_t patch, bool spread,
                            const ExposureQuery* exposure) {
  const Patch& p = mesh.patches[patch];
  const Vec3d c(p.centroid);
  int seen = 0, visible = 0;
  for (uint32_t k = spread ? 0 : p.count; k <= p.count; ++k) {
    const Vec3d x = k == p.count ? c : 0.5 * (c + Vec3d(p.v[k]));
    if (exposure && exposure->buried(x)) continue;
    const int v = pointVisibility(views, *s.weights, rays, x, near);
    if (v >= 0) ++seen, visible += v;
  }
  return seen > 0 ? double(visible) / seen : -1.0;
}

/// Which side of patch @p p sample @p s lights: 0 the normal's side, 1 the other.
int litSide(const SampleSetup& s, const Patch& p) {
  const Vec3d n(p.normal);
  const double side = s.kind == LightSampleKind::Directional ? -glm::dot(s.axis, n) : glm::dot(s.position - Vec3d(p.centroid), n);
  return side >= 0 ? 0 : 1;
}

/// The analytic estimator's visible fraction (preprocess/coverage.h; the factor is closed form × fraction), the fraction
/// decided in exact geometry at the pixel centres inside the patch, or at a few points on it when
/// fewer than kMinPixelsForAnalytic centres fall inside; a partly visible patch takes it over its
/// exposed part only (preprocess/exposure.h). @p touched: the patch shows in the item buffer.
/// @p exposure is required (it also lends its ray caster to the point tests). ≤ 0: no light.
double visibleFraction(const SampleSetup& s, const std::vector<View>& views, const std::vector<std::vector<uint32_t>>& ids,
                        double near, const PatchMesh& mesh, uint32_t patch, bool touched, ExposureCache* exposure) {
  auto coverage = [&](const ExposureQuery* mask) {
    PatchCoverage total;
    for (size_t v = 0; v < views.size(); ++v) {
      const PatchCoverage c = patchCoverage(views[v], (*s.weights)[v], ids[v], mesh, patch, near, mask);
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
    PatchCoverage total = coverage(nullptr);
    if (total.visible < total.expected && total.visible > 0) {  // partly visible: buried?
      getMask();
      if (query.mask->partial) total = coverage(&query);
    }
    if (total.pixels >= kMinPixelsForAnalytic && total.expected > 0)
      fraction = std::min(1.0, total.visible / total.expected);
  }
  if (fraction < 0) {
    // 5 points; a patch that shows nowhere (occluded, or smaller than a pixel) is decided by its
    // centroid unless that lies outside the window.
    fraction = pointVisibleFraction(views, s, exposure->rays(), near, mesh, patch, touched, nullptr);
    if (fraction < 0 && !touched) fraction = pointVisibleFraction(views, s, exposure->rays(), near, mesh, patch, true, nullptr);
    if (fraction > 0 && fraction < 1) {
      getMask();
      if (query.mask->partial) fraction = pointVisibleFraction(views, s, exposure->rays(), near, mesh, patch, touched, &query);
    }
  }
  return fraction;
}

/// One factor before it is sorted into the CSR table.
struct Entry {
  uint32_t patch;
  float factor;
};

/// Renders one sample's views and returns its non-zero factors, sorted by patch.
std::vector<Entry> renderSample(ItemBufferRenderer& renderer, const SampleSetup& s, const PatchMesh& mesh,
                                std::vector<double>& acc, std::vector<uint32_t>& touched,
                                std::vector<std::vector<uint32_t>>& idsPerView, ExposureCache* exposure) {
  Framed frame(s.axis);
  if (s.rotation != 0) {  // turn the window about its axis: decorrelates aliasing between samples
    const double c = std::cos(s.rotation), sn = std::sin(s.rotation);
    const Vec3d a = frame.s, b = frame.t;
    frame.s = c * a + sn * b, frame.t = -sn * a + c * b;
  }
  const std::vector<View> views = placeWindow(*s.window, s.position, frame, s.eyeOffset);
  idsPerView.resize(views.size());
  for (size_t v = 0; v < views.size(); ++v) {
    std::vector<uint32_t>& ids = idsPerView[v];
    renderer.render(views[v], ids);
    const std::vector<double>& w = (*s.weights)[v];
    for (size_t p = 0; p < ids.size(); ++p) {
      const uint32_t id = ids[p];
      if (id == kNoPatch || w[p] == 0.0) continue;
      if (acc[id] == 0.0) touched.push_back(id);
      acc[id] += w[p];
    }
  }
  std::sort(touched.begin(), touched.end());
  std::vector<Entry> out;
  out.reserve(touched.size());
  if (!s.analytic) {
    for (uint32_t id : touched) {
      if (acc[id] > 0) out.push_back({id, static_cast<float>(s.scale * acc[id] / mesh.patches[id].area)});
      acc[id] = 0.0;
    }
  } else {
    // Every patch: those that show in the item buffer, and those too small to hold a pixel centre
    // (missing them would lose their light, since their neighbours get only their own exact share).
    size_t next = 0;
    for (uint32_t id = 0; id < mesh.size(); ++id) {
      const bool shown = next < touched.size() && touched[next] == id;
      if (shown) ++next, acc[id] = 0.0;
      const double fraction = visibleFraction(s, views, idsPerView, renderer.nearPlane(), mesh, id, shown, exposure);
      if (!(fraction > 0)) continue;
      const double U = unoccludedIntegral(s, mesh.patches[id]);
      if (fraction * U > 0) out.push_back({id, analyticFactor(s.scale, fraction, U, mesh.patches[id].area)});
    }
  }
  touched.clear();
  return out;
}

std::unique_ptr<ItemBufferRenderer> makeRenderer(const PreprocessOptions& o, const ItemGeometry& geo, const Bounds3d& b) {
  if (o.settings.backend == "embree") return std::make_unique<EmbreeItemBuffer>(geo, b);
  if (o.settings.backend == "gl") return std::make_unique<GLItemBuffer>(geo, b, parseGLBackend(o.gl));
  throw std::invalid_argument("unknown item-buffer back end \"" + o.settings.backend + "\" (gl, embree)");
}

}  // namespace

FirstShotTable preprocessScene(const SceneDesc& scene, const PreprocessOptions& options, PreprocessStats* stats) {
  Progress timer("", 0, true);
  FirstShotTable t;
  t.sceneHash = hashScene(scene);
  t.settings = options.settings;
  t.mesh = buildPatches(scene, options.settings.patchSize);
  t.replacedLights = smallLights(scene, options.settings.smallLightMaxSolidAngle);
  t.samples = makeLightSamples(scene, t.replacedLights, options.settings.lightPatchSize);
  const int R = static_cast<int>(options.settings.resolution);

  // The scene's bounds: patches, emitters and positional lights (near/far planes, eye offsets).
  Bounds3d bounds;
  Vec3d lo, hi;
  scene.bounds(lo, hi);
  bounds.extend(lo), bounds.extend(hi);
  t.areaEyeOffset = areaLightEyeOffset(bounds);

  // Windows and weight tables, built once.
  const Window cube = makeCubeWindow(R);
  const Window area = parseWindowKind(options.settings.window) == WindowKind::Tetrahedron ? makeTetraWindow(R)
                                                                                           : makeHemicubeWindow(R);
  std::vector<std::unique_ptr<Window>> perLight(scene.lights.size());  // directional windows, spot profiles
  std::vector<SampleSetup> setups(t.samples.size());
  for (size_t i = 0; i < t.samples.size(); ++i) {
    const LightSample& ls = t.samples[i];
    const LightDesc& light = scene.lights[ls.light];
    SampleSetup& s = setups[i];
    s.sample = &ls;
    s.position = Vec3d(ls.position);
    s.kind = ls.kind;
    s.analytic = options.settings.estimator == "analytic" && ls.kind != LightSampleKind::Spot;
    switch (ls.kind) {
      case LightSampleKind::Point:
        s.window = &cube, s.weights = &cube.weights, s.scale = analyticScale(ls);
        break;
      case LightSampleKind::Spot: {
        if (!perLight[ls.light]) {  // cube weights times the spot profile, in the spot's frame (z = axis)
          auto w = std::make_unique<Window>(cube);
          for (size_t v = 0; v < w->views.size(); ++v)
            for (int y = 0; y < w->views[v].height; ++y)
              for (int x = 0; x < w->views[v].width; ++x) {
                const View& view = w->views[v];
                const Vec3d d = glm::normalize(view.pixelDirection(x, y));
                w->weights[v][size_t(y) * view.width + x] *= spotProfile(light, static_cast<float>(d.z));
              }
          perLight[ls.light] = std::move(w);
        }
        s.window = perLight[ls.light].get(), s.weights = &perLight[ls.light]->weights;
        s.axis = light.direction, s.scale = 1.0 / spotProfileIntegral(light);
        break;
      }
      case LightSampleKind::Directional:
        if (!perLight[ls.light]) perLight[ls.light] = std::make_unique<Window>(makeOrthoWindow(R, bounds, light.direction));
        s.window = perLight[ls.light].get(), s.weights = &perLight[ls.light]->weights;
        s.position = bounds.centre(), s.axis = light.direction, s.scale = 1.0;
        break;
      case LightSampleKind::AreaVertex:
        s.window = &area, s.weights = &area.weights, s.axis = Vec3d(ls.normal);
        s.eyeOffset = t.areaEyeOffset, s.scale = analyticScale(ls);
        break;
    }
    if (options.settings.rotationSeed != 0 && ls.kind != LightSampleKind::Directional)
      s.rotation = 2.0 * kPi * bitsToUnitDouble(hashKeys(options.settings.rotationSeed, i));
  }

  // Workers: each with its own renderer (GL context); samples taken in any order, results stored
  // by sample index, so the table does not depend on the thread count.
  const ItemGeometry geometry = ItemGeometry::fromPatches(t.mesh);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(
                                                               options.timeLimit > 0 ? options.timeLimit : 1e9);
  int threads = options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::max(1, std::min<int>(threads, static_cast<int>(std::max<size_t>(1, t.samples.size()))));
  // Exposure of partly visible patches (analytic estimator), probed with rays on first use.
  std::unique_ptr<EmbreeItemBuffer> probe;
  std::unique_ptr<ExposureCache> exposure;
  if (options.settings.estimator == "analytic") {
    probe = std::make_unique<EmbreeItemBuffer>(geometry, bounds);
    exposure = std::make_unique<ExposureCache>(t.mesh, *probe);
  }
  std::vector<std::vector<Entry>> results(t.samples.size());
  std::atomic<size_t> next{0};
  std::mutex errorMutex;
  std::exception_ptr error;
  std::string rendererName;
  Progress progress("first-shot", t.samples.size(), options.quiet);
  auto work = [&](int worker) {
    try {
      std::unique_ptr<ItemBufferRenderer> renderer;
      std::vector<double> acc;
      std::vector<uint32_t> touched;
      std::vector<std::vector<uint32_t>> ids;
      for (size_t i; (i = next++) < t.samples.size();) {
        if (!renderer) {
          renderer = makeRenderer(options, geometry, bounds);
          acc.assign(t.mesh.size(), 0.0);
          if (worker == 0) rendererName = renderer->name();
        }
        if (std::chrono::steady_clock::now() > deadline)
          throw std::runtime_error("time limit of " + std::to_string(options.timeLimit) + " s reached after " +
                                   std::to_string(i) + " of " + std::to_string(t.samples.size()) +
                                   " light samples; nothing written");
        results[i] = renderSample(*renderer, setups[i], t.mesh, acc, touched, ids, exposure.get());
        progress.advance();
      }
    } catch (...) {
      std::lock_guard lock(errorMutex);
      if (!error) error = std::current_exception();
      next = t.samples.size();
    }
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < threads; ++w) pool.emplace_back(work, w);
  work(0);
  for (auto& th : pool) th.join();
  progress.finish();
  if (error) std::rethrow_exception(error);

  // CSR by patch; within a row, samples ascend.
  const uint32_t n = t.mesh.size();
  t.rowStart.assign(size_t(n) + 1, 0);
  for (const auto& r : results)
    for (const Entry& e : r) ++t.rowStart[e.patch + 1];
  for (uint32_t j = 0; j < n; ++j) t.rowStart[j + 1] += t.rowStart[j];
  t.sampleIndex.resize(t.rowStart[n]);
  t.factor.resize(t.rowStart[n]);
  std::vector<uint64_t> cursor(t.rowStart.begin(), t.rowStart.end() - 1);
  for (size_t i = 0; i < results.size(); ++i)
    for (const Entry& e : results[i]) {
      const uint64_t k = cursor[e.patch]++;
      t.sampleIndex[k] = static_cast<uint32_t>(i);
      t.factor[k] = e.factor;
    }
  if (stats) {
    stats->lightSamples = t.samples.size();
    stats->patches = n;
    stats->nonZeros = t.factor.size();
    stats->smallLights = t.replacedLights.size();
    stats->largeLights = scene.lights.size() - t.replacedLights.size();
    stats->seconds = timer.elapsed();
    stats->renderer = rendererName.empty() ? options.settings.backend : rendererName;
  }
  return t;
}

}  // namespace fs
