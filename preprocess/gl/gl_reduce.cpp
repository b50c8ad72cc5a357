// Item buffers reduced on the GPU by compute shaders (preprocess/gl/gl_reduce.h).
#include "preprocess/gl/gl_reduce.h"

#include <fmt/core.h>
#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/gl/gl_program.h"
#include "preprocess/gl/egl_devices.h"
#include "preprocess/gl/gl_item_buffer.h"
#include "preprocess/profile.h"

namespace firstshot {

namespace {

/// Σ w per patch over the pixels showing it, and the list of touched patches.
const char* kTouchShader = R"(#version 450 core
layout(local_size_x = 16, local_size_y = 16) in;
layout(r32ui, binding = 0) readonly uniform uimage2D ids;
layout(std430, binding = 0) readonly buffer Weights { uvec2 weight[]; };  // fixed point: lo, hi
layout(std430, binding = 1) buffer Acc { uint acc[]; };                   // per patch: lo, hi
layout(std430, binding = 2) buffer Flags { uint flag[]; };                // per patch: listed
layout(std430, binding = 3) buffer List { uint count; uint list[]; };
uniform ivec2 size;
uniform uint offset;
uniform uint patchCount;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= size.x || p.y >= size.y) return;
  uint id = imageLoad(ids, p).r;
  if (id >= patchCount) return;
  uvec2 w = weight[offset + uint(p.y) * uint(size.x) + uint(p.x)];
  if ((w.x | w.y) == 0u) return;
  uint old = atomicAdd(acc[2u * id], w.x);
  uint hi = w.y + (old + w.x < old ? 1u : 0u);  // the low word's carry
  if (hi != 0u) atomicAdd(acc[2u * id + 1u], hi);
  if (atomicExchange(flag[id], 1u) == 0u) list[atomicAdd(count, 1u)] = id;
}
)";

/// The touched patches' sums to a compact buffer; their counters cleared for the next sample.
const char* kGatherShader = R"(#version 450 core
layout(local_size_x = 64) in;
layout(std430, binding = 1) buffer Acc { uint acc[]; };
layout(std430, binding = 2) buffer Flags { uint flag[]; };
layout(std430, binding = 3) buffer List { uint count; uint list[]; };
layout(std430, binding = 4) buffer Out { uint outSum[]; };  // per touched patch: lo, hi
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= count) return;
  uint id = list[k];
  outSum[2u * k] = acc[2u * id];
  outSum[2u * k + 1u] = acc[2u * id + 1u];
  acc[2u * id] = 0u;
  acc[2u * id + 1u] = 0u;
  flag[id] = 0u;
}
)";

/// patchCoverage() of (touched patch, view) jobs, one work group per tile of 256 pixels of a job's box.
/// Every double expression is the CPU's (preprocess/coverage.cpp), in its order, `precise` (no fused
/// multiply-add, no reassociation).
const char* kCoverageShader = R"(#version 450 core
layout(local_size_x = 256) in;
layout(r32ui, binding = 0) readonly uniform uimage2D ids;
layout(std430, binding = 0) readonly buffer Weights { uvec2 weight[]; };
layout(std430, binding = 1) readonly buffer Patches { double P[]; };  // 16 per patch: v0..v3, Newell n, count
layout(std430, binding = 2) readonly buffer JobD { double J[]; };     // 18 per job: q[8] (u, v), sign, eye side
layout(std430, binding = 3) readonly buffer JobI { ivec4 JI[]; };     // 2 per job: (i0, j0, w, h), (n, slot, patch, 0)
layout(std430, binding = 4) readonly buffer Tiles { uvec2 tile[]; };  // (job, first pixel of the box)
layout(std430, binding = 5) buffer Sums { uint sums[]; };             // 8 per slot: expected, visible (lo, hi), pixels
uniform dvec3 eye, axisRight, axisUp, axisForward;
uniform dvec2 planeMin, planeMax;
uniform ivec2 size;
uniform uint offset, patchCount, tileBase, tileCount;
uniform int persp;
uniform double nearDepth;

shared uvec2 sE[256], sV[256];
shared uint sN[256];

uvec2 add64(uvec2 a, uvec2 b) { uint lo = a.x + b.x; return uvec2(lo, a.y + b.y + (lo < a.x ? 1u : 0u)); }
void atomicAdd64(uint i, uvec2 v) {
  uint old = atomicAdd(sums[i], v.x);
  uint hi = v.y + (old + v.x < old ? 1u : 0u);
  if (hi != 0u) atomicAdd(sums[i + 1u], hi);
}
dvec3 vtx(uint p, int k) { uint b = 16u * p + 3u * uint(k); return dvec3(P[b], P[b + 1u], P[b + 2u]); }
dvec3 nrm(uint p) { uint b = 16u * p + 12u; return dvec3(P[b], P[b + 1u], P[b + 2u]); }
int cnt(uint p) { return int(P[16u * p + 15u]); }
double dot3(dvec3 a, dvec3 b) { precise double r = (a.x * b.x + a.y * b.y) + a.z * b.z; return r; }
dvec3 cross3(dvec3 x, dvec3 y) {
  precise dvec3 r = dvec3(x.y * y.z - y.y * x.z, x.z * y.x - y.z * x.x, x.x * y.y - y.x * x.y);
  return r;
}
dvec2 centre(int i, int j) {  // View::pixelCentre
  precise double u = planeMin.x + (double(i) + 0.5LF) * (planeMax.x - planeMin.x) / double(size.x);
  precise double v = planeMax.y - (double(j) + 0.5LF) * (planeMax.y - planeMin.y) / double(size.y);
  return dvec2(u, v);
}
bool inside(uint job, int n, dvec2 c) {
  uint b = 18u * job;
  double sgn = J[b + 16u];
  for (int e = 0; e < n; ++e) {
    int f = (e + 1) % n;
    dvec2 a = dvec2(J[b + 2u * uint(e)], J[b + 2u * uint(e) + 1u]);
    dvec2 q = dvec2(J[b + 2u * uint(f)], J[b + 2u * uint(f) + 1u]);
    precise double s = sgn * ((q.x - a.x) * (c.y - a.y) - (q.y - a.y) * (c.x - a.x));
    if (!(s >= 0.0LF)) return false;
  }
  return true;
}
bool contains(uint p, dvec3 x) {  // ExactPolygon::contains
  int c = cnt(p);
  dvec3 n = nrm(p);
  for (int k = 0; k < c; ++k) {
    dvec3 a = vtx(p, k);
    precise dvec3 e = vtx(p, (k + 1) % c) - a;
    precise dvec3 r = x - a;
    if (dot3(cross3(e, r), n) < 0.0LF) return false;
  }
  return true;
}
/// PolygonCache: some vertex of candidate p strictly on the eye's side of the plane (s0, sn).
bool inFrontOf(uint p, dvec3 s0, dvec3 sn, double eyeSide) {
  if (eyeSide == 0.0LF) return true;
  int c = cnt(p);
  for (int k = 0; k < c; ++k) {
    precise double side = eyeSide * dot3(vtx(p, k) - s0, sn);
    if (side > 0.0LF) return true;
  }
  return false;
}
/// patchCoverage()'s visibility of pixel centre c of (i, j) for patch self: clean neighbourhood, else
/// occludedNear() over the 3×3 proposals.
bool visible(uint job, uint self, int i, int j, dvec2 c) {
  int y0 = max(0, j - 1), y1 = min(size.y - 1, j + 1), x0 = max(0, i - 1), x1 = min(size.x - 1, i + 1);
  bool clean = true;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      uint id = imageLoad(ids, ivec2(x, y)).r;
      clean = clean && (id == self || id >= patchCount);
    }
  if (clean) return true;
  precise dvec3 o = persp != 0 ? eye : eye + c.x * axisRight + c.y * axisUp;
  precise dvec3 d = persp != 0 ? axisForward + c.x * axisRight + c.y * axisUp : axisForward;
  dvec3 sn = nrm(self), s0 = vtx(self, 0);
  precise double den = dot3(d, sn);
  if (den == 0.0LF) return true;  // the CPU's tSelf = inf: its tolerance is NaN, nothing is nearer
  precise double tSelf = dot3(s0 - o, sn) / den;
  precise double tMax = tSelf - 1e-6LF * abs(tSelf);
  double eyeSide = J[18u * job + 17u];
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      uint id = imageLoad(ids, ivec2(x, y)).r;
      if (id == self || id >= patchCount) continue;
      if (!inFrontOf(id, s0, sn, eyeSide)) continue;
      dvec3 on = nrm(id);
      precise double den2 = dot3(d, on);
      if (den2 == 0.0LF) continue;
      precise double t = dot3(vtx(id, 0) - o, on) / den2;
      precise dvec3 hit = o + t * d;
      if (t >= nearDepth && t < tMax && contains(id, hit)) return false;
    }
  return true;
}
void main() {
  uint lid = gl_LocalInvocationID.x;
  for (uint t = gl_WorkGroupID.x; t < tileCount; t += gl_NumWorkGroups.x) {
    uvec2 tl = tile[tileBase + t];
    uint job = tl.x;
    ivec4 box = JI[2u * job], info = JI[2u * job + 1u];
    uint lin = tl.y + lid;
    uvec2 e = uvec2(0u), v = uvec2(0u);
    uint np = 0u;
    if (lin < uint(box.z) * uint(box.w)) {
      int i = box.x + int(lin % uint(box.z)), j = box.y + int(lin / uint(box.z));
      uvec2 w = weight[offset + uint(j) * uint(size.x) + uint(i)];
      dvec2 c = centre(i, j);
      if ((w.x | w.y) != 0u && inside(job, info.x, c)) {
        e = w, np = 1u;
        if (visible(job, uint(info.z), i, j, c)) v = w;
      }
    }
    sE[lid] = e, sV[lid] = v, sN[lid] = np;
    barrier();
    for (uint s = 128u; s > 0u; s >>= 1) {
      if (lid < s) {
        sE[lid] = add64(sE[lid], sE[lid + s]);
        sV[lid] = add64(sV[lid], sV[lid + s]);
        sN[lid] += sN[lid + s];
      }
      barrier();
    }
    if (lid == 0u && sN[0] != 0u) {
      uint b = 8u * uint(info.y);
      atomicAdd64(b, sE[0]);
      atomicAdd64(b + 2u, sV[0]);
      atomicAdd(sums[b + 4u], sN[0]);
    }
    barrier();  // the shared sums are reused by the next tile
  }
}
)";

constexpr uint32_t kTile = 256;          // pixels per work group of the coverage shader
constexpr uint32_t kMaxGroups = 65535;   // the guaranteed GL_MAX_COMPUTE_WORK_GROUP_COUNT
// Storage-buffer binding points 0…5 only: GL 4.3 guarantees 8 (GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS); each pass
// binds its own buffers before its dispatches.

GLuint reduceProgram(const char* source, const char* what) {
  return linkProgram(fmt::format("GL reduction, the {} program", what), {{GL_COMPUTE_SHADER, {source}}});
}

/// (Re)fills @p buffer with @p bytes bytes (at least 4: a buffer's store must not be empty).
void reduceUpload(GLuint buffer, size_t bytes, const void* data) {
  glNamedBufferData(buffer, GLsizeiptr(std::max<size_t>(bytes, 4)), bytes ? data : nullptr, GL_STREAM_DRAW);
}

int reduceLoc(GLuint program, const char* name) { return glGetUniformLocation(program, name); }

void reduceCheck(const char* where) {
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR) throw std::runtime_error(fmt::format("GL reduction: OpenGL error 0x{:04x} in {}", e, where));
}

double fromFixed(uint32_t lo, uint32_t hi, int shift) {
  return std::ldexp(double((uint64_t(hi) << 32) | lo), -shift);
}

}  // namespace

void checkGLReduceMode(const std::string& mode) {
  if (mode != "cpu" && mode != "gpu" && mode != "auto")
    throw std::invalid_argument("unknown GL reduction \"" + mode + "\" (cpu, gpu, auto)");
}

GLReduce* GLReduce::forRenderer(ItemBufferRenderer* renderer, const PatchMesh& mesh, const std::string& mode,
                                std::shared_ptr<GLReduce>& cache) {
  checkGLReduceMode(mode);
  auto* gl = dynamic_cast<GLItemBuffer*>(renderer);
  if (!gl || mode == "cpu" || gl->hasCutouts()) return nullptr;  // cut-outs: their coverage needs the CPU's alpha
  if (cache && &cache->gl_ == gl) return cache.get();
  if (mode == "auto" && isSoftwareRenderer(gl->context().description())) return nullptr;
  profile::Scope setupTime(profile::RendererSetup);
  cache = std::make_shared<GLReduce>(*gl, mesh);
  return cache.get();
}

GLReduce::GLReduce(GLItemBuffer& gl, const PatchMesh& mesh) : gl_(gl), patchCount_(mesh.size()), patches_(mesh.patches) {
  gl_.context().makeCurrent();
  touchProgram_ = reduceProgram(kTouchShader, "touched-sum");
  gatherProgram_ = reduceProgram(kGatherShader, "gather");
  coverageProgram_ = reduceProgram(kCoverageShader, "coverage");
  GLuint* buffers[] = {&patchBuffer_, &accBuffer_, &flagBuffer_, &listBuffer_, &outBuffer_,
                       &jobDBuffer_,  &jobIBuffer_, &tileBuffer_, &sumBuffer_};
  for (GLuint* b : buffers) glCreateBuffers(1, b);
  std::vector<double> P(size_t(patchCount_) * 16, 0.0);
  for (uint32_t p = 0; p < patchCount_; ++p) {
    const Patch& patch = mesh.patches[p];
    double* d = &P[size_t(p) * 16];
    for (uint32_t k = 0; k < patch.count; ++k)
      for (int c = 0; c < 3; ++c) d[3 * k + c] = double(patch.v[k][c]);
    const Vec3d n = exactNormal(patch);
    d[12] = n.x, d[13] = n.y, d[14] = n.z, d[15] = double(patch.count);
  }
  reduceUpload(patchBuffer_, P.size() * sizeof(double), P.data());
  const size_t n = std::max<size_t>(patchCount_, 1);
  glNamedBufferStorage(accBuffer_, GLsizeiptr(2 * n * sizeof(uint32_t)), nullptr, GL_DYNAMIC_STORAGE_BIT);
  glNamedBufferStorage(flagBuffer_, GLsizeiptr(n * sizeof(uint32_t)), nullptr, GL_DYNAMIC_STORAGE_BIT);
  glNamedBufferStorage(listBuffer_, GLsizeiptr((n + 1) * sizeof(uint32_t)), nullptr, GL_DYNAMIC_STORAGE_BIT);
  glNamedBufferStorage(outBuffer_, GLsizeiptr(2 * n * sizeof(uint32_t)), nullptr, GL_DYNAMIC_STORAGE_BIT);
  const GLuint zero = 0;
  for (GLuint b : {accBuffer_, flagBuffer_, listBuffer_})
    glClearNamedBufferData(b, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  reduceCheck("setup");
}

GLReduce::~GLReduce() {
  try {
    gl_.context().makeCurrent();
  } catch (...) {
    return;
  }
  for (GLuint p : {touchProgram_, gatherProgram_, coverageProgram_}) glDeleteProgram(p);
  for (GLuint b : {patchBuffer_, accBuffer_, flagBuffer_, listBuffer_, outBuffer_, jobDBuffer_, jobIBuffer_, tileBuffer_,
                   sumBuffer_})
    glDeleteBuffers(1, &b);
  for (auto& [key, w] : windows_) glDeleteBuffers(1, &w.buffer);
}

const GLReduce::WindowWeights& GLReduce::weightsFor(const std::vector<std::vector<double>>& weights) {
  auto it = windows_.find(&weights);
  if (it != windows_.end()) return it->second;
  if (windows_.size() >= 8) {  // spots have a window each: keep a few
    for (auto& [key, w] : windows_) glDeleteBuffers(1, &w.buffer);
    windows_.clear();
  }
  WindowWeights w;
  double total = 0;
  size_t pixels = 0;
  for (const auto& view : weights) {
    w.offset.push_back(uint32_t(pixels));
    pixels += view.size();
    for (double x : view) total += x > 0 ? x : 0.0;
  }
  int e = 0;
  std::frexp(std::max(total, 1e-300), &e);  // total < 2^e
  w.shift = 61 - e;
  std::vector<uint32_t> fixed(2 * pixels, 0);
  size_t k = 0;
  for (const auto& view : weights)
    for (double x : view) {
      const uint64_t q = x > 0 ? std::max<uint64_t>(1, uint64_t(std::ldexp(x, w.shift))) : 0;
      fixed[2 * k] = uint32_t(q), fixed[2 * k + 1] = uint32_t(q >> 32), ++k;
    }
  glCreateBuffers(1, &w.buffer);
  reduceUpload(w.buffer, fixed.size() * sizeof(uint32_t), fixed.data());
  return windows_.emplace(&weights, std::move(w)).first->second;
}

void GLReduce::touch(const std::vector<View>& views, const std::vector<std::vector<double>>& weights,
                     std::vector<uint32_t>& touched, std::vector<double>& acc) {
  std::vector<GLuint>& textures = textures_;
  textures.resize(views.size());
  for (size_t v = 0; v < views.size(); ++v) textures[v] = gl_.renderToTexture(views[v], int(v));
  profile::Scope reduceTime(profile::GpuReduce);
  const WindowWeights& w = weightsFor(weights);
  current_ = &w, views_ = views.size();
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  glUseProgram(touchProgram_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, w.buffer);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, accBuffer_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, flagBuffer_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, listBuffer_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, outBuffer_);
  glProgramUniform1ui(touchProgram_, reduceLoc(touchProgram_, "patchCount"), patchCount_);
  for (size_t v = 0; v < views.size(); ++v) {
    if (views[v].pixelCount() == 0) continue;
    glBindImageTexture(0, textures[v], 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
    glProgramUniform2i(touchProgram_, reduceLoc(touchProgram_, "size"), views[v].width, views[v].height);
    glProgramUniform1ui(touchProgram_, reduceLoc(touchProgram_, "offset"), w.offset[v]);
    glDispatchCompute(GLuint((views[v].width + 15) / 16), GLuint((views[v].height + 15) / 16), 1);
  }
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  uint32_t count = 0;
  glGetNamedBufferSubData(listBuffer_, 0, sizeof count, &count);
  std::vector<uint32_t> list(count), sums(2 * size_t(count));
  if (count > 0) {
    glUseProgram(gatherProgram_);
    glDispatchCompute((count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
    glGetNamedBufferSubData(listBuffer_, sizeof(uint32_t), GLsizeiptr(count * sizeof(uint32_t)), list.data());
    glGetNamedBufferSubData(outBuffer_, 0, GLsizeiptr(sums.size() * sizeof(uint32_t)), sums.data());
    const GLuint zero = 0;
    glClearNamedBufferSubData(listBuffer_, GL_R32UI, 0, sizeof(uint32_t), GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  }
  reduceCheck("touched sums");
  for (uint32_t k = 0; k < count; ++k) {
    touched.push_back(list[k]);
    acc[list[k]] += fromFixed(sums[2 * k], sums[2 * k + 1], w.shift);
  }
}

void GLReduce::coverage(const std::vector<View>& views, const std::vector<uint32_t>& touched, double near,
                        std::vector<PatchCoverage>& out) {
  profile::Scope setupTime(profile::GpuJobs);
  out.assign(touched.size(), PatchCoverage{});
  if (touched.empty()) return;
  // Jobs (touched patch, view) and their tiles, view by view, set up with the CPU's own projection.
  std::vector<double> jobD;
  std::vector<int32_t> jobI;
  std::vector<uint32_t> tiles;  // (job, first pixel) pairs
  std::vector<size_t> tileStart(views.size() + 1, 0);
  for (size_t v = 0; v < views.size(); ++v) {
    tileStart[v] = tiles.size() / 2;
    for (size_t k = 0; k < touched.size(); ++k) {
      CoverageSetup cs;
      if (!coverageSetup(views[v], patches_[touched[k]], near, cs)) continue;
      const uint32_t job = uint32_t(jobI.size() / 8);
      for (int e = 0; e < 8; ++e) jobD.push_back(e < cs.n ? cs.q[e].x : 0.0), jobD.push_back(e < cs.n ? cs.q[e].y : 0.0);
      jobD.push_back(cs.sign), jobD.push_back(cs.eyeSide);
      const int bw = cs.i1 - cs.i0 + 1, bh = cs.j1 - cs.j0 + 1;
      jobI.insert(jobI.end(), {cs.i0, cs.j0, bw, bh, cs.n, int32_t(k), int32_t(touched[k]), 0});
      for (uint32_t first = 0; first < uint32_t(bw) * uint32_t(bh); first += kTile) tiles.push_back(job), tiles.push_back(first);
    }
  }
  tileStart[views.size()] = tiles.size() / 2;
  setupTime.stop();
  profile::Scope reduceTime(profile::GpuCoverage);
  reduceUpload(jobDBuffer_, jobD.size() * sizeof(double), jobD.data());
  reduceUpload(jobIBuffer_, jobI.size() * sizeof(int32_t), jobI.data());
  reduceUpload(tileBuffer_, tiles.size() * sizeof(uint32_t), tiles.data());
  std::vector<uint32_t> sums(8 * touched.size(), 0);
  reduceUpload(sumBuffer_, sums.size() * sizeof(uint32_t), sums.data());
  const GLuint p = coverageProgram_;
  glUseProgram(p);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, current_->buffer);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, patchBuffer_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, jobDBuffer_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, jobIBuffer_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, tileBuffer_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, sumBuffer_);
  glProgramUniform1ui(p, reduceLoc(p, "patchCount"), patchCount_);
  glProgramUniform1d(p, reduceLoc(p, "nearDepth"), near);
  for (size_t v = 0; v < views.size(); ++v) {
    const uint32_t count = uint32_t(tileStart[v + 1] - tileStart[v]);
    if (count == 0) continue;
    const View& view = views[v];
    glBindImageTexture(0, textures_[v], 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
    glProgramUniform3d(p, reduceLoc(p, "eye"), view.eye.x, view.eye.y, view.eye.z);
    glProgramUniform3d(p, reduceLoc(p, "axisRight"), view.right.x, view.right.y, view.right.z);
    glProgramUniform3d(p, reduceLoc(p, "axisUp"), view.up.x, view.up.y, view.up.z);
    glProgramUniform3d(p, reduceLoc(p, "axisForward"), view.forward.x, view.forward.y, view.forward.z);
    glProgramUniform2d(p, reduceLoc(p, "planeMin"), view.planeMin.x, view.planeMin.y);
    glProgramUniform2d(p, reduceLoc(p, "planeMax"), view.planeMax.x, view.planeMax.y);
    glProgramUniform2i(p, reduceLoc(p, "size"), view.width, view.height);
    glProgramUniform1ui(p, reduceLoc(p, "offset"), current_->offset[v]);
    glProgramUniform1ui(p, reduceLoc(p, "tileBase"), uint32_t(tileStart[v]));
    glProgramUniform1ui(p, reduceLoc(p, "tileCount"), count);
    glProgramUniform1i(p, reduceLoc(p, "persp"), view.projection == Projection::Perspective ? 1 : 0);
    glDispatchCompute(std::min(count, kMaxGroups), 1, 1);
  }
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  glGetNamedBufferSubData(sumBuffer_, 0, GLsizeiptr(sums.size() * sizeof(uint32_t)), sums.data());
  reduceCheck("coverage sums");
  for (size_t k = 0; k < touched.size(); ++k) {
    const uint32_t* s = &sums[8 * k];
    out[k].expected = fromFixed(s[0], s[1], current_->shift);
    out[k].visible = fromFixed(s[2], s[3], current_->shift);
    out[k].pixels = s[4];
  }
}

void GLReduce::readBack(std::vector<std::vector<uint32_t>>& ids) {
  ids.resize(views_);
  for (size_t v = 0; v < views_; ++v) gl_.readTexture(int(v), ids[v]);
}

}  // namespace firstshot
