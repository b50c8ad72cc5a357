// Embree 3 behind EmbreeScene: build, closest hit, occlusion.
#include "render/scene/embree_scene.h"

#include "render/scene/embree_cutout_filter.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#if defined(__SSE__) || defined(__x86_64__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#define FS_HAVE_SSE 1
#endif

namespace firstshot {

void enableFlushToZero() {
#ifdef FS_HAVE_SSE
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
#endif
}

namespace {

constexpr unsigned kPatchGeometry = 0;  ///< emitter k is geometry 1 + k

void onEmbreeError(void* userPtr, RTCError code, const char* message) {
  if (code == RTC_ERROR_NONE) return;
  auto* last = static_cast<std::string*>(userPtr);
  *last = "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "");
}

RTCRay toRTC(const Ray& r) {
  RTCRay ray;
  ray.org_x = r.o.x, ray.org_y = r.o.y, ray.org_z = r.o.z;
  ray.dir_x = r.d.x, ray.dir_y = r.d.y, ray.dir_z = r.d.z;
  ray.tnear = r.tmin;
  ray.tfar = r.tmax;
  ray.time = 0.0f;
  ray.mask = 0xffffffffu;
  ray.id = 0;
  ray.flags = 0;
  return ray;
}

RTCRayHit toRTCHit(const Ray& r) {
  RTCRayHit rh;
  rh.ray = toRTC(r);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

float maxAbs(const Vec3& v) { return std::max(std::abs(v.x), std::max(std::abs(v.y), std::abs(v.z))); }

}  // namespace

struct EmbreeScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::string lastError;
  std::vector<Vec3> patchNormals;                ///< by patch ID
  /// Where the faces are traced (not the patches): the patch of a face's hit point (null: primitive = patch ID).
  std::shared_ptr<const PatchLocator> locator;
  std::vector<std::vector<Vec3>> emitterNormals; ///< by emitter, by triangle
  GlassPatches glass;                            ///< the thin glass panes (transmittance())
  std::shared_ptr<const PatchCutouts> cutouts;   ///< alpha cut-outs (null: none)
  /// Smallest ray offset, m: 16 float ulps of the largest vertex coordinate (a point interpolated
  /// from the vertices is that accurate), so that offsets scale with the scene.
  float epsFloor = 0.0f;

  /// Fills @p hit from Embree's hit on @p ray at @p t.
  void fill(const Ray& ray, float t, unsigned geomID, unsigned primID, Hit& hit) const {
    hit.t = t;
    hit.p = ray.at(t);
    if (geomID == kPatchGeometry) {
      hit.patch = locator ? locator->locate(primID, hit.p) : primID;
      hit.emitter = hit.triangle = kNoId;
      hit.ng = patchNormals[hit.patch];
    } else {
      hit.patch = kNoId;
      hit.emitter = geomID - 1;
      hit.triangle = primID;
      hit.ng = emitterNormals[hit.emitter][primID];
    }
    hit.eps = eps(hit.p, t * glm::length(ray.d));
  }

  /// Offset for a hit at @p p, @p travelled metres along its ray: the hit point's rounding error
  /// grows with its coordinates, the scene's and the distance travelled.
  float eps(const Vec3& p, float travelled) const { return 1e-5f * maxAbs(p) + epsFloor + 2e-6f * travelled; }

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
  void check(const char* what) const {
    if (!lastError.empty()) throw std::runtime_error(std::string(what) + ": " + lastError);
  }
};

EmbreeScene::EmbreeScene(const PatchMesh& patches, const std::vector<EmitterMesh>& emitters, GlassPatches glass,
                         std::shared_ptr<const PatchCutouts> cutouts, std::shared_ptr<const PatchLocator> locator)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.glass = std::move(glass);
  m.cutouts = std::move(cutouts);
  m.locator = std::move(locator);
  if (m.locator && m.cutouts) throw std::logic_error("EmbreeScene: cut-outs filter patches: trace the patches");
  m.patchNormals.resize(patches.size());
  for (size_t j = 0; j < patches.size(); ++j) m.patchNormals[j] = patches.patches[j].normal;
  if (m.locator && !m.glass.empty()) {  // the panes' filter sees faces: a face is glass where its patches are
    std::vector<uint16_t> paneOfFace(m.locator->faces().size());
    for (uint32_t f = 0; f < paneOfFace.size(); ++f) paneOfFace[f] = m.glass.paneOfPatch[m.locator->patchesOf(f)[0]];
    m.glass.paneOfPatch = std::move(paneOfFace);
  }
  const PatchMesh& traced = m.locator ? m.locator->faces() : patches;
  m.device = rtcNewDevice("verbose=0");
  if (!m.device) throw std::runtime_error("cannot create the Embree device (error " + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(m.device, onEmbreeError, &m.lastError);
  m.scene = rtcNewScene(m.device);
  // Robust: watertight edges between patches that share (bit-identical) vertices.
  // Context filters: allHits() collects every crossing in one traversal.
  rtcSetSceneFlags(m.scene, RTCSceneFlags(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION));
  rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_HIGH);

  // Patches (or faces): one quad primitive each (a triangle repeats its last vertex), so primID = patch (face) ID.
  const size_t n = traced.size();
  if (n > 0) {
    RTCGeometry g = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_QUAD);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4 * n));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(unsigned), n));
    m.check("creating the patch geometry");
    for (size_t j = 0; j < n; ++j) {
      const Patch& p = traced.patches[j];
      for (int k = 0; k < 4; ++k) {
        const Vec3& v = p.v[k < int(p.count) ? k : int(p.count) - 1];
        vb[12 * j + 3 * k + 0] = v.x, vb[12 * j + 3 * k + 1] = v.y, vb[12 * j + 3 * k + 2] = v.z;
      }
      const unsigned b = static_cast<unsigned>(4 * j);
      ib[4 * j + 0] = b, ib[4 * j + 1] = b + 1, ib[4 * j + 2] = b + 2, ib[4 * j + 3] = p.count == 4 ? b + 3 : b + 2;
      for (uint32_t k = 0; k < p.count; ++k) m.epsFloor = std::max(m.epsFloor, 1e-6f * maxAbs(p.v[k]));
    }
    if (m.cutouts) installCutoutFilter(g, *m.cutouts);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(m.scene, g, kPatchGeometry);
    rtcReleaseGeometry(g);
  }

  // Emitters: triangle meshes, geometry 1 + k.
  m.emitterNormals.resize(emitters.size());
  for (size_t k = 0; k < emitters.size(); ++k) {
    const EmitterMesh& e = emitters[k];
    const uint32_t tris = e.triangleCount();
    auto& normals = m.emitterNormals[k];
    normals.resize(tris);
    for (uint32_t t = 0; t < tris; ++t) {
      const Vec3 a = e.vertices[e.indices[3 * t]], b = e.vertices[e.indices[3 * t + 1]], c = e.vertices[e.indices[3 * t + 2]];
      const Vec3 cr = glm::cross(b - a, c - a);
      const float len = glm::length(cr);
      normals[t] = len > 0.0f ? cr / len : Vec3(0, 0, 1);
    }
    if (tris == 0) continue;
    RTCGeometry g = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), e.vertices.size()));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), tris));
    m.check("creating an emitter geometry");
    for (size_t i = 0; i < e.vertices.size(); ++i) {
      vb[3 * i] = e.vertices[i].x, vb[3 * i + 1] = e.vertices[i].y, vb[3 * i + 2] = e.vertices[i].z;
      m.epsFloor = std::max(m.epsFloor, 1e-6f * maxAbs(e.vertices[i]));
    }
    std::copy(e.indices.begin(), e.indices.begin() + 3 * tris, ib);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(m.scene, g, static_cast<unsigned>(1 + k));
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(m.scene);
  m.check("building the Embree scene");
}

EmbreeScene::~EmbreeScene() = default;

bool EmbreeScene::tracesFaces() const { return impl_->locator != nullptr; }

size_t EmbreeScene::tracedPolygons() const {
  return impl_->locator ? impl_->locator->faces().size() : impl_->patchNormals.size();
}

bool EmbreeScene::intersect(const Ray& ray, Hit& hit) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh = toRTCHit(ray);
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  impl_->fill(ray, rh.ray.tfar, rh.hit.geomID, rh.hit.primID, hit);
  return true;
}

namespace {

/// Closest hits of rays[k], k < N, with valid[k] = -1, as one Embree packet of N (8 or 16).
template <int N, typename Packet>
void tracePacket(RTCScene scene, const Ray* rays, int* valid, Packet& rh) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  for (int k = 0; k < N; ++k) {
    const Ray& r = rays[valid[k] ? k : 0];  // inactive lanes: any finite ray (Embree ignores them)
    rh.ray.org_x[k] = r.o.x, rh.ray.org_y[k] = r.o.y, rh.ray.org_z[k] = r.o.z;
    rh.ray.dir_x[k] = r.d.x, rh.ray.dir_y[k] = r.d.y, rh.ray.dir_z[k] = r.d.z;
    rh.ray.tnear[k] = r.tmin, rh.ray.tfar[k] = r.tmax, rh.ray.time[k] = 0.0f;
    rh.ray.mask[k] = 0xffffffffu, rh.ray.id[k] = unsigned(k), rh.ray.flags[k] = 0;
    rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
  }
  if constexpr (N == 8)
    rtcIntersect8(valid, scene, &context, &rh);
  else
    rtcIntersect16(valid, scene, &context, &rh);
}

}  // namespace

void EmbreeScene::intersect16(const Ray* rays, const bool* active, int count, Hit* hits, bool* found) const {
  for (int half = 0; half < 2; ++half) {
    const int k0 = 8 * half;
    if (count <= k0) break;
    alignas(32) RTCRayHit8 rh;
    alignas(32) int valid[8];
    for (int k = 0; k < 8; ++k) valid[k] = k0 + k < count && active[k0 + k] ? -1 : 0;
    tracePacket<8>(impl_->scene, rays + k0, valid, rh);
    for (int k = 0; k < 8 && k0 + k < count; ++k) {
      found[k0 + k] = valid[k] && rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
      if (found[k0 + k]) impl_->fill(rays[k0 + k], rh.ray.tfar[k], rh.hit.geomID[k], rh.hit.primID[k], hits[k0 + k]);
    }
  }
}

bool EmbreeScene::occluded(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r = toRTC(ray);
  rtcOccluded1(impl_->scene, &context, &r);
  return r.tfar < 0.0f;  // Embree sets tfar = -inf on a hit
}

namespace {

/// An intersect context that carries the list allHits() fills (the context must come first).
struct CollectContext {
  RTCIntersectContext context;
  std::vector<std::pair<float, uint64_t>>* hits;  ///< (t, geomID << 32 | primID)
};

void collectHit(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<const CollectContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const uint64_t id = (uint64_t(RTCHitN_geomID(args->hit, args->N, i)) << 32) | RTCHitN_primID(args->hit, args->N, i);
    c->hits->emplace_back(RTCRayN_tfar(args->ray, args->N, i), id);
    args->valid[i] = 0;  // reject: the traversal goes on to the next candidate
  }
}

}  // namespace

void EmbreeScene::allHits(const Ray& ray, std::vector<Hit>& out) const {
  std::vector<std::pair<float, uint64_t>> hits;
  CollectContext c;
  rtcInitIntersectContext(&c.context);
  c.context.filter = collectHit;
  c.hits = &hits;
  RTCRayHit rh = toRTCHit(ray);
  rtcIntersect1(impl_->scene, &c.context, &rh);
  std::sort(hits.begin(), hits.end());
  for (size_t k = 0; k < hits.size(); ++k) {
    if (k > 0 && hits[k].second == hits[k - 1].second) continue;  // the same primitive again
    Hit hit;
    impl_->fill(ray, hits[k].first, unsigned(hits[k].second >> 32), unsigned(hits[k].second), hit);
    out.push_back(hit);
  }
}

namespace {

/// An occlusion context that multiplies the thin glass panes' transmittance (transmittance()).
struct GlassContext {
  RTCIntersectContext context;  ///< first, as Embree requires
  const GlassPatches* glass;
  const Vec3* dir;              ///< the ray's direction
  float tolerance;              ///< two pane hits closer than this in t are one
  Color T{1.0f};
  float counted[8];             ///< the t of the panes multiplied so far (the first 8)
  int n = 0;
};

void crossGlass(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<GlassContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const unsigned geom = RTCHitN_geomID(args->hit, args->N, i);
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    const uint16_t pane = geom == kPatchGeometry ? c->glass->paneOfPatch[prim] : 0;
    if (pane == 0) continue;  // opaque: accept, the traversal ends
    const float t = RTCRayN_tfar(args->ray, args->N, i);
    bool seen = false;
    for (int k = 0; k < std::min(c->n, 8); ++k) seen = seen || std::abs(c->counted[k] - t) <= c->tolerance;
    if (!seen) {
      const Vec3 ng(RTCHitN_Ng_x(args->hit, args->N, i), RTCHitN_Ng_y(args->hit, args->N, i), RTCHitN_Ng_z(args->hit, args->N, i));
      const float cosTheta = std::abs(glm::dot(ng, *c->dir)) / (glm::length(ng) * glm::length(*c->dir));
      c->T *= c->glass->panes[pane - 1u].transmittance(cosTheta);
      if (c->n < 8) c->counted[c->n] = t;
      ++c->n;
    }
    if (maxComponent(c->T) > 0.0f) args->valid[i] = 0;  // reject: go on to the next candidate
  }
}

}  // namespace

bool EmbreeScene::hasGlass() const { return !impl_->glass.empty(); }

Color EmbreeScene::transmittance(const Ray& ray) const {
  if (impl_->glass.empty()) return occluded(ray) ? Color(0.0f) : Color(1.0f);
  GlassContext c;
  rtcInitIntersectContext(&c.context);
  c.context.filter = crossGlass;
  c.glass = &impl_->glass;
  c.dir = &ray.d;
  const float len = glm::length(ray.d);
  c.tolerance = len > 0.0f ? impl_->eps(ray.o, 0.0f) / len + 1e-6f * std::abs(ray.tmax < 1e30f ? ray.tmax : 0.0f) : 0.0f;
  RTCRay r = toRTC(ray);
  rtcOccluded1(impl_->scene, &c.context, &r);
  return r.tfar < 0.0f ? Color(0.0f) : c.T;
}

size_t EmbreeScene::intersectRaw(const Ray* rays, size_t count) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  size_t hits = 0;
  for (size_t i = 0; i < count; ++i) {
    RTCRayHit rh = toRTCHit(rays[i]);
    rtcIntersect1(impl_->scene, &context, &rh);
    hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }
  return hits;
}

size_t EmbreeScene::intersectRawPackets(const Ray* rays, size_t count) const {
  size_t hits = 0;
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  for (size_t first = 0; first < count; first += 16) {
    for (int k = 0; k < 16; ++k) valid[k] = first + size_t(k) < count ? -1 : 0;
    tracePacket<16>(impl_->scene, rays + first, valid, rh);
    for (int k = 0; k < 16; ++k) hits += valid[k] && rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
  }
  return hits;
}

size_t EmbreeScene::intersectRawStream(const Ray* rays, size_t count) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  std::vector<RTCRayHit> stream(count);
  for (size_t i = 0; i < count; ++i) stream[i] = toRTCHit(rays[i]);
  rtcIntersect1M(impl_->scene, &context, stream.data(), static_cast<unsigned>(count), sizeof(RTCRayHit));
  size_t hits = 0;
  for (const RTCRayHit& h : stream) hits += h.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  return hits;
}

}  // namespace firstshot
