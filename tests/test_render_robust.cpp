// Robustness of the renderer: the image does not depend on the number of threads, and the
// preprocessor's hard-case scenes (plus the delta BSDFs) render without a NaN or Inf pixel, with
// NEE and with first-shot in both primary modes, with the path tracer and the ray-bundle integrator.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <cstring>
#include <map>
#include <memory>

#include "common/formats/load_scene.h"
#include "preprocess/preprocessor.h"
#include "render/scene/embree_scene.h"
#include "tests/bundle_util.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

FirstShotTable preprocessEmbree(const SceneDesc& desc, int R = 64) {
  PreprocessOptions po = defaultOptions(desc);
  po.settings.backend = "embree";
  po.settings.resolution = static_cast<uint32_t>(R);
  po.quiet = true;
  return preprocessScene(desc, po);
}

/// True if both films hold bit-identical pixel means.
bool identical(const Film& a, const Film& b) {
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      const Vec3d p = a.mean(x, y), q = b.mean(x, y);
      if (std::memcmp(&p, &q, sizeof p) != 0) return false;
    }
  return true;
}

const char* kCamera = R"("camera": {"position": [1.9, 1.4, 0.1], "look_at": [0.2, 0.2, 0.9], "fov_y": 80, "resolution": [24, 24]})";

/// A closed box (inside faces), with lights and extra shapes, seen from inside.
std::string closedBox(const std::string& lights, const std::string& extraShapes = "", const std::string& extraMaterials = "") {
  return std::string("{") + kCamera + R"(,
    "materials": {"white": {"type": "diffuse", "albedo": 0.5}, "lamp": {"type": "diffuse", "emission": 1})" + extraMaterials + R"(},
    "shapes": [{"type": "box", "material": "white", "min": [0,0,0], "max": [2,1.5,1], "flip_normals": true})" + extraShapes +
         R"(], "lights": [)" + lights + R"(], "settings": {"patch_size": 0.25, "light_patch_size": 0.1}})";
}

/// Cornell at @p width × @p height, with NEE only (patches of 0.1 m) and with a first-shot table.
struct CornellScenes {
  SceneDesc desc;
  std::unique_ptr<RenderScene> nee, fs;
};
CornellScenes cornellScenes(int width, int height) {
  CornellScenes c;
  c.desc = loadScene(test::source("scenes/cornell.json"));
  c.desc.camera.width = width, c.desc.camera.height = height;
  c.nee = std::make_unique<RenderScene>(c.desc, 0.1);
  PreprocessOptions po = defaultOptions(c.desc);
  po.settings.backend = "embree";
  po.settings.resolution = 64;
  po.settings.patchSize = 0.1;
  po.quiet = true;
  c.fs = std::make_unique<RenderScene>(c.desc, preprocessScene(c.desc, po));
  return c;
}

}  // namespace

TEST(RenderDeterminism, SameImageForOneAndTwoThreads) {
  const CornellScenes c = cornellScenes(40, 24);  // tiles of 16 do not divide the image
  const RenderScene &nee = *c.nee, &fs = *c.fs;
  IntegratorOptions exact, patch;
  patch.primary = PrimaryMode::Patch;
  for (const auto& [scene, io, what] : {std::tuple{&nee, exact, "NEE"}, std::tuple{&fs, exact, "first-shot, exact"},
                                        std::tuple{&fs, patch, "first-shot, patch"}}) {
    const auto one = test::renderPath(*scene, io, 4, 5, 1);
    const auto two = test::renderPath(*scene, io, 4, 5, 2);
    EXPECT_TRUE(identical(one.film, two.film)) << what;
    EXPECT_EQ(one.stats.rays, two.stats.rays) << what;
    const auto other = test::renderPath(*scene, io, 4, 6, 2);
    EXPECT_FALSE(identical(one.film, other.film)) << what << ": the seed must matter";
  }
}

/// The renderer traces the camera rays of the path tracer and the irradiance cache by 4 × 4 pixel
/// blocks as Embree packets (Integrator::LiBlock): the film must equal, bit for bit, one made with
/// Li() per camera ray, which traces each ray alone, and the ray count too — with NEE and with the
/// first-shot table. (The cache is filled first, by its two passes, and then frozen.)
TEST(RenderDeterminism, CameraPacketsGiveTheSingleRayImage) {
  const CornellScenes c = cornellScenes(38, 22);  // blocks of 4 × 4 cut by the image's edges
  const RenderScene &nee = *c.nee, &fs = *c.fs;
  const Camera camera(c.desc.camera);
  const int spp = 3;
  const uint64_t seed = 7;
  for (const auto& [scene, name, what] :
       {std::tuple{&nee, "path", "NEE"}, std::tuple{&fs, "path", "first-shot"},
        std::tuple{&nee, "irradiance-cache", "cache, NEE"}, std::tuple{&fs, "irradiance-cache", "cache, first-shot"}}) {
    auto integrator = makeIntegrator(name, IntegratorOptions{});
    integrator->preprocess(*scene);
    const auto blocks = test::renderWith(*integrator, *scene, spp, seed, 2);
    Film single(camera.width(), camera.height());
    uint64_t rays = 0;
    for (int y = 0; y < camera.height(); ++y)
      for (int x = 0; x < camera.width(); ++x)
        for (int s = 0; s < spp; ++s) {
          Sampler sampler(seed, uint64_t(y) * uint64_t(camera.width()) + uint64_t(x), uint64_t(s));
          const Vec2 jitter = sampler.next2D();
          SampleInfo info;
          const Color L = integrator->Li(camera.generateRay(float(x) + jitter.x, float(y) + jitter.y), sampler, &info);
          single.add(x, y, L, info.albedo, info.normal);
          rays += info.rays;
        }
    int differing = 0;
    for (int y = 0; y < camera.height(); ++y)
      for (int x = 0; x < camera.width(); ++x) {
        const Film::PixelSums a = blocks.film.pixelSums(x, y), b = single.pixelSums(x, y);
        differing += std::memcmp(&a.sum, &b.sum, sizeof a.sum) != 0 || std::memcmp(&a.albedo, &b.albedo, sizeof a.albedo) != 0 ||
                     std::memcmp(&a.normal, &b.normal, sizeof a.normal) != 0 || a.count != b.count;
      }
    EXPECT_EQ(differing, 0) << what;
    EXPECT_EQ(blocks.stats.rays, rays) << what;
  }
}

/// EmbreeScene::intersect16 (two packets of 8) finds, for every active ray of a block, the hit
/// intersect() finds alone, and nothing for the inactive ones; a partial block (count < 16) too.
TEST(RenderDeterminism, PacketHitsEqualSingleRayHits) {
  SceneDesc desc = loadScene(test::source("scenes/cornell.json"));
  desc.camera.width = desc.camera.height = 16;
  const RenderScene scene(desc, 0.1);
  const Camera camera(desc.camera);
  Sampler sampler(3, 0, 0);
  int compared = 0, missed = 0;
  for (int block = 0; block < 16; ++block) {
    const int count = block == 15 ? 11 : 16;
    Ray rays[16];
    bool active[16];
    for (int k = 0; k < 16; ++k) {
      const Vec2 j = sampler.next2D();
      // Some rays leave through the open front of the box (no hit): the camera turned around.
      const Vec3 d = camera.generateRay(float(4 * (block % 4) + k % 4) + j.x, float(4 * (block / 4) + k / 4) + j.y).d;
      rays[k] = Ray(camera.position(), k == 5 ? -d : d);
      active[k] = (k + block) % 7 != 0;
    }
    Hit hits[16];
    bool found[16];
    scene.embree().intersect16(rays, active, count, hits, found);
    for (int k = 0; k < count; ++k) {
      Hit alone;
      const bool hit = scene.embree().intersect(rays[k], alone);
      if (!active[k]) {
        EXPECT_FALSE(found[k]) << block << ", " << k;
        continue;
      }
      ASSERT_EQ(found[k], hit) << block << ", " << k;
      missed += !hit;
      if (!hit) continue;
      EXPECT_EQ(hits[k].t, alone.t);
      EXPECT_EQ(hits[k].patch, alone.patch);
      EXPECT_EQ(hits[k].emitter, alone.emitter);
      EXPECT_EQ(hits[k].triangle, alone.triangle);
      EXPECT_EQ(hits[k].ng, alone.ng);
      EXPECT_EQ(hits[k].eps, alone.eps);
      ++compared;
    }
  }
  EXPECT_GT(compared, 150);
  EXPECT_GT(missed, 0);
}

/// The preprocessor's hard cases (tests/test_preprocess.cpp) with a camera, plus delta and sharp BSDFs.
std::string hardCaseScene(const std::string& name) {
  const std::map<std::string, std::string> scenes = {

        {"PointLightInClosedBox", closedBox(R"({"type": "point", "position": [0.7, 0.9, 0.4], "power": 5})")},
        {"SpotLightInClosedBox",
                  closedBox(R"({"type": "spot", "position": [1, 1.2, 0.5], "direction": [0.3, -1, 0.1], "power": 3,
                                "inner_angle": 20, "outer_angle": 35})")},
        {"HardEdgedSpot",
                  closedBox(R"({"type": "spot", "position": [1, 1.2, 0.5], "direction": [0, -1, 0], "power": 3,
                                "inner_angle": 25, "outer_angle": 25})")},
        {"AreaLightCoplanarWithCeiling",
                  closedBox("", R"(, {"type": "quad", "material": "lamp", "small": true,
                                      "vertices": [[0.8,1.5,0.3],[1.2,1.5,0.3],[1.2,1.5,0.7],[0.8,1.5,0.7]]})")},
        {"PointLightOnAWall", closedBox(R"({"type": "point", "position": [1, 0, 0.5], "power": 5})")},
        {"PatchVeryCloseToPointLight",
                  std::string("{") + R"("camera": {"position": [0.003, 0.002, 0.003], "look_at": [0, 0, 0], "fov_y": 60, "resolution": [24, 24]},
                   "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
                   "shapes": [{"type": "quad", "material": "m", "vertices": [[-0.001,0,-0.001],[-0.001,0,0.001],[0.001,0,0.001],[0.001,0,-0.001]]},
                              {"type": "quad", "material": "m", "vertices": [[-1,-1,-1],[-1,-1,1],[1,-1,1],[1,-1,-1]]}],
                   "lights": [{"type": "point", "position": [0, 0.0001, 0], "power": 1}], "settings": {"patch_size": 1}})"},
        {"PatchSeenEdgeOn",
                  std::string("{") + R"("camera": {"position": [1.5, 1.2, 1.5], "look_at": [0, 0.3, 0], "fov_y": 60, "resolution": [24, 24]},
                   "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
                   "shapes": [{"type": "quad", "material": "m", "vertices": [[0.2,0,-0.5],[0.2,0,0.5],[0.2,1,0.5],[0.2,1,-0.5]]},
                              {"type": "quad", "material": "m", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}],
                   "lights": [{"type": "point", "position": [0.2, 0.5, 0], "power": 1}], "settings": {"patch_size": 2}})"},
        {"PatchesSmallerThanAPixel",
                  std::string("{") + R"("camera": {"position": [0, 2, 0.01], "look_at": [0, 0, 0], "fov_y": 40, "resolution": [24, 24]},
                   "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
                   "shapes": [{"type": "quad", "material": "m", "vertices": [[-0.5,0,-0.5],[-0.5,0,0.5],[0.5,0,0.5],[0.5,0,-0.5]]}],
                   "lights": [{"type": "point", "position": [0, 1, 0], "power": 1}], "settings": {"patch_size": 0.01}})"},
        {"DirectionalLightOnFloor",
                  std::string("{") + R"("camera": {"position": [0, 2, 0.01], "look_at": [0, 0, 0], "fov_y": 40, "resolution": [24, 24]},
                   "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
                   "shapes": [{"type": "quad", "material": "m", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}],
                   "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": 3}], "settings": {"patch_size": 0.25}})"},
        {"GlassMirrorAndGlossy",
                  closedBox(R"({"type": "point", "position": [1.0, 1.3, 0.5], "power": 5})",
                            R"(, {"type": "sphere", "material": "glass", "center": [0.6, 0.35, 0.5], "radius": 0.3, "subdivisions": 2},
                               {"type": "quad", "material": "mirror", "vertices": [[1.99,0.2,0.2],[1.99,0.2,0.8],[1.99,1.2,0.8],[1.99,1.2,0.2]]},
                               {"type": "box", "material": "shiny", "min": [1.2,0,0.3], "max": [1.5,0.4,0.6]},
                               {"type": "quad", "material": "lamp", "small": false,
                                "vertices": [[0.2,1.49,0.2],[0.4,1.49,0.2],[0.4,1.49,0.4],[0.2,1.49,0.4]]})",
                            R"(, "glass": {"type": "dielectric", "ior": 1.5}, "mirror": {"type": "mirror", "specular": 0.9},
                               "shiny": {"type": "glossy", "albedo": 0.1, "specular": 0.8, "exponent": 2000})")}};
  return scenes.at(name);
}

class HardCase : public ::testing::TestWithParam<const char*> {};

TEST_P(HardCase, NoNaNOrInfPixel) {
  const SceneDesc desc = test::sceneFromJson(hardCaseScene(GetParam()));
  const RenderScene nee(desc);
  const RenderScene fs(desc, preprocessEmbree(desc));
  IntegratorOptions exact, patch;
  patch.primary = PrimaryMode::Patch;
  for (const auto& [scene, io, what] : {std::tuple{&nee, exact, "NEE"}, std::tuple{&fs, exact, "first-shot, exact"},
                                        std::tuple{&fs, patch, "first-shot, patch"}}) {
    for (const char* integrator : {"path", "bundle"}) {
      SCOPED_TRACE(std::string(what) + ", " + integrator);
      const auto run = std::string(integrator) == "path" ? test::renderPath(*scene, io, 8)
                                                         : test::renderWith(*test::makeBundle(*scene, io, 32), *scene, 8);
      EXPECT_EQ(run.stats.nonFinite, 0u);
      double sum = 0;
      for (int y = 0; y < run.film.height(); ++y)
        for (int x = 0; x < run.film.width(); ++x) {
          const Vec3d m = run.film.mean(x, y);
          ASSERT_TRUE(isFinite(m)) << "pixel " << x << ", " << y;
          sum += m.x + m.y + m.z;
        }
      EXPECT_GT(sum, 0.0) << "the scene is lit";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, HardCase,
                         ::testing::Values("PointLightInClosedBox", "SpotLightInClosedBox", "HardEdgedSpot",
                                           "AreaLightCoplanarWithCeiling", "PointLightOnAWall", "PatchVeryCloseToPointLight",
                                           "PatchSeenEdgeOn", "PatchesSmallerThanAPixel", "DirectionalLightOnFloor",
                                           "GlassMirrorAndGlossy"),
                         [](const auto& p) { return std::string(p.param); });
