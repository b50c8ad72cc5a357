// The instant picture's triangles: patches coloured by first-shot radiance, emitters by emission.
#include "render/preview/raster_mesh.h"

#include <algorithm>
#include <cmath>

#include "common/materials/emission_texture.h"
#include "common/patches/patch_cutouts.h"

namespace firstshot {

std::vector<Color> sideIrradiance(const RenderScene& scene) {
  const FirstShotTable* t = scene.firstShot();
  return t ? t->sideIrradiance() : std::vector<Color>();
}

namespace {

/// Appends polygon @p v (3 or 4 vertices, planar) as a triangle fan with the given colours, and texture
/// coordinates @p uv (one per vertex) when given.
void addPolygon(RasterMesh& m, const Vec3* v, uint32_t count, const Vec3& normal, const Color& front,
                const Color& back, float headlight, const Vec2* uv = nullptr, const Color& texScale = Color(1.0f)) {
  for (uint32_t k = 1; k + 1 < count; ++k)
    for (uint32_t idx : {0u, k, k + 1})
      m.triangles.push_back({v[idx], normal, front, back, headlight, uv ? uv[idx] : Vec2(0.0f), texScale});
}

/// Starts a new batch at the end of @p m's triangles unless the last one already uses @p texture and @p cutout.
void useTexture(RasterMesh& m, int texture, int cutout = -1) {
  if (m.batches.empty() || m.batches.back().texture != texture || m.batches.back().cutout != cutout)
    m.batches.push_back({uint32_t(m.triangles.size()), 0, texture, cutout});
}

/// The index in @p m.cutouts of patch @p j's cut-out (appended on first use), -1 for an opaque patch.
int cutoutIndex(RasterMesh& m, const RenderScene& scene, uint32_t j) {
  const PatchCutouts* cut = scene.cutouts();
  if (!cut || !cut->cutout(j)) return -1;
  const MaterialDesc& mat = cut->material(j);
  Vec2 uv;
  const bool textured = cut->uvAt(j, Vec3d(scene.mesh().patches[j].centroid), uv);
  const std::shared_ptr<const Texture> alpha = textured ? mat.alphaTexture : nullptr;
  for (size_t i = 0; i < m.cutouts.size(); ++i)
    if (m.cutouts[i].alpha == alpha && m.cutouts[i].mode == mat.alphaMode && m.cutouts[i].cutoff == mat.alphaCutoff &&
        m.cutouts[i].factor == mat.alpha && m.cutouts[i].mean == cut->meanAlpha(cut->materialOf(j)))
      return int(i);
  m.cutouts.push_back({alpha, mat.alphaMode, mat.alphaCutoff, mat.alpha, cut->meanAlpha(cut->materialOf(j))});
  return int(m.cutouts.size() - 1);
}

/// Sets the alpha texture coordinates of @p m's vertices from @p first on, all on cut-out patch @p j.
void setAlphaUv(RasterMesh& m, const RenderScene& scene, uint32_t j, size_t first) {
  const PatchCutouts* cut = scene.cutouts();
  const MaterialDesc& mat = cut->material(j);
  for (size_t v = first; v < m.triangles.size(); ++v) {
    Vec2 uv;
    if (cut->uvAt(j, Vec3d(m.triangles[v].position), uv)) m.triangles[v].alphaUv = mat.alphaTexture->transform.apply(uv);
  }
}

/// The index of @p t in @p m.textures, appended on first use.
int textureIndex(RasterMesh& m, const std::shared_ptr<const Texture>& t) {
  for (size_t i = 0; i < m.textures.size(); ++i)
    if (m.textures[i] == t) return int(i);
  m.textures.push_back(t);
  return int(m.textures.size() - 1);
}

}  // namespace

RasterMesh buildRasterMesh(const RenderScene& scene, bool useFirstShot) {
  RasterMesh m;
  const SceneDesc& desc = scene.desc();
  const PatchMesh& mesh = scene.mesh();
  const std::vector<Color> e = useFirstShot ? sideIrradiance(scene) : std::vector<Color>();
  m.firstShot = !e.empty();

  // Patches that first-shot cannot colour (mirror, glass) get a headlight at the picture's
  // average radiance level, so that they are neither black nor glaring.
  float level = 1.0f;
  if (m.firstShot) {
    double sum = 0, area = 0;
    for (uint32_t j = 0; j < mesh.size(); ++j)
      if (scene.bsdf(mesh.patches[j].material).isDiffuse()) {
        sum += mesh.patches[j].area * luminance(glm::max(e[2 * j], e[2 * j + 1])) * kInvPi;
        area += mesh.patches[j].area;
      }
    level = area > 0 && sum > 0 ? float(sum / area) : 1.0f;
  }

  m.triangles.reserve(size_t(mesh.size()) * 6);
  m.edges.reserve(size_t(mesh.size()) * 8);
  const SurfaceTextures& textures = scene.textures();
  for (uint32_t j = 0; j < mesh.size(); ++j) {
    const Patch& p = mesh.patches[j];
    const MaterialDesc& mat = desc.materials[p.material];
    // The pbr material is shaded with its base colour (the patch's: a texture averaged over it) as if it were diffuse.
    const bool diffusePart =
        mat.type == MaterialType::Diffuse || mat.type == MaterialType::Glossy || mat.type == MaterialType::Pbr;
    const BSDF& patchBsdf = scene.patchBsdf(j);  // a texture averaged over the patch
    const auto* pbr = std::get_if<MetallicRoughnessBRDF>(&patchBsdf.model());
    const Color* pbrBase = pbr ? &pbr->baseColor : nullptr;
    // An albedo texture shows its texels relative to the patch's mean: texScale · texel = ρ(x) / ρ̄.
    Vec2 uv[4];
    Color texScale(1.0f);
    const bool textured = diffusePart && mat.albedoTexture && textures.textured(j) && desc.shapes[p.shape].hasUv();
    const int cutout = cutoutIndex(m, scene, j);
    useTexture(m, textured ? textureIndex(m, mat.albedoTexture) : -1, cutout);
    const size_t firstVertex = m.triangles.size();
    if (textured) {
      for (uint32_t k = 0; k < p.count; ++k) uv[k] = mat.albedoTexture->transform.apply(textures.uvAt(j, p.v[k]));
      const Color mean = textures.patchAlbedo(j);
      for (int c = 0; c < 3; ++c) texScale[c] = mean[c] > 0.0f ? mat.albedo[c] / mean[c] : 0.0f;
    }
    const Vec2* uvs = textured ? uv : nullptr;
    if (m.firstShot && patchBsdf.hasTransmission() && !patchBsdf.hasDelta()) {
      // Rough glass: a frosted surface glows on both sides with what either side receives, as a diffuser.
      const Color glow = patchBsdf.albedo() * (0.5f * kInvPiF) * (e[2 * size_t(j)] + e[2 * size_t(j) + 1]);
      addPolygon(m, p.v, p.count, p.normal, glow, glow, 0.0f, uvs, texScale);
    } else if (m.firstShot && diffusePart) {
      const Color f = (pbrBase ? *pbrBase : patchBsdf.diffuseAlbedo()) * kInvPiF;
      addPolygon(m, p.v, p.count, p.normal, f * e[2 * size_t(j)], f * e[2 * size_t(j) + 1], 0.0f, uvs, texScale);
    } else {
      const Color base = (pbrBase ? *pbrBase : patchBsdf.albedo()) * (m.firstShot ? level : 1.0f);
      addPolygon(m, p.v, p.count, p.normal, base, base, 1.0f, uvs, texScale);
    }
    if (cutout >= 0) setAlphaUv(m, scene, j, firstVertex);
    for (uint32_t k = 0; k < p.count; ++k) {
      m.edges.push_back(p.v[k]);
      m.edges.push_back(p.v[(k + 1) % p.count]);
    }
  }

  // Emitters are not patches: take their polygons from the scene description.
  // An emitter with an emission texture shows factor × texel per point (the texel clamped to [0, 1], as albedo).
  for (const ShapeDesc& s : desc.shapes) {
    const MaterialDesc& mat = desc.materials[size_t(s.material)];
    if (!mat.isEmissive()) continue;
    const bool textured = emitsPerPoint(mat, s);
    useTexture(m, textured ? textureIndex(m, mat.emissionTexture) : -1);
    for (size_t fi = 0; fi < s.faces.size(); ++fi) {
      const Face& f = s.faces[fi];
      Vec3 v[4];
      Vec2 uv[4];
      for (uint32_t k = 0; k < f.count; ++k) {
        v[k] = Vec3(s.vertices[f.v[k]]);
        if (textured) uv[k] = mat.emissionTexture->transform.apply(s.cornerUv(fi, int(k)));
      }
      const Vec3 n = glm::cross(v[1] - v[0], v[2] - v[0]);
      const float len = glm::length(n);
      if (!(len > 0.0f)) continue;
      if (textured)
        addPolygon(m, v, f.count, n / len, Color(1.0f), Color(0.0f), 0.0f, uv, mat.emissionFactor);
      else
        addPolygon(m, v, f.count, n / len, mat.emission, Color(0.0f), 0.0f);
    }
  }

  for (size_t b = 0; b < m.batches.size(); ++b)
    m.batches[b].count = (b + 1 < m.batches.size() ? m.batches[b + 1].first : uint32_t(m.triangles.size())) - m.batches[b].first;
  std::erase_if(m.batches, [](const RasterBatch& b) { return b.count == 0; });

  if (!m.triangles.empty()) {
    m.lo = m.hi = m.triangles.front().position;
    for (const RasterVertex& v : m.triangles) m.lo = glm::min(m.lo, v.position), m.hi = glm::max(m.hi, v.position);
  }
  return m;
}

std::vector<Vec3> recordCircles(const std::vector<IntegratorRecord>& records, int segments) {
  std::vector<Vec3> lines;
  lines.reserve(records.size() * size_t(segments) * 2);
  for (const IntegratorRecord& r : records) {
    const Frame frame(r.normal);
    auto at = [&](int k) {
      const float a = 2.0f * kPiF * float(k) / float(segments);
      return r.position + r.radius * (std::cos(a) * frame.s + std::sin(a) * frame.t);
    };
    for (int k = 0; k < segments; ++k) {
      lines.push_back(at(k));
      lines.push_back(at(k + 1));
    }
  }
  return lines;
}

}  // namespace firstshot
