// Mitsuba 3 <bsdf> plugins → MaterialDesc (docs/scene-format.md, "Mitsuba 3 XML scenes").
#include "common/formats/mitsuba/mitsuba_bsdf.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

#include "common/formats/mitsuba/mitsuba_lobes.h"
#include "common/materials/conductor_presets.h"
#include "common/materials/thin_glass.h"

namespace firstshot::mitsuba {
namespace {

/// Mitsuba's named indices of refraction (its "ior" table).
const std::map<std::string, double>& namedIors() {
  static const std::map<std::string, double> table = {
      {"vacuum", 1.0},         {"helium", 1.000036},         {"hydrogen", 1.000132},     {"air", 1.000277},
      {"carbon dioxide", 1.00045}, {"water", 1.3330},        {"acetone", 1.36},          {"ethanol", 1.361},
      {"carbon tetrachloride", 1.461}, {"glycerol", 1.4729}, {"benzene", 1.501},         {"silicone oil", 1.52045},
      {"bromine", 1.661},      {"water ice", 1.31},          {"fused quartz", 1.458},    {"pyrex", 1.470},
      {"acrylic glass", 1.49}, {"polypropylene", 1.49},      {"bk7", 1.5046},            {"sodium chloride", 1.544},
      {"amber", 1.55},         {"pet", 1.5750},              {"diamond", 2.419}};
  return table;
}

template <typename Table>
std::string keys(const Table& table) {
  std::string list;
  for (const auto& [k, v] : table) list += (list.empty() ? "" : ", ") + k;
  return list;
}

/// An index of refraction given as a number or as one of Mitsuba's names.
double ior(Plugin& p, const char* name, const char* fallback) {
  const pugi::xml_node n = p.take(name);
  if (n && std::string(n.name()) == "float") {
    const double v = numbers(p.doc(), n, "value", 1)[0];
    if (!(v > 0)) p.doc().fail(n, "an index of refraction must be positive");
    return v;
  }
  if (n && std::string(n.name()) != "string") p.doc().fail(n, "expected <float> or <string>");
  const std::string key = n ? n.attribute("value").value() : fallback;
  const auto it = namedIors().find(key);
  if (it == namedIors().end()) p.doc().fail(n, "unknown index of refraction \"" + key + "\" (" + keys(namedIors()) + ")");
  return it->second;
}

/// Whether the document is a Mitsuba 0.x scene (`version` below 2), whose defaults differ here and there.
bool mitsuba0(const Document& doc) { return std::atoi(doc.scene().attribute("version").value()) < 2; }

/// A conductor's Fresnel as Mitsuba defines it: the `material` preset (common/materials/conductor_presets.h; Mitsuba 3's default
/// "none", the ideal mirror, Mitsuba 0.x's "Cu"), whose η and k an explicit `eta` and `k` replace, both over
/// `ext_eta` (a number or a named index; Mitsuba 3 vacuum, Mitsuba 0.x air).
ConductorFresnel conductorFresnel(Plugin& p) {
  const bool v0 = mitsuba0(p.doc());
  const pugi::xml_node named = p.take("material");
  if (named && std::string(named.name()) != "string") p.doc().fail(named, "expected <string>");
  const std::string name = named ? named.attribute("value").value() : v0 ? "Cu" : "none";
  const std::optional<ConductorFresnel> preset = conductorPreset(name);
  if (!preset) p.doc().fail(named, "unknown conductor material \"" + name + "\" (" + conductorPresetNames() + "; or give eta and k)");
  const float ext = float(ior(p, "ext_eta", v0 ? "air" : "vacuum"));
  return ConductorFresnel(p.color("eta", preset->eta()) / ext, p.color("k", preset->k()) / ext);
}

/// alpha, or the mean of alpha_u and alpha_v (anisotropy noted).
double roughness(Plugin& p) {
  if (!p.has("alpha_u") && !p.has("alpha_v")) return p.number("alpha", 0.1);
  p.doc().note("anisotropic", "anisotropic roughness approximated by the mean of alpha_u and alpha_v");
  return 0.5 * (p.number("alpha_u", 0.1) + p.number("alpha_v", 0.1));
}

/// `distribution`: Mitsuba's default beckmann, ggx, or phong (Beckmann's near twin, as Beckmann of the same alpha,
/// noted).
MicrofacetModel microfacet(Plugin& p) {
  const std::string d = p.string("distribution", "beckmann");
  if (d == "ggx") return MicrofacetModel::Ggx;
  if (d == "phong")
    p.doc().note("phong_distribution", "the phong microfacet distribution rendered as Beckmann of the same alpha");
  else if (d != "beckmann")
    p.doc().fail(p.node(), "unknown microfacet distribution \"" + d + "\" (beckmann, ggx, phong)");
  return MicrofacetModel::Beckmann;
}

/// The diffuse reflectance (or pbr base colour) of @p m from @p c: its factor and texture.
void setAlbedo(MaterialDesc& m, const TexturedColor& c) {
  m.albedo = c.factor;
  m.albedoTexture = c.texture;
}

/// Mitsuba 0.6's energy conservation of a diffuse and a specular part (its ensureEnergyConservation): both scaled by
/// 1/s when the sum s of their largest channels exceeds 1.
void conserveEnergy(TexturedColor& diffuse, Color& specular) {
  float top = 0.0f;  // the largest texel
  if (diffuse.texture)
    for (const Color& c : diffuse.texture->image->texels) top = std::max(top, maxComponent(c));
  const float s = maxComponent(diffuse.factor) * (diffuse.texture ? top : 1.0f) + maxComponent(specular);
  if (s > 1.0f) diffuse.factor /= s, specular /= s;
}

/// The glossy material (stretched Phong, docs/scene-format.md) of diffuse reflectance @p diffuse plus a Phong lobe of
/// exponent @p n whose albedo at normal incidence is @p lobeAlbedo: glossy's lobe reflects specular·(n+1)/(n+2)
/// there, so specular = lobeAlbedo·(n+2)/(n+1); then fitted to glossy's bound (leaveRoomForLobe).
MaterialDesc glossyMaterial(const TexturedColor& diffuse, const Color& lobeAlbedo, double n) {
  MaterialDesc m;
  m.type = MaterialType::Glossy;
  m.exponent = float(n);
  m.specular = glm::min(lobeAlbedo * float((n + 2) / (n + 1)), Color(1.0f));
  setAlbedo(m, diffuse);
  leaveRoomForLobe(m);
  return m;
}

}  // namespace

int BsdfMapper::material(pugi::xml_node node) {
  const auto it = done_.find(node);
  if (it != done_.end()) return it->second;
  MaterialDesc m = map(node, false);
  m.name = node.attribute("id") ? node.attribute("id").value() : doc_.path(node);
  scene_.materials.push_back(m);
  return done_[node] = int(scene_.materials.size() - 1);
}

int BsdfMapper::defaultMaterial() {
  if (default_ < 0) {
    MaterialDesc m;
    m.name = "default (diffuse 0.5)";
    m.albedo = Color(0.5f);
    scene_.materials.push_back(m);
    default_ = int(scene_.materials.size() - 1);
  }
  return default_;
}

MaterialDesc BsdfMapper::map(pugi::xml_node node, bool wrapped) {
  const Document::Nested nested(doc_, node);
  Plugin p(doc_, node);
  const std::string& t = p.type();
  if (t == "blendbsdf") return blended(p, wrapped);
  if (t == "mask") return masked(p, wrapped);
  if (t == "coating" || t == "roughcoating") return coated(p, wrapped);
  if (t == "twosided" || t == "bumpmap" || t == "normalmap") {
    const std::vector<pugi::xml_node> inner = p.nested("bsdf");
    if (inner.empty()) doc_.fail(node, t + " needs a nested <bsdf>");
    if (t == "twosided") {
      if (inner.size() > 1) doc_.note("twosided2", "twosided with two bsdfs: the front one is used on both sides");
      p.finish();
    } else {
      doc_.note(t, t + " approximated by its nested bsdf (the surface detail is dropped)");
    }
    return map(inner[0], wrapped || t == "twosided");
  }
  MaterialDesc m;
  const bool glass = t == "dielectric" || t == "roughdielectric" || t == "thindielectric";
  if (!wrapped && !glass)
    doc_.note("onesided", "a bsdf without twosided is black from behind in Mitsuba; firstshot's surfaces reflect on both sides");
  if (t == "diffuse") {
    setAlbedo(m, textures_.color(p, "reflectance", Color(0.5f)));
  } else if (t == "roughdiffuse") {
    // Lambert of Oren–Nayar's white-sky albedo (common/formats/mitsuba/mitsuba_lobes.h): the same light reflected in all, spread
    // evenly instead of back towards the light; ρ² (facets lighting each other) from the texture's mean.
    const char* key = p.has("reflectance") || !p.has("diffuse_reflectance") ? "reflectance" : "diffuse_reflectance";
    const TexturedColor rho = textures_.color(p, key, Color(0.5f));
    const double alpha = textures_.scalar(p, "alpha", 0.2);
    if (!(alpha >= 0)) doc_.fail(p.take("alpha"), "alpha must not be negative");
    const OrenNayarAlbedo on = orenNayarAlbedo(alpha, p.boolean("use_fast_approx", false));
    setAlbedo(m, rho);
    m.albedo = rho.factor * (float(on.single) + float(on.twice) * rho.mean());
    doc_.note(t, "roughdiffuse (Oren–Nayar, sigma = alpha/sqrt(2)) mapped to diffuse: albedo = its white-sky albedo "
                 "(0.988 × reflectance at alpha 0.2, reflectance 0.5); its backscatter towards the light and flatter "
                 "look are not modelled");
  } else if (t == "phong" || t == "ward") {
    m = glossy(p);
  } else if (t == "plastic" || t == "roughplastic") {
    // A dielectric coat of index η over a diffuse base: the metallic-roughness model with metallic 0 (its
    // Schlick Fresnel and GGX lobe for Mitsuba's exact Fresnel and GGX/Beckmann lobe; Mitsuba's internal
    // scattering under the coat, "nonlinear", is not modelled).
    m.type = MaterialType::Pbr;
    m.ior = float(ior(p, "int_ior", "polypropylene") / ior(p, "ext_ior", "air"));
    setAlbedo(m, textures_.color(p, "diffuse_reflectance", Color(0.5f)));
    m.albedo = glm::min(m.albedo, Color(1.0f));
    m.metallic = 0.0f;
    m.roughness = t == "plastic" ? 0.0f : float(std::sqrt(std::clamp(roughness(p), 0.0, 1.0)));
    if (p.has("specular_reflectance"))
      doc_.note("plastic_specular", "a plastic's specular_reflectance is ignored (the coat's Fresnel reflection kept)");
    p.take("specular_reflectance");
    doc_.note(t, t + " mapped to the pbr material (metallic 0, roughness = sqrt(alpha), ior = int_ior/ext_ior, "
                     "base colour = diffuse_reflectance)");
  } else if (t == "conductor") {  // a mirror of reflectance specular_reflectance × F(η, k): exact
    m.type = MaterialType::Mirror;
    m.conductor = conductorFresnel(p);
    m.specular = glm::min(p.color("specular_reflectance", Color(1.0f)), Color(1.0f));
  } else if (t == "roughconductor") {
    m.type = MaterialType::Pbr;
    m.conductor = conductorFresnel(p);
    m.albedo = glm::min(p.color("specular_reflectance", Color(1.0f)), Color(1.0f));
    m.metallic = 1.0f;
    m.roughness = float(std::sqrt(std::clamp(roughness(p), 0.0, 1.0)));
    m.microfacet = microfacet(p);
    p.take("sample_visible");  // a sampling choice: the same expected image
    doc_.note(t, "roughconductor mapped to the pbr material (metallic 1, roughness = sqrt(alpha), tint = "
                 "specular_reflectance, the exact Fresnel of eta + ik); its Smith masking-shadowing is "
                 "height-correlated where Mitsuba's is the product G1(wi)·G1(wo)");
  } else if (t == "principled") {
    // Mitsuba's Disney-style principled BSDF shares base_color, metallic and roughness (α = roughness²) with the
    // glTF model; its specular is eta's other name. Sheen, clearcoat, transmission and anisotropy are dropped.
    m.type = MaterialType::Pbr;
    setAlbedo(m, textures_.color(p, "base_color", Color(0.5f)));
    m.albedo = glm::min(m.albedo, Color(1.0f));
    m.metallic = float(std::clamp(p.number("metallic", 0.0), 0.0, 1.0));
    m.roughness = float(std::clamp(p.number("roughness", 0.5), 0.0, 1.0));
    const double eta = p.number("eta", 1.5);
    if (!(eta > 0)) doc_.fail(node, "principled's eta must be positive");
    m.ior = float(eta);
    doc_.note(t, "principled mapped to the pbr material (base_color, metallic, roughness, eta; its sheen, clearcoat, "
                 "transmission, anisotropy and specular tint are not modelled)");
  } else if (glass) {
    m.type = MaterialType::Dielectric;
    m.ior = float(ior(p, "int_ior", "bk7") / ior(p, "ext_ior", "air"));
    m.transmittance = p.color("specular_transmittance", Color(1.0f));
    if (p.has("specular_reflectance"))
      doc_.note("specular_reflectance", "a dielectric's specular_reflectance is ignored (Fresnel reflection kept)");
    p.take("specular_reflectance");
    if (t == "roughdielectric") {
      m.glassRoughness = float(std::sqrt(std::clamp(roughness(p), 0.0, 1.0)));  // rough glass, α = r²
    } else if (t == "thindielectric") {  // a window pane: thin_glass of that index, lossless unless tinted
      m.type = MaterialType::ThinGlass;  // Mitsuba's R + T²R/(1 − R²) per face pair, times specular_transmittance
      if (m.ior > 0.0f && m.ior < 1.0f) m.ior = 1.0f / m.ior;  // a pane is the same seen from either side
      m.transmittance *= ThinGlassBSDF::maxTransmittance(m.ior);
    }
  } else {
    doc_.fail(node, "bsdf type \"" + t + "\" is not supported (diffuse, roughdiffuse, twosided, plastic, roughplastic, "
                    "phong, ward, conductor, roughconductor, principled, dielectric, roughdielectric, thindielectric, "
                    "coating, roughcoating, blendbsdf, mask, bumpmap, normalmap)");
  }
  p.finish();
  return m;
}

void leaveRoomForLobe(MaterialDesc& m) {
  if (maxComponent(m.albedo + m.specular) <= 1.0f) return;
  if (m.albedoTexture) {  // the texels carry the diffuse reflectance, the factor only what leaves room for the lobe
    const Color room = glm::max(Color(1.0f) - m.specular, Color(1e-6f)), scale = m.albedo / room;
    m.albedoTexture = mapTexels(*m.albedoTexture, [&](const Color& c) { return glm::min(c * scale, Color(1.0f)); });
    m.albedo = glm::min(m.albedo, room);
  } else {
    m.specular = glm::max(glm::min(m.specular, Color(1.0f) - m.albedo), Color(0.0f));
  }
}

pugi::xml_node BsdfMapper::onlyNested(Plugin& p) {
  const std::vector<pugi::xml_node> inner = p.nested("bsdf");
  if (inner.size() != 1) doc_.fail(p.node(), p.type() + " needs one nested <bsdf> (it has " + std::to_string(inner.size()) + ")");
  return inner[0];
}

MaterialDesc BsdfMapper::glossy(Plugin& p) {
  const std::string& t = p.type();
  TexturedColor diffuse = textures_.color(p, "diffuse_reflectance", Color(0.5f));
  Color specular = p.color("specular_reflectance", Color(0.2f));
  conserveEnergy(diffuse, specular);
  if (t == "phong") {  // Mitsuba's normalised Phong lobe (n+2)/(2π) cosⁿ reflects specular_reflectance at normal incidence
    const double n = textures_.scalar(p, "exponent", 30.0);
    if (!(n >= 0)) doc_.fail(p.take("exponent"), "exponent must not be negative");
    doc_.note(t, "phong mapped to glossy (stretched Phong): the same exponent, albedo = diffuse_reflectance, specular "
                 "matching the lobe's albedo at normal incidence; the stretched lobe keeps more light at grazing angles");
    return glossyMaterial(diffuse, specular, n);
  }
  const std::string variant = p.string("variant", "balanced");
  if (variant != "balanced" && variant != "ward" && variant != "ward-duer")
    doc_.fail(p.take("variant"), "unknown ward variant \"" + variant + "\" (ward, ward-duer, balanced)");
  const double alpha = roughness(p);
  if (!(alpha > 0)) doc_.fail(p.node(), "ward's alpha must be positive");
  doc_.note(t, "ward mapped to glossy (stretched Phong): albedo = diffuse_reflectance, a Phong lobe as wide at normal "
               "incidence (exponent (2/alpha^2 - 2)/4) and of the same albedo there; the Ward lobe's shape at grazing "
               "angles is not kept");
  return glossyMaterial(diffuse, specular * float(wardAlbedoAtNormalIncidence(alpha, variant.c_str())),
                        phongExponentOfRoughness(alpha));
}

MaterialDesc BsdfMapper::coated(Plugin& p, bool wrapped) {
  // A dielectric layer of index η over the nested bsdf, absorbing σa per unit length over its thickness.
  const std::string& t = p.type();
  const double eta = ior(p, "int_ior", "bk7") / ior(p, "ext_ior", "air");
  const Color absorbed = glm::exp(-2.0f * float(p.number("thickness", 1.0)) * p.color("sigma_a", Color(0.0f)));
  const float rough = t == "roughcoating" ? float(std::sqrt(std::clamp(roughness(p), 0.0, 1.0))) : 0.0f;
  if (p.has("specular_reflectance"))
    doc_.note("coating_specular", "a coating's specular_reflectance is ignored (the coat's Fresnel reflection kept)");
  p.take("specular_reflectance");
  MaterialDesc m = map(onlyNested(p), wrapped);
  p.finish();
  if (m.type == MaterialType::Diffuse && !m.isEmissive()) {  // a coated diffuse base is what the pbr material models
    m.type = MaterialType::Pbr;
    m.albedo = glm::min(m.albedo * absorbed, Color(1.0f));
    m.metallic = 0.0f;
    m.roughness = rough;
    m.ior = float(eta);
    doc_.note(t, t + " over a diffuse bsdf mapped to the pbr material (metallic 0, ior = int_ior/ext_ior, roughness "
                     "= sqrt(alpha); base colour = reflectance × the coat's absorption at normal incidence, "
                     "exp(-2 sigma_a thickness)), as plastic");
    return m;
  }
  m.albedo *= absorbed, m.specular *= absorbed;
  if (m.type == MaterialType::Dielectric || m.type == MaterialType::ThinGlass) m.transmittance *= absorbed;
  doc_.note(t + " other", t + " over a bsdf other than diffuse: the nested bsdf, tinted by the coat's absorption at "
                          "normal incidence; the coat's own reflection is not modelled");
  return m;
}

}  // namespace firstshot::mitsuba
