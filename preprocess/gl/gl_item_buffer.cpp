#include "preprocess/gl/gl_item_buffer.h"

#include "common/gl/gl_program.h"
#include "preprocess/profile.h"

#include <fmt/core.h>
#include <glad/gl.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace firstshot {

namespace {

// The version line is given apart: a scene with alpha cut-outs puts GLCutouts::vertexDefines() between.
const char* kVersion = "#version 450 core\n";
const char* kVertexShader = R"(
layout(location = 0) in vec3 position;
layout(location = 1) in uint patchId;
uniform vec3 eyeHi;      // eye = eyeHi + eyeLo
uniform vec3 eyeLo;
uniform vec3 axisRight;
uniform vec3 axisUp;
uniform vec3 axisForward;
uniform vec4 plane;      // clip.x = plane.x*x + plane.y*w, clip.y = plane.z*y + plane.w*w (row 0 at the top)
uniform vec2 depthAB;    // clip.z = depthAB.x*d + depthAB.y: reversed Z, 1 at near, 0 at far
uniform int ortho;
flat out uint vPatch;
#ifdef CUTOUTS
layout(location = 2) in vec2 uv;
layout(location = 3) in uint slot;
out vec2 vUV;
flat out uint vSlot;
#endif
void main() {
#ifdef CUTOUTS
  vUV = uv;
  vSlot = slot;
#endif
  // Camera-relative first: each difference is correctly rounded relative to its own size.
  precise vec3 rel = (position - eyeHi) - eyeLo;
  float x = dot(rel, axisRight);
  float y = dot(rel, axisUp);
  float d = dot(rel, axisForward);
  float w = ortho != 0 ? 1.0 : d;
  gl_Position = vec4(plane.x * x + plane.y * w, plane.z * y + plane.w * w, depthAB.x * d + depthAB.y, w);
  vPatch = patchId;
}
)";

const char* kFragmentShader = R"(#version 450 core
flat in uint vPatch;
layout(location = 0) out uint outPatch;
void main() { outPatch = vPatch; }
)";

constexpr size_t kClusterSize = 128;  // triangles per culling cluster

/// Triangle indices sorted by the 30-bit Morton code of their centroids (stable, so deterministic).
std::vector<uint32_t> mortonOrder(const ItemGeometry& g) {
  const size_t n = g.triangleCount();
  const Vec3d lo = g.bounds.lo, ext = glm::max(g.bounds.hi - g.bounds.lo, Vec3d(1e-30));
  auto spread = [](uint32_t x) {  // 10 bits -> every third bit
    x = (x | (x << 16)) & 0x030000FFu;
    x = (x | (x << 8)) & 0x0300F00Fu;
    x = (x | (x << 4)) & 0x030C30C3u;
    x = (x | (x << 2)) & 0x09249249u;
    return x;
  };
  std::vector<std::pair<uint32_t, uint32_t>> keys(n);
  for (size_t t = 0; t < n; ++t) {
    const Vec3d c = (Vec3d(g.positions[3 * t]) + Vec3d(g.positions[3 * t + 1]) + Vec3d(g.positions[3 * t + 2])) / 3.0;
    const Vec3d q = glm::clamp((c - lo) / ext, 0.0, 1.0) * 1023.0;
    keys[t] = {spread(uint32_t(q.x)) | (spread(uint32_t(q.y)) << 1) | (spread(uint32_t(q.z)) << 2), uint32_t(t)};
  }
  std::stable_sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<uint32_t> order(n);
  for (size_t t = 0; t < n; ++t) order[t] = keys[t].second;
  return order;
}

/// A plane of the view frustum: a point p is inside when dot(p − eye, n) + offset ≥ 0.
struct Plane {
  Vec3d n;
  double offset;
};

/// The six frustum planes of @p v with depth range [near, far].
void frustumPlanes(const View& v, double near, double far, Plane (&planes)[6]) {
  const double l = v.planeMin.x, r = v.planeMax.x, b = v.planeMin.y, t = v.planeMax.y;
  if (v.projection == Projection::Perspective) {  // u = x/d ≥ l  <=>  x − l·d ≥ 0, etc.
    planes[0] = {v.right - l * v.forward, 0};
    planes[1] = {r * v.forward - v.right, 0};
    planes[2] = {v.up - b * v.forward, 0};
    planes[3] = {t * v.forward - v.up, 0};
  } else {
    planes[0] = {v.right, -l};
    planes[1] = {-v.right, r};
    planes[2] = {v.up, -b};
    planes[3] = {-v.up, t};
  }
  planes[4] = {v.forward, -near};
  planes[5] = {-v.forward, far};
  for (Plane& p : planes) {  // normalise so that offsets are distances
    const double len = glm::length(p.n);
    p.n /= len;
    p.offset /= len;
  }
}

struct Vertex {
  float x, y, z;
  uint32_t patch;
};
static_assert(sizeof(Vertex) == 16);

}  // namespace

GLItemBuffer::GLItemBuffer(const PatchMesh& mesh, const Bounds3d& sceneBounds, GLBackend backend, double nearRelative)
    : GLItemBuffer(ItemGeometry::fromPatches(mesh), sceneBounds, backend, nearRelative) {}

GLItemBuffer::GLItemBuffer(const ItemGeometry& geometry, const Bounds3d& sceneBounds, GLBackend backend,
                           double nearRelative)
    : context_(backend), bounds_(sceneBounds), near_(itemBufferNear(sceneBounds, nearRelative)) {
  if (geometry.positions.size() != 3 * geometry.patchIds.size())
    throw std::invalid_argument("GL item buffer: positions must be 3 per triangle");
  vertexCount_ = static_cast<int64_t>(geometry.positions.size());
  if (vertexCount_ > std::numeric_limits<GLsizei>::max())
    throw std::runtime_error("GL item buffer: too many triangles for one draw call");

  // Program.
  const bool cutouts = geometry.cutouts != nullptr;  // absent fragments discarded (gl_cutouts.h)
  program_ = linkProgram("GL item buffer",
                         {{GL_VERTEX_SHADER, {kVersion, cutouts ? GLCutouts::vertexDefines() : "", kVertexShader}},
                          {GL_FRAGMENT_SHADER, {cutouts ? GLCutouts::fragmentShader() : kFragmentShader}}});
  locEyeHi_ = glGetUniformLocation(program_, "eyeHi");
  locEyeLo_ = glGetUniformLocation(program_, "eyeLo");
  locRight_ = glGetUniformLocation(program_, "axisRight");
  locUp_ = glGetUniformLocation(program_, "axisUp");
  locForward_ = glGetUniformLocation(program_, "axisForward");
  locPlane_ = glGetUniformLocation(program_, "plane");
  locDepth_ = glGetUniformLocation(program_, "depthAB");
  locOrtho_ = glGetUniformLocation(program_, "ortho");

  // Vertex data: non-indexed triangles, position + patch ID per vertex (IDs as integers end to end),
  // in Morton order of the triangle centroids, then cut into clusters for frustum culling.
  const size_t nTri = geometry.triangleCount();
  const std::vector<uint32_t> order = mortonOrder(geometry);
  std::vector<Vertex> vertices(3 * nTri);
  for (size_t t = 0; t < nTri; ++t)
    for (int c = 0; c < 3; ++c) {
      const Vec3& p = geometry.positions[3 * size_t(order[t]) + c];
      vertices[3 * t + c] = {p.x, p.y, p.z, geometry.patchIds[order[t]]};
    }
  for (size_t t0 = 0; t0 < nTri; t0 += kClusterSize) {
    const size_t t1 = std::min(nTri, t0 + kClusterSize);
    Bounds3d b;
    for (size_t v = 3 * t0; v < 3 * t1; ++v) b.extend(Vec3d(vertices[v].x, vertices[v].y, vertices[v].z));
    clusters_.push_back({b.centre(), 0.5 * b.diagonal() * (1 + 1e-6) + 1e-12, int(3 * t0), int(3 * (t1 - t0))});
  }
  // A scene without patches (every surface emissive) draws nothing, but a buffer's storage must not be
  // empty (GL_INVALID_VALUE): it gets one unused vertex.
  if (vertices.empty()) vertices.push_back({0.0f, 0.0f, 0.0f, kNoPatch});
  glCreateBuffers(1, &vbo_);
  glNamedBufferStorage(vbo_, static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)), vertices.data(), 0);
  glCreateVertexArrays(1, &vao_);
  glVertexArrayVertexBuffer(vao_, 0, vbo_, 0, sizeof(Vertex));
  glEnableVertexArrayAttrib(vao_, 0);
  glVertexArrayAttribFormat(vao_, 0, 3, GL_FLOAT, GL_FALSE, offsetof(Vertex, x));
  glVertexArrayAttribBinding(vao_, 0, 0);
  glEnableVertexArrayAttrib(vao_, 1);
  glVertexArrayAttribIFormat(vao_, 1, 1, GL_UNSIGNED_INT, offsetof(Vertex, patch));
  glVertexArrayAttribBinding(vao_, 1, 0);
  if (cutouts) {
    cutouts_ = std::make_unique<GLCutouts>(geometry, order);
    cutouts_->attach(vao_);
  }

  // Fixed state: reversed Z, nothing that could alter an integer ID.
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDisable(GL_DITHER);
  glDisable(GL_MULTISAMPLE);
  glDisable(GL_DEPTH_CLAMP);
  glDisable(GL_SCISSOR_TEST);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  checkErrors("setup");
}

GLItemBuffer::~GLItemBuffer() {
  try {
    context_.makeCurrent();
  } catch (...) {
    return;  // resources die with the context
  }
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (colour_) glDeleteRenderbuffers(1, &colour_);
  if (depth_) glDeleteRenderbuffers(1, &depth_);
  if (cutouts_) cutouts_->destroy();
  for (const Slot& s : slots_) glDeleteTextures(1, &s.texture);
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (vbo_) glDeleteBuffers(1, &vbo_);
  if (program_) glDeleteProgram(program_);
}

const char* GLItemBuffer::name() const {
  return context_.backend() == GLBackend::OSMesa ? "gl/osmesa" : "gl/egl";
}

void GLItemBuffer::checkErrors(const char* where) {
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR)
    throw std::runtime_error(fmt::format("GL item buffer ({}): OpenGL error 0x{:04x} in {}", name(), e, where));
}

void GLItemBuffer::ensureFramebuffer(int width, int height) {
  if (width <= fbWidth_ && height <= fbHeight_) return;
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
  if (width > maxSize || height > maxSize)
    throw std::runtime_error("GL item buffer: view of " + std::to_string(width) + "x" + std::to_string(height) +
                             " exceeds GL_MAX_RENDERBUFFER_SIZE " + std::to_string(maxSize));
  fbWidth_ = std::max(width, fbWidth_);
  fbHeight_ = std::max(height, fbHeight_);
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (colour_) glDeleteRenderbuffers(1, &colour_);
  if (depth_) glDeleteRenderbuffers(1, &depth_);
  glCreateRenderbuffers(1, &colour_);
  glNamedRenderbufferStorage(colour_, GL_R32UI, fbWidth_, fbHeight_);
  glCreateRenderbuffers(1, &depth_);
  glNamedRenderbufferStorage(depth_, GL_DEPTH_COMPONENT32F, fbWidth_, fbHeight_);
  glCreateFramebuffers(1, &fbo_);
  glNamedFramebufferRenderbuffer(fbo_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
  glNamedFramebufferRenderbuffer(fbo_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  glNamedFramebufferReadBuffer(fbo_, GL_COLOR_ATTACHMENT0);
  const GLenum status = glCheckNamedFramebufferStatus(fbo_, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("GL item buffer: incomplete framebuffer (status " + std::to_string(status) + ")");
}

void GLItemBuffer::render(const View& view, std::vector<uint32_t>& ids) {
  ids.assign(view.pixelCount(), kNoPatch);
  if (!draw(view, 0)) return;
  profile::Scope readTime(profile::Readback);
  glReadPixels(0, 0, view.width, view.height, GL_RED_INTEGER, GL_UNSIGNED_INT, ids.data());
  checkErrors("render");
}

bool GLItemBuffer::draw(const View& view, unsigned int texture) {
  if (view.pixelCount() == 0) return false;
  const double far = farDepth(view, bounds_);
  const bool empty = !(far > near_) || vertexCount_ == 0;  // nothing in front of the eye
  if (empty && texture == 0) return false;

  profile::Scope drawTime(profile::Render);
  context_.makeCurrent();
  ensureFramebuffer(view.width, view.height);
  if (texture)  // a texture kept in GPU memory (renderToTexture), else the renderbuffer read back
    glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, texture, 0);
  else
    glNamedFramebufferRenderbuffer(fbo_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, view.width, view.height);
  const GLuint clearId[4] = {kNoPatch, 0, 0, 0};
  glClearBufferuiv(GL_COLOR, 0, clearId);
  const GLfloat clearDepth = 0.0f;  // reversed Z: 0 is the far plane
  glClearBufferfv(GL_DEPTH, 0, &clearDepth);
  if (empty) return true;
  glUseProgram(program_);
  const Vec3 eyeHi(view.eye);
  const Vec3 eyeLo(view.eye - Vec3d(eyeHi));
  glUniform3f(locEyeHi_, eyeHi.x, eyeHi.y, eyeHi.z);
  glUniform3f(locEyeLo_, eyeLo.x, eyeLo.y, eyeLo.z);
  glUniform3f(locRight_, float(view.right.x), float(view.right.y), float(view.right.z));
  glUniform3f(locUp_, float(view.up.x), float(view.up.y), float(view.up.z));
  glUniform3f(locForward_, float(view.forward.x), float(view.forward.y), float(view.forward.z));
  // NDC x = (2u − (l+r))/(r−l); NDC y = −(2v − (b+t))/(t−b) so that GL's bottom row is the view's top row.
  const double l = view.planeMin.x, r = view.planeMax.x, b = view.planeMin.y, t = view.planeMax.y;
  glUniform4f(locPlane_, float(2.0 / (r - l)), float(-(r + l) / (r - l)), float(-2.0 / (t - b)),
              float((t + b) / (t - b)));
  // Reversed Z: depth = 1 at d = near, 0 at d = far (perspective: depth = A + B/d; ortho: A·d + B).
  const bool ortho = view.projection == Projection::Orthographic;
  const double n = near_, f = far;
  const double A = ortho ? -1.0 / (f - n) : -n / (f - n);
  const double B = ortho ? f / (f - n) : n * f / (f - n);
  glUniform2f(locDepth_, float(A), float(B));
  glUniform1i(locOrtho_, ortho ? 1 : 0);
  if (cutouts_) cutouts_->bind(program_, view);

  // Clusters that may reach the frustum, merged into runs.
  Plane planes[6];
  frustumPlanes(view, n, f, planes);
  drawFirst_.clear();
  drawCount_.clear();
  for (const Cluster& c : clusters_) {
    bool inside = true;
    for (const Plane& p : planes) inside = inside && glm::dot(c.centre - view.eye, p.n) + p.offset >= -c.radius;
    if (!inside) continue;
    if (!drawFirst_.empty() && drawFirst_.back() + drawCount_.back() == c.first)
      drawCount_.back() += c.count;
    else {
      drawFirst_.push_back(c.first);
      drawCount_.push_back(c.count);
    }
  }
  glBindVertexArray(vao_);
  if (!drawFirst_.empty())
    glMultiDrawArrays(GL_TRIANGLES, drawFirst_.data(), drawCount_.data(), static_cast<GLsizei>(drawFirst_.size()));
  if (profile::enabled()) glFinish();  // so that the draw is not counted as readback
  drawTime.stop();
  return true;
}

// ---- item buffers kept in GPU memory (reduced there, preprocess/gl/gl_reduce.h) ----

unsigned int GLItemBuffer::renderToTexture(const View& view, int slot) {
  context_.makeCurrent();
  if (slot >= int(slots_.size())) slots_.resize(size_t(slot) + 1);
  Slot& s = slots_[size_t(slot)];
  if (s.width != view.width || s.height != view.height) {
    if (s.texture) glDeleteTextures(1, &s.texture);
    glCreateTextures(GL_TEXTURE_2D, 1, &s.texture);
    glTextureStorage2D(s.texture, 1, GL_R32UI, std::max(1, view.width), std::max(1, view.height));
    s.width = view.width, s.height = view.height;
  }
  if (!draw(view, s.texture)) {
    const GLuint none = kNoPatch;
    glClearTexImage(s.texture, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
  }
  checkErrors("render to texture");
  return s.texture;
}

void GLItemBuffer::readTexture(int slot, std::vector<uint32_t>& ids) {
  const Slot& s = slots_.at(size_t(slot));
  ids.resize(size_t(s.width) * size_t(s.height));
  if (ids.empty()) return;
  profile::Scope readTime(profile::Readback);
  context_.makeCurrent();
  glGetTextureImage(s.texture, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, GLsizei(ids.size() * sizeof(uint32_t)), ids.data());
  checkErrors("texture read-back");
}

}  // namespace firstshot
