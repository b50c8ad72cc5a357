// Film accumulation and image output (OpenEXR and PNG through render/output/image_io.h).
#include "render/output/film.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "common/lights/photometry.h"
#include "common/util/atomic_file.h"
#include "common/util/error.h"
#include "common/util/memory_limit.h"
#include "render/output/image_io.h"

namespace firstshot {

void Film::requireFits(int width, int height, const std::string& file) {
  const std::string size = std::to_string(width) + "×" + std::to_string(height) + " pixels";
  if (width < 1 || height < 1) throw InputError(file, "image size", size + ": both must be at least 1");
  const double bytes = double(width) * double(height) * (4.0 * sizeof(Vec3d) + sizeof(uint32_t));
  requireMemory(bytes, file, "image size", size, "lower camera.resolution (--width, --height)");
}

Film::Film(int width, int height)
    : width_(width), height_(height) {
  requireFits(width, height);
  const size_t n = size_t(width) * size_t(height);
  s_.sum.assign(n, Vec3d(0.0));
  s_.sumSq.assign(n, Vec3d(0.0));
  s_.albedo.assign(n, Vec3d(0.0));
  s_.normal.assign(n, Vec3d(0.0));
  s_.count.assign(n, 0);
}

void Film::setSums(Sums sums) {
  const size_t n = size_t(width_) * size_t(height_);
  if (sums.sum.size() != n || sums.sumSq.size() != n || sums.albedo.size() != n || sums.normal.size() != n ||
      sums.count.size() != n)
    throw std::invalid_argument("Film::setSums: the sums are not width x height");
  s_ = std::move(sums);
}

Vec3d Film::mean(int x, int y) const {
  const size_t i = index(x, y);
  return s_.count[i] ? s_.sum[i] / double(s_.count[i]) : Vec3d(0.0);
}

Vec3d Film::variance(int x, int y) const {
  const size_t i = index(x, y);
  const double n = s_.count[i];
  if (n < 2) return Vec3d(0.0);
  const Vec3d m = s_.sum[i] / n;
  return glm::max(Vec3d(0.0), (s_.sumSq[i] - n * m * m) / (n - 1));
}

Vec3d Film::albedo(int x, int y) const {
  const size_t i = index(x, y);
  return s_.count[i] ? s_.albedo[i] / double(s_.count[i]) : Vec3d(0.0);
}

Vec3d Film::normal(int x, int y) const {
  const Vec3d n = s_.normal[index(x, y)];
  const double len = glm::length(n);
  return len > 0 ? n / len : Vec3d(0.0);
}

float linearToSrgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

std::vector<double> Film::luminance(double efficacy) const {
  std::vector<double> y(size_t(width_) * height_);
  for (int j = 0; j < height_; ++j)
    for (int i = 0; i < width_; ++i) y[index(i, j)] = efficacy * photometry::luminance(Color(mean(i, j)));
  return y;
}

void Film::write(const std::string& path, bool aov, float exposure, double efficacy) const {
  const std::string ext = lowerExtension(path);
  if (ext == ".exr")
    writeExr(path, aov, efficacy);
  else if (ext == ".png")
    writePng(path, exposure);
  else
    throw InputError(path, "", "unsupported image type \"" + ext + "\" (expected .exr or .png)");
}

void Film::writeExr(const std::string& path, bool aov, double efficacy) const {
  const int base = efficacy > 0 ? 1 : 3;  // Y in cd/m², or R, G, B radiance
  const int channels = base + (aov ? 6 : 0);
  std::vector<float> data(size_t(width_) * height_ * channels);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      float* p = &data[(size_t(y) * width_ + x) * channels];
      const Vec3d m = mean(x, y);
      if (base == 1)
        p[0] = float(efficacy * photometry::luminance(Color(m)));
      else
        p[0] = float(m.x), p[1] = float(m.y), p[2] = float(m.z);
      if (aov) {
        const Vec3d a = albedo(x, y), n = normal(x, y);
        p[base + 0] = float(a.x), p[base + 1] = float(a.y), p[base + 2] = float(a.z);
        p[base + 3] = float(n.x), p[base + 4] = float(n.y), p[base + 5] = float(n.z);
      }
    }
  std::vector<std::string> names = base == 1 ? std::vector<std::string>{"Y"} : std::vector<std::string>{"R", "G", "B"};
  if (aov) names.insert(names.end(), {"albedo.R", "albedo.G", "albedo.B", "normal.X", "normal.Y", "normal.Z"});
  image::writeExr(path, width_, height_, names, data.data());
}

void Film::writePng(const std::string& path, float exposure) const {
  const float scale = std::exp2(exposure);
  std::vector<unsigned char> data(size_t(width_) * height_ * 3);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const Vec3d m = mean(x, y);
      for (int c = 0; c < 3; ++c) {
        const float v = std::isfinite(m[c]) ? float(m[c]) * scale : 0.0f;
        data[(size_t(y) * width_ + x) * 3 + c] = static_cast<unsigned char>(std::lround(255.0f * linearToSrgb(v)));
      }
    }
  image::writePng(path, width_, height_, data.data());
}

std::vector<float> Film::read(const std::string& path, int& width, int& height, std::vector<std::string>& channelNames) {
  image::Image im = image::read(path);
  width = im.width, height = im.height;
  channelNames = std::move(im.channels);
  return std::move(im.data);
}

}  // namespace firstshot
