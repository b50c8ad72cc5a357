#pragma once
/// @file scene_memo.h
/// What integrators derive alike from one RenderScene and take long to build (the first-shot lighting, a light
/// sampler with its visibility factors), kept once built for the scene's lifetime: --integrator auto's pilot makes a
/// dozen integrators over one scene, and the render one more, each of which built them again (docs/integrators.md).
/// The products are deterministic functions of the scene and the key, so a kept one is the one a build would make.
/// The first-shot lighting's data is shared as it is (FirstShotLighting holds it by pointer); a light sampler, a
/// few MB, is copied out.
#include <memory>
#include <mutex>
#include <string>
#include <typeinfo>
#include <unordered_map>

namespace firstshot {

class SceneMemo {
 public:
  /// The product of type @p T kept under @p key, or null.
  template <class T>
  std::shared_ptr<const T> find(const std::string& key) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = items_.find(typed<T>(key));
    return it == items_.end() ? nullptr : std::static_pointer_cast<const T>(it->second);
  }
  /// Keeps @p product under @p key (replacing one kept there).
  template <class T>
  void keep(const std::string& key, std::shared_ptr<const T> product) {
    std::lock_guard<std::mutex> lock(mutex_);
    items_[typed<T>(key)] = std::move(product);
  }

 private:
  template <class T>
  static std::string typed(const std::string& key) {
    return std::string(typeid(T).name()) + '/' + key;
  }

  mutable std::mutex mutex_;
  std::unordered_map<std::string, std::shared_ptr<const void>> items_;
};

}  // namespace firstshot
