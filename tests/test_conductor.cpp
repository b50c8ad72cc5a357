// A conductor's Fresnel (common/materials/conductor_fresnel.h) against the complex-amplitude formulae evaluated independently
// in double, its limits (normal incidence, grazing, k = 0 = the dielectric, η = 0 and k = 1 = the ideal mirror) and
// hemispherical mean; the named presets; the Beckmann lobe (common/materials/beckmann.h); and the mirror and the rough metal
// with a conductor's Fresnel (common/materials/bsdf.h): the tint scales the whole Fresnel, white furnace with Fresnel 1,
// reciprocity, sampling against pdf.
//
// Thresholds: float against double within 2e-6 absolute (F ∈ [0, 1]); Monte Carlo means within 4 standard errors
// (from the samples) of a deterministic quadrature; chi-square p > kAlpha (Šidák-corrected 1% over the 4 tests).
#include <gtest/gtest.h>

#include <complex>
#include <cstdio>

#include "common/materials/bsdf.h"
#include "common/materials/conductor_fresnel.h"
#include "common/materials/conductor_presets.h"
#include "common/materials/fresnel.h"
#include "common/scene/scene_desc.h"
#include "tests/bsdf_checks.h"

namespace firstshot {
namespace {

using test::dirFromAngles;
using test::RunningStats;

const double kAlpha = test::sidakAlpha(0.01, 4);

/// The unpolarised Fresnel reflectance from the amplitude ratios themselves, in complex double: n = η + ik,
/// w = √(n² − sin²θ) (the principal root: Re w ≥ 0, and Im w ≥ 0 as Im n² ≥ 0), r_s = (cos − w)/(cos + w),
/// r_p = (n² cos − w)/(n² cos + w).
double fresnelReference(double cosI, double eta, double k) {
  const std::complex<double> n(eta, k), n2 = n * n;
  const std::complex<double> w = std::sqrt(n2 - (1.0 - cosI * cosI));
  const std::complex<double> rs = (cosI - w) / (cosI + w), rp = (n2 * cosI - w) / (n2 * cosI + w);
  return 0.5 * (std::norm(rs) + std::norm(rp));
}

/// Metals (Cu's RGB η, k from the Veach MIS scene), an absorbing dielectric, strong and weak absorbers.
const std::vector<std::pair<double, double>> kIndices = {{0.200438, 3.91295}, {0.924033, 2.45285}, {1.10221, 2.14219},
                                                         {1.5, 0.2},          {3.0, 0.01},         {0.05, 8.0},
                                                         {2.5, 4.0}};

TEST(ConductorFresnel, NormalIncidenceIsTheClosedForm) {
  for (const auto& [eta, k] : kIndices) {
    const double f0 = ((eta - 1) * (eta - 1) + k * k) / ((eta + 1) * (eta + 1) + k * k);
    EXPECT_NEAR(fresnelConductor(1.0f, float(eta), float(k)), f0, 2e-6) << eta << " + " << k << "i";
    const ConductorFresnel c{Color(float(eta)), Color(float(k))};
    EXPECT_NEAR(c.normalIncidence().x, f0, 2e-6);
    EXPECT_NEAR(c.eval(1.0f).y, f0, 2e-6);
  }
}

TEST(ConductorFresnel, MatchesTheAmplitudesAtEveryAngleAndIsOneAtGrazing) {
  for (const auto& [eta, k] : kIndices) {
    for (int i = 0; i <= 200; ++i) {
      const double c = i / 200.0;
      EXPECT_NEAR(fresnelConductor(float(c), float(eta), float(k)), fresnelReference(c, eta, k), 2e-6)
          << eta << " + " << k << "i at cos " << c;
    }
    EXPECT_EQ(fresnelConductor(0.0f, float(eta), float(k)), 1.0f) << "grazing";
    // A grazing angle, 89°: the rise towards 1, far above normal incidence for the weak absorber, as the formulae say.
    const double c89 = std::cos(89.0 * kPi / 180.0);
    EXPECT_NEAR(fresnelConductor(float(c89), float(eta), float(k)), fresnelReference(c89, eta, k), 2e-6);
  }
  // Copper's red channel at 89°: 0.99247 (normal incidence 0.95214).
  EXPECT_NEAR(fresnelConductor(float(std::cos(89.0 * kPi / 180.0)), 0.200438f, 3.91295f), 0.99247, 2e-5);
}

TEST(ConductorFresnel, WithoutExtinctionIsTheDielectric) {
  for (float eta : {1.5f, 1.0f / 1.5f, 1.33f, 2.4f})
    for (int i = 0; i <= 400; ++i) {
      const float c = i / 400.0f;
      EXPECT_NEAR(fresnelConductor(c, eta, 0.0f), fresnelDielectric(c, eta), 2e-6) << eta << " at cos " << c;
    }
}

TEST(ConductorFresnel, IdealMirrorReflectsEverythingAtEveryAngle) {
  const ConductorFresnel none;  // η = 0, k = 1
  for (int i = 0; i <= 100; ++i) EXPECT_EQ(none.eval(i / 100.0f), Color(1.0f)) << i;
  EXPECT_EQ(none.hemisphericalMean(), Color(1.0f));
  const ConductorFresnel explicitNone(Color(0.0f), Color(1.0f));  // the same, its mean by quadrature
  EXPECT_NEAR(explicitNone.hemisphericalMean().x, 1.0, 1e-6);
  EXPECT_EQ(conductorPreset("none"), none);
}

TEST(ConductorFresnel, HemisphericalMeanAgreesWithAFineQuadrature) {
  for (const auto& [eta, k] : kIndices) {
    double sum = 0.0;
    constexpr int n = 200000;
    for (int i = 0; i < n; ++i) {
      const double c = (i + 0.5) / n;
      sum += 2.0 * c * fresnelReference(c, eta, k) / n;
    }
    EXPECT_NEAR(ConductorFresnel(Color(float(eta)), Color(float(k))).hemisphericalMean().z, sum, 1e-5) << eta << " + " << k << "i";
  }
  // A dielectric of index 1.5: the well-known 9.2 % of diffuse light reflected by a glass surface.
  EXPECT_NEAR(ConductorFresnel(Color(1.5f), Color(0.0f)).hemisphericalMean().x, 0.0918, 5e-4);
}

TEST(ConductorPresets, CopperIsMitsubasRgbCopper) {
  // Mitsuba's RGB reduction of its spectral copper: the numbers the Veach MIS scene spells out for its plates.
  const std::optional<ConductorFresnel> cu = conductorPreset("Cu");
  ASSERT_TRUE(cu);
  const Color eta(0.200438f, 0.924033f, 1.10221f), k(3.91295f, 2.45285f, 2.14219f);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(cu->eta()[c], eta[c], 2e-6f * eta[c]);
    EXPECT_NEAR(cu->k()[c], k[c], 2e-6f * k[c]);
  }
  // Gold reflects red more than blue; silver and aluminium above 0.9 in every channel; "none" is the ideal mirror.
  const Color au = conductorPreset("Au")->normalIncidence();
  EXPECT_GT(au.x, 0.9f);
  EXPECT_LT(au.z, 0.5f);
  for (const char* white : {"Ag", "Al"}) EXPECT_GT(std::min({conductorPreset(white)->normalIncidence().x,
                                                             conductorPreset(white)->normalIncidence().y,
                                                             conductorPreset(white)->normalIncidence().z}), 0.9f) << white;
  EXPECT_FALSE(conductorPreset("Unobtainium"));
  EXPECT_FALSE(conductorPreset("cu")) << "names are case-sensitive, as Mitsuba's files";
  for (const char* name : {"none", "Au", "Ag", "Al", "Cu", "Cr", "Ni_palik", "a-C", "W"})
    EXPECT_NE(conductorPresetNames().find(name), std::string::npos) << name;
}

// ---- The mirror and the rough metal with a conductor's Fresnel ----

const ConductorFresnel kCopper(Color(0.200438f, 0.924033f, 1.10221f), Color(3.91295f, 2.45285f, 2.14219f));

TEST(ConductorBsdf, TintScalesTheWholeFresnelOfTheMirror) {
  const Color tint(0.3f);
  const BSDF mirror = MirrorBRDF{tint, kCopper};
  for (float cosO : {1.0f, 0.5f, 0.1f, 1e-4f}) {
    BSDFQuery q(Vec3(std::sqrt(1 - cosO * cosO), 0.0f, cosO));
    const Color w = mirror.sample(q, Vec2(0.5f));
    EXPECT_TRUE(q.specular);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(w[c], tint[c] * kCopper.eval(cosO)[c], 1e-6f) << cosO;
  }
  // Grazing: tint × F → tint (0.3), where a Schlick rise from F0 × tint would reach 1.
  BSDFQuery grazing(Vec3(1.0f, 0.0f, 1e-6f));
  const Color g = mirror.sample(grazing, Vec2(0.5f));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(g[c], 0.3f, 1e-4f);
  // Without a Fresnel the mirror reflects its tint at every angle, bit for bit.
  BSDFQuery plain(Vec3(0.6f, 0.0f, 0.8f));
  EXPECT_EQ(BSDF(MirrorBRDF{Color(0.9f, 0.8f, 0.7f)}).sample(plain, Vec2(0.5f)), Color(0.9f, 0.8f, 0.7f));
  EXPECT_NEAR(mirror.albedo().x, 0.3f * kCopper.hemisphericalMean().x, 1e-7f);
}

TEST(ConductorBsdf, TintScalesTheWholeFresnelOfTheRoughMetal) {
  for (MicrofacetModel model : {MicrofacetModel::Ggx, MicrofacetModel::Beckmann}) {
    const Color tint(0.3f, 0.5f, 0.7f);
    const MetallicRoughnessBRDF metal{tint, 1.0f, 0.4f, 1.5f, model, kCopper};
    const float alpha = ggxAlpha(0.4f);
    for (float theta : {0.0f, 40.0f, 80.0f, 89.9f}) {
      // wi the mirror direction of wo: h = the normal, c = wo·h = cos θ sweeping towards 0.
      const Vec3 wo = dirFromAngles(theta, 0), wi = dirFromAngles(theta, 180);
      const Vec3 h = glm::normalize(wi + wo);
      const float c = glm::dot(wo, h), s = microfacetSpecular(model, wi, wo, alpha);
      const Color f = BSDF(metal).eval(BSDFQuery(wi, wo));
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(f[ch], tint[ch] * kCopper.eval(c)[ch] * s, 1e-5f * f[ch]) << theta;
    }
    // A facet seen at grazing incidence (c → 0): the Fresnel → tint, not 1 (copper's F at c = 0.0087: 0.977 and up).
    const Vec3 wo = dirFromAngles(89.5f, 0), wi = dirFromAngles(89.5f, 180);
    const float c = glm::dot(wo, glm::normalize(wi + wo));
    EXPECT_LT(c, 0.01f);
    const Color ratio = BSDF(metal).eval(BSDFQuery(wi, wo)) / microfacetSpecular(model, wi, wo, alpha);
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_GT(ratio[ch], 0.95f * tint[ch]);
      EXPECT_LE(ratio[ch], tint[ch] * 1.0001f);
    }
  }
}

TEST(ConductorBsdf, RoughMetalIsReciprocal) {
  Sampler rng(test::kBsdfCheckSeed, 40, 0);
  for (MicrofacetModel model : {MicrofacetModel::Ggx, MicrofacetModel::Beckmann})
    for (int i = 0; i < 2000; ++i) {
      const BSDF metal = MetallicRoughnessBRDF{Color(0.8f, 0.6f, 0.4f), 0.7f, 0.3f, 1.5f, model, kCopper};
      const Vec3 a = squareToUniformHemisphere(rng.next2D()), b = squareToUniformHemisphere(rng.next2D());
      const Color f1 = metal.eval(BSDFQuery(a, b)), f2 = metal.eval(BSDFQuery(b, a));
      for (int c = 0; c < 3; ++c) ASSERT_TRUE(test::nearRel(f1[c], f2[c], 1e-4f)) << f1[c] << " vs " << f2[c];
    }
}

TEST(ConductorBsdf, GgxWithFresnelOneIsTheWhiteMetal) {
  // F ≡ 1 both ways (Schlick from F0 = 1, and η = 0, k = 1): the same BRDF value for value.
  Sampler rng(test::kBsdfCheckSeed, 41, 0);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 a = squareToUniformHemisphere(rng.next2D()), b = squareToUniformHemisphere(rng.next2D());
    const BSDF schlick = MetallicRoughnessBRDF{Color(1.0f), 1.0f, 0.4f, 1.5f};
    const BSDF none = MetallicRoughnessBRDF{Color(1.0f), 1.0f, 0.4f, 1.5f, MicrofacetModel::Ggx, ConductorFresnel()};
    ASSERT_EQ(schlick.eval(BSDFQuery(a, b)), none.eval(BSDFQuery(a, b)));
  }
}

/// Beckmann's Λ in double: (e^(−a²)/(a√π) − erfc(a))/2, a = 1/(α tan θ).
double lambdaBeckmann(const glm::dvec3& w, double alpha) {
  const double a = w.z / (alpha * std::sqrt(w.x * w.x + w.y * w.y));
  return 0.5 * (std::exp(-a * a) / (a * std::sqrt(kPi)) - std::erfc(a));
}

// Not test_microfacet.cpp's GGX quadrature: Beckmann's slopes (tan² = −α² ln(1 − s)) and Λ differ.
/// The directional albedo of the white Beckmann conductor for wo by a deterministic midpoint quadrature over normals
/// drawn as D(h) cos θ_h (tan²θ_h = −α² ln(1 − s)): ∫ G2 (wo·h)/(wo.z h.z) over that density, in double.
double beckmannFurnace(double alpha, const Vec3& wo, int ns = 800, int nphi = 128) {
  const glm::dvec3 o(wo);
  double sum = 0.0;
  for (int i = 0; i < ns; ++i) {
    const double tan2 = -alpha * alpha * std::log(1.0 - (i + 0.5) / ns);
    const double cosH = 1.0 / std::sqrt(1.0 + tan2), sinH = std::sqrt(1.0 - cosH * cosH);
    for (int j = 0; j < nphi; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / nphi;
      const glm::dvec3 h(sinH * std::cos(phi), sinH * std::sin(phi), cosH);
      const double oh = glm::dot(o, h);
      if (oh <= 0.0) continue;
      const glm::dvec3 in = 2.0 * oh * h - o;
      if (in.z <= 0.0) continue;
      sum += oh / (o.z * cosH) / (1.0 + lambdaBeckmann(in, alpha) + lambdaBeckmann(o, alpha));
    }
  }
  return sum / (double(ns) * nphi);
}

TEST(Beckmann, DistributionIsNormalised) {
  for (float alpha : {0.1f, 0.3f, 0.7f}) {
    RunningStats d;
    Sampler rng(test::kBsdfCheckSeed, 42, 0);
    for (int i = 0; i < 200000; ++i) {
      const Vec3 h = squareToUniformHemisphere(rng.next2D());
      d.add(beckmannD(h, alpha) * h.z * 2.0 * kPi);
    }
    EXPECT_NEAR(d.mean, 1.0, 4 * d.standardError() + 1e-3) << alpha;
  }
  EXPECT_NEAR(beckmannD(Vec3(0, 0, 1), 0.2f), 1.0 / (kPi * 0.04), 1e-4);
  EXPECT_EQ(beckmannLambda(Vec3(0, 0, 1), 0.3f), 0.0f);
}

TEST(Beckmann, WhiteFurnaceWithFresnelOne) {
  // The white rough conductor (Fresnel 1: η = 0, k = 1) reflects at most what it receives; its albedo by sample()
  // matches the quadrature within 4σ, and loses under 1% at small roughness and moderate angles.
  std::printf("roughness  theta_o  albedo(quadrature)  albedo(sampled) ± σ\n");
  for (float r : {0.1f, 0.3f, 0.5f, 1.0f})
    for (float theta : {0.0f, 45.0f, 80.0f}) {
      const Vec3 wo = dirFromAngles(theta, 30);
      const double a = beckmannFurnace(ggxAlpha(r), wo);
      const BSDF white = MetallicRoughnessBRDF{Color(1.0f), 1.0f, r, 1.5f, MicrofacetModel::Beckmann, ConductorFresnel()};
      RunningStats s;
      Sampler rng(test::kBsdfCheckSeed, 43, 0);
      for (int i = 0; i < 40000; ++i) {
        BSDFQuery q(wo);
        s.add(white.sample(q, rng.next2D()).x);
      }
      std::printf("%9.2f  %7.0f  %18.5f  %.5f ± %.5f\n", r, theta, a, s.mean, s.standardError());
      EXPECT_LE(a, 1.0 + 1e-6);
      EXPECT_NEAR(s.mean, a, 4 * s.standardError() + 2e-4) << r << " at " << theta;
      if (r <= 0.3f && theta <= 45.0f) {
        EXPECT_GT(a, 0.99) << r;
      }
    }
}

TEST(Beckmann, SamplingMatchesPdf) {
  for (float r : {0.5f, 0.9f})
    for (float theta : {20.0f, 70.0f}) {
      const BSDF metal = MetallicRoughnessBRDF{Color(0.9f), 1.0f, r, 1.5f, MicrofacetModel::Beckmann, kCopper};
      EXPECT_GT(test::bsdfChiSquare(metal, dirFromAngles(theta, 10), Frame(), -1.0, 100000).pValue, kAlpha)
          << r << " at " << theta;
    }
  test::checkSampleConsistency(MetallicRoughnessBRDF{Color(0.7f), 0.6f, 0.3f, 1.5f, MicrofacetModel::Beckmann, kCopper});
}

TEST(ConductorBsdf, MaterialCarriesTheFresnelToTheBsdf) {
  MaterialDesc m;
  m.type = MaterialType::Pbr;
  m.albedo = Color(0.3f);
  m.roughness = 0.2f;
  m.conductor = kCopper;
  m.microfacet = MicrofacetModel::Beckmann;
  const BSDF metal = makeBSDF(m);
  const auto* p = std::get_if<MetallicRoughnessBRDF>(&metal.model());
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->conductor, kCopper);
  EXPECT_EQ(p->microfacet, MicrofacetModel::Beckmann);
  EXPECT_NEAR(metal.albedo().y, 0.3f * kCopper.hemisphericalMean().y, 1e-7f);
  m.type = MaterialType::Mirror;
  m.specular = Color(0.5f);
  const BSDF smooth = makeBSDF(m);
  const auto* mirror = std::get_if<MirrorBRDF>(&smooth.model());
  ASSERT_NE(mirror, nullptr);
  EXPECT_EQ(mirror->fresnel, kCopper);
  MaterialDesc plain;  // a scene that does not ask: no Fresnel, GGX
  plain.type = MaterialType::Pbr;
  EXPECT_FALSE(std::get<MetallicRoughnessBRDF>(makeBSDF(plain).model()).conductor);
  EXPECT_EQ(std::get<MetallicRoughnessBRDF>(makeBSDF(plain).model()).microfacet, MicrofacetModel::Ggx);
}

}  // namespace
}  // namespace firstshot
