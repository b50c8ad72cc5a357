#include "common/scene/scene_shapes.h"

#include <algorithm>
#include <map>

namespace firstshot::shapes {

void makeQuad(ShapeDesc& s, const std::array<Vec3d, 4>& v) {
  const uint32_t base = static_cast<uint32_t>(s.vertices.size());
  s.vertices.insert(s.vertices.end(), v.begin(), v.end());
  // Planar when the 4th vertex lies in the plane of the first three (relative to the quad's size).
  const Vec3d n = glm::cross(v[1] - v[0], v[2] - v[0]);
  const double scale = std::max(glm::length(v[2] - v[0]), glm::length(v[3] - v[1]));
  const double nl = glm::length(n);
  const bool planar = nl > 0 && std::abs(glm::dot(v[3] - v[0], n / nl)) <= 1e-9 * scale;
  // Convex when both diagonals separate the other two vertices.
  const Vec3d n2 = glm::cross(v[2] - v[1], v[3] - v[1]);
  const Vec3d n3 = glm::cross(v[3] - v[2], v[0] - v[2]);
  const Vec3d n4 = glm::cross(v[0] - v[3], v[1] - v[3]);
  const bool convex = glm::dot(n, n2) > 0 && glm::dot(n, n3) > 0 && glm::dot(n, n4) > 0;
  // Natural coordinates: the image upright on the quad, its bottom-left corner at v[0] (glTF's v points down).
  static const Vec2 corner[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  if (s.faces.empty()) s.uv.clear();
  const bool uv = s.faces.size() * 4 == s.uv.size();  // every face so far has coordinates
  if (planar && convex) {
    Face f;
    f.count = 4;
    for (uint32_t i = 0; i < 4; ++i) f.v[i] = base + i;
    s.faces.push_back(f);
    if (uv) s.uv.insert(s.uv.end(), corner, corner + 4);
    return;
  }
  // Split along the shorter diagonal.
  Face a, b;
  if (glm::length(v[2] - v[0]) <= glm::length(v[3] - v[1])) {
    a.v[0] = base, a.v[1] = base + 1, a.v[2] = base + 2;
    b.v[0] = base, b.v[1] = base + 2, b.v[2] = base + 3;
  } else {
    a.v[0] = base, a.v[1] = base + 1, a.v[2] = base + 3;
    b.v[0] = base + 1, b.v[1] = base + 2, b.v[2] = base + 3;
  }
  s.faces.push_back(a);
  s.faces.push_back(b);
  if (uv)
    for (const Face& f : {a, b})
      for (int k = 0; k < 4; ++k) s.uv.push_back(k < 3 ? corner[f.v[k] - base] : Vec2(0.0f));
}

void makeBox(ShapeDesc& s, const Vec3d& lo, const Vec3d& hi) {
  const uint32_t base = static_cast<uint32_t>(s.vertices.size());
  for (int i = 0; i < 8; ++i)
    s.vertices.emplace_back(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
  // Counter-clockwise seen from outside.
  static const uint32_t quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  // Each face gets the whole image, upright-ish: its first corner at the image's bottom left (as makeQuad).
  static const Vec2 corner[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  const bool uv = s.faces.empty() || s.faces.size() * 4 == s.uv.size();
  for (const auto& q : quads) {
    Face f;
    f.count = 4;
    for (int i = 0; i < 4; ++i) f.v[i] = base + q[i];
    s.faces.push_back(f);
    if (uv) s.uv.insert(s.uv.end(), corner, corner + 4);
  }
}

void makeSphere(ShapeDesc& s, const Vec3d& center, double radius, int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                          {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p = glm::normalize(p);
  std::vector<std::array<uint32_t, 3>> tris = {
      {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
      {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(glm::normalize(v[a] + v[b]));
      return mid[key] = static_cast<uint32_t>(v.size() - 1);
    };
    std::vector<std::array<uint32_t, 3>> next;
    next.reserve(tris.size() * 4);
    for (const auto& tr : tris) {
      const uint32_t ab = midpoint(tr[0], tr[1]), bc = midpoint(tr[1], tr[2]), ca = midpoint(tr[2], tr[0]);
      next.push_back({tr[0], ab, ca});
      next.push_back({tr[1], bc, ab});
      next.push_back({tr[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    tris.swap(next);
  }
  const uint32_t base = static_cast<uint32_t>(s.vertices.size());
  s.uv.clear();  // no texture coordinates on spheres
  for (const auto& p : v) s.vertices.push_back(center + radius * p);
  for (const auto& tr : tris) {
    Face f;
    f.count = 3;
    for (int i = 0; i < 3; ++i) f.v[i] = base + tr[i];
    s.faces.push_back(f);
  }
}

void transform(ShapeDesc& s, const Mat4d& m) {
  for (auto& p : s.vertices) p = Vec3d(m * glm::dvec4(p, 1.0));
  const bool mirror = glm::determinant(Mat4d(m)) < 0;
  if (s.hasNormals()) {  // normals by the inverse transpose; a mirror's flip below turns them back
    const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(m)));
    for (auto& n : s.normals)
      if (n != Vec3(0.0f)) n = Vec3(glm::normalize(normalMatrix * Vec3d(n))) * (mirror ? -1.0f : 1.0f);
  }
  for (std::vector<Vec3>* frame : {&s.tangents, &s.bitangents})  // surface vectors, by the matrix itself
    for (auto& t : *frame)
      if (t != Vec3(0.0f)) t = Vec3(glm::normalize(glm::dmat3(m) * Vec3d(t)));
  if (mirror) flip(s);
}

void flip(ShapeDesc& s) {
  for (size_t i = 0; i < s.faces.size(); ++i) {
    Face& f = s.faces[i];
    std::reverse(f.v, f.v + f.count);
    if (s.hasUv()) std::reverse(s.uv.begin() + long(4 * i), s.uv.begin() + long(4 * i + f.count));
    if (s.hasNormals()) std::reverse(s.normals.begin() + long(4 * i), s.normals.begin() + long(4 * i + f.count));
    for (std::vector<Vec3>* frame : {&s.tangents, &s.bitangents})  // the file's tangent frame stays as it is
      if (!frame->empty()) std::reverse(frame->begin() + long(4 * i), frame->begin() + long(4 * i + f.count));
  }
  for (auto& n : s.normals) n = -n;  // the shading normals follow the front side
}

void smoothSphere(ShapeDesc& s, const Vec3d& center) {
  s.normals.assign(4 * s.faces.size(), Vec3(0.0f));
  for (size_t i = 0; i < s.faces.size(); ++i)
    for (int k = 0; k < s.faces[i].count; ++k)
      s.normals[4 * i + size_t(k)] = Vec3(glm::normalize(s.vertices[s.faces[i].v[k]] - center));
}

double faceArea(const ShapeDesc& s, const Face& f) {
  const Vec3d& a = s.vertices[f.v[0]];
  Vec3d sum(0.0);
  for (int i = 1; i + 1 < f.count; ++i) sum += glm::cross(s.vertices[f.v[i]] - a, s.vertices[f.v[i + 1]] - a);
  return 0.5 * glm::length(sum);
}

}  // namespace firstshot::shapes
