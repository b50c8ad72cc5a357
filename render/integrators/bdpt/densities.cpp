// Area densities of bidirectional path tracing.
#include "render/integrators/bdpt/densities.h"

#include <cmath>

namespace firstshot {

namespace {

/// Unit direction from @p from to @p to (a directional light's vertex lies "against its travel").
Vec3 directionTo(const SubpathVertex& from, const SubpathVertex& to) {
  if (to.kind == SubpathVertex::Kind::Light && to.deltaDirection) return -to.hit.ng;
  return glm::normalize(to.hit.p - from.hit.p);
}

}  // namespace

float BdptDensities::pdf(const SubpathVertex* prev, const SubpathVertex& cur, const SubpathVertex& next) const {
  using Kind = SubpathVertex::Kind;
  const bool toDirectional = next.kind == Kind::Light && next.deltaDirection;
  const Vec3 d = next.hit.p - cur.hit.p;
  const float dist2 = glm::dot(d, d);
  if (!toDirectional && !(dist2 > 0.0f)) return 0.0f;
  const Vec3 w = toDirectional ? -next.hit.ng : d / std::sqrt(dist2);
  const float cosNext = next.onSurface() ? std::abs(glm::dot(next.hit.ng, w)) : 1.0f;
  switch (cur.kind) {
    case Kind::Camera: {
      CameraConnection c;
      if (!camera_.connect(next.hit.p, c)) return 0.0f;
      // c.importance = 1/(A_pixel·cos³θ·d²); over the whole film A_film = A_pixel·width·height.
      return c.importance / (float(camera_.width()) * float(camera_.height())) * cosNext;
    }
    case Kind::Light: {
      if (cur.deltaDirection)
        return emission_.pdfPosition(cur.light) * (next.onSurface() ? std::abs(glm::dot(next.hit.ng, cur.hit.ng)) : 1.0f);
      const float pdfDir = emission_.pdfDirection(cur.light, cur.hit.p, cur.hit.ng, w);
      return toDirectional ? pdfDir : pdfDir * cosNext / dist2;
    }
    case Kind::Surface: {
      if (cur.delta || !prev) return 0.0f;
      const Frame frame = scene_.shadingFrame(cur.hit);  // as the BSDF was sampled
      const BSDFQuery q(frame.toLocal(w), frame.toLocal(directionTo(cur, *prev)));
      const float pdfDir = scene_.bsdfAt(cur.hit).pdf(q);
      return toDirectional ? pdfDir : pdfDir * cosNext / dist2;
    }
  }
  return 0.0f;
}

uint32_t BdptDensities::lightOf(const SubpathVertex& v) const {
  if (v.hit.onPatch()) {
    const uint32_t side = glm::dot(v.wi, scene_.mesh().patches[v.hit.patch].normal) >= 0.0f ? 0 : 1;
    return emission_.patchEmitter(v.hit.patch, side);
  }
  const LightSet& lights = scene_.lights();
  return uint32_t(&lights.emitterLight(v.hit.emitter) - lights.lights().data());
}

float BdptDensities::pdfOrigin(const SubpathVertex& v) const {
  const uint32_t e = v.kind == SubpathVertex::Kind::Light ? v.light : lightOf(v);
  return e == kNoId ? 0.0f : emission_.pdfChoice(e) * emission_.pdfPosition(e);
}

void BdptDensities::setDensities(std::vector<SubpathVertex>& path) const {
  const size_t n = path.size();
  for (size_t k = 1; k < n; ++k) path[k].pdfFwd = pdf(k >= 2 ? &path[k - 2] : nullptr, path[k - 1], path[k]);
  for (size_t k = 0; k + 2 < n; ++k) path[k].pdfRev = pdf(&path[k + 2], path[k + 1], path[k]);
}

}  // namespace firstshot
