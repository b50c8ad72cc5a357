// PNG and JPEG texture images through libpng and libjpeg, and their means (common/materials/texture_image.h).
#include "common/materials/texture_image.h"

#include <png.h>
// jpeglib.h needs size_t and FILE declared first.
#include <cstdio>
#include <jpeglib.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstring>
#include <string>

#include "common/color/spectrum_rgb.h"
#include "common/util/error.h"

namespace firstshot {
namespace {

constexpr uint64_t kMaxTexels = uint64_t(1) << 28;  ///< 1 GiB of RGBA: larger images are refused

[[noreturn]] void fail(const std::string& why) { throw InputError("", "", why); }

void checkSize(uint64_t width, uint64_t height, const char* format) {
  if (width == 0 || height == 0 || width * height > kMaxTexels)
    fail(std::string(format) + " of unsupported size " + std::to_string(width) + " x " + std::to_string(height));
}

/// libpng's error callback: keeps the message and returns to decodePng's setjmp.
struct PngState {
  std::string_view bytes;
  size_t at = 0;
  char message[256] = "";
};
void pngError(png_structp png, png_const_charp message) {
  auto* state = static_cast<PngState*>(png_get_error_ptr(png));
  std::snprintf(state->message, sizeof state->message, "%s", message);
  png_longjmp(png, 1);
}
void pngWarning(png_structp, png_const_charp) {}
void pngRead(png_structp png, png_bytep out, png_size_t n) {
  auto* state = static_cast<PngState*>(png_get_io_ptr(png));
  if (n > state->bytes.size() - state->at) png_error(png, "the data ends early");
  std::memcpy(out, state->bytes.data() + state->at, n);
  state->at += n;
}

/// Decodes a PNG to 8-bit RGBA. Only trivially destructible objects live between setjmp and longjmp here.
void decodePng(std::string_view bytes, TextureImage& image) {
  PngState state{bytes};
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &state, pngError, pngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    fail("PNG: out of memory");
  }
  std::vector<png_bytep> rows;
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    fail(std::string("PNG: ") + state.message);
  }
  png_set_read_fn(png, &state, pngRead);
  png_read_info(png, info);
  const png_uint_32 width = png_get_image_width(png, info), height = png_get_image_height(png, info);
  const int colorType = png_get_color_type(png, info);
  checkSize(width, height, "PNG");
  png_set_expand(png);  // palette -> RGB, grey below 8 bits -> 8, tRNS -> alpha
  png_set_strip_16(png);
  if (!(colorType & PNG_COLOR_MASK_ALPHA) && !png_get_valid(png, info, PNG_INFO_tRNS))
    png_set_filler(png, 0xff, PNG_FILLER_AFTER);
  if (!(colorType & PNG_COLOR_MASK_COLOR)) png_set_gray_to_rgb(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  if (png_get_rowbytes(png, info) != size_t(width) * 4) png_error(png, "unexpected row layout");
  image.width = int(width), image.height = int(height);
  image.rgba.resize(size_t(width) * height * 4);
  rows.resize(height);
  for (png_uint_32 y = 0; y < height; ++y) rows[y] = image.rgba.data() + size_t(y) * width * 4;
  png_read_image(png, rows.data());
  png_destroy_read_struct(&png, &info, nullptr);
}

/// libjpeg's error manager: keeps the message and returns to decodeJpeg's setjmp; warnings are silent.
struct JpegError {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = "";
};
void jpegError(j_common_ptr info) {
  auto* error = reinterpret_cast<JpegError*>(info->err);
  info->err->format_message(info, error->message);
  std::longjmp(error->jump, 1);
}
void jpegMessage(j_common_ptr, int) {}

/// Decodes a JPEG to 8-bit RGBA (alpha 1). Only trivially destructible objects live between setjmp and longjmp.
void decodeJpeg(std::string_view bytes, TextureImage& image) {
  jpeg_decompress_struct info;
  JpegError error;
  std::vector<uint8_t> row;
  info.err = jpeg_std_error(&error.manager);
  error.manager.error_exit = jpegError;
  error.manager.emit_message = jpegMessage;
  if (setjmp(error.jump)) {
    jpeg_destroy_decompress(&info);
    fail(std::string("JPEG: ") + error.message);
  }
  jpeg_create_decompress(&info);
  jpeg_mem_src(&info, reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&info, TRUE);
  if (info.jpeg_color_space == JCS_CMYK || info.jpeg_color_space == JCS_YCCK) {
    jpeg_destroy_decompress(&info);
    fail("JPEG: CMYK images are not supported");
  }
  info.out_color_space = JCS_RGB;
  if (info.image_width == 0 || info.image_height == 0 || uint64_t(info.image_width) * info.image_height > kMaxTexels) {
    const std::string size = std::to_string(info.image_width) + " x " + std::to_string(info.image_height);
    jpeg_destroy_decompress(&info);
    fail("JPEG of unsupported size " + size);
  }
  jpeg_start_decompress(&info);
  image.width = int(info.output_width), image.height = int(info.output_height);
  image.rgba.assign(size_t(image.width) * image.height * 4, 0xff);
  row.resize(size_t(image.width) * 3);
  while (info.output_scanline < info.output_height) {
    const size_t y = info.output_scanline;
    JSAMPROW rowPointer = row.data();
    jpeg_read_scanlines(&info, &rowPointer, 1);
    for (size_t x = 0; x < size_t(image.width); ++x)
      std::memcpy(&image.rgba[(y * image.width + x) * 4], &row[x * 3], 3);
  }
  jpeg_finish_decompress(&info);
  jpeg_destroy_decompress(&info);
}

/// The whole-tile shift that brings @p lo into the first period of @p wrap (none for clamping).
double tileShift(double lo, TextureWrap wrap) {
  if (wrap == TextureWrap::ClampToEdge) return 0;
  const double period = wrap == TextureWrap::MirroredRepeat ? 2.0 : 1.0;
  return period * std::floor(lo / period);
}

double cross(const Vec2d& a, const Vec2d& b) { return a.x * b.y - a.y * b.x; }
int64_t toIndex(double x) { return int64_t(std::clamp(x, -1e12, 1e12)); }

}  // namespace

int64_t foldTexelIndex(int64_t i, int64_t n, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::ClampToEdge: return std::clamp<int64_t>(i, 0, n - 1);
    case TextureWrap::MirroredRepeat: {
      const int64_t m = ((i % (2 * n)) + 2 * n) % (2 * n);
      return m < n ? m : 2 * n - 1 - m;
    }
    default: return ((i % n) + n) % n;
  }
}

float srgbDecode(double c) { return float(srgbToLinear(c)); }

float srgbToLinear(uint8_t v) {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = srgbDecode(i / 255.0);
    return t;
  }();
  return table[v];
}

std::array<float, 4> TextureImage::texel(int x, int y) const {
  const uint8_t* p = &rgba[(size_t(y) * width + x) * 4];
  std::array<float, 4> t;
  for (int c = 0; c < 4; ++c) t[c] = srgb && c < 3 ? srgbToLinear(p[c]) : p[c] / 255.0f;
  return t;
}

std::array<float, 4> TextureImage::mean() const {
  std::array<double, 4> sum{};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::array<float, 4> t = texel(x, y);
      for (int c = 0; c < 4; ++c) sum[c] += t[c];
    }
  std::array<float, 4> m{};
  for (int c = 0; c < 4; ++c) m[c] = float(sum[c] / (double(width) * height));
  return m;
}

TextureImage decodeTextureImage(std::string_view bytes, bool srgb) {
  TextureImage image;
  image.srgb = srgb;
  if (bytes.size() >= 8 && png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) == 0)
    decodePng(bytes, image);
  else if (bytes.size() >= 3 && std::memcmp(bytes.data(), "\xff\xd8\xff", 3) == 0)
    decodeJpeg(bytes, image);
  else
    fail("not a PNG or JPEG image");
  return image;
}

std::array<float, 4> meanOverTriangles(const TextureImage& image, const std::vector<UvTriangle>& triangles,
                                       TextureWrap wrapU, TextureWrap wrapV, bool* wholeImage, double maxTexels) {
  const Vec2d size(image.width, image.height);
  // Each triangle in texel space (centres at integers), shifted by whole tiles next to the first one.
  std::vector<std::array<Vec2d, 3>> texelSpace;
  std::vector<double> weights;
  double texels = 0, totalWeight = 0;
  for (const UvTriangle& t : triangles) {
    const Vec2d lo = glm::min(t.uv[0], glm::min(t.uv[1], t.uv[2])), hi = glm::max(t.uv[0], glm::max(t.uv[1], t.uv[2]));
    if (!isFinite(Vec3d(lo, 0)) || !isFinite(Vec3d(hi, 0)) || !(t.weight > 0)) continue;
    const Vec2d shift(tileShift(lo.x, wrapU), tileShift(lo.y, wrapV));
    std::array<Vec2d, 3> p;
    for (int k = 0; k < 3; ++k) p[k] = (t.uv[k] - shift) * size - 0.5;
    texels += ((hi.x - lo.x) * size.x + 1) * ((hi.y - lo.y) * size.y + 1);
    texelSpace.push_back(p);
    weights.push_back(t.weight);
    totalWeight += t.weight;
  }
  if (wholeImage) *wholeImage = texels > maxTexels || !(totalWeight > 0);
  if (texels > maxTexels || !(totalWeight > 0)) return image.mean();
  std::array<double, 4> sum{};
  for (size_t k = 0; k < texelSpace.size(); ++k) {
    const auto& [a, b, c] = texelSpace[k];
    const double area = cross(b - a, c - a), sign = area < 0 ? -1 : 1;
    std::array<double, 4> triangleSum{};
    size_t n = 0;
    auto add = [&](int64_t x, int64_t y) {
      const std::array<float, 4> t =
          image.texel(int(foldTexelIndex(x, image.width, wrapU)), int(foldTexelIndex(y, image.height, wrapV)));
      for (int ch = 0; ch < 4; ++ch) triangleSum[ch] += t[ch];
      ++n;
    };
    const Vec2d lo = glm::min(a, glm::min(b, c)), hi = glm::max(a, glm::max(b, c));
    for (int64_t y = toIndex(std::ceil(lo.y)); area != 0 && y <= toIndex(std::floor(hi.y)); ++y)
      for (int64_t x = toIndex(std::ceil(lo.x)); x <= toIndex(std::floor(hi.x)); ++x) {
        const Vec2d q{double(x), double(y)};
        if (sign * cross(b - a, q - a) >= 0 && sign * cross(c - b, q - b) >= 0 && sign * cross(a - c, q - c) >= 0)
          add(x, y);
      }
    if (n == 0) {  // no texel centre inside: the texel under the centroid
      const Vec2d centroid = (a + b + c) / 3.0;
      add(toIndex(std::floor(centroid.x + 0.5)), toIndex(std::floor(centroid.y + 0.5)));
    }
    for (int ch = 0; ch < 4; ++ch) sum[ch] += weights[k] * triangleSum[ch] / double(n);
  }
  std::array<float, 4> mean{};
  for (int ch = 0; ch < 4; ++ch) mean[ch] = float(sum[ch] / totalWeight);
  return mean;
}

}  // namespace firstshot
