#pragma once
// An object created inside a plugin, destroyed by the same plugin, and keeping the
// plugin's library loaded for as long as it lives.

#include <memory>
#include <string>

#include "shellflow/runtime/scene.hpp"
#include "shellflow/sdk/context.hpp"
#include "shellflow/sdk/fluid_solver.hpp"
#include "shellflow/sdk/solid_solver.hpp"
#include "shellflow/sdk/writer.hpp"

namespace shellflow::runtime {

template <class T>
class PluginInstance {
 public:
  PluginInstance() = default;
  PluginInstance(std::shared_ptr<PluginLibrary> library, T* object, std::string name)
      : m_library(std::move(library)), m_object(object), m_name(std::move(name)) {}
  PluginInstance(PluginInstance&& o) noexcept { *this = std::move(o); }
  PluginInstance& operator=(PluginInstance&& o) noexcept {
    reset();
    m_library = std::move(o.m_library);
    m_object = o.m_object;
    m_name = std::move(o.m_name);
    o.m_object = nullptr;
    return *this;
  }
  PluginInstance(const PluginInstance&) = delete;
  PluginInstance& operator=(const PluginInstance&) = delete;
  ~PluginInstance() { reset(); }

  T* get() const { return m_object; }
  T* operator->() const { return m_object; }
  T& operator*() const { return *m_object; }
  explicit operator bool() const { return m_object != nullptr; }
  const std::string& name() const { return m_name; }
  const PluginLibrary& library() const { return *m_library; }

 private:
  void reset() {
    if (m_object) m_library->descriptor().destroy(static_cast<void*>(m_object));
    m_object = nullptr;
  }
  std::shared_ptr<PluginLibrary> m_library;
  T* m_object = nullptr;
  std::string m_name;
};

/// Creates the instance a scene entry describes.
/// @throw SceneError naming the scene file and the JSON path of the offending value.
PluginInstance<sdk::SolidSolver> create_solid(const Scene& scene, const PluginSpec& spec);
PluginInstance<sdk::FluidSolver> create_fluid(const Scene& scene, const PluginSpec& spec);
PluginInstance<sdk::Writer> create_writer(const Scene& scene, const PluginSpec& spec);

/// The context every plugin of `scene` is given.
sdk::Context make_context(const Scene& scene, const PluginSpec& spec);

}  // namespace shellflow::runtime
