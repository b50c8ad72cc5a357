#pragma once
/// @file subpath_vertex.h
/// A vertex of a camera or light subpath, with the area densities of having been sampled from
/// either side, which bidirectional path tracing's MIS weights are built from (docs/bdpt.md). The
/// camera-side small lights (small_lights.h) read camera subpaths of it, for BDPT and light tracing.
#include <cstdint>

#include "common/util/math.h"
#include "render/scene/ray.h"

namespace firstshot {

/// One vertex of a camera or light subpath (docs/bdpt.md). Subpaths are ordered from their
/// endpoint: vertex 0 is the pinhole (camera subpath) or the point on the light (light subpath).
struct SubpathVertex {
  enum class Kind : uint8_t { Camera, Light, Surface };
  Kind kind = Kind::Surface;
  /// p and ng (area light: front normal; directional light: the travel direction), eps, emitter.
  Hit hit;
  Vec3 wi{0.0f};  ///< unit direction to the previous vertex of the same subpath; 0 at vertex 0
  /// Throughput arriving at the vertex, before its BSDF: camera subpath W_e·Π(f·cos/pdf) (1 at the
  /// first hit, dimensionless); light subpath the particle's power, W (vertex 0: Le/(p_light·p_pos)).
  Color beta{0.0f};
  /// Area density of the vertex when sampled by its own subpath from the previous vertex, 1/m²
  /// (0 after a delta vertex: MIS maps it to 1). Vertex 0 of a light subpath: p_light·p_pos.
  float pdfFwd = 0;
  /// Area density of the vertex when sampled from the other side (from the next vertex of its own
  /// subpath), 1/m²; the connection vertices' are set per strategy by misWeight().
  float pdfRev = 0;
  uint32_t material = kNoId;  ///< surfaces only
  uint32_t light = kNoId;     ///< Kind::Light: index in LightSet::lights()
  bool delta = false;         ///< a delta BSDF (mirror, glass): no connection through it
  bool deltaLight = false;    ///< Kind::Light: a point, spot or directional light
  bool deltaDirection = false;  ///< Kind::Light: a directional light (hit.ng is its travel direction)
  /// Kind::Light: a luminaire's exit patch (EmissionSampler::isExit), on a face of its box in empty space, which no
  /// camera subpath meets (rays see through the box): no strategy s = 0 makes its paths.
  bool exitPatch = false;

  /// True if densities towards the vertex are per unit area of a surface (take its cosine).
  bool onSurface() const { return kind == Kind::Surface || (kind == Kind::Light && !deltaLight); }
};

}  // namespace firstshot
