#pragma once
/// @file integrator_cli.h
/// An integrator's command line, and the table of integrators: each integrator declares
/// the options only it has (name, help, checks, defaults), says which of the options shared by
/// several integrators (those that set IntegratorOptions, declared once by the tool in
/// render/cli/integrator_options.h) it reads, checks the values given and makes itself with them.
/// firstshot-render refuses an option the chosen integrator does not read. The table
/// (integratorTable(), render/integrators/integrator.cpp) has one line per integrator; makeIntegrator() and
/// integratorNames() (render/integrators/integrator.h) read it too. The implementations live in the
/// integrators' folders (cli.h there) and use CLI11; this header does not need it.
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common/scene/scene_desc.h"
#include "render/integrators/integrator.h"

namespace CLI {
class App;
}

namespace firstshot {

class Film;

/// The names of the options that set IntegratorOptions, for IntegratorCli::shared().
namespace integrator_option {
inline constexpr const char* kPrimary = "--primary";                  ///< IntegratorOptions::primary
inline constexpr const char* kLightSampler = "--light-sampler";       ///< IntegratorOptions::lightSampler
inline constexpr const char* kPatchNee = "--patch-nee";               ///< IntegratorOptions::patchNee
inline constexpr const char* kLightVisibility = "--light-visibility"; ///< IntegratorOptions::lightVisibility
inline constexpr const char* kTableVisibility = "--table-visibility"; ///< IntegratorOptions::tableVisibility
inline constexpr const char* kShootFirstShot = "--shoot-firstshot";   ///< IntegratorOptions::shootFromPatches
inline constexpr const char* kLuminaires = "--luminaires";           ///< IntegratorOptions::luminaires
inline constexpr const char* kEmitterChoice = "--emitter-choice";   ///< IntegratorOptions::cameraEmitterChoice
}  // namespace integrator_option

/// What the tool has resolved when the chosen integrator's options are checked (IntegratorCli::configure).
struct IntegratorSetup {
  const CLI::App* app = nullptr;     ///< the parsed command line (which options were given)
  const SceneDesc* scene = nullptr;  ///< the loaded scene, its camera resized by --width/--height
  uint64_t seed = 0;                 ///< --seed, or the scene's settings.seed
  int threads = 0;                   ///< --threads (0: one per core)
  int spp = 0;                       ///< --spp (0: the scene's); an integrator may set it (--iterations)
  SamplerMode sampler = SamplerMode::Independent;  ///< --sampler (common/sampling/rng.h)
  bool quiet = false;                ///< --quiet (or a pilot render, render/loop/integrator_pilot.h): no progress
};

/// One integrator's command line. Before configure() (and without a command line: makeIntegrator)
/// make() gives the integrator with its default settings.
class IntegratorCli {
 public:
  virtual ~IntegratorCli() = default;
  /// Declares the options only this integrator has on @p app (default: none).
  virtual void add(CLI::App& /*app*/) {}
  /// Checks the values of its options given on the command line and keeps them for make().
  /// @throws InputError naming the option at fault.
  virtual void configure(IntegratorSetup& /*setup*/) {}
  /// The integrator with @p options and the settings configure() kept. Callable more than once (the preview).
  virtual std::unique_ptr<Integrator> make(const IntegratorOptions& options) const = 0;
  /// After the render (@p film: its image, null in sensor mode; @p renderSeconds: its time, s): writes
  /// the integrator's own outputs and prints its summary unless @p quiet. Default: nothing.
  virtual void finish(const Integrator& /*integrator*/, const Film* /*film*/, float /*exposure*/,
                      double /*renderSeconds*/, bool /*quiet*/) const {}
  /// A file the integrator reads whose contents change the image (the checkpoint key hashes it); empty: none.
  virtual std::string inputFile() const { return {}; }
  /// Without a first-shot table and --patch-size: true if the integrator needs the scene cut into
  /// patches as the preprocessor would (the bundle's elements), false to keep the faces whole.
  virtual bool needsPatches() const { return false; }
  /// An integrator whose preprocessing gathers per record (the irradiance cache): its hemisphere rays per record, or
  /// 0 for the others.
  virtual int recordSamples() const { return 0; }
  /// Sets them to @p samples unless the command line gave them (`--integrator auto` sizes them to a render's budget,
  /// a resumed render takes its checkpoint's). Default: nothing.
  virtual void setRecordSamples(int /*samples*/) {}

  /// Every option it reads: the shared ones (shared()), then its own (add()).
  std::vector<std::string> options() const {
    std::vector<std::string> all = shared();
    all.insert(all.end(), own_.begin(), own_.end());
    return all;
  }

 protected:
  /// The options that set IntegratorOptions (integrator_option::k...) that this integrator reads.
  virtual std::vector<std::string> shared() const = 0;
  std::vector<std::string> own_;  ///< the names of the options add() declared
};

/// The command line of an integrator @p I that has no options of its own (the path tracer, BDPT):
/// it reads the shared options named in its constructor and makes an I with them.
template <class I>
class SharedOptionsCli : public IntegratorCli {
 public:
  /// @p shared: the shared options (integrator_option::k...) that I reads.
  explicit SharedOptionsCli(std::vector<std::string> shared) : shared_(std::move(shared)) {}
  std::unique_ptr<Integrator> make(const IntegratorOptions& options) const override {
    return std::make_unique<I>(options);
  }

 protected:
  std::vector<std::string> shared() const override { return shared_; }

 private:
  std::vector<std::string> shared_;
};

/// One line of the table of integrators.
struct IntegratorEntry {
  const char* name;         ///< --integrator NAME
  const char* description;  ///< for --help: what it is and where it is documented (empty: the name says it)
  /// A fresh command line of the integrator.
  std::unique_ptr<IntegratorCli> (*cli)();
};

/// The integrators, in the order --help lists them and the preview offers them (keys 1, 2, ...).
const std::vector<IntegratorEntry>& integratorTable();

/// The entry named @p name. @throws InputError (--integrator) for an unknown name.
const IntegratorEntry& integratorEntry(const std::string& name);

}  // namespace firstshot
