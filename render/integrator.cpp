// The integrator factory.
#include "render/integrator.h"

#include "common/error.h"
#include "render/integrators/bdpt/integrator.h"
#include "render/integrators/bundle/integrator.h"
#include "render/integrators/irradiance_cache/integrator.h"
#include "render/integrators/light/light_tracer.h"
#include "render/integrators/path.h"

namespace fs {

std::vector<std::string> integratorNames() { return {"path", "irradiance-cache", "light", "bundle", "bdpt"}; }

std::unique_ptr<Integrator> makeIntegrator(const std::string& name, const IntegratorOptions& options) {
  if (name == "path") return std::make_unique<PathIntegrator>(options);
  if (name == "irradiance-cache") return std::make_unique<IrradianceCacheIntegrator>(options);
  if (name == "light") return std::make_unique<LightTracingIntegrator>(options);
  if (name == "bundle") return std::make_unique<BundleIntegrator>(options);
  if (name == "bdpt") return std::make_unique<BdptIntegrator>(options);
  throw InputError("", "--integrator", "unknown integrator \"" + name + "\" (available: path, irradiance-cache, light, bundle, bdpt)");
}

}  // namespace fs
