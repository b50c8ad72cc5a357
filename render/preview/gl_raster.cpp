// The preview's OpenGL drawing: instant raster, tone-mapped display, line overlays.
#include "render/preview/gl_raster.h"

#include <glad/gl.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/gl/gl_program.h"

namespace firstshot {

namespace {

// The instant picture: flat radiance per patch side, or albedo under a headlight; a textured batch
// (uTextured) multiplies it by texScale × the texel, clamped to [0, 1] as SurfaceTextures::at does
// (bilinear, level 0, the texture's wrap modes: Texture::lookup). Untextured batches skip the product.
// A cut-out batch (uCutout) discards the fragments where the surface is absent: mask where factor × the alpha
// texture (its first channel: the alpha as Texture::alphaLookup reads it) is below the cut-off, blend with
// probability 1 − alpha by a hash of the pixel (a screen-door dither).
const char* kRasterVS = R"(#version 330 core
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec3 aFront;
layout(location = 3) in vec3 aBack;
layout(location = 4) in float aHeadlight;
layout(location = 5) in vec2 aUV;
layout(location = 6) in vec3 aTexScale;
layout(location = 7) in vec2 aAlphaUV;
uniform mat4 uViewProj;
out vec3 vPos;
out vec2 vUV;
out vec2 vAlphaUV;
flat out vec3 vNormal, vFront, vBack, vTexScale;
flat out float vHeadlight;
void main() {
  vPos = aPos; vNormal = aNormal; vFront = aFront; vBack = aBack; vHeadlight = aHeadlight;
  vUV = aUV; vTexScale = aTexScale; vAlphaUV = aAlphaUV;
  gl_Position = uViewProj * vec4(aPos, 1.0);
})";

const char* kRasterFS = R"(#version 330 core
uniform vec3 uEye;
uniform bool uTextured;
uniform sampler2D uAlbedo;
uniform int uCutout;         // 0 opaque, 1 mask, 2 blend (RasterCutout)
uniform bool uAlphaTextured;
uniform sampler2D uAlpha;
uniform float uAlphaFactor, uAlphaMean, uAlphaCutoff;
in vec3 vPos;
in vec2 vUV;
in vec2 vAlphaUV;
flat in vec3 vNormal, vFront, vBack, vTexScale;
flat in float vHeadlight;
layout(location = 0) out vec4 fragColor;
uint mixBits(uint x) {
  x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;
  return x;
}
void main() {
  if (uCutout != 0) {
    float a = uAlphaTextured ? clamp(uAlphaFactor * texture(uAlpha, vAlphaUV).r, 0.0, 1.0) : uAlphaMean;
    if (uCutout == 1 && a < uAlphaCutoff) discard;
    if (uCutout == 2 && float(mixBits(mixBits(uint(gl_FragCoord.x)) + uint(gl_FragCoord.y)) >> 8) / 16777216.0 >= a)
      discard;
  }
  vec3 toEye = uEye - vPos;
  float c = dot(vNormal, toEye);
  vec3 L = c > 0.0 ? vFront : vBack;
  if (vHeadlight > 0.5) L *= abs(c) / max(length(toEye), 1e-20);
  if (uTextured) L *= vTexScale * clamp(texture(uAlbedo, vUV).rgb, 0.0, 1.0);
  fragColor = vec4(L, 1.0);
})";

// A full-window triangle; uv (0,0) at the bottom left.
const char* kDisplayVS = R"(#version 330 core
out vec2 vUV;
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  vUV = p;
  gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
})";

// Exposure, clamp to [0, 1], sRGB transfer curve: the same steps as Film::write's PNG.
const char* kDisplayFS = R"(#version 330 core
uniform sampler2D uImage;
uniform float uScale;
uniform bool uFlipY;
in vec2 vUV;
layout(location = 0) out vec4 fragColor;
float srgb(float v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055; }
void main() {
  vec2 uv = uFlipY ? vec2(vUV.x, 1.0 - vUV.y) : vUV;
  vec3 v = clamp(texture(uImage, uv).rgb * uScale, 0.0, 1.0);
  fragColor = vec4(srgb(v.r), srgb(v.g), srgb(v.b), 1.0);
})";

// Overlay lines, hidden behind the instant picture's surfaces. Window depth is linear in screen
// space over a plane, so a line lying on a surface is no deeper than the farthest of the 3×3 pixel
// centres around it; anything deeper is behind something. (No polygon offset on the surfaces: it
// would move grazing faces behind their neighbours and change the instant picture.)
const char* kLineVS = R"(#version 330 core
layout(location = 0) in vec3 aPos;
uniform mat4 uViewProj;
void main() { gl_Position = uViewProj * vec4(aPos, 1.0); })";

const char* kLineFS = R"(#version 330 core
uniform sampler2D uDepth;
uniform vec4 uRect;  // the image's viewport: x, y, width, height
uniform vec3 uColor;
layout(location = 0) out vec4 fragColor;
void main() {
  ivec2 size = textureSize(uDepth, 0);
  ivec2 p = ivec2((gl_FragCoord.xy - uRect.xy) / uRect.zw * vec2(size));
  float d = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) d = max(d, texelFetch(uDepth, clamp(p + ivec2(dx, dy), ivec2(0), size - 1), 0).r);
  if (gl_FragCoord.z > d + 1e-7) discard;
  fragColor = vec4(uColor, 1.0);
})";

GLuint link(const char* what, const char* vs, const char* fs) {
  return linkProgram(std::string("preview, the ") + what + " program",
                     {{GL_VERTEX_SHADER, {vs}}, {GL_FRAGMENT_SHADER, {fs}}});
}

void setTextureFilter(GLuint tex, GLint filter) {
  glBindTexture(GL_TEXTURE_2D, tex);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

GLint glWrap(TextureWrap w) {
  switch (w) {
    case TextureWrap::ClampToEdge: return GL_CLAMP_TO_EDGE;
    case TextureWrap::MirroredRepeat: return GL_MIRRORED_REPEAT;
    default: return GL_REPEAT;
  }
}

/// A new texture sampled as Texture::lookup samples @p t: bilinear or nearest on level 0 with its wrap modes (bound).
GLuint newTextureLike(const Texture& t) {
  GLuint tex = 0;
  glGenTextures(1, &tex);
  glBindTexture(GL_TEXTURE_2D, tex);
  const GLint filter = t.filter == TextureFilter::Nearest ? GL_NEAREST : GL_LINEAR;
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, glWrap(t.wrapU));
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, glWrap(t.wrapV));
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  return tex;
}

/// Uploads @p t's image as a linear RGB float texture (rows from the top: GL's t = 0 is v = 0).
GLuint uploadTexture(const Texture& t) {
  const GLuint tex = newTextureLike(t);
  const TexelImage& im = *t.image;
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, im.width, im.height, 0, GL_RGB, GL_FLOAT, im.texels.data());
  return tex;
}

/// Uploads @p t's alpha (its alpha channel, else its first channel, as Texture::alphaLookup reads it) as a linear
/// one-channel float texture.
GLuint uploadAlpha(const Texture& t) {
  const TexelImage& im = *t.image;
  std::vector<float> a = im.alpha;
  if (a.empty())
    for (const Color& c : im.texels) a.push_back(c.x);
  const GLuint tex = newTextureLike(t);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, im.width, im.height, 0, GL_RED, GL_FLOAT, a.data());
  return tex;
}

/// A vertex array with one buffer of points (lines).
struct LineBuffer {
  GLuint vao = 0, vbo = 0;
  GLsizei count = 0;
  void upload(const std::vector<Vec3>& points) {
    if (!vao) {
      glGenVertexArrays(1, &vao);
      glGenBuffers(1, &vbo);
      glBindVertexArray(vao);
      glBindBuffer(GL_ARRAY_BUFFER, vbo);
      glEnableVertexAttribArray(0);
      glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vec3), nullptr);
    }
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(points.size() * sizeof(Vec3)), points.data(), GL_STATIC_DRAW);
    count = GLsizei(points.size());
  }
  void release() {
    if (vbo) glDeleteBuffers(1, &vbo);
    if (vao) glDeleteVertexArrays(1, &vao);
  }
};

}  // namespace

struct GLRaster::Impl {
  GLuint rasterProgram = 0, displayProgram = 0, lineProgram = 0;
  GLuint meshVao = 0, meshVbo = 0, emptyVao = 0;
  GLsizei meshCount = 0;
  std::vector<RasterBatch> batches;
  // Albedo textures, uploaded once each (kept across setMesh) and the GL texture of each batch's index.
  std::vector<std::pair<std::shared_ptr<const Texture>, GLuint>> uploaded;
  std::vector<GLuint> batchTextures;
  // Cut-outs: their alpha textures (0: none, alpha is the mean), by RasterMesh::cutouts' index.
  std::vector<RasterCutout> cutouts;
  std::vector<GLuint> cutoutTextures;
  LineBuffer edges, records;
  Vec3 lo{0.0f}, hi{0.0f};  // mesh bounds, for the depth range

  // The instant picture's target.
  GLuint fbo = 0, colorTex = 0, depthTex = 0;
  int width = 0, height = 0;
  glm::mat4 viewProj{1.0f};

  GLuint filmTex = 0;
  int filmWidth = 0, filmHeight = 0;

  int rect[4] = {0, 0, 0, 0};  // the image's viewport in the window, set by display()

  void ensureTarget(int w, int h) {
    if (fbo && w == width && h == height) return;
    if (!fbo) {
      glGenFramebuffers(1, &fbo);
      glGenTextures(1, &colorTex);
      glGenTextures(1, &depthTex);
    }
    width = w, height = h;
    setTextureFilter(colorTex, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, h, 0, GL_RGBA, GL_FLOAT, nullptr);
    setTextureFilter(depthTex, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, w, h, 0, GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colorTex, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depthTex, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("preview: the offscreen framebuffer is incomplete");
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  void drawLines(const LineBuffer& lines, const Vec3& color) {
    if (lines.count == 0 || !fbo) return;
    glUseProgram(lineProgram);
    glUniformMatrix4fv(glGetUniformLocation(lineProgram, "uViewProj"), 1, GL_FALSE, glm::value_ptr(viewProj));
    glUniform4f(glGetUniformLocation(lineProgram, "uRect"), float(rect[0]), float(rect[1]), float(rect[2]), float(rect[3]));
    glUniform3f(glGetUniformLocation(lineProgram, "uColor"), color.x, color.y, color.z);
    glUniform1i(glGetUniformLocation(lineProgram, "uDepth"), 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, depthTex);
    glBindVertexArray(lines.vao);
    glDrawArrays(GL_LINES, 0, lines.count);
  }
};

GLRaster::GLRaster() : impl_(std::make_unique<Impl>()) {
  impl_->rasterProgram = link("raster", kRasterVS, kRasterFS);
  impl_->displayProgram = link("display", kDisplayVS, kDisplayFS);
  impl_->lineProgram = link("line", kLineVS, kLineFS);
  glGenVertexArrays(1, &impl_->emptyVao);
}

GLRaster::~GLRaster() {
  Impl& m = *impl_;
  glDeleteProgram(m.rasterProgram);
  glDeleteProgram(m.displayProgram);
  glDeleteProgram(m.lineProgram);
  if (m.meshVbo) glDeleteBuffers(1, &m.meshVbo);
  if (m.meshVao) glDeleteVertexArrays(1, &m.meshVao);
  glDeleteVertexArrays(1, &m.emptyVao);
  m.edges.release();
  m.records.release();
  if (m.fbo) {
    glDeleteFramebuffers(1, &m.fbo);
    glDeleteTextures(1, &m.colorTex);
    glDeleteTextures(1, &m.depthTex);
  }
  if (m.filmTex) glDeleteTextures(1, &m.filmTex);
  for (const auto& u : m.uploaded) glDeleteTextures(1, &u.second);
  for (GLuint t : m.cutoutTextures)
    if (t) glDeleteTextures(1, &t);
}

void GLRaster::setMesh(const RasterMesh& mesh) {
  Impl& m = *impl_;
  if (!m.meshVao) {
    glGenVertexArrays(1, &m.meshVao);
    glGenBuffers(1, &m.meshVbo);
    glBindVertexArray(m.meshVao);
    glBindBuffer(GL_ARRAY_BUFFER, m.meshVbo);
    const auto stride = GLsizei(sizeof(RasterVertex));
    auto attrib = [&](GLuint index, GLint size, size_t offset) {
      glEnableVertexAttribArray(index);
      glVertexAttribPointer(index, size, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offset));
    };
    attrib(0, 3, offsetof(RasterVertex, position));
    attrib(1, 3, offsetof(RasterVertex, normal));
    attrib(2, 3, offsetof(RasterVertex, front));
    attrib(3, 3, offsetof(RasterVertex, back));
    attrib(4, 1, offsetof(RasterVertex, headlight));
    attrib(5, 2, offsetof(RasterVertex, uv));
    attrib(6, 3, offsetof(RasterVertex, texScale));
    attrib(7, 2, offsetof(RasterVertex, alphaUv));
  }
  glBindVertexArray(m.meshVao);
  glBindBuffer(GL_ARRAY_BUFFER, m.meshVbo);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(mesh.triangles.size() * sizeof(RasterVertex)), mesh.triangles.data(),
               GL_STATIC_DRAW);
  m.meshCount = GLsizei(mesh.triangles.size());
  m.batches = mesh.batches;
  m.batchTextures.clear();
  for (const std::shared_ptr<const Texture>& t : mesh.textures) {
    auto it = std::find_if(m.uploaded.begin(), m.uploaded.end(), [&](const auto& u) { return u.first == t; });
    if (it == m.uploaded.end()) it = m.uploaded.insert(m.uploaded.end(), {t, uploadTexture(*t)});
    m.batchTextures.push_back(it->second);
  }
  for (GLuint t : m.cutoutTextures)
    if (t) glDeleteTextures(1, &t);
  m.cutouts = mesh.cutouts;
  m.cutoutTextures.clear();
  for (const RasterCutout& c : mesh.cutouts) m.cutoutTextures.push_back(c.alpha ? uploadAlpha(*c.alpha) : 0);
  m.edges.upload(mesh.edges);
  m.lo = mesh.lo, m.hi = mesh.hi;
}

void GLRaster::setRecords(const std::vector<Vec3>& lines) { impl_->records.upload(lines); }

void GLRaster::renderInstant(const CameraDesc& camera) {
  Impl& m = *impl_;
  m.ensureTarget(camera.width, camera.height);
  // Depth range from the distance to the farthest corner of the scene's bounds.
  double far = 0;
  for (int k = 0; k < 8; ++k) {
    const Vec3d corner((k & 1) ? m.hi.x : m.lo.x, (k & 2) ? m.hi.y : m.lo.y, (k & 4) ? m.hi.z : m.lo.z);
    far = std::max(far, glm::length(corner - camera.position));
  }
  far = std::max(far * 1.01, 1e-3);
  const double near = far * 5e-4;
  // The renderer's pinhole: vertical field of view, image aspect, top row at +y.
  const glm::dmat4 proj = glm::perspective(glm::radians(camera.fovYDeg), double(camera.width) / camera.height, near, far);
  const glm::dmat4 view = glm::lookAt(camera.position, camera.lookAt, camera.up);
  m.viewProj = glm::mat4(proj * view);

  glBindFramebuffer(GL_FRAMEBUFFER, m.fbo);
  glViewport(0, 0, m.width, m.height);
  glClearColor(0, 0, 0, 0);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  if (m.meshCount > 0) {
    glUseProgram(m.rasterProgram);
    glUniformMatrix4fv(glGetUniformLocation(m.rasterProgram, "uViewProj"), 1, GL_FALSE, glm::value_ptr(m.viewProj));
    const Vec3 eye(camera.position);
    glUniform3f(glGetUniformLocation(m.rasterProgram, "uEye"), eye.x, eye.y, eye.z);
    glUniform1i(glGetUniformLocation(m.rasterProgram, "uAlbedo"), 0);
    glUniform1i(glGetUniformLocation(m.rasterProgram, "uAlpha"), 1);
    const GLint textured = glGetUniformLocation(m.rasterProgram, "uTextured");
    const GLint cutout = glGetUniformLocation(m.rasterProgram, "uCutout");
    glBindVertexArray(m.meshVao);
    for (const RasterBatch& b : m.batches) {
      glUniform1i(textured, b.texture >= 0 ? 1 : 0);
      glActiveTexture(GL_TEXTURE0);
      if (b.texture >= 0) glBindTexture(GL_TEXTURE_2D, m.batchTextures[size_t(b.texture)]);
      const RasterCutout* c = b.cutout >= 0 ? &m.cutouts[size_t(b.cutout)] : nullptr;
      glUniform1i(cutout, !c ? 0 : c->mode == AlphaMode::Blend ? 2 : 1);
      if (c) {
        const GLuint alphaTex = m.cutoutTextures[size_t(b.cutout)];
        glUniform1i(glGetUniformLocation(m.rasterProgram, "uAlphaTextured"), alphaTex ? 1 : 0);
        glUniform1f(glGetUniformLocation(m.rasterProgram, "uAlphaFactor"), c->factor);
        glUniform1f(glGetUniformLocation(m.rasterProgram, "uAlphaMean"), c->mean);
        glUniform1f(glGetUniformLocation(m.rasterProgram, "uAlphaCutoff"), c->cutoff);
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D, alphaTex);
        glActiveTexture(GL_TEXTURE0);
      }
      glDrawArrays(GL_TRIANGLES, GLint(b.first), GLsizei(b.count));
    }
  }
  glDisable(GL_DEPTH_TEST);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void GLRaster::uploadFilm(const std::vector<float>& rgb, int width, int height) {
  Impl& m = *impl_;
  if (!m.filmTex) glGenTextures(1, &m.filmTex);
  glBindTexture(GL_TEXTURE_2D, m.filmTex);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (width != m.filmWidth || height != m.filmHeight) {
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, width, height, 0, GL_RGB, GL_FLOAT, rgb.data());
    m.filmWidth = width, m.filmHeight = height;
  } else {
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGB, GL_FLOAT, rgb.data());
  }
}

void GLRaster::display(int fbWidth, int fbHeight, const DisplaySettings& settings) {
  Impl& m = *impl_;
  const bool film = settings.showFilm && m.filmTex;
  const int w = film ? m.filmWidth : m.width, h = film ? m.filmHeight : m.height;
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, fbWidth, fbHeight);
  glClearColor(0.12f, 0.12f, 0.12f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (w <= 0 || h <= 0) return;
  // Letterbox: the largest rectangle of the image's aspect ratio, centred; 1:1 when it fits exactly.
  const double s = std::min(double(fbWidth) / w, double(fbHeight) / h);
  const int rw = std::max(1, int(std::lround(w * s))), rh = std::max(1, int(std::lround(h * s)));
  m.rect[0] = (fbWidth - rw) / 2, m.rect[1] = (fbHeight - rh) / 2, m.rect[2] = rw, m.rect[3] = rh;
  glViewport(m.rect[0], m.rect[1], rw, rh);

  const GLuint tex = film ? m.filmTex : m.colorTex;
  setTextureFilter(tex, rw == w && rh == h ? GL_NEAREST : GL_LINEAR);
  glUseProgram(m.displayProgram);
  glUniform1i(glGetUniformLocation(m.displayProgram, "uImage"), 0);
  glUniform1f(glGetUniformLocation(m.displayProgram, "uScale"), std::exp2(settings.exposure));
  glUniform1i(glGetUniformLocation(m.displayProgram, "uFlipY"), film ? 1 : 0);  // the film's top row comes first
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, tex);
  glBindVertexArray(m.emptyVao);
  glDrawArrays(GL_TRIANGLES, 0, 3);

  if (settings.edges) m.drawLines(m.edges, Vec3(1.0f, 0.85f, 0.2f));
  if (settings.records) m.drawLines(m.records, Vec3(0.2f, 0.9f, 1.0f));
}

std::vector<float> GLRaster::readInstant(int& width, int& height) const {
  const Impl& m = *impl_;
  width = m.width, height = m.height;
  std::vector<float> rgb(size_t(width) * size_t(height) * 3);
  if (!m.fbo) return rgb;
  std::vector<float> rows(rgb.size());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, m.fbo);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_FLOAT, rows.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  const size_t row = size_t(width) * 3;
  for (int y = 0; y < height; ++y)  // GL's first row is the bottom one
    std::copy_n(&rows[size_t(height - 1 - y) * row], row, &rgb[size_t(y) * row]);
  return rgb;
}

std::vector<uint8_t> GLRaster::readDisplay(int& width, int& height) const {
  const Impl& m = *impl_;
  width = m.rect[2], height = m.rect[3];
  std::vector<uint8_t> rows(size_t(width) * size_t(height) * 3), rgb(rows.size());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(m.rect[0], m.rect[1], width, height, GL_RGB, GL_UNSIGNED_BYTE, rows.data());
  const size_t row = size_t(width) * 3;
  for (int y = 0; y < height; ++y) std::copy_n(&rows[size_t(height - 1 - y) * row], row, &rgb[size_t(y) * row]);
  return rgb;
}

}  // namespace firstshot
