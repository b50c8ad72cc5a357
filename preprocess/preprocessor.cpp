// Driving the item buffers over all light samples and gathering the factors into a CSR table.
#include "preprocess/preprocessor.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include <fmt/core.h>
#include <tbb/parallel_for.h>

#include "common/lights/emission_profile.h"
#include "common/patches/patch_size.h"
#include "common/patches/patches.h"
#include "common/sampling/rng.h"
#include "common/table/firstshot_groups.h"
#include "common/util/error.h"
#include "common/util/interrupt.h"
#include "common/util/memory_limit.h"
#include "common/util/progress.h"
#include "preprocess/adaptive_mesh.h"
#include "preprocess/embree_item_buffer.h"
#include "preprocess/exposure.h"
#include "preprocess/gl/gl_item_buffer.h"
#include "preprocess/kept_item_buffers.h"
#include "preprocess/light_samples.h"
#include "preprocess/occlusion_cull.h"
#include "preprocess/pane_transmittance.h"
#include "preprocess/profile.h"
#include "preprocess/sample_shot.h"
#include "preprocess/window.h"

namespace firstshot {

namespace {

/// Alpha cut-outs: both back ends see through their holes (the GL one discards fragments,
/// preprocess/gl/gl_cutouts.h), but on llvmpipe the GL one is the slower (the shipped cut-out screen on one core:
/// 4.4 s against Embree's 2.9 s), so the default and "auto" take Embree; "gl" on the command line is honoured.
void resolveCutoutBackend(const SceneDesc& scene, const SettingsOverrides& cli, FirstShotSettings& s) {
  const auto m = std::find_if(scene.materials.begin(), scene.materials.end(), [](const MaterialDesc& d) { return d.isCutout(); });
  if (m == scene.materials.end() || (cli.backend && *cli.backend == "gl")) return;
  s.backend = "embree";
}

}  // namespace

FirstShotSettings resolveSettings(const SceneDesc& scene, const SettingsOverrides& cli) {
  FirstShotSettings s = scene.settings;  // the scene's values, or the defaults where it gives none
  if (cli.resolution) s.resolution = static_cast<uint32_t>(*cli.resolution);
  if (cli.window) s.window = *cli.window;
  if (cli.backend) s.backend = *cli.backend;
  if (cli.patchSize) s.patchSize = *cli.patchSize;
  if (cli.minPatchSize) s.minPatchSize = *cli.minPatchSize;
  if (cli.refineTolerance) s.refineTolerance = *cli.refineTolerance;
  if (cli.lightPatchSize) s.lightPatchSize = *cli.lightPatchSize;
  if (cli.lightTolerance) s.lightTolerance = *cli.lightTolerance;
  if (cli.estimator) s.estimator = *cli.estimator;
  if (cli.rotationSeed) s.rotationSeed = *cli.rotationSeed;
  resolvePatchSizes(scene, s);
  resolveCutoutBackend(scene, cli, s);
  if (s.resolution % 2) throw InputError("", "--resolution", "must be even (the hemicube's side faces are R/2 high)");
  return s;
}

PreprocessOptions defaultOptions(const SceneDesc& scene) {
  PreprocessOptions o;
  o.settings = resolveSettings(scene);
  return o;
}

namespace {

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

/// Memory for the item buffers kept between shooting passes, shared evenly by the light samples: a
/// sample whose buffers take more than its share is re-traced instead (the same for any thread
/// count or rank). At the default R = 256 a cube's 6 buffers take 1.5 MB raw and far less as runs.
constexpr size_t kKeptItemBufferBytes = size_t(512) << 20;

/// The back end of sample window @p w for backend "auto" (docs/preprocess-performance.md): the GL
/// rasteriser's cost grows with the triangles it draws (llvmpipe: about 0.4 µs each), Embree's with
/// the pixels it traces (about 33 ns each, growing only as the log of the triangles); so GL while
/// the scene has at most 1/12 as many triangles as the window has pixels. On a GPU (@p glOnGpu) always GL.
constexpr size_t kPixelsPerTriangleForGL = 12;
const char* autoBackend(size_t triangles, const Window& w, bool glOnGpu) {
  return glOnGpu || triangles * kPixelsPerTriangleForGL <= w.pixelCount() ? "gl" : "embree";
}

/// Whether OpenGL back end @p gl ("osmesa" | "egl") runs on a GPU: its GL_RENDERER (of a probe context on
/// the device EGL chooses, preprocess/gl/egl_devices.h) is not one of Mesa's CPU rasterisers. OSMesa never does.
bool glRunsOnGpu(const std::string& gl) {
  if (parseGLBackend(gl) != GLBackend::EGL) return false;
  try {
    const GLContext probe(GLBackend::EGL);
    return !isSoftwareRenderer(probe.renderer());
  } catch (const std::runtime_error&) {
    return false;  // no EGL: the rule for CPUs (the GL workers report the error if GL is chosen)
  }
}

/// One shooting pass over a fixed mesh: workers with their own renderer (GL context) take tasks in
/// any order; results are stored by sample index, so the table does not depend on the thread count.
/// With several ranks (PreprocessOptions::comm), each shoots the tasks dealt to it and the results
/// are exchanged after the pass (exchange()).
struct Shooter {
  const SceneDesc& scene;
  const PreprocessOptions& options;
  const std::vector<SampleSetup>& setups;
  const Bounds3d& bounds;
  Comm& comm;
  bool quiet = false;
  std::string rendererName;
  std::chrono::steady_clock::time_point deadline;  ///< past it the run fails (nothing is written)
  double exchangeSeconds = 0;
  uint64_t bytesSent = 0;
  int glOnGpu = -1;        ///< backend "auto": whether GL runs on a GPU (glRunsOnGpu); -1 not asked yet
  std::string glRenderer;  ///< GL_RENDERER of the first GL item buffer made (empty: none)
  /// Per light sample, its item buffers from the first pass while refinement passes may need them
  /// (on the rank that shoots the sample: tasks are dealt by sample).
  std::vector<KeptItemBuffers> kept;
  size_t keptBytesPerSample = 0;  ///< 0: keep none

  /// Runs @p tasks over @p mesh; each task's factors are added to results[task.sample], which ends
  /// sorted by patch. A refinement pass gives the split that made @p mesh (@p first, as
  /// AdaptiveMesh::split() returns it) and its @p level.
  void run(const PatchMesh& mesh, const std::vector<Task>& tasks, bool needVisible, const std::string& label,
           std::vector<std::vector<Entry>>& results, const std::vector<uint32_t>* first = nullptr, int level = 0) {
    if (tasks.empty()) return;
    std::vector<size_t> mine;  // this rank's tasks
    for (size_t k = 0; k < tasks.size(); ++k)
      if (comm.mine(tasks[k].sample)) mine.push_back(k);
    profile::Scope meshTime(profile::Mesh);
    ItemGeometry geometry = ItemGeometry::fromPatches(mesh, seeThroughMaterials(scene));  // panes left out
    geometry.cutouts = PatchCutouts::build(scene, mesh);  // alpha cut-outs: null without
    meshTime.stop();
    int threads = options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    threads = std::max(1, std::min<int>(threads, static_cast<int>(mine.size())));
    // Exposure of partly visible patches (analytic estimator), probed with rays on first use.
    std::unique_ptr<EmbreeItemBuffer> probe, fastProbe;
    std::unique_ptr<ExposureCache> exposure;
    // One watertight BVH for the point tests, the refinement passes' item buffers and, with the embree
    // back end, every worker's item buffers; the exposure probes trace a second one (below).
    if (options.settings.estimator == "analytic" || needVisible || !tasks.front().patches.empty() ||
        options.settings.backend != "gl") {
      profile::Scope probeTime(profile::ProbeSetup);
      probe = std::make_unique<EmbreeItemBuffer>(geometry, bounds);
      // The exposure probes' votes (16 rays) do not need watertight rays: a faster BVH without it.
      fastProbe = std::make_unique<EmbreeItemBuffer>(geometry, bounds, 1e-6, EmbreeRayMode::Packet16, false);
      exposure = std::make_unique<ExposureCache>(mesh, *probe, *fastProbe);
    }
    std::unique_ptr<OcclusionCull> cull;
    if (options.settings.estimator == "analytic" && tasks.front().patches.empty()) {
      profile::Scope cullTime(profile::Mesh);
      cull = std::make_unique<OcclusionCull>(scene, mesh);
    }
    std::atomic<size_t> next{0};
    std::atomic<int> used[2] = {0, 0};  // which back ends "auto" chose
    if (options.settings.backend == "auto" && glOnGpu < 0) glOnGpu = glRunsOnGpu(options.gl);
    std::mutex errorMutex;
    std::exception_ptr error;
    Progress progress(label, mine.size(), quiet);
    auto work = [&](int worker) {
      try {
        std::unique_ptr<ItemBufferRenderer> renderers[2];  // gl, embree
        ShotScratch scratch;
        scratch.glReduce = options.glReduce;
        for (size_t m; (m = next++) < mine.size();) {
          const size_t k = mine[m];
          const Task& task = tasks[k];
          if (scratch.acc.empty()) scratch.acc.assign(mesh.size(), 0.0);
          ItemBufferRenderer* renderer = nullptr;
          if (task.patches.empty()) {
            std::string backend = options.settings.backend;
            if (backend == "auto") backend = autoBackend(geometry.triangleCount(), *setups[task.sample].window, glOnGpu > 0);
            auto& r = renderers[backend == "gl" ? 0 : 1];
            if (!r) {
              profile::Scope setupTime(profile::RendererSetup);
              r = makeRenderer(backend, options, geometry, bounds, probe.get());
              if (auto* gl = dynamic_cast<GLItemBuffer*>(r.get())) {
                std::lock_guard lock(errorMutex);
                if (glRenderer.empty()) glRenderer = gl->context().renderer();
              }
            }
            renderer = r.get();
            used[backend == "gl" ? 0 : 1] = 1;
            if (options.settings.backend != "auto" && worker == 0 && rendererName.empty()) rendererName = renderer->name();
          }
          throwIfInterrupted();  // SIGINT/SIGTERM: stop between light samples, write nothing
          if (std::chrono::steady_clock::now() > deadline)
            throw std::runtime_error("time limit of " + std::to_string(options.timeLimit) + " s reached (" + label +
                                     ", " + std::to_string(k) + " of " + std::to_string(tasks.size()) +
                                     " light samples); nothing written");
          Keeping keeping;
          if (!kept.empty()) keeping = {&kept[task.sample], keptBytesPerSample, first, level};
          std::vector<Entry> out = renderSample(renderer, setups[task.sample], mesh, task, needVisible, scratch,
                                                exposure.get(), cull.get(), keeping);
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
        next = mine.size();
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
    if (!glRenderer.empty() && rendererName.find("gl") != std::string::npos && rendererName.find(" (") == std::string::npos)
      rendererName += " (" + glRenderer + ")";  // the device GL ran on (GL_RENDERER)
    exchange(tasks, mine, results);
  }

  /// Every rank's results of its tasks to every rank: afterwards each rank holds, for every task's
  /// sample, what the rank that shot it holds (the same bytes as one process shooting them all).
  void exchange(const std::vector<Task>& tasks, const std::vector<size_t>& mine, std::vector<std::vector<Entry>>& results) {
    if (comm.size() == 1) return;
    const auto start = std::chrono::steady_clock::now();
    ByteWriter out;
    out.put<uint64_t>(mine.size());
    for (const size_t k : mine) {
      out.put<uint32_t>(tasks[k].sample);
      out.putVector(results[tasks[k].sample]);
    }
    const uint64_t before = comm.bytesSent();
    const std::vector<Bytes> all = comm.allGather(out.bytes());
    bytesSent += comm.bytesSent() - before;
    for (int r = 0; r < comm.size(); ++r) {
      if (r == comm.rank()) continue;
      ByteReader in(all[size_t(r)]);
      for (uint64_t n = in.get<uint64_t>(); n > 0; --n) {
        const uint32_t sample = in.get<uint32_t>();
        if (sample >= results.size()) throw std::runtime_error("exchange between ranks: unknown light sample");
        results[sample] = in.getVector<Entry>();
      }
    }
    exchangeSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
};

/// The leaves to split: where the first-shot irradiance varies across a patch by partial visibility
/// (0 < V_ij < 1), measured as Σ_i E⁰_ij·V_ij(1 − V_ij) / Σ_i E⁰_ij with E⁰_ij the unoccluded
/// irradiance (luminance) sample i would bring; above the tolerance, and while the children stay
/// at least settings.minPatchSize. The renderer evaluates the unoccluded term exactly at each point
/// (render/firstshot/lighting.h), so smooth variation near a light needs no split: only V does, which the
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

/// Thin glass: each factor times the panes' transmittance between its light sample and its
/// patch's centroid (preprocess/pane_transmittance.h); the item buffers did not draw the panes. The panes'
/// own patches lose their factors (the analytic estimator's point tests found them lit: a pane is a delta
/// surface, never a lit patch), as do factors that no light crosses to. Nothing for a scene without glass.
void applyPaneTransmittance(const SceneDesc& scene, const PatchMesh& mesh, const std::vector<LightSample>& samples,
                            std::vector<std::vector<Entry>>& results) {
  const PaneTransmittance panes(scene);
  if (panes.empty()) return;
  const std::vector<uint8_t> seeThrough = seeThroughMaterials(scene);
  tbb::parallel_for(size_t(0), results.size(), [&](size_t i) {
    const LightSample& s = samples[i];
    const bool directional = s.kind == LightSampleKind::Directional;
    std::vector<Entry>& r = results[i];
    for (Entry& e : r) {
      if (seeThrough[mesh.patches[e.patch].material]) {
        e.factor = 0.0f;
        continue;
      }
      const Vec3d c(mesh.patches[e.patch].centroid);
      const double T = directional ? panes.toward(c, -glm::normalize(Vec3d(s.normal))) : panes.between(c, Vec3d(s.position));
      e.factor = static_cast<float>(e.factor * T);
    }
    r.erase(std::remove_if(r.begin(), r.end(), [](const Entry& e) { return !(e.factor > 0.0f); }), r.end());
  });
}

/// Rejects an item-buffer resolution out of the windows' range, or whose windows and item buffers
/// cannot fit in memory: weights (8 bytes a pixel) of a cube (6R²) and of a cubic tetrahedron (4
/// faces of (√2R)², the largest area-light window) or hemicube (3R²), plus one view's IDs (4 bytes a
/// pixel, at most 2R²) per worker — a lower bound of what the run allocates.
void checkItemBufferSize(const SceneDesc& scene, const PreprocessOptions& options) {
  const double R = options.settings.resolution;
  const char* element = "settings.item_buffer_resolution (--resolution)";
  if (R < 2 || R > 16384) throw InputError(scene.file, element, fmt::format("R = {} is outside [2, 16384]", R));
  const bool tetra = parseWindowKind(options.settings.window) == WindowKind::Tetrahedron;
  const double workers = options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  const double bytes = 8.0 * (6.0 + (tetra ? 8.0 : 3.0)) * R * R + workers * 4.0 * 2.0 * R * R;
  requireMemory(bytes, scene.file, element, fmt::format("item buffers of R = {}", R), "lower it");
}

}  // namespace

FirstShotTable preprocessScene(const SceneDesc& scene, const PreprocessOptions& given, PreprocessStats* stats) {
  PreprocessOptions options = given;
  resolvePatchSizes(scene, options.settings);  // a caller's automatic sizes (0), as resolveSettings resolves them
  checkItemBufferSize(scene, options);
  Progress timer("", 0, true);
  FirstShotTable t;
  t.sceneHash = hashScene(scene);
  t.settings = options.settings;
  t.replacedLights = smallLights(scene, options.settings.smallLightMaxSolidAngle);
  // Luminaires first: their lights are sampled through their exit patches, so they get no light samples here.
  LuminaireOptions lumOptions = options.luminaires;
  lumOptions.quiet = options.quiet;
  std::vector<double> luminaireSeconds;
  t.luminaires = makeLuminaires(scene, t.replacedLights, lumOptions, &luminaireSeconds);
  for (const Luminaire& lum : t.luminaires)
    std::erase_if(t.replacedLights, [&](uint32_t l) { return std::binary_search(lum.lights.begin(), lum.lights.end(), l); });
  t.samples = makeLightSamples(scene, t.replacedLights, options.settings.lightPatchSize,
                               options.settings.lightTolerance, options.quiet);
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
  std::vector<std::unique_ptr<Window>> perLight(scene.lights.size());  // directional windows, IES spots
  // A spot's window: the cube's weights times its profile, in the frame Framed(axis) (renderSample).
  // A cone's profile depends only on the angle to the axis, so spots with the same cone share one.
  std::map<std::pair<double, double>, std::unique_ptr<Window>> coneWindows;
  auto profiled = [&](auto&& profileOfLocal) {
    auto w = std::make_unique<Window>(cube());
    for (size_t v = 0; v < w->views.size(); ++v) {
      const View& view = w->views[v];
      tbb::parallel_for(0, view.height, [&](int y) {
        for (int x = 0; x < view.width; ++x)
          w->weights[v][size_t(y) * view.width + x] *= profileOfLocal(glm::normalize(view.pixelDirection(x, y)));
      });
    }
    cropToWeights(*w);  // only the cone is rendered
    return w;
  };
  std::vector<SampleSetup> setups(t.samples.size());
  for (size_t i = 0; i < t.samples.size(); ++i) {
    const LightSample& ls = t.samples[i];
    const LightDesc& light = scene.lights[ls.light];
    SampleSetup& s = setups[i];
    s.sample = &ls;
    s.position = Vec3d(ls.position);
    s.kind = ls.kind;
    s.analytic = options.settings.estimator == "analytic";
    switch (ls.kind) {
      case LightSampleKind::Point:
        s.window = &cube(), s.weights = &cube().weights, s.scale = analyticScale(ls);
        break;
      case LightSampleKind::Spot: {
        s.profile = EmissionProfile(light);
        const Window* w = nullptr;
        if (light.ies) {
          if (!perLight[ls.light]) {
            const Framed frame(light.direction);
            perLight[ls.light] = profiled([&](const Vec3d& d) { return s.profile(frame.s * d.x + frame.t * d.y + frame.n * d.z); });
          }
          w = perLight[ls.light].get();
        } else {
          const SpotCone cone(light);
          auto& shared = coneWindows[{cone.cosInner, cone.cosOuter}];
          if (!shared) shared = profiled([&](const Vec3d& d) { return cone.profile(d.z); });
          w = shared.get();
        }
        s.window = w, s.weights = &w->weights;
        s.axis = light.direction, s.scale = 1.0 / s.profile.integral();
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
    // (Not an IES light's window: its weights are tabulated in the unrotated frame.)
    if (options.settings.rotationSeed != 0 && ls.kind != LightSampleKind::Directional && !light.ies)
      s.rotation = 2.0 * kPi * bitsToUnitDouble(hashKeys(options.settings.rotationSeed, i));
  }

  windowTime.stop();
  // Level 0 over the coarse mesh, then refinement levels that re-shoot only what changed.
  profile::Scope meshTime(profile::Mesh);
  AdaptiveMesh adaptive(scene, options.settings.patchSize);
  meshTime.stop();
  Shooter shooter{scene, options, setups, bounds, options.comm ? *options.comm : serialComm(), options.quiet, {},
                  std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                         std::chrono::duration<double>(options.timeLimit > 0 ? options.timeLimit : 1e9))};
  std::vector<Task> tasks(t.samples.size());
  for (size_t i = 0; i < tasks.size(); ++i) tasks[i].sample = static_cast<uint32_t>(i);
  const bool refine = options.settings.minPatchSize < options.settings.patchSize;  // equal (resolved): a uniform mesh
  if (refine && options.keepItemBuffers && !t.samples.empty()) {
    shooter.kept.resize(t.samples.size());
    shooter.keptBytesPerSample = kKeptItemBufferBytes / t.samples.size();
  }
  std::vector<std::vector<Entry>> results(t.samples.size());
  shooter.run(adaptive.mesh(), tasks, refine, "first-shot", results);
  std::string rendererName = shooter.rendererName;
  for (int level = 1; refine; ++level) {
    const std::vector<uint8_t> flags = splitFlags(adaptive, results, t.samples, options.settings);
    if (std::find(flags.begin(), flags.end(), uint8_t(1)) == flags.end()) break;
    const std::vector<uint32_t> first = adaptive.split(flags);
    carryOver(adaptive.mesh(), setups, flags, first, results, tasks);
    if (!shooter.kept.empty()) {  // a sample without a task now has none later (carryOver): free its buffers
      std::vector<uint8_t> tasked(t.samples.size(), 0);
      for (const Task& task : tasks) tasked[task.sample] = 1;
      for (size_t i = 0; i < tasked.size(); ++i)
        if (!tasked[i]) shooter.kept[i].clear();
    }
    shooter.run(adaptive.mesh(), tasks, true, "refine " + std::to_string(level), results, &first, level);
  }
  shooter.kept.clear();
  applyPaneTransmittance(scene, adaptive.mesh(), t.samples, results);
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
    size_t inLuminaires = 0;
    for (const Luminaire& lum : t.luminaires) inLuminaires += lum.lights.size();
    stats->largeLights = scene.lights.size() - t.replacedLights.size() - inLuminaires;
    stats->seconds = timer.elapsed();
    stats->renderer = rendererName.empty() ? options.settings.backend : rendererName;
    stats->exchangeSeconds = shooter.exchangeSeconds;
    stats->bytesSent = shooter.bytesSent;
    stats->luminaireSeconds = luminaireSeconds;
  }
  return t;
}

}  // namespace firstshot
