// The luminaires' particle tracer: BVH, emission, walk and exit distribution (luminaire_trace.h).
#include "preprocess/luminaire_trace.h"

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/lights/emission_profile.h"
#include "common/materials/texture.h"
#include "common/sampling/sampling.h"
#include "common/util/progress.h"
#include "preprocess/embree_triangles.h"

namespace firstshot {

struct ParticleScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<int> material;      ///< per triangle
  std::vector<Vec3> normal;       ///< per triangle, unit
  std::vector<float> vertices;    ///< 9 per triangle
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

ParticleScene::ParticleScene(const SceneDesc& scene) : ParticleScene(scene, Vec3(-INFINITY), Vec3(INFINITY)) {}

ParticleScene::ParticleScene(const SceneDesc& scene, const Vec3& lo, const Vec3& hi) : impl_(std::make_unique<Impl>()) {
  scene.bounds(lo_, hi_);
  Impl& m = *impl_;
  const Vec3d boxLo(lo), boxHi(hi);
  for (const ShapeDesc& s : scene.shapes)
    for (const Face& f : s.faces)
      for (int k = 1; k + 1 < int(f.count); ++k) {  // a fan: quads are planar and convex (common/scene/scene_desc.h)
        const Vec3d a = s.vertices[f.v[0]], b = s.vertices[f.v[k]], c = s.vertices[f.v[k + 1]];
        const Vec3d n = glm::cross(b - a, c - a);
        const double len = glm::length(n);
        if (!(len > 0)) continue;
        const Vec3d tlo = glm::min(a, glm::min(b, c)), thi = glm::max(a, glm::max(b, c));
        if (glm::any(glm::lessThan(thi, boxLo)) || glm::any(glm::greaterThan(tlo, boxHi))) continue;
        for (const Vec3d& v : {a, b, c}) m.vertices.insert(m.vertices.end(), {float(v.x), float(v.y), float(v.z)});
        m.material.push_back(s.material);
        m.normal.push_back(Vec3(n / len));
      }
  m.device = rtcNewDevice(nullptr);
  if (!m.device) throw std::runtime_error("Embree: cannot create a device for the luminaires' particles");
  m.scene = rtcNewScene(m.device);
  rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_ROBUST);
  commitTriangleSoup(m.device, m.scene, m.vertices, "Embree: cannot allocate the luminaires' particle scene",
                     "Embree: building the luminaires' particle scene failed");
}

ParticleScene::~ParticleScene() = default;

bool ParticleScene::intersect(const Vec3& o, const Vec3& d, float tfar, Hit& hit, float tnear) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = o.x, rh.ray.org_y = o.y, rh.ray.org_z = o.z;
  rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z;
  rh.ray.tnear = tnear;
  rh.ray.tfar = tfar;
  rh.ray.time = 0.0f, rh.ray.mask = 0xffffffffu, rh.ray.id = 0, rh.ray.flags = 0;
  rh.hit.geomID = rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  const unsigned tri = rh.hit.primID;
  hit.t = rh.ray.tfar;
  hit.material = impl_->material[tri];
  hit.ng = impl_->normal[tri];
  const float* v = &impl_->vertices[9 * size_t(tri)];
  hit.lo = hit.hi = Vec3(v[0], v[1], v[2]);
  for (int k = 1; k < 3; ++k) {
    const Vec3 p(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
    hit.lo = glm::min(hit.lo, p), hit.hi = glm::max(hit.hi, p);
  }
  return true;
}

float ParticleScene::offset(const Vec3& p) const {
  // Float coordinates near p are spaced |p|·2^-23; a few hundred of those clear the surface, and a floor tied to the
  // scene's size covers points near the origin.
  const float scale = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  return 2e-5f * scale + 1e-7f * float(glm::length(hi_ - lo_));
}

// ---------------------------------------------------------------------------------------------------------------

struct ParticleSource::Emitter {
  const LightDesc* light = nullptr;
  Color power{0.0f};       ///< W
  EmissionProfile profile;  ///< point, spot, IES
  double profileIntegral = 0;  ///< sr
  // Area lights: the emissive faces as triangles.
  std::vector<Vec3> corners;   ///< 3 per triangle
  std::vector<Vec3> normals;   ///< per triangle, unit, front side
  Distribution1D triangles;    ///< by area
};

Color ParticleSource::lightPower(const SceneDesc& scene, uint32_t l) {
  const LightDesc& light = scene.lights[l];
  if (light.type == LightType::Directional) return Color(0.0f);
  if (light.type != LightType::Area) return light.power;
  const ShapeDesc& s = scene.shapes[size_t(light.shape)];
  double area = 0;
  for (const Face& f : s.faces)
    for (int k = 1; k + 1 < int(f.count); ++k)
      area += 0.5 * glm::length(glm::cross(s.vertices[f.v[k]] - s.vertices[f.v[0]], s.vertices[f.v[k + 1]] - s.vertices[f.v[0]]));
  return scene.materials[size_t(s.material)].emission * float(kPi * area);
}

ParticleSource::ParticleSource(const SceneDesc& scene, const std::vector<uint32_t>& lights, const ParticleScene& geometry)
    : geometry_(geometry) {
  std::vector<double> shares;
  for (uint32_t l : lights) {
    const LightDesc& light = scene.lights[l];
    if (light.type == LightType::Directional) continue;
    Emitter e;
    e.light = &light;
    e.power = lightPower(scene, l);
    if (light.type == LightType::Area) {
      const ShapeDesc& s = scene.shapes[size_t(light.shape)];
      std::vector<double> areas;
      for (const Face& f : s.faces)
        for (int k = 1; k + 1 < int(f.count); ++k) {
          const Vec3d a = s.vertices[f.v[0]], b = s.vertices[f.v[k]], c = s.vertices[f.v[k + 1]];
          const Vec3d n = glm::cross(b - a, c - a);
          if (!(glm::length(n) > 0)) continue;
          e.corners.insert(e.corners.end(), {Vec3(a), Vec3(b), Vec3(c)});
          e.normals.push_back(Vec3(glm::normalize(n)));
          areas.push_back(0.5 * glm::length(n));
        }
      e.triangles = Distribution1D(areas);
      if (!(e.triangles.total() > 0)) continue;
    } else {
      e.profile = EmissionProfile(light);
      e.profileIntegral = e.profile.integral();
      if (!(e.profileIntegral > 0)) continue;
    }
    const double share = (double(e.power.x) + e.power.y + e.power.z) / 3.0;
    if (!(share > 0)) continue;
    power_ += e.power;
    shares.push_back(share);
    emitters_.push_back(std::move(e));
  }
  byPower_ = Distribution1D(shares);
}

ParticleSource::~ParticleSource() = default;

EmittedParticle ParticleSource::sample(Sampler& sampler) const {
  EmittedParticle p;
  const double uLight = sampler.next1Dd();
  const Vec2d uDir = sampler.next2Dd();
  if (emitters_.empty()) return p;
  const size_t light = byPower_.sampleDiscrete(uLight);
  const double pLight = byPower_.probability(light);
  const Emitter& e = emitters_[light];
  if (!(pLight > 0)) return p;
  if (e.light->type != LightType::Area) {
    double pdf = 0;
    const Vec3d w = e.profile.sample(uDir.x, uDir.y, pdf);
    if (!(pdf > 0)) return p;
    p.origin = Vec3(e.light->position);
    p.direction = Vec3(glm::normalize(w));
    p.weight = e.power * float(e.profile(w) / (e.profileIntegral * pdf * pLight));
    return p;
  }
  // Area: a triangle by area, a point uniform on it, a cosine-weighted direction about its front normal. The
  // densities 1/A and cos θ/π against Le·cos θ leave π·Le·A = the light's power.
  const size_t t = e.triangles.sampleDiscrete(sampler.next1Dd());
  const Vec3 b = squareToUniformTriangle(sampler.next2D());
  const Vec3 x = b.x * e.corners[3 * t] + b.y * e.corners[3 * t + 1] + b.z * e.corners[3 * t + 2];
  const Vec3 n = e.normals[t];
  const Vec3 local = squareToCosineHemisphere(Vec2(uDir));
  const Framed frame{Vec3d(n)};
  p.direction = Vec3(glm::normalize(double(local.x) * frame.s + double(local.y) * frame.t + double(local.z) * frame.n));
  p.origin = x + geometry_.offset(x) * n;
  p.weight = e.power / float(pLight);
  return p;
}

// ---------------------------------------------------------------------------------------------------------------

std::vector<BSDF> makeLuminaireBSDFs(const SceneDesc& scene) {
  std::vector<BSDF> bsdfs;
  bsdfs.reserve(scene.materials.size());
  for (const MaterialDesc& m : scene.materials)
    bsdfs.push_back(m.albedoTexture && m.albedoTexture->image ? makeBSDF(m, m.albedo * m.albedoTexture->image->mean)
                                                              : makeBSDF(m));
  return bsdfs;
}

namespace {

/// Distance from @p o along @p d to where the ray leaves the box [@p lo, @p hi], ≥ 0, and the face @p f it leaves by.
float slabExit(const Vec3& lo, const Vec3& hi, const Vec3& o, const Vec3& d, int& f) {
  float t = std::numeric_limits<float>::infinity();
  f = 0;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0f) continue;
    const float ta = ((d[a] > 0.0f ? hi[a] : lo[a]) - o[a]) / d[a];
    if (ta < t) t = ta, f = 2 * a + (d[a] > 0.0f ? 1 : 0);
  }
  return std::max(t, 0.0f);
}

/// Σ σ_i / Σ S_i over bins i of the luminance S_i = Σ y (over n particles), σ_i² = Σ y² − S_i²/n from the sums of
/// squares @p q: the power-weighted mean of the bins' relative standard errors (Luminaire::cellError).
double weightedRelativeError(const std::vector<double>& s, const std::vector<double>& q, double n) {
  double sigma = 0, total = 0;
  for (size_t i = 0; i < s.size(); ++i) sigma += std::sqrt(std::max(0.0, q[i] - s[i] * s[i] / n)), total += s[i];
  return total > 0 ? sigma / total : 0.0;
}

/// Luminance and its square summed per bin, for weightedRelativeError.
struct BinSums {
  std::vector<double> s, q;
  explicit BinSums(size_t bins) : s(bins, 0.0), q(bins, 0.0) {}
  void add(size_t i, double y) { s[i] += y, q[i] += y * y; }
  double error(double n) const { return weightedRelativeError(s, q, n); }
};

/// The particles that leave a box after delta bounces only: their power per goniophotometric bin, and the normal
/// equations of the point nearest their lines, Σ y·(I − d·dᵀ)·c = Σ y·(I − d·dᵀ)·x (y a particle's luminance, x its
/// exit point, d its direction).
struct SpecularSums {
  std::vector<double> bins = std::vector<double>(3 * size_t(Luminaire::kGonioBins), 0.0);  ///< W
  glm::dmat3 normal{0.0};
  Vec3d rhs{0.0};
  double weight = 0;  ///< Σ y

  void add(const ParticleExit& e) {
    const size_t b = size_t(Luminaire::gonioBin(e.direction));
    for (size_t k = 0; k < 3; ++k) bins[3 * b + k] += double(e.power[int(k)]);
    const double y = luminance(e.power);
    if (!(y > 0)) return;
    const Vec3d d(e.direction);
    const glm::dmat3 projector = glm::dmat3(1.0) - glm::outerProduct(d, d);
    normal += y * projector;
    rhs += y * (projector * Vec3d(e.point));
    weight += y;
  }

  /// Fills @p lum's specularPower, intensity and centre from @p n particles. The centre is pulled towards the box's
  /// centre by 10⁻³ of the weight (so parallel lines, a collimated beam, still give a point) and kept in the box.
  void finish(Luminaire& lum, double n) const {
    lum.intensity.assign(bins.size(), 0.0f);
    Vec3d power(0.0);
    const double toIntensity = double(Luminaire::kGonioBins) / (4.0 * kPi) / n;
    for (size_t i = 0; i < bins.size(); ++i) {
      power[int(i % 3)] += bins[i] / n;
      lum.intensity[i] = float(bins[i] * toIntensity);
    }
    lum.specularPower = Color(power);
    const Vec3d middle = 0.5 * (Vec3d(lum.lo) + Vec3d(lum.hi));
    Vec3d c = middle;
    if (weight > 0) {
      const double lambda = 1e-3 * weight;
      c = glm::inverse(normal + lambda * glm::dmat3(1.0)) * (rhs + lambda * middle);
    }
    lum.centre = glm::clamp(Vec3(c), lum.lo, lum.hi);
  }
};

}  // namespace

bool walkParticle(const SceneDesc& scene, const ParticleScene& geometry, const std::vector<BSDF>& bsdfs,
                  const Luminaire& box, EmittedParticle p, Sampler& sampler, ParticleExit& out) {
  Color throughput(1.0f);
  bool scattered = false;  // a non-delta surface inside the box was met
  for (int bounce = 0;; ++bounce) {
    int face = 0;
    const float tExit = slabExit(box.lo, box.hi, p.origin, p.direction, face);
    ParticleScene::Hit hit;
    // A light that touches a surface (a point light on a wall) does not hit it where it starts.
    const float tnear = bounce == 0 ? geometry.offset(p.origin) : 0.0f;
    if (!geometry.intersect(p.origin, p.direction, tExit, hit, tnear)) {
      const int b = Luminaire::bin(face, p.direction);
      if (b < 0) return false;  // grazing the face it leaves by (a direction within it): no projected solid angle
      out.cell = uint32_t(Luminaire::kBins) * box.patchAt(face, p.origin + tExit * p.direction) + uint32_t(b);
      out.power = p.weight * throughput;
      out.kind = bounce == 0 ? ParticleExit::Kind::Direct
                 : scattered ? ParticleExit::Kind::Scattered
                             : ParticleExit::Kind::Specular;
      out.point = p.origin + tExit * p.direction;
      out.direction = p.direction;
      return true;
    }
    if (bounce >= kLuminaireMaxBounces) return false;
    const MaterialDesc& m = scene.materials[size_t(hit.material)];
    if (m.isEmissive()) return false;  // an emitter is a light only: it does not reflect (docs/scene-format.md)
    const BSDF& bsdf = bsdfs[size_t(hit.material)];
    const Framed frame{Vec3d(hit.ng)};
    const Vec3 s(frame.s), t(frame.t), n(frame.n);
    const Vec3 wo = -p.direction;
    BSDFQuery q(Vec3(glm::dot(wo, s), glm::dot(wo, t), glm::dot(wo, n)), TransportMode::Importance);
    const Color weight = bsdf.sample(q, sampler.next2D());
    if (!(q.pdf > 0.0f) || !(maxComponent(weight) > 0.0f)) return false;
    scattered = scattered || !q.specular;
    const Vec3 wi = glm::normalize(q.wi.x * s + q.wi.y * t + q.wi.z * n);
    throughput *= weight;
    const Vec3 x = p.origin + hit.t * p.direction;
    p.origin = x + (glm::dot(wi, hit.ng) > 0.0f ? 1.0f : -1.0f) * geometry.offset(x) * hit.ng;
    p.direction = wi;
    const float u = sampler.next1D();  // drawn at every bounce: the dimensions stay aligned
    if (bounce + 1 >= kLuminaireRouletteDepth) {
      const float survive = std::min(0.95f, maxComponent(throughput));
      if (!(u < survive)) return false;
      throughput /= survive;
    }
  }
}

void traceExitDistribution(const SceneDesc& scene, const ParticleScene& geometry, Luminaire& lum, uint32_t index,
                           uint64_t particles, uint64_t seed, Progress* progress) {
  const ParticleSource source(scene, lum.lights, geometry);
  const std::vector<BSDF> bsdfs = makeLuminaireBSDFs(scene);
  const uint32_t patches = lum.patchCount();
  std::vector<double> sum(3 * size_t(Luminaire::kBins) * patches, 0.0);  // W, Σ over the particles
  const uint64_t chunks = (particles + kLuminaireChunk - 1) / kLuminaireChunk;
  std::vector<double> chunkY(chunks, 0.0), chunkN(chunks, 0.0);  // per chunk: Σ luminance leaving, particles
  std::vector<double> squares(chunks, 0.0);                       // per chunk: Σ luminance² (one chunk's fallback)
  Vec3d direct(0.0);  // W, Σ over the particles that left straight from a light (not in the table)
  SpecularSums specular;  // the particles that left after delta bounces only
  // The table's own error: per exit patch and bin, per face and bin, per intensity bin.
  BinSums cells(size_t(Luminaire::kBins) * patches), far(6 * size_t(Luminaire::kBins)), gonio(Luminaire::kGonioBins);
  // Chunks in blocks: each chunk keeps its exits, then the block is added up in chunk order.
  const uint64_t block = 64;
  std::vector<std::vector<ParticleExit>> exits(block);
  for (uint64_t first = 0; first < chunks; first += block) {
    const uint64_t last = std::min(chunks, first + block);
    tbb::parallel_for(first, last, [&](uint64_t c) {
      std::vector<ParticleExit>& mine = exits[c - first];
      mine.clear();
      const uint64_t begin = c * kLuminaireChunk, end = std::min(particles, begin + kLuminaireChunk);
      for (uint64_t i = begin; i < end; ++i) {
        // Particle i's numbers: sample i of one Sobol' sequence per luminaire, so that the particles' light, points
        // and directions are stratified over all of them (the intensity bins of a bulb in glass then hold nearly
        // their exact share, where independent numbers left each a Poisson count's noise).
        Sampler sampler = Sampler::sobol(seed, index, i);
        ParticleExit e;
        if (walkParticle(scene, geometry, bsdfs, lum, source.sample(sampler), sampler, e)) mine.push_back(e);
      }
      chunkN[c] = double(end - begin);
      if (progress) progress->advance();
    });
    for (uint64_t c = first; c < last; ++c)
      for (const ParticleExit& e : exits[c - first]) {
        if (e.kind == ParticleExit::Kind::Direct) {
          for (int k = 0; k < 3; ++k) direct[k] += double(e.power[k]);
          continue;
        }
        if (e.kind == ParticleExit::Kind::Specular) {
          gonio.add(size_t(Luminaire::gonioBin(e.direction)), luminance(e.power));
          specular.add(e);
          continue;
        }
        for (int k = 0; k < 3; ++k) sum[3 * size_t(e.cell) + size_t(k)] += double(e.power[k]);
        const double y = luminance(e.power);
        const uint32_t bin = e.cell % uint32_t(Luminaire::kBins);
        cells.add(e.cell, y);
        far.add(size_t(lum.patch(e.cell / uint32_t(Luminaire::kBins)).face) * Luminaire::kBins + bin, y);
        chunkY[c] += y;
        squares[c] += y * y;
      }
  }
  const double n = double(particles);
  lum.particles = particles;
  lum.power = source.power();
  lum.radiance.assign(sum.size(), 0.0f);
  Vec3d exitPower(0.0);
  for (uint32_t k = 0; k < patches; ++k) {
    const double toRadiance = double(Luminaire::kBins) / (kPi * double(lum.patch(k).area)) / n;
    for (size_t b = 0; b < size_t(Luminaire::kBins); ++b)
      for (size_t c = 0; c < 3; ++c) {
        const double s = sum[3 * (size_t(Luminaire::kBins) * k + b) + c];
        exitPower[int(c)] += s / n;
        lum.radiance[3 * (size_t(Luminaire::kBins) * k + b) + c] = float(s * toRadiance);
      }
  }
  lum.exitPower = Color(exitPower);
  lum.directPower = Color(direct / n);
  specular.finish(lum, n);
  lum.cellError = float(cells.error(n)), lum.farError = float(far.error(n)), lum.intensityError = float(gonio.error(n));
  // Relative standard error of the mean luminance leaving: from the chunks' sums (a ratio estimator, so a shorter last
  // chunk counts for its size), or from the particles themselves when there is one chunk.
  double total = 0, squaresTotal = 0;
  for (uint64_t c = 0; c < chunks; ++c) total += chunkY[c], squaresTotal += squares[c];
  const double mean = n > 0 ? total / n : 0.0;
  double variance = 0;  // of the estimate total/n
  if (chunks >= 2) {
    double dev = 0;
    for (uint64_t c = 0; c < chunks; ++c) dev += (chunkY[c] - mean * chunkN[c]) * (chunkY[c] - mean * chunkN[c]);
    variance = double(chunks) / double(chunks - 1) * dev / (n * n);
  } else if (n > 1) {
    variance = (squaresTotal / n - mean * mean) / (n - 1);
  }
  lum.relError = mean > 0 ? float(std::sqrt(std::max(0.0, variance)) / mean) : 0.0f;
}

}  // namespace firstshot
