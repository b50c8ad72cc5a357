// Rough glass (common/materials/rough_dielectric.h): the GGX dielectric and the rough thin pane. White furnace
// (R + T = 1 minus the multiple-scattering loss, by roughness), generalised reciprocity with η², the adjoint of
// Importance mode, eval/pdf/sample consistency and chi-square from roughness 0.05 to 1, the smooth (delta) limit,
// energy ≤ 1, and the JSON keys.
//
// Thresholds: Monte Carlo means within 4 standard errors (from the samples); chi-square p > kAlpha, the Šidák-corrected
// level for a 1% family-wise error over the chi-square tests here; float identities within 1e-3 relative.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/formats/load_scene.h"
#include "common/materials/bsdf.h"
#include "common/materials/fresnel.h"
#include "common/materials/microfacet.h"
#include "common/materials/rough_dielectric.h"
#include "common/scene/scene_desc.h"
#include "common/util/error.h"
#include "tests/bsdf_checks.h"
#include "tests/quad_over_floor.h"
#include "tests/test_util.h"

namespace firstshot {
namespace {

using test::dirFromAngles;
using test::RunningStats;

const double kAlpha = test::sidakAlpha(0.01, 17);

RoughDielectricBSDF glass(float roughness, float ior = 1.5f) { return {ior, Color(1.0f), roughness}; }
/// A lossless rough pane (a0 = 1: R + T = 1 at every angle).
RoughThinGlassBSDF losslessPane(float roughness) {
  return {ThinGlassBSDF(Color(ThinGlassBSDF::maxTransmittance(1.52f)), 1.52f), roughness};
}

/// Mean and standard error of the sample weights for wo (channel 0), split by the side wi lands on.
struct Split {
  RunningStats all, reflected, transmitted;  // the last two: weight × indicator, so their means add up to all's
};
Split sampledAlbedo(const BSDF& bsdf, const Vec3& wo, TransportMode mode, int n = 200000, uint64_t stream = 1) {
  Split s;
  Sampler rng(test::kBsdfCheckSeed, stream, 0);
  for (int i = 0; i < n; ++i) {
    BSDFQuery q(wo, mode);
    const float w = bsdf.sample(q, rng.next2D()).x;
    const bool same = w > 0.0f && q.wi.z * wo.z > 0.0f;
    s.all.add(w);
    s.reflected.add(same ? w : 0.0f);
    s.transmitted.add(same ? 0.0f : w);
  }
  return s;
}

/// ∫ f·|cos θ_i| dω_i by eval() alone: directions uniform on the sphere (independent of sample() and pdf()).
RunningStats evalAlbedo(const BSDF& bsdf, const Vec3& wo, TransportMode mode, int n = 400000) {
  RunningStats s;
  Sampler rng(test::kBsdfCheckSeed, 9, 0);
  for (int i = 0; i < n; ++i) {
    const Vec3 wi = squareToUniformSphere(rng.next2D());
    s.add(bsdf.eval(BSDFQuery(wi, wo, mode)).x * std::abs(wi.z) * 4.0 * kPi);
  }
  return s;
}

TEST(RoughDielectric, WhiteFurnacePerRoughness) {
  // Importance mode (no 1/η² on refraction): R + T = 1 minus the energy lost between microfacets (single scattering,
  // as the pbr material's GGX: at roughness 1 a white conductor loses ln 2 = 69% at normal incidence). sample() and
  // eval() (uniform directions, where the lobes are broad enough for that estimate: roughness ≥ 0.25) agree within
  // 4σ; R + T ≤ 1 within 4σ; the loss at θ_o ≤ 45° is bounded by roughness (measured: outside 0.05–0.1%, 0.8–2%,
  // 11–20% at roughness 0.25, 0.5, 1; inside, where light beyond the critical angle bounces back, 0.4–1.3%,
  // 7–13%, 50–58%) and grows with it at normal incidence.
  std::printf("roughness  theta_o  side     R+T(sampled) ± σ      R        T     R+T(eval) ± σ\n");
  double previousIn = 1.001, previousOut = 1.001;
  for (float r : {0.05f, 0.25f, 0.5f, 1.0f})
    for (float theta : {0.0f, 45.0f, 75.0f})
      for (bool inside : {false, true}) {
        const Vec3 wo = dirFromAngles(inside ? 180.0f - theta : theta, 30);
        const BSDF b = glass(r);
        const Split s = sampledAlbedo(b, wo, TransportMode::Importance);
        const RunningStats e = r >= 0.25f ? evalAlbedo(b, wo, TransportMode::Importance) : s.all;
        std::printf("%9.2f  %7.0f  %-7s  %.5f ± %.5f  %.4f  %.4f  %.5f ± %.5f\n", r, theta, inside ? "inside" : "outside",
                    s.all.mean, s.all.standardError(), s.reflected.mean, s.transmitted.mean, e.mean, e.standardError());
        const double sigma = std::hypot(s.all.standardError(), e.standardError());
        EXPECT_NEAR(s.all.mean, e.mean, 4 * sigma + 1e-3) << r << " " << theta << " " << inside;
        EXPECT_LE(s.all.mean, 1.0 + 4 * s.all.standardError() + 1e-4) << r << " " << theta << " " << inside;
        const double bound = r <= 0.05f ? 0.001 : r <= 0.25f ? 0.02 : r <= 0.5f ? (inside ? 0.15 : 0.03) : (inside ? 0.6 : 0.25);
        if (theta <= 45.0f) {
          EXPECT_GT(s.all.mean, 1.0 - bound) << r << " " << theta << " " << inside;
        }
        if (theta == 0.0f) {
          double& previous = inside ? previousIn : previousOut;
          EXPECT_LT(s.all.mean, previous) << r << " " << inside;  // the loss grows with roughness
          previous = s.all.mean;
        }
      }
}

TEST(RoughDielectric, RadianceModeScalesRefractionByOneOverEtaSquared) {
  // Radiance entering the glass from outside is divided by η² = 2.25 (and multiplied leaving it): T_radiance =
  // T_importance/η² for wo outside, ×η² for wo inside (wi then outside), per sample.
  for (float r : {0.1f, 0.6f}) {
    const Vec3 wo = dirFromAngles(30, 0);
    const Split imp = sampledAlbedo(glass(r), wo, TransportMode::Importance, 100000, 3);
    const Split rad = sampledAlbedo(glass(r), wo, TransportMode::Radiance, 100000, 3);
    EXPECT_NEAR(rad.transmitted.mean, imp.transmitted.mean / 2.25, 1e-4) << r;  // same random numbers
    EXPECT_NEAR(rad.reflected.mean, imp.reflected.mean, 1e-6) << r;
    const Vec3 wIn = dirFromAngles(160, 0);
    const Split impIn = sampledAlbedo(glass(r), wIn, TransportMode::Importance, 100000, 3);
    const Split radIn = sampledAlbedo(glass(r), wIn, TransportMode::Radiance, 100000, 3);
    EXPECT_NEAR(radIn.transmitted.mean, impIn.transmitted.mean * 2.25, 1e-3) << r;
  }
}

TEST(RoughDielectric, ReciprocityWithEtaSquared) {
  // Veach's generalised reciprocity f(wi → wo)/η_o² = f(wo → wi)/η_i², and Importance mode is the adjoint:
  // eval_importance(wi, wo) = eval_radiance(wo, wi). Random pairs on both sides, roughness 0.05 … 1.
  Sampler rng(test::kBsdfCheckSeed, 4, 0);
  int refracting = 0;
  for (float r : {0.05f, 0.3f, 1.0f}) {
    const BSDF b = glass(r, 1.33f);
    for (int i = 0; i < 4000; ++i) {
      const Vec3 wi = squareToUniformSphere(rng.next2D()), wo = squareToUniformSphere(rng.next2D());
      const float fwd = b.eval(BSDFQuery(wi, wo)).x, back = b.eval(BSDFQuery(wo, wi)).x;
      const float etaI = wi.z > 0.0f ? 1.0f : 1.33f, etaO = wo.z > 0.0f ? 1.0f : 1.33f;
      ASSERT_TRUE(test::nearRel(fwd / (etaO * etaO), back / (etaI * etaI), 1e-3f)) << fwd << " " << back;
      const float adj = b.eval(BSDFQuery(wi, wo, TransportMode::Importance)).x;
      ASSERT_TRUE(test::nearRel(adj, back, 1e-3f)) << adj << " " << back;
      refracting += (wi.z * wo.z < 0.0f && fwd > 0.0f) ? 1 : 0;
    }
  }
  EXPECT_GT(refracting, 500);  // the refraction lobe was exercised (not only reflection and zeros)
}

// Not test::checkSampleConsistency: this one samples in a transport mode, counts transmissions and checks both sides.
/// Per sample: weight = eval·|cos|/pdf, q.pdf = pdf(q), unit wi, q.eta the refraction's.
void checkConsistency(const BSDF& bsdf, float ior, TransportMode mode) {
  Sampler rng(test::kBsdfCheckSeed, 2, 0);
  int ok = 0, through = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 wo = squareToUniformSphere(rng.next2D());
    BSDFQuery q(wo, mode);
    const Color w = bsdf.sample(q, rng.next2D());
    if (maxComponent(w) <= 0.0f) {
      ASSERT_EQ(q.pdf, 0.0f);
      continue;
    }
    ++ok;
    ASSERT_NEAR(glm::length(q.wi), 1.0f, 1e-5f);
    ASSERT_FALSE(q.specular);
    const float pdf = bsdf.pdf(q);
    const Color f = bsdf.eval(q);
    ASSERT_TRUE(test::nearRel(q.pdf, pdf, 1e-3f)) << q.pdf << " vs " << pdf;
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(test::nearRel(w[c], f[c] * std::abs(q.wi.z) / pdf, 1e-3f)) << w[c];
    if (q.wi.z * wo.z < 0.0f) {
      ++through;
      if (ior > 0.0f) {
        ASSERT_FLOAT_EQ(q.eta, wo.z > 0.0f ? ior : 1.0f / ior);
      }
    }
  }
  EXPECT_GT(ok, 10000);
  EXPECT_GT(through, 2000);
}

TEST(RoughDielectric, ConsistentForEveryRoughness) {
  for (float r : {0.05f, 0.1f, 0.3f, 0.6f, 1.0f}) {
    SCOPED_TRACE(r);
    checkConsistency(glass(r), 1.5f, TransportMode::Radiance);
    checkConsistency(glass(r), 1.5f, TransportMode::Importance);
    checkConsistency(losslessPane(r), 0.0f, TransportMode::Radiance);
  }
}

/// Chi-square of the refracted directions near the smooth refraction direction t, in a polar histogram about t
/// (12 rings of angle up to 6α, 16 sectors; angles from the float directions' components, so a lobe of 10⁻³ rad is
/// resolved), against pdf() integrated over each cell by a fine midpoint rule in double; conditioned on landing in
/// the window, with a binomial check that the fraction landing there equals pdf's integral over it.
test::ChiSquareResult refractedChiSquare(const BSDF& bsdf, const Vec3& wo, float ior, double alpha, int samples = 300000) {
  float cosT = 0.0f;
  const float eta = wo.z > 0.0f ? ior : 1.0f / ior;
  fresnelDielectric(std::abs(wo.z), eta, &cosT);
  const Frame frame(refractLocal(wo, eta, cosT));
  const int rings = 12, sectors = 16;
  const double window = 6 * alpha;
  std::vector<double> counts(rings * sectors, 0.0), expected(rings * sectors, 0.0);
  Sampler rng(test::kBsdfCheckSeed, 11, 0);
  double inWindow = 0.0;
  for (int i = 0; i < samples; ++i) {
    BSDFQuery q(wo);
    if (!(maxComponent(bsdf.sample(q, rng.next2D())) > 0.0f)) continue;
    const Vec3 l = frame.toLocal(q.wi);
    const double psi = std::atan2(std::hypot(double(l.x), double(l.y)), double(l.z));
    if (psi >= window) continue;
    double phi = std::atan2(double(l.y), double(l.x));
    if (phi < 0) phi += 2 * kPi;
    counts[std::min(rings - 1, int(psi / window * rings)) * sectors + std::min(sectors - 1, int(phi / (2 * kPi) * sectors))] += 1;
    inWindow += 1;
  }
  const int kr = 40, kp = 16;
  double integral = 0.0;
  for (int i = 0; i < rings * kr; ++i) {
    const double psi = (i + 0.5) / (rings * kr) * window, dpsi = window / (rings * kr);
    for (int j = 0; j < sectors * kp; ++j) {
      const double phi = (j + 0.5) / (sectors * kp) * 2 * kPi;
      const Vec3 w = frame.toWorld(Vec3(float(std::sin(psi) * std::cos(phi)), float(std::sin(psi) * std::sin(phi)), float(std::cos(psi))));
      const double m = bsdf.pdf(BSDFQuery(w, wo)) * std::sin(psi) * dpsi * (2 * kPi / (sectors * kp));
      expected[(i / kr) * sectors + j / kp] += m;
      integral += m;
    }
  }
  for (double& e : expected) e *= inWindow / integral;
  const double rate = inWindow / samples;
  EXPECT_NEAR(rate, integral, 3 * std::sqrt(integral * (1 - integral) / samples) + 2e-3);
  const auto r = test::chiSquareTest(counts, expected);
  std::printf("refracted chi-square: %8.1f, dof %3d, p = %.4f; fraction in the window %.4f, integral %.4f\n", r.statistic,
              r.dof, r.pValue, rate, integral);
  return r;
}

TEST(RoughDielectric, SamplingMatchesPdf) {
  // Broad lobes on the whole sphere (both lobes in one histogram), from outside and inside.
  for (float r : {0.6f, 1.0f})
    for (float theta : {20.0f, 60.0f, 130.0f, 170.0f}) {
      const auto res = test::bsdfChiSquare(glass(r), dirFromAngles(theta, 40));
      EXPECT_GT(res.pValue, kAlpha) << "r " << r << " theta " << theta;
    }
  // Sharp refraction lobes, entering and leaving the glass, in a polar histogram about the refracted direction.
  for (float r : {0.05f, 0.1f, 0.3f})
    for (float theta : {35.0f, 160.0f}) {
      const auto res = refractedChiSquare(glass(r), dirFromAngles(theta, 40), 1.5f, ggxAlpha(r));
      EXPECT_GT(res.pValue, kAlpha) << "r " << r << " theta " << theta;
    }
}

TEST(RoughDielectric, SmoothLimit) {
  // Roughness 0 is the smooth (delta) dielectric; a very small one samples its two directions with Fresnel's odds.
  MaterialDesc m;
  m.type = MaterialType::Dielectric;
  m.ior = 1.5f;
  EXPECT_TRUE(makeBSDF(m).hasDelta());
  m.glassRoughness = 0.05f;
  const BSDF rough = makeBSDF(m);
  EXPECT_FALSE(rough.hasDelta());
  EXPECT_TRUE(rough.hasTransmission());
  EXPECT_TRUE(rough.tooSharpForTable());
  const BSDF sharp = glass(0.01f);  // α at its floor, 1e-3
  for (float theta : {10.0f, 50.0f}) {
    const Vec3 wo = dirFromAngles(theta, 0);
    float cosT = 0.0f;
    const float F = fresnelDielectric(wo.z, 1.5f, &cosT);
    const Vec3 t = refractLocal(wo, 1.5f, cosT);
    Sampler rng(test::kBsdfCheckSeed, 6, 0);
    double reflected = 0.0, transmitted = 0.0;
    const int n = 20000;
    int near = 0;  // within 0.8° of the smooth directions (GGX's long tails leave a few farther out)
    for (int i = 0; i < n; ++i) {
      BSDFQuery q(wo, TransportMode::Importance);
      const float w = sharp.sample(q, rng.next2D()).x;
      if (q.wi.z > 0.0f) {
        near += glm::dot(q.wi, reflectLocal(wo)) > 0.9999f;
        reflected += w;
      } else if (w > 0.0f) {
        near += glm::dot(q.wi, t) > 0.9999f;
        transmitted += w;
      }
    }
    EXPECT_GT(near, 0.98 * n) << theta;
    EXPECT_NEAR(reflected / n, F, 0.01) << theta;
    EXPECT_NEAR(transmitted / n, 1.0 - F, 0.01) << theta;
  }
}

TEST(RoughThinGlass, LosslessPaneConservesTheMicrofacetEnergy) {
  // R + T = 1 per microfacet: the pane's albedo is the white GGX conductor's (1 − its multiple-scattering loss),
  // and at small roughness the split between the sides is the smooth pane's R(θ) : T(θ).
  for (float r : {0.05f, 0.3f, 0.7f})
    for (float theta : {0.0f, 40.0f, 70.0f}) {
      const Vec3 wo = dirFromAngles(theta, 10);
      const Split s = sampledAlbedo(losslessPane(r), wo, TransportMode::Radiance, 200000, 7);
      const BSDF metal = MetallicRoughnessBRDF{Color(1.0f), 1.0f, r, 1.5f};
      RunningStats m;
      Sampler rng(test::kBsdfCheckSeed, 8, 0);
      for (int i = 0; i < 200000; ++i) {
        BSDFQuery q(wo);
        m.add(metal.sample(q, rng.next2D()).x);
      }
      const double sigma = std::hypot(s.all.standardError(), m.standardError());
      EXPECT_NEAR(s.all.mean, m.mean, 4 * sigma + 1e-4) << r << " " << theta;
      EXPECT_LE(s.all.mean, 1.0 + 4 * s.all.standardError());
      if (r <= 0.05f) {
        const ThinGlassBSDF smooth = losslessPane(r).pane;
        EXPECT_NEAR(s.transmitted.mean, smooth.transmittance(wo.z).x, 0.005) << theta;
        EXPECT_NEAR(s.reflected.mean, smooth.reflectance(wo.z).x, 0.005) << theta;
      }
      // From the other side: the same (a pane has no inside).
      const Split back = sampledAlbedo(losslessPane(r), -wo, TransportMode::Radiance, 200000, 7);
      EXPECT_NEAR(back.transmitted.mean, s.transmitted.mean, 1e-5);
    }
}

TEST(RoughThinGlass, ReciprocalAndModeFree) {
  const BSDF b = RoughThinGlassBSDF{ThinGlassBSDF(Color(0.7f, 0.6f, 0.5f), 1.52f), 0.4f};
  Sampler rng(test::kBsdfCheckSeed, 5, 0);
  int through = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 wi = squareToUniformSphere(rng.next2D()), wo = squareToUniformSphere(rng.next2D());
    const Color f = b.eval(BSDFQuery(wi, wo)), g = b.eval(BSDFQuery(wo, wi)), h = b.eval(BSDFQuery(wi, wo, TransportMode::Importance));
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(test::nearRel(f[c], g[c], 1e-3f));
      ASSERT_EQ(f[c], h[c]);
    }
    through += wi.z * wo.z < 0.0f && f.x > 0.0f;
  }
  EXPECT_GT(through, 500);
  for (float theta : {10.0f, 60.0f, 120.0f}) {
    const auto res = test::bsdfChiSquare(b, dirFromAngles(theta, 70));
    EXPECT_GT(res.pValue, kAlpha) << theta;
  }
}

// ---- Scene keys ----

SceneDesc withMaterial(const std::string& material) { return test::quadOverFloor("glass", material, "frosted.json"); }

TEST(RoughGlassKeys, RoughnessMakesTheRoughModels) {
  auto bsdfOf = [](const std::string& material) {
    const SceneDesc d = withMaterial(material);
    return makeBSDF(d.materials[size_t(d.findMaterial("glass"))]);
  };
  EXPECT_TRUE(bsdfOf(R"({"type": "thin_glass"})").thinGlass());
  EXPECT_TRUE(bsdfOf(R"({"type": "thin_glass", "roughness": 0})").thinGlass());
  const BSDF pane = bsdfOf(R"({"type": "thin_glass", "roughness": 0.4})");
  ASSERT_TRUE(std::holds_alternative<RoughThinGlassBSDF>(pane.model()));
  EXPECT_FLOAT_EQ(std::get<RoughThinGlassBSDF>(pane.model()).roughness, 0.4f);
  EXPECT_FALSE(pane.thinGlass());  // scatters: not crossed straight through
  EXPECT_TRUE(bsdfOf(R"({"type": "dielectric", "ior": 1.5})").hasDelta());
  const BSDF solid = bsdfOf(R"({"type": "dielectric", "ior": 1.5, "roughness": 0.7})");
  ASSERT_TRUE(std::holds_alternative<RoughDielectricBSDF>(solid.model()));
  EXPECT_FALSE(solid.tooSharpForTable());
  for (const char* bad : {R"({"type": "thin_glass", "roughness": 1.5})", R"({"type": "dielectric", "ior": 1.5, "roughness": -0.1})",
                          R"({"type": "dielectric", "ior": 1.5, "roughness": "rough"})"}) {
    try {
      withMaterial(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), testing::HasSubstr("frosted.json")) << e.what();
      EXPECT_THAT(e.what(), testing::HasSubstr("materials.glass.roughness")) << e.what();
    }
  }
}

TEST(RoughGlassKeys, MitsubaRoughDielectricIsRoughGlass) {
  // Mitsuba's roughdielectric of GGX width alpha: a dielectric of roughness √alpha (not made smooth).
  const std::string path = test::tempDir() + "/rough.xml";
  test::writeText(path, R"(<scene version="3.0.0">
    <bsdf type="roughdielectric" id="frosted"><float name="alpha" value="0.25"/><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>
    <shape type="rectangle"><ref id="frosted"/></shape></scene>)");
  const SceneDesc s = loadScene(path);
  const MaterialDesc& m = s.materials.at(s.shapes.at(0).material);
  EXPECT_EQ(m.type, MaterialType::Dielectric);
  EXPECT_FLOAT_EQ(m.glassRoughness, 0.5f);
  EXPECT_TRUE(std::holds_alternative<RoughDielectricBSDF>(makeBSDF(m).model()));
}

}  // namespace
}  // namespace firstshot
