#pragma once
/// @file preprocessor.h
/// The preprocessing stage as a library: scene → patches → light samples → item buffers →
/// first-shot table (common/firstshot.h).
#include <cstdint>
#include <string>

#include "common/comm.h"
#include "common/firstshot.h"
#include "common/scene_desc.h"

namespace fs {

struct PreprocessOptions {
  FirstShotSettings settings;     ///< resolution, window, backend, patch sizes, small-light rule
  std::string gl = "osmesa";      ///< OpenGL back end for backend "gl": osmesa | egl
  int threads = 0;                ///< workers (0 = one per core); each has its own GL context
  bool quiet = true;              ///< no progress on stderr (common/progress.h; the tool: unless --quiet)
  double timeLimit = 0;           ///< seconds; 0 = none. Past it the run fails (nothing is written).
  /// The ranks sharing the work (common/comm.h; null: this process alone). Each rank shoots the
  /// light-sample tasks dealt to it; the factors are exchanged after every shooting pass, so every
  /// rank ends with the same table, byte for byte the one a single process makes.
  Comm* comm = nullptr;
  /// Refinement passes read the first pass's item buffers, brought up to each split
  /// (preprocess/kept_item_buffers.h), instead of re-tracing the pixels around split patches.
  /// Off: always re-trace (to compare the two).
  bool keepItemBuffers = true;
};

struct PreprocessStats {
  size_t lightSamples = 0, patches = 0, nonZeros = 0;
  size_t smallLights = 0, largeLights = 0;
  double seconds = 0;
  double exchangeSeconds = 0;     ///< of them, spent exchanging factors between ranks
  uint64_t bytesSent = 0;         ///< factor bytes this rank sent to the others
  std::string renderer;           ///< e.g. "gl/osmesa (llvmpipe ...)" or "embree"
};

/// min_patch_size when the scene does not give it: patch_size / this (adaptive refinement by up to
/// log2 of it levels).
constexpr double kDefaultRefineRatio = 16.0;

/// The smallest patch edge refinement may reach for coarse patches of @p patchSize (m): @p given if
/// positive (at most patchSize), else patchSize / kDefaultRefineRatio.
inline double minPatchSizeFor(double patchSize, double given) {
  return given > 0 ? (given < patchSize ? given : patchSize) : patchSize / kDefaultRefineRatio;
}

/// Options from the scene's settings (command-line values are applied on top by the caller).
PreprocessOptions defaultOptions(const SceneDesc& scene);

/// Computes the first-shot table of the scene's small lights. The result does not depend on the
/// number of threads. A scene without small lights gives a valid table with no samples.
/// @throws std::runtime_error if the item-buffer back end cannot start.
FirstShotTable preprocessScene(const SceneDesc& scene, const PreprocessOptions& options, PreprocessStats* stats = nullptr);

}  // namespace fs
