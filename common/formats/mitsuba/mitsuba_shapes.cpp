// Mitsuba <shape> plugins → ShapeDesc (common/formats/mitsuba/mitsuba_shapes.h; docs/scene-format.md, "Mitsuba 3 XML scenes").
#include "common/formats/mitsuba/mitsuba_shapes.h"

#include <cmath>

#include "common/formats/assets/mesh_import.h"
#include "common/formats/mitsuba/mitsuba_serialized.h"
#include "common/scene/scene_shapes.h"

namespace firstshot::mitsuba {
namespace {

constexpr int kDiskSegments = 64;      ///< triangles of a tessellated disk
constexpr int kSphereSubdivisions = 3; ///< icosphere levels of a tessellated sphere (1280 triangles)

/// Mitsuba's disk (the unit disk in z = 0, normal +z) as a fan of kDiskSegments triangles around its centre; the
/// polygon's radius is enlarged so that its area is the disk's, π.
void makeDisk(ShapeDesc& s) {
  const double step = 2 * kPi / kDiskSegments;
  const double r = std::sqrt(2 * kPi / (kDiskSegments * std::sin(step)));
  const uint32_t centre = uint32_t(s.vertices.size());
  s.vertices.emplace_back(0.0);
  for (int i = 0; i < kDiskSegments; ++i) s.vertices.emplace_back(r * std::cos(i * step), r * std::sin(i * step), 0.0);
  for (uint32_t i = 0; i < uint32_t(kDiskSegments); ++i) {
    Face f;
    f.v[0] = centre, f.v[1] = centre + 1 + i, f.v[2] = centre + 1 + (i + 1) % kDiskSegments;
    s.faces.push_back(f);
  }
}

/// Two unit vectors @p s, @p t perpendicular to the unit vector @p n with s × t = n, by the branch-free construction
/// of Duff et al. ("Building an orthonormal basis, revisited", 2017), the one Mitsuba's frames use: a cylinder's
/// φ = 0 lies along s, so its texture seam is where Mitsuba's is.
void perpendicularPair(const Vec3d& n, Vec3d& s, Vec3d& t) {
  const double sign = std::copysign(1.0, n.z), a = -1.0 / (sign + n.z), b = n.x * n.y * a;
  s = Vec3d(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
  t = Vec3d(b, sign + n.y * n.y * a, -n.y);
}

}  // namespace

void makeCylinder(ShapeDesc& s, const Vec3d& p0, const Vec3d& p1, double radius) {
  const Vec3d axis = p1 - p0;
  Vec3d sx, sy;
  perpendicularPair(glm::normalize(axis), sx, sy);
  const int n = kCylinderSegments;
  // n facets of width 2r·sin(π/n) along the axis: their area is 2π·radius·length for this r.
  const double step = 2 * kPi / n, r = radius * kPi / (n * std::sin(kPi / n));
  std::vector<Vec3> radial(size_t(n) + 1);
  for (int i = 0; i <= n; ++i) {
    const Vec3d d = std::cos(i * step) * sx + std::sin(i * step) * sy;
    radial[size_t(i)] = Vec3(d);
    if (i < n) s.vertices.push_back(p0 + r * d), s.vertices.push_back(p1 + r * d);  // 2i: at p0, 2i + 1: at p1
  }
  for (int i = 0; i < n; ++i) {
    const uint32_t a = 2 * uint32_t(i), b = 2 * uint32_t((i + 1) % n);
    Face f;
    f.count = 4;
    f.v[0] = a, f.v[1] = b, f.v[2] = b + 1, f.v[3] = a + 1;  // counter-clockwise seen from outside
    s.faces.push_back(f);
    const float u0 = float(i) / float(n), u1 = float(i + 1) / float(n);
    s.uv.insert(s.uv.end(), {Vec2(u0, 0.0f), Vec2(u1, 0.0f), Vec2(u1, 1.0f), Vec2(u0, 1.0f)});
    const Vec3 n0 = radial[size_t(i)], n1 = radial[size_t(i) + 1];
    s.normals.insert(s.normals.end(), {n0, n1, n1, n0});
  }
}

void ShapeMapper::add(pugi::xml_node node) {
  const std::string type = node.attribute("type").value();
  if (type == "shapegroup") {
    group(node);  // made now, so that its errors come in the file's order; rendered only through instances
  } else if (type == "instance") {
    instance(node);
  } else {
    scene_.shapes.push_back(make(node, false));
  }
}

ShapeDesc ShapeMapper::make(pugi::xml_node node, bool inGroup) {
  Plugin p(doc_, node);
  if (inGroup && (p.type() == "shapegroup" || p.type() == "instance"))
    doc_.fail(node, "a " + p.type() + " inside a shapegroup: nested instancing is not permitted (as in Mitsuba)");
  ShapeDesc s;
  s.name = elementName(doc_, node);
  geometry(p, s);
  shapes::transform(s, p.transform("to_world"));
  if (p.boolean("flip_normals", false)) shapes::flip(s);
  std::vector<pugi::xml_node> bsdfs = p.nested("bsdf");
  if (const pugi::xml_node named = p.take("bsdf")) bsdfs.push_back(doc_.resolve(named));
  if (bsdfs.size() > 1) doc_.fail(node, "a shape takes one bsdf");
  s.material = bsdfs.empty() ? bsdfs_.defaultMaterial() : bsdfs_.material(bsdfs[0]);
  for (pugi::xml_node e : p.nested("emitter")) {
    if (inGroup)
      doc_.fail(e, "an emitter on a shape inside a shapegroup: instancing of emitters is not supported (as in "
                   "Mitsuba); give the emitting shape outside the group");
    Plugin emitter(doc_, e);
    if (emitter.type() != "area") doc_.fail(e, "emitter type \"" + emitter.type() + "\" inside a shape (only area)");
    MaterialDesc m = scene_.materials[s.material];
    m.name = s.name + " emitter";
    if (m.isCutout()) {  // an emitter cannot be a cut-out here
      doc_.note("masked emitter", "a masked area emitter is opaque (its mask's opacity is dropped)");
      m.alphaMode = AlphaMode::Opaque, m.alphaTexture = nullptr, m.alpha = 1.0f;
    }
    m.emission = emitter.color("radiance", Color(1.0f));
    emitter.finish();
    scene_.materials.push_back(m);
    s.material = int(scene_.materials.size() - 1);
  }
  p.finish();
  return s;
}

void ShapeMapper::geometry(Plugin& p, ShapeDesc& s) {
  const std::string& t = p.type();
  const pugi::xml_node node = p.node();
  if (t == "obj" || t == "ply" || t == "serialized") {
    s.type = ShapeType::Mesh;
    const std::string name = p.string("filename", "");
    if (name.empty()) doc_.fail(node, "missing <string name=\"filename\">");
    s.sourceFile = resolve_(name).string();
    bool flat = p.boolean("face_normals", false);
    MeshData mesh;
    if (t == "serialized") {
      const int index = p.integer("shape_index", 0);
      if (index < 0) doc_.fail(p.take("shape_index"), "shape_index must not be negative");
      SerializedShape shape = readSerializedShape(s.sourceFile, index, doc_.file(), doc_.where(node));
      mesh = std::move(shape.mesh);
      flat = flat || shape.faceNormals;
    } else {
      mesh = loadMeshFile(s.sourceFile, doc_.file(), doc_.where(node));
    }
    s.vertices = std::move(mesh.vertices);
    s.faces = std::move(mesh.faces);
    s.uv = std::move(mesh.uv);
    s.normals = std::move(mesh.normals);  // the file's vertex normals, per face corner
    s.tangents = std::move(mesh.tangents), s.bitangents = std::move(mesh.bitangents);
    if (flat) {
      s.normals.clear();  // face_normals: shaded with the faces' own normals
    } else if (!s.hasNormals()) {
      doc_.note("mesh normals", "meshes without vertex normals in their file are shaded flat (Mitsuba shades them "
                                "with vertex normals it computes)");
    }
    if (t == "obj" && !p.boolean("flip_tex_coords", true) && s.hasUv())  // Mitsuba's default flips OBJ's v, as we do
      for (size_t f = 0; f < s.faces.size(); ++f)
        for (int k = 0; k < s.faces[f].count; ++k) s.uv[4 * f + size_t(k)].y = 1.0f - s.uv[4 * f + size_t(k)].y;
  } else if (t == "rectangle") {
    s.type = ShapeType::Quad;
    shapes::makeQuad(s, {Vec3d(-1, -1, 0), Vec3d(1, -1, 0), Vec3d(1, 1, 0), Vec3d(-1, 1, 0)});
    for (Vec2& uv : s.uv) uv.y = 1.0f - uv.y;  // Mitsuba's: (u, v) = ((x + 1)/2, (y + 1)/2)
  } else if (t == "cube") {
    s.type = ShapeType::Box;
    shapes::makeBox(s, Vec3d(-1.0), Vec3d(1.0));
  } else if (t == "sphere") {
    s.type = ShapeType::Sphere;
    const double radius = p.number("radius", 1.0);
    if (!(radius > 0)) doc_.fail(p.take("radius"), "radius must be positive");
    shapes::makeSphere(s, p.point("center", Vec3d(0.0)), radius, kSphereSubdivisions);
  } else if (t == "disk") {
    s.type = ShapeType::Mesh;
    makeDisk(s);
  } else if (t == "cylinder") {
    s.type = ShapeType::Mesh;
    const double radius = p.number("radius", 1.0);
    if (!(radius > 0)) doc_.fail(p.take("radius"), "radius must be positive");
    const Vec3d p0 = p.point("p0", Vec3d(0.0)), p1 = p.point("p1", Vec3d(0, 0, 1));
    if (!(glm::length(p1 - p0) > 0)) doc_.fail(node, "p0 and p1 coincide: the cylinder has no length");
    makeCylinder(s, p0, p1, radius);
  } else {
    doc_.fail(node, "shape type \"" + t + "\" is not supported (obj, ply, serialized, rectangle, cube, sphere, disk, "
                    "cylinder, shapegroup, instance)");
  }
}

const std::vector<ShapeDesc>& ShapeMapper::group(pugi::xml_node node) {
  if (const auto it = groups_.find(node); it != groups_.end()) return it->second;
  Plugin p(doc_, node);
  std::vector<ShapeDesc> shapes;
  for (pugi::xml_node c : p.nested("shape")) shapes.push_back(make(c, true));
  p.finish();
  return groups_.emplace(node, std::move(shapes)).first->second;
}

void ShapeMapper::instance(pugi::xml_node node) {
  Plugin p(doc_, node);
  std::vector<pugi::xml_node> groups = p.nested("shape");
  if (const pugi::xml_node named = p.take("shapegroup")) groups.push_back(doc_.resolve(named));  // <ref name="shapegroup" …>
  if (groups.size() != 1 || std::string(groups[0].attribute("type").value()) != "shapegroup")
    doc_.fail(node, "an instance takes exactly one shapegroup (a <ref id=\"…\"/> to it)");
  for (const char* tag : {"bsdf", "emitter"})
    if (!p.nested(tag).empty())
      doc_.fail(node, std::string("an instance takes no ") + tag + ": the shapes of its group keep their own (as in Mitsuba)");
  const Mat4d m = p.transform("to_world");
  const std::string name = elementName(doc_, node);
  for (const ShapeDesc& g : group(groups[0])) {
    ShapeDesc s = g;
    s.name = name + ": " + g.name;
    shapes::transform(s, m);
    scene_.shapes.push_back(std::move(s));
  }
  p.finish();
  doc_.note("instance", "shapegroup instances are made into copies of the group's shapes (memory and preprocessing "
                        "time grow with the number of instances)");
}

}  // namespace firstshot::mitsuba
