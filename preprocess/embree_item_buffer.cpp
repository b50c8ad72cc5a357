#include "preprocess/embree_item_buffer.h"

#include "preprocess/profile.h"

#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace firstshot {

namespace {

[[noreturn]] void embreeFail(RTCDevice device, const char* what) {
  const RTCError e = device ? rtcGetDeviceError(device) : RTC_ERROR_UNKNOWN;
  throw std::runtime_error(std::string("Embree item buffer: ") + what + " failed (RTCError " + std::to_string(e) + ")");
}

/// Sets FTZ and DAZ on the calling thread and restores the previous MXCSR when done.
class FlushDenormals {
 public:
  FlushDenormals() : saved_(_mm_getcsr()) {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
  }
  ~FlushDenormals() { _mm_setcsr(saved_); }
  FlushDenormals(const FlushDenormals&) = delete;
  FlushDenormals& operator=(const FlushDenormals&) = delete;

 private:
  unsigned int saved_;
};

/// Per-pixel ray setup shared by every mode.
struct RaySetup {
  const View& view;
  float tnear, tfar;
  void operator()(int i, int j, float* org, float* dir) const {
    const Vec3d o = view.pixelOrigin(i, j), d = view.pixelDirection(i, j);
    org[0] = float(o.x), org[1] = float(o.y), org[2] = float(o.z);
    dir[0] = float(d.x), dir[1] = float(d.y), dir[2] = float(d.z);
  }
};

/// A single ray with no hit yet.
void fillRay(RTCRayHit& rh, const float org[3], const float dir[3], float tnear, float tfar) {
  rh.ray.org_x = org[0], rh.ray.org_y = org[1], rh.ray.org_z = org[2];
  rh.ray.dir_x = dir[0], rh.ray.dir_y = dir[1], rh.ray.dir_z = dir[2];
  rh.ray.tnear = tnear;
  rh.ray.tfar = tfar;
  rh.ray.time = 0;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

/// Lane @p k of a packet's rays (RTCRay8, RTCRay16) set to @p r.
template <typename Rays>
void setLane(Rays& rays, int k, const RTCRay& r) {
  rays.org_x[k] = r.org_x, rays.org_y[k] = r.org_y, rays.org_z[k] = r.org_z;
  rays.dir_x[k] = r.dir_x, rays.dir_y[k] = r.dir_y, rays.dir_z[k] = r.dir_z;
  rays.tnear[k] = r.tnear, rays.tfar[k] = r.tfar, rays.time[k] = r.time;
  rays.mask[k] = r.mask, rays.id[k] = r.id, rays.flags[k] = r.flags;
}
/// Lane @p k of a packet's hits (RTCHit8, RTCHit16): none yet.
template <typename Hits>
void clearLaneHit(Hits& hits, int k) {
  hits.geomID[k] = RTC_INVALID_GEOMETRY_ID;
  hits.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
}

/// Traces W×H tiles with packets of N = W·H rays (RTCRayHit8 or RTCRayHit16).
template <int N, int TW, typename Packet, typename Fn>
void tracePackets(RTCScene scene, const RaySetup& setup, const std::vector<uint32_t>& triPatch,
                  std::vector<uint32_t>& ids, Fn intersect) {
  constexpr int TH = N / TW;
  const View& v = setup.view;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) Packet p;
  alignas(64) int valid[N];
  for (int ty = 0; ty < v.height; ty += TH)
    for (int tx = 0; tx < v.width; tx += TW) {
      for (int k = 0; k < N; ++k) {
        const int i = tx + k % TW, j = ty + k / TW;
        valid[k] = (i < v.width && j < v.height) ? -1 : 0;
        float org[3] = {0, 0, 0}, dir[3] = {0, 0, 1};
        if (valid[k]) setup(i, j, org, dir);
        RTCRayHit rh;
        fillRay(rh, org, dir, setup.tnear, setup.tfar);
        setLane(p.ray, k, rh.ray);
        clearLaneHit(p.hit, k);
      }
      intersect(valid, scene, &ctx, &p);
      for (int k = 0; k < N; ++k) {
        if (!valid[k] || p.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) continue;
        const int i = tx + k % TW, j = ty + k / TW;
        ids[static_cast<size_t>(j) * v.width + i] = triPatch[p.hit.primID[k]];
      }
    }
}

/// The alpha cut-outs' filter: rejects each valid candidate hit on a cut-out patch where the surface is
/// absent. Embree calls it for candidate hits in any order; rejecting is all it does.
void rejectCutoutHoles(const RTCFilterFunctionNArguments* args) {
  const auto* f = static_cast<const std::pair<const PatchCutouts*, const uint32_t*>*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const uint32_t patch = f->second[RTCHitN_primID(args->hit, args->N, i)];
    if (!f->first->cutout(patch)) continue;
    const Vec3 o(RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                 RTCRayN_org_z(args->ray, args->N, i));
    const Vec3 d(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                 RTCRayN_dir_z(args->ray, args->N, i));
    if (!f->first->existsOnRay(patch, o, d, RTCRayN_tfar(args->ray, args->N, i))) args->valid[i] = 0;
  }
}

void initRay(RTCRayHit& rh, const RaySetup& setup, int i, int j) {
  float org[3], dir[3];
  setup(i, j, org, dir);
  fillRay(rh, org, dir, setup.tnear, setup.tfar);
}

}  // namespace

EmbreeItemBuffer::EmbreeItemBuffer(const PatchMesh& mesh, const Bounds3d& sceneBounds, double nearRelative,
                                   EmbreeRayMode mode)
    : EmbreeItemBuffer(ItemGeometry::fromPatches(mesh), sceneBounds, nearRelative, mode) {}

EmbreeItemBuffer::EmbreeItemBuffer(const ItemGeometry& geometry, const Bounds3d& sceneBounds, double nearRelative,
                                   EmbreeRayMode mode, bool robust)
    : triPatch_(geometry.patchIds), bounds_(sceneBounds), near_(itemBufferNear(sceneBounds, nearRelative)),
      mode_(mode), cutouts_(geometry.cutouts) {
  if (geometry.positions.size() != 3 * geometry.patchIds.size())
    throw std::invalid_argument("Embree item buffer: positions must be 3 per triangle");
  FlushDenormals ftz;
  device_ = rtcNewDevice(nullptr);
  if (!device_) embreeFail(nullptr, "rtcNewDevice");
  scene_ = rtcNewScene(device_);
  if (robust) rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_MEDIUM);
  const size_t nTri = geometry.triangleCount();
  if (nTri > 0) {
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * nTri));
    auto* ib = static_cast<uint32_t*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), nTri));
    if (!vb || !ib) embreeFail(device_, "rtcSetNewGeometryBuffer");
    for (size_t k = 0; k < 3 * nTri; ++k) {
      vb[3 * k + 0] = geometry.positions[k].x;
      vb[3 * k + 1] = geometry.positions[k].y;
      vb[3 * k + 2] = geometry.positions[k].z;
      ib[k] = static_cast<uint32_t>(k);
    }
    if (cutouts_) {  // alpha cut-outs: a filter for closest hits and occlusion (none without cut-outs)
      cutoutFilter_ = {cutouts_.get(), triPatch_.data()};
      rtcSetGeometryUserData(geom, &cutoutFilter_);
      rtcSetGeometryIntersectFilterFunction(geom, rejectCutoutHoles);
      rtcSetGeometryOccludedFilterFunction(geom, rejectCutoutHoles);
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(scene_);
  if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) embreeFail(device_, "building the scene");
}

EmbreeItemBuffer::~EmbreeItemBuffer() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

void EmbreeItemBuffer::renderMasked(const View& view, const std::vector<uint8_t>& mask, std::vector<uint32_t>& ids) const {
  ids.assign(view.pixelCount(), kNoPatch);
  const double far = farDepth(view, bounds_);
  if (view.pixelCount() == 0 || !(far > near_) || triPatch_.empty()) return;
  FlushDenormals ftz;
  const RaySetup setup{view, float(near_), float(far)};
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  RTCRayHit rh;
  for (int j = 0; j < view.height; ++j)
    for (int i = 0; i < view.width; ++i) {
      const size_t k = static_cast<size_t>(j) * view.width + i;
      if (!mask[k]) continue;
      initRay(rh, setup, i, j);
      rtcIntersect1(scene_, &ctx, &rh);
      if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) ids[k] = triPatch_[rh.hit.primID];
    }
}

namespace {

/// The ray @p origin + t·@p direction, t in [0, @p tfar], as Embree takes it.
RTCRayHit rayOf(const Vec3d& origin, const Vec3d& direction, double tfar) {
  RTCRayHit rh;
  const float org[3] = {float(origin.x), float(origin.y), float(origin.z)};
  const float dir[3] = {float(direction.x), float(direction.y), float(direction.z)};
  fillRay(rh, org, dir, 0.0f, float(tfar));
  return rh;
}

}  // namespace

uint32_t EmbreeItemBuffer::firstHit(const Vec3d& origin, const Vec3d& direction, double tfar, double& t) const {
  if (triPatch_.empty()) return kNoPatch;
  FlushDenormals ftz;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh = rayOf(origin, direction, tfar);
  rtcIntersect1(scene_, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return kNoPatch;
  t = rh.ray.tfar;
  return triPatch_[rh.hit.primID];
}

bool EmbreeItemBuffer::occluded(const Vec3d& origin, const Vec3d& direction, double tfar) const {
  if (triPatch_.empty()) return false;
  FlushDenormals ftz;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh = rayOf(origin, direction, tfar);
  rtcOccluded1(scene_, &ctx, &rh.ray);
  return rh.ray.tfar < 0.0f;  // Embree sets tfar to −∞ when it finds a hit
}

void EmbreeItemBuffer::firstHits(const Vec3d& origin, const Vec3d* directions, size_t n, uint32_t* out) const {
  if (triPatch_.empty() || n == 0) {
    std::fill(out, out + n, kNoPatch);
    return;
  }
  FlushDenormals ftz;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  alignas(32) RTCRayHit8 packet;
  alignas(32) int valid[8];
  for (size_t k = 0; k < 8; ++k) {
    valid[k] = k < n ? -1 : 0;
    setLane(packet.ray, int(k), rayOf(origin, directions[std::min(k, n - 1)], std::numeric_limits<double>::infinity()).ray);
    clearLaneHit(packet.hit, int(k));
  }
  rtcIntersect8(valid, scene_, &ctx, &packet);
  for (size_t k = 0; k < n; ++k)
    out[k] = packet.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID ? kNoPatch : triPatch_[packet.hit.primID[k]];
}

void EmbreeItemBuffer::occluded(const Vec3d* origins, const Vec3d* directions, double tfar, size_t n,
                                uint8_t* out) const {
  if (triPatch_.empty()) {
    std::fill(out, out + n, uint8_t(0));
    return;
  }
  FlushDenormals ftz;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  for (size_t begin = 0; begin < n; begin += 16) {
    const size_t count = std::min<size_t>(16, n - begin);
    alignas(64) RTCRay16 packet;
    alignas(64) int valid[16];
    for (size_t k = 0; k < 16; ++k) {
      valid[k] = k < count ? -1 : 0;
      const size_t i = begin + std::min(k, count - 1);
      setLane(packet, int(k), rayOf(origins[i], directions[i], tfar).ray);
    }
    rtcOccluded16(valid, scene_, &ctx, &packet);
    for (size_t k = 0; k < count; ++k) out[begin + k] = packet.tfar[k] < 0.0f ? 1 : 0;
  }
}

namespace {

/// What anyPatchNear's query carries to its callback.
struct NearQuery {
  const std::vector<uint32_t>* triPatch;
  const std::function<bool(uint32_t)>* test;
  bool found = false;
};

bool nearCallback(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<NearQuery*>(args->userPtr);
  if (q->found || !(*q->test)((*q->triPatch)[args->primID])) return false;
  q->found = true;
  args->query->radius = 0.0f;  // nothing further is wanted: shrink the query to its centre
  return true;
}

}  // namespace

bool EmbreeItemBuffer::anyPatchNear(const Vec3& centre, float radius, const std::function<bool(uint32_t)>& test) const {
  if (triPatch_.empty()) return false;
  RTCPointQuery query;
  query.x = centre.x, query.y = centre.y, query.z = centre.z;
  query.time = 0.0f;
  query.radius = radius;
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  NearQuery q{&triPatch_, &test};
  rtcPointQuery(scene_, &query, &ctx, nearCallback, &q);
  return q.found;
}

void EmbreeItemBuffer::render(const View& view, std::vector<uint32_t>& ids) {
  profile::Scope time(profile::Render);
  ids.assign(view.pixelCount(), kNoPatch);
  const double far = farDepth(view, bounds_);
  if (view.pixelCount() == 0 || !(far > near_) || triPatch_.empty()) return;
  FlushDenormals ftz;
  const RaySetup setup{view, float(near_), float(far)};
  switch (mode_) {
    case EmbreeRayMode::Packet16:
      tracePackets<16, 4, RTCRayHit16>(scene_, setup, triPatch_, ids,
                                       [](const int* valid, RTCScene s, RTCIntersectContext* c, RTCRayHit16* p) {
                                         rtcIntersect16(valid, s, c, p);
                                       });
      break;
    case EmbreeRayMode::Packet8:
      tracePackets<8, 4, RTCRayHit8>(scene_, setup, triPatch_, ids,
                                     [](const int* valid, RTCScene s, RTCIntersectContext* c, RTCRayHit8* p) {
                                       rtcIntersect8(valid, s, c, p);
                                     });
      break;
    case EmbreeRayMode::Single:
    case EmbreeRayMode::Stream: {
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
      std::vector<RTCRayHit> row(static_cast<size_t>(view.width));
      for (int j = 0; j < view.height; ++j) {
        for (int i = 0; i < view.width; ++i) initRay(row[i], setup, i, j);
        if (mode_ == EmbreeRayMode::Stream) {
          rtcIntersect1M(scene_, &ctx, row.data(), static_cast<unsigned>(row.size()), sizeof(RTCRayHit));
        } else {
          for (RTCRayHit& rh : row) rtcIntersect1(scene_, &ctx, &rh);
        }
        for (int i = 0; i < view.width; ++i)
          if (row[i].hit.geomID != RTC_INVALID_GEOMETRY_ID)
            ids[static_cast<size_t>(j) * view.width + i] = triPatch_[row[i].hit.primID];
      }
      break;
    }
  }
}

}  // namespace firstshot
