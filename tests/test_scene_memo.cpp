// What integrators build alike from one scene, kept in its memo (render/scene/scene_memo.h): a light sampler or the
// first-shot lighting built again on the same scene is the one a fresh scene builds, outlives the integrator that
// built it first, and a build with other arguments is not served the kept one.
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "render/firstshot/lighting.h"
#include "render/lights/light_sampler.h"
#include "render/scene/render_scene.h"
#include "tests/shaded_room.h"

using namespace firstshot;

namespace {

/// The choices two samplers make for the same points and numbers, compared: the same emitter with the same
/// probability, and the same pmf for it. @return the choices compared.
int expectSameChoices(const LightSampler& a, const LightSampler& b, LightGroup g) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  int compared = 0;
  for (int k = 0; k < 400; ++k) {
    const Vec3 x(0.2f + 3.6f * u01(rng), 0.2f + 2.6f * u01(rng), 0.2f + 3.6f * u01(rng));
    const Vec3 n = glm::normalize(Vec3(u01(rng) - 0.5f, u01(rng) - 0.5f, u01(rng) - 0.5f));
    const float u = u01(rng);
    SampledEmitter sa, sb;
    const bool fa = a.sample(g, x, n, u, sa), fb = b.sample(g, x, n, u, sb);
    EXPECT_EQ(fa, fb) << "point " << k;
    if (!fa || !fb) continue;
    EXPECT_EQ(int(sa.emitter.kind), int(sb.emitter.kind)) << "point " << k;
    EXPECT_EQ(sa.emitter.index, sb.emitter.index) << "point " << k;
    EXPECT_EQ(sa.emitter.sub, sb.emitter.sub) << "point " << k;
    EXPECT_EQ(sa.p, sb.p) << "point " << k;
    ++compared;
  }
  return compared;
}

}  // namespace

TEST(SceneMemo, ALightSamplerBuiltAgainIsTheFreshOneAndOutlivesTheFirst) {
  const SceneDesc desc = test::shadedLightRoom(16);
  const FirstShotTable table = test::quickTable(desc);
  const RenderScene scene(desc, FirstShotTable(table)), fresh(desc, FirstShotTable(table));
  FirstShotLighting lighting, freshLighting;
  lighting.build(scene);
  freshLighting.build(fresh);
  LightSampler again;
  {
    // The first build, with visibility factors over the lit patches, then gone (its integrator destroyed): the
    // second is served the memo's copy, whose trees must not point into the first.
    auto first = std::make_unique<LightSampler>();
    first->build(scene, lighting, LightStrategy::Tree, true, true);
    again.build(scene, lighting, LightStrategy::Tree, true, true);
  }
  LightSampler reference;
  reference.build(fresh, freshLighting, LightStrategy::Tree, true, true);
  ASSERT_TRUE(again.hasPatchEmitters());
  EXPECT_GT(expectSameChoices(again, reference, LightGroup::Patches), 200);
  EXPECT_GT(expectSameChoices(again, reference, LightGroup::Replaced), 200);
  EXPECT_EQ(&again.lighting(), &lighting);  // the caller's lighting, not the first builder's

  // Other arguments are other samplers: without patch emitters, and without visibility factors (then its choices
  // are a fresh scene's without them, not the kept one's with them).
  LightSampler noPatches, noVisibility, freshNoVisibility;
  noPatches.build(scene, lighting, LightStrategy::Tree, false, true);
  EXPECT_FALSE(noPatches.hasPatchEmitters());
  noVisibility.build(scene, lighting, LightStrategy::Tree, true, false);
  freshNoVisibility.build(fresh, freshLighting, LightStrategy::Tree, true, false);
  EXPECT_GT(expectSameChoices(noVisibility, freshNoVisibility, LightGroup::Patches), 200);
  int differ = 0;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int k = 0; k < 200; ++k) {
    const Vec3 x(0.2f + 3.6f * u01(rng), 0.2f + 0.5f * u01(rng), 0.2f + 3.6f * u01(rng)), n(0, 1, 0);
    SampledEmitter a, b;
    const float u = u01(rng);
    if (noVisibility.sample(LightGroup::Patches, x, n, u, a) && again.sample(LightGroup::Patches, x, n, u, b))
      differ += a.p != b.p || a.emitter.index != b.emitter.index;
  }
  EXPECT_GT(differ, 20) << "the visibility factors changed no choice: the kept sampler served both?";
}

TEST(SceneMemo, TheFirstShotLightingBuiltAgainIsTheFreshOne) {
  const SceneDesc desc = test::shadedLightRoom(16);
  const FirstShotTable table = test::quickTable(desc);
  const RenderScene scene(desc, FirstShotTable(table)), fresh(desc, FirstShotTable(table));
  FirstShotLighting again, reference;
  {
    FirstShotLighting first;
    first.build(scene);
    again.build(scene);
  }
  reference.build(fresh);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  int lit = 0;
  for (int k = 0; k < 500; ++k) {
    // From above the shade, up to the ceiling it lights.
    const Vec3 o(2.0f, 2.85f, 2.0f), d = glm::normalize(Vec3(u01(rng) - 0.5f, 0.2f + u01(rng), u01(rng) - 0.5f));
    Hit hit, hitFresh;
    ASSERT_TRUE(scene.intersect(Ray(o, d), hit));
    ASSERT_TRUE(fresh.intersect(Ray(o, d), hitFresh));
    ASSERT_EQ(hit.patch, hitFresh.patch);
    const Color e = again.irradiance(hit, true), f = reference.irradiance(hitFresh, true);
    EXPECT_EQ(e.x, f.x) << "direction " << k;
    EXPECT_EQ(e.y, f.y) << "direction " << k;
    EXPECT_EQ(e.z, f.z) << "direction " << k;
    lit += e.x > 0.0f;
  }
  EXPECT_GT(lit, 400);
}
