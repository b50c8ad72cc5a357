// Textures: reading through the OpenImageIO module, bilinear and nearest lookups (common/materials/texture.h).
#include "common/materials/texture.h"

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <mutex>

#include "common/oiio/read_image.h"
#include "common/util/error.h"
#include "common/util/hash.h"

namespace firstshot {
namespace {

/// The module's function, loaded once: beside the executable first, then where the build put it.
ReadImageFn readImageFunction() {
  static std::once_flag once;
  static ReadImageFn fn = nullptr;
  static std::string why;
  std::call_once(once, [] {
    std::vector<std::string> candidates;
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) candidates.push_back((exe.parent_path() / "libfirstshot_oiio.so").string());
#ifdef FIRSTSHOT_OIIO_MODULE
    candidates.push_back(FIRSTSHOT_OIIO_MODULE);
#endif
    for (const std::string& path : candidates) {
      if (!std::filesystem::exists(path, ec)) continue;
      void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!handle) {
        why = dlerror();
        continue;
      }
      fn = reinterpret_cast<ReadImageFn>(dlsym(handle, kReadImageSymbol));
      if (fn) return;
      why = path + " has no " + kReadImageSymbol;
    }
    if (why.empty()) why = "libfirstshot_oiio.so not found beside the executable";
  });
  if (!fn) throw InputError("", "", "cannot read textures: " + why);
  return fn;
}

/// The texel image of a module image: grey → RGB, integer colour sRGB-decoded when @p srgb.
TexelImage toTexels(const ModuleImage& m, const std::string& name, bool srgb) {
  if (!m.error.empty()) throw InputError("", "", "cannot read image " + name + ": " + m.error);
  std::vector<Color> texels(size_t(m.width) * size_t(m.height));
  const size_t n = size_t(m.channels);
  // An 8-bit image has at most 256 values per channel: each decoded once (its first float as the key, so the result
  // is srgbDecode's whatever the reader's conversion), not a pow per texel (the classroom's 3 textures: 0.1 s).
  std::array<float, 256> key, decoded;
  key.fill(-1.0f);
  const auto decode = [&](float v) {
    const double x = std::clamp(double(v), 0.0, 1.0);
    const size_t k = size_t(std::lround(x * 255.0));
    if (key[k] == v) return decoded[k];
    const float d = srgbDecode(x);
    if (key[k] < 0.0f) key[k] = v, decoded[k] = d;
    return d;
  };
  for (size_t i = 0; i < texels.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const float v = m.pixels[i * n + (n >= 3 ? size_t(c) : 0)];
      texels[i][c] = m.integer && srgb ? decode(v) : v;
    }
  TexelImage im = makeTexelImage(m.width, m.height, std::move(texels), name);
  if (n == 2 || n == 4) {  // grey + alpha, RGBA: alpha is always linear (not in im.hash: hashScene adds it for cut-outs)
    im.alpha.resize(im.texels.size());
    for (size_t i = 0; i < im.alpha.size(); ++i) im.alpha[i] = std::clamp(m.pixels[i * n + n - 1], 0.0f, 1.0f);
  }
  return im;
}

/// A texel index from a scaled coordinate, clamped far outside any image (where folding is exact) before the cast.
int64_t texelIndex(double x) { return int64_t(std::clamp(std::floor(x), -1e15, 1e15)); }

/// The lookup of a texture at @p uvIn by its filter: @p fetch(x, y) gives texel (x, y)'s value (Color or float).
template <typename Fetch>
auto filtered(const Texture& t, const Vec2& uvIn, const Fetch& fetch) {
  const TexelImage& im = *t.image;
  const Vec2 uv = t.transform.apply(uvIn);
  if (t.filter == TextureFilter::Nearest)  // texel (i, j) covers u ∈ [i/w, (i+1)/w), v ∈ [j/h, (j+1)/h)
    return fetch(int(foldTexelIndex(texelIndex(double(uv.x) * im.width), im.width, t.wrapU)),
                 int(foldTexelIndex(texelIndex(double(uv.y) * im.height), im.height, t.wrapV)));
  // Texel centres at (i + ½)/w: the lookup is exact there and linear between them.
  const double x = double(uv.x) * im.width - 0.5, y = double(uv.y) * im.height - 0.5;
  const int64_t ix = texelIndex(x), iy = texelIndex(y);
  const float tx = float(x - std::floor(x)), ty = float(y - std::floor(y));
  const int x0 = int(foldTexelIndex(ix, im.width, t.wrapU)), x1 = int(foldTexelIndex(ix + 1, im.width, t.wrapU));
  const int y0 = int(foldTexelIndex(iy, im.height, t.wrapV)), y1 = int(foldTexelIndex(iy + 1, im.height, t.wrapV));
  const auto top = fetch(x0, y0) * (1.0f - tx) + fetch(x1, y0) * tx;
  const auto bottom = fetch(x0, y1) * (1.0f - tx) + fetch(x1, y1) * tx;
  return top * (1.0f - ty) + bottom * ty;
}

}  // namespace

Vec2 TextureTransform::apply(const Vec2& uv) const {
  const Vec2 s = uv * scale;
  const float c = std::cos(rotation), sn = std::sin(rotation);
  return Vec2(c * s.x + sn * s.y, -sn * s.x + c * s.y) + offset;
}

Color Texture::lookup(const Vec2& uvIn) const {
  const TexelImage& im = *image;
  return filtered(*this, uvIn, [&](int x, int y) { return im.at(x, y); });
}

float Texture::alphaLookup(const Vec2& uvIn) const {
  const TexelImage& im = *image;
  if (im.alpha.empty()) return filtered(*this, uvIn, [&](int x, int y) { return im.at(x, y).x; });
  return filtered(*this, uvIn, [&](int x, int y) { return im.alpha[size_t(y) * size_t(im.width) + size_t(x)]; });
}

uint64_t Texture::hash() const {
  Hasher h;
  h.add(image ? image->hash : 0).add(wrapU).add(wrapV);
  h.add(transform.offset).add(transform.rotation).add(transform.scale);
  if (filter != TextureFilter::Linear) h.add(filter);
  return h.value();
}

TexelImage makeTexelImage(int width, int height, std::vector<Color> texels, std::string name) {
  TexelImage im;
  im.width = width;
  im.height = height;
  im.texels = std::move(texels);
  im.name = std::move(name);
  Vec3d sum(0.0);
  for (const Color& c : im.texels) sum += Vec3d(c);
  if (!im.texels.empty()) im.mean = Color(sum / double(im.texels.size()));
  Hasher h;
  h.add(width).add(height).bytes(im.texels.data(), im.texels.size() * sizeof(Color));
  im.hash = h.value();
  return im;
}

TexelImage readTexelImage(const std::string& path, bool srgb) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError("", "", "texture file not found: " + path);
  ModuleImage m;
  readImageFunction()(path.c_str(), nullptr, 0, &m);
  return toTexels(m, path, srgb);
}

TexelImage decodeTexelImage(std::string_view bytes, const std::string& name, bool srgb) {
  std::string hint = name;
  if (bytes.substr(0, 4) == "\x89PNG") hint = "image.png";
  else if (bytes.substr(0, 3) == "\xff\xd8\xff") hint = "image.jpg";
  ModuleImage m;
  readImageFunction()(hint.c_str(), bytes.data(), bytes.size(), &m);
  return toTexels(m, name, srgb);
}

}  // namespace firstshot
