// Bidirectional path tracing: the MIS weights of one path over all its strategies sum to 1, the
// image is bit-identical for any thread count, and the command line runs it (the preview: test_preview.cpp).
#include <gtest/gtest.h>

#include <algorithm>

#include "render/integrators/bdpt/densities.h"
#include "render/integrators/bdpt/integrator.h"
#include "render/integrators/bdpt/mis.h"
#include "tests/render_util.h"
#include "tests/splat_checks.h"
#include "tests/test_util.h"

using namespace firstshot;

namespace {

/// Σ over the strategies (s, t), s + t = 4, of the MIS weights of the path camera → x1 → x2 → y
/// (3 segments, 2 bounces) on the floor, the wall (material @p wall) and a light (the lamp, or a
/// point light at y with @p point). Strategies with a connection through a delta vertex are not
/// evaluated (they cannot sample the path); t = 0 does not exist for a pinhole.
double weightSum(const char* wall, bool point, int& strategies) {
  SceneDesc d = test::sceneFromJson(std::string(R"({"materials": {"d": {"type": "diffuse", "albedo": 0.6},
      "g": {"type": "glossy", "albedo": 0.2, "specular": 0.5, "exponent": 8}, "m": {"type": "mirror", "specular": 0.9},
      "lamp": {"type": "diffuse", "emission": [5, 4, 3]}},
    "shapes": [{"type": "quad", "material": "d", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]},
               {"type": "quad", "material": ")") + wall + R"(", "vertices": [[1.5,-1,-1],[1.5,1,-1],[1.5,1,1],[1.5,-1,1]]},
               {"type": "quad", "material": "lamp", "vertices": [[-0.1,2,-0.1],[0.1,2,-0.1],[0.1,2,0.1],[-0.1,2,0.1]]}],
    "lights": [{"type": "point", "position": [0.02, 1.9, 0.01], "power": 30}],
    "camera": {"position": [0, 1, -3], "look_at": [0, 0, 0], "fov_y": 50, "resolution": [40, 30]}})");
  const RenderScene scene(d, 0.5);
  const EmissionSampler emission(scene.lights(), d);
  const Camera camera(d.camera);
  const BdptDensities dens(scene, emission, camera);
  const auto& lights = scene.lights().lights();
  const uint32_t light = uint32_t(std::find_if(lights.begin(), lights.end(), [&](const RenderLight& l) {
                                    return (l.type == LightType::Point) == point;
                                  }) - lights.begin());

  using Kind = SubpathVertex::Kind;
  SubpathVertex cam, x1, x2, yLight, ySurface;
  cam.kind = Kind::Camera, cam.hit.p = camera.position();
  x1.hit.p = Vec3(0.3f, 0.0f, -0.2f), x1.hit.ng = Vec3(0, 1, 0), x1.hit.patch = 0;
  x1.material = uint32_t(d.findMaterial("d"));
  x2.hit.p = Vec3(1.5f, 0.6f, 0.2f), x2.hit.ng = Vec3(-1, 0, 0), x2.hit.patch = 1;
  x2.material = uint32_t(d.findMaterial(wall));
  x2.delta = scene.bsdf(x2.material).hasDelta();
  yLight.kind = Kind::Light, yLight.light = light, yLight.deltaLight = point;
  yLight.hit.p = point ? Vec3(0.02f, 1.9f, 0.01f) : Vec3(0.02f, 2.0f, 0.01f);
  yLight.hit.ng = point ? Vec3(0.0f) : Vec3(0, -1, 0);
  ySurface = yLight;
  ySurface.kind = Kind::Surface, ySurface.deltaLight = false, ySurface.hit.emitter = 0;
  ySurface.material = uint32_t(d.findMaterial("lamp"));

  // The subpaths of strategy (s, t), with the directions to their previous vertices and densities.
  auto subpath = [&](std::vector<SubpathVertex> v) {
    if (v.empty()) return v;
    for (size_t k = 1; k < v.size(); ++k) v[k].wi = glm::normalize(v[k - 1].hit.p - v[k].hit.p);
    if (v[0].kind == Kind::Light) v[0].pdfFwd = dens.pdfOrigin(v[0]);
    dens.setDensities(v);
    return v;
  };
  const std::vector<SubpathVertex> eye = {cam, x1, x2, ySurface}, fromLight = {yLight, x2, x1};
  double sum = 0;
  strategies = 0;
  for (int s = 0; s <= 3; ++s) {
    const int t = 4 - s;
    const auto l = subpath(std::vector<SubpathVertex>(fromLight.begin(), fromLight.begin() + s));
    const auto c = subpath(std::vector<SubpathVertex>(eye.begin(), eye.begin() + t));
    if (s == 0 && point) continue;                       // a point light cannot be hit
    if ((s > 0 && l[size_t(s - 1)].delta) || c[size_t(t - 1)].delta) continue;  // no connection through a delta
    const float w = misWeight(dens, l, c, s, t);
    EXPECT_GT(w, 0.0f) << wall << " (" << s << ", " << t << ")";
    EXPECT_LE(w, 1.0f);
    sum += w;
    ++strategies;
  }
  return sum;
}

}  // namespace

TEST(BdptMis, WeightsOfOnePathSumToOne) {
  int n = 0;
  EXPECT_NEAR(weightSum("g", false, n), 1.0, 1e-4);  // area light: (0,4), (1,3), (2,2), (3,1)
  EXPECT_EQ(n, 4);
  EXPECT_NEAR(weightSum("d", false, n), 1.0, 1e-4);
  EXPECT_EQ(n, 4);
  EXPECT_NEAR(weightSum("g", true, n), 1.0, 1e-4);  // point light: no (0, 4)
  EXPECT_EQ(n, 3);
  EXPECT_NEAR(weightSum("m", false, n), 1.0, 1e-4);  // mirror x2: only (0, 4) and (3, 1)
  EXPECT_EQ(n, 2);
}

// The image does not depend on the number of threads, and passes one at a time give one render's film.
TEST(BdptMis, BitIdenticalForOneAndTwoThreadsAndByPasses) { test::expectSameFilmForThreadsAndPasses("bdpt"); }

TEST(BdptMis, CommandLine) { test::expectCommandLine("bdpt", "bdtp"); }
