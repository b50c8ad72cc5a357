#pragma once
/// @file embree_triangles.h
/// A triangle soup as the one geometry of an Embree scene: the luminaires' particle scene
/// (luminaire_trace.cpp) and the glass panes (pane_transmittance.cpp).
#include <embree3/rtcore.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace firstshot {

/// Attaches the triangles of @p vertices (x, y, z of three corners per triangle; triangle k is primID k) to
/// @p scene of @p device as one geometry, when there are any, and commits @p scene. Throws std::runtime_error
/// @p cannotAllocate when Embree gives no buffers, @p buildFailed when the build reports an error.
inline void commitTriangleSoup(RTCDevice device, RTCScene scene, const std::vector<float>& vertices,
                               const char* cannotAllocate, const char* buildFailed) {
  const size_t n = vertices.size() / 9;
  if (n > 0) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
    if (!vb || !ib) throw std::runtime_error(cannotAllocate);
    std::copy(vertices.begin(), vertices.end(), vb);
    for (size_t k = 0; k < 3 * n; ++k) ib[k] = static_cast<unsigned>(k);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(scene);
  if (rtcGetDeviceError(device) != RTC_ERROR_NONE) throw std::runtime_error(buildFailed);
}

}  // namespace firstshot
