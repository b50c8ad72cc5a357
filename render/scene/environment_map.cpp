#include "render/scene/environment_map.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include "common/lights/photometry.h"
#include "common/materials/texture.h"
#include "common/util/error.h"
#include "render/output/image_io.h"

namespace firstshot {

EnvironmentMap::EnvironmentMap(std::vector<Color> texels, int width, int height, float scale, double rotationDeg)
    : texels_(std::move(texels)), width_(width), height_(height) {
  const double r = rotationDeg * kPi / 180.0;
  cosRot_ = std::cos(r);
  sinRot_ = std::sin(r);
  std::vector<double> weights(texels_.size());
  for (int j = 0; j < height_; ++j) {
    const double sinTheta = std::sin(kPi * (j + 0.5) / height_);
    for (int i = 0; i < width_; ++i) {
      Color& c = texels_[size_t(j) * width_ + i];
      c *= scale;
      weights[size_t(j) * width_ + i] = std::max(photometry::luminance(c), 0.0) * sinTheta;
    }
  }
  distribution_ = Distribution2D(weights, size_t(width_), size_t(height_));
}

namespace {
/// Whether @p path starts with the PNG or OpenEXR signature (read by render/output/image_io.h; anything else
/// goes through OpenImageIO).
bool pngOrExr(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char b[4] = {0, 0, 0, 0};
  in.read(reinterpret_cast<char*>(b), 4);
  return (b[0] == 0x89 && b[1] == 'P' && b[2] == 'N' && b[3] == 'G') ||
         (b[0] == 0x76 && b[1] == 0x2f && b[2] == 0x31 && b[3] == 0x01);
}

/// Radiance .hdr, float TIFF, PFM and whatever else OpenImageIO reads (common/materials/texture.h's module): float data as
/// stored, integer data / its maximum (as a PNG's bytes / 255), grey as RGB.
image::Image readThroughOiio(const std::string& path) {
  const TexelImage t = readTexelImage(path, false);
  image::Image img;
  img.width = t.width;
  img.height = t.height;
  img.channels = {"R", "G", "B"};
  img.data.reserve(t.texels.size() * 3);
  for (const Color& c : t.texels) img.data.insert(img.data.end(), {c.x, c.y, c.z});
  return img;
}
}  // namespace

EnvironmentMap EnvironmentMap::load(const std::string& path, float scale, double rotationDeg) {
  if (!std::ifstream(path, std::ios::binary)) throw InputError(path, "", "cannot open image");
  const image::Image img = pngOrExr(path) ? image::read(path) : readThroughOiio(path);
  auto channel = [&](const char* name) {
    const auto it = std::find(img.channels.begin(), img.channels.end(), name);
    if (it == img.channels.end()) throw InputError(path, "", std::string("no ") + name + " channel");
    return size_t(it - img.channels.begin());
  };
  const size_t r = channel("R"), g = channel("G"), b = channel("B"), n = img.channels.size();
  if (img.width < 2 || img.height < 1) throw InputError(path, "", "an environment map needs at least 2 × 1 texels");
  std::vector<Color> texels(size_t(img.width) * img.height);
  for (size_t k = 0; k < texels.size(); ++k) {
    texels[k] = Color(img.data[k * n + r], img.data[k * n + g], img.data[k * n + b]);
    if (!(texels[k].x >= 0 && texels[k].y >= 0 && texels[k].z >= 0 && std::isfinite(texels[k].x + texels[k].y + texels[k].z)))
      throw InputError(path, "texel " + std::to_string(k % img.width) + "," + std::to_string(k / img.width),
                       "negative or non-finite radiance");
  }
  return EnvironmentMap(std::move(texels), img.width, img.height, scale, rotationDeg);
}

Vec2d EnvironmentMap::toUv(const Vec3& dir) const {
  // Rotate by −rotation about y: x' = cos·x − sin·z... (the inverse of fromUv's rotation).
  const double x = cosRot_ * dir.x - sinRot_ * dir.z, z = sinRot_ * dir.x + cosRot_ * dir.z;
  const double theta = std::acos(std::clamp(double(dir.y), -1.0, 1.0)), phi = std::atan2(x, -z);
  double u = 0.5 + phi / (2.0 * kPi);
  u -= std::floor(u);
  return {std::min(u, std::nextafter(1.0, 0.0)), std::min(theta / kPi, std::nextafter(1.0, 0.0))};
}

Vec3 EnvironmentMap::fromUv(const Vec2d& uv) const {
  const double phi = (uv.x - 0.5) * 2.0 * kPi, theta = uv.y * kPi;
  const double s = std::sin(theta), x = s * std::sin(phi), z = -s * std::cos(phi);
  return Vec3(float(cosRot_ * x + sinRot_ * z), float(std::cos(theta)), float(-sinRot_ * x + cosRot_ * z));
}

const Color& EnvironmentMap::texel(const Vec2d& uv) const {
  const int i = std::min(int(uv.x * width_), width_ - 1), j = std::min(int(uv.y * height_), height_ - 1);
  return texels_[size_t(j) * width_ + i];
}

Color EnvironmentMap::radiance(const Vec3& dir) const { return texel(toUv(dir)); }

Color EnvironmentMap::sample(const Vec2& u, Vec3& dir, float& pdf) const {
  double pdfUv = 0;
  const Vec2d uv = distribution_.sample(Vec2d(u.x, u.y), pdfUv);
  dir = glm::normalize(fromUv(uv));
  const double sinTheta = std::sin(uv.y * kPi);
  pdf = sinTheta > 0 && pdfUv > 0 ? float(pdfUv / (2.0 * kPi * kPi * sinTheta)) : 0.0f;
  return pdf > 0 ? texel(uv) : Color(0.0f);
}

float EnvironmentMap::pdf(const Vec3& dir) const {
  const Vec2d uv = toUv(dir);
  const double sinTheta = std::sin(uv.y * kPi);
  return sinTheta > 0 ? float(distribution_.pdf(uv) / (2.0 * kPi * kPi * sinTheta)) : 0.0f;
}

}  // namespace firstshot
