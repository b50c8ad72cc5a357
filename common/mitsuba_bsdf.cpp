// Mitsuba 3 <bsdf> plugins → MaterialDesc (docs/scene-format.md, "Mitsuba 3 XML scenes").
#include "common/mitsuba_bsdf.h"

#include <algorithm>
#include <array>
#include <cmath>

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

/// Linear RGB reflectance at normal incidence of Mitsuba's conductor presets (Real-Time Rendering,
/// 4th ed., table 9.2); "none" is Mitsuba's ideal 100 % mirror.
const std::map<std::string, Color>& conductorF0s() {
  static const std::map<std::string, Color> table = {
      {"none", Color(1.0f)},                      {"Au", Color(1.000f, 0.782f, 0.344f)},
      {"Ag", Color(0.972f, 0.960f, 0.915f)},      {"Cu", Color(0.955f, 0.638f, 0.538f)},
      {"Al", Color(0.913f, 0.922f, 0.924f)},      {"Cr", Color(0.549f, 0.556f, 0.554f)},
      {"Hg", Color(0.781f, 0.780f, 0.778f)},      {"Ni_palik", Color(0.660f, 0.609f, 0.526f)}};
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

/// A conductor's reflectance at normal incidence: from eta and k (relative to ext_eta) when given, else from the
/// "material" preset; times specular_reflectance.
Color conductorF0(Plugin& p) {
  Color f0;
  if (p.has("eta") || p.has("k")) {
    const double ext = p.number("ext_eta", 1.0);
    const Color eta = p.color("eta", Color(0.0f)) / float(ext), k = p.color("k", Color(1.0f)) / float(ext);
    for (int c = 0; c < 3; ++c)
      f0[c] = ((eta[c] - 1) * (eta[c] - 1) + k[c] * k[c]) / ((eta[c] + 1) * (eta[c] + 1) + k[c] * k[c]);
  } else {
    const std::string name = p.string("material", "none");
    const auto it = conductorF0s().find(name);
    if (it == conductorF0s().end())
      p.doc().fail(p.take("material"), "conductor material \"" + name + "\" has no RGB table here (" + keys(conductorF0s()) +
                                           "; or give eta and k)");
    f0 = it->second;
  }
  return glm::min(f0 * p.color("specular_reflectance", Color(1.0f)), Color(1.0f));
}

/// alpha, or the mean of alpha_u and alpha_v (anisotropy noted).
double roughness(Plugin& p) {
  if (!p.has("alpha_u") && !p.has("alpha_v")) return p.number("alpha", 0.1);
  p.doc().note("anisotropic", "anisotropic roughness approximated by the mean of alpha_u and alpha_v");
  return 0.5 * (p.number("alpha_u", 0.1) + p.number("alpha_v", 0.1));
}

/// The diffuse reflectance (or pbr base colour) of @p m from @p c: its factor and texture.
void setAlbedo(MaterialDesc& m, const TexturedColor& c) {
  m.albedo = c.factor;
  m.albedoTexture = c.texture;
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
    setAlbedo(m, textures_.color(p, "reflectance", Color(0.5f)));
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
  } else if (t == "conductor") {
    m.type = MaterialType::Mirror;
    m.specular = conductorF0(p);
    doc_.note(t, "conductor approximated as a mirror reflecting its Fresnel reflectance at normal incidence");
  } else if (t == "roughconductor") {
    m.type = MaterialType::Pbr;
    m.albedo = conductorF0(p);
    m.metallic = 1.0f;
    m.roughness = float(std::sqrt(std::clamp(roughness(p), 0.0, 1.0)));
    doc_.note(t, "roughconductor mapped to the pbr material (metallic 1, roughness = sqrt(alpha), base colour = "
                 "Fresnel reflectance at normal incidence, Schlick's Fresnel for the complex one)");
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

