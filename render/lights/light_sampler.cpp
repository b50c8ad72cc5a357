// Light sampling: the emitters, their trees, and the choice of one (light_sampler.h).
#include "render/lights/light_sampler.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "common/sampling/sampling.h"
#include "render/firstshot/patch_emitters.h"

namespace firstshot {

namespace {

constexpr int kPatchLeaf = 8;  ///< patch emitters per leaf of a light tree at most

inline float meanOf(const Color& c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }

LightBounds surfaceBounds(const Vec3* v, int count, const Vec3& normal, float phi) {
  LightBounds b;
  b.lo = b.hi = v[0];
  for (int i = 1; i < count; ++i) b.lo = glm::min(b.lo, v[i]), b.hi = glm::max(b.hi, v[i]);
  b.w = normal;
  b.cosO = 1.0f;  // one normal
  b.cosE = 0.0f;  // a hemisphere around it
  b.phi = phi;
  return b;
}

}  // namespace

float LightSampler::Group::pDirectional() const {
  const uint32_t beside = besideCount();
  if (beside == 0) return 0.0f;
  return float(beside) / float(beside + (tree.empty() ? 0 : 1));
}

void LightSampler::addLight(Group& g, GroupId id, uint32_t l, std::vector<LightBounds>& bounds) {
  const LightSet& lights = scene_->lights();
  const RenderLight& light = lights.lights()[l];
  lightGroup_[l] = id;
  lightFirst_[l] = static_cast<uint32_t>(g.emitters.size());
  LightBounds b;
  switch (light.type) {
    case LightType::Directional:
      g.directional.push_back(l);
      return;
    case LightType::Point:
    case LightType::Spot:
      b.lo = b.hi = light.position;
      b.phi = meanOf(light.intensity) * 4.0f * kPiF;
      if (light.type == LightType::Spot && !light.desc.ies) {  // IES tables: the whole sphere
        const float inner = float(glm::radians(light.desc.innerAngleDeg));
        const float outer = float(glm::radians(light.desc.outerAngleDeg));
        b.w = light.direction;
        b.cosO = std::cos(inner);
        b.cosE = std::cos(std::max(outer - inner, 1e-3f));
      }
      g.emitters.push_back({Emitter::Kind::Light, l, 0, 0.0f});
      bounds.push_back(b);
      return;
    case LightType::Area: {
      const EmitterMesh& m = lights.emitterMeshes()[light.emitter];
      for (uint32_t t = 0; t < m.triangleCount(); ++t) {
        const Vec3 v[3] = {m.vertices[m.indices[3 * t]], m.vertices[m.indices[3 * t + 1]], m.vertices[m.indices[3 * t + 2]]};
        const Vec3 c = glm::cross(v[1] - v[0], v[2] - v[0]);
        const float len = glm::length(c);
        const float area = 0.5f * len;
        const Vec3 normal = len > 0.0f ? c / len : Vec3(0, 0, 1);
        triangles_.push_back({v[0], v[1] - v[0], v[2] - v[0], normal, t});
        g.emitters.push_back({Emitter::Kind::Triangle, l, uint32_t(triangles_.size() - 1), area});
        const Color le = light.textured ? light.triangleRadiance[t] : light.radiance;  // its texels' mean
        bounds.push_back(surfaceBounds(v, 3, normal, len > 0.0f ? meanOf(le) * kPiF * area : 0.0f));
      }
      return;
    }
  }
}

void LightSampler::addPatches(Group& g, GroupId id, std::vector<LightBounds>& bounds) {
  const FirstShotTable& table = *scene_->firstShot();
  const std::vector<Color> side = table.sideIrradiance();
  const PatchMesh& mesh = scene_->mesh();
  patchGroup_ = id;
  patchSide_.assign(2 * size_t(mesh.size()), kNoId);
  for (uint32_t j = 0; j < mesh.size(); ++j) {
    const Patch& p = mesh.patches[j];
    for (uint32_t s = 0; s < 2; ++s) {
      const float phi = patchSidePower(*scene_, side, j, s);  // 0 for mirrors and glass
      if (!(phi > 0.0f)) continue;
      patchSide_[2 * size_t(j) + s] = static_cast<uint32_t>(g.emitters.size());
      g.emitters.push_back({Emitter::Kind::Patch, j, s, float(p.area)});
      bounds.push_back(surfaceBounds(p.v, int(p.count), s == 0 ? p.normal : -p.normal, phi));
      ++patchCount_;
    }
  }
}

void LightSampler::addExits(Group& g, std::vector<LightBounds>& bounds) {
  const LuminaireBoxes& boxes = scene_->luminaires();
  // One emitter per luminaire, bounded by its box in every direction; next_event.cpp then chooses a face facing the
  // receiver and a patch by power (LuminaireBoxes::choosePatch): a short descent, and no patch it cannot see.
  // Its specular light, a point at its centre sending light every way, is one more.
  exitEmitter_.assign(boxes.items().size(), kNoId);
  for (uint32_t i = 0; i < boxes.items().size(); ++i) {
    const Luminaire& lum = boxes.items()[i];
    const float phi = meanOf(lum.exitPower);
    if (phi > 0.0f) {
      LightBounds b;
      b.lo = lum.lo, b.hi = lum.hi, b.phi = phi;  // cosO = −1: every direction
      exitEmitter_[i] = uint32_t(g.emitters.size());
      g.emitters.push_back({Emitter::Kind::Exit, i, i, 0.0f});
      bounds.push_back(b);
    }
    const float specular = meanOf(lum.specularPower);
    if (specular > 0.0f) {
      LightBounds b;
      b.lo = b.hi = lum.centre, b.phi = specular;
      g.emitters.push_back({Emitter::Kind::Gonio, i, i, 0.0f});
      bounds.push_back(b);
    }
  }
}

void LightSampler::build(const RenderScene& scene, const FirstShotLighting& firstShot, LightStrategy strategy,
                         bool patchEmitters, bool visibility, const std::vector<uint8_t>* include, bool infinite,
                         bool luminaires) {
  // The same arguments make the same sampler (the lighting is only kept, for the patches' radiance): a scene's
  // integrators share one build (render/scene/scene_memo.h), its visibility factors above all. Luminaires asked for
  // in a scene without them (or for another strategy than the tree) change nothing: the key says so, or the pilot
  // built the patches' visibility twice (Bitterli's box with its table: 0.95 s each, of a 3.1-s pilot).
  luminaires = luminaires && strategy == LightStrategy::Tree && !scene.luminaires().empty();
  std::string key{char('0' + int(strategy)), char('0' + patchEmitters), char('0' + visibility), char('0' + infinite),
                  char('0' + luminaires), include ? '+' : '-'};
  if (include)
    for (uint8_t in : *include) key += in ? '1' : '0';
  if (const std::shared_ptr<const LightSampler> kept = scene.memo().find<LightSampler>(key)) {
    *this = *kept;
    firstShot_ = &firstShot;
    return;
  }
  buildAnew(scene, firstShot, strategy, patchEmitters, visibility, include, infinite, luminaires);
  scene.memo().keep(key, std::make_shared<const LightSampler>(*this));
}

void LightSampler::buildAnew(const RenderScene& scene, const FirstShotLighting& firstShot, LightStrategy strategy,
                             bool patchEmitters, bool visibility, const std::vector<uint8_t>* include, bool infinite,
                             bool luminaires) {
  scene_ = &scene;
  firstShot_ = &firstShot;
  strategy_ = strategy;
  patchCount_ = 0;
  patchGroup_ = kNone;
  for (Group& g : groups_) g = Group();
  triangles_.clear();
  const size_t n = scene.lights().lights().size();
  lightGroup_.assign(n, kNone);
  lightFirst_.assign(n, 0);
  included_.assign(n, 1);
  luminaires_ = luminaires;  // as build() reduced it to what the scene has
  exitEmitter_.clear();
  if (include)
    for (size_t l = 0; l < n; ++l) included_[l] = l < include->size() && (*include)[l] != 0;
  std::vector<LightBounds> bounds[kGroups];
  if (strategy == LightStrategy::Tree)
    for (uint32_t l = 0; l < n; ++l) {
      if (!included_[l]) continue;
      const GroupId id = luminaires_ && scene.luminaires().ofLight(l) >= 0 ? kInner
                         : scene.lights().lights()[l].replaced           ? kReplaced
                                                                         : kKept;
      addLight(groups_[id], id, l, bounds[id]);
    }
  // The infinite light: never replaced, so a kept light; left out of a sampler over a subset of the lights unless
  // asked for (the irradiance cache's direct lights).
  if (strategy == LightStrategy::Tree && scene.lights().environment() && (!include || infinite))
    groups_[kKept].environment = true;
  if (patchEmitters && scene.firstShot()) {
    addPatches(groups_[kPatches], kPatches, bounds[kPatches]);
  }
  if (luminaires_) addExits(groups_[kKept], bounds[kKept]);
  for (int g = 0; g < kGroups; ++g) {
    // Patches are small and many, and the triangles of one area light lie together: up to
    // kPatchLeaf of either share a leaf, chosen there by power, which spares the descent.
    std::vector<uint32_t> groupable(groups_[g].emitters.size(), 0);
    for (size_t e = 0; e < groupable.size(); ++e) {
      const Emitter& em = groups_[g].emitters[e];
      if (em.kind == Emitter::Kind::Patch) groupable[e] = 1;  // a group of its own: no lights in it
      if (em.kind == Emitter::Kind::Triangle) groupable[e] = em.index + 1;
    }
    groups_[g].tree = LightTree(bounds[g], &groupable, kPatchLeaf);
  }
  if (visibility) buildVisibility();
}

Color LightSampler::emitterRadiance(const Emitter& e, const Vec2& u) const {
  const Vec3 bary = squareToUniformTriangle(u);  // as emitterPoint
  const LightSet& lights = scene_->lights();
  return lights.radianceAt(lights.lights()[e.index], triangles_[e.sub].meshTriangle, Vec2(bary.y, bary.z));
}

Vec3 LightSampler::emitterPoint(const Emitter& e, const Vec2& u) const {
  const LightSet& lights = scene_->lights();
  switch (e.kind) {
    case Emitter::Kind::Light:
      return lights.lights()[e.index].position;
    case Emitter::Kind::Triangle: {
      const TriangleEmitter& t = triangles_[e.sub];
      const Vec3 bary = squareToUniformTriangle(u);
      return t.a + bary.y * t.e1 + bary.z * t.e2;
    }
    case Emitter::Kind::Patch:
      return samplePatchPoint(scene_->mesh().patches[e.index], u);
    case Emitter::Kind::Exit:  // a point of the luminaire's box surface (next_event.cpp chooses NEE's patch)
    case Emitter::Kind::Gonio: {  // (its shadow rays stop at the box: what the visibility grid's rays aim at)
      const Luminaire& lum = scene_->luminaires().items()[e.index];
      const int f = std::min(5, int(u.x * 6.0f)), a = f / 2;
      Vec3 p(0.0f);
      p[a] = (f & 1) ? lum.hi[a] : lum.lo[a];
      p[(a + 1) % 3] = lum.lo[(a + 1) % 3] + (u.x * 6.0f - float(f)) * (lum.hi[(a + 1) % 3] - lum.lo[(a + 1) % 3]);
      p[(a + 2) % 3] = lum.lo[(a + 2) % 3] + u.y * (lum.hi[(a + 2) % 3] - lum.lo[(a + 2) % 3]);
      return p;
    }
    case Emitter::Kind::Environment:
      break;  // a direction, no point
  }
  return Vec3(0.0f);
}

float LightSampler::environmentPmf() const {
  if (!scene_ || !scene_->lights().environment()) return 0.0f;
  if (strategy_ == LightStrategy::All) {
    const bool all = std::all_of(included_.begin(), included_.end(), [](uint8_t i) { return i != 0; });
    return all ? 1.0f : 0.0f;
  }
  const Group& g = groups_[kKept];
  return g.environment ? g.pDirectional() / float(g.besideCount()) : 0.0f;
}

float LightSampler::exitPmf(const Vec3& x, const Vec3& n, uint32_t exit, float& area) const {
  if (!luminaires_) return 0.0f;
  const LuminaireBoxes& boxes = scene_->luminaires();
  const uint32_t i = boxes.exitLuminaire(exit);
  if (exitEmitter_[i] == kNoId) return 0.0f;
  const uint32_t k = exit - boxes.exitFirst(i);
  const float p = boxes.patchProbability(i, x, k);
  if (!(p > 0.0f)) return 0.0f;
  area = boxes.items()[i].patch(k).area;
  return selectProbability(groups_[kKept], x, n, exitEmitter_[i]) * p;
}

uint32_t LightSampler::patchEmitter(const Hit& y, const Vec3& x) const {
  if (patchGroup_ == kNone || !y.onPatch()) return kNoId;
  const Patch& p = scene_->mesh().patches[y.patch];
  const uint32_t side = glm::dot(x - y.p, p.normal) >= 0.0f ? 0 : 1;
  return patchSide_[2 * size_t(y.patch) + side];
}

float LightSampler::selectProbability(const Group& g, const Vec3& x, const Vec3& n, uint32_t emitter) const {
  return (1.0f - g.pDirectional()) * g.tree.pmf(x, n, emitter);
}

float LightSampler::pmf(const Vec3& x, const Vec3& n, const Hit& y, float& area) const {
  if (y.onPatch()) {
    const uint32_t e = patchEmitter(y, x);
    if (e == kNoId) return 0.0f;
    const Group& g = groups_[patchGroup_];
    area = g.emitters[e].area;
    return selectProbability(g, x, n, e);
  }
  const LightSet& lights = scene_->lights();
  const uint32_t l = static_cast<uint32_t>(&lights.emitterLight(y.emitter) - lights.lights().data());
  if (!included_[l]) return 0.0f;
  if (strategy_ == LightStrategy::All) {
    area = float(lights.lights()[l].area);
    return 1.0f;
  }
  const Group& g = groups_[lightGroup_[l]];
  const uint32_t e = lightFirst_[l] + y.triangle;
  area = g.emitters[e].area;
  return selectProbability(g, x, n, e);
}

bool LightSampler::sample(LightGroup group, const Vec3& x, const Vec3& n, float u, SampledEmitter& out,
                          float* rest) const {
  const Group& g = groups_[size_t(group)];
  float uSelect = u;
  const float pDir = g.pDirectional();
  if (pDir > 0.0f) {
    if (uSelect < pDir) {
      const uint32_t count = g.besideCount();
      const float scaled = uSelect / pDir * float(count);
      const uint32_t k = std::min(count - 1, static_cast<uint32_t>(scaled));
      if (rest) *rest = std::clamp(scaled - float(k), 0.0f, 0x1.fffffep-1f);
      out = k < g.directional.size() ? SampledEmitter{{Emitter::Kind::Light, g.directional[k], 0, 0.0f}, pDir / float(count)}
                                     : SampledEmitter{{Emitter::Kind::Environment, 0, 0, 0.0f}, pDir / float(count)};
      return true;
    }
    uSelect = std::min((uSelect - pDir) / (1.0f - pDir), 0x1.fffffep-1f);
  }
  uint32_t e;
  float pmf;
  if (!g.tree.sample(x, n, uSelect, e, pmf, rest)) return false;
  out = {g.emitters[e], pmf * (1.0f - pDir)};
  return true;
}

}  // namespace firstshot
