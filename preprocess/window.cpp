#include "preprocess/window.h"

#include <cmath>
#include <stdexcept>

namespace firstshot {

namespace {

/// A perspective view looking along @p forward with @p up; right = up × forward.
View perspective(const Vec3d& forward, const Vec3d& up, Vec2d planeMin, Vec2d planeMax, int width, int height) {
  View v;
  v.forward = forward;
  v.up = up;
  v.right = glm::cross(up, forward);
  v.projection = Projection::Perspective;
  v.planeMin = planeMin;
  v.planeMax = planeMax;
  v.width = width;
  v.height = height;
  return v;
}

/// δω·(dir·axis)^power at the centre of every pixel: δω = δP / r³ with r² = 1 + u² + v² (focal distance 1).
std::vector<double> solidAngleWeights(const View& view, const Vec3d& axis, int cosinePower) {
  std::vector<double> w(view.pixelCount());
  const double dP = view.pixelArea();
  for (int j = 0; j < view.height; ++j)
    for (int i = 0; i < view.width; ++i) {
      const Vec3d d = view.pixelDirection(i, j);
      const double r2 = glm::dot(d, d);
      double weight = dP / (r2 * std::sqrt(r2));
      if (cosinePower == 1) weight *= std::max(0.0, glm::dot(d, axis)) / std::sqrt(r2);
      w[static_cast<size_t>(j) * view.width + i] = weight;
    }
  return w;
}

void checkResolution(int R, const char* what) {
  if (R < 2 || R > 16384) throw std::invalid_argument(std::string(what) + ": resolution must be in [2, 16384]");
}

}  // namespace

double Window::totalWeight() const {
  double sum = 0;
  for (const auto& w : weights)
    for (double x : w) sum += x;
  return sum;
}

size_t Window::pixelCount() const {
  size_t n = 0;
  for (const View& v : views) n += v.pixelCount();
  return n;
}

void cropToWeights(Window& window) {
  std::vector<View> views;
  std::vector<std::vector<double>> weights;
  for (size_t v = 0; v < window.views.size(); ++v) {
    const View& view = window.views[v];
    const std::vector<double>& w = window.weights[v];
    int i0 = view.width, i1 = -1, j0 = view.height, j1 = -1;
    for (int j = 0; j < view.height; ++j)
      for (int i = 0; i < view.width; ++i)
        if (w[size_t(j) * view.width + i] > 0) i0 = std::min(i0, i), i1 = std::max(i1, i), j0 = std::min(j0, j), j1 = std::max(j1, j);
    if (i1 < 0) continue;
    View c = view;
    const double du = (view.planeMax.x - view.planeMin.x) / view.width, dv = (view.planeMax.y - view.planeMin.y) / view.height;
    c.width = i1 - i0 + 1, c.height = j1 - j0 + 1;
    if (c.width != view.width) c.planeMin.x = view.planeMin.x + i0 * du, c.planeMax.x = view.planeMin.x + (i1 + 1) * du;
    if (c.height != view.height) c.planeMax.y = view.planeMax.y - j0 * dv, c.planeMin.y = view.planeMax.y - (j1 + 1) * dv;
    std::vector<double> cw(c.pixelCount());
    for (int j = 0; j < c.height; ++j)
      std::copy_n(w.begin() + size_t(j + j0) * view.width + i0, c.width, cw.begin() + size_t(j) * c.width);
    views.push_back(c);
    weights.push_back(std::move(cw));
  }
  window.views = std::move(views);
  window.weights = std::move(weights);
}

Window makeCubeWindow(int R) {
  checkResolution(R, "cube window");
  Window win;
  win.kind = WindowKind::Cube;
  win.resolution = R;
  const Vec3d X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);
  const Vec3d forwards[6] = {X, -X, Y, -Y, Z, -Z};
  const Vec3d ups[6] = {Z, Z, Z, Z, Y, Y};
  for (int f = 0; f < 6; ++f) {
    win.views.push_back(perspective(forwards[f], ups[f], {-1, -1}, {1, 1}, R, R));
    win.weights.push_back(solidAngleWeights(win.views.back(), Z, 0));
  }
  return win;
}

Window makeHemicubeWindow(int R) {
  checkResolution(R, "hemicube window");
  if (R % 2 != 0) throw std::invalid_argument("hemicube window: resolution must be even");
  Window win;
  win.kind = WindowKind::Hemicube;
  win.resolution = R;
  const Vec3d X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);
  win.views.push_back(perspective(Z, Y, {-1, -1}, {1, 1}, R, R));
  for (const Vec3d& f : {X, -X, Y, -Y})  // upper halves only: v in [0, 1] along up = +z
    win.views.push_back(perspective(f, Z, {-1, 0}, {1, 1}, R, R / 2));
  for (const View& v : win.views) win.weights.push_back(solidAngleWeights(v, Z, 1));
  return win;
}

int tetraFaceResolution(int R) { return static_cast<int>(std::lround(std::sqrt(2.0) * R)); }

Window makeTetraWindow(int R, int subgrid) {
  checkResolution(R, "tetrahedron window");
  if (subgrid < 1) throw std::invalid_argument("tetrahedron window: subgrid must be >= 1");
  Window win;
  win.kind = WindowKind::Tetrahedron;
  win.resolution = R;
  const int W = tetraFaceResolution(R);
  // Tetrahedron coordinates -> local frame: axis (1,1,1)/√3 becomes +z.
  const Vec3d ex = Vec3d(1, -1, 0) / std::sqrt(2.0);
  const Vec3d ey = Vec3d(1, 1, -2) / std::sqrt(6.0);
  const Vec3d ez = Vec3d(1, 1, 1) / std::sqrt(3.0);
  auto toLocal = [&](const Vec3d& p) { return Vec3d(glm::dot(p, ex), glm::dot(p, ey), glm::dot(p, ez)); };
  // Faces x = 1, y = 1, z = 1, each with (u, v) the next two coordinates in cyclic order.
  const Vec3d axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const double s = 3.0 / W;  // pixel size on the face
  const double invSqrt3 = 1.0 / std::sqrt(3.0);
  // δω·cosθL density per unit face area at (u, v): (1+u+v) / (√3 (1+u²+v²)²), zero below the base plane.
  auto density = [&](double u, double v) {
    const double r2 = 1.0 + u * u + v * v;
    return std::max(0.0, 1.0 + u + v) * invSqrt3 / (r2 * r2);
  };
  for (int f = 0; f < 3; ++f) {
    const Vec3d fwd = axes[f], rgt = axes[(f + 1) % 3], up = axes[(f + 2) % 3];
    View v = perspective(toLocal(fwd), toLocal(up), {-2, -2}, {1, 1}, W, W);
    v.right = toLocal(rgt);  // exact, same as up × forward
    std::vector<double> w(v.pixelCount(), 0.0);
    // Cell (i, j) spans u in [-2+i·s, -2+(i+1)·s] and v in [1-(j+1)·s, 1-j·s]; the line u+v = −1 passes
    // through its corners when i == j. Valid: i > j; boundary (halved): i == j; invalid: i < j.
    for (int j = 0; j < W; ++j)
      for (int i = j; i < W; ++i) {
        double weight = 0;
        if (i > j) {
          const Vec2d uv = v.pixelCentre(i, j);
          weight = density(uv.x, uv.y) * s * s;
        } else {
          // Valid half: the triangle A = (u0+s, v0), B = (u0, v0+s), C = (u0+s, v0+s), split into n²
          // congruent sub-triangles, each integrated with its centroid (exact for linear densities).
          const double u0 = -2.0 + i * s, v0 = 1.0 - (j + 1) * s;
          const Vec2d A(u0 + s, v0), e1 = Vec2d(u0, v0 + s) - A, e2 = Vec2d(u0 + s, v0 + s) - A;
          const int n = subgrid;
          for (int b = 0; b < n; ++b)
            for (int a = 0; a + b < n; ++a) {
              const Vec2d pUp = A + ((a + 1.0 / 3) * e1 + (b + 1.0 / 3) * e2) / double(n);
              weight += density(pUp.x, pUp.y);
              if (a + b < n - 1) {
                const Vec2d pDown = A + ((a + 2.0 / 3) * e1 + (b + 2.0 / 3) * e2) / double(n);
                weight += density(pDown.x, pDown.y);
              }
            }
          weight *= 0.5 * s * s / (double(n) * n);
        }
        w[static_cast<size_t>(j) * W + i] = weight;
      }
    win.views.push_back(v);
    win.weights.push_back(std::move(w));
  }
  return win;
}

Window makeOrthoWindow(int R, const Bounds3d& bounds, const Vec3d& direction) {
  checkResolution(R, "ortho window");
  if (bounds.empty()) throw std::invalid_argument("ortho window: empty scene bounds");
  const Framed frame(glm::normalize(direction));
  const Vec3d c = bounds.centre();
  const double diag = std::max(bounds.diagonal(), 1e-30);
  Vec3d lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (int k = 0; k < 8; ++k) {
    const Vec3d d = bounds.corner(k) - c;
    const Vec3d p(glm::dot(d, frame.s), glm::dot(d, frame.t), glm::dot(d, frame.n));
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const double margin = 1e-4 * diag;  // geometry on the box boundary stays strictly inside
  lo -= Vec3d(margin);
  hi += Vec3d(margin);
  const double pixel = std::max(hi.x - lo.x, hi.y - lo.y) / R;
  const int W = std::max(1, static_cast<int>(std::ceil((hi.x - lo.x) / pixel - 1e-9)));
  const int H = std::max(1, static_cast<int>(std::ceil((hi.y - lo.y) / pixel - 1e-9)));
  View v;
  v.projection = Projection::Orthographic;
  v.right = {1, 0, 0};
  v.up = {0, 1, 0};
  v.forward = {0, 0, 1};
  v.eye = {0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z - 0.01 * diag};
  v.planeMin = {-0.5 * W * pixel, -0.5 * H * pixel};
  v.planeMax = {0.5 * W * pixel, 0.5 * H * pixel};
  v.width = W;
  v.height = H;
  Window win;
  win.kind = WindowKind::Ortho;
  win.resolution = R;
  win.views.push_back(v);
  win.weights.emplace_back(v.pixelCount(), v.pixelArea());
  return win;
}

std::vector<View> placeWindow(const Window& window, const Vec3d& position, const Framed& frame, double eyeOffset) {
  auto rotate = [&](const Vec3d& a) { return a.x * frame.s + a.y * frame.t + a.z * frame.n; };
  std::vector<View> out;
  out.reserve(window.views.size());
  for (View v : window.views) {
    v.eye = position + rotate(v.eye) + eyeOffset * frame.n;
    v.right = rotate(v.right);
    v.up = rotate(v.up);
    v.forward = rotate(v.forward);
    out.push_back(v);
  }
  return out;
}

double areaLightEyeOffset(const Bounds3d& sceneBounds, double relative) { return relative * sceneBounds.diagonal(); }

WindowKind parseWindowKind(const std::string& name) {
  if (name == "cube") return WindowKind::Cube;
  if (name == "hemicube") return WindowKind::Hemicube;
  if (name == "tetra" || name == "tetrahedron") return WindowKind::Tetrahedron;
  if (name == "ortho") return WindowKind::Ortho;
  throw std::invalid_argument("unknown window '" + name + "' (cube | hemicube | tetra | ortho)");
}

}  // namespace firstshot
