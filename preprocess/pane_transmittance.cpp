// The thin glass panes' transmittance between light samples and patches (pane_transmittance.h).
#include "preprocess/pane_transmittance.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "common/materials/thin_glass.h"
#include "preprocess/embree_triangles.h"

namespace firstshot {

std::vector<uint8_t> seeThroughMaterials(const SceneDesc& scene) {
  std::vector<uint8_t> flags(scene.materials.size(), 0);
  bool any = false;
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    // A rough pane scatters: the item buffers keep it, as an opaque surface with patches of its own.
    flags[m] = scene.materials[m].type == MaterialType::ThinGlass && scene.materials[m].glassRoughness == 0.0f;
    any = any || flags[m];
  }
  if (!any) flags.clear();
  return flags;
}

struct PaneTransmittance::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<ThinGlassBSDF> panes;     ///< by material order of appearance
  std::vector<uint16_t> paneOfTriangle;
  std::vector<Vec3> normalOfTriangle;   ///< unit
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

/// A context that collects every pane the ray crosses: (t, triangle).
struct PaneHits {
  RTCIntersectContext context;  ///< first, as Embree requires
  std::vector<std::pair<float, unsigned>>* hits;
};

void collectPane(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<const PaneHits*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    c->hits->emplace_back(RTCRayN_tfar(args->ray, args->N, i), RTCHitN_primID(args->hit, args->N, i));
    args->valid[i] = 0;  // reject: on to the next pane
  }
}

}  // namespace

PaneTransmittance::PaneTransmittance(const SceneDesc& scene) {
  const std::vector<uint8_t> glass = seeThroughMaterials(scene);
  if (glass.empty()) return;
  impl_ = std::make_unique<Impl>();
  Impl& m = *impl_;
  std::vector<uint16_t> paneOfMaterial(scene.materials.size(), 0);
  for (size_t k = 0; k < scene.materials.size(); ++k)
    if (glass[k]) {
      const MaterialDesc& d = scene.materials[k];
      m.panes.emplace_back(d.transmittance, d.ior);
      paneOfMaterial[k] = static_cast<uint16_t>(m.panes.size() - 1);
    }
  std::vector<float> vertices;
  for (const ShapeDesc& s : scene.shapes) {
    if (!glass[size_t(s.material)]) continue;
    for (const Face& f : s.faces)
      for (int k = 1; k + 1 < int(f.count); ++k) {
        const Vec3 a(s.vertices[f.v[0]]), b(s.vertices[f.v[k]]), c(s.vertices[f.v[k + 1]]);
        const Vec3 n = glm::cross(b - a, c - a);
        const float len = glm::length(n);
        if (!(len > 0.0f)) continue;
        for (const Vec3& v : {a, b, c}) vertices.insert(vertices.end(), {v.x, v.y, v.z});
        m.paneOfTriangle.push_back(paneOfMaterial[size_t(s.material)]);
        m.normalOfTriangle.push_back(n / len);
      }
  }
  m.device = rtcNewDevice(nullptr);
  if (!m.device) throw std::runtime_error("Embree: cannot create a device for the glass panes");
  m.scene = rtcNewScene(m.device);
  rtcSetSceneFlags(m.scene, RTCSceneFlags(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION));
  commitTriangleSoup(m.device, m.scene, vertices, "Embree: cannot allocate the glass panes' buffers",
                     "Embree: building the glass panes failed");
}

PaneTransmittance::~PaneTransmittance() = default;

double PaneTransmittance::along(const Vec3d& o, const Vec3d& d, double tfar) const {
  if (!impl_ || impl_->paneOfTriangle.empty()) return 1.0;
  std::vector<std::pair<float, unsigned>> hits;
  PaneHits c;
  rtcInitIntersectContext(&c.context);
  c.context.filter = collectPane;
  c.hits = &hits;
  RTCRayHit rh;
  rh.ray.org_x = float(o.x), rh.ray.org_y = float(o.y), rh.ray.org_z = float(o.z);
  rh.ray.dir_x = float(d.x), rh.ray.dir_y = float(d.y), rh.ray.dir_z = float(d.z);
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = float(tfar);
  rh.ray.time = 0.0f, rh.ray.mask = 0xffffffffu, rh.ray.id = 0, rh.ray.flags = 0;
  rh.hit.geomID = rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &c.context, &rh);
  std::sort(hits.begin(), hits.end());
  // A pane met twice at one distance (a quad's diagonal, an edge two faces share) is crossed once.
  const double scale = std::max({std::abs(o.x), std::abs(o.y), std::abs(o.z), 1.0});
  Color T(1.0f);
  float last = -1.0f;
  for (const auto& [t, tri] : hits) {
    if (last >= 0.0f && double(t) - double(last) <= 1e-5 * scale + 1e-6 * double(t)) continue;
    last = t;
    const float cosTheta = float(std::abs(glm::dot(Vec3d(impl_->normalOfTriangle[tri]), d)));
    T *= impl_->panes[impl_->paneOfTriangle[tri]].transmittance(cosTheta);
  }
  return double(luminance(T));
}

double PaneTransmittance::between(const Vec3d& a, const Vec3d& b) const {
  const Vec3d d = b - a;
  const double len = glm::length(d);
  if (!(len > 0)) return 1.0;
  return along(a, d / len, len * (1 - 1e-6));
}

double PaneTransmittance::toward(const Vec3d& a, const Vec3d& d) const {
  return along(a, d, std::numeric_limits<double>::infinity());
}

}  // namespace firstshot
