// Visibility from the first-shot table (render/firstshot/table_visibility.h, --table-visibility): a small point
// or spot light the table finds visible from a whole patch and its neighbours, or from none of them,
// needs no shadow ray at the camera-visible surfaces. The classes must agree with shadow rays at
// points of the patches, only patches at a shadow edge may be left to rays, and images must not change.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cmath>
#include <memory>
#include <string>

#include "common/formats/load_scene.h"
#include "common/scene/scene_desc.h"
#include "render/firstshot/lighting.h"
#include "render/integrators/integrator.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "render/lights/next_event.h"
#include "render/scene/render_scene.h"
#include "tests/bias_util.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

/// A 4 m × 4 m floor (0.5 m patches, refined at the shadow edge), a light 2 m above its centre and
/// a 0.8 m square occluder 1 m above it: the shadow is the square |x|, |z| < 0.8 m. The camera
/// looks down at the floor.
SceneDesc shadowScene(const std::string& light) {
  return test::sceneFromJson(std::string(R"({"materials": {"white": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [
      {"type": "quad", "material": "white", "vertices": [[-2,0,-2],[-2,0,2],[2,0,2],[2,0,-2]], "name": "floor"},
      {"type": "quad", "material": "white", "vertices": [[-0.4,1,-0.4],[0.4,1,-0.4],[0.4,1,0.4],[-0.4,1,0.4]]}],
    "lights": [)") + light + R"(],
    "camera": {"position": [0.3, 3.5, 2.5], "look_at": [0, 0, 0], "fov_y": 60, "resolution": [48, 36]},
    "settings": {"patch_size": 0.5, "max_depth": 2}})");
}

const char* kPoint = R"({"type": "point", "position": [0.0371, 2, 0.0213], "power": 100})";
const char* kSpot = R"({"type": "spot", "position": [0.0371, 2, 0.0213], "direction": [0, -1, 0], "power": 100,
                        "inner_angle": 30, "outer_angle": 50})";

/// The shadow of the occluder (|x|, |z| ≤ 0.4 at y = 1) cast from (0.0371, 2, 0.0213) on the floor:
/// x ∈ [−0.8371, 0.7629], z ∈ [−0.8213, 0.7787] (edges that fall on no patch edge).
bool crossesShadowEdge(const Patch& p) {
  int inside = 0;
  for (uint32_t k = 0; k < p.count; ++k)
    inside += p.v[k].x > -0.8371f && p.v[k].x < 0.7629f && p.v[k].z > -0.8213f && p.v[k].z < 0.7787f;
  return inside > 0 && inside < int(p.count);
}

/// True if @p p crosses the shadow edge or touches a floor patch of @p mesh that does.
bool atShadowEdge(const PatchMesh& mesh, const Patch& p) {
  if (crossesShadowEdge(p)) return true;
  auto box = [](const Patch& q, Vec3& lo, Vec3& hi) {
    lo = hi = q.v[0];
    for (uint32_t k = 1; k < q.count; ++k) lo = glm::min(lo, q.v[k]), hi = glm::max(hi, q.v[k]);
  };
  Vec3 lo, hi;
  box(p, lo, hi);
  for (const Patch& q : mesh.patches) {
    if (q.shape != 0 || !crossesShadowEdge(q)) continue;
    Vec3 qlo, qhi;
    box(q, qlo, qhi);
    if (glm::all(glm::lessThanEqual(lo, qhi + 1e-3f)) && glm::all(glm::lessThanEqual(qlo, hi + 1e-3f))) return true;
  }
  return false;
}

}  // namespace

// At 256 points of every floor patch: a Visible patch has no occluded point, a Hidden one no point
// the light reaches; Unknown patches cross the shadow edge or touch a patch that does.
TEST(TableVisibility, ClassesAgreeWithShadowRays) {
  for (const char* light : {kPoint, kSpot}) {
    SCOPED_TRACE(light);
    const SceneDesc desc = shadowScene(light);
    const RenderScene scene(desc, test::preprocessDefault(desc));
    FirstShotLighting fsl;
    fsl.build(scene);
    const FirstShotTable& t = *scene.firstShot();
    const LightSample& ls = t.samples[0];
    int count[3] = {0, 0, 0}, unknownOffEdge = 0;
    long points = 0, wrong = 0;
    for (uint32_t j = 0; j < t.mesh.size(); ++j) {
      const Patch& p = t.mesh.patches[j];
      if (p.shape != 0) continue;
      const TableVisibility v = fsl.visibility(j, 0);
      ++count[int(v)];
      if (v == TableVisibility::Unknown) {
        unknownOffEdge += !atShadowEdge(t.mesh, p);
        continue;
      }
      for (int m = 0; m < 256; ++m) {
        Sampler sm(5, j, m);
        const Vec3 x = test::samplePatch(p, sm.next2D());
        const Vec3 o = x + p.normal * 1e-5f, d = ls.position - o;
        const bool occluded = scene.occluded(Ray(o, glm::normalize(d), 0.0f, glm::length(d) * (1 - 1e-5f)));
        ++points;
        if (v == TableVisibility::Visible)
          wrong += occluded;
        else  // Hidden: nothing arrives (occluded, or outside a spot's cone)
          wrong += !occluded && test::unoccludedSampleIrradiance(ls, x, p.normal, &desc.lights[0]).x > 0.0;
      }
    }
    fmt::print("  floor patches: {} visible, {} hidden, {} unknown ({} off the shadow edge); {} of {} points "
               "disagree with their shadow ray\n", count[1], count[2], count[0], unknownOffEdge, wrong, points);
    EXPECT_GT(count[int(TableVisibility::Visible)], 50);
    EXPECT_GT(count[int(TableVisibility::Hidden)], 20);
    EXPECT_GT(count[int(TableVisibility::Unknown)], 20);  // the shadow edge's patches
    EXPECT_EQ(wrong, 0);
    EXPECT_EQ(unknownOffEdge, 0);
  }
}

// Path tracing (light sampler: every light) and the irradiance cache (nextEventEveryLight at the camera
// vertex) with the table and --primary exact: the same seed with and without visibility from the
// table gives the same image (the classes agree with the shadow rays they replace, and the random
// numbers do not shift), with fewer rays.
TEST(TableVisibility, ImageIsTheImageOfShadowRays) {
  for (const char* light : {kPoint, kSpot}) {
    const SceneDesc desc = shadowScene(light);
    const RenderScene scene(desc, test::preprocessDefault(desc));
    for (const char* integrator : {"path", "irradiance-cache"}) {
      SCOPED_TRACE(std::string(integrator) + " " + light);
      IntegratorOptions io;
      io.maxDepth = desc.settings.maxDepth;
      io.lightSampler = LightStrategy::All;
      auto renderWith = [&](bool tableVisibility) {
        io.tableVisibility = tableVisibility;
        std::unique_ptr<Integrator> it = std::string(integrator) == "path"
                                             ? makeIntegrator("path", io)
                                             : std::make_unique<IrradianceCacheIntegrator>(io, IrradianceCacheSettings());
        it->preprocess(scene);
        return test::renderWith(*it, scene, 16, 3, 1);
      };
      const test::RenderRun rays = renderWith(false), table = renderWith(true);
      double meanRays = 0, meanTable = 0;
      int changed = 0;
      const int w = rays.film.width(), h = rays.film.height();
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const double a = rays.film.mean(x, y).x, b = table.film.mean(x, y).x;
          changed += std::abs(b - a) > 1e-5 * std::max(a, 1e-3);
          meanRays += a, meanTable += b;
        }
      fmt::print("  {}: image mean {:.5f} -> {:.5f}; {} of {} pixels changed; rays {} -> {}\n", integrator,
                 meanRays / (w * h), meanTable / (w * h), changed, w * h, rays.stats.rays, table.stats.rays);
      EXPECT_GT(meanRays, 0.0);
      EXPECT_EQ(changed, 0);
      EXPECT_LT(double(table.stats.rays), 0.9 * double(rays.stats.rays));
    }
  }
}

// The cursor (nextEventEveryLight's lookups, lights in ascending order) answers as query() does, in any
// order; on the 64 point lights of many-lights every class occurs.
TEST(TableVisibility, CursorAnswersAsQuery) {
  const SceneDesc desc = loadScene(test::source("scenes/many-lights.json"));
  const RenderScene scene(desc, test::preprocessDefault(desc));
  FirstShotLighting fsl;
  fsl.build(scene);
  const uint32_t lights = static_cast<uint32_t>(desc.lights.size());
  int count[3] = {0, 0, 0}, mismatches = 0;
  for (uint32_t j = 0; j < scene.firstShot()->mesh.size(); j += 7) {
    TableVisibilityMap::Cursor up = fsl.visibilityCursor(j), down = fsl.visibilityCursor(j);
    for (uint32_t l = 0; l < lights; ++l) {
      const TableVisibility q = fsl.visibility(j, l);
      ++count[int(q)];
      mismatches += up.next(l) != q;
      mismatches += down.next(lights - 1 - l) != fsl.visibility(j, lights - 1 - l);
    }
  }
  fmt::print("  many-lights, every 7th patch: {} visible, {} hidden, {} unknown\n", count[1], count[2], count[0]);
  EXPECT_EQ(mismatches, 0);
  for (int c = 0; c < 3; ++c) EXPECT_GT(count[c], 100);
}
