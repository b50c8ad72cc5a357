#pragma once
/// @file preprocessor.h
/// The preprocessing stage as a library: scene → patches → light samples → item buffers →
/// first-shot table (common/table/firstshot.h).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/scene/scene_desc.h"
#include "common/table/firstshot.h"
#include "common/util/comm.h"
#include "preprocess/luminaires.h"

namespace firstshot {

/// The settings a command line gives (firstshot-preprocess's options); each one not given leaves the
/// scene's. Fields as in FirstShotSettings (common/scene/scene_desc.h), of the same meaning.
struct SettingsOverrides {
  std::optional<int> resolution;                     ///< --resolution
  std::optional<std::string> window;                 ///< --window
  std::optional<std::string> backend;                ///< --backend
  std::optional<double> patchSize;                   ///< --patch-size
  std::optional<double> minPatchSize;                ///< --min-patch-size
  std::optional<double> refineTolerance;             ///< --refine-tolerance
  std::optional<double> lightPatchSize;              ///< --light-patch-size
  std::optional<double> lightTolerance;              ///< --light-tolerance
  std::optional<std::string> estimator;              ///< --estimator
  std::optional<uint64_t> rotationSeed;              ///< --seed
};

/// The preprocessor's settings, the one place they are put together: the scene's (scene.settings, a
/// FirstShotSettings: the file's values or the documented defaults), each one @p cli gives replaced by
/// it, then the automatic patch sizes resolved (common/patches/patch_size.h, resolvePatchSizes: patchSize 0 from
/// the scene's faces, minPatchSize 0 = patchSize/kDefaultRefineRatio, at most patchSize).
/// @throws InputError if the resolution is odd (the hemicube's side faces are R/2 high).
FirstShotSettings resolveSettings(const SceneDesc& scene, const SettingsOverrides& cli = {});

struct PreprocessOptions {
  /// resolution, window, backend, patch sizes, small-light rule (resolveSettings); automatic patch sizes
  /// left in them (0) are resolved by preprocessScene the same way
  FirstShotSettings settings;
  std::string gl = "osmesa";      ///< OpenGL back end for backend "gl": osmesa | egl
  int threads = 0;                ///< workers (0 = one per core); each has its own GL context
  bool quiet = true;              ///< no progress on stderr (common/util/progress.h; the tool: unless --quiet)
  double timeLimit = 0;           ///< seconds; 0 = none. Past it the run fails (nothing is written).
  /// The ranks sharing the work (common/util/comm.h; null: this process alone). Each rank shoots the
  /// light-sample tasks dealt to it; the factors are exchanged after every shooting pass, so every
  /// rank ends with the same table, byte for byte the one a single process makes.
  Comm* comm = nullptr;
  /// Refinement passes read the first pass's item buffers, brought up to each split
  /// (preprocess/kept_item_buffers.h), instead of re-tracing the pixels around split patches.
  /// Off: always re-trace (to compare the two).
  bool keepItemBuffers = true;
  /// GL back end: where the item buffers are reduced (preprocess/gl/gl_reduce.h): "cpu" (read back),
  /// "gpu" (compute shaders), "auto" (gpu unless GL_RENDERER is a software rasteriser: llvmpipe, softpipe).
  std::string glReduce = "auto";
  /// Luminaires (preprocess/luminaires.h): how they are found and how many particles each gets. Their lights leave
  /// the replaced lights (no light samples, no factors) and the table carries their exit distributions. Its quiet
  /// flag is replaced by the one above.
  LuminaireOptions luminaires;
};

struct PreprocessStats {
  size_t lightSamples = 0, patches = 0, nonZeros = 0;
  size_t smallLights = 0, largeLights = 0;
  double seconds = 0;
  double exchangeSeconds = 0;     ///< of them, spent exchanging factors between ranks
  uint64_t bytesSent = 0;         ///< factor bytes this rank sent to the others
  std::string renderer;           ///< e.g. "gl/osmesa (llvmpipe ...)" or "embree"
  std::vector<double> luminaireSeconds;  ///< per luminaire of the table, the time its exit distribution took
};

/// Options at the scene's settings: resolveSettings(scene) and the defaults of the rest (the library's
/// callers change fields on top; firstshot-preprocess passes its command line to resolveSettings).
PreprocessOptions defaultOptions(const SceneDesc& scene);

/// Computes the first-shot table of the scene's small lights. The result does not depend on the
/// number of threads. A scene without small lights gives a valid table with no samples.
/// @throws std::runtime_error if the item-buffer back end cannot start.
FirstShotTable preprocessScene(const SceneDesc& scene, const PreprocessOptions& options, PreprocessStats* stats = nullptr);

}  // namespace firstshot
