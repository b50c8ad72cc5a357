// The paths a luminaire's own lights make in bidirectional path tracing (luminaire_paths.h).
#include "render/integrators/bdpt/luminaire_paths.h"

namespace firstshot {

bool exitPatchesPath(const Luminaire& box, std::span<const SubpathVertex> light, int s,
                     std::span<const SubpathVertex> camera, int t) {
  enum class State { Inside, Scattered, Room, Left } state = State::Inside;
  // Left: out of the box after a non-delta vertex in it; joinable: the vertex before this one is the exit point or a
  // non-delta hit; hits: vertices past the box.
  bool joinable = true;
  int hits = 0;
  // Vertices in the light's order after the light's own; true once the path is the exit patches'.
  auto exitPatches = [&](const SubpathVertex& v) {
    const bool nonDelta = v.kind == SubpathVertex::Kind::Surface && !v.delta;
    switch (state) {
      case State::Inside:
      case State::Scattered:
        if (!box.contains(v.hit.p)) {  // convex: the path cannot come back in
          state = state == State::Scattered ? State::Left : State::Room;
          break;
        }
        if (nonDelta) state = State::Scattered;
        return false;
      case State::Room: return false;
      case State::Left: break;
    }
    if (state != State::Left) return false;
    if (v.kind == SubpathVertex::Kind::Camera) return joinable && hits > 0;  // the last hit joined to the pinhole
    if (joinable && nonDelta) return true;
    joinable = nonDelta;
    ++hits;
    return false;
  };
  for (int k = 1; k < s; ++k)
    if (exitPatches(light[size_t(k)])) return true;
  for (int k = s > 0 ? t - 1 : t - 2; k >= 0; --k)
    if (exitPatches(camera[size_t(k)])) return true;
  return false;
}

}  // namespace firstshot
