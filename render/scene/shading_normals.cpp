// Shading normals on the traced patches: interpolated corner normals and normal maps (render/scene/shading_normals.h).
#include "render/scene/shading_normals.h"

#include "common/materials/texture.h"

namespace firstshot {
namespace {

/// A shape's corner normal @p c turned to the front side of @p ng; ng itself where the file gave none (0).
Vec3 frontNormal(const Vec3& c, const Vec3& ng) {
  if (c == Vec3(0.0f)) return ng;
  return glm::dot(c, ng) < 0.0f ? -c : c;
}

/// The tangent frame (T, B) at the point of triangle @p t of face @p f that @p n is perturbed in: the file's (glTF
/// TANGENT) interpolated where its corners have one, else generated from the triangle's uv (∂p/∂u and the
/// image's up, −∂p/∂v). T is made orthogonal to @p n and B = ±n × T, its sign the given frame's (the file's
/// bitangent, or −∂p/∂v: mirrored uv). @return false where neither is usable (degenerate uv, a zero tangent).
bool tangentFrame(const ShapeDesc& s, uint32_t f, const FaceTriangle& t, const Vec3& n, Vec3& tangent, Vec3& bitangent) {
  Vec3 along, up;
  const auto fromFile = [&](int k) { return s.tangents[4 * f + size_t(k)] != Vec3(0.0f); };
  if (s.hasTangents() && fromFile(t.corner[0]) && fromFile(t.corner[1]) && fromFile(t.corner[2])) {
    along = t.interpolate<Vec3>([&](int k) { return s.tangents[4 * f + size_t(k)]; });
    up = t.interpolate<Vec3>([&](int k) { return s.bitangents[4 * f + size_t(k)]; });
  } else {
    const Face& face = s.faces[f];
    const Vec3 p0(s.vertices[face.v[t.corner[0]]]), p1(s.vertices[face.v[t.corner[1]]]), p2(s.vertices[face.v[t.corner[2]]]);
    const Vec2 uv0 = s.cornerUv(f, t.corner[0]);
    const Vec2 d1 = s.cornerUv(f, t.corner[1]) - uv0, d2 = s.cornerUv(f, t.corner[2]) - uv0;
    const Vec3 e1 = p1 - p0, e2 = p2 - p0;
    const float det = d1.x * d2.y - d2.x * d1.y;
    if (!(std::abs(det) > 0.0f)) return false;
    along = (d2.y * e1 - d1.y * e2) / det;        // ∂p/∂u
    up = -(d1.x * e2 - d2.x * e1) / det;          // −∂p/∂v: the image's up
  }
  tangent = along - n * glm::dot(n, along);
  const float length = glm::length(tangent);
  if (!(length > 0.0f) || !std::isfinite(length)) return false;
  tangent /= length;
  bitangent = glm::cross(n, tangent);
  if (glm::dot(bitangent, up) < 0.0f) bitangent = -bitangent;  // mirrored uv, or the file's w = −1
  return true;
}

/// @p n perturbed by the normal map of @p m at the point of triangle @p t of face @p f (shape @p s has texture
/// coordinates), in tangentFrame(); @p n itself where there is no frame.
Vec3 normalMapped(const MaterialDesc& m, const ShapeDesc& s, uint32_t f, const FaceTriangle& t, const Vec3& n) {
  Vec3 tangent, bitangent;
  if (!tangentFrame(s, f, t, n, tangent, bitangent)) return n;
  const Vec2 uv = t.interpolate<Vec2>([&](int k) { return s.cornerUv(f, k); });
  const Color texel = 2.0f * m.normalTexture->lookup(uv) - Color(1.0f);
  const Vec3 mapped = texel.x * m.normalScale * tangent + texel.y * m.normalScale * bitangent + texel.z * n;
  const float l = glm::length(mapped);
  return l > 0.0f && std::isfinite(l) ? mapped / l : n;
}

}  // namespace

ShadingNormals::ShadingNormals(const SceneDesc& scene, const PatchMesh& mesh) : scene_(&scene), mesh_(&mesh) {
  const auto wanted = [&](const Patch& p) {
    const ShapeDesc& s = scene.shapes[p.shape];
    return s.hasNormals() || (scene.materials[p.material].normalTexture && s.hasUv());
  };
  bool any = false;
  for (const Patch& p : mesh.patches) any = any || wanted(p);
  if (any) face_ = mapPatchesToFaces(scene, mesh, wanted);
}

Vec3 ShadingNormals::normalAt(uint32_t patch, const Vec3& p, const Vec3& ng) const {
  const Patch& q = mesh_->patches[patch];
  const ShapeDesc& s = scene_->shapes[q.shape];
  const MaterialDesc& m = scene_->materials[q.material];
  const uint32_t f = face_[patch];
  const FaceTriangle t = faceTriangle(s, s.faces[f], Vec3d(p));
  Vec3 n = ng;
  if (s.hasNormals()) {
    const Vec3 sum = t.interpolate<Vec3>([&](int k) { return frontNormal(s.cornerNormal(f, k), ng); });
    const float l = glm::length(sum);
    if (l > 0.0f && glm::dot(sum, ng) > 0.0f) n = sum / l;
  }
  if (m.normalTexture && s.hasUv()) {
    const Vec3 mapped = normalMapped(m, s, f, t, n);
    if (glm::dot(mapped, ng) > 0.0f) n = mapped;
  }
  return n;
}

}  // namespace firstshot
