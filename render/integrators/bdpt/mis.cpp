// MIS weights of bidirectional path tracing (power heuristic), from forward and reverse densities.
#include "render/integrators/bdpt/mis.h"

namespace firstshot {

namespace {

/// A density of 0 stands for a delta: it cancels in the ratios, so it counts 1.
float remap0(float p) { return p != 0.0f ? p : 1.0f; }

}  // namespace

float misWeight(const BdptDensities& densities, std::span<const SubpathVertex> light,
                std::span<const SubpathVertex> camera, int s, int t) {
  if (s + t == 2) return 1.0f;
  const SubpathVertex& pt = camera[size_t(t - 1)];
  const SubpathVertex* ptMinus = t > 1 ? &camera[size_t(t - 2)] : nullptr;
  const SubpathVertex* qs = s > 0 ? &light[size_t(s - 1)] : nullptr;
  const SubpathVertex* qsMinus = s > 1 ? &light[size_t(s - 2)] : nullptr;

  // Reverse densities of the connection vertices and their predecessors under this strategy.
  float ptRev = 0, ptMinusRev = 0, qsRev = 0, qsMinusRev = 0;
  if (qs) {
    ptRev = densities.pdf(qsMinus, *qs, pt);
    if (ptMinus) ptMinusRev = densities.pdf(qs, pt, *ptMinus);
    qsRev = densities.pdf(ptMinus, pt, *qs);
    if (qsMinus) qsMinusRev = densities.pdf(&pt, *qs, *qsMinus);
  } else {  // s = 0: pt lies on an area light, which could have emitted it
    SubpathVertex asLight = pt;
    asLight.kind = SubpathVertex::Kind::Light;
    asLight.light = densities.lightOf(pt);
    ptRev = densities.pdfOrigin(asLight);
    if (ptMinus) ptMinusRev = densities.pdf(nullptr, asLight, *ptMinus);
  }

  // Ratios p_i/p_s of the other strategies' densities to this one's, walked outwards from the
  // connection: more camera vertices sampled from the light side …
  float sum = 0, r = 1;
  for (int i = t - 1; i > 0; --i) {
    const float rev = i == t - 1 ? ptRev : i == t - 2 ? ptMinusRev : camera[size_t(i)].pdfRev;
    r *= remap0(rev) / remap0(camera[size_t(i)].pdfFwd);
    const bool delta = i == t - 1 ? false : camera[size_t(i)].delta;
    if (!delta && !camera[size_t(i - 1)].delta) sum += r * r;
  }
  // … and more light vertices sampled from the camera side (i = 0: the camera path meets the light).
  r = 1;
  for (int i = s - 1; i >= 0; --i) {
    const float rev = i == s - 1 ? qsRev : i == s - 2 ? qsMinusRev : light[size_t(i)].pdfRev;
    r *= remap0(rev) / remap0(light[size_t(i)].pdfFwd);
    const bool delta = i == s - 1 ? false : light[size_t(i)].delta;
    // i = 0: a camera subpath meeting the light, which no camera subpath does at an exit patch.
    const bool deltaBefore = i > 0 ? light[size_t(i - 1)].delta : light[0].deltaLight || light[0].exitPatch;
    if (!delta && !deltaBefore) sum += r * r;
  }
  return 1.0f / (1.0f + sum);
}

}  // namespace firstshot
