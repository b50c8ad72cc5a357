// Alpha cut-outs in the GL item buffer: per-vertex texture coordinates, slots, the alpha texels in a storage
// buffer and the discarding fragment shader (preprocess/gl/gl_cutouts.h).
#include "preprocess/gl/gl_cutouts.h"

#include <glad/gl.h>

#include <map>
#include <stdexcept>
#include <utility>

#include "common/materials/texture.h"
#include "common/patches/patch_cutouts.h"
#include "common/util/hash.h"

namespace firstshot {

namespace {

/// One vertex's cut-out attributes (buffer binding 1).
struct CutoutVertex {
  float u = 0, v = 0;
  uint32_t slot = 0;  ///< 0: opaque; else 1 + index into the slots
};
static_assert(sizeof(CutoutVertex) == 12);

/// One slot as the shader reads it (std430: twelve 4-byte members, stride 48).
struct CutoutSlot {
  int32_t mode = 0;        ///< 1 mask, 2 blend
  float cutoff = 0.5f;
  float factor = 1.0f;     ///< the material's alpha factor
  float mean = 1.0f;       ///< the alpha where there is no lookup
  int32_t width = 0, height = 0, wrapU = 0, wrapV = 0;
  uint32_t offset = 0;     ///< first texel in the texel buffer
  int32_t textured = 0;
  int32_t nearest = 0;     ///< 1: TextureFilter::Nearest
  int32_t pad = 0;
};
static_assert(sizeof(CutoutSlot) == 48);

int32_t wrapCode(TextureWrap w) {
  return w == TextureWrap::ClampToEdge ? 1 : w == TextureWrap::MirroredRepeat ? 2 : 0;
}

const char* kCutoutFragmentShader = R"(#version 450 core
struct Slot {
  int mode; float cutoff; float factor; float mean;
  int width; int height; int wrapU; int wrapV;
  uint offset; int textured; int nearest; int pad;
};
layout(std430, binding = 0) readonly buffer CutoutSlots { Slot slots[]; };
layout(std430, binding = 1) readonly buffer CutoutTexels { float texels[]; };
uniform uint coinSeed;
flat in uint vPatch;
in vec2 vUV;
flat in uint vSlot;
layout(location = 0) out uint outPatch;
int floorDiv(int i, int n) { return i >= 0 ? i / n : -((-i - 1) / n) - 1; }
int fold(int i, int n, int wrap) {  // common/materials/texture_image.cpp foldTexelIndex, without % of negatives
  if (wrap == 1) return clamp(i, 0, n - 1);
  if (wrap == 2) { int m = i - 2 * n * floorDiv(i, 2 * n); return m < n ? m : 2 * n - 1 - m; }
  return i - n * floorDiv(i, n);
}
float texel(Slot s, int x, int y) { return texels[s.offset + uint(y * s.width + x)]; }
uint mixBits(uint x) {
  x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;
  return x;
}
void main() {
  if (vSlot != 0u) {
    Slot s = slots[vSlot - 1u];
    float a = s.mean;
    if (s.textured != 0 && s.nearest != 0) {  // Texture::alphaLookup, nearest: the texel the point lies in
      int ix = int(clamp(floor(vUV.x * float(s.width)), -1.0e8, 1.0e8));
      int iy = int(clamp(floor(vUV.y * float(s.height)), -1.0e8, 1.0e8));
      a = clamp(s.factor * texel(s, fold(ix, s.width, s.wrapU), fold(iy, s.height, s.wrapV)), 0.0, 1.0);
    } else if (s.textured != 0) {  // Texture::alphaLookup: texel centres at (i + 1/2)/w, bilinear between them
      float x = vUV.x * float(s.width) - 0.5, y = vUV.y * float(s.height) - 0.5;
      float fx = floor(x), fy = floor(y);
      int ix = int(clamp(fx, -1.0e8, 1.0e8)), iy = int(clamp(fy, -1.0e8, 1.0e8));
      float tx = x - fx, ty = y - fy;
      int x0 = fold(ix, s.width, s.wrapU), x1 = fold(ix + 1, s.width, s.wrapU);
      int y0 = fold(iy, s.height, s.wrapV), y1 = fold(iy + 1, s.height, s.wrapV);
      float top = texel(s, x0, y0) * (1.0 - tx) + texel(s, x1, y0) * tx;
      float bottom = texel(s, x0, y1) * (1.0 - tx) + texel(s, x1, y1) * tx;
      a = clamp(s.factor * (top * (1.0 - ty) + bottom * ty), 0.0, 1.0);
    }
    if (s.mode == 1) {
      if (a < s.cutoff) discard;
    } else {
      uint h = mixBits(mixBits(mixBits(uint(gl_FragCoord.x) ^ coinSeed) + uint(gl_FragCoord.y)) + vPatch);
      if (float(h >> 8) * (1.0 / 16777216.0) >= a) discard;
    }
  }
  outPatch = vPatch;
}
)";

}  // namespace

const char* GLCutouts::vertexDefines() { return "#define CUTOUTS 1\n"; }
const char* GLCutouts::fragmentShader() { return kCutoutFragmentShader; }

GLCutouts::GLCutouts(const ItemGeometry& geometry, const std::vector<uint32_t>& order) {
  const PatchCutouts& cut = *geometry.cutouts;
  std::vector<CutoutVertex> vertices(3 * order.size());
  std::vector<CutoutSlot> slots;
  std::map<std::pair<uint32_t, bool>, uint32_t> slotOf;  // (material, textured) → slot (1-based)
  std::map<const TexelImage*, uint32_t> offsetOf;
  std::vector<float> texels;
  for (size_t t = 0; t < order.size(); ++t) {
    const uint32_t patch = geometry.patchIds[order[t]];
    if (!cut.cutout(patch)) continue;
    const uint32_t material = cut.materialOf(patch);
    const MaterialDesc& m = cut.material(patch);
    for (int c = 0; c < 3; ++c) {
      Vec2 uv;
      const bool textured = cut.uvAt(patch, Vec3d(geometry.positions[3 * size_t(order[t]) + c]), uv);
      auto [it, fresh] = slotOf.try_emplace({material, textured}, uint32_t(slots.size() + 1));
      if (fresh) {
        CutoutSlot s;
        s.mode = m.alphaMode == AlphaMode::Mask ? 1 : 2;
        s.cutoff = m.alphaCutoff;
        s.factor = m.alpha;
        s.mean = cut.meanAlpha(material);
        if (textured) {
          const TexelImage& im = *m.alphaTexture->image;
          auto [at, newImage] = offsetOf.try_emplace(&im, uint32_t(texels.size()));
          if (newImage) {  // Texture::alphaLookup's values: the alpha channel, else the first channel
            if (!im.alpha.empty())
              texels.insert(texels.end(), im.alpha.begin(), im.alpha.end());
            else
              for (const Color& x : im.texels) texels.push_back(x.x);
          }
          s.textured = 1, s.width = im.width, s.height = im.height, s.offset = at->second;
          s.wrapU = wrapCode(m.alphaTexture->wrapU), s.wrapV = wrapCode(m.alphaTexture->wrapV);
          s.nearest = m.alphaTexture->filter == TextureFilter::Nearest ? 1 : 0;
        }
        slots.push_back(s);
      }
      if (textured) uv = m.alphaTexture->transform.apply(uv);
      vertices[3 * t + size_t(c)] = {uv.x, uv.y, it->second};
    }
  }
  if (vertices.empty()) vertices.emplace_back();  // a buffer's storage must not be empty
  if (slots.empty()) slots.emplace_back();
  if (texels.empty()) texels.push_back(1.0f);
  glCreateBuffers(1, &vbo_);
  glNamedBufferStorage(vbo_, GLsizeiptr(vertices.size() * sizeof(CutoutVertex)), vertices.data(), 0);
  glCreateBuffers(1, &params_);
  glNamedBufferStorage(params_, GLsizeiptr(slots.size() * sizeof(CutoutSlot)), slots.data(), 0);
  glCreateBuffers(1, &texels_);
  glNamedBufferStorage(texels_, GLsizeiptr(texels.size() * sizeof(float)), texels.data(), 0);
}

void GLCutouts::destroy() {
  if (vbo_) glDeleteBuffers(1, &vbo_);
  if (params_) glDeleteBuffers(1, &params_);
  if (texels_) glDeleteBuffers(1, &texels_);
  vbo_ = params_ = texels_ = 0;
}

// The item buffer sets up its own two attributes with the same calls on binding 0 (gl_item_buffer.cpp); each
// side names its own buffer, attributes and types, so the near-copy stays.
void GLCutouts::attach(unsigned int vao) const {
  glVertexArrayVertexBuffer(vao, 1, vbo_, 0, sizeof(CutoutVertex));
  glEnableVertexArrayAttrib(vao, 2);
  glVertexArrayAttribFormat(vao, 2, 2, GL_FLOAT, GL_FALSE, offsetof(CutoutVertex, u));
  glVertexArrayAttribBinding(vao, 2, 1);
  glEnableVertexArrayAttrib(vao, 3);
  glVertexArrayAttribIFormat(vao, 3, 1, GL_UNSIGNED_INT, offsetof(CutoutVertex, slot));
  glVertexArrayAttribBinding(vao, 3, 1);
}

void GLCutouts::bind(unsigned int program, const View& view) const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, params_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, texels_);
  Hasher h;  // the same view, the same coins
  h.add(view.eye).add(view.forward).add(view.right).add(view.width).add(view.height);
  glUniform1ui(glGetUniformLocation(program, "coinSeed"), uint32_t(h.value()));
}

}  // namespace firstshot
