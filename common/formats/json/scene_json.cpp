// Parsing the JSON scene format (docs/scene-format.md) into SceneDesc. Every key is checked:
// unknown keys are errors, and every error names the file and the element's JSON path.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include "common/formats/assets/mesh_import.h"
#include "common/formats/json/scene_json.h"
#include "common/formats/json/scene_json_reader.h"
#include "common/formats/json/scene_sky.h"
#include "common/lights/ies.h"
#include "common/lights/photometry.h"
#include "common/lights/spot_cone.h"
#include "common/materials/conductor_presets.h"
#include "common/materials/texture.h"
#include "common/materials/thin_glass.h"
#include "common/scene/scene_desc.h"
#include "common/scene/scene_shapes.h"
#include "common/scene/skipped_faces.h"
#include "common/util/error.h"

namespace firstshot {
namespace {

using Reader = SceneJsonReader;

Mat4d parseTransform(const Reader& r, const Json& j, const std::string& where) {
  r.keys(j, where, {"translate", "rotate", "scale", "matrix"});
  if (j.contains("matrix")) {
    if (j.size() != 1) r.fail(where, "\"matrix\" cannot be combined with translate/rotate/scale");
    const Json& m = j["matrix"];
    if (!m.is_array() || m.size() != 16) r.fail(where + ".matrix", "expected 16 numbers (row-major)");
    Mat4d M(1.0);
    for (int row = 0; row < 4; ++row)
      for (int col = 0; col < 4; ++col)
        M[col][row] = r.number(m[row * 4 + col], where + ".matrix[" + std::to_string(row * 4 + col) + "]");
    return M;
  }
  Mat4d S(1.0), R(1.0), T(1.0);
  if (j.contains("scale")) {
    Vec3d s = j["scale"].is_number() ? Vec3d(r.positive(j["scale"], where + ".scale"))
                                     : r.vec3(j["scale"], where + ".scale");
    if (s.x == 0 || s.y == 0 || s.z == 0) r.fail(where + ".scale", "scale must not be zero");
    S = glm::scale(Mat4d(1.0), s);
  }
  if (j.contains("rotate")) {
    const Json& rot = j["rotate"];
    const std::string w = where + ".rotate";
    if (!rot.is_array() || rot.size() != 4) r.fail(w, "expected [axis x, axis y, axis z, angle in degrees]");
    Vec3d axis(r.number(rot[0], w + "[0]"), r.number(rot[1], w + "[1]"), r.number(rot[2], w + "[2]"));
    if (glm::length(axis) == 0) r.fail(w, "rotation axis is zero");
    R = glm::rotate(Mat4d(1.0), glm::radians(r.number(rot[3], w + "[3]")), glm::normalize(axis));
  }
  if (j.contains("translate")) T = glm::translate(Mat4d(1.0), r.vec3(j["translate"], where + ".translate"));
  return T * R * S;
}

/// Images read so far, by resolved path: a file used by several materials is read once.
using TextureImages = std::map<std::string, std::shared_ptr<const TexelImage>>;

/// A texture's wrap mode by name: repeat, clamp or mirror.
TextureWrap parseWrap(const Reader& r, const Json& j, const std::string& where) {
  const std::string w = r.string(j, where);
  if (w != "repeat" && w != "clamp" && w != "mirror") r.fail(where, "unknown wrap mode \"" + w + "\" (repeat, clamp, mirror)");
  return w == "clamp" ? TextureWrap::ClampToEdge : w == "mirror" ? TextureWrap::MirroredRepeat : TextureWrap::Repeat;
}

/// "albedo_texture": a file name (relative to the scene file), or {"file", "wrap", "filter", "offset", "scale",
/// "rotation"} (docs/scene-format.md). A file that cannot be read is an error naming it and the material @p name.
std::shared_ptr<const Texture> parseTexture(const Reader& r, const Json& j, const std::string& name,
                                            const std::string& where, TextureImages& images, bool srgb = true) {
  auto texture = std::make_shared<Texture>();
  const Json* file = &j;
  if (j.is_object()) {
    r.keys(j, where, {"file", "wrap", "filter", "offset", "scale", "rotation"});
    file = &r.need(j, where, "file");
    if (j.contains("wrap") && j["wrap"].is_array()) {  // [u, v]: a mode per axis
      if (j["wrap"].size() != 2) r.fail(where + ".wrap", "expected a mode or [mode along u, mode along v]");
      texture->wrapU = parseWrap(r, j["wrap"][0], where + ".wrap[0]");
      texture->wrapV = parseWrap(r, j["wrap"][1], where + ".wrap[1]");
    } else if (j.contains("wrap")) {
      texture->wrapU = texture->wrapV = parseWrap(r, j["wrap"], where + ".wrap");
    }
    if (j.contains("filter")) {
      const std::string f = r.string(j["filter"], where + ".filter");
      if (f != "linear" && f != "nearest") r.fail(where + ".filter", "unknown filter \"" + f + "\" (linear, nearest)");
      texture->filter = f == "nearest" ? TextureFilter::Nearest : TextureFilter::Linear;
    }
    const auto pair = [&](const char* key, Vec2& out) {
      const Json& v = j[key];
      const std::string w = where + "." + key;
      if (!v.is_array() || v.size() != 2) r.fail(w, "expected [u, v]");
      out = Vec2(float(r.number(v[0], w + "[0]")), float(r.number(v[1], w + "[1]")));
    };
    if (j.contains("offset")) pair("offset", texture->transform.offset);
    if (j.contains("scale")) pair("scale", texture->transform.scale);
    if (j.contains("rotation"))
      texture->transform.rotation = float(glm::radians(r.number(j["rotation"], where + ".rotation")));
  }
  std::filesystem::path path(r.string(*file, where + (j.is_object() ? ".file" : "")));
  if (path.is_relative()) path = std::filesystem::path(r.file()).parent_path() / path;
  std::shared_ptr<const TexelImage>& image = images[path.string() + (srgb ? "" : "\n(linear)")];
  try {
    if (!image) image = std::make_shared<const TexelImage>(readTexelImage(path.string(), srgb));
  } catch (const InputError& e) {
    r.fail(where, "material \"" + name + "\": " + e.what());
  }
  texture->image = image;
  return texture;
}

/// A dielectric's or thin glass's optional "roughness" ∈ [0, 1] (0, the default, is smooth glass).
float parseGlassRoughness(const Reader& r, const Json& j, const std::string& where) {
  if (!j.contains("roughness")) return 0.0f;
  const double v = r.number(j["roughness"], where + ".roughness");
  if (v < 0 || v > 1) r.fail(where + ".roughness", "must be in [0, 1] (got " + std::to_string(v) + ")");
  return static_cast<float>(v);
}

/// A mirror's or pbr material's optional conductor Fresnel: "conductor" (a preset name, common/materials/conductor_presets.h)
/// or "eta" and "k" together (RGB or one number each, ≥ 0).
void parseConductor(const Reader& r, const Json& j, const std::string& where, MaterialDesc& m) {
  const bool named = j.contains("conductor"), given = j.contains("eta") || j.contains("k");
  if (named && given) r.fail(where + ".conductor", "give either \"conductor\" or \"eta\" and \"k\", not both");
  if (named) {
    const std::string name = r.string(j["conductor"], where + ".conductor");
    m.conductor = conductorPreset(name);
    if (!m.conductor) r.fail(where + ".conductor", "unknown conductor \"" + name + "\" (" + conductorPresetNames() + ")");
  } else if (given) {
    m.conductor = ConductorFresnel(r.color(r.need(j, where, "eta"), where + ".eta"), r.color(r.need(j, where, "k"), where + ".k"));
  }
}

/// A pbr material's optional "microfacet": "ggx" (the default, glTF's) or "beckmann".
MicrofacetModel parseMicrofacet(const Reader& r, const Json& j, const std::string& where) {
  if (!j.contains("microfacet")) return MicrofacetModel::Ggx;
  const std::string d = r.string(j["microfacet"], where + ".microfacet");
  if (d != "ggx" && d != "beckmann") r.fail(where + ".microfacet", "unknown microfacet distribution \"" + d + "\" (ggx, beckmann)");
  return d == "beckmann" ? MicrofacetModel::Beckmann : MicrofacetModel::Ggx;
}

MaterialDesc parseMaterial(const Reader& r, const Json& j, const std::string& name, const std::string& where,
                           TextureImages& images) {
  MaterialDesc m;
  m.name = name;
  const std::string type = r.string(r.need(j, where, "type"), where + ".type");
  if (type == "diffuse") {
    r.keys(j, where, {"type", "albedo", "albedo_texture", "emission", "emission_texture", "normal_texture",
                      "normal_scale"});
    m.type = MaterialType::Diffuse;
  } else if (type == "glossy") {
    r.keys(j, where, {"type", "albedo", "albedo_texture", "specular", "exponent", "emission", "emission_texture",
                      "normal_texture", "normal_scale"});
    m.type = MaterialType::Glossy;
    m.specular = r.color(r.need(j, where, "specular"), where + ".specular");
    m.exponent = static_cast<float>(r.nonNegative(r.need(j, where, "exponent"), where + ".exponent"));
  } else if (type == "mirror") {
    r.keys(j, where, {"type", "specular", "conductor", "eta", "k", "normal_texture", "normal_scale"});
    m.type = MaterialType::Mirror;
    m.specular = Color(1.0f);
    parseConductor(r, j, where, m);
  } else if (type == "dielectric") {
    r.keys(j, where, {"type", "ior", "transmittance", "roughness"});
    m.type = MaterialType::Dielectric;
    m.ior = static_cast<float>(r.positive(r.need(j, where, "ior"), where + ".ior"));
    m.glassRoughness = parseGlassRoughness(r, j, where);
  } else if (type == "thin_glass") {  // a window pane (common/materials/thin_glass.h); transmittance read below
    r.keys(j, where, {"type", "transmittance", "ior", "roughness"});
    m.type = MaterialType::ThinGlass;
    m.transmittance = Color(kThinGlassTransmittance);
    m.ior = j.contains("ior") ? static_cast<float>(r.positive(j["ior"], where + ".ior")) : kThinGlassIor;
    m.glassRoughness = parseGlassRoughness(r, j, where);
  } else if (type == "pbr") {
    r.keys(j, where, {"type", "base_color", "base_color_texture", "metallic", "roughness", "metallic_roughness_texture",
                      "ior", "conductor", "eta", "k", "microfacet", "emission", "emission_texture", "normal_texture",
                      "normal_scale"});
    m.type = MaterialType::Pbr;
    parseConductor(r, j, where, m);
    m.microfacet = parseMicrofacet(r, j, where);
    m.albedo = j.contains("base_color") ? r.color(j["base_color"], where + ".base_color") : Color(1.0f);
    if (maxComponent(m.albedo) > 1.0f) r.fail(where + ".base_color", "must be in [0, 1]");
    auto unit = [&](const char* key, float fallback) {
      if (!j.contains(key)) return fallback;
      const double v = r.number(j[key], where + "." + key);
      if (v < 0 || v > 1) r.fail(where + "." + key, "must be in [0, 1] (got " + std::to_string(v) + ")");
      return static_cast<float>(v);
    };
    m.metallic = unit("metallic", m.metallic);
    m.roughness = unit("roughness", m.roughness);
    if (j.contains("ior")) m.ior = static_cast<float>(r.positive(j["ior"], where + ".ior"));
    if (j.contains("base_color_texture"))  // base colour = base_color (the factor) × the texture at each point
      m.albedoTexture = parseTexture(r, j["base_color_texture"], name, where + ".base_color_texture", images);
    if (j.contains("metallic_roughness_texture"))  // glTF's layout: roughness × G, metallic × B, not sRGB
      m.metallicRoughnessTexture = parseTexture(r, j["metallic_roughness_texture"], name,
                                                where + ".metallic_roughness_texture", images, false);
  } else {
    r.fail(where + ".type", "unknown material type \"" + type + "\" (diffuse, glossy, mirror, dielectric, thin_glass, pbr)");
  }
  if (j.contains("albedo_texture")) {
    m.albedoTexture = parseTexture(r, j["albedo_texture"], name, where + ".albedo_texture", images);
    m.albedo = Color(1.0f);  // the factor, unless given
  }
  if (j.contains("albedo")) m.albedo = r.color(j["albedo"], where + ".albedo");
  if (j.contains("specular")) m.specular = r.color(j["specular"], where + ".specular");
  if (j.contains("transmittance")) m.transmittance = r.color(j["transmittance"], where + ".transmittance");
  if (j.contains("emission")) m.emission = r.color(j["emission"], where + ".emission");
  if (j.contains("emission_texture")) {  // emission × the texel at each point; `emission` the mean
    m.emissionTexture = parseTexture(r, j["emission_texture"], name, where + ".emission_texture", images);
    m.emissionFactor = j.contains("emission") ? m.emission : Color(1.0f);
    m.emission = m.emissionFactor * m.emissionTexture->image->mean;
  }
  // A tangent-space normal map (linear texels, glTF's convention) and its scale.
  if (j.contains("normal_texture"))
    m.normalTexture = parseTexture(r, j["normal_texture"], name, where + ".normal_texture", images, false);
  if (j.contains("normal_scale")) {
    if (!m.normalTexture) r.fail(where + ".normal_scale", "goes with \"normal_texture\"");
    m.normalScale = static_cast<float>(r.number(j["normal_scale"], where + ".normal_scale"));
  }
  return m;
}

// Alpha cut-outs (docs/scene-format.md, "Cut-outs") ----------------------------------------------

/// The alpha keys every textured material type (diffuse, glossy, pbr) takes; parseAlpha reads them.
constexpr std::array<const char*, 4> kAlphaKeys = {"alpha_mode", "alpha_cutoff", "alpha", "alpha_texture"};

/// Material @p j without the alpha keys (what parseMaterial checks).
Json withoutAlphaKeys(const Json& j) {
  Json rest = j;
  if (rest.is_object())
    for (const char* k : kAlphaKeys) rest.erase(k);
  return rest;
}

/// Reads the alpha keys of material @p j into @p m (parsed by parseMaterial): the mode, the cut-off, the factor and
/// the alpha texture (linear; without one, the base-colour texture's A channel when it has one).
void parseAlpha(const Reader& r, const Json& j, const std::string& where, TextureImages& images, MaterialDesc& m) {
  if (!j.is_object() || std::none_of(kAlphaKeys.begin(), kAlphaKeys.end(), [&](const char* k) { return j.contains(k); }))
    return;
  const char* key = *std::find_if(kAlphaKeys.begin(), kAlphaKeys.end(), [&](const char* k) { return j.contains(k); });
  if (m.type != MaterialType::Diffuse && m.type != MaterialType::Glossy && m.type != MaterialType::Pbr)
    r.fail(where + "." + key, "alpha keys apply to diffuse, glossy and pbr materials");
  if (j.contains("alpha_mode")) {
    const std::string mode = r.string(j["alpha_mode"], where + ".alpha_mode");
    if (mode != "opaque" && mode != "mask" && mode != "blend")
      r.fail(where + ".alpha_mode", "unknown alpha mode \"" + mode + "\" (opaque, mask, blend)");
    m.alphaMode = mode == "mask" ? AlphaMode::Mask : mode == "blend" ? AlphaMode::Blend : AlphaMode::Opaque;
  }
  const auto unit = [&](const char* k, float& out) {
    if (!j.contains(k)) return;
    const double v = r.number(j[k], where + "." + k);
    if (!(v >= 0 && v <= 1)) r.fail(where + "." + k, "must be in [0, 1] (got " + std::to_string(v) + ")");
    out = float(v);
  };
  unit("alpha_cutoff", m.alphaCutoff);
  unit("alpha", m.alpha);
  if (j.contains("alpha_texture"))
    m.alphaTexture = parseTexture(r, j["alpha_texture"], m.name, where + ".alpha_texture", images, false);
  else if (m.albedoTexture && !m.albedoTexture->image->alpha.empty())
    m.alphaTexture = m.albedoTexture;
}

// -------------------------------------------------------------------------------------------------------------

/// A "luminaire" key's value: the name of the luminaire a shape or light belongs to (a non-empty string).
std::string luminaireName(const Reader& r, const Json& j, const std::string& where) {
  std::string name = r.string(j, where);
  if (name.empty()) r.fail(where, "the luminaire's name is empty");
  return name;
}

ShapeDesc parseShape(const Reader& r, const Json& j, const std::string& where, const SceneDesc& scene) {
  ShapeDesc s;
  s.name = where;
  const std::string type = r.string(r.need(j, where, "type"), where + ".type");
  std::initializer_list<const char*> common = {"type", "name", "material", "transform", "small", "flip_normals",
                                               "luminaire"};
  std::vector<const char*> allowed(common);
  auto allow = [&](std::initializer_list<const char*> extra) {
    allowed.insert(allowed.end(), extra);
    // keys() takes an initializer_list; check by hand against the vector.
    for (auto it = j.begin(); it != j.end(); ++it) {
      bool ok = false;
      for (const char* a : allowed) ok = ok || it.key() == a;
      if (!ok) r.fail(where, "unknown key \"" + it.key() + "\" for a " + type + " shape");
    }
  };
  if (j.contains("name")) s.name = where + " (\"" + r.string(j["name"], where + ".name") + "\")";
  const std::string mat = r.string(r.need(j, where, "material"), where + ".material");
  s.material = scene.findMaterial(mat);
  if (s.material < 0) r.fail(where + ".material", "unknown material \"" + mat + "\"");
  if (j.contains("small")) s.small = r.small(j["small"], where + ".small");
  if (j.contains("luminaire")) s.luminaire = luminaireName(r, j["luminaire"], where + ".luminaire");

  if (type == "quad") {
    allow({"vertices"});
    s.type = ShapeType::Quad;
    const Json& v = r.need(j, where, "vertices");
    if (!v.is_array() || v.size() != 4) r.fail(where + ".vertices", "a quad needs 4 vertices");
    std::array<Vec3d, 4> q;
    for (int i = 0; i < 4; ++i) q[i] = r.vec3(v[i], where + ".vertices[" + std::to_string(i) + "]");
    shapes::makeQuad(s, q);
  } else if (type == "box") {
    allow({"min", "max"});
    s.type = ShapeType::Box;
    const Vec3d lo = r.vec3(r.need(j, where, "min"), where + ".min");
    const Vec3d hi = r.vec3(r.need(j, where, "max"), where + ".max");
    if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z)) r.fail(where, "box max must exceed min on every axis");
    shapes::makeBox(s, lo, hi);
  } else if (type == "sphere") {
    allow({"center", "radius", "subdivisions", "smooth"});
    s.type = ShapeType::Sphere;
    const Vec3d c = r.vec3(r.need(j, where, "center"), where + ".center");
    const double rad = r.positive(r.need(j, where, "radius"), where + ".radius");
    const int sub = j.contains("subdivisions") ? int(r.integer(j["subdivisions"], where + ".subdivisions", 0, 7)) : 3;
    shapes::makeSphere(s, c, rad, sub);
    if (j.contains("smooth") && r.boolean(j["smooth"], where + ".smooth")) shapes::smoothSphere(s, c);
  } else if (type == "mesh") {
    allow({"file"});
    s.type = ShapeType::Mesh;
    const std::string f = r.string(r.need(j, where, "file"), where + ".file");
    std::filesystem::path p(f);
    if (p.is_relative()) p = std::filesystem::path(r.file()).parent_path() / p;
    s.sourceFile = p.string();
    MeshData mesh = loadMeshFile(s.sourceFile, r.file(), where + ".file");
    s.vertices = std::move(mesh.vertices);
    s.faces = std::move(mesh.faces);
    s.uv = std::move(mesh.uv);
    s.normals = std::move(mesh.normals);  // shading normals from the file
    s.tangents = std::move(mesh.tangents), s.bitangents = std::move(mesh.bitangents);  // and its TANGENT
  } else {
    r.fail(where + ".type", "unknown shape type \"" + type + "\" (quad, box, sphere, mesh)");
  }
  if (j.contains("transform")) shapes::transform(s, parseTransform(r, j["transform"], where + ".transform"));
  if (j.contains("flip_normals") && r.boolean(j["flip_normals"], where + ".flip_normals")) shapes::flip(s);
  return s;
}

/// A mesh shape without "material": the asset file's own meshes and materials (importAssetScene: glTF
/// metallic-roughness with its textures, OBJ/MTL colours and maps), each mesh a shape, the materials appended to the
/// scene's under the shape's name; the shape's transform, "small" and "flip_normals" apply to every mesh. The file's
/// lights and cameras are not used (the JSON scene places its own).
void appendAssetShapes(const Reader& r, const Json& j, const std::string& where, SceneDesc& scene) {
  for (auto it = j.begin(); it != j.end(); ++it) {
    static const std::set<std::string> allowed = {"type", "name", "file", "transform", "small", "flip_normals", "luminaire"};
    if (!allowed.count(it.key())) r.fail(where, "unknown key \"" + it.key() + "\" for a mesh shape");
  }
  std::string name = where;
  if (j.contains("name")) name = where + " (\"" + r.string(j["name"], where + ".name") + "\")";
  std::filesystem::path p(r.string(r.need(j, where, "file"), where + ".file"));
  if (p.is_relative()) p = std::filesystem::path(r.file()).parent_path() / p;
  SceneDesc asset = importAssetScene(p.string());
  const int offset = static_cast<int>(scene.materials.size());
  for (MaterialDesc& m : asset.materials) {
    m.name = name + ": " + m.name;
    scene.materials.push_back(std::move(m));
  }
  const std::optional<Mat4d> m =
      j.contains("transform") ? std::optional(parseTransform(r, j["transform"], where + ".transform")) : std::nullopt;
  const bool flip = j.contains("flip_normals") && r.boolean(j["flip_normals"], where + ".flip_normals");
  const SmallOverride small = j.contains("small") ? r.small(j["small"], where + ".small") : SmallOverride::Auto;
  const std::string luminaire = j.contains("luminaire") ? luminaireName(r, j["luminaire"], where + ".luminaire") : "";
  for (ShapeDesc& s : asset.shapes) {
    s.name = name + ": " + s.name;
    s.material += offset;
    s.small = small;
    s.luminaire = luminaire;
    if (m) shapes::transform(s, *m);
    if (flip) shapes::flip(s);
    scene.shapes.push_back(std::move(s));
  }
}

/// The unit keys of a point, spot or IES light → LightDesc::power in W (docs/photometry.md, "Light units"):
/// exactly one of power (RGB W), lumens or candela (with a chromaticity "color" normalised to Y = 1);
/// an IES light may give none (its file's absolute candela).
void parseLightUnits(const Reader& r, const Json& j, const std::string& where, LightDesc& l) {
  const int given = int(j.contains("power")) + int(j.contains("lumens")) + int(j.contains("candela"));
  if (given > 1) r.fail(where, "give only one of \"power\", \"lumens\", \"candela\"");
  if (given == 0 && !l.ies) r.fail(where, "missing key \"power\" (or \"lumens\" or \"candela\")");
  if (j.contains("color") && j.contains("power"))
    r.fail(where + ".color", "\"color\" goes with \"lumens\" or \"candela\" (\"power\" is already RGB)");
  Color color(1.0f);
  if (j.contains("color")) {
    color = r.color(j["color"], where + ".color");
    const double y = photometry::luminance(color);
    if (!(y > 0)) r.fail(where + ".color", "the colour has zero luminance");
    color *= float(1.0 / y);
  }
  if (j.contains("power")) {
    l.power = r.color(j["power"], where + ".power");
  } else if (j.contains("lumens")) {
    l.power = photometry::toRadiometric(r.nonNegative(j["lumens"], where + ".lumens"), color);
  } else if (j.contains("candela")) {
    if (l.ies) r.fail(where + ".candela", "an IES light's candela come from its file (rescale with \"lumens\")");
    l.power = powerFromCandela(l, r.nonNegative(j["candela"], where + ".candela"), color);
  } else {
    l.power = photometry::toRadiometric(l.ies->flux, color);
  }
}

LightDesc parseLight(const Reader& r, const Json& j, const std::string& where) {
  LightDesc l;
  l.name = where;
  const std::string type = r.string(r.need(j, where, "type"), where + ".type");
  if (type == "point") {
    r.keys(j, where, {"type", "name", "small", "luminaire", "position", "power", "lumens", "candela", "color"});
    l.type = LightType::Point;
  } else if (type == "spot") {
    r.keys(j, where, {"type", "name", "small", "luminaire", "position", "power", "lumens", "candela", "color", "direction",
                      "inner_angle", "outer_angle"});
    l.type = LightType::Spot;
    l.direction = r.vec3(r.need(j, where, "direction"), where + ".direction");
    if (j.contains("inner_angle")) l.innerAngleDeg = r.positive(j["inner_angle"], where + ".inner_angle");
    if (j.contains("outer_angle")) l.outerAngleDeg = r.positive(j["outer_angle"], where + ".outer_angle");
  } else if (type == "ies") {
    r.keys(j, where, {"type", "name", "small", "luminaire", "position", "power", "lumens", "color", "direction", "file", "ies_reference"});
    l.type = LightType::Spot;  // a spot whose profile is the table (LightDesc::ies)
    if (j.contains("direction")) l.direction = r.vec3(j["direction"], where + ".direction");
    if (j.contains("ies_reference")) {
      l.iesReference = r.vec3(j["ies_reference"], where + ".ies_reference");
      if (!(glm::length(l.iesReference) > 0)) r.fail(where + ".ies_reference", "the reference vector is zero");
    }
    std::filesystem::path p(r.string(r.need(j, where, "file"), where + ".file"));
    if (p.is_relative()) p = std::filesystem::path(r.file()).parent_path() / p;
    if (!std::filesystem::is_regular_file(p)) r.fail(where + ".file", "cannot open the IES file \"" + p.string() + "\"");
    l.ies = loadIes(p.string());
  } else if (type == "directional") {
    r.keys(j, where, {"type", "name", "small", "direction", "irradiance", "luminaire"});
    l.type = LightType::Directional;
    l.direction = r.vec3(r.need(j, where, "direction"), where + ".direction");
    l.irradiance = r.color(r.need(j, where, "irradiance"), where + ".irradiance");
  } else {
    r.fail(where + ".type", "unknown light type \"" + type + "\" (point, spot, ies, directional; area lights are emissive shapes)");
  }
  if (j.contains("name")) l.name = where + " (\"" + r.string(j["name"], where + ".name") + "\")";
  if (l.type != LightType::Directional) {
    l.position = r.vec3(r.need(j, where, "position"), where + ".position");
    parseLightUnits(r, j, where, l);
  }
  if (j.contains("small")) l.small = r.small(j["small"], where + ".small");
  if (j.contains("luminaire")) {
    if (l.type == LightType::Directional)
      r.fail(where + ".luminaire", "a directional light cannot be part of a luminaire (it has no position)");
    l.luminaire = luminaireName(r, j["luminaire"], where + ".luminaire");
  }
  return l;
}

void parseCamera(const Reader& r, const Json& j, CameraDesc& c) {
  const std::string w = "camera";
  r.keys(j, w, {"position", "look_at", "up", "fov_y", "resolution"});
  c.given = true;
  c.position = r.vec3(r.need(j, w, "position"), w + ".position");
  c.lookAt = r.vec3(r.need(j, w, "look_at"), w + ".look_at");
  if (j.contains("up")) c.up = r.vec3(j["up"], w + ".up");
  if (j.contains("fov_y")) c.fovYDeg = r.positive(j["fov_y"], w + ".fov_y");
  if (j.contains("resolution")) {
    const Json& res = j["resolution"];
    if (!res.is_array() || res.size() != 2) r.fail(w + ".resolution", "expected [width, height]");
    c.width = int(r.integer(res[0], w + ".resolution[0]", 1, 1 << 15));
    c.height = int(r.integer(res[1], w + ".resolution[1]", 1, 1 << 15));
  }
}

void parseSettings(const Reader& r, const Json& j, SettingsDesc& s) {
  const std::string w = "settings";
  r.keys(j, w, {"patch_size", "min_patch_size", "refine_tolerance", "light_patch_size", "light_tolerance", "spp", "seed", "max_depth", "item_buffer_resolution", "window",
                "small_light_max_solid_angle"});
  if (j.contains("patch_size")) s.patchSize = r.positive(j["patch_size"], w + ".patch_size");
  if (j.contains("min_patch_size")) s.minPatchSize = r.positive(j["min_patch_size"], w + ".min_patch_size");
  if (j.contains("refine_tolerance")) s.refineTolerance = r.positive(j["refine_tolerance"], w + ".refine_tolerance");
  if (j.contains("light_patch_size")) s.lightPatchSize = r.positive(j["light_patch_size"], w + ".light_patch_size");
  if (j.contains("light_tolerance")) s.lightTolerance = r.positive(j["light_tolerance"], w + ".light_tolerance");
  if (j.contains("spp")) s.spp = int(r.integer(j["spp"], w + ".spp", 1, 1 << 24));
  if (j.contains("seed")) s.seed = uint64_t(r.integer(j["seed"], w + ".seed", 0, INT64_MAX));
  if (j.contains("max_depth")) s.maxDepth = int(r.integer(j["max_depth"], w + ".max_depth", 0, 1024));
  if (j.contains("item_buffer_resolution"))
    s.resolution = uint32_t(r.integer(j["item_buffer_resolution"], w + ".item_buffer_resolution", 2, 8192));
  if (j.contains("window")) {
    s.window = r.string(j["window"], w + ".window");
    if (s.window != "hemicube" && s.window != "tetra") r.fail(w + ".window", "expected \"hemicube\" or \"tetra\"");
  }
  if (j.contains("small_light_max_solid_angle"))
    s.smallLightMaxSolidAngle = r.nonNegative(j["small_light_max_solid_angle"], w + ".small_light_max_solid_angle");
}

/// "line L, column C" of a byte offset in the text.
std::string lineColumn(const std::string& text, size_t byte) {
  size_t line = 1, col = 1;
  for (size_t i = 0; i < text.size() && i + 1 < byte; ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(col);
}

}  // namespace

SceneDesc parseSceneJson(const std::string& text, const std::string& path) {
  Json root;
  try {
    root = Json::parse(text);
  } catch (const Json::parse_error& e) {
    std::string what = e.what();
    const auto pos = what.find("syntax error");
    throw InputError(path, lineColumn(text, e.byte),
                     "malformed JSON: " + (pos == std::string::npos ? what : what.substr(pos)));
  } catch (const Json::exception& e) {
    // e.g. a number too large for a double ("1e999"): report it without the library's prefix.
    std::string what = e.what();
    const auto pos = what.find("] ");
    throw InputError(path, "", "malformed JSON: " + (pos == std::string::npos ? what : what.substr(pos + 2)) +
                                   " (numbers must be finite)");
  }
  Reader r(path);
  SceneDesc scene;
  scene.file = path;
  r.keys(root, "scene",
         {"description", "camera", "materials", "shapes", "lights", "settings", "sky", "sun", "environment"});
  if (root.contains("description")) r.string(root["description"], "description");
  if (root.contains("settings")) parseSettings(r, root["settings"], scene.settings);
  if (root.contains("camera")) parseCamera(r, root["camera"], scene.camera);
  const Json& mats = r.need(root, "scene", "materials");
  if (!mats.is_object()) r.fail("materials", "expected an object of named materials");
  TextureImages images;
  for (auto it = mats.begin(); it != mats.end(); ++it) {
    scene.materials.push_back(parseMaterial(r, withoutAlphaKeys(it.value()), it.key(), "materials." + it.key(), images));
    parseAlpha(r, it.value(), "materials." + it.key(), images, scene.materials.back());
  }
  const Json& shapes = r.need(root, "scene", "shapes");
  if (!shapes.is_array()) r.fail("shapes", "expected an array");
  for (size_t i = 0; i < shapes.size(); ++i) {
    const std::string where = "shapes[" + std::to_string(i) + "]";
    const Json& j = shapes[i];
    if (j.is_object() && !j.contains("material") && j.contains("type") && j["type"] == "mesh")
      appendAssetShapes(r, j, where, scene);  // the file's own materials
    else
      scene.shapes.push_back(parseShape(r, j, where, scene));
  }
  if (root.contains("lights")) {
    const Json& lights = root["lights"];
    if (!lights.is_array()) r.fail("lights", "expected an array");
    for (size_t i = 0; i < lights.size(); ++i)
      scene.lights.push_back(parseLight(r, lights[i], "lights[" + std::to_string(i) + "]"));
  }
  parseDaylight(r, root, scene);  // "sky", "sun", "environment" (common/formats/json/scene_sky.h); the sun after the lights
  skipDegenerateFaces(scene);  // the faces are final: zero-area and duplicate ones skipped, with a line on stderr
  return scene;
}

}  // namespace firstshot
