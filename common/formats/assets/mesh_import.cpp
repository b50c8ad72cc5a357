#include "common/formats/assets/mesh_import.h"
#include "common/lights/spot_cone.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>

#include "common/formats/assets/asset_checks.h"
#include "common/formats/assets/gltf_file.h"
#include "common/formats/assets/gltf_materials.h"
#include "common/formats/vertex_welder.h"
#include "common/lights/photometry.h"
#include "common/materials/bump_map.h"
#include "common/materials/texture.h"
#include "common/scene/skipped_faces.h"
#include "common/util/error.h"

namespace firstshot {
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

/// Reads @p path with assimp (triangulated, nothing else changed). The importer owns the scene. A glTF file's
/// buffers are checked first (GltfFile::bufferDefect), and the file read beside assimp is left in @p gltf.
const aiScene* readAsset(Assimp::Importer& importer, const std::string& path, const std::string& sceneFile,
                         const std::string& element, std::optional<GltfFile>& gltf) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(sceneFile, element, "mesh file not found: " + path);
  if (isGitLfsPointer(fileHead(path)))
    throw InputError(sceneFile, element, "mesh file " + path + " " + kGitLfsPointerMessage);
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
  if (isGltf(path)) {
    gltf.emplace(path);
    if (const std::string defect = gltf->bufferDefect(); !defect.empty())
      throw InputError(sceneFile, element, "mesh file " + path + ": " + defect);
  }
  // No aiProcess_ValidateDataStructure: it rejects meshes without faces, which we report as "no triangles".
  // Triangulation runs only once the indices are checked (ReadFile(path, flags) is this, unchecked).
  const aiScene* scene = importer.ReadFile(path, 0);
  if (!scene || !scene->mRootNode) {
    std::string why = importer.GetErrorString();
    if (gltf && !gltf->parseError().empty()) why = gltf->parseError();  // assimp says "no suitable reader"
    throw InputError(sceneFile, element, "cannot read mesh file " + path + ": " + why);
  }
  if (const std::string defect = structureDefect(*scene); !defect.empty())
    throw InputError(sceneFile, element, "mesh file " + path + ": " + defect);
  setPrimitiveTypes(*scene);
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate);
  if (!scene) throw InputError(sceneFile, element, "cannot read mesh file " + path + ": " + importer.GetErrorString());
  return scene;
}

/// A file's normal @p n in world space (by @p normalMatrix, the inverse transpose), unit; 0 where it is not finite
/// or zero (such a corner then takes its face's geometric normal: render/scene/shading_normals.h).
Vec3 importedNormal(const Mat3d& normalMatrix, const aiVector3D& n) {
  const Vec3d w = normalMatrix * Vec3d(n.x, n.y, n.z);
  const double length = glm::length(w);
  return std::isfinite(length) && length > 0.0 ? Vec3(w / length) : Vec3(0.0f);
}

/// A file's tangent-frame vector @p v (glTF TANGENT's xyz, or assimp's bitangent) in world space: a surface
/// vector, transformed by @p m itself; unit, 0 where it is not finite or zero.
Vec3 importedTangent(const Mat3d& m, const aiVector3D& v) {
  const Vec3d w = m * Vec3d(v.x, v.y, v.z);
  const double length = glm::length(w);
  return std::isfinite(length) && length > 0.0 ? Vec3(w / length) : Vec3(0.0f);
}

/// Where appendTriangles puts a mesh's tangent frames (ShapeDesc::tangents, bitangents); null pointers: nowhere.
struct TangentsOut {
  std::vector<Vec3>* tangents = nullptr;
  std::vector<Vec3>* bitangents = nullptr;
};

/// Appends every triangle of @p mesh, transformed by @p toWorld, keeping degenerate ones, and its first set of
/// texture coordinates to @p uv (4 per face, ShapeDesc::uv) unless @p uv is null: (u, 1 − v) of assimp's, which
/// holds OBJ's vt as it is (v up) and glTF's as 1 − v; (0, 0) when the mesh has none; and its normals to
/// @p normals (4 per face, ShapeDesc::normals) unless null: world space, 0 when the mesh has none; likewise its
/// tangent frames (glTF TANGENT, which assimp keeps only beside NORMAL, as tangent and w × N × T) to @p frames.
/// A mirroring transform
/// (negative determinant) reverses the winding so that the front side stays the front.
/// @return false when a face indexes past the mesh's vertices.
bool appendTriangles(const aiMesh& mesh, const Mat4d& toWorld, Welder& welder, std::vector<Face>& faces,
                     std::vector<Vec2>* uv, std::vector<Vec3>* normals, TangentsOut frames = {}) {
  const bool flip = glm::determinant(Mat3d(toWorld)) < 0.0;
  const bool framed = mesh.mNormals && mesh.mTangents && mesh.mBitangents;  // tangent frames from the file
  const aiVector3D* coords = mesh.mTextureCoords[0];
  const Mat3d normalMatrix = glm::transpose(glm::inverse(Mat3d(toWorld)));  // normals by the inverse transpose
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& in = mesh.mFaces[f];
    if (in.mNumIndices != 3) continue;  // points and lines
    Face out;
    Vec2 corner[4] = {Vec2(0.0f), Vec2(0.0f), Vec2(0.0f), Vec2(0.0f)};
    Vec3 normal[4] = {Vec3(0.0f), Vec3(0.0f), Vec3(0.0f), Vec3(0.0f)};
    Vec3 tangent[4] = {Vec3(0.0f), Vec3(0.0f), Vec3(0.0f), Vec3(0.0f)};
    Vec3 bitangent[4] = {Vec3(0.0f), Vec3(0.0f), Vec3(0.0f), Vec3(0.0f)};
    for (int k = 0; k < 3; ++k) {
      if (in.mIndices[k] >= mesh.mNumVertices) return false;
      out.v[k] = welder.index(point(toWorld, mesh.mVertices[in.mIndices[k]]));
      if (coords) corner[k] = Vec2(coords[in.mIndices[k]].x, 1.0f - coords[in.mIndices[k]].y);
      if (mesh.mNormals) normal[k] = importedNormal(normalMatrix, mesh.mNormals[in.mIndices[k]]);
      if (framed) {
        tangent[k] = importedTangent(Mat3d(toWorld), mesh.mTangents[in.mIndices[k]]);
        bitangent[k] = importedTangent(Mat3d(toWorld), mesh.mBitangents[in.mIndices[k]]);
      }
    }
    if (flip) std::swap(out.v[1], out.v[2]), std::swap(corner[1], corner[2]), std::swap(normal[1], normal[2]);
    if (flip) std::swap(tangent[1], tangent[2]), std::swap(bitangent[1], bitangent[2]);
    faces.push_back(out);
    if (uv) uv->insert(uv->end(), corner, corner + 4);
    if (normals) normals->insert(normals->end(), normal, normal + 4);
    if (frames.tangents) frames.tangents->insert(frames.tangents->end(), tangent, tangent + 4);
    if (frames.bitangents) frames.bitangents->insert(frames.bitangents->end(), bitangent, bitangent + 4);
  }
  return true;
}

/// Whether any mesh of @p scene has normals (glTF NORMAL, OBJ vn, PLY nx ny nz).
bool hasNormals(const aiScene& scene) {
  for (unsigned m = 0; m < scene.mNumMeshes; ++m)
    if (scene.mMeshes[m] && scene.mMeshes[m]->mNormals) return true;
  return false;
}

/// Whether any mesh of @p scene has tangent frames (glTF TANGENT beside NORMAL).
bool hasTangents(const aiScene& scene) {
  for (unsigned m = 0; m < scene.mNumMeshes; ++m)
    if (scene.mMeshes[m] && scene.mMeshes[m]->mNormals && scene.mMeshes[m]->mTangents && scene.mMeshes[m]->mBitangents)
      return true;
  return false;
}

/// Whether any mesh of @p scene has texture coordinates (set 0).
bool hasTextureCoordinates(const aiScene& scene) {
  for (unsigned m = 0; m < scene.mNumMeshes; ++m)
    if (scene.mMeshes[m] && scene.mMeshes[m]->mTextureCoords[0]) return true;
  return false;
}

/// Calls f(mesh index, node-to-world transform) for every mesh instance, depth first.
template <typename F>
void forEachMeshInstance(const aiNode* node, const Mat4d& parent, const F& f) {
  const Mat4d m = parent * toMat(node->mTransformation);
  for (unsigned i = 0; i < node->mNumMeshes; ++i) f(node->mMeshes[i], m);
  for (unsigned i = 0; i < node->mNumChildren; ++i) forEachMeshInstance(node->mChildren[i], m, f);
}

/// Converts an OBJ or PLY material: diffuse colour -> albedo, emissive colour -> emission; assimp's PBR keys
/// (OBJ's Pm/Pr) to the pbr material through metallicRoughnessMaterial when there are any. Else OBJ's Phong
/// highlight (illum 2, which assimp reports as Phong shading, with Ks > 0 and Ns > 0) makes a glossy material:
/// specular = Ks, exponent = Ns, the MTL's own Phong model; where Kd + Ks exceeds 1 (common in exported files) both
/// are scaled down to sum to 1 in that channel's maximum. Other textures than map_Kd (MaterialTable::diffuseTexture)
/// are not read here.
MaterialDesc convertMaterial(const aiMaterial& mat) {
  aiColor3D c(0.5f, 0.5f, 0.5f), e(0.0f, 0.0f, 0.0f), ks(0.0f, 0.0f, 0.0f);
  if (mat.Get(AI_MATKEY_BASE_COLOR, c) != aiReturn_SUCCESS) mat.Get(AI_MATKEY_COLOR_DIFFUSE, c);
  mat.Get(AI_MATKEY_COLOR_EMISSIVE, e);
  float metallic = 0.0f, roughness = 1.0f, ns = 0.0f;
  const bool pbr = mat.Get(AI_MATKEY_METALLIC_FACTOR, metallic) == aiReturn_SUCCESS;
  mat.Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness);
  int shading = 0;
  mat.Get(AI_MATKEY_SHADING_MODEL, shading);
  mat.Get(AI_MATKEY_COLOR_SPECULAR, ks);
  mat.Get(AI_MATKEY_SHININESS, ns);
  MaterialDesc m;
  m.albedo = color(c);
  if (pbr) {
    m = metallicRoughnessMaterial(color(c), metallic, roughness);
  } else if (shading == aiShadingMode_Phong && maxComponent(color(ks)) > 0.0f && ns > 0.0f && std::isfinite(ns)) {
    m.type = MaterialType::Glossy;
    m.specular = glm::max(color(ks), Color(0.0f));
    m.exponent = ns;
    const float sum = maxComponent(m.albedo + m.specular);
    if (sum > 1.0f) m.albedo /= sum, m.specular /= sum;
  }
  m.emission = color(e);
  return m;
}

/// The texture coordinates of @p mesh's triangles in TEXCOORD_<@p set> (glTF's v, down from the image's top: assimp
/// 5.2's glTF importer stores 1 − v), each weighted by its area in m² under @p toWorld; nullopt without that set.
std::optional<std::vector<UvTriangle>> uvTriangles(const aiMesh& mesh, const Mat4d& toWorld, unsigned set) {
  if (set >= AI_MAX_NUMBER_OF_TEXTURECOORDS || !mesh.mTextureCoords[set]) return std::nullopt;
  std::vector<UvTriangle> triangles;
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& face = mesh.mFaces[f];
    if (face.mNumIndices != 3) continue;
    UvTriangle t;
    Vec3d p[3];
    for (int k = 0; k < 3; ++k) {
      const aiVector3D& uv = mesh.mTextureCoords[set][face.mIndices[k]];
      t.uv[k] = Vec2d(uv.x, 1.0 - double(uv.y));
      p[k] = point(toWorld, mesh.mVertices[face.mIndices[k]]);
    }
    t.weight = 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
    triangles.push_back(t);
  }
  return triangles;
}

/// Converts a light placed by @p node. KHR_lights_punctual intensities are photometric, point and spot in candela
/// (on the axis), directional in lux; assimp stores colour·intensity in mColorDiffuse, and they become watts as
/// the JSON's "candela" does (powerFromCandela, photometry::toRadiometric: the colour multiplies the intensity).
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
      d.irradiance = photometry::toRadiometric(1.0, intensity);  // lx -> W/m²
      break;
    case aiLightSource_SPOT:
      d.type = LightType::Spot;
      d.innerAngleDeg = glm::degrees(double(l.mAngleInnerCone));
      d.outerAngleDeg = glm::degrees(double(l.mAngleOuterCone));
      d.power = powerFromCandela(d, 1.0, intensity);
      break;
    default:  // point (and anything else assimp knows: treated as a point)
      d.type = LightType::Point;
      d.power = powerFromCandela(d, 1.0, intensity);
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

/// The scene's materials, each converted when first used: one per asset material, and for a glTF material with an
/// emissive texture one per emission its meshes get (emissionOnMesh). Defaults stand in for "no material":
/// assimp's OBJ/PLY default (unnamed or "DefaultMaterial") and the one its glTF2 importer appends last.
class MaterialTable {
 public:
  MaterialTable(const aiScene& scene, const GltfFile* gltf, std::vector<MaterialDesc>& materials, std::string file)
      : scene_(scene), gltf_(gltf), materials_(materials), converted_(scene.mNumMaterials), file_(std::move(file)) {
    if (gltf) textures_.emplace(*gltf);
    // assimp's material k is the file's materials[order_[k]] (gltfAssimpOrder); the last one is its default. Where
    // the count disagrees, the file's order is kept (what assimp did before it reordered).
    if (gltf) order_ = gltfAssimpOrder(gltf->json()).materials;
    if (order_.size() + 1 != scene.mNumMaterials) order_.clear();
  }

  /// The index in the scene's materials of the material of @p mesh, placed by @p toWorld, named @p meshName.
  int index(const aiMesh& mesh, const Mat4d& toWorld, const std::string& meshName) {
    const unsigned k = mesh.mMaterialIndex;
    if (k >= converted_.size()) return add(defaultMaterial(), k, meshName);
    if (!converted_[k]) converted_[k] = convert(k);
    MaterialDesc m = converted_[k]->first;
    if (const std::optional<GltfMaterial>& g = converted_[k]->second; g && g->emissiveTexture.texture >= 0) {
      const auto uv = uvTriangles(mesh, toWorld, g->emissiveTexture.texCoord);
      m.emission = emissionOnMesh(*g, *textures_, uv ? &*uv : nullptr);
      // Emission per point, through the coordinates the shapes keep; an image that could not be read is
      // already named once (emissionOnMesh asked for it) and leaves the factor alone.
      if (g->emissiveTexture.texCoord == 0 && mesh.mTextureCoords[0] && maxComponent(g->emissive) > 0.0f &&
          textures_->image(g->emissiveTexture, true))
        if ((m.emissionTexture = textures_->texture(g->emissiveTexture))) m.emissionFactor = g->emissive;
    }
    for (size_t i = 0; i < sources_.size(); ++i)
      if (sources_[i] == k && materials_[i].emission == m.emission &&
          !materials_[i].emissionTexture == !m.emissionTexture)  // one glTF material: one texture, ref and sampler
        return int(i);
    return add(std::move(m), k, meshName);
  }

  /// Prints the line of textures that could not be read (GltfTextures::report; likewise for OBJ's map_Kd).
  void reportTextures(const std::string& file) const {
    if (textures_) textures_->report(file);
    if (!objFailures_.empty())
      std::fprintf(stderr, "%s: %zu texture%s not read, their factors used alone (first: %s)\n", file.c_str(),
                   objFailures_.size(), objFailures_.size() == 1 ? "" : "s", objFailures_.front().c_str());
    if (!bumpMaps_.empty())
      std::fprintf(stderr, "%s: %zu bump (height) map%s turned into normal maps (first: %s)\n", file.c_str(),
                   bumpMaps_.size(), bumpMaps_.size() == 1 ? "" : "s", bumpMaps_.front().c_str());
  }

 private:
  static MaterialDesc defaultMaterial() {
    MaterialDesc m;
    m.name = "default";
    m.albedo = Color(0.5f);
    return m;
  }

  /// Material @p k of the asset, and for glTF the JSON's material (empty for defaults).
  std::pair<MaterialDesc, std::optional<GltfMaterial>> convert(unsigned k) {
    const aiMaterial* mat = scene_.mMaterials[k];
    aiString name;
    if (mat) mat->Get(AI_MATKEY_NAME, name);
    const bool isDefault = !mat || (gltf_ ? k + 1 == scene_.mNumMaterials
                                          : name.length == 0 || std::strcmp(name.C_Str(), AI_DEFAULT_MATERIAL_NAME) == 0);
    if (isDefault) return {defaultMaterial(), std::nullopt};
    std::optional<GltfMaterial> g;
    const uint64_t fileIndex = k < order_.size() ? order_[k] : k;
    if (gltf_) g = readGltfMaterial(gltf_->json(), fileIndex);
    MaterialDesc m = g ? convertGltfMaterial(*g, *textures_) : convertMaterial(*mat);
    if (!g) m.albedoTexture = diffuseTexture(*mat);
    if (!g) opacityCutout(*mat, m);  // map_d: a mask cut-out
    if (!g) objNormalMaps(*mat, m);
    m.name = name.length > 0 ? name.C_Str() : "material[" + std::to_string(fileIndex) + "]";
    return {std::move(m), std::move(g)};
  }

  /// Appends @p m, made unique in name: " [k]" when another material has its name, " on <mesh>" for a second
  /// emission of one glTF material.
  int add(MaterialDesc m, unsigned k, const std::string& meshName) {
    const auto taken = [&](const std::string& name) {
      return std::any_of(materials_.begin(), materials_.end(), [&](const MaterialDesc& o) { return o.name == name; });
    };
    if (std::find(sources_.begin(), sources_.end(), k) != sources_.end()) m.name += " on " + meshName;
    if (taken(m.name)) m.name += " [" + std::to_string(k) + "]";
    if (taken(m.name)) m.name += " (" + std::to_string(materials_.size()) + ")";
    materials_.push_back(std::move(m));
    sources_.push_back(k);
    return int(materials_.size()) - 1;
  }

  /// OBJ/MTL's map_d (assimp's opacity texture) makes @p m a mask cut-out: alpha = d × the texture
  /// (its alpha channel, else its grey, linear), cut-off 0.5. Without map_d, or when it cannot be read (then
  /// reportTextures() names it), or on an emitting material, @p m stays opaque (d alone is not read).
  void opacityCutout(const aiMaterial& mat, MaterialDesc& m) {
    aiString file;
    if (m.isEmissive() || mat.GetTexture(aiTextureType_OPACITY, 0, &file) != aiReturn_SUCCESS || file.length == 0) return;
    std::string name = file.C_Str();
    std::replace(name.begin(), name.end(), '\\', '/');
    const std::string path = (std::filesystem::path(file_).parent_path() / name).string();
    auto texture = std::make_shared<Texture>();
    try {
      std::shared_ptr<const TexelImage>& image = objImages_[path + "\n(linear)"];
      if (!image) image = std::make_shared<const TexelImage>(readTexelImage(path, false));
      texture->image = image;
    } catch (const InputError& e) {
      objFailures_.push_back(e.what());
      return;
    }
    float d = 1.0f;
    if (mat.Get(AI_MATKEY_OPACITY, d) != aiReturn_SUCCESS) d = 1.0f;
    m.alphaMode = AlphaMode::Mask;
    m.alpha = std::clamp(d, 0.0f, 1.0f);
    m.alphaTexture = std::move(texture);
  }

  /// OBJ/MTL's map_Kd (the file relative to the asset's folder), multiplying Kd; nullptr without one or when it
  /// cannot be read (then reportTextures() names it).
  std::shared_ptr<const Texture> diffuseTexture(const aiMaterial& mat, aiTextureType type = aiTextureType_DIFFUSE) {
    aiString file;
    if (mat.GetTexture(type, 0, &file) != aiReturn_SUCCESS || file.length == 0) return nullptr;
    std::string name = file.C_Str();
    std::replace(name.begin(), name.end(), '\\', '/');
    const std::string path = (std::filesystem::path(file_).parent_path() / name).string();
    auto texture = std::make_shared<Texture>();
    try {
      std::shared_ptr<const TexelImage>& image = objImages_[path];
      if (!image) image = std::make_shared<const TexelImage>(readTexelImage(path, type == aiTextureType_DIFFUSE));
      texture->image = image;
    } catch (const InputError& e) {
      objFailures_.push_back(e.what());
      return nullptr;
    }
    return texture;
  }

  /// MTL's `norm` (assimp's NORMALS) as the normal map, read linear as glTF's; without one, a bump map
  /// (`bump`, `map_bump`: assimp's HEIGHT) becomes it (common/materials/bump_map.h: a normal map as it is, a height map
  /// converted with its `-bm` multiplier); reportTextures() says how many were converted.
  void objNormalMaps(const aiMaterial& mat, MaterialDesc& m) {
    m.normalTexture = diffuseTexture(mat, aiTextureType_NORMALS);
    if (m.normalTexture) return;
    std::shared_ptr<const Texture> bump = diffuseTexture(mat, aiTextureType_HEIGHT);
    if (!bump || bumpImageIsNormalMap(*bump->image)) {
      m.normalTexture = bump;
      return;
    }
    float scale = 1.0f;
    if (mat.Get(AI_MATKEY_BUMPSCALING, scale) != aiReturn_SUCCESS) scale = 1.0f;
    auto converted = std::make_shared<Texture>(*bump);
    converted->image = std::make_shared<const TexelImage>(normalMapFromHeights(*bump->image, scale));
    m.normalTexture = converted;
    bumpMaps_.push_back(bump->image->name);
  }

  const aiScene& scene_;
  const GltfFile* gltf_;
  std::vector<MaterialDesc>& materials_;
  std::vector<std::optional<std::pair<MaterialDesc, std::optional<GltfMaterial>>>> converted_;
  std::vector<unsigned> sources_;  ///< the asset material of each of materials_
  std::vector<uint64_t> order_;    ///< glTF: the file's index of each assimp material but the default (gltfAssimpOrder)
  std::optional<GltfTextures> textures_;
  std::string file_;  ///< the asset file
  std::map<std::string, std::shared_ptr<const TexelImage>> objImages_;  ///< map_Kd images by path
  std::vector<std::string> objFailures_;
  std::vector<std::string> bumpMaps_;  ///< MTL height maps turned into normal maps
};

}  // namespace

MeshData loadMeshFile(const std::string& path, const std::string& sceneFile, const std::string& element) {
  Assimp::Importer importer;
  std::optional<GltfFile> gltf;
  const aiScene* scene = readAsset(importer, path, sceneFile, element, gltf);
  MeshData data;
  Welder welder(data.vertices);
  const bool uv = hasTextureCoordinates(*scene), normals = hasNormals(*scene), framed = hasTangents(*scene);
  const TangentsOut frames = framed ? TangentsOut{&data.tangents, &data.bitangents} : TangentsOut{};
  forEachMeshInstance(scene->mRootNode, Mat4d(1.0), [&](unsigned mesh, const Mat4d& m) {
    if (!appendTriangles(*scene->mMeshes[mesh], m, welder, data.faces, uv ? &data.uv : nullptr,
                         normals ? &data.normals : nullptr, frames))
      throw InputError(sceneFile, element, "mesh file " + path + ": vertex index out of range");
  });
  if (data.faces.empty()) throw InputError(sceneFile, element, "mesh file " + path + " holds no triangles");
  return data;
}

SceneDesc importAssetScene(const std::string& path) {
  Assimp::Importer importer;
  std::optional<GltfFile> gltf;
  const aiScene* scene = readAsset(importer, path, path, "", gltf);
  SceneDesc s;
  s.file = path;
  MaterialTable materials(*scene, gltf ? &*gltf : nullptr, s.materials, path);
  forEachMeshInstance(scene->mRootNode, Mat4d(1.0), [&](unsigned k, const Mat4d& m) {
    const aiMesh& mesh = *scene->mMeshes[k];
    ShapeDesc shape;
    shape.type = ShapeType::Mesh;
    shape.name = mesh.mName.length > 0 ? mesh.mName.C_Str() : "mesh[" + std::to_string(k) + "]";
    shape.sourceFile = path;
    Welder welder(shape.vertices);
    const bool framed = mesh.mNormals && mesh.mTangents && mesh.mBitangents;
    if (!appendTriangles(mesh, m, welder, shape.faces, mesh.mTextureCoords[0] ? &shape.uv : nullptr,
                         mesh.mNormals ? &shape.normals : nullptr,
                         framed ? TangentsOut{&shape.tangents, &shape.bitangents} : TangentsOut{}))
      throw InputError(path, shape.name, "vertex index out of range");
    if (shape.faces.empty()) return;  // points or lines only
    shape.material = materials.index(mesh, m, shape.name);
    s.shapes.push_back(std::move(shape));
  });
  if (s.shapes.empty()) throw InputError(path, "", "holds no triangles");
  materials.reportTextures(path);
  if (gltf) reportUnsupportedGltfExtensions(gltf->json(), path);
  skipDegenerateFaces(s);

  // Lights and cameras are placed by the node of the same name; those no node places are not in the scene.
  for (unsigned k = 0; k < scene->mNumLights; ++k)
    if (const aiNode* node = scene->mRootNode->FindNode(scene->mLights[k]->mName))
      s.lights.push_back(convertLight(*scene->mLights[k], *node, k));
  for (unsigned k = 0; k < scene->mNumCameras && !s.camera.given; ++k)
    if (const aiNode* node = scene->mRootNode->FindNode(scene->mCameras[k]->mName))
      s.camera = convertCamera(*scene->mCameras[k], *node, gltf.has_value());
  return s;
}

}  // namespace firstshot
