// Light samples of an emissive mesh merged into clusters as its receivers allow.
#include "preprocess/light_clusters.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "common/lights/form_factors.h"

namespace firstshot {

namespace {

constexpr double kFar = std::numeric_limits<double>::infinity();

/// A face of a non-emissive shape and its bounding sphere.
struct Receiver {
  std::array<Vec3d, 4> v;
  int count = 0;
  Vec3d centre{0.0};
  double radius = 0;  ///< m
};

std::vector<Receiver> receiversOf(const SceneDesc& scene) {
  std::vector<Receiver> out;
  for (const ShapeDesc& s : scene.shapes) {
    if (scene.materials[s.material].isEmissive()) continue;
    for (const Face& f : s.faces) {
      Receiver r;
      r.count = f.count;
      for (int i = 0; i < f.count; ++i) r.v[i] = s.vertices[f.v[i]], r.centre += r.v[i];
      r.centre /= double(f.count);
      for (int i = 0; i < f.count; ++i) r.radius = std::max(r.radius, glm::length(r.v[i] - r.centre));
      out.push_back(r);
    }
  }
  return out;
}

class Clusterer {
 public:
  Clusterer(const std::vector<Receiver>& receivers, const LightTessellation& fine, double tolerance, double floor)
      : receivers_(receivers), fine_(fine), tolerance_(tolerance), scale_(std::sqrt(kVertexRuleErrorConstant / tolerance)),
        floor_(floor) {}

  /// Clusters the samples fine_[*begin..*end) and appends one sample per cluster kept whole to @p out.
  void split(uint32_t* begin, uint32_t* end, LightTessellation& out) const {
    if (end - begin == 1)
      return emit(fine_.positions[*begin], fine_.weights[*begin], fine_.normals[*begin], emissionOf(begin, end), out);
    double weight = 0;
    Vec3d centre(0.0), moment(0.0);
    for (const uint32_t* i = begin; i != end; ++i) {
      weight += fine_.weights[*i];
      centre += fine_.weights[*i] * fine_.positions[*i];
      moment += fine_.weights[*i] * fine_.normals[*i];
    }
    centre /= weight;
    const double agreement = glm::length(moment);
    const bool coherent = weight <= (1 + tolerance_) * agreement;
    if (coherent) {
      const Vec3d n = moment / agreement;
      double rear = kFar, radius = 0;
      for (const uint32_t* i = begin; i != end; ++i) {
        rear = std::min(rear, glm::dot(n, fine_.positions[*i]));
        radius = std::max(radius, glm::length(fine_.positions[*i] - centre));
      }
      if (2 * radius <= floor_ || 2 * radius * scale_ <= distance(centre, radius, n, rear))
        return emit(centre, weight, n, emissionOf(begin, end), out);
    }
    // Split at the median of the widest spread: of the normals while they disagree, else of the positions.
    const std::vector<Vec3d>& key = coherent ? fine_.positions : fine_.normals;
    Vec3d lo(kFar), hi(-kFar);
    for (const uint32_t* i = begin; i != end; ++i) lo = glm::min(lo, key[*i]), hi = glm::max(hi, key[*i]);
    const Vec3d extent = hi - lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    uint32_t* mid = begin + (end - begin) / 2;
    std::nth_element(begin, mid, end, [&](uint32_t a, uint32_t b) {
      return key[a][axis] < key[b][axis] || (key[a][axis] == key[b][axis] && a < b);
    });
    split(begin, mid, out);
    split(mid, end, out);
  }

 private:
  void emit(const Vec3d& p, double w, const Vec3d& n, const Color& emission, LightTessellation& out) const {
    out.positions.push_back(p);
    out.weights.push_back(w);
    out.normals.push_back(n);
    if (!fine_.emission.empty()) out.emission.push_back(emission);  // textured emitters
  }

  /// The weight-averaged emission of fine_[*begin..*end) (a textured emitter); 0 when fine_ has none.
  Color emissionOf(const uint32_t* begin, const uint32_t* end) const {
    if (fine_.emission.empty()) return Color(0.0f);
    Vec3d sum(0.0);
    double weight = 0;
    for (const uint32_t* i = begin; i != end; ++i)
      sum += fine_.weights[*i] * Vec3d(fine_.emission[*i]), weight += fine_.weights[*i];
    return weight > 0 ? Color(sum / weight) : Color(0.0f);
  }

  /// Distance (m) from the ball (@p c, @p r) to the nearest receiver part in front of the plane
  /// n·x = @p rear (faces lying in that plane, which the cluster cannot light, left out); ≥ 0.
  double distance(const Vec3d& c, double r, const Vec3d& n, double rear) const {
    double best = kFar;
    for (const Receiver& q : receivers_) {
      if (glm::length(q.centre - c) - q.radius - r >= best) continue;
      Vec3d clipped[8];
      const int m = analytic::clipPolygonToPlane(q.v.data(), q.count, Vec3d(0.0), n, rear, clipped);
      if (m < 3) continue;
      double height = 0;
      for (int i = 0; i < m; ++i) height = std::max(height, glm::dot(n, clipped[i]) - rear);
      if (height <= 1e-9 * 2 * q.radius) continue;
      best = std::min(best, std::max(0.0, pointPolygonDistance(c, clipped, m) - r));
    }
    return best;
  }

  const std::vector<Receiver>& receivers_;
  const LightTessellation& fine_;
  double tolerance_, scale_, floor_;
};

}  // namespace

LightTessellation clusterLightSamples(const SceneDesc& scene, LightTessellation fine, double tolerance, double floor) {
  const std::vector<Receiver> receivers = receiversOf(scene);
  std::vector<uint32_t> order(fine.positions.size());
  std::iota(order.begin(), order.end(), 0u);
  LightTessellation out;
  if (!order.empty()) Clusterer(receivers, fine, tolerance, floor).split(order.data(), order.data() + order.size(), out);
  out.triangles = std::move(fine.triangles);
  return out;
}

}  // namespace firstshot
