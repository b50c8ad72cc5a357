#pragma once
/// @file path_recorder.h
/// An optional observer of the path walk (path_walk.h): each amount the walk adds to a camera sample's radiance,
/// told apart by the path length at which it arrives and by what brought it, so that a report
/// (bench/variance_by_depth.cpp) can split an image's mean and variance by those. The walk reads the calling
/// thread's recorder once per trace() and records nothing when it is null, the default: rendering without a
/// recorder does the same arithmetic as before and makes the same images.
#include "common/util/math.h"

namespace firstshot {

/// What one contribution to a path's radiance came from.
enum class PathTerm : int {
  LargeLightHit,  ///< a kept emitter (an area light the table does not replace) met by the camera ray or a BSDF sample
  SmallLightHit,  ///< a replaced (small) emitter met: seen by the camera, after a delta bounce, or where NEE took it
  LargeLightNee,  ///< next-event estimation to a kept light
  SmallLightNee,  ///< next-event estimation to a replaced light: its direct term where the table is not used
  TableHit,       ///< the first-shot term of the lit patch a vertex lies on (the patch met as an emitter)
  PatchNee,       ///< patch NEE: a point of a lit patch sampled as an emitter of its first-shot radiance
  Environment,    ///< the infinite light (a sky or an environment map): met by an escaping ray or by NEE
  ExitHit,        ///< a luminaire's exit light, met where a BSDF-sampled segment enters its box
  Count
};

/// A short name of @p t for tables ("patch-nee", …).
inline const char* pathTermName(PathTerm t) {
  switch (t) {
    case PathTerm::LargeLightHit: return "large-light-hit";
    case PathTerm::SmallLightHit: return "small-light-hit";
    case PathTerm::LargeLightNee: return "large-light-nee";
    case PathTerm::SmallLightNee: return "small-light-nee";
    case PathTerm::TableHit: return "table-hit";
    case PathTerm::PatchNee: return "patch-nee";
    case PathTerm::Environment: return "environment";
    case PathTerm::ExitHit: return "exit-hit";
    case PathTerm::Count: break;
  }
  return "?";
}

/// What the light passed between its emitter and the path's first non-delta vertex (in the camera's order: the
/// first surface whose BSDF the camera's view takes). Delta vertices before that one (a scene seen in a mirror or
/// through glass) do not count: they do not make the light harder to find.
enum class PathVia : int {
  Direct,  ///< only Lambertian vertices (and panes crossed)
  Glossy,  ///< a glossy vertex (neither Lambertian nor delta: a rough conductor, pbr, rough glass), no delta one
  Delta,   ///< a delta vertex (a mirror, glass, a pane's reflection): a caustic
  Count
};

/// A short name of @p v for tables.
inline const char* pathViaName(PathVia v) {
  switch (v) {
    case PathVia::Direct: return "direct";
    case PathVia::Glossy: return "glossy";
    case PathVia::Delta: return "caustic";
    case PathVia::Count: break;
  }
  return "?";
}

/// Receives every amount the walk adds to a path's radiance L, in the order it adds them.
class PathRecorder {
 public:
  virtual ~PathRecorder() = default;
  /// @p value (W/(m² sr), the throughput included) was added to L. @p bounces: the light's scattering events
  /// between its emitter and the camera (0: an emitter seen directly; 1: direct light at the first hit; the first
  /// shot's reflection on a lit patch counts as one, so a table term at the first hit is 1 and patch NEE there
  /// is 2). @p via: what the light passed on its way (PathVia).
  virtual void record(int bounces, PathTerm term, PathVia via, const Color& value) = 0;
};

/// The calling thread's recorder (null, the default: none). The walk reads it once at the start of each trace().
inline PathRecorder*& threadPathRecorder() {
  thread_local PathRecorder* recorder = nullptr;
  return recorder;
}

}  // namespace firstshot
