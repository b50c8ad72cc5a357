// The .fsd file: writer and verifying reader (layout in docs/firstshot-format.md).
#include "common/table/firstshot.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "common/table/firstshot_groups.h"
#include "common/table/firstshot_patches.h"
#include "common/util/binary_file.h"
#include "common/util/hash.h"

namespace firstshot {
namespace {

/// 2: the analytic estimator's factors are exact per patch (visible fraction from exact occlusion
/// tests, over the exposed part of a patch); version-1 tables carried the biases fixed then.
/// 3: settings for adaptive patches and light tessellation; grouped factors (common/table/firstshot_groups.h).
/// 4: packed patches (common/table/firstshot_patches.h).
/// 5: the luminaires' exit distributions (common/table/luminaire.h), section LUMN.
/// 6: a luminaire's exit distribution without its lights' direct light (LUMN: directPower after exitPower).
/// 7: nor its specular light (LUMN: specularPower, centre and intensity after the relative error).
/// 8: the exit distribution's own error (LUMN: cellError, farError, intensityError after the intensity).
constexpr BinaryFormat kFormat{.magic = {"FSHOTFSD", 8},
                               .endMarker = {"FSHOTEND", 8},
                               .version = 8,
                               .headerBytes = 48,  // magic, version, flags, scene, settings and patch hashes
                               .noun = "first-shot file",
                               .identity = "a first-shot (.fsd) file",
                               .remedy = "run firstshot-preprocess again"};

/// The most exit patches along one edge of a box face the reader accepts (the preprocessor makes at most 8).
constexpr uint32_t kMaxExitCells = 64;

/// The LUMN section: every luminaire, checked (counts, sizes, finite non-negative values, lights ascending and
/// not replaced by factors).
void readLuminaires(BinaryReader& in, FirstShotTable& t) {
  in.enter("LUMN");
  const uint64_t count = in.get<uint64_t>("LUMN");
  // The smallest luminaire takes 4 + 24 + 8 + 48 + 8 + 40 + 8 bytes and its radiance (6 patches at least).
  if (count > in.remaining() / 128) in.fail("LUMN", "truncated or corrupt: fewer luminaires than counted");
  t.luminaires.resize(count);
  auto finite = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  auto finiteNonNegative = [&](const Color& c) { return finite(c) && c.x >= 0.0f && c.y >= 0.0f && c.z >= 0.0f; };
  for (size_t i = 0; i < count; ++i) {
    Luminaire& l = t.luminaires[i];
    const std::string which = "luminaire " + std::to_string(i);
    l.name = in.str("LUMN");
    l.lo = in.get<Vec3>("LUMN"), l.hi = in.get<Vec3>("LUMN");
    if (!finite(l.lo) || !finite(l.hi) || !(l.lo.x <= l.hi.x && l.lo.y <= l.hi.y && l.lo.z <= l.hi.z))
      in.fail("LUMN", which + ": invalid box (corrupt file)");
    in.array(l.lights, in.get<uint64_t>("LUMN"), "LUMN");
    if (l.lights.empty()) in.fail("LUMN", which + ": no lights (corrupt file)");
    for (size_t k = 0; k < l.lights.size(); ++k) {
      if (k > 0 && !(l.lights[k] > l.lights[k - 1])) in.fail("LUMN", which + ": lights not ascending (corrupt file)");
      if (t.replaces(l.lights[k])) in.fail("LUMN", which + ": a light that the factors also replace (corrupt file)");
    }
    l.nu = in.get<std::array<uint32_t, 6>>("LUMN"), l.nv = in.get<std::array<uint32_t, 6>>("LUMN");
    for (int f = 0; f < 6; ++f)
      if (l.nu[size_t(f)] < 1 || l.nu[size_t(f)] > kMaxExitCells || l.nv[size_t(f)] < 1 || l.nv[size_t(f)] > kMaxExitCells)
        in.fail("LUMN", which + ": exit patches per face edge outside 1.." + std::to_string(kMaxExitCells) + " (corrupt file)");
    l.particles = in.get<uint64_t>("LUMN");
    l.power = in.get<Color>("LUMN"), l.exitPower = in.get<Color>("LUMN"), l.directPower = in.get<Color>("LUMN");
    l.relError = in.get<float>("LUMN");
    if (!finiteNonNegative(l.power) || !finiteNonNegative(l.exitPower) || !finiteNonNegative(l.directPower) ||
        !std::isfinite(l.relError) ||
        !(l.relError >= 0.0f))
      in.fail("LUMN", which + ": invalid power or error (corrupt file)");
    const uint64_t n = in.get<uint64_t>("LUMN");
    if (n != 3 * uint64_t(Luminaire::kBins) * l.patchCount())
      in.fail("LUMN", which + ": radiance of " + std::to_string(n) + " values, its exit patches need " +
                          std::to_string(3 * uint64_t(Luminaire::kBins) * l.patchCount()) + " (corrupt file)");
    in.array(l.radiance, n, "LUMN");
    for (float v : l.radiance)
      if (!(v >= 0.0f) || !std::isfinite(v)) in.fail("LUMN", which + ": a radiance negative or not finite (corrupt file)");
    l.specularPower = in.get<Color>("LUMN");
    l.centre = in.get<Vec3>("LUMN");
    if (!finiteNonNegative(l.specularPower)) in.fail("LUMN", which + ": invalid specular power (corrupt file)");
    if (!finite(l.centre) || !l.contains(l.centre)) in.fail("LUMN", which + ": a centre outside its box (corrupt file)");
    const uint64_t m = in.get<uint64_t>("LUMN");
    if (m != 3 * uint64_t(Luminaire::kGonioBins))
      in.fail("LUMN", which + ": intensity of " + std::to_string(m) + " values, not " +
                          std::to_string(3 * Luminaire::kGonioBins) + " (corrupt file)");
    in.array(l.intensity, m, "LUMN");
    for (float v : l.intensity)
      if (!(v >= 0.0f) || !std::isfinite(v)) in.fail("LUMN", which + ": an intensity negative or not finite (corrupt file)");
    l.cellError = in.get<float>("LUMN"), l.farError = in.get<float>("LUMN"), l.intensityError = in.get<float>("LUMN");
    for (float e : {l.cellError, l.farError, l.intensityError})
      if (!std::isfinite(e) || !(e >= 0.0f))
        in.fail("LUMN", which + ": an exit table error negative or not finite (corrupt file)");
  }
  in.leave("LUMN");
}

}  // namespace

uint64_t FirstShotSettings::hash() const {
  Hasher h;
  h.add(resolution).add(std::string_view(window)).add(std::string_view(backend));
  h.add(patchSize).add(minPatchSize).add(refineTolerance).add(lightPatchSize).add(lightTolerance);
  h.add(smallLightMaxSolidAngle).add(rotationSeed);
  h.add(std::string_view(estimator));
  return h.value();
}

bool FirstShotTable::replaces(uint32_t l) const {
  for (uint32_t r : replacedLights)
    if (r == l) return true;
  return false;
}

Color FirstShotTable::irradiance(uint32_t j) const {
  Color e(0.0f);
  for (uint64_t k = rowStart[j]; k < rowStart[j + 1]; ++k) e += samples[sampleIndex[k]].emission * factor[k];
  return e;
}

std::vector<Color> FirstShotTable::sideIrradiance() const {
  std::vector<Color> e(2 * size_t(mesh.size()), Color(0.0f));
  for (uint32_t j = 0; j < mesh.size(); ++j) {
    const Patch& p = mesh.patches[j];
    for (uint64_t k = rowStart[j]; k < rowStart[j + 1]; ++k) {
      const LightSample& s = samples[sampleIndex[k]];
      const float side = s.kind == LightSampleKind::Directional ? -glm::dot(s.normal, p.normal)
                                                                 : glm::dot(s.position - p.centroid, p.normal);
      if (side != 0.0f) e[2 * size_t(j) + (side > 0.0f ? 0 : 1)] += s.emission * factor[k];
    }
  }
  return e;
}

void writeFirstShot(const std::string& path, const FirstShotTable& t) {
  if (t.rowStart.size() != size_t(t.mesh.size()) + 1 || t.sampleIndex.size() != t.factor.size())
    throw std::runtime_error(path + ": inconsistent first-shot table (internal error)");
  for (const Luminaire& l : t.luminaires)
    if (l.radiance.size() != 3 * size_t(Luminaire::kBins) * l.patchCount())
      throw std::runtime_error(path + ": luminaire \"" + l.name + "\": radiance of the wrong size (internal error)");
  writeBinaryFile(path, kFormat, [&](BinaryWriter& o) {
    o.put<uint32_t>(0);  // flags
    o.put(t.sceneHash);
    o.put(t.settings.hash());
    o.put(hashPatches(t.mesh));
    o.beginSection("SETT");
    o.put(t.settings.resolution);
    o.str(t.settings.window);
    o.str(t.settings.backend);
    o.put(t.settings.patchSize);
    o.put(t.settings.minPatchSize);
    o.put(t.settings.refineTolerance);
    o.put(t.settings.lightPatchSize);
    o.put(t.settings.lightTolerance);
    o.put(t.settings.smallLightMaxSolidAngle);
    o.put(t.settings.rotationSeed);
    o.str(t.settings.estimator);
    o.endSection();
    o.beginSection("PTCH");
    o.put<uint64_t>(t.mesh.size());
    o.put(t.mesh.patchSize);
    const PackedPatches pp = packPatches(t.mesh);
    o.put<uint64_t>(pp.vertices.size());
    o.put<uint64_t>(pp.runLength.size());
    o.put<uint64_t>(pp.index.size());
    o.array(pp.runShape), o.array(pp.runMaterial), o.array(pp.runLength);
    o.array(pp.corners), o.array(pp.index), o.array(pp.vertices);
    o.array(pp.normal), o.array(pp.centroid), o.array(pp.area);
    o.endSection();
    o.beginSection("LSMP");
    o.put<uint64_t>(t.samples.size());
    for (const LightSample& l : t.samples) {
      o.put(l.kind), o.put(l.light), o.put(l.position), o.put(l.normal), o.put(l.emission), o.put(l.weight);
    }
    o.put<uint64_t>(t.replacedLights.size());
    o.array(t.replacedLights);
    o.endSection();
    o.beginSection("CSRR");
    const GroupedFactors g = groupFactors(t);
    o.put<uint64_t>(t.factor.size());
    o.put<uint64_t>(g.singleSample.size());
    o.put<uint64_t>(g.groupLight.size());
    o.put(t.areaEyeOffset);
    o.array(g.rowCount);
    if (!g.groupLight.empty()) {  // without groups, every factor is a single
      o.array(g.singleCount);
      o.array(g.groupCount);
    }
    o.array(g.singleSample);
    o.array(g.singleFactor);
    o.array(g.groupLight);
    o.array(g.groupVisible);
    o.endSection();
    o.beginSection("LUMN");
    o.put<uint64_t>(t.luminaires.size());
    for (const Luminaire& l : t.luminaires) {
      o.str(l.name);
      o.put(l.lo), o.put(l.hi);
      o.put<uint64_t>(l.lights.size());
      o.array(l.lights);
      o.put(l.nu), o.put(l.nv);
      o.put(l.particles);
      o.put(l.power), o.put(l.exitPower), o.put(l.directPower), o.put(l.relError);
      o.put<uint64_t>(l.radiance.size());
      o.array(l.radiance);
      // A luminaire made without its specular light (no intensity yet) is written with none, centred in its box.
      const bool gonio = l.intensity.size() == 3 * size_t(Luminaire::kGonioBins);
      o.put(gonio ? l.specularPower : Color(0.0f));
      o.put(gonio ? glm::clamp(l.centre, l.lo, l.hi) : 0.5f * (l.lo + l.hi));
      o.put<uint64_t>(3 * uint64_t(Luminaire::kGonioBins));
      o.array(gonio ? l.intensity : std::vector<float>(3 * size_t(Luminaire::kGonioBins), 0.0f));
      o.put(l.cellError), o.put(l.farError), o.put(gonio ? l.intensityError : 0.0f);
    }
    o.endSection();
  });
}

FirstShotTable readFirstShot(const std::string& path, uint64_t expectedSceneHash) {
  BinaryReader in(path, kFormat);
  FirstShotTable t;
  in.get<uint32_t>("header");  // flags
  t.sceneHash = in.get<uint64_t>("header");
  const uint64_t settingsHash = in.get<uint64_t>("header");
  const uint64_t patchHash = in.get<uint64_t>("header");
  if (expectedSceneHash != 0 && t.sceneHash != expectedSceneHash) {
    std::ostringstream msg;
    msg << "made for a different scene (scene hash " << std::hex << t.sceneHash << ", this scene " << expectedSceneHash
        << "): run firstshot-preprocess on this scene again";
    in.fail("header", msg.str());
  }
  in.enter("SETT");
  t.settings.resolution = in.get<uint32_t>("SETT");
  t.settings.window = in.str("SETT");
  t.settings.backend = in.str("SETT");
  t.settings.patchSize = in.get<double>("SETT");
  t.settings.minPatchSize = in.get<double>("SETT");
  t.settings.refineTolerance = in.get<double>("SETT");
  t.settings.lightPatchSize = in.get<double>("SETT");
  t.settings.lightTolerance = in.get<double>("SETT");
  t.settings.smallLightMaxSolidAngle = in.get<double>("SETT");
  t.settings.rotationSeed = in.get<uint64_t>("SETT");
  t.settings.estimator = in.str("SETT");
  in.leave("SETT");
  if (t.settings.hash() != settingsHash) in.fail("SETT", "settings do not match their hash (corrupt file)");

  in.enter("PTCH");
  const uint64_t n = in.get<uint64_t>("PTCH");
  if (n > std::numeric_limits<uint32_t>::max()) in.fail("PTCH", "patch count above 2^32-1 (corrupt file)");
  t.mesh.patchSize = in.get<double>("PTCH");
  {
    PackedPatches pp;
    const uint64_t nv = in.get<uint64_t>("PTCH"), runs = in.get<uint64_t>("PTCH"), ni = in.get<uint64_t>("PTCH");
    in.array(pp.runShape, runs, "PTCH"), in.array(pp.runMaterial, runs, "PTCH"), in.array(pp.runLength, runs, "PTCH");
    in.array(pp.corners, n, "PTCH"), in.array(pp.index, ni, "PTCH"), in.array(pp.vertices, nv, "PTCH");
    in.array(pp.normal, n, "PTCH"), in.array(pp.centroid, n, "PTCH"), in.array(pp.area, n, "PTCH");
    in.leave("PTCH");
    unpackPatches(pp, t.mesh, [&](const std::string& msg) { in.fail("PTCH", msg); });
  }
  if (hashPatches(t.mesh) != patchHash) in.fail("PTCH", "patches do not match their hash (corrupt file)");

  in.enter("LSMP");
  const uint64_t ns = in.get<uint64_t>("LSMP");
  if (ns > in.remaining() / 48) in.fail("LSMP", "truncated or corrupt: fewer light samples than counted");
  t.samples.resize(ns);
  for (LightSample& l : t.samples) {
    l.kind = in.get<LightSampleKind>("LSMP"), l.light = in.get<uint32_t>("LSMP");
    l.position = in.get<Vec3>("LSMP"), l.normal = in.get<Vec3>("LSMP"), l.emission = in.get<Color>("LSMP");
    l.weight = in.get<float>("LSMP");
    if (uint32_t(l.kind) > uint32_t(LightSampleKind::AreaVertex)) in.fail("LSMP", "unknown light sample kind");
  }
  in.array(t.replacedLights, in.get<uint64_t>("LSMP"), "LSMP");
  in.leave("LSMP");

  in.enter("CSRR");
  const uint64_t nnz = in.get<uint64_t>("CSRR");
  const uint64_t singles = in.get<uint64_t>("CSRR");
  const uint64_t groups = in.get<uint64_t>("CSRR");
  t.areaEyeOffset = in.get<double>("CSRR");
  if (!std::isfinite(t.areaEyeOffset)) in.fail("CSRR", "invalid area-light eye offset (corrupt file)");
  GroupedFactors g;
  in.array(g.rowCount, n, "CSRR");
  if (groups > 0) {
    in.array(g.singleCount, n, "CSRR");
    in.array(g.groupCount, n, "CSRR");
  } else {
    g.singleCount = g.rowCount;
    g.groupCount.assign(n, 0);
  }
  in.array(g.singleSample, singles, "CSRR");
  in.array(g.singleFactor, singles, "CSRR");
  in.array(g.groupLight, groups, "CSRR");
  in.array(g.groupVisible, groups, "CSRR");
  in.leave("CSRR");
  expandFactors(g, nnz, t, [&](const std::string& msg) { in.fail("CSRR", msg); });
  readLuminaires(in, t);
  in.expectEnd("LUMN");
  return t;
}

}  // namespace firstshot
