// IES LM-63 files and light units (common/lights/ies.h, common/lights/emission_profile.h, scene keys power /
// lumens / candela): exact flux of the interpolated table, symmetries, the sampling distribution
// against its pdf, orientation of the table in the scene, and the unit keys.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>

#include "common/lights/emission_profile.h"
#include "common/lights/ies.h"
#include "common/lights/photometry.h"
#include "common/sampling/rng.h"
#include "common/sampling/sampling.h"
#include "common/util/error.h"
#include "tests/ies_util.h"
#include "tests/light_tracing_util.h"
#include "tests/render_util.h"

using namespace firstshot;

namespace {

constexpr double kDeg = kPi / 180.0;

/// ∫ valueLocal dω by the midpoint rule on a fine grid of (cos θ, φ) cells, independent of the
/// table's angle conventions (lm).
double sphereIntegral(const IesData& d, int n = 1200) {
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double z = -1 + 2 * (i + 0.5) / n, r = std::sqrt(1 - z * z), phi = kPi * (j + 0.5) / n;
      sum += d.valueLocal({r * std::cos(phi), r * std::sin(phi), z});
    }
  return sum * 4 * kPi / (2.0 * n * n);
}

/// Three tables with structure in both angles: type C (full 0–360), type B and type A (both halves).
std::vector<IesData> testTables() {
  auto f = [](double v, double h) { return 300 + 200 * std::cos(v * kDeg) * std::cos(v * kDeg) + 100 * std::sin(h * kDeg / 2); };
  auto g = [](double v, double h) { return std::max(0.0, 500 * std::cos(v * kDeg) * std::cos(h * kDeg) + 30 * std::abs(h) / 90); };
  return {parseIes(test::iesText(1, test::angleRange(0, 180, 10), test::angleRange(0, 360, 30), f), "c.ies"),
          parseIes(test::iesText(2, test::angleRange(-90, 90, 10), test::angleRange(-90, 90, 15), g), "b.ies"),
          parseIes(test::iesText(3, test::angleRange(-60, 90, 7.5), test::angleRange(0, 90, 10), g), "a.ies")};
}

LightDesc onlyLight(const std::string& lightJson) {
  const SceneDesc s = test::sceneFromJson(R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5}},
      "shapes": [{"type": "quad", "material": "m", "vertices": [[-1,0,-1],[-1,0,1],[1,0,1],[1,0,-1]]}],
      "lights": [)" + lightJson + "]}");
  return s.lights.at(0);
}

}  // namespace

// 1000 cd everywhere (type C, axial symmetry): the flux is 4π·1000 lm to rounding, the table 1000 cd everywhere.
TEST(Ies, ConstantTableFluxIsExact) {
  const IesData d = parseIes(test::iesText(1, {0, 45, 90, 135, 180}, {0}, [](double, double) { return 1000.0; }, 2.5), "k.ies");
  EXPECT_NEAR(d.flux, 4 * kPi * 1000, 1e-9 * d.flux);
  EXPECT_DOUBLE_EQ(d.maxCandela, 1000);
  for (double v : {0.0, 10.0, 91.0, 180.0})
    for (double h : {0.0, 33.0, 200.0, 359.9}) EXPECT_NEAR(d.value(v, h), 1000, 1e-9);
  EXPECT_NEAR(sphereIntegral(d, 200), d.flux, 1e-9 * d.flux);

  // A file that rates its lamp at the luminaire's flux (efficiency 1): the table's flux is the file's lumens.
  const double rated = 4 * kPi * 1000;
  const IesData r = parseIes(test::iesText(1, {0, 45, 90, 135, 180}, {0}, [](double, double) { return 1000.0; }, 1, rated), "r.ies");
  EXPECT_NEAR(r.lamps * r.lumensPerLamp, rated, 1e-9 * rated);
  EXPECT_NEAR(r.flux, r.lamps * r.lumensPerLamp, 1e-9 * rated);
}

// I = 1000 cos V in the lower hemisphere (zero above): the interpolated table's flux is exact (against a fine
// midpoint rule) and close to the analytic 1000π lm; the multiplier and ballast factor scale the values.
TEST(Ies, CosineLobeFlux) {
  const IesData d = parseIes(test::iesText(1, test::angleRange(0, 90, 2.5), {0},
                                           [](double v, double) { return 1000 * std::cos(v * kDeg); }, 0.5), "cos.ies");
  EXPECT_NEAR(d.value(60, 123), 500, 0.2);
  EXPECT_EQ(d.value(90.5, 0), 0.0);
  EXPECT_NEAR(d.flux, 1000 * kPi, 1e-3 * d.flux);
  double midpoint = 0;  // ∫ value(V) sin V dV · 2π
  const int n = 200000;
  for (int k = 0; k < n; ++k) {
    const double v = 90.0 * (k + 0.5) / n;
    midpoint += d.value(v, 0) * std::sin(v * kDeg) * (90.0 / n) * kDeg;
  }
  EXPECT_NEAR(d.flux, 2 * kPi * midpoint, 1e-8 * d.flux);
}

// Types C, B and A with structure in both angles: the exact flux against an integral over the sphere of the
// local directions (which checks the angle conventions' solid-angle weights).
TEST(Ies, FluxOfAllTypesMatchesSphereIntegral) {
  for (const IesData& d : testTables()) {
    const double s = sphereIntegral(d);
    fmt::print("{}: flux {:.4f} lm, sphere integral {:.4f} lm\n", d.file, d.flux, s);
    EXPECT_NEAR(d.flux, s, 2e-5 * d.flux) << d.file;
  }
}

// The piecewise-constant direction distribution: the density sampleLocal returns is pdfLocal at the sampled
// direction, positive wherever the table is, and E[I/pdf] is the flux (within 3σ).
TEST(Ies, SamplingDensityMatchesPdf) {
  for (const IesData& d : testTables()) {
    test::Moments m;
    int mismatched = 0;
    const int n = 40000;
    for (int k = 0; k < n; ++k) {
      Sampler s(7, 0, uint64_t(k));
      double pdf = 0;
      const double u0 = s.next1Dd(), u1 = s.next1Dd();
      const Vec3d w = d.sampleLocal(u0, u1, pdf);
      ASSERT_GT(pdf, 0.0);
      ASSERT_NEAR(glm::length(w), 1.0, 1e-9);
      if (std::abs(d.pdfLocal(w) - pdf) > 1e-9 * pdf) ++mismatched;  // only on cell borders
      m.add(d.valueLocal(w) / pdf);
      const Vec3d u = glm::normalize(Vec3d(squareToUniformSphere(s.next2D())));
      if (d.valueLocal(u) > 0) {
        EXPECT_GT(d.pdfLocal(u), 0.0);
      }
    }
    fmt::print("{}: E[I/pdf] = {:.3f} ± {:.3f}, flux {:.3f}; {} pdf mismatches\n", d.file, m.mean(), m.se(), d.flux, mismatched);
    EXPECT_LE(mismatched, n / 1000);
    EXPECT_LE(std::abs(m.mean() - d.flux), 3 * m.se() + 1e-9 * d.flux) << d.file;
    EXPECT_GT(m.se(), 0.0);
  }
}

// Type C symmetries expand to the mirrored values; types A and B with H in 0–90 mirror about H = 0.
TEST(Ies, SymmetriesReturnMirroredValues) {
  auto f = [](double v, double h) { return 100 + v + 3 * h; };
  const auto v = test::angleRange(0, 180, 15);
  const IesData quadrant = parseIes(test::iesText(1, v, {0, 30, 60, 90}, f), "q.ies");
  const IesData bilateral = parseIes(test::iesText(1, v, test::angleRange(0, 180, 30), f), "b.ies");
  const IesData other = parseIes(test::iesText(1, v, test::angleRange(90, 270, 30), f), "o.ies");
  const IesData wrap = parseIes(test::iesText(1, v, test::angleRange(0, 330, 30), f), "w.ies");
  for (double vv : {0.0, 20.0, 95.0, 170.0})
    for (double h : {0.0, 10.0, 45.0, 80.0, 90.0}) {
      const double q = quadrant.value(vv, h);
      EXPECT_NEAR(q, f(vv, h), 1e-9);
      for (double m : {180 - h, 180 + h, 360 - h}) EXPECT_NEAR(quadrant.value(vv, m), q, 1e-9) << vv << " " << m;
      EXPECT_NEAR(bilateral.value(vv, 360 - h), bilateral.value(vv, h), 1e-9);
      EXPECT_NEAR(bilateral.value(vv, 360 - (h + 90)), f(vv, h + 90), 1e-9);
      EXPECT_NEAR(other.value(vv, 180 - (90 + h)), f(vv, 90 + h), 1e-9);  // mirror about the 90–270 plane
      EXPECT_NEAR(other.value(vv, 360 - h), f(vv, 180 + h), 1e-9);
    }
  EXPECT_NEAR(wrap.value(30, 345), 0.5 * (f(30, 330) + f(30, 0)), 1e-9);  // 330–360 interpolates towards 0°
  const IesData b = parseIes(test::iesText(2, test::angleRange(-90, 90, 10), {0, 45, 90}, f), "bb.ies");
  for (double h : {10.0, 45.0, 70.0}) EXPECT_NEAR(b.value(20, -h), b.value(20, h), 1e-9);
  EXPECT_EQ(b.value(20, 0), f(20, 0));
}

// The table in the scene: direction = photometric axis (V = 0), ies_reference = C0; C90 = C0 × axis.
// A table of 2000 cd in the C0–C180 plane and 500 cd in C90–C270 (lower hemisphere) turns with both.
TEST(Ies, OrientationFollowsDirectionAndReference) {
  const std::string file = test::writeIes("orient.ies", test::iesText(1, test::angleRange(0, 90, 5), {0, 90},
                                                                      [](double, double h) { return h == 0 ? 2000.0 : 500.0; }));
  const double K = photometry::kEfficacy;
  auto candela = [&](const std::string& extra, const Vec3d& w) {
    const LightDesc l = onlyLight(R"({"type": "ies", "position": [0, 1, 0], "file": ")" + file + "\"" + extra + "}");
    return EmissionProfile(l).intensity(l, glm::normalize(w)).y * K;
  };
  const double s = std::sin(40 * kDeg), c = std::cos(40 * kDeg);
  // Default: axis (0, −1, 0), C0 = +x, C90 = x × (−y) = −z.
  EXPECT_NEAR(candela("", {s, -c, 0}), 2000, 0.01);
  EXPECT_NEAR(candela("", {-s, -c, 0}), 2000, 0.01);
  EXPECT_NEAR(candela("", {0, -c, -s}), 500, 0.01);
  EXPECT_NEAR(candela("", {0, c, 0.1}), 0, 1e-9);  // upper hemisphere: dark
  // C0 = +z: the bright plane is now the y–z plane.
  EXPECT_NEAR(candela(R"(, "ies_reference": [0, 0, 1])", {0, -c, s}), 2000, 0.01);
  EXPECT_NEAR(candela(R"(, "ies_reference": [0, 0, 1])", {s, -c, 0}), 500, 0.01);
  // Axis +x, C0 = +y: bright in the x–y plane, dark behind (−x).
  const std::string side = R"(, "direction": [1, 0, 0], "ies_reference": [0, 1, 0])";
  EXPECT_NEAR(candela(side, {c, s, 0}), 2000, 0.01);
  EXPECT_NEAR(candela(side, {c, 0, s}), 500, 0.01);
  EXPECT_NEAR(candela(side, {-1, 0, 0}), 0, 1e-9);
  // The default reference of an axis along x is +z.
  EXPECT_NEAR(candela(R"(, "direction": [1, 0, 0])", {c, 0, s}), 2000, 0.01);
}

// Types A and B: axis = forward, reference = up, +H to the right (axis × up), +V up. Type B: planes through the
// right–left axis (w = cos H (cos V f + sin V u) + sin H r); type A: planes through the up–down axis
// (w = cos V (cos H f + sin H r) + sin V u).
TEST(Ies, TypesAAndBFollowTheirAngleConventions) {
  auto I = [](double v, double h) { return 1000 + 5 * h + 2 * v; };
  const Vec3d f(0, 0, -1), u(0, 1, 0), r(1, 0, 0);  // forward −z, up +y: right = (−z) × y = +x
  const double V = 30 * kDeg, H = 20 * kDeg;
  for (int type : {2, 3}) {
    const std::string file = test::writeIes("ab.ies", test::iesText(type, test::angleRange(-90, 90, 10), test::angleRange(-90, 90, 10), I));
    const LightDesc l = onlyLight(R"({"type": "ies", "position": [0, 1, 0], "direction": [0, 0, -1], "file": ")" + file + "\"}");
    const EmissionProfile p(l);
    const Vec3d w = type == 2 ? std::cos(H) * (std::cos(V) * f + std::sin(V) * u) + std::sin(H) * r
                              : std::cos(V) * (std::cos(H) * f + std::sin(H) * r) + std::sin(V) * u;
    EXPECT_NEAR(p.intensity(l, w).x * photometry::kEfficacy, I(30, 20), 1e-3) << type;
    EXPECT_NEAR(p.intensity(l, -f).x, 0.0, 1e-12) << type;  // behind the luminaire
  }
}

// power, lumens and candela describe the same light: the same LightDesc::power (W) for a point and a spot;
// colours are chromaticities (Y = 1); an IES light takes its file's flux or the given lumens.
TEST(LightUnits, WattsLumensCandelaAgree) {
  const double K = photometry::kEfficacy, watts = 12.0;
  auto power = [&](const std::string& j) { return onlyLight(j).power; };
  const Color p = power(R"({"type": "point", "position": [0,1,0], "power": 12})");
  EXPECT_EQ(p, Color(12.0f));
  const Color pl = power(fmt::format(R"({{"type": "point", "position": [0,1,0], "lumens": {}}})", watts * K));
  const Color pc = power(fmt::format(R"({{"type": "point", "position": [0,1,0], "candela": {}}})", watts * K / (4 * kPi)));
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(pl[c], watts, 1e-5 * watts);
    EXPECT_NEAR(pc[c], watts, 1e-5 * watts);
  }

  const std::string spot = R"("type": "spot", "position": [0,1,0], "direction": [0,-1,0], "inner_angle": 20, "outer_angle": 35)";
  const LightDesc sw = onlyLight("{" + spot + R"(, "power": 12})");
  const double I0 = watts * K / EmissionProfile(sw).integral();
  const Color sc = power(fmt::format("{{{}, \"candela\": {}}}", spot, I0));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sc[c], watts, 1e-5 * watts);
  EXPECT_NEAR(EmissionProfile(sw).intensity(sw, {0, -1, 0}).x * K, I0, 1e-5 * I0);  // on-axis intensity

  const Color red = power(R"({"type": "point", "position": [0,1,0], "lumens": 1000, "color": [2, 0, 0]})");
  EXPECT_NEAR(photometry::luminance(red) * K, 1000, 1e-3);
  EXPECT_EQ(red.y, 0.0f);

  const std::string file = test::writeIes("k.ies", test::iesText(1, {0, 90, 180}, {0}, [](double, double) { return 1000.0; }));
  const Color ies = power(R"({"type": "ies", "position": [0,1,0], "file": ")" + file + "\"}");
  EXPECT_NEAR(ies.x, 4 * kPi * 1000 / K, 1e-4);
  const Color iesLm = power(R"({"type": "ies", "position": [0,1,0], "lumens": 500, "file": ")" + file + "\"}");
  EXPECT_NEAR(iesLm.y, 500 / K, 1e-5);

  for (const std::string bad : {R"({"type": "point", "position": [0,1,0], "power": 1, "lumens": 2})",
                                R"({"type": "point", "position": [0,1,0]})",
                                R"({"type": "point", "position": [0,1,0], "power": 1, "color": [1,1,1]})",
                                R"({"type": "point", "position": [0,1,0], "lumens": 1, "color": [0,0,0]})"}) {
    EXPECT_THROW(onlyLight(bad), InputError) << bad;
  }
  EXPECT_THROW(onlyLight(R"({"type": "ies", "position": [0,1,0], "candela": 5, "file": ")" + file + "\"}"), InputError);
  EXPECT_THROW(onlyLight(R"({"type": "ies", "position": [0,1,0], "ies_reference": [0,2,0], "file": ")" + file + "\"}"),
               InputError);  // parallel to the default axis
}

// Limits and unsupported layouts are input errors (the malformed files through the tools: test_ies_render).
TEST(Ies, RejectsOversizedFilesAndUnsupportedLayouts) {
  auto one = [](double, double) { return 10.0; };
  EXPECT_THROW(parseIes(std::string(kMaxIesBytes + 1, ' '), "big.ies"), InputError);
  EXPECT_THROW(parseIes(test::iesText(1, {0, 90}, {0, 120}, one), "c.ies"), InputError);       // C range 0–120
  EXPECT_THROW(parseIes(test::iesText(2, {0, 90}, {0}, one), "b.ies"), InputError);            // B with one H
  EXPECT_THROW(parseIes(test::iesText(1, {0, 200}, {0}, one), "v.ies"), InputError);           // V beyond 180
  EXPECT_THROW(parseIes(test::iesText(1, {0, 90}, {0}, [](double, double) { return 0.0; }), "z.ies"), InputError);
  EXPECT_THROW(parseIes(test::iesText(1, {0, 90}, {0}, [](double, double) { return 1e300; }), "h.ies"), InputError);
  try {
    const std::string text = test::iesText(1, {0, 45, 90}, {0}, one);
    parseIes(text.substr(0, text.size() - 6), "cut.ies");
    ADD_FAILURE() << "a truncated file parsed";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "cut.ies");
    EXPECT_EQ(e.element().rfind("line ", 0), 0u) << e.what();
  }
  EXPECT_THROW(loadIes("/nonexistent/x.ies"), InputError);
}
