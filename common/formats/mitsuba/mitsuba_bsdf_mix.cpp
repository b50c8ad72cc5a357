// Mitsuba's blendbsdf and mask → MaterialDesc (docs/scene-format.md, "Mitsuba 3 XML scenes"; common/formats/mitsuba/mitsuba_bsdf.h).
#include <algorithm>
#include <cmath>

#include "common/formats/mitsuba/mitsuba_bsdf.h"

namespace firstshot::mitsuba {
namespace {

/// A weight or opacity texel as Mitsuba reads a colour texture where it takes one number: its channels' mean.
float grey(const Color& c) { return std::clamp((c.x + c.y + c.z) / 3.0f, 0.0f, 1.0f); }

template <typename T>
T lerp(const T& a, const T& b, float w) {
  return a * (1.0f - w) + b * w;
}

/// (1 − w)·a + w·b per point, for colours @p a, @p b and a weight @p w that may each vary (@p wMean: w's mean).
/// Exact (@p exact stays true) while at most one of the three has a texture: the blend is baked into that texture's
/// texels, which keeps its filter, wrap modes and transform. Otherwise the texture of the heavier side, its factor
/// chosen so that the mean is the blend's mean.
TexturedColor blendColors(const TexturedColor& a, const TexturedColor& b, const TexturedColor& w, float wMean,
                          bool& exact) {
  const int textures = int(bool(a.texture)) + int(bool(b.texture)) + int(bool(w.texture));
  if (textures == 0) return {lerp(a.factor, b.factor, wMean), nullptr};
  if (textures == 1) {
    if (a.texture)
      return {Color(1.0f), mapTexels(*a.texture, [&](const Color& c) { return lerp(a.factor * c, b.factor, wMean); })};
    if (b.texture)
      return {Color(1.0f), mapTexels(*b.texture, [&](const Color& c) { return lerp(a.factor, b.factor * c, wMean); })};
    return {Color(1.0f), mapTexels(*w.texture, [&](const Color& c) { return lerp(a.factor, b.factor, grey(w.factor * c)); })};
  }
  exact = false;
  const TexturedColor& kept = (wMean >= 0.5f && b.texture) || !a.texture ? b : a;
  const Color target = lerp(a.mean(), b.mean(), wMean), mean = kept.texture->image->mean;
  Color factor(0.0f);
  for (int c = 0; c < 3; ++c) factor[c] = mean[c] > 0.0f ? std::min(target[c] / mean[c], 1.0f) : 0.0f;
  return {factor, kept.texture};
}

TexturedColor albedoOf(const MaterialDesc& m) { return {m.albedo, m.albedoTexture}; }

/// The index of refraction whose Fresnel reflectance at normal incidence is @p f0 ∈ [0, 1).
float iorOfF0(double f0) {
  const double r = std::sqrt(std::clamp(f0, 0.0, 0.999));
  return float((1 + r) / (1 - r));
}

/// F0 = ((η − 1)/(η + 1))² of index @p ior.
double f0Of(double ior) { return (ior - 1) * (ior - 1) / ((ior + 1) * (ior + 1)); }

/// A mirror as the pbr metal it nearly is (roughness 0: α = 10⁻³), so that it can blend with a diffuse or pbr one.
MaterialDesc asPbrMetal(const MaterialDesc& mirror) {
  MaterialDesc m = mirror;
  m.type = MaterialType::Pbr;
  m.albedo = glm::min(mirror.specular, Color(1.0f));
  m.albedoTexture = nullptr;
  m.specular = Color(0.0f);
  m.metallic = 1.0f, m.roughness = 0.0f;
  return m;
}

}  // namespace

MaterialDesc BsdfMapper::blended(Plugin& p, bool wrapped) {
  const std::vector<pugi::xml_node> inner = p.nested("bsdf");
  if (inner.size() != 2) doc_.fail(p.node(), "blendbsdf needs two nested <bsdf> (it has " + std::to_string(inner.size()) + ")");
  TexturedColor w = textures_.color(p, "weight", Color(0.5f));
  const float wMean = grey(w.mean());
  MaterialDesc a = map(inner[0], wrapped), b = map(inner[1], wrapped);
  p.finish();
  if (!w.texture && wMean <= 0.0f) return a;  // (1 − w)·first + w·second
  if (!w.texture && wMean >= 1.0f) return b;
  // A diffuse bsdf beside a glossy one is a glossy one without lobe; a mirror beside a diffuse or pbr one, the pbr
  // metal of roughness 0.
  for (auto [x, y] : {std::pair{&a, &b}, std::pair{&b, &a}}) {
    if (x->type == MaterialType::Diffuse && y->type == MaterialType::Glossy) x->type = MaterialType::Glossy, x->exponent = y->exponent;
    if (x->type == MaterialType::Mirror && (y->type == MaterialType::Diffuse || y->type == MaterialType::Pbr)) *x = asPbrMetal(*x);
  }
  bool exact = true;
  MaterialDesc m = wMean >= 0.5f ? b : a;  // the heavier one: names, alpha and whatever is not blended below
  const TexturedColor albedo = blendColors(albedoOf(a), albedoOf(b), w, wMean, exact);
  if (a.type == b.type) {
    // Each part of these materials is linear in its colours (albedo, specular, transmittance): blending those is
    // exact while the other parameters agree; the others are blended too, approximately.
    const auto same = [](float x, float y) { return x == y; };
    exact = exact && (a.type != MaterialType::Glossy || same(a.exponent, b.exponent)) &&
            (a.type != MaterialType::Pbr || (same(a.metallic, b.metallic) && same(a.roughness, b.roughness) && same(a.ior, b.ior))) &&
            ((a.type != MaterialType::Dielectric && a.type != MaterialType::ThinGlass) ||
             (same(a.ior, b.ior) && same(a.glassRoughness, b.glassRoughness) && (a.type == MaterialType::Dielectric || a.transmittance == b.transmittance))) &&
            (!w.texture || (a.specular == b.specular && a.transmittance == b.transmittance));
    m.albedo = albedo.factor, m.albedoTexture = albedo.texture;
    m.specular = lerp(a.specular, b.specular, wMean), m.transmittance = lerp(a.transmittance, b.transmittance, wMean);
    m.exponent = lerp(a.exponent, b.exponent, wMean), m.ior = lerp(a.ior, b.ior, wMean);
    m.metallic = lerp(a.metallic, b.metallic, wMean), m.roughness = lerp(a.roughness, b.roughness, wMean);
    m.glassRoughness = lerp(a.glassRoughness, b.glassRoughness, wMean);
    if (m.type == MaterialType::Glossy) leaveRoomForLobe(m);  // a texture baked with factor 1 beside a lobe
    if (!exact)
      doc_.note("blendbsdf mix", "blendbsdf of two bsdfs of one kind whose lobes differ (exponent, roughness, index, "
                                 "metallic): their parameters blended by the weight (its mean where it is a texture)");
  } else if ((a.type == MaterialType::Diffuse && b.type == MaterialType::Pbr) ||
             (a.type == MaterialType::Pbr && b.type == MaterialType::Diffuse)) {
    // The pbr material's metal part takes its weight's share, its dielectric coat the share that keeps the coat's
    // reflectance at normal incidence; the diffuse reflectances and base colours are blended per point.
    const MaterialDesc& pbr = a.type == MaterialType::Pbr ? a : b;
    const float wp = a.type == MaterialType::Pbr ? 1.0f - wMean : wMean;
    m = pbr;
    m.albedo = glm::min(albedo.factor, Color(1.0f)), m.albedoTexture = albedo.texture;
    m.metallic = wp * pbr.metallic;
    m.ior = m.metallic < 1.0f ? iorOfF0(f0Of(pbr.ior) * wp * (1 - pbr.metallic) / (1 - m.metallic)) : pbr.ior;
    exact = false;
    doc_.note("blendbsdf pbr", "blendbsdf of a diffuse and a pbr-like bsdf mapped to the pbr material: base colour "
                               "blended, metallic and the coat's reflectance at normal incidence scaled by the weight");
  } else {
    exact = false;
    doc_.note("blendbsdf heavier", "blendbsdf of bsdfs that do not combine here (glass, mirror, glossy with pbr): "
                                   "the one of larger weight is used");
    return m;
  }
  if (a.isCutout() || b.isCutout())
    doc_.note("blendbsdf mask", "blendbsdf of masked bsdfs: the opacity of the one of larger weight is used");
  return m;
}

MaterialDesc BsdfMapper::masked(Plugin& p, bool wrapped) {
  // Mitsuba's mask lets a ray through with probability 1 − opacity: the blend cut-out's stochastic transparency.
  std::shared_ptr<const Texture> texture;
  float opacity = 1.0f;
  const pugi::xml_node node = p.take("opacity");
  const pugi::xml_node target = node ? doc_.resolve(node) : node;
  const std::string type = target ? target.attribute("type").value() : "";
  if (target && std::string(target.name()) == "texture" && (type == "bitmap" || type == "checkerboard"))
    texture = textures_.opacity(target);
  else
    opacity = float(std::clamp(textures_.scalar(p, "opacity", 0.5), 0.0, 1.0));
  MaterialDesc m = map(onlyNested(p), wrapped);
  p.finish();
  if (!texture && opacity >= 1.0f) return m;
  if (m.type != MaterialType::Diffuse && m.type != MaterialType::Glossy && m.type != MaterialType::Pbr) {
    doc_.note("mask glass", "mask over a glass or mirror bsdf: its opacity is dropped (cut-outs apply to reflecting "
                            "surfaces: diffuse, glossy, pbr)");
    return m;
  }
  m.alphaMode = AlphaMode::Blend;
  if (!texture) {
    m.alpha *= opacity;  // a mask inside a mask: the probabilities of meeting the surface multiply
  } else {
    if (m.alphaTexture) doc_.note("mask mask", "a textured mask inside a textured mask: the outer opacity is used");
    m.alphaTexture = texture;
  }
  return m;
}

}  // namespace firstshot::mitsuba
