// The renderer's Embree filter for alpha cut-outs (render/scene/embree_cutout_filter.h).
#include "render/scene/embree_cutout_filter.h"

namespace firstshot {
namespace {

/// Rejects each valid candidate hit on a cut-out patch where the surface is absent.
void rejectCutoutHoles(const RTCFilterFunctionNArguments* args) {
  const auto* cutouts = static_cast<const PatchCutouts*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    if (!cutouts->cutout(prim)) continue;
    const Vec3 o(RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                 RTCRayN_org_z(args->ray, args->N, i));
    const Vec3 d(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                 RTCRayN_dir_z(args->ray, args->N, i));
    if (!cutouts->existsOnRay(prim, o, d, RTCRayN_tfar(args->ray, args->N, i))) args->valid[i] = 0;
  }
}

}  // namespace

void installCutoutFilter(RTCGeometry g, const PatchCutouts& cutouts) {
  rtcSetGeometryUserData(g, const_cast<PatchCutouts*>(&cutouts));
  rtcSetGeometryIntersectFilterFunction(g, rejectCutoutHoles);
  rtcSetGeometryOccludedFilterFunction(g, rejectCutoutHoles);
}

}  // namespace firstshot
