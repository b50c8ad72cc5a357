// Which small lights form luminaires, their boxes and exit patches, and their traced exit distributions (luminaires.h).
#include "preprocess/luminaires.h"

#include <fmt/core.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>

#include "common/sampling/rng.h"
#include "common/sampling/sampling.h"
#include "common/util/progress.h"
#include "preprocess/luminaire_trace.h"

namespace firstshot {
namespace {

/// An axis-aligned box being built up; empty until extended.
struct BoxBuilder {
  Vec3d lo{std::numeric_limits<double>::infinity()}, hi{-std::numeric_limits<double>::infinity()};
  bool empty() const { return !(lo.x <= hi.x); }
  void extend(const Vec3d& p) { lo = glm::min(lo, p), hi = glm::max(hi, p); }
  void extend(const BoxBuilder& b) {
    if (!b.empty()) extend(b.lo), extend(b.hi);
  }
};

/// The bounds of light @p l: its position, or its emissive shape's vertices.
BoxBuilder lightBounds(const SceneDesc& scene, uint32_t l) {
  const LightDesc& light = scene.lights[l];
  BoxBuilder b;
  if (light.type == LightType::Area) {
    for (const Vec3d& v : scene.shapes[size_t(light.shape)].vertices) b.extend(v);
  } else {
    b.extend(light.position);
  }
  return b;
}

/// Sets @p lum's box to @p b grown by the margin (1e-3 of its diagonal + 1e-5 of the scene's, @p sceneDiagonal): a
/// light or surface on its boundary is inside it.
void setBox(Luminaire& lum, const BoxBuilder& b, double sceneDiagonal) {
  const double margin = 1e-3 * glm::length(b.hi - b.lo) + 1e-5 * sceneDiagonal;
  lum.lo = Vec3(b.lo - Vec3d(margin));
  lum.hi = Vec3(b.hi + Vec3d(margin));
}

/// A luminaire of box @p b and its margin (setBox).
Luminaire boxed(std::string name, std::vector<uint32_t> lights, const BoxBuilder& b, double sceneDiagonal) {
  Luminaire lum;
  lum.name = std::move(name);
  lum.lights = std::move(lights);
  std::sort(lum.lights.begin(), lum.lights.end());
  setBox(lum, b, sceneDiagonal);
  return lum;
}

bool overlap(const Luminaire& a, const Luminaire& b) {
  for (int k = 0; k < 3; ++k)
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
  return true;
}

/// Luminaires whose boxes overlap, merged (box union, lights joined, the first one's name) until none do.
void mergeOverlapping(std::vector<Luminaire>& lums, double maxDiagonal) {
  auto named = [](const Luminaire& l) { return l.name.rfind("auto:", 0) != 0; };
  for (bool changed = true; changed;) {
    changed = false;
    for (size_t i = 0; i < lums.size() && !changed; ++i)
      for (size_t j = i + 1; j < lums.size() && !changed; ++j) {
        if (!overlap(lums[i], lums[j])) continue;
        changed = true;
        Luminaire& a = lums[i];
        const Vec3 lo = glm::min(a.lo, lums[j].lo), hi = glm::max(a.hi, lums[j].hi);
        if (glm::length(hi - lo) > maxDiagonal && !(named(a) && named(lums[j]))) {
          // A chain of lamps whose boxes touch (desk lamps on adjacent desks) would become one room-sized box: the
          // detected ones among them stay ordinary small lights.
          if (!named(lums[j])) lums.erase(lums.begin() + long(j));
          if (!named(a)) lums.erase(lums.begin() + long(i));
          continue;
        }
        a.lo = lo, a.hi = hi;
        a.lights.insert(a.lights.end(), lums[j].lights.begin(), lums[j].lights.end());
        std::sort(a.lights.begin(), a.lights.end());
        a.lights.erase(std::unique(a.lights.begin(), a.lights.end()), a.lights.end());
        lums.erase(lums.begin() + long(j));
      }
  }
}

/// The named luminaires: every shape and light of one name, in the order the names first appear.
std::vector<Luminaire> namedLuminaires(const SceneDesc& scene, const std::vector<uint32_t>& smallLights,
                                       double sceneDiagonal, bool quiet) {
  std::vector<std::string> names;
  auto note = [&](const std::string& n) {
    if (!n.empty() && std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
  };
  for (const ShapeDesc& s : scene.shapes) note(s.luminaire);
  for (const LightDesc& l : scene.lights) note(l.luminaire);
  std::vector<Luminaire> out;
  for (const std::string& name : names) {
    BoxBuilder b;
    std::vector<uint32_t> lights;
    for (const ShapeDesc& s : scene.shapes)
      if (s.luminaire == name)
        for (const Vec3d& v : s.vertices) b.extend(v);
    for (uint32_t l = 0; l < scene.lights.size(); ++l) {
      const LightDesc& light = scene.lights[l];
      if (light.luminaire != name || light.type == LightType::Directional) continue;
      b.extend(lightBounds(scene, l));
      if (std::binary_search(smallLights.begin(), smallLights.end(), l))
        lights.push_back(l);
      else if (!quiet)
        std::fprintf(stderr, "%s: luminaire \"%s\": %s is a large light, left to the renderer\n", scene.file.c_str(),
                     name.c_str(), light.name.c_str());
    }
    if (lights.empty()) {
      if (!quiet)
        std::fprintf(stderr, "%s: luminaire \"%s\" has no small light: none made\n", scene.file.c_str(), name.c_str());
      continue;
    }
    out.push_back(boxed(name, std::move(lights), b, sceneDiagonal));
  }
  return out;
}

/// The rule of luminaires.h for one light: its luminaire's box before the margin, or nothing.
std::optional<BoxBuilder> probeLight(const SceneDesc& scene, const ParticleScene& geometry, uint32_t l, uint64_t seed,
                                     double sceneDiagonal) {
  const ParticleSource source(scene, {l}, geometry);
  if (!(maxComponent(source.power()) > 0.0f)) return std::nullopt;
  const BoxBuilder own = lightBounds(scene, l);
  const Vec3d centre = 0.5 * (own.lo + own.hi);
  Sampler sampler(seed, kProbeStream, l);
  struct FirstHit {
    double w;
    Vec3d x;
  };
  std::vector<FirstHit> hits;
  std::vector<double> onward;  // length of the segment after each first hit (a diffuse bounce), m
  double total = 0, glass = 0;
  BoxBuilder glassBox;
  for (int i = 0; i < kProbeParticles; ++i) {
    const EmittedParticle p = source.sample(sampler);
    const Vec2 u = sampler.next2D();
    const double w = (double(p.weight.x) + p.weight.y + p.weight.z) / 3.0;
    total += w;
    ParticleScene::Hit hit;
    // Not a surface the light touches (a point light on a wall): those hits are where the particle starts.
    if (!(w > 0) || !geometry.intersect(p.origin, p.direction, std::numeric_limits<float>::infinity(), hit,
                                        geometry.offset(p.origin)))
      continue;
    if (scene.materials[size_t(hit.material)].type == MaterialType::Dielectric) {
      glass += w;
      glassBox.extend(Vec3d(hit.lo)), glassBox.extend(Vec3d(hit.hi));
    }
    // The room's scale as this light sees it: how far light goes after its first reflection.
    const Vec3 x = p.origin + hit.t * p.direction;
    hits.push_back({w, Vec3d(x)});
    const Vec3 n = glm::dot(hit.ng, p.direction) < 0.0f ? hit.ng : -hit.ng;
    const Vec3 d = Frame(n).toWorld(squareToCosineHemisphere(u));
    ParticleScene::Hit next;
    onward.push_back(geometry.intersect(x, d, std::numeric_limits<float>::infinity(), next, geometry.offset(x))
                         ? double(next.t)
                         : sceneDiagonal);
  }
  if (!(total > 0)) return std::nullopt;
  BoxBuilder b = own;
  if (glass >= kGlassShare * total) {
    b.extend(glassBox);
    return b;
  }
  if (onward.empty()) return std::nullopt;
  const size_t q = onward.size() * 9 / 10;  // the 90th percentile: inside a bowl most bounces meet the bowl again
  std::nth_element(onward.begin(), onward.begin() + long(q), onward.end());
  const double radius = std::min(kNearRadius * sceneDiagonal, kFixtureScale * onward[q]);
  double near = 0;
  BoxBuilder nearBox;
  for (const FirstHit& h : hits)
    if (glm::length(h.x - centre) <= radius) near += h.w, nearBox.extend(h.x);
  if (near >= kNearShare * total) {
    b.extend(nearBox);
    return b;
  }
  return std::nullopt;
}

/// Whether a face of @p s (its bounds) meets the box [@p lo, @p hi].
bool entersBox(const ShapeDesc& s, const Vec3d& lo, const Vec3d& hi) {
  for (const Face& f : s.faces) {
    BoxBuilder b;
    for (int k = 0; k < int(f.count); ++k) b.extend(s.vertices[f.v[k]]);
    if (!glm::any(glm::lessThan(b.hi, lo)) && !glm::any(glm::greaterThan(b.lo, hi))) return true;
  }
  return false;
}

}  // namespace

std::vector<uint32_t> holdWholeShapes(const SceneDesc& scene, Luminaire& lum, double sceneDiagonal) {
  // The reach allowed past each face: kWholeShapeReach of the box's extent as found, so that the growth does not
  // spread from a lamp to the desk it stands on and on.
  const Vec3d reach = kWholeShapeReach * Vec3d(lum.hi - lum.lo);
  const Vec3d outerLo = Vec3d(lum.lo) - reach, outerHi = Vec3d(lum.hi) + reach;
  // The shapes within the reach, the only ones that can be taken.
  std::vector<std::pair<uint32_t, BoxBuilder>> near;
  for (uint32_t i = 0; i < scene.shapes.size(); ++i) {
    BoxBuilder b;
    for (const Vec3d& v : scene.shapes[i].vertices) b.extend(v);
    if (!b.empty() && !glm::any(glm::lessThan(b.lo, outerLo)) && !glm::any(glm::greaterThan(b.hi, outerHi)))
      near.emplace_back(i, b);
  }
  std::vector<uint32_t> taken;
  for (bool grown = true; grown;) {
    grown = false;
    for (const auto& [i, b] : near) {
      if (std::find(taken.begin(), taken.end(), i) != taken.end()) continue;
      const Vec3d lo(lum.lo), hi(lum.hi);  // as grown so far
      if (!glm::any(glm::lessThan(b.lo, lo)) && !glm::any(glm::greaterThan(b.hi, hi))) continue;  // inside
      if (!entersBox(scene.shapes[i], lo, hi)) continue;
      BoxBuilder box;
      box.extend(lo), box.extend(hi), box.extend(b);
      setBox(lum, box, sceneDiagonal);
      taken.push_back(i);
      grown = true;  // the new box may cut others within the reach: test them all again
    }
  }
  return taken;
}

void setExitPatches(Luminaire& lum) {
  const Vec3 e = lum.hi - lum.lo;
  const float s = std::max({e.x, e.y, e.z}) / 8.0f;
  auto cells = [&](float extent) { return uint32_t(std::clamp(s > 0.0f ? std::lround(extent / s) : 1L, 1L, 8L)); };
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2;
    lum.nu[size_t(f)] = cells(e[(a + 1) % 3]);
    lum.nv[size_t(f)] = cells(e[(a + 2) % 3]);
  }
}

std::vector<Luminaire> findLuminaires(const SceneDesc& scene, const std::vector<uint32_t>& smallLights,
                                      const LuminaireOptions& options, const ParticleScene* geometry) {
  if (options.mode == "off") return {};
  Vec3d lo, hi;
  scene.bounds(lo, hi);
  const double diagonal = glm::length(hi - lo);
  std::vector<Luminaire> lums = namedLuminaires(scene, smallLights, diagonal, options.quiet);
  if (options.mode == "auto") {
    std::vector<uint32_t> candidates;
    for (uint32_t l : smallLights) {
      bool taken = scene.lights[l].type == LightType::Directional;
      for (const Luminaire& n : lums) taken = taken || std::binary_search(n.lights.begin(), n.lights.end(), l);
      if (!taken) candidates.push_back(l);
    }
    if (!candidates.empty()) {
      std::unique_ptr<ParticleScene> own;
      if (!geometry) own = std::make_unique<ParticleScene>(scene), geometry = own.get();
      std::vector<std::optional<BoxBuilder>> found(candidates.size());
      tbb::parallel_for(size_t(0), candidates.size(), [&](size_t i) {
        found[i] = probeLight(scene, *geometry, candidates[i], options.seed, diagonal);
      });
      for (size_t i = 0; i < candidates.size(); ++i)
        if (found[i]) {
          lums.push_back(boxed("auto:" + scene.lights[candidates[i]].name, {candidates[i]}, *found[i], diagonal));
          holdWholeShapes(scene, lums.back(), diagonal);
        }
    }
  } else if (options.mode != "named") {
    throw std::invalid_argument("unknown luminaire mode \"" + options.mode + "\" (auto, named, off)");
  }
  mergeOverlapping(lums, kNearRadius * diagonal);
  for (Luminaire& lum : lums) setExitPatches(lum);
  return lums;
}

std::vector<Luminaire> makeLuminaires(const SceneDesc& scene, const std::vector<uint32_t>& smallLights,
                                      const LuminaireOptions& options, std::vector<double>* seconds) {
  if (options.mode == "off") return {};
  // The BVH only when some light could be in a luminaire.
  bool any = false;
  for (uint32_t l : smallLights) any = any || scene.lights[l].type != LightType::Directional;
  if (!any) return {};
  const ParticleScene geometry(scene);
  std::vector<Luminaire> lums = findLuminaires(scene, smallLights, options, &geometry);
  if (seconds) seconds->clear();
  // Each luminaire's share of the particles: its lights' power (mean RGB) over all luminaires'.
  std::vector<double> power(lums.size(), 0.0);
  double total = 0;
  for (size_t i = 0; i < lums.size(); ++i) {
    const Color c = ParticleSource(scene, lums[i].lights, geometry).power();
    power[i] = (double(c.x) + c.y + c.z) / 3.0, total += power[i];
  }
  for (size_t i = 0; i < lums.size(); ++i) {
    const double share = total > 0 ? power[i] / total : 1.0 / double(lums.size());
    const uint64_t particles =
        std::max(std::min(kMinLuminaireParticles, options.particles), uint64_t(std::llround(share * double(options.particles))));
    const auto start = std::chrono::steady_clock::now();
    {
      Progress progress("luminaire " + lums[i].name, (particles + kLuminaireChunk - 1) / kLuminaireChunk,
                        options.quiet);
      const ParticleScene inBox(scene, lums[i].lo, lums[i].hi);  // its rays end where they leave the box
      traceExitDistribution(scene, inBox, lums[i], uint32_t(i), particles, options.seed, &progress);
      progress.finish();
    }
    if (seconds) seconds->push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return lums;
}

std::string luminaireSummary(const Luminaire& lum, double seconds) {
  const Vec3 e = lum.hi - lum.lo;
  const double emitted = double(luminance(lum.power));
  const double ratio = emitted > 0 ? double(luminance(lum.exitPower)) / emitted : 0.0;
  const double direct = emitted > 0 ? double(luminance(lum.directPower)) / emitted : 0.0;
  const double specular = emitted > 0 ? double(luminance(lum.specularPower)) / emitted : 0.0;
  const std::string specularPart =
      specular > 0 ? fmt::format(", {:.4f} through glass or off mirrors, an intensity about ({:.4g}, {:.4g}, {:.4g}) m",
                                 specular, lum.centre.x, lum.centre.y, lum.centre.z)
                   : std::string();
  std::string table = fmt::format("its table's standard error {:.1f}% per exit patch and bin, {:.1f}% per face and bin",
                                  100.0 * lum.cellError, 100.0 * lum.farError);
  if (specular > 0) table += fmt::format(", at most {:.1f}% per intensity bin", 100.0 * lum.intensityError);
  return fmt::format("luminaire {}: {} light{}, box {:.4g} × {:.4g} × {:.4g} m, {} exit patches, {} particles, "
                     "exit/emitted power {:.4f} (and {:.4f} straight from the lights, sampled as lights{}), "
                     "relative error {:.2e} ({}), {:.2f} s",
                     lum.name, lum.lights.size(), lum.lights.size() == 1 ? "" : "s", e.x, e.y, e.z, lum.patchCount(),
                     lum.particles, ratio, direct, specularPart, lum.relError, table, seconds);
}

}  // namespace firstshot
