// Driving the item buffers over all light samples and gathering the factors into a CSR table.
#include "preprocess/preprocessor.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "common/firstshot_groups.h"
#include "common/lights.h"
#include "common/patches.h"
#include "common/progress.h"
#include "common/rng.h"
#include "preprocess/adaptive_mesh.h"
#include "preprocess/coverage.h"
#include "preprocess/embree_item_buffer.h"
#include "preprocess/exposure.h"
#include "preprocess/gl_item_buffer.h"
#include "preprocess/light_samples.h"
#include "preprocess/occlusion_cull.h"
#include "preprocess/profile.h"
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
    profile::Scope coverageTime(profile::Coverage);
    PatchCoverage total = coverage(nullptr);
    if (total.visible < total.expected && total.visible > 0) {  // partly visible: buried?
      coverageTime.stop();
      {
        profile::Scope exposureTime(profile::Exposure);
        getMask();
      }
      profile::Scope again(profile::CoverageExposed);
      if (query.mask->partial) total = coverage(&query);
    }
    if (total.pixels >= kMinPixelsForAnalytic && total.expected > 0)
      fraction = std::min(1.0, total.visible / total.expected);
  }
  if (fraction < 0) {
    // 5 points; a patch that shows nowhere (occluded, or smaller than a pixel) is decided by its
    // centroid unless that lies outside the window.
    profile::Scope pointTime(profile::PointTests);
    fraction = pointVisibleFraction(views, s, exposure->rays(), near, mesh, patch, touched, nullptr);
    if (fraction < 0 && !touched) fraction = pointVisibleFraction(views, s, exposure->rays(), near, mesh, patch, true, nullptr);
    if (fraction > 0 && fraction < 1) {
      pointTime.stop();
      {
        profile::Scope exposureTime(profile::Exposure);
        getMask();
      }
      profile::Scope again(profile::PointTests);
      if (query.mask->partial) fraction = pointVisibleFraction(views, s, exposure->rays(), near, mesh, patch, touched, &query);
    }
  }
  return fraction;
}

/// One factor before it is sorted into the CSR table.
struct Entry {
  uint32_t patch;
  float factor;
  float visible;  ///< V_ij, the visible fraction (the refinement's measure); −1 if not computed
};

/// r_ij of a patch with visible fraction @p fraction > 0 (closed-form kinds): the closed form times the
/// fraction, computed as the .fsd reader recomputes grouped factors (0 if the patch gets nothing).
float analyticPatchFactor(const SampleSetup& s, const Patch& p, double fraction) {
  const double U = unoccludedIntegral(s, p);
  return fraction * U > 0 ? analyticFactor(s.scale, fraction, U, p.area) : 0.0f;
}

/// What one task of a shooting pass computes: a sample's factors over all patches, or over a
/// sorted subset of them (the children of patches split since the sample was last shot).
struct Task {
  uint32_t sample = 0;
  std::vector<uint32_t> patches;  ///< empty: all
};

/// Renders one sample's views and returns its non-zero factors over @p task's patches, sorted by
/// patch. With @p needVisible, factors from pixel sums (spots, the pixels estimator) also get their
/// visible fraction. A task over a subset of patches traces only the pixels around them with
/// @p exposure's ray caster (a refinement pass: a few split patches per window); a task over all
/// patches renders whole views with @p renderer.
std::vector<Entry> renderSample(ItemBufferRenderer* renderer, const SampleSetup& s, const PatchMesh& mesh, const Task& task,
                                bool needVisible, std::vector<double>& acc, std::vector<uint32_t>& touched,
                                std::vector<std::vector<uint32_t>>& idsPerView, ExposureCache* exposure,
                                const OcclusionCull* cull, std::vector<uint32_t>& candidates) {
  Framed frame(s.axis);
  if (s.rotation != 0) {  // turn the window about its axis: decorrelates aliasing between samples
    const double c = std::cos(s.rotation), sn = std::sin(s.rotation);
    const Vec3d a = frame.s, b = frame.t;
    frame.s = c * a + sn * b, frame.t = -sn * a + c * b;
  }
  const std::vector<View> views = placeWindow(*s.window, s.position, frame, s.eyeOffset);
  idsPerView.resize(views.size());
  const bool masked = !task.patches.empty();
  const double near = masked ? exposure->rays().nearPlane() : renderer->nearPlane();
  std::vector<uint8_t> mask;
  for (size_t v = 0; v < views.size(); ++v) {
    std::vector<uint32_t>& ids = idsPerView[v];
    profile::Scope renderTime(profile::Render);
    if (masked) {
      mask.assign(views[v].pixelCount(), 0);
      for (uint32_t id : task.patches) markProjection(views[v], mesh.patches[id], near, 2, mask);
      exposure->rays().renderMasked(views[v], mask, ids);
    } else {
      renderTime.stop();
      renderer->render(views[v], ids);
    }
    renderTime.stop();
    profile::Scope accumulateTime(profile::Accumulate);
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
  auto emit = [&](uint32_t id, float factor, double fraction) {
    if (factor > 0) out.push_back({id, factor, static_cast<float>(fraction)});
  };
  auto fraction = [&](uint32_t id, bool shown) {
    return visibleFraction(s, views, idsPerView, near, mesh, id, shown, exposure);
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

/// A worker's view of an Embree item buffer shared by all workers (its render() only reads the BVH).
class SharedEmbree final : public ItemBufferRenderer {
 public:
  explicit SharedEmbree(EmbreeItemBuffer& rays) : rays_(rays) {}
  void render(const View& view, std::vector<uint32_t>& ids) override { rays_.render(view, ids); }
  const char* name() const override { return rays_.name(); }
  double nearPlane() const override { return rays_.nearPlane(); }

 private:
  EmbreeItemBuffer& rays_;
};

std::unique_ptr<ItemBufferRenderer> makeRenderer(const std::string& backend, const PreprocessOptions& o,
                                                 const ItemGeometry& geo, const Bounds3d& b, EmbreeItemBuffer* shared) {
  if (backend == "embree" && shared) return std::make_unique<SharedEmbree>(*shared);
  if (backend == "embree") return std::make_unique<EmbreeItemBuffer>(geo, b);
  if (backend == "gl") return std::make_unique<GLItemBuffer>(geo, b, parseGLBackend(o.gl));
  throw std::invalid_argument("unknown item-buffer back end \"" + backend + "\" (gl, embree, auto)");
}

/// The back end of sample window @p w for backend "auto" (docs/preprocess-performance.md): the GL
/// rasteriser's cost grows with the triangles it draws (llvmpipe: about 0.4 µs each), Embree's with
/// the pixels it traces (about 33 ns each, growing only as the log of the triangles); so GL while
/// the scene has at most 1/12 as many triangles as the window has pixels.
constexpr size_t kPixelsPerTriangleForGL = 12;
const char* autoBackend(size_t triangles, const Window& w) {
  return triangles * kPixelsPerTriangleForGL <= w.pixelCount() ? "gl" : "embree";
}

/// One shooting pass over a fixed mesh: workers with their own renderer (GL context) take tasks in
/// any order; results are stored by sample index, so the table does not depend on the thread count.
struct Shooter {
  const SceneDesc& scene;
  const PreprocessOptions& options;
  const std::vector<SampleSetup>& setups;
  const Bounds3d& bounds;
  bool quiet = false;
  std::string rendererName;
  std::chrono::steady_clock::time_point deadline;  ///< past it the run fails (nothing is written)

  /// Runs @p tasks over @p mesh; each task's factors are added to results[task.sample], which ends
  /// sorted by patch.
  void run(const PatchMesh& mesh, const std::vector<Task>& tasks, bool needVisible, const std::string& label,
           std::vector<std::vector<Entry>>& results) {
    if (tasks.empty()) return;
    profile::Scope meshTime(profile::Mesh);
    const ItemGeometry geometry = ItemGeometry::fromPatches(mesh);
    meshTime.stop();
    int threads = options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    threads = std::max(1, std::min<int>(threads, static_cast<int>(tasks.size())));
    // Exposure of partly visible patches (analytic estimator), probed with rays on first use.
    std::unique_ptr<EmbreeItemBuffer> probe;
    std::unique_ptr<ExposureCache> exposure;
    // One BVH for the point tests, the probes and, with the embree back end, every worker's item buffers.
    if (options.settings.estimator == "analytic" || needVisible || !tasks.front().patches.empty() ||
        options.settings.backend != "gl") {
      profile::Scope probeTime(profile::ProbeSetup);
      probe = std::make_unique<EmbreeItemBuffer>(geometry, bounds);
      exposure = std::make_unique<ExposureCache>(mesh, *probe);
    }
    std::unique_ptr<OcclusionCull> cull;
    if (options.settings.estimator == "analytic" && tasks.front().patches.empty()) {
      profile::Scope cullTime(profile::Mesh);
      cull = std::make_unique<OcclusionCull>(scene, mesh);
    }
    std::atomic<size_t> next{0};
    std::atomic<int> used[2] = {0, 0};  // which back ends "auto" chose
    std::mutex errorMutex;
    std::exception_ptr error;
    Progress progress(label, tasks.size(), quiet);
    auto work = [&](int worker) {
      try {
        std::unique_ptr<ItemBufferRenderer> renderers[2];  // gl, embree
        std::vector<double> acc;
        std::vector<uint32_t> touched;
        std::vector<std::vector<uint32_t>> ids;
        std::vector<uint32_t> candidates;
        for (size_t k; (k = next++) < tasks.size();) {
          const Task& task = tasks[k];
          if (acc.empty()) acc.assign(mesh.size(), 0.0);
          ItemBufferRenderer* renderer = nullptr;
          if (task.patches.empty()) {
            std::string backend = options.settings.backend;
            if (backend == "auto") backend = autoBackend(geometry.triangleCount(), *setups[task.sample].window);
            auto& r = renderers[backend == "gl" ? 0 : 1];
            if (!r) {
              profile::Scope setupTime(profile::RendererSetup);
              r = makeRenderer(backend, options, geometry, bounds, probe.get());
            }
            renderer = r.get();
            used[backend == "gl" ? 0 : 1] = 1;
            if (options.settings.backend != "auto" && worker == 0 && rendererName.empty()) rendererName = renderer->name();
          }
          if (std::chrono::steady_clock::now() > deadline)
            throw std::runtime_error("time limit of " + std::to_string(options.timeLimit) + " s reached (" + label +
                                     ", " + std::to_string(k) + " of " + std::to_string(tasks.size()) +
                                     " light samples); nothing written");
          std::vector<Entry> out = renderSample(renderer, setups[task.sample], mesh, task, needVisible, acc, touched, ids,
                                                exposure.get(), cull.get(), candidates);
          std::vector<Entry>& r = results[task.sample];
          if (r.empty()) {
            r = std::move(out);
          } else {
            r.insert(r.end(), out.begin(), out.end());
            std::sort(r.begin(), r.end(), [](const Entry& a, const Entry& b) { return a.patch < b.patch; });
          }
          progress.advance();
        }
      } catch (...) {
        std::lock_guard lock(errorMutex);
        if (!error) error = std::current_exception();
        next = tasks.size();
      }
    };
    std::vector<std::thread> pool;
    for (int w = 1; w < threads; ++w) pool.emplace_back(work, w);
    work(0);
    for (auto& th : pool) th.join();
    progress.finish();
    if (error) std::rethrow_exception(error);
    if (options.settings.backend == "auto" && (used[0] || used[1]) && rendererName.empty())
      rendererName = used[0] && used[1] ? "auto: gl+embree" : used[0] ? "auto: gl" : "auto: embree";
  }
};

/// The leaves to split: where the first-shot irradiance varies across a patch by partial visibility
/// (0 < V_ij < 1), measured as Σ_i E⁰_ij·V_ij(1 − V_ij) / Σ_i E⁰_ij with E⁰_ij the unoccluded
/// irradiance (luminance) sample i would bring; above the tolerance, and while the children stay
/// at least settings.minPatchSize. The renderer evaluates the unoccluded term exactly at each point
/// (render/direct_light.h), so smooth variation near a light needs no split: only V does, which the
/// table holds per patch.
std::vector<uint8_t> splitFlags(const AdaptiveMesh& adaptive, const std::vector<std::vector<Entry>>& results,
                                const std::vector<LightSample>& samples, const FirstShotSettings& settings) {
  const uint32_t n = adaptive.mesh().size();
  std::vector<double> varying(n, 0.0), total(n, 0.0);
  for (size_t i = 0; i < results.size(); ++i) {
    const double lum = luminance(samples[i].emission);
    for (const Entry& e : results[i]) {
      if (!(e.visible > 0)) continue;
      const double unoccluded = lum * e.factor / e.visible;
      varying[e.patch] += unoccluded * e.visible * (1.0 - e.visible);
      total[e.patch] += unoccluded;
    }
  }
  std::vector<uint8_t> flags(n, 0);
  for (uint32_t j = 0; j < n; ++j)
    flags[j] = total[j] > 0 && varying[j] > settings.refineTolerance * total[j] &&
               adaptive.splittable(j, settings.minPatchSize);
  return flags;
}

/// Moves the factors onto the refined mesh: unsplit patches keep theirs; the children of a split
/// patch that sample i saw whole (V = 1, closed-form kinds) get their closed forms; children of a
/// patch it saw in part (or by pixel sums) become a task for sample i. A patch the sample did not
/// reach has no entry and its children none either.
void carryOver(const PatchMesh& mesh, const std::vector<SampleSetup>& setups, const std::vector<uint8_t>& flags,
               const std::vector<uint32_t>& first, std::vector<std::vector<Entry>>& results, std::vector<Task>& tasks) {
  tasks.clear();
  for (size_t i = 0; i < results.size(); ++i) {
    const SampleSetup& s = setups[i];
    std::vector<Entry> moved;
    moved.reserve(results[i].size());
    Task task;
    task.sample = static_cast<uint32_t>(i);
    for (const Entry& e : results[i]) {
      const uint32_t c0 = first[e.patch];
      if (!flags[e.patch]) {
        moved.push_back({c0, e.factor, e.visible});
        continue;
      }
      const bool whole = s.analytic && e.visible >= 1.0f;
      for (uint32_t c = c0; c < first[e.patch + 1]; ++c) {
        if (!whole) {
          task.patches.push_back(c);
          continue;
        }
        const float factor = analyticPatchFactor(s, mesh.patches[c], 1.0);
        if (factor > 0) moved.push_back({c, factor, 1.0f});
      }
    }
    results[i] = std::move(moved);
    if (!task.patches.empty()) tasks.push_back(std::move(task));
  }
}

}  // namespace

FirstShotTable preprocessScene(const SceneDesc& scene, const PreprocessOptions& options, PreprocessStats* stats) {
  Progress timer("", 0, true);
  FirstShotTable t;
  t.sceneHash = hashScene(scene);
  t.settings = options.settings;
  t.replacedLights = smallLights(scene, options.settings.smallLightMaxSolidAngle);
  t.samples = makeLightSamples(scene, t.replacedLights, options.settings.lightPatchSize,
                               options.settings.lightTolerance);
  const int R = static_cast<int>(options.settings.resolution);

  // The scene's bounds: patches, emitters and positional lights (near/far planes, eye offsets).
  Bounds3d bounds;
  Vec3d lo, hi;
  scene.bounds(lo, hi);
  bounds.extend(lo), bounds.extend(hi);
  t.areaEyeOffset = areaLightEyeOffset(bounds);

  // Windows and weight tables, built once.
  profile::Scope windowTime(profile::Windows);
  // (Each built on first use: a cube window at R = 512 is 1.5 M pixels of directions and weights.)
  std::optional<Window> cubeWindow, areaWindow;
  auto cube = [&]() -> const Window& {
    if (!cubeWindow) cubeWindow = makeCubeWindow(R);
    return *cubeWindow;
  };
  auto area = [&]() -> const Window& {
    if (!areaWindow)
      areaWindow = parseWindowKind(options.settings.window) == WindowKind::Tetrahedron ? makeTetraWindow(R)
                                                                                       : makeHemicubeWindow(R);
    return *areaWindow;
  };
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
        s.window = &cube(), s.weights = &cube().weights, s.scale = analyticScale(ls);
        break;
      case LightSampleKind::Spot: {
        if (!perLight[ls.light]) {  // cube weights times the spot profile, in the spot's frame (z = axis)
          auto w = std::make_unique<Window>(cube());
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
        s.window = &area(), s.weights = &area().weights, s.axis = Vec3d(ls.normal);
        s.eyeOffset = t.areaEyeOffset, s.scale = analyticScale(ls);
        break;
    }
    if (options.settings.rotationSeed != 0 && ls.kind != LightSampleKind::Directional)
      s.rotation = 2.0 * kPi * bitsToUnitDouble(hashKeys(options.settings.rotationSeed, i));
  }

  windowTime.stop();
  // Level 0 over the coarse mesh, then refinement levels that re-shoot only what changed.
  profile::Scope meshTime(profile::Mesh);
  AdaptiveMesh adaptive(scene, options.settings.patchSize);
  meshTime.stop();
  Shooter shooter{scene, options, setups, bounds, options.quiet, {},
                  std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                         std::chrono::duration<double>(options.timeLimit > 0 ? options.timeLimit : 1e9))};
  std::vector<Task> tasks(t.samples.size());
  for (size_t i = 0; i < tasks.size(); ++i) tasks[i].sample = static_cast<uint32_t>(i);
  const bool refine = options.settings.minPatchSize > 0 && options.settings.minPatchSize < options.settings.patchSize;
  std::vector<std::vector<Entry>> results(t.samples.size());
  shooter.run(adaptive.mesh(), tasks, refine, "first-shot", results);
  std::string rendererName = shooter.rendererName;
  for (int level = 1; refine; ++level) {
    const std::vector<uint8_t> flags = splitFlags(adaptive, results, t.samples, options.settings);
    if (std::find(flags.begin(), flags.end(), uint8_t(1)) == flags.end()) break;
    const std::vector<uint32_t> first = adaptive.split(flags);
    carryOver(adaptive.mesh(), setups, flags, first, results, tasks);
    shooter.run(adaptive.mesh(), tasks, true, "refine " + std::to_string(level), results);
  }
  profile::Scope tableTime(profile::Table);
  t.mesh = adaptive.mesh();
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
  tableTime.stop();
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
