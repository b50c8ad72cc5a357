// Mitsuba shapes and cameras (common/formats/mitsuba/mitsuba_shapes.cpp, common/formats/mitsuba/mitsuba_serialized.cpp, common/scene/camera_fov.h):
// a serialized file written here in the format's layout against the same mesh as OBJ (the same SceneDesc and the
// same image), corrupt and truncated serialized files named precisely, the cylinder's area and normals, shape groups'
// instances as transformed copies, and the field of view kept on a sensor's fov_axis when the resolution changes.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fmt/core.h>
#include <zlib.h>

#include <cstring>
#include <random>

#include "common/formats/load_scene.h"
#include "common/formats/mitsuba/mitsuba_serialized.h"
#include "common/formats/mitsuba/mitsuba_shapes.h"
#include "common/scene/camera_fov.h"
#include "common/scene/scene_shapes.h"
#include "common/util/error.h"
#include "tests/block_compare.h"
#include "tests/render_util.h"
#include "tests/test_util.h"

using namespace firstshot;
using ::testing::HasSubstr;

namespace {

// --- A writer of Mitsuba's serialized format (common/formats/mitsuba/mitsuba_serialized.h has the layout) ---------------------------

/// One shape to write: reals per vertex as the flags say, 3 indices per triangle.
struct SerialShape {
  std::vector<double> positions, normals, uv, colours;
  std::vector<uint32_t> indices;
  bool dbl = false, faceNormals = false;
  std::string name = "tent";
  int64_t vertexCount = -1, triangleCount = -1;  ///< written instead of the true counts when ≥ 0
};

template <typename T>
void put(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

/// The shape's stream before compression.
std::string payload(const SerialShape& s, int version) {
  std::string out;
  const uint32_t flags = (s.normals.empty() ? 0 : 0x1) | (s.uv.empty() ? 0 : 0x2) | (s.colours.empty() ? 0 : 0x8) |
                         (s.faceNormals ? 0x10 : 0) | (s.dbl ? 0x2000 : 0x1000);
  put(out, flags);
  if (version == 4) out.append(s.name.c_str(), s.name.size() + 1);
  put(out, uint64_t(s.vertexCount >= 0 ? uint64_t(s.vertexCount) : s.positions.size() / 3));
  put(out, uint64_t(s.triangleCount >= 0 ? uint64_t(s.triangleCount) : s.indices.size() / 3));
  for (const auto* a : {&s.positions, &s.normals, &s.uv, &s.colours})
    for (double v : *a) s.dbl ? put(out, v) : put(out, float(v));
  for (uint32_t i : s.indices) put(out, i);
  return out;
}

std::string compressed(const std::string& data) {
  uLongf size = compressBound(uLong(data.size()));
  std::string out(size, '\0');
  EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(data.data()),
                      uLong(data.size()), 9), Z_OK);
  out.resize(size);
  return out;
}

/// A whole file: each shape's header and stream, then the dictionary of their offsets and their number.
std::string serializedFile(const std::vector<SerialShape>& shapes, int version = 4) {
  std::string out;
  std::vector<uint64_t> offsets;
  for (const SerialShape& s : shapes) {
    offsets.push_back(out.size());
    put(out, uint16_t(0x041C)), put(out, uint16_t(version));
    out += compressed(payload(s, version));
  }
  for (uint64_t o : offsets) version == 4 ? put(out, o) : put(out, uint32_t(o));
  put(out, uint32_t(shapes.size()));
  return out;
}

/// A ridge of two quads (4 triangles) with texture coordinates and normals (not unit), in dyadic numbers so that the
/// OBJ text parses to the same floats; the OBJ's vt is (u, 1 − v) of Mitsuba's (and ShapeDesc's) coordinates.
SerialShape tent() {
  SerialShape s;
  s.positions = {0, 0, 0, 1, 0, 0, 1, 0.5, 1, 0, 0.5, 1, 0, 0, 2, 1, 0, 2};
  s.normals = {0, 1, -0.5, 0, 1, -0.5, 0, 1, 0, 0, 2, 0, 0, 1, 0.5, 0, 1, 0.5};
  s.uv = {0, 0, 1, 0, 1, 0.5, 0, 0.5, 0, 1, 1, 0.75};
  s.indices = {0, 1, 2, 0, 2, 3, 3, 2, 5, 3, 5, 4};
  return s;
}

std::string tentObj() {
  const SerialShape s = tent();
  std::string obj;
  for (size_t v = 0; v < 6; ++v) {
    obj += fmt::format("v {} {} {}\n", s.positions[3 * v], s.positions[3 * v + 1], s.positions[3 * v + 2]);
    obj += fmt::format("vt {} {}\n", s.uv[2 * v], 1.0 - s.uv[2 * v + 1]);
    obj += fmt::format("vn {} {} {}\n", s.normals[3 * v], s.normals[3 * v + 1], s.normals[3 * v + 2]);
  }
  for (size_t t = 0; t < 4; ++t) {
    obj += "f";
    for (size_t k = 0; k < 3; ++k) obj += fmt::format(" {0}/{0}/{0}", s.indices[3 * t + k] + 1);
    obj += "\n";
  }
  return obj;
}

/// A one-triangle shape in double precision, without normals or texture coordinates but with colours.
SerialShape triangle() {
  SerialShape s;
  s.positions = {0, 0, 0, 0.1, 0, 0, 0, 0.1, 0};
  s.colours = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  s.indices = {0, 1, 2};
  s.dbl = true;
  s.name = "triangle";
  return s;
}

/// Writes the files and @p xml's scene (the body of <scene>) into a fresh folder; returns the scene's path.
std::string writeScene(const std::string& body, const std::vector<std::pair<std::string, std::string>>& files) {
  const std::string dir = test::tempDir();
  for (const auto& [name, content] : files) test::writeText(dir + "/" + name, content);
  test::writeText(dir + "/scene.xml", "<scene version=\"3.0.0\">\n" + body + "\n</scene>\n");
  return dir + "/scene.xml";
}

const char* kLitRoom = R"(
  <sensor type="perspective"><float name="fov" value="60"/>
    <transform name="to_world"><lookat origin="0.5, 2.5, -2.5" target="0.5, 0, 1" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="16"/></film></sensor>
  <bsdf type="twosided" id="grey"><bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.5, 0.4"/></bsdf></bsdf>
  <shape type="rectangle"><transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/></transform><ref id="grey"/></shape>
  <shape type="sphere"><point name="center" x="0.5" y="3" z="1"/><float name="radius" value="0.3"/>
    <emitter type="area"><rgb name="radiance" value="8, 8, 8"/></emitter></shape>)";

/// The tent as @p shape (an obj or serialized element's type and properties) in the lit room.
SceneDesc tentScene(const std::string& shape, const std::vector<std::pair<std::string, std::string>>& files) {
  return loadScene(writeScene(std::string(kLitRoom) + "\n<shape " + shape + R"(
      <transform name="to_world"><rotate y="1" angle="30"/><translate x="0.25" y="0.01"/></transform><ref id="grey"/>
    </shape>)", files));
}

void expectSameShape(const ShapeDesc& a, const ShapeDesc& b) {
  EXPECT_EQ(a.vertices, b.vertices) << a.name;
  ASSERT_EQ(a.faces.size(), b.faces.size()) << a.name;
  for (size_t f = 0; f < a.faces.size(); ++f) {
    EXPECT_EQ(a.faces[f].count, b.faces[f].count);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(a.faces[f].v[k], b.faces[f].v[k]) << a.name << " face " << f;
  }
  EXPECT_EQ(a.uv, b.uv) << a.name;
  EXPECT_EQ(a.normals, b.normals) << a.name;
  EXPECT_EQ(a.material, b.material) << a.name;
}

}  // namespace

TEST(MitsubaShapes, SerializedMatchesTheSameMeshAsObj) {
  const std::string file = serializedFile({triangle(), tent()});
  const SceneDesc obj = tentScene(R"(type="obj"><string name="filename" value="tent.obj"/>)", {{"tent.obj", tentObj()}});
  const SceneDesc ser = tentScene(R"(type="serialized"><string name="filename" value="mesh.serialized"/>
      <integer name="shape_index" value="1"/>)", {{"mesh.serialized", file}});
  ASSERT_EQ(obj.shapes.size(), 3u);
  ASSERT_EQ(ser.shapes.size(), 3u);
  const ShapeDesc &a = obj.shapes[2], &b = ser.shapes[2];
  ASSERT_EQ(b.faces.size(), 4u);
  ASSERT_EQ(b.vertices.size(), 6u);
  ASSERT_TRUE(b.hasUv() && b.hasNormals());
  expectSameShape(a, b);
  // The second corner of the first triangle: vertex 1, (1, 0, 0) turned 30° about y and moved; uv (1, 0) as written.
  const double c = std::cos(glm::radians(30.0)), s = std::sin(glm::radians(30.0));
  EXPECT_NEAR(glm::length(b.vertices[b.faces[0].v[1]] - Vec3d(0.25 + c, 0.01, -s)), 0.0, 1e-12);
  EXPECT_EQ(b.cornerUv(0, 1), Vec2(1.0f, 0.0f));
  EXPECT_NEAR(glm::length(b.cornerNormal(3, 0) - Vec3(0, 1, 0)), 0.0f, 1e-6f) << "vertex 3's normal (0, 2, 0), unit";
  // The same scene, so the same image for the same seed (and not a black one).
  const RenderScene ra(obj, 1.0), rb(ser, 1.0);
  const auto ia = test::renderPath(ra, IntegratorOptions{}, 2, 5), ib = test::renderPath(rb, IntegratorOptions{}, 2, 5);
  EXPECT_EQ(test::filmValues(ia.film), test::filmValues(ib.film));
  EXPECT_GT(test::greyImageMean(ib.film), 0.01);
}

TEST(MitsubaShapes, SerializedVersionsPrecisionsAndFlags) {
  SerialShape flat = tent();
  flat.faceNormals = true;
  for (int version : {3, 4}) {
    SCOPED_TRACE(version);
    const std::string path = writeScene(R"(
        <shape type="serialized"><string name="filename" value="m.serialized"/></shape>
        <shape type="serialized"><string name="filename" value="m.serialized"/><integer name="shape_index" value="1"/></shape>
        <shape type="serialized"><string name="filename" value="m.serialized"/><integer name="shape_index" value="2"/></shape>
        <shape type="serialized"><string name="filename" value="m.serialized"/><integer name="shape_index" value="1"/>
          <boolean name="face_normals" value="true"/></shape>)",
        {{"m.serialized", serializedFile({triangle(), tent(), flat}, version)}});
    const SceneDesc s = loadScene(path);
    ASSERT_EQ(s.shapes.size(), 4u);
    // Double precision, colours skipped: the triangle's corners as written.
    const ShapeDesc& t = s.shapes[0];
    ASSERT_EQ(t.faces.size(), 1u);
    EXPECT_EQ(t.vertices[t.faces[0].v[1]], Vec3d(0.1, 0, 0));
    EXPECT_EQ(t.vertices[t.faces[0].v[2]], Vec3d(0, 0.1, 0));
    EXPECT_FALSE(t.hasUv() || t.hasNormals());
    EXPECT_TRUE(s.shapes[1].hasNormals());
    EXPECT_FALSE(s.shapes[2].hasNormals()) << "the file's face-normals flag";
    EXPECT_FALSE(s.shapes[3].hasNormals()) << "face_normals";
    EXPECT_EQ(s.shapes[2].vertices, s.shapes[1].vertices);
    EXPECT_EQ(s.shapes[2].uv, s.shapes[1].uv);
  }
}

namespace {

/// loadScene(@p path) must fail with an InputError containing each of @p parts.
void expectLoadError(const std::string& path, std::initializer_list<std::string> parts) {
  try {
    loadScene(path);
    ADD_FAILURE() << "loaded: " << *parts.begin();
  } catch (const InputError& e) {
    for (const std::string& p : parts) EXPECT_THAT(e.what(), HasSubstr(p));
  }
}

/// The error of loading shape @p index of @p file as a serialized mesh (and firstshot-preprocess's exit code 2 when
/// @p cli): it must name the scene element, the file and contain @p what.
void expectSerializedError(const std::string& file, int index, const std::string& what, bool cli = false) {
  const std::string path = writeScene(fmt::format(R"(<shape type="serialized">
      <string name="filename" value="m.serialized"/><integer name="shape_index" value="{}"/></shape>)", index),
      {{"m.serialized", file}});
  expectLoadError(path, {"scene.xml: scene/shape (line 2): serialized file ", "m.serialized", what});
  if (!cli) return;
  const test::CommandResult r = test::run(std::string(FIRSTSHOT_PREPROCESS_EXE) + " --stats " + path);
  EXPECT_EQ(r.exitCode, kExitBadInput) << r.output;
  EXPECT_THAT(r.output, HasSubstr(what));
}

/// @p file with @p n bytes at @p at replaced by @p bytes.
std::string patched(std::string file, size_t at, const std::string& bytes) {
  file.replace(at, bytes.size(), bytes);
  return file;
}

}  // namespace

TEST(MitsubaShapes, CorruptSerializedFilesAreNamed) {
  const std::string good = serializedFile({triangle(), tent()});
  const size_t second = 4 + compressed(payload(triangle(), 4)).size();  // the tent's header
  expectSerializedError(good, 2, "shape_index 2 is out of range: the file holds 2 shapes (0 to 1)", true);
  expectSerializedError(patched(good, 0, "\x1d\x04"), 0, "not a Mitsuba serialized file");
  expectSerializedError(patched(good, 2, std::string("\x05\x00", 2)), 0, "format version 5 is not supported");
  expectSerializedError(good.substr(0, second / 2), 0, "shape 0: truncated: the file ends inside the shape's compressed data");
  expectSerializedError(good.substr(0, good.size() - 3), 1, "corrupt or truncated end-of-file dictionary");
  expectSerializedError(patched(good, good.size() - 12, std::string("\x07\x00", 2)), 1,
                        "shape 1: the end-of-file dictionary gives offset 7, where no shape header is");
  expectSerializedError(patched(good, 4, std::string("\x00\x00", 2)), 0, "shape 0: corrupt compressed data (zlib: ");
  expectSerializedError("", 0, "truncated: shorter than its 4-byte header");
  // Counts the data does not match.
  SerialShape more = tent(), fewer = tent(), huge = tent(), index = tent(), empty = tent();
  more.vertexCount = 7, fewer.triangleCount = 3, huge.vertexCount = int64_t(1) << 31, index.indices[4] = 9;
  empty.triangleCount = 0;
  expectSerializedError(serializedFile({more}), 0, "shape 0: corrupt: the compressed stream ends before the data");
  expectSerializedError(serializedFile({fewer}), 0, "shape 0: corrupt: the data goes on past the 6 vertices, 3 triangles");
  expectSerializedError(serializedFile({huge}), 0, "need more data than the rest of the file holds");
  expectSerializedError(serializedFile({index}), 0, "shape 0: triangle 1 uses vertex 9 of 6");
  expectSerializedError(serializedFile({empty}), 0, "holds no triangles (6 vertices, 0 triangles)");
  // A missing file, and a negative index.
  expectLoadError(writeScene(R"(<shape type="serialized"><string name="filename" value="none.serialized"/></shape>)", {}),
                  {"none.serialized: file not found"});
  expectLoadError(writeScene(R"(<shape type="serialized"><string name="filename" value="m.serialized"/>
      <integer name="shape_index" value="-1"/></shape>)", {{"m.serialized", good}}),
                  {"scene/shape/shape_index (line 3)", "shape_index must not be negative"});
}

TEST(MitsubaShapes, MutatedSerializedFilesLoadOrAreInputErrors) {
  // Bytes changed at random, or the file cut short: each read of either shape loads or is an InputError naming the
  // file, never a crash or another exception (counts are checked before anything is allocated).
  const std::string good = serializedFile({triangle(), tent()}), path = test::tempDir() + "/m.serialized";
  std::mt19937 rng(7);
  int refused = 0;
  for (int i = 0; i < 120; ++i) {
    std::string file = good;
    if (i % 4 == 0) {
      file.resize(rng() % file.size());
    } else {
      for (uint32_t k = 0, n = 1 + rng() % 4; k < n; ++k) file[rng() % file.size()] = char(rng());
    }
    test::writeText(path, file);
    try {
      mitsuba::readSerializedShape(path, i % 2, "scene.xml", "scene/shape");
    } catch (const InputError& e) {
      ++refused;
      EXPECT_THAT(e.what(), HasSubstr("scene.xml: scene/shape: serialized file " + path));
    }
  }
  EXPECT_GT(refused, 60);
}

TEST(MitsubaShapes, CylinderAreaNormalsAndTextureCoordinates) {
  // Radius 0.3 from (1, 0, 0) to (1, 2, 0), moved by to_world; and Mitsuba's default one (radius 1, z from 0 to 1)
  // with its normals flipped.
  const SceneDesc s = loadScene(writeScene(R"(
      <shape type="cylinder"><point name="p0" x="1" y="0" z="0"/><point name="p1" x="1" y="2" z="0"/>
        <float name="radius" value="0.3"/><transform name="to_world"><translate z="0.5"/></transform></shape>
      <shape type="cylinder"><boolean name="flip_normals" value="true"/></shape>)", {}));
  ASSERT_EQ(s.shapes.size(), 2u);
  struct Case {
    const ShapeDesc& shape;
    Vec3d p0, axis;
    double radius, length, side;  ///< side: +1 normals outward, −1 inward
  };
  for (const Case& c : {Case{s.shapes[0], Vec3d(1, 0, 0.5), Vec3d(0, 1, 0), 0.3, 2.0, 1.0},
                        Case{s.shapes[1], Vec3d(0.0), Vec3d(0, 0, 1), 1.0, 1.0, -1.0}}) {
    const ShapeDesc& m = c.shape;
    ASSERT_EQ(m.faces.size(), size_t(mitsuba::kCylinderSegments));
    ASSERT_TRUE(m.hasNormals() && m.hasUv());
    double area = 0;
    for (size_t f = 0; f < m.faces.size(); ++f) {
      const Face& face = m.faces[f];
      ASSERT_EQ(face.count, 4);
      area += shapes::faceArea(m, face);
      // The facet: parallel to the axis (an open tube: no caps), facing away from it (towards it when flipped).
      const Vec3d a = m.vertices[face.v[0]], b = m.vertices[face.v[1]], d = m.vertices[face.v[3]];
      const Vec3d n = glm::normalize(glm::cross(b - a, d - a)), mid = 0.25 * (a + b + m.vertices[face.v[2]] + d) - c.p0;
      EXPECT_NEAR(glm::dot(n, c.axis), 0.0, 1e-12);
      EXPECT_GT(c.side * glm::dot(n, glm::normalize(mid - glm::dot(mid, c.axis) * c.axis)), 0.999);
      for (int k = 0; k < 4; ++k) {
        const Vec3d p = m.vertices[face.v[k]] - c.p0, radial = p - glm::dot(p, c.axis) * c.axis;
        const double along = glm::dot(p, c.axis), r = glm::length(radial);
        // On the tube: the corners 0.04% outside the radius (the facets' area is the cylinder's), at either end.
        EXPECT_NEAR(r / c.radius, kPi / (mitsuba::kCylinderSegments * std::sin(kPi / mitsuba::kCylinderSegments)), 1e-12);
        EXPECT_NEAR(std::min(std::abs(along), std::abs(along - c.length)), 0.0, 1e-12);
        // Smooth shading: the tube's own normal at the corner; v from 0 at p0 to 1 at p1.
        EXPECT_NEAR(glm::length(Vec3d(m.cornerNormal(f, k)) - c.side * radial / r), 0.0, 1e-6);
        EXPECT_NEAR(m.cornerUv(f, k).y, along / c.length, 1e-6);
      }
    }
    EXPECT_NEAR(area, 2 * kPi * c.radius * c.length, 1e-9 * area) << "2π r h";
  }
  // Mitsuba's u = φ/2π on the default cylinder: φ measured from +x towards +y.
  const ShapeDesc& d = s.shapes[1];
  for (size_t f = 0; f < d.faces.size(); ++f)
    for (int k = 0; k < 4; ++k) {
      const Vec3d p = d.vertices[d.faces[f].v[k]];
      const double u = d.cornerUv(f, k).x, phi = std::atan2(p.y, p.x);
      EXPECT_NEAR(std::remainder(2 * kPi * u - phi, 2 * kPi), 0.0, 1e-5) << "face " << f << " corner " << k;
    }
  expectLoadError(writeScene(R"(<shape type="cylinder"><point name="p1" x="0" y="0" z="0"/></shape>)", {}),
                  {"scene/shape (line 2)", "p0 and p1 coincide"});
  expectLoadError(writeScene(R"(<shape type="cylinder"><float name="radius" value="0"/></shape>)", {}),
                  {"scene/shape/radius (line 2)", "radius must be positive"});
}

TEST(MitsubaShapes, InstancesAreTransformedCopiesOfTheirGroup) {
  const std::string red = R"(<bsdf type="diffuse" id="red"><rgb name="reflectance" value="0.8, 0.1, 0.1"/></bsdf>)";
  const std::string rectangle = R"(<shape type="rectangle"><transform name="to_world"><scale value="0.5"/><translate y="1"/>{}</transform>
      <ref id="red"/></shape>)";
  const std::string tentMesh = R"(<shape type="obj"><string name="filename" value="tent.obj"/>{}
      <bsdf type="diffuse"><rgb name="reflectance" value="0.25"/></bsdf></shape>)";
  const std::string move = R"(<rotate y="1" angle="90"/><translate x="3"/>)";
  const SceneDesc s = loadScene(writeScene(red + R"(
      <shape type="shapegroup" id="g">)" + fmt::format(fmt::runtime(rectangle), "") + fmt::format(fmt::runtime(tentMesh), "") + R"(</shape>
      <shape type="instance"><ref id="g"/></shape>
      <shape type="instance"><ref name="shapegroup" id="g"/><transform name="to_world">)" + move + R"(</transform></shape>)",
      {{"tent.obj", tentObj()}}));
  // The same shapes written out, each instance's transform after the shape's own (the second instance names its
  // reference, as Mitsuba's Python dictionaries do).
  const SceneDesc flat = loadScene(writeScene(red + fmt::format(fmt::runtime(rectangle), "") + fmt::format(fmt::runtime(tentMesh), "") +
      fmt::format(fmt::runtime(rectangle), move) + fmt::format(fmt::runtime(tentMesh), "<transform name=\"to_world\">" + move + "</transform>"),
      {{"tent.obj", tentObj()}}));
  ASSERT_EQ(s.shapes.size(), 4u) << "the group itself is not rendered";
  ASSERT_EQ(flat.shapes.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    const ShapeDesc &a = s.shapes[i], &b = flat.shapes[i];
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    for (size_t v = 0; v < a.vertices.size(); ++v) EXPECT_NEAR(glm::length(a.vertices[v] - b.vertices[v]), 0.0, 1e-12);
    ASSERT_EQ(a.normals.size(), b.normals.size());
    for (size_t n = 0; n < a.normals.size(); ++n) EXPECT_NEAR(glm::length(a.normals[n] - b.normals[n]), 0.0f, 1e-6f);
    EXPECT_EQ(a.uv, b.uv);
    ASSERT_EQ(a.faces.size(), b.faces.size());
    for (size_t f = 0; f < a.faces.size(); ++f) EXPECT_EQ(std::memcmp(a.faces[f].v, b.faces[f].v, sizeof a.faces[f].v), 0);
    EXPECT_EQ(s.materials[a.material].albedo, flat.materials[b.material].albedo);
  }
  // The copies share their group's materials, and are named by the instance and the group's shape.
  EXPECT_EQ(s.shapes[0].material, s.shapes[2].material);
  EXPECT_EQ(s.shapes[1].material, s.shapes[3].material);
  EXPECT_EQ(s.shapes[3].name, "scene/shape[3]: scene/shape[1]/shape[2]");
  // Refused as Mitsuba refuses them: emitters and nested groups inside a group; an instance of anything but one group.
  expectLoadError(writeScene(R"(<shape type="shapegroup" id="g"><shape type="rectangle">
      <emitter type="area"/></shape></shape>)", {}), {"scene/shape/shape/emitter (line 3)", "instancing of emitters is not supported"});
  expectLoadError(writeScene(R"(<shape type="shapegroup" id="g"><shape type="cube"/></shape>
      <shape type="shapegroup" id="h"><shape type="instance"><ref id="g"/></shape></shape>)", {}),
                  {"scene/shape[2]/shape (line 3)", "nested instancing is not permitted"});
  expectLoadError(writeScene(R"(<shape type="instance"/>)", {}), {"scene/shape (line 2)", "exactly one shapegroup"});
  expectLoadError(writeScene(R"(<shape type="cube" id="c"/><shape type="instance"><ref id="c"/></shape>)", {}),
                  {"scene/shape[2] (line 2)", "exactly one shapegroup"});
}

TEST(MitsubaCamera, ResolutionKeepsTheFieldOfViewOnTheSensorsAxis) {
  // A 200 × 100 film with fov 50° on each axis, then rendered at other resolutions: the field on that axis stays
  // 50°, so with t = tan 25° and the new aspect a = w/h, tan(fov_y/2) is t/a (x), t (y), t/√(1 + a²) (diagonal),
  // and for smaller and larger that of y or x, whichever is the smaller or larger side of the new film.
  const double t = std::tan(glm::radians(25.0));
  auto sensor = [](const std::string& axis) {
    return loadScene(writeScene(fmt::format(R"(<sensor type="perspective"><float name="fov" value="50"/>
        <string name="fov_axis" value="{}"/><film type="hdrfilm"><integer name="width" value="200"/>
        <integer name="height" value="100"/></film></sensor><shape type="cube"/>)", axis), {})).camera;
  };
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{100, 100}, {300, 100}, {100, 200}, {200, 100}}) {
    SCOPED_TRACE(fmt::format("{} x {}", w, h));
    const double a = double(w) / h;
    const std::vector<std::pair<std::string, double>> expected = {
        {"x", t / a}, {"y", t}, {"diagonal", t / std::sqrt(1 + a * a)}, {"smaller", a > 1 ? t : t / a}, {"larger", a > 1 ? t / a : t}};
    for (const auto& [axis, tanHalfY] : expected) {
      CameraDesc c = sensor(axis);
      resizeCamera(c, w, h);
      EXPECT_EQ(c.width, w);
      EXPECT_EQ(c.height, h);
      EXPECT_NEAR(std::tan(glm::radians(c.fovYDeg) / 2), tanHalfY, 1e-12) << axis;
    }
  }
  // A JSON camera keeps its vertical field.
  CameraDesc json = test::sceneFromJson(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 40, "resolution": [200, 100]},
      "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
      "shapes": [{"type": "box", "material": "m", "min": [0, 0, 0], "max": [1, 1, 1]}]})").camera;
  resizeCamera(json, 100, 300);
  EXPECT_EQ(json.fovYDeg, 40.0);
}

TEST(MitsubaCamera, RenderWidthAndHeightKeepTheHorizontalField) {
  // The sensor at the origin looks along +z with 50° across its 64 × 32 film (fov_axis x). A lamp (radiance 1) at
  // z = 1 spans |x| ≤ tan(25°)/2, the middle half of that field, and the whole height. Rendered with --width 32
  // --height 32 the field across stays 50°, so columns 8 to 23 see the lamp and the others see nothing; a vertical
  // field kept from the file's aspect (tan(fov_y/2) = tan(25°)/2) would show the lamp across all 32 columns.
  const std::string scene = writeScene(fmt::format(R"(<sensor type="perspective"><float name="fov" value="50"/>
        <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="32"/></film></sensor>
      <shape type="rectangle"><boolean name="flip_normals" value="true"/>
        <transform name="to_world"><scale x="{}" y="10"/><translate z="1"/></transform>
        <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)", std::tan(glm::radians(25.0)) / 2), {});
  const std::string out = std::filesystem::path(scene).parent_path().string() + "/img.exr";
  const test::CommandResult r = test::run(std::string(FIRSTSHOT_RENDER_EXE) + " " + scene +
                                          " --integrator path --spp 2 --width 32 --height 32 -q -o " + out);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  int w = 0, h = 0;
  std::vector<std::string> channels;
  const std::vector<float> image = Film::read(out, w, h, channels);
  ASSERT_EQ(w, 32);
  ASSERT_EQ(h, 32);
  const size_t nc = channels.size();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      EXPECT_NEAR(image[(size_t(y) * w + x) * nc], x >= 8 && x < 24 ? 1.0f : 0.0f, 1e-5f) << "pixel " << x << ", " << y;
}

TEST(MitsubaCamera, ThinlensIsAPinholeAndSaysSo) {
  const char* lens = R"(<sensor type="{}"><float name="fov" value="40"/>{}
      <transform name="to_world"><lookat origin="0, 1, 4" target="0, 0.5, 0"/></transform></sensor><shape type="cube"/>)";
  testing::internal::CaptureStderr();
  const SceneDesc thin = loadScene(writeScene(fmt::format(fmt::runtime(lens), "thinlens",
      R"(<float name="aperture_radius" value="0.05"/><float name="focus_distance" value="4"/>)"), {}));
  const std::string err = testing::internal::GetCapturedStderr();
  const SceneDesc pin = loadScene(writeScene(fmt::format(fmt::runtime(lens), "perspective", ""), {}));
  EXPECT_THAT(err, HasSubstr("thinlens sensor rendered as a pinhole"));
  EXPECT_THAT(err, ::testing::Not(HasSubstr("not used by firstshot")));
  EXPECT_EQ(thin.camera.position, pin.camera.position);
  EXPECT_EQ(thin.camera.lookAt, pin.camera.lookAt);
  EXPECT_EQ(thin.camera.fovYDeg, pin.camera.fovYDeg);
  expectLoadError(writeScene(fmt::format(fmt::runtime(lens), "thinlens", R"(<float name="aperture_radius" value="-1"/>)"), {}),
                  {"scene/sensor/aperture_radius (line 2)", "must not be negative"});
}
