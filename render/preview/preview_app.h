#pragma once
/// @file preview_app.h
/// `firstshot-render SCENE --preview`: an interactive window that shows the scene at once,
/// rasterised from the patch mesh and coloured by first-shot radiance, then refines it with the
/// chosen integrator (one sample per pixel per pass, on the CPU, in a background thread), with an
/// orbit/pan/dolly/fly camera and keys for the integrator, first-shot, overlays, exposure,
/// screenshots and the camera as JSON. See printKeys() for the controls.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "render/integrators/integrator.h"
#include "render/scene/render_scene.h"

namespace firstshot {

struct PreviewOptions {
  std::string integrator = "path";
  IntegratorOptions integratorOptions;
  /// Makes an integrator by name, configured like the offline render (keys 1..n switch between
  /// integratorNames()); empty: makeIntegrator(name, integratorOptions).
  std::function<std::unique_ptr<Integrator>(const std::string& name)> factory;
  uint64_t seed = 1;
  SamplerMode sampler = SamplerMode::Independent;  ///< the passes' samplers (RenderOptions::sampler, --sampler)
  int threads = 0;         ///< render threads; 0 = one per core
  int spp = 64;            ///< refinement stops at this many samples per pixel
  /// >= 0: scripted run: the instant picture, then this many refinement frames (one pass of
  /// 1 spp each, so the film equals an offline render with --spp frames), then the screenshot,
  /// then exit. < 0: interactive.
  int frames = -1;
  std::string screenshot;  ///< OUT.png: scripted runs save OUT.png and OUT.exr; P saves OUT-NNN.{png,exr}
  std::string windowGrab;  ///< scripted runs: the window's pixels as shown (8-bit PNG), for tests
  float exposure = 0.0f;   ///< stops
  bool quiet = false;
};

/// Opens the window and runs until it is closed (or until a scripted run is done).
/// @p scene is what the offline renderer would trace (with or without a first-shot table).
/// @return the exit code (0).
/// @throws std::runtime_error "--preview needs a display (...); use xvfb-run or render offline
///         with -o" when no window can be opened.
int runPreview(const RenderScene& scene, const PreviewOptions& options);

/// The key list printed at start and on H.
std::string previewKeyHelp();

/// The camera as a scene-file "camera" JSON object (exact: shortest round-trip decimals).
std::string cameraJson(const CameraDesc& camera);

}  // namespace firstshot
