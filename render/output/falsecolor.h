#pragma once
/// @file falsecolor.h
/// False-colour pictures of a scalar field: the luminance of a rendered image (cd/m²) or
/// the illuminance of a sensor grid (lx), mapped through a perceptually ordered colour map on a log
/// or linear scale, with a legend bar whose ticks are labelled in the field's units, and optional
/// iso-lines at the ticks (docs/cli.md, "Photometric outputs"; docs/photometry.md).
///
/// The picture is the field (scaled up by a whole factor when small, nearest neighbour, so a grid's
/// cells stay visible) at the top left, and to its right the legend: the units, then a vertical bar
/// from the range's minimum (bottom) to its maximum (top) with ticks and labels. Values outside the
/// range take the colour of its nearer end; on a log scale, values ≤ 0 take the minimum's colour.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/util/math.h"

namespace firstshot::falsecolor {

enum class Scale { Log, Linear };

/// A closed range of field values (in the field's units); max > min, and min > 0 on a log scale.
struct Range {
  double min = 0, max = 1;
};

/// The colour map at @p t ∈ [0, 1] (clamped), as 8-bit sRGB. Its relative luminance (Rec. 709
/// weights of the linearised sRGB) increases strictly with t, from a dark violet through blue,
/// teal and green to a light yellow, so the order of values survives printing in grey.
std::array<uint8_t, 3> colorMap(double t);

/// Position of @p value in @p range on @p scale: 0 at min, 1 at max, not clamped (−∞ for v ≤ 0 on a
/// log scale).
double position(double value, const Range& range, Scale scale);

/// The automatic range of @p values: their 1st and 99th percentiles (over the positive values on a
/// log scale), widened to nice numbers: on a log scale to 1, 2 or 5 × 10^k and at most 6 decades
/// (the minimum is raised to max·10⁻⁶); on a linear scale to multiples of a 1, 2 or 5 × 10^k step
/// of about a fifth of the span. Non-finite values are ignored. A field without spread (or, on a
/// log scale, without positive values) gets a range around its value ([1, 10] for nothing usable).
Range autoRange(const std::vector<double>& values, Scale scale);

/// The largest of 1, 2, 5 × 10^k that is ≤ @p x (@p up false) or the smallest that is ≥ @p x (@p up
/// true); @p x > 0.
double niceNumber(double x, bool up);

/// Tick values in @p range, ascending, about @p count of them: its two ends, and in between on a
/// linear scale the multiples of a nice step of about span/(count − 1), on a log scale the powers
/// of ten (every n-th one when there are more than @p count), with 2 and 5 × 10^k added when there
/// are fewer than three.
std::vector<double> ticks(const Range& range, Scale scale, int count = 6);

/// Label of a tick value: plain decimals from 0.001 to 99999 ("0.005", "0.5", "200", "20000"),
/// otherwise two significant digits with an exponent ("1e+05", "2.5e-04").
std::string label(double value);

/// A scalar field on a width × height raster, row-major from the top left.
struct Field {
  int width = 0, height = 0;
  std::vector<double> values;
  std::string units;  ///< legend title, e.g. "cd/m²" or "lx"
};

struct Options {
  Scale scale = Scale::Log;
  bool autoRange = true;
  Range range;        ///< used when autoRange is false
  int contours = 0;   ///< > 0: iso-lines at about this many nice levels (the legend's ticks)
  int minSide = 320;  ///< the field is scaled up by a whole factor until its longer side reaches this
};

/// Where the parts of a picture are (pixels, from the top left), for tests and documentation.
struct Layout {
  int scale = 1;                         ///< field pixel (x, y) covers [x·scale, (x+1)·scale) × ...
  int mapWidth = 0, mapHeight = 0;       ///< the scaled field at (0, 0)
  int barX = 0, barWidth = 0;            ///< legend bar columns
  int barTop = 0, barBottom = 0;         ///< rows [barTop, barBottom): top = max, bottom − 1 = min
  int labelX = 0;                        ///< tick labels start at this column
  Range range;                           ///< the range used
  std::vector<double> ticks;             ///< tick values (labelled unless too close to the ends' labels or each other)
  std::vector<double> contourLevels;     ///< iso-line values (ticks strictly inside the range)
};

/// An 8-bit sRGB picture, row-major, 3 bytes a pixel.
struct Picture {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  Layout layout;
  const uint8_t* at(int x, int y) const { return &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3]; }
};

/// Background (white), text, tick and contour colour (black).
inline constexpr std::array<uint8_t, 3> kBackground{255, 255, 255}, kInk{0, 0, 0};

/// Draws the picture of @p field.
/// @throws std::runtime_error if the labels cannot be drawn (no font; see requireFont()).
Picture draw(const Field& field, const Options& options);

/// Writes @p picture as a PNG, atomically (temporary file, then rename).
/// @throws std::runtime_error on I/O failure.
void writePng(const std::string& path, const Picture& picture);

/// The font the labels are drawn with (DejaVu Sans, Debian package fonts-dejavu-core).
/// @throws InputError naming the option @p option if it is not installed.
std::string requireFont(const std::string& option = "--falsecolor");

}  // namespace firstshot::falsecolor
