// False colour: drawing the picture (field, contours, legend with OpenImageIO's text) and writing it.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "common/error.h"
#include "render/falsecolor.h"
#include "render/film.h"

namespace fs::falsecolor {

namespace {

constexpr const char* kFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
constexpr int kMargin = 12, kBarWidth = 22, kTickLength = 5, kFontSize = 13, kLegendWidth = 112, kMinHeight = 220;

void fill(Picture& p, int x0, int y0, int x1, int y1, const std::array<uint8_t, 3>& c) {
  for (int y = std::max(0, y0); y < std::min(p.height, y1); ++y)
    for (int x = std::max(0, x0); x < std::min(p.width, x1); ++x)
      std::copy(c.begin(), c.end(), &p.rgb[(size_t(y) * size_t(p.width) + size_t(x)) * 3]);
}

/// Draws @p text into @p p with its baseline's left end at (x, y); returns the end of its advance.
int text(Picture& p, int x, int y, const std::string& s, int size) {
  OIIO::ImageSpec spec(p.width, p.height, 3, OIIO::TypeDesc::UINT8);
  OIIO::ImageBuf buf(spec, p.rgb.data());  // wraps the picture's pixels
  const float ink[3] = {kInk[0] / 255.0f, kInk[1] / 255.0f, kInk[2] / 255.0f};
  if (!OIIO::ImageBufAlgo::render_text(buf, x, y, s, size, kFontPath, ink))
    throw std::runtime_error("--falsecolor: cannot draw the legend's text with " + std::string(kFontPath) + " (" +
                             buf.geterror() + ")");
  const OIIO::ROI r = OIIO::ImageBufAlgo::text_size(s, size, kFontPath);
  return x + (r.defined() ? r.xend : int(s.size()) * size / 2);
}

/// Draws @p units, with "²" (which OpenImageIO 2.4 does not decode) as a smaller, raised "2".
void unitsText(Picture& p, int x, int y, const std::string& units) {
  const std::string sup = "\xC2\xB2";
  const auto at = units.find(sup);
  if (at == std::string::npos) {
    text(p, x, y, units, kFontSize + 1);
    return;
  }
  const int end = text(p, x, y, units.substr(0, at), kFontSize + 1);
  const int end2 = text(p, end + 1, y - 6, "2", kFontSize - 3);
  if (at + sup.size() < units.size()) text(p, end2 + 1, y, units.substr(at + sup.size()), kFontSize + 1);
}

}  // namespace

std::string requireFont(const std::string& option) {
  if (!std::filesystem::exists(kFontPath))
    throw InputError(kFontPath, option, "the legend's font is missing (install the Debian package fonts-dejavu-core)");
  return kFontPath;
}

Picture draw(const Field& field, const Options& options) {
  if (field.width < 1 || field.height < 1 || field.values.size() != size_t(field.width) * size_t(field.height))
    throw std::invalid_argument("falsecolor::draw: the field's values are not width x height");
  Picture p;
  Layout& l = p.layout;
  l.range = options.autoRange ? autoRange(field.values, options.scale) : options.range;
  l.ticks = ticks(l.range, options.scale, options.contours > 0 ? options.contours + 2 : 6);
  if (options.contours > 0)
    for (double t : l.ticks)
      if (t > l.range.min && t < l.range.max) l.contourLevels.push_back(t);  // the ends are exact ticks
  const int longer = std::max(field.width, field.height);
  l.scale = std::max(1, (options.minSide + longer - 1) / longer);
  l.mapWidth = field.width * l.scale, l.mapHeight = field.height * l.scale;
  p.width = l.mapWidth + kMargin + kLegendWidth;
  p.height = std::max(l.mapHeight, kMinHeight);
  p.rgb.assign(size_t(p.width) * size_t(p.height) * 3, 0);
  fill(p, 0, 0, p.width, p.height, kBackground);

  // The field, and the iso-lines: a pixel at or above a level with a 4-neighbour below it.
  auto value = [&](int x, int y) { return field.values[size_t(y / l.scale) * size_t(field.width) + size_t(x / l.scale)]; };
  for (int y = 0; y < l.mapHeight; ++y)
    for (int x = 0; x < l.mapWidth; ++x) {
      const double v = value(x, y);
      bool onLine = false;
      for (double c : l.contourLevels) {
        if (!(v >= c)) continue;
        for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
          const int qx = x + dx, qy = y + dy;
          if (qx >= 0 && qy >= 0 && qx < l.mapWidth && qy < l.mapHeight && value(qx, qy) < c) onLine = true;
        }
      }
      fill(p, x, y, x + 1, y + 1, onLine ? kInk : colorMap(position(v, l.range, options.scale)));
    }

  // The legend: units, bar (max at the top), ticks and labels.
  l.barX = l.mapWidth + kMargin, l.barWidth = kBarWidth;
  l.barTop = kMargin + 22, l.barBottom = p.height - kMargin;
  l.labelX = l.barX + kBarWidth + kTickLength + 3;
  unitsText(p, l.barX, kMargin + 10, field.units);
  const int rows = l.barBottom - l.barTop;
  for (int y = l.barTop; y < l.barBottom; ++y)
    fill(p, l.barX, y, l.barX + kBarWidth, y + 1, colorMap(double(l.barBottom - 1 - y) / double(rows - 1)));
  std::vector<int> labelled;  // rows of the labels drawn: the ends first, then ticks that do not overlap them
  std::vector<double> order = l.ticks;
  if (order.size() > 1) std::swap(order[1], order.back());  // min, max, then the rest
  for (double t : order) {
    const int y = l.barBottom - 1 - int(std::lround(position(t, l.range, options.scale) * double(rows - 1)));
    fill(p, l.barX + kBarWidth, y, l.barX + kBarWidth + kTickLength, y + 1, kInk);
    if (options.contours > 0 && t > l.range.min && t < l.range.max) fill(p, l.barX, y, l.barX + kBarWidth, y + 1, kInk);
    if (std::any_of(labelled.begin(), labelled.end(), [y](int z) { return std::abs(z - y) < kFontSize + 1; })) continue;
    text(p, l.labelX, y + kFontSize / 2 - 1, label(t), kFontSize);
    labelled.push_back(y);
  }
  return p;
}

void writePng(const std::string& path, const Picture& picture) {
  writeRgb8(path, picture.width, picture.height, picture.rgb.data());
}

}  // namespace fs::falsecolor
