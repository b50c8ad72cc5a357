#include "common/mesh_import.h"
#include "common/lights.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <unordered_map>

#include "common/asset_checks.h"
#include "common/error.h"
#include "common/hash.h"

namespace fs {
namespace {

using Mat3d = glm::dmat3;

Mat4d toMat(const aiMatrix4x4& a) {
  Mat4d m(1.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = a[r][c];  // assimp is row-major, GLM column-major
  return m;
}

/// Node-to-world transform: the product of the transforms from the root down to @p n.
Mat4d worldTransform(const aiNode* n) {
  Mat4d m(1.0);
  for (; n; n = n->mParent) m = toMat(n->mTransformation) * m;
  return m;
}

Vec3d point(const Mat4d& m, const aiVector3D& p) { return Vec3d(m * glm::dvec4(p.x, p.y, p.z, 1.0)); }
Vec3d vector(const Mat4d& m, const aiVector3D& v) { return Mat3d(m) * Vec3d(v.x, v.y, v.z); }
Vec3d unit(const Vec3d& v) { return glm::length(v) > 0.0 ? glm::normalize(v) : v; }
Color color(const aiColor3D& c) { return {c.r, c.g, c.b}; }

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

bool isGltf(const std::string& path) {
  const std::string ext = lowerExtension(path);
  return ext == ".gltf" || ext == ".glb";
}

/// The JSON part of a .gltf or .glb file (null when unreadable); @p error receives the parser's message.
nlohmann::json readGltfJson(const std::string& path, std::string* error = nullptr) {
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.size() >= 20 && text.compare(0, 4, "glTF") == 0) {  // GLB: 12-byte header, then the JSON chunk
    uint32_t length = 0;
    std::memcpy(&length, text.data() + 12, 4);
    text = text.substr(20, std::min<size_t>(length, text.size() - 20));
  }
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    if (error) *error = e.what();
    return nullptr;
  }
}

/// KHR_materials_emissive_strength of glTF material @p k (1 when absent or not a number).
float emissiveStrength(const nlohmann::json& gltf, unsigned k) {
  try {
    return gltf.at("materials").at(k).at("extensions").at("KHR_materials_emissive_strength")
        .at("emissiveStrength").get<float>();
  } catch (const nlohmann::json::exception&) {
    return 1.0f;
  }
}

/// What is wrong with the structure of an imported scene, or "": a node naming a mesh that does not exist,
/// a face without vertices or indexing past its mesh's vertices. assimp's importers do not all check (the
/// PLY one does not), and its triangulation reads what the faces index.
std::string structureDefect(const aiScene& scene, const aiNode& node) {
  for (unsigned i = 0; i < node.mNumMeshes; ++i)
    if (node.mMeshes[i] >= scene.mNumMeshes || !scene.mMeshes[node.mMeshes[i]]) return "a node refers to a missing mesh";
  for (unsigned i = 0; i < node.mNumChildren; ++i)
    if (const std::string d = node.mChildren[i] ? structureDefect(scene, *node.mChildren[i]) : "a node is missing"; !d.empty())
      return d;
  return "";
}
std::string structureDefect(const aiScene& scene) {
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh* mesh = scene.mMeshes[m];
    for (unsigned f = 0; mesh && f < mesh->mNumFaces; ++f) {
      if (mesh->mFaces[f].mNumIndices == 0) return "a face without vertices";
      for (unsigned k = 0; k < mesh->mFaces[f].mNumIndices; ++k)
        if (mesh->mFaces[f].mIndices[k] >= mesh->mNumVertices) return "vertex index out of range";
    }
  }
  return structureDefect(scene, *scene.mRootNode);
}

/// Sets every mesh's primitive types from its faces (each with at least one vertex: structureDefect).
/// Importers may claim polygons where no face has more than three vertices (the PLY one, on some
/// malformed files), and assimp's triangulation then aborts on an assertion instead of reporting an error.
void setPrimitiveTypes(const aiScene& scene) {
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    aiMesh* mesh = scene.mMeshes[m];  // the scene is read-only to us, its meshes are not
    if (!mesh) continue;
    unsigned types = 0;
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const unsigned n = mesh->mFaces[f].mNumIndices;
      types |= n == 1 ? aiPrimitiveType_POINT : n == 2 ? aiPrimitiveType_LINE : n == 3 ? aiPrimitiveType_TRIANGLE
                                                                                 : aiPrimitiveType_POLYGON;
    }
    mesh->mPrimitiveTypes = types;
  }
}

/// Reads @p path with assimp (triangulated, nothing else changed). The importer owns the scene.
const aiScene* readAsset(Assimp::Importer& importer, const std::string& path, const std::string& sceneFile,
                         const std::string& element) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(sceneFile, element, "mesh file not found: " + path);
  // Only the documented types: assimp's other importers are not part of firstshot (nor fuzzed).
  const std::string ext = lowerExtension(path);
  if (ext != ".obj" && ext != ".ply" && !isGltf(path))
    throw InputError(sceneFile, element,
                     "mesh file " + path + ": unsupported type \"" + ext + "\" (expected .obj, .gltf, .glb or .ply)");
  if (ext == ".ply" || ext == ".glb") {
    std::ifstream in(path, std::ios::binary);
    const std::string defect =
        ext == ".ply" ? plyHeaderDefect(in) : glbHeaderDefect(in, std::filesystem::file_size(path, ec));
    if (!defect.empty()) throw InputError(sceneFile, element, "mesh file " + path + ": " + defect);
  }
  // No aiProcess_ValidateDataStructure: it rejects meshes without faces, which we report as "no triangles".
  // Triangulation runs only once the indices are checked (ReadFile(path, flags) is this, unchecked).
  const aiScene* scene = importer.ReadFile(path, 0);
  if (!scene || !scene->mRootNode) {
    std::string why = importer.GetErrorString();
    std::string jsonError;  // assimp only says "no suitable reader" for a .gltf with broken JSON
    if (isGltf(path) && readGltfJson(path, &jsonError).is_null() && !jsonError.empty()) why = jsonError;
    throw InputError(sceneFile, element, "cannot read mesh file " + path + ": " + why);
  }
  if (const std::string defect = structureDefect(*scene); !defect.empty())
    throw InputError(sceneFile, element, "mesh file " + path + ": " + defect);
  setPrimitiveTypes(*scene);
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate);
  if (!scene) throw InputError(sceneFile, element, "cannot read mesh file " + path + ": " + importer.GetErrorString());
  return scene;
}

/// Joins vertices at bit-identical positions, so that triangles sharing an edge share its vertices.
class Welder {
 public:
  explicit Welder(std::vector<Vec3d>& vertices) : vertices_(vertices) {}
  uint32_t index(Vec3d p) {
    p += Vec3d(0.0);  // -0 -> +0
    auto [it, inserted] = map_.try_emplace(p, uint32_t(vertices_.size()));
    if (inserted) vertices_.push_back(p);
    return it->second;
  }

 private:
  struct KeyHash {
    size_t operator()(const Vec3d& p) const { return size_t(Hasher().add(p).value()); }
  };
  std::vector<Vec3d>& vertices_;
  std::unordered_map<Vec3d, uint32_t, KeyHash> map_;
};

/// Appends every triangle of @p mesh, transformed by @p toWorld, keeping degenerate ones. A mirroring
/// transform (negative determinant) reverses the winding so that the front side stays the front.
/// @return false when a face indexes past the mesh's vertices.
bool appendTriangles(const aiMesh& mesh, const Mat4d& toWorld, Welder& welder, std::vector<Face>& faces) {
  const bool flip = glm::determinant(Mat3d(toWorld)) < 0.0;
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& in = mesh.mFaces[f];
    if (in.mNumIndices != 3) continue;  // points and lines
    Face out;
    for (int k = 0; k < 3; ++k) {
      if (in.mIndices[k] >= mesh.mNumVertices) return false;
      out.v[k] = welder.index(point(toWorld, mesh.mVertices[in.mIndices[k]]));
    }
    if (flip) std::swap(out.v[1], out.v[2]);
    faces.push_back(out);
  }
  return true;
}

/// Calls f(mesh index, node-to-world transform) for every mesh instance, depth first.
template <typename F>
void forEachMeshInstance(const aiNode* node, const Mat4d& parent, const F& f) {
  const Mat4d m = parent * toMat(node->mTransformation);
  for (unsigned i = 0; i < node->mNumMeshes; ++i) f(node->mMeshes[i], m);
  for (unsigned i = 0; i < node->mNumChildren; ++i) forEachMeshInstance(node->mChildren[i], m, f);
}

/// Converts one material. Base colour (else diffuse colour) -> albedo; emissive colour, times the glTF
/// KHR_materials_emissive_strength (read from the JSON: assimp 5.2 ignores it) -> emission. Textures
/// are ignored. glTF metallic/roughness (metallic m, roughness r, base colour b, F0 = 0.04) becomes a
/// stretched-Phong glossy material unless it is a plain rough dielectric (m = 0, r = 1, then diffuse):
///   albedo = b·(1−m)·(1−F0), specular = F0·(1−m) + b·m (their sum stays ≤ 1),
///   exponent n = 2/α² − 2 with α = r² (Walter et al. 2007's Phong–Beckmann match), clamped to [1, 10⁴].
/// OBJ Ks/Ns are ignored (diffuse only).
MaterialDesc convertMaterial(const aiMaterial& mat, float emissiveStrength) {
  MaterialDesc m;
  aiColor3D c(0.5f, 0.5f, 0.5f);
  if (mat.Get(AI_MATKEY_BASE_COLOR, c) != aiReturn_SUCCESS) mat.Get(AI_MATKEY_COLOR_DIFFUSE, c);
  m.albedo = color(c);
  aiColor3D e(0.0f, 0.0f, 0.0f);
  mat.Get(AI_MATKEY_COLOR_EMISSIVE, e);
  m.emission = color(e) * emissiveStrength;
  float metallic = 0.0f, roughness = 1.0f;
  const bool pbr = mat.Get(AI_MATKEY_METALLIC_FACTOR, metallic) == aiReturn_SUCCESS;
  mat.Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness);
  if (pbr && (metallic > 0.0f || roughness < 1.0f)) {
    constexpr float kF0 = 0.04f;
    const Color base = m.albedo;
    m.type = MaterialType::Glossy;
    m.albedo = base * (1.0f - metallic) * (1.0f - kF0);
    m.specular = Color(kF0 * (1.0f - metallic)) + base * metallic;
    const double alpha = std::max(double(roughness) * roughness, 1e-3);
    m.exponent = float(std::clamp(2.0 / (alpha * alpha) - 2.0, 1.0, 1e4));
  }
  return m;
}

/// Converts a light placed by @p node. glTF (KHR_lights_punctual) intensities are taken as radiometric:
/// point/spot candela -> W/sr, directional lux -> W/m²; assimp stores colour·intensity in mColorDiffuse.
/// The glTF range is ignored (inverse-square falloff). glTF spot cone angles are half-angles from the
/// axis, and assimp's glTF2 importer copies them unchanged into mAngleInnerCone/mAngleOuterCone.
LightDesc convertLight(const aiLight& l, const aiNode& node, unsigned k) {
  LightDesc d;
  d.name = "lights[" + std::to_string(k) + "]";
  if (l.mName.length > 0) d.name += " (" + std::string(l.mName.C_Str()) + ")";
  const Mat4d m = worldTransform(&node);
  const Color intensity = color(l.mColorDiffuse);
  d.position = point(m, l.mPosition);
  d.direction = unit(vector(m, l.mDirection));
  switch (l.mType) {
    case aiLightSource_DIRECTIONAL:
      d.type = LightType::Directional;
      d.irradiance = intensity;
      break;
    case aiLightSource_SPOT:
      d.type = LightType::Spot;
      d.innerAngleDeg = glm::degrees(double(l.mAngleInnerCone));
      d.outerAngleDeg = glm::degrees(double(l.mAngleOuterCone));
      d.power = intensity * static_cast<float>(spotProfileIntegral(d));  // Φ = I0·∫profile dω (common/lights.h)
      break;
    default:  // point (and anything else assimp knows: treated as a point)
      d.type = LightType::Point;
      d.power = intensity * float(4.0 * kPi);
  }
  return d;
}

/// Converts a camera placed by @p node. Quirks of assimp 5.2's glTF2 importer: it stores yfov·aspect
/// in mHorizontalFOV (not the documented half angle) and copies the node's translation into mPosition
/// although the node transform already holds it; so for glTF the camera sits at the node's origin.
CameraDesc convertCamera(const aiCamera& c, const aiNode& node, bool gltf) {
  CameraDesc d;
  const Mat4d m = worldTransform(&node);
  d.position = point(m, gltf ? aiVector3D(0, 0, 0) : c.mPosition);
  d.lookAt = d.position + unit(vector(m, c.mLookAt));
  d.up = unit(vector(m, c.mUp));
  const double aspect = c.mAspect > 0.0f ? c.mAspect : 1.0;
  const double fovY = gltf ? c.mHorizontalFOV / aspect : 2.0 * std::atan(std::tan(c.mHorizontalFOV) / aspect);
  d.fovYDeg = glm::degrees(fovY);
  d.width = std::max(1, int(std::lround(d.height * aspect)));
  d.given = true;
  return d;
}

}  // namespace

MeshData loadMeshFile(const std::string& path, const std::string& sceneFile, const std::string& element) {
  Assimp::Importer importer;
  const aiScene* scene = readAsset(importer, path, sceneFile, element);
  MeshData data;
  Welder welder(data.vertices);
  forEachMeshInstance(scene->mRootNode, Mat4d(1.0), [&](unsigned mesh, const Mat4d& m) {
    if (!appendTriangles(*scene->mMeshes[mesh], m, welder, data.faces))
      throw InputError(sceneFile, element, "mesh file " + path + ": vertex index out of range");
  });
  if (data.faces.empty()) throw InputError(sceneFile, element, "mesh file " + path + " holds no triangles");
  return data;
}

SceneDesc importAssetScene(const std::string& path) {
  Assimp::Importer importer;
  const aiScene* scene = readAsset(importer, path, path, "");
  const bool gltf = isGltf(path);
  const nlohmann::json json = gltf ? readGltfJson(path) : nlohmann::json();
  SceneDesc s;
  s.file = path;

  // Materials are converted when first used. Defaults stand in for "no material": assimp's OBJ/PLY
  // default (unnamed or "DefaultMaterial") and the one its glTF2 importer appends last.
  std::vector<int> materialIndex(scene->mNumMaterials, -1);
  auto material = [&](unsigned k) -> int {
    if (k < materialIndex.size() && materialIndex[k] >= 0) return materialIndex[k];
    MaterialDesc m;
    aiString name;
    const aiMaterial* mat = k < scene->mNumMaterials ? scene->mMaterials[k] : nullptr;
    if (mat) mat->Get(AI_MATKEY_NAME, name);
    const bool isDefault = !mat || (gltf ? k + 1 == scene->mNumMaterials
                                         : name.length == 0 || std::strcmp(name.C_Str(), AI_DEFAULT_MATERIAL_NAME) == 0);
    if (isDefault) {
      m.name = "default";
      m.albedo = Color(0.5f);
    } else {
      m = convertMaterial(*mat, gltf ? emissiveStrength(json, k) : 1.0f);
      m.name = name.length > 0 ? name.C_Str() : "material[" + std::to_string(k) + "]";
    }
    const auto sameName = [&](const MaterialDesc& other) { return other.name == m.name; };
    if (std::any_of(s.materials.begin(), s.materials.end(), sameName)) m.name += " [" + std::to_string(k) + "]";
    s.materials.push_back(m);
    const int index = int(s.materials.size()) - 1;
    if (k < materialIndex.size()) materialIndex[k] = index;
    return index;
  };

  forEachMeshInstance(scene->mRootNode, Mat4d(1.0), [&](unsigned k, const Mat4d& m) {
    const aiMesh& mesh = *scene->mMeshes[k];
    ShapeDesc shape;
    shape.type = ShapeType::Mesh;
    shape.name = mesh.mName.length > 0 ? mesh.mName.C_Str() : "mesh[" + std::to_string(k) + "]";
    shape.sourceFile = path;
    Welder welder(shape.vertices);
    if (!appendTriangles(mesh, m, welder, shape.faces))
      throw InputError(path, shape.name, "vertex index out of range");
    if (shape.faces.empty()) return;  // points or lines only
    shape.material = material(mesh.mMaterialIndex);
    s.shapes.push_back(std::move(shape));
  });
  if (s.shapes.empty()) throw InputError(path, "", "holds no triangles");

  // Lights and cameras are placed by the node of the same name; those no node places are not in the scene.
  for (unsigned k = 0; k < scene->mNumLights; ++k)
    if (const aiNode* node = scene->mRootNode->FindNode(scene->mLights[k]->mName))
      s.lights.push_back(convertLight(*scene->mLights[k], *node, k));
  for (unsigned k = 0; k < scene->mNumCameras && !s.camera.given; ++k)
    if (const aiNode* node = scene->mRootNode->FindNode(scene->mCameras[k]->mName))
      s.camera = convertCamera(*scene->mCameras[k], *node, gltf);
  return s;
}

}  // namespace fs
