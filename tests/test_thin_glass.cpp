// Thin glass: the pane's reflectance and transmittance against hand-computed values, its two
// delta lobes, the JSON material and its errors.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "common/materials/bsdf.h"
#include "common/materials/thin_glass.h"
#include "common/sampling/rng.h"
#include "common/scene/scene_desc.h"
#include "common/util/error.h"
#include "tests/quad_over_floor.h"

using namespace firstshot;

namespace {

/// Unpolarised Fresnel of one face, in double: (rs², rp²) at incidence cos @p ci, index @p n.
std::pair<double, double> faceFresnel(double ci, double n) {
  const double ct = std::sqrt(1 - (1 - ci * ci) / (n * n));
  const double rs = (ci - n * ct) / (ci + n * ct), rp = (n * ci - ct) / (n * ci + ct);
  return {rs * rs, rp * rp};
}

}  // namespace

TEST(ThinGlass, NormalIncidenceGivesTheTransmittance) {
  for (float tau : {0.0f, 0.1f, 0.5f, 0.88f, 0.9f}) {
    const ThinGlassBSDF g(Color(tau, 0.5f * tau, 0.25f * tau), 1.52f);
    const Color T = g.transmittance(1.0f);
    EXPECT_NEAR(T.x, tau, 2e-6f) << tau;
    EXPECT_NEAR(T.y, 0.5f * tau, 2e-6f) << tau;
    EXPECT_NEAR(T.z, 0.25f * tau, 2e-6f) << tau;
  }
}

TEST(ThinGlass, LosslessPaneMatchesTheClosedForm) {
  // a = 1: T = (1 − r)/(1 + r) per polarisation, R = 2r/(1 + r), R + T = 1 at every angle.
  const double n = 1.52;
  const ThinGlassBSDF g{Color(ThinGlassBSDF::maxTransmittance(float(n))), float(n)};
  for (double deg : {0.0, 20.0, 45.0, 60.0, 75.0, 85.0, 89.0}) {
    const double ci = std::cos(deg * M_PI / 180);
    const auto [s, p] = faceFresnel(ci, n);
    const double T = 0.5 * ((1 - s) / (1 + s) + (1 - p) / (1 + p));
    Color r, t;
    g.reflectTransmit(float(ci), r, t);
    EXPECT_NEAR(t.x, T, 1e-5) << deg;
    EXPECT_NEAR(r.x + t.x, 1.0, 1e-5) << deg;
  }
  EXPECT_NEAR(ThinGlassBSDF::maxTransmittance(1.52f), 0.918318f, 2e-6f);  // r0 = (0.52/2.52)² = 0.042580
}

TEST(ThinGlass, AbsorbingPaneMatchesTheSeries) {
  // τ = 0.6 at normal incidence: a0 from the quadratic; at 60° the path inside is 1/cos θt longer.
  const double n = 1.52, tau = 0.6, r0 = std::pow((n - 1) / (n + 1), 2), q = (1 - r0) * (1 - r0);
  const double a0 = (-q + std::sqrt(q * q + 4 * tau * tau * r0 * r0)) / (2 * tau * r0 * r0);
  const ThinGlassBSDF g{Color(float(tau)), float(n)};
  EXPECT_NEAR(g.a0.x, a0, 1e-6);
  const double ci = 0.5, ct = std::sqrt(1 - (1 - ci * ci) / (n * n)), a = std::pow(a0, 1 / ct);
  const auto [s, p] = faceFresnel(ci, n);
  double T = 0, R = 0;
  for (double r : {s, p}) {
    T += 0.5 * (1 - r) * (1 - r) * a / (1 - r * r * a * a);
    R += 0.5 * (r + r * (1 - r) * (1 - r) * a * a / (1 - r * r * a * a));
  }
  Color rr, tt;
  g.reflectTransmit(float(ci), rr, tt);
  EXPECT_NEAR(tt.x, T, 1e-5);
  EXPECT_NEAR(rr.x, R, 1e-5);
  EXPECT_LT(tt.x, g.transmittance(0.9f).x);  // less light through at a steeper angle
  EXPECT_EQ(g.transmittance(0.0f).x, 0.0f);  // none at grazing incidence
}

TEST(ThinGlass, SampleChoosesTheLobesByTheirWeights) {
  const ThinGlassBSDF g(Color(0.7f, 0.6f, 0.5f), 1.52f);
  const BSDF bsdf(g);
  ASSERT_TRUE(bsdf.hasDelta());
  ASSERT_NE(bsdf.thinGlass(), nullptr);
  const Vec3 wo = glm::normalize(Vec3(0.3f, -0.2f, -0.8f));  // from the back: the pane is two-sided
  Color R, T;
  g.reflectTransmit(std::abs(wo.z), R, T);
  const int n = 20000;
  int through = 0;
  Color sum(0.0f);
  Sampler rng(7, 0, 0);
  for (int i = 0; i < n; ++i) {
    BSDFQuery q(wo);
    const Color w = bsdf.sample(q, Vec2(rng.next1D(), rng.next1D()));
    ASSERT_TRUE(q.specular);
    ASSERT_GT(q.pdf, 0.0f);
    if (q.wi.z * wo.z < 0.0f) {
      ++through;
      EXPECT_NEAR(glm::length(q.wi + wo), 0.0f, 1e-6f);  // straight through, not refracted
    } else {
      EXPECT_NEAR(glm::length(q.wi - Vec3(-wo.x, -wo.y, wo.z)), 0.0f, 1e-6f);
    }
    sum += w;
  }
  const double p = ThinGlassBSDF::transmitProbability(R, T), sigma = std::sqrt(p * (1 - p) / n);
  EXPECT_NEAR(double(through) / n, p, 4 * sigma);
  // Each lobe's weight is its value over its probability; the mean weight is R + T (both weights equal
  // it per channel only when R and T are grey, so compare the means).
  const Color mean = sum / float(n);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], R[c] + T[c], 0.02f) << c;
}

namespace {

SceneDesc pane(const std::string& material) { return test::quadOverFloor("pane", material, "pane.json"); }

}  // namespace

TEST(ThinGlass, JsonDefaultsAndKeys) {
  const SceneDesc d = pane(R"({"type": "thin_glass"})");
  const MaterialDesc& m = d.materials[size_t(d.findMaterial("pane"))];
  EXPECT_EQ(m.type, MaterialType::ThinGlass);
  EXPECT_FLOAT_EQ(m.transmittance.y, kThinGlassTransmittance);
  EXPECT_FLOAT_EQ(m.ior, kThinGlassIor);
  const SceneDesc t = pane(R"({"type": "thin_glass", "transmittance": [0.8, 0.7, 0.6], "ior": 1.4})");
  const MaterialDesc& g = t.materials[size_t(t.findMaterial("pane"))];
  EXPECT_FLOAT_EQ(g.transmittance.z, 0.6f);
  EXPECT_FLOAT_EQ(g.ior, 1.4f);
  EXPECT_NEAR(makeBSDF(g).thinGlass()->transmittance(1.0f).x, 0.8f, 1e-5f);
}

TEST(ThinGlass, BadInputNamesTheMaterial) {
  using testing::HasSubstr;
  for (const char* bad : {R"({"type": "thin_glass", "transmittance": 1.2})", R"({"type": "thin_glass", "transmittance": -0.1})",
                          R"({"type": "thin_glass", "transmittance": 0.95})"}) {
    try {
      pane(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("materials.pane.transmittance")) << bad;
      EXPECT_THAT(e.what(), HasSubstr("pane.json")) << bad;
    }
  }
  EXPECT_THROW(pane(R"({"type": "thin_glass", "ior": 0.8})"), InputError);
  EXPECT_THROW(pane(R"({"type": "thin_glass", "albedo": 0.5})"), InputError);  // not a key of thin glass
}
