// False colour: drawing the picture (field, contours, legend with FreeType's text) and writing it.
#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "common/util/error.h"
#include "render/output/falsecolor.h"
#include "render/output/image_io.h"

namespace firstshot::falsecolor {

namespace {

constexpr const char* kFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
constexpr int kMargin = 12, kBarWidth = 22, kTickLength = 5, kFontSize = 13, kLegendWidth = 112, kMinHeight = 220;

void fill(Picture& p, int x0, int y0, int x1, int y1, const std::array<uint8_t, 3>& c) {
  for (int y = std::max(0, y0); y < std::min(p.height, y1); ++y)
    for (int x = std::max(0, x0); x < std::min(p.width, x1); ++x)
      std::copy(c.begin(), c.end(), &p.rgb[(size_t(y) * size_t(p.width) + size_t(x)) * 3]);
}

/// The code point starting at byte @p i of UTF-8 @p s; advances @p i past it (a stray byte counts as itself).
FT_ULong nextCodePoint(const std::string& s, size_t& i) {
  const auto b = [&](size_t k) { return FT_ULong(static_cast<unsigned char>(s[k])); };
  const FT_ULong c = b(i);
  const int extra = c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : c >= 0xC0 ? 1 : 0;
  if (extra == 0 || i + size_t(extra) >= s.size()) {
    ++i;
    return c;
  }
  FT_ULong cp = c & (0x3Fu >> extra);
  for (int k = 1; k <= extra; ++k) cp = (cp << 6) | (b(i + size_t(k)) & 0x3Fu);
  i += size_t(extra) + 1;
  return cp;
}

/// The legend's typeface (FreeType), opened once per picture.
class Font {
 public:
  Font() {
    if (FT_Init_FreeType(&lib_) != 0) throw std::runtime_error("--falsecolor: cannot start FreeType");
    if (FT_New_Face(lib_, kFontPath, 0, &face_) != 0) {
      FT_Done_FreeType(lib_);
      throw std::runtime_error("--falsecolor: cannot open the legend's font " + std::string(kFontPath));
    }
  }
  ~Font() {
    FT_Done_Face(face_);
    FT_Done_FreeType(lib_);
  }
  Font(const Font&) = delete;
  Font& operator=(const Font&) = delete;

  /// Draws @p s (UTF-8) into @p p at @p size pixels with its baseline's left end at (x, y), blending the ink
  /// over what is there by the glyphs' coverage; returns the end of its advance.
  int draw(Picture& p, int x, int y, const std::string& s, int size) {
    FT_Set_Pixel_Sizes(face_, 0, FT_UInt(size));
    for (size_t i = 0; i < s.size();) {
      if (FT_Load_Char(face_, nextCodePoint(s, i), FT_LOAD_RENDER) != 0) continue;
      const FT_GlyphSlot g = face_->glyph;
      const FT_Bitmap& bm = g->bitmap;
      for (unsigned r = 0; r < bm.rows; ++r)
        for (unsigned c = 0; c < bm.width; ++c) {
          const int px = x + g->bitmap_left + int(c), py = y - g->bitmap_top + int(r);
          if (px < 0 || py < 0 || px >= p.width || py >= p.height) continue;
          const float a = float(bm.buffer[int(r) * bm.pitch + int(c)]) / 255.0f;
          uint8_t* dst = &p.rgb[(size_t(py) * size_t(p.width) + size_t(px)) * 3];
          for (int k = 0; k < 3; ++k) dst[k] = uint8_t(std::lround(float(kInk[k]) * a + float(dst[k]) * (1.0f - a)));
        }
      x += int(g->advance.x >> 6);
    }
    return x;
  }

 private:
  FT_Library lib_ = nullptr;
  FT_Face face_ = nullptr;
};

/// Draws @p units, with "²" as a smaller, raised "2".
void unitsText(Font& font, Picture& p, int x, int y, const std::string& units) {
  auto text = [&font](Picture& q, int tx, int ty, const std::string& s, int size) { return font.draw(q, tx, ty, s, size); };
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
  Font font;
  unitsText(font, p, l.barX, kMargin + 10, field.units);
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
    font.draw(p, l.labelX, y + kFontSize / 2 - 1, label(t), kFontSize);
    labelled.push_back(y);
  }
  return p;
}

void writePng(const std::string& path, const Picture& picture) {
  image::writePng(path, picture.width, picture.height, picture.rgb.data());
}

}  // namespace firstshot::falsecolor
