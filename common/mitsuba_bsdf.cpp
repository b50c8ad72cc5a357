// Mitsuba 3 <bsdf> plugins → MaterialDesc (docs/scene-format.md, "Mitsuba 3 XML scenes").
#include "common/mitsuba_bsdf.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

#include "common/conductor_presets.h"
#include "common/thin_glass.h"

namespace fs::mitsuba {
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

/// A conductor's Fresnel as Mitsuba defines it: the `material` preset (common/conductor_presets.h; Mitsuba 3's default
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
    m.albedo = p.color("reflectance", Color(0.5f));
  } else if (t == "plastic" || t == "roughplastic") {
    // A dielectric coat of index η over a diffuse base: the metallic-roughness model with metallic 0 (its
    // Schlick Fresnel and GGX lobe for Mitsuba's exact Fresnel and GGX/Beckmann lobe; Mitsuba's internal
    // scattering under the coat, "nonlinear", is not modelled).
    m.type = MaterialType::Pbr;
    m.ior = float(ior(p, "int_ior", "polypropylene") / ior(p, "ext_ior", "air"));
    m.albedo = glm::min(p.color("diffuse_reflectance", Color(0.5f)), Color(1.0f));
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
    m.albedo = glm::min(p.color("base_color", Color(0.5f)), Color(1.0f));
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
      m.glassRoughness = float(std::sqrt(std::clamp(roughness(p), 0.0, 1.0)));  // issue 34: rough glass, α = r²
    } else if (t == "thindielectric") {  // a window pane: thin_glass of that index, lossless unless tinted
      m.type = MaterialType::ThinGlass;  // Mitsuba's R + T²R/(1 − R²) per face pair, times specular_transmittance
      if (m.ior > 0.0f && m.ior < 1.0f) m.ior = 1.0f / m.ior;  // a pane is the same seen from either side
      m.transmittance *= ThinGlassBSDF::maxTransmittance(m.ior);
    }
  } else {
    doc_.fail(node, "bsdf type \"" + t + "\" is not supported (diffuse, twosided, plastic, roughplastic, conductor, "
                    "roughconductor, principled, dielectric, roughdielectric, thindielectric, bumpmap, normalmap)");
  }
  p.finish();
  return m;
}

}  // namespace fs::mitsuba
