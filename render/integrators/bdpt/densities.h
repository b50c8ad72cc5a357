#pragma once
/// @file densities.h
/// The area densities of bidirectional path tracing: with which density a vertex samples the next
/// one (BSDF, emission or camera directions converted to area), for the forward and reverse
/// densities of the subpaths and the MIS weights of every strategy (docs/bdpt.md).
#include <vector>

#include "render/scene/camera.h"
#include "render/integrators/common/subpath_vertex.h"
#include "render/lights/light_emission.h"
#include "render/scene/render_scene.h"

namespace firstshot {

class BdptDensities {
 public:
  /// All three must outlive the object.
  BdptDensities(const RenderScene& scene, const EmissionSampler& emission, const Camera& camera)
      : scene_(scene), emission_(emission), camera_(camera) {}

  /// Density with which @p cur, reached from @p prev (nullptr when @p cur is a subpath's vertex 0),
  /// samples @p next, as an area density at @p next (1/m²; per unit solid angle, 1/sr, when @p next is
  /// a directional light). Camera: the pinhole's direction density over the whole film,
  /// 1/(A_film·cos³θ); light: the emission direction's (directional: the beam's area density
  /// p_pos·|cos| at @p next); surface: the BSDF's, 0 for a delta BSDF. Light choice not included.
  float pdf(const SubpathVertex* prev, const SubpathVertex& cur, const SubpathVertex& next) const;
  /// Density of @p v as a light subpath's origin, p_light·p_pos (1/m²): a Kind::Light vertex, or a
  /// surface vertex on an emitter (the camera subpath meeting it); 0 if it is none.
  float pdfOrigin(const SubpathVertex& v) const;
  /// The emitter index (EmissionSampler) of a surface vertex on an area light's geometry, or on a
  /// lit patch in table mode (the side facing v.wi; kNoId if that side does not emit).
  uint32_t lightOf(const SubpathVertex& v) const;
  /// Sets pdfFwd (from vertex 1 on) and the pdfRev that the subpath itself determines (vertices
  /// 0 … n−3) of a traced subpath; vertex 0's pdfFwd is left as it is.
  void setDensities(std::vector<SubpathVertex>& path) const;

  const RenderScene& scene() const { return scene_; }
  const EmissionSampler& emission() const { return emission_; }
  const Camera& camera() const { return camera_; }

 private:
  const RenderScene& scene_;
  const EmissionSampler& emission_;
  const Camera& camera_;
};

}  // namespace firstshot
