// IES LM-63 photometric files (common/lights/ies.h).
#include "common/lights/ies.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string_view>

#include "common/util/error.h"

namespace firstshot {
namespace {

constexpr double kDeg = kPi / 180.0;
constexpr size_t kMaxAngles = 100000;         ///< per direction
constexpr size_t kMaxValues = size_t(1) << 20;  ///< candela values in the file (real files: ~65,000 at most)

struct Token {
  std::string_view text;
  int line = 0;
};

/// The numbers after the TILT line, one by one, with their line numbers for messages.
class Numbers {
 public:
  Numbers(std::vector<Token> tokens, std::string file, int lastLine)
      : tokens_(std::move(tokens)), file_(std::move(file)), lastLine_(lastLine) {}
  [[noreturn]] void fail(int line, const std::string& msg) const {
    throw InputError(file_, "line " + std::to_string(line), msg);
  }
  int line() const { return next_ < tokens_.size() ? tokens_[next_].line : lastLine_; }
  double next(const std::string& what) {
    if (next_ >= tokens_.size()) fail(lastLine_, "file ends early: expected " + what);
    const Token& t = tokens_[next_++];
    const std::string s(t.text);
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0') fail(t.line, "expected a number for " + what + ", got \"" + s + "\"");
    if (!std::isfinite(v)) fail(t.line, what + " is not finite (" + s + ")");
    return v;
  }
  /// A count in [lo, hi], written as an integer.
  size_t count(const std::string& what, size_t lo, size_t hi) {
    const int l = line();
    const double v = next(what);
    if (v != std::floor(v) || v < double(lo) || v > double(hi))
      fail(l, what + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return size_t(v);
  }
  bool done() const { return next_ >= tokens_.size(); }

 private:
  std::vector<Token> tokens_;
  std::string file_;
  int lastLine_;
  size_t next_ = 0;
};

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::string upper(std::string_view s) {
  std::string u(s);
  for (char& c : u) c = char(std::toupper(static_cast<unsigned char>(c)));
  return u;
}

/// i with grid[i] ≤ x ≤ grid[i + 1], clamped to [0, n − 2] (n ≥ 2).
size_t interval(const std::vector<double>& grid, double x) {
  const size_t i = size_t(std::upper_bound(grid.begin(), grid.end(), x) - grid.begin());
  return std::min(i == 0 ? 0 : i - 1, grid.size() - 2);
}

/// Linear interpolation of column values @p col (over angles @p h) at @p x; a single column is constant.
double interpolate(const std::vector<double>& h, const std::vector<double>& col, size_t nv, size_t v, double x) {
  if (h.size() == 1) return col[v];
  const size_t j = interval(h, x);
  const double t = std::clamp((x - h[j]) / (h[j + 1] - h[j]), 0.0, 1.0);
  return (1 - t) * col[j * nv + v] + t * col[(j + 1) * nv + v];
}

/// ∫ w0(x) g(x) dx and ∫ w1(x) g(x) dx over [x0, x1] (radians) for the linear hat functions
/// w0 = (x1 − x)/Δ, w1 = (x − x0)/Δ and g = sin (@p useSin) or cos.
void moments(double x0, double x1, bool useSin, double& i0, double& i1) {
  const double S = useSin ? std::cos(x0) - std::cos(x1) : std::sin(x1) - std::sin(x0);
  const double M = useSin ? (std::sin(x1) - x1 * std::cos(x1)) - (std::sin(x0) - x0 * std::cos(x0))
                          : (std::cos(x1) + x1 * std::sin(x1)) - (std::cos(x0) + x0 * std::sin(x0));
  const double d = x1 - x0;
  i1 = (M - x0 * S) / d;
  i0 = S - i1;
}

/// Expands the file's horizontal angles to the full range their symmetry implies (common/lights/ies.h).
void expandHorizontal(IesData& d, const std::vector<double>& h, const std::vector<double>& values, Numbers& in, int line) {
  const size_t nv = d.vertical.size();
  std::vector<double> nodes;
  double (*fold)(double) = [](double x) { return x; };
  const double first = h.front(), last = h.back();
  if (d.type == IesType::C) {
    if (first < 0 || last > 360) in.fail(line, "type C horizontal angles must lie in [0, 360]");
    if (h.size() == 1) {  // axial symmetry
      nodes = {0.0, 360.0};
      fold = [](double) { return 0.0; };
    } else if (first == 0 && last == 90) {  // quadrant symmetry
      for (double x : h) nodes.insert(nodes.end(), {x, 180 - x, 180 + x, 360 - x});
      fold = [](double x) { return x <= 90 ? x : x <= 180 ? 180 - x : x <= 270 ? x - 180 : 360 - x; };
    } else if (first == 0 && last == 180) {  // bilateral about the 0–180 plane
      for (double x : h) nodes.insert(nodes.end(), {x, 360 - x});
      fold = [](double x) { return x <= 180 ? x : 360 - x; };
    } else if (first == 90 && last == 270) {  // bilateral about the 90–270 plane
      for (double x : h) nodes.insert(nodes.end(), {x, 180 - x, 540 - x});  // those in [0, 360]
      fold = [](double x) { return x < 90 ? 180 - x : x > 270 ? 540 - x : x; };
    } else if (first == 0 && last > 180) {  // full; the 360° column repeats 0° if missing
      nodes = h;
      if (last < 360) nodes.push_back(360.0);
      fold = [](double x) { return x >= 360 ? 0.0 : x; };
    } else {
      in.fail(line, "unsupported type C horizontal angle range [" + std::to_string(first) + ", " +
                        std::to_string(last) + "] (0, 0–90, 0–180, 90–270, 0–360)");
    }
  } else {
    if (h.size() < 2) in.fail(line, "types A and B need at least 2 horizontal angles");
    if (first < -90 || last > 90) in.fail(line, "type A/B horizontal angles must lie in [−90, 90]");
    if (first == 0) {  // lateral symmetry
      for (double x : h) nodes.insert(nodes.end(), {x, -x});
      fold = [](double x) { return std::abs(x); };
    } else {
      nodes = h;
    }
  }
  if (d.type == IesType::C)
    nodes.erase(std::remove_if(nodes.begin(), nodes.end(), [](double x) { return x < 0 || x > 360; }), nodes.end());
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }),
              nodes.end());
  d.horizontal = nodes;
  d.candela.resize(nodes.size() * nv);
  for (size_t j = 0; j < nodes.size(); ++j)
    for (size_t v = 0; v < nv; ++v) d.candela[j * nv + v] = interpolate(h, values, nv, v, fold(nodes[j]));
}

/// The largest corner of table cell (i, j), cd.
double cellMax(const IesData& d, size_t i, size_t j) {
  const size_t nv = d.vertical.size();
  return std::max({d.candela[j * nv + i], d.candela[j * nv + i + 1], d.candela[(j + 1) * nv + i],
                   d.candela[(j + 1) * nv + i + 1]});
}

/// Solid angle of table cell (i, j), sr.
double cellSolidAngle(const IesData& d, size_t i, size_t j) {
  const double v0 = d.vertical[i] * kDeg, v1 = d.vertical[i + 1] * kDeg;
  const double h0 = d.horizontal[j] * kDeg, h1 = d.horizontal[j + 1] * kDeg;
  switch (d.type) {
    case IesType::C: return (std::cos(v0) - std::cos(v1)) * (h1 - h0);
    case IesType::A: return (std::sin(v1) - std::sin(v0)) * (h1 - h0);
    case IesType::B: return (std::sin(h1) - std::sin(h0)) * (v1 - v0);
  }
  return 0;
}

/// The exact integral of the bilinear table over the sphere (flux), and the sampling distribution.
void integrate(IesData& d) {
  const size_t nv = d.vertical.size(), nh = d.horizontal.size();
  auto f = [&](size_t i, size_t j) { return d.candela[j * nv + i]; };
  d.flux = 0;
  std::vector<double> cellWeights;
  for (size_t i = 0; i + 1 < nv; ++i)
    for (size_t j = 0; j + 1 < nh; ++j) {
      const double v0 = d.vertical[i] * kDeg, v1 = d.vertical[i + 1] * kDeg;
      const double h0 = d.horizontal[j] * kDeg, h1 = d.horizontal[j + 1] * kDeg;
      double a0, a1;
      if (d.type == IesType::B) {  // dω = cos H dH dV
        moments(h0, h1, false, a0, a1);
        d.flux += 0.5 * (v1 - v0) * (a0 * (f(i, j) + f(i + 1, j)) + a1 * (f(i, j + 1) + f(i + 1, j + 1)));
      } else {  // C: dω = sin V dV dH; A: cos V dV dH
        moments(v0, v1, d.type == IesType::C, a0, a1);
        d.flux += 0.5 * (h1 - h0) * (a0 * (f(i, j) + f(i, j + 1)) + a1 * (f(i + 1, j) + f(i + 1, j + 1)));
      }
      cellWeights.push_back(cellMax(d, i, j) * cellSolidAngle(d, i, j));
    }
  d.cells = Distribution1D(cellWeights);
}

}  // namespace

IesData parseIes(const std::string& text, const std::string& file) {
  if (text.size() > kMaxIesBytes) throw InputError(file, "", "file larger than " + std::to_string(kMaxIesBytes) + " bytes");
  // Header lines (IESNA:LM-63-…, [KEYWORD] …) up to the TILT line, then free-form numbers.
  std::vector<Token> tokens;
  int line = 0, tiltLine = 0;
  size_t pos = 0;
  while (pos < text.size() || line == 0) {
    const size_t end = std::min(text.find('\n', pos), text.size());
    const std::string_view l(text.data() + pos, end - pos);
    ++line;
    pos = end + 1;
    if (tiltLine == 0) {
      const std::string_view t = trim(l);
      if (upper(t.substr(0, 5)) != "TILT=") {
        if (pos >= text.size()) break;
        continue;
      }
      tiltLine = line;
      const std::string tilt = upper(trim(t.substr(5)));
      if (tilt != "NONE")
        throw InputError(file, "line " + std::to_string(line),
                         "TILT=" + std::string(trim(t.substr(5))) + " is unsupported (only TILT=NONE)");
    } else {
      size_t k = 0;
      while (k < l.size()) {
        while (k < l.size() && (std::isspace(static_cast<unsigned char>(l[k])) || l[k] == ',')) ++k;
        const size_t s = k;
        while (k < l.size() && !std::isspace(static_cast<unsigned char>(l[k])) && l[k] != ',') ++k;
        if (k > s) tokens.push_back({l.substr(s, k - s), line});
      }
    }
    if (pos >= text.size()) break;
  }
  if (tiltLine == 0) throw InputError(file, "line " + std::to_string(line), "no TILT= line (not an IES LM-63 file?)");
  Numbers in(std::move(tokens), file, line);

  IesData d;
  d.file = file;
  int l = in.line();
  d.lamps = in.next("number of lamps");
  if (!(d.lamps > 0)) in.fail(l, "number of lamps must be positive");
  l = in.line();
  d.lumensPerLamp = in.next("lumens per lamp");
  if (!(d.lumensPerLamp > 0 || d.lumensPerLamp == -1)) in.fail(l, "lumens per lamp must be positive or −1 (absolute)");
  l = in.line();
  const double multiplier = in.next("candela multiplier");
  if (!(multiplier > 0)) in.fail(l, "candela multiplier must be positive");
  const size_t nv = in.count("number of vertical angles", 2, kMaxAngles);
  const size_t nh = in.count("number of horizontal angles", 1, kMaxAngles);
  if (nv * nh > kMaxValues) in.fail(in.line(), "too many candela values (" + std::to_string(nv * nh) + ")");
  d.type = IesType(in.count("photometric type", 1, 3));
  in.count("units type", 1, 2);
  for (const char* what : {"width", "length", "height"}) in.next(what);
  l = in.line();
  const double ballast = in.next("ballast factor");
  if (!(ballast > 0)) in.fail(l, "ballast factor must be positive");
  in.next("ballast-lamp photometric factor");  // LM-63-1995; "future use" since 2002
  in.next("input watts");

  auto angles = [&](size_t n, const std::string& what, double lo, double hi) {
    std::vector<double> a(n);
    for (size_t k = 0; k < n; ++k) {
      const int at = in.line();
      a[k] = in.next(what + " angle " + std::to_string(k + 1));
      if (a[k] < lo || a[k] > hi)
        in.fail(at, what + " angle " + std::to_string(a[k]) + " outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
      if (k > 0 && !(a[k] > a[k - 1])) in.fail(at, what + " angles must increase strictly");
    }
    return a;
  };
  const bool c = d.type == IesType::C;
  d.vertical = angles(nv, "vertical", c ? 0 : -90, c ? 180 : 90);
  const int hLine = in.line();
  const std::vector<double> h = angles(nh, "horizontal", c ? 0 : -90, c ? 360 : 90);
  std::vector<double> values(nv * nh);
  for (size_t j = 0; j < nh; ++j)
    for (size_t v = 0; v < nv; ++v) {
      const int at = in.line();
      const double x = in.next("candela value " + std::to_string(j * nv + v + 1));
      if (x < 0) in.fail(at, "negative candela value");
      values[j * nv + v] = x * multiplier * ballast;
      if (!std::isfinite(values[j * nv + v]) || values[j * nv + v] > 1e15) in.fail(at, "candela value too large");
      d.maxCandela = std::max(d.maxCandela, values[j * nv + v]);
    }
  if (!in.done()) in.fail(in.line(), "unexpected data after the candela values (wrong angle counts?)");
  expandHorizontal(d, h, values, in, hLine);
  integrate(d);
  if (!(d.maxCandela > 0) || !(d.flux > 0)) in.fail(tiltLine, "all candela values are zero");
  return d;
}

std::shared_ptr<const IesData> loadIes(const std::string& file) {
  std::ifstream f(file, std::ios::binary);
  if (!f) throw InputError(file, "", "cannot open the photometric file");
  f.seekg(0, std::ios::end);
  const std::streamoff size = f.tellg();
  if (size < 0 || size_t(size) > kMaxIesBytes)
    throw InputError(file, "", "file larger than " + std::to_string(kMaxIesBytes) + " bytes (or unreadable)");
  f.seekg(0);
  std::string text(size_t(size), '\0');
  if (!f.read(text.data(), size)) throw InputError(file, "", "cannot read the photometric file");
  return std::make_shared<const IesData>(parseIes(text, file));
}

void IesData::angles(const Vec3d& d, double& v, double& h) const {
  switch (type) {
    case IesType::C:
      v = std::acos(std::clamp(d.z, -1.0, 1.0)) / kDeg;
      h = std::atan2(d.y, d.x) / kDeg;
      if (h < 0) h += 360;
      break;
    case IesType::A:
      v = std::asin(std::clamp(d.y, -1.0, 1.0)) / kDeg;
      h = std::atan2(d.x, d.z) / kDeg;
      break;
    case IesType::B:
      h = std::asin(std::clamp(d.x, -1.0, 1.0)) / kDeg;
      v = std::atan2(d.y, d.z) / kDeg;
      break;
  }
}

double IesData::value(double v, double h) const {
  if (type == IesType::C) {
    h = std::fmod(h, 360.0);
    if (h < 0) h += 360;
  }
  if (!(v >= vertical.front() && v <= vertical.back() && h >= horizontal.front() && h <= horizontal.back())) return 0;
  const size_t nv = vertical.size(), i = interval(vertical, v), j = interval(horizontal, h);
  const double s = std::clamp((v - vertical[i]) / (vertical[i + 1] - vertical[i]), 0.0, 1.0);
  const double t = std::clamp((h - horizontal[j]) / (horizontal[j + 1] - horizontal[j]), 0.0, 1.0);
  return (1 - t) * ((1 - s) * candela[j * nv + i] + s * candela[j * nv + i + 1]) +
         t * ((1 - s) * candela[(j + 1) * nv + i] + s * candela[(j + 1) * nv + i + 1]);
}

double IesData::valueLocal(const Vec3d& d) const {
  double v = 0, h = 0;
  angles(d, v, h);
  return value(v, h);
}

Vec3d IesData::sampleLocal(double u0, double u2, double& pdf) const {
  pdf = 0;
  if (cells.empty() || !(cells.total() > 0)) return Vec3d(0, 0, 1);
  double u1 = 0;  // the rest of u0 inside the cell's CDF interval
  const size_t k = cells.sampleDiscrete(u0, &u1);
  const size_t nh = horizontal.size(), i = k / (nh - 1), j = k % (nh - 1);
  pdf = cellMax(*this, i, j) / cells.total();
  const double v0 = vertical[i] * kDeg, v1 = vertical[i + 1] * kDeg;
  const double h0 = horizontal[j] * kDeg, h1 = horizontal[j + 1] * kDeg;
  switch (type) {
    case IesType::C: {
      const double cv = std::cos(v0) + u1 * (std::cos(v1) - std::cos(v0)), sv = std::sqrt(std::max(0.0, 1 - cv * cv));
      const double h = h0 + u2 * (h1 - h0);
      return {sv * std::cos(h), sv * std::sin(h), cv};
    }
    case IesType::A: {
      const double sv = std::sin(v0) + u1 * (std::sin(v1) - std::sin(v0)), cv = std::sqrt(std::max(0.0, 1 - sv * sv));
      const double h = h0 + u2 * (h1 - h0);
      return {cv * std::sin(h), sv, cv * std::cos(h)};
    }
    case IesType::B: {
      const double sh = std::sin(h0) + u1 * (std::sin(h1) - std::sin(h0)), ch = std::sqrt(std::max(0.0, 1 - sh * sh));
      const double v = v0 + u2 * (v1 - v0);
      return {sh, ch * std::sin(v), ch * std::cos(v)};
    }
  }
  return Vec3d(0, 0, 1);
}

double IesData::pdfLocal(const Vec3d& d) const {
  if (!(cells.total() > 0)) return 0;
  double v = 0, h = 0;
  angles(d, v, h);
  if (!(v >= vertical.front() && v <= vertical.back() && h >= horizontal.front() && h <= horizontal.back())) return 0;
  return cellMax(*this, interval(vertical, v), interval(horizontal, h)) / cells.total();
}

}  // namespace firstshot
