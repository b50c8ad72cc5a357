// The table of integrators: one line each (render/integrators/integrator_cli.h), and the factory that reads it.
#include "render/integrators/integrator.h"

#include <fmt/core.h>

#include "common/util/error.h"
#include "render/integrators/bdpt/cli.h"
#include "render/integrators/bundle/cli.h"
#include "render/integrators/integrator_cli.h"
#include "render/integrators/irradiance_cache/cli.h"
#include "render/integrators/light/cli.h"
#include "render/integrators/path/cli.h"

namespace firstshot {

namespace {

template <class Cli>
std::unique_ptr<IntegratorCli> makeCli() {
  return std::make_unique<Cli>();
}

}  // namespace

const std::vector<IntegratorEntry>& integratorTable() {
  static const std::vector<IntegratorEntry> table = {
      {"path", "", makeCli<PathCli>},
      {"irradiance-cache", "", makeCli<IrradianceCacheCli>},
      {"light", "light tracing, docs/light-tracing.md", makeCli<LightCli>},
      {"bundle", "ray-bundle stochastic iteration, docs/bundle.md", makeCli<BundleCli>},
      {"bdpt", "bidirectional path tracing, docs/bdpt.md", makeCli<BdptCli>},
  };
  return table;
}

const IntegratorEntry& integratorEntry(const std::string& name) {
  std::string names;
  for (const IntegratorEntry& e : integratorTable()) {
    if (name == e.name) return e;
    names += fmt::format("{}{}", names.empty() ? "" : ", ", e.name);
  }
  throw InputError("", "--integrator", fmt::format("unknown integrator \"{}\" (available: {})", name, names));
}

std::vector<std::string> integratorNames() {
  std::vector<std::string> names;
  for (const IntegratorEntry& e : integratorTable()) names.emplace_back(e.name);
  return names;
}

std::unique_ptr<Integrator> makeIntegrator(const std::string& name, const IntegratorOptions& options) {
  return integratorEntry(name).cli()->make(options);
}

}  // namespace firstshot
