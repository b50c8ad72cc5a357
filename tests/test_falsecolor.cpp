// False-colour pictures (render/output/falsecolor.h): the colour map's order, nice ranges and ticks, known
// values at known pixels on log and linear scales, the legend's text, iso-lines at the ticks.
#include <gtest/gtest.h>

#include <cmath>

#include "render/output/falsecolor.h"

using namespace firstshot;
using namespace firstshot::falsecolor;

namespace {

double srgbToLinear(double c) {
  c /= 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

/// Relative luminance (Rec. 709 weights) of an 8-bit sRGB colour.
double relativeLuminance(const uint8_t* c) {
  return 0.2126 * srgbToLinear(c[0]) + 0.7152 * srgbToLinear(c[1]) + 0.0722 * srgbToLinear(c[2]);
}

bool isInk(const uint8_t* c) { return c[0] == kInk[0] && c[1] == kInk[1] && c[2] == kInk[2]; }

/// Asserts pixel (x, y) of @p p has colour @p c, each channel within @p tol.
void expectColor(const Picture& p, int x, int y, const std::array<uint8_t, 3>& c, int tol, const std::string& what) {
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(int(p.at(x, y)[k]), int(c[k]), tol) << what << " channel " << k << " at " << x << "," << y;
}

/// A width × 1 field of @p values.
Field row(const std::vector<double>& values, const std::string& units = "lx") {
  return {int(values.size()), 1, values, units};
}

}  // namespace

// The map's luminance increases strictly at 129 evenly spaced t (8-bit rounding hides finer steps),
// from a dark to a light end: the order survives a grey print.
TEST(FalseColor, ColorMapLuminanceIncreases) {
  double previous = -1;
  for (int k = 0; k <= 128; ++k) {
    const auto c = colorMap(k / 128.0);
    const double y = relativeLuminance(c.data());
    EXPECT_GT(y, previous) << "t = " << k / 128.0;
    previous = y;
  }
  EXPECT_LT(relativeLuminance(colorMap(0).data()), 0.02);
  EXPECT_GT(relativeLuminance(colorMap(1).data()), 0.7);
  EXPECT_EQ(colorMap(-3), colorMap(0));  // clamped
  EXPECT_EQ(colorMap(7), colorMap(1));
  EXPECT_EQ(colorMap(std::nan("")), colorMap(0));
}

TEST(FalseColor, NiceNumbersAndAutoRange) {
  EXPECT_DOUBLE_EQ(niceNumber(3.2, true), 5);
  EXPECT_DOUBLE_EQ(niceNumber(3.2, false), 2);
  EXPECT_DOUBLE_EQ(niceNumber(7, true), 10);
  EXPECT_DOUBLE_EQ(niceNumber(0.013, false), 0.01);
  EXPECT_DOUBLE_EQ(niceNumber(200, true), 200);
  EXPECT_DOUBLE_EQ(niceNumber(200, false), 200);

  // Linear: 1st and 99th percentiles of 0..1000 are 10 and 990; a step of nice(980/5) = 200.
  std::vector<double> ramp;
  for (int i = 0; i <= 1000; ++i) ramp.push_back(i);
  Range r = autoRange(ramp, Scale::Linear);
  EXPECT_DOUBLE_EQ(r.min, 0);
  EXPECT_DOUBLE_EQ(r.max, 1000);
  for (double& v : ramp) v += 47;  // 57..1037 → a step of 200: [0, 1200]
  r = autoRange(ramp, Scale::Linear);
  EXPECT_DOUBLE_EQ(r.min, 0);
  EXPECT_DOUBLE_EQ(r.max, 1200);

  // Log: 3 .. 700 widened to [2, 1000]; zeros, negatives and NaN ignored; an outlier beyond the 99th percentile too.
  std::vector<double> logRamp;
  for (int i = 0; i <= 1000; ++i) logRamp.push_back(3 * std::pow(700.0 / 3, i / 1000.0));
  logRamp.insert(logRamp.end(), {0.0, -5.0, std::nan(""), 1e9});
  r = autoRange(logRamp, Scale::Log);
  EXPECT_DOUBLE_EQ(r.min, 2);
  EXPECT_DOUBLE_EQ(r.max, 1000);
  // At most six decades below the maximum.
  r = autoRange({1e-12, 1e-12, 5, 100, 100}, Scale::Log);
  EXPECT_DOUBLE_EQ(r.max, 100);
  EXPECT_DOUBLE_EQ(r.min, 1e-4);

  // Fields without spread still get a valid range.
  r = autoRange({300, 300}, Scale::Linear);
  EXPECT_EQ(r.min, 0);
  EXPECT_EQ(r.max, 500);
  r = autoRange({1, 1}, Scale::Log);
  EXPECT_DOUBLE_EQ(r.min, 0.1);
  EXPECT_DOUBLE_EQ(r.max, 1);
  r = autoRange({0, 0}, Scale::Log);
  EXPECT_EQ(r.min, 1);
  EXPECT_EQ(r.max, 10);
}

TEST(FalseColor, Ticks) {
  EXPECT_EQ(ticks({0, 1000}, Scale::Linear), (std::vector<double>{0, 200, 400, 600, 800, 1000}));
  EXPECT_EQ(ticks({0, 1200}, Scale::Linear, 4), (std::vector<double>{0, 500, 1000, 1200}));  // ends always
  EXPECT_EQ(ticks({3, 97}, Scale::Linear), (std::vector<double>{3, 20, 40, 60, 80, 97}));
  EXPECT_EQ(ticks({1, 1000}, Scale::Log), (std::vector<double>{1, 10, 100, 1000}));
  EXPECT_EQ(ticks({0.2, 100}, Scale::Log), (std::vector<double>{0.2, 1, 10, 100}));
  const auto few = ticks({2, 50}, Scale::Log);
  ASSERT_EQ(few.size(), 5u);
  const double expected[] = {2, 5, 10, 20, 50};
  for (size_t i = 0; i < few.size(); ++i) EXPECT_NEAR(few[i], expected[i], 1e-12 * expected[i]);
  const auto many = ticks({1e-2, 1e6}, Scale::Log);  // 9 decades: every second one
  ASSERT_EQ(many.size(), 5u);
  EXPECT_NEAR(many[0], 0.01, 1e-15);
  EXPECT_NEAR(many[4], 1e6, 1e-6);
  EXPECT_EQ(label(0.5), "0.5");
  EXPECT_EQ(label(20000), "20000");
  EXPECT_EQ(label(0.30000000000000004), "0.3");
  EXPECT_EQ(label(1e6), "1e+06");
  EXPECT_EQ(label(0), "0");
}

// Known values land on known colours: the stops of the map at t = 0, 0.6 and 1, on a linear and
// a log range; values outside the range take the nearer end's colour; the legend bar agrees.
TEST(FalseColor, KnownValuesAtKnownPixels) {
  struct Case {
    Scale scale;
    Range range;
    std::vector<double> values;
    std::vector<std::array<uint8_t, 3>> colours;
  };
  const std::array<uint8_t, 3> bottom{48, 12, 80}, stop06{32, 158, 128}, top{250, 232, 60};
  const std::vector<Case> cases = {
      {Scale::Linear, {0, 100}, {0, 60, 100, -10, 150}, {bottom, stop06, top, bottom, top}},
      {Scale::Log, {1, 1000}, {1, std::pow(10.0, 1.8), 1000, 0, 0.5, 5000}, {bottom, stop06, top, bottom, bottom, top}},
  };
  for (const auto& c : cases) {
    Options o;
    o.scale = c.scale;
    o.autoRange = false;
    o.range = c.range;
    const Picture p = draw(row(c.values), o);
    const Layout& l = p.layout;
    EXPECT_EQ(l.scale, (320 + int(c.values.size()) - 1) / int(c.values.size()));
    EXPECT_EQ(p.width, l.mapWidth + 12 + 112);
    EXPECT_EQ(p.height, 220);
    const int barRows = l.barBottom - l.barTop;
    for (size_t i = 0; i < c.values.size(); ++i) {
      const std::string what = "value " + std::to_string(c.values[i]);
      const int x = int(i) * l.scale + l.scale / 2;
      expectColor(p, x, 0, c.colours[i], 0, what);
      // The legend bar's row for this value has the same colour (up to the row's quantisation).
      const double t = std::clamp(position(c.values[i], l.range, c.scale), 0.0, 1.0);
      const int y = l.barBottom - 1 - int(std::lround(t * (barRows - 1)));
      expectColor(p, l.barX + l.barWidth / 2, y, c.colours[i], 2, what + " (legend)");
    }
    // Below the field (the picture is taller than the one-row map): background.
    expectColor(p, 0, l.mapHeight + 1, kBackground, 0, "background");
  }
}

// The legend has text: ink in the label column beside each tick, and the units above the bar.
TEST(FalseColor, LegendHasLabelsAndUnits) {
  Options o;
  o.scale = Scale::Linear;
  const Picture p = draw(row({0, 250, 500, 1000}, "cd/m\xC2\xB2"), o);
  const Layout& l = p.layout;
  ASSERT_GE(l.ticks.size(), 3u);
  auto inkIn = [&](int x0, int y0, int x1, int y1) {
    int n = 0;
    for (int y = std::max(0, y0); y < std::min(p.height, y1); ++y)
      for (int x = x0; x < std::min(p.width, x1); ++x) n += p.at(x, y)[0] < 128;
    return n;
  };
  const int rows = l.barBottom - l.barTop;
  for (double t : {l.ticks.front(), l.ticks.back()}) {
    const int y = l.barBottom - 1 - int(std::lround(position(t, l.range, o.scale) * (rows - 1)));
    EXPECT_GT(inkIn(l.labelX, y - 8, p.width, y + 8), 15) << "label " << label(t);
  }
  EXPECT_GT(inkIn(l.barX, 0, l.barX + l.barWidth, l.barTop - 2), 20) << "units";
  // Between the bar and the labels there is nothing but the tick marks; right of the map, left of the bar, nothing.
  EXPECT_EQ(inkIn(l.mapWidth, 0, l.barX, p.height), 0);
}

// Iso-lines: on a ramp v = x, at the interior ticks 10, 20, 30 of [0, 40] (linear), the first
// pixel column at or above each level is ink, its neighbours are not; without contours none is.
TEST(FalseColor, ContoursWhereTheValueCrossesATick) {
  Field f{40, 20, {}, "lx"};
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) f.values.push_back(x);
  Options o;
  o.scale = Scale::Linear;
  o.autoRange = false;
  o.range = {0, 40};
  o.contours = 3;
  const Picture p = draw(f, o);
  const Layout& l = p.layout;
  ASSERT_EQ(l.contourLevels, (std::vector<double>{10, 20, 30}));
  ASSERT_EQ(l.scale, 8);
  for (int level : {10, 20, 30}) {
    const int x = level * l.scale;
    for (int y = 0; y < l.mapHeight; y += 7) {
      EXPECT_TRUE(isInk(p.at(x, y))) << "level " << level << " y " << y;
      EXPECT_FALSE(isInk(p.at(x - 1, y))) << "level " << level << " y " << y;
      EXPECT_FALSE(isInk(p.at(x + 1, y))) << "level " << level << " y " << y;
    }
  }
  o.contours = 0;
  const Picture plain = draw(f, o);
  for (int x = 0; x < plain.layout.mapWidth; ++x) EXPECT_FALSE(isInk(plain.at(x, 5))) << x;
}
