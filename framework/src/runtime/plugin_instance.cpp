#include "shellflow/runtime/plugin_instance.hpp"

#include "shellflow/sdk/plugin.hpp"

namespace shellflow::runtime {

sdk::Context make_context(const Scene& scene, const PluginSpec& spec) {
  sdk::Context context;
  context.instance_name = spec.instance_name;
  context.scene_file = scene.file;
  context.gravity = scene.gravity;
  context.fps = scene.time.fps;
  return context;
}

namespace {
template <class T>
PluginInstance<T> create(const Scene& scene, const PluginSpec& spec) {
  ShellflowCreateError error{};
  const std::string params = spec.params.dump();
  const std::string context = sdk::context_to_json(make_context(scene, spec)).dump();
  void* object = spec.library->descriptor().create(params.c_str(), context.c_str(), &error);
  if (!object)
    throw SceneError(scene.file.string(), spec.json_path + error.json_path,
                     std::string(error.message) + " [plugin '" + spec.library->name() + "', " +
                         spec.library->file().string() + "]");
  return PluginInstance<T>(spec.library, static_cast<T*>(object), spec.instance_name);
}
}  // namespace

PluginInstance<sdk::SolidSolver> create_solid(const Scene& scene, const PluginSpec& spec) {
  return create<sdk::SolidSolver>(scene, spec);
}
PluginInstance<sdk::FluidSolver> create_fluid(const Scene& scene, const PluginSpec& spec) {
  return create<sdk::FluidSolver>(scene, spec);
}
PluginInstance<sdk::Writer> create_writer(const Scene& scene, const PluginSpec& spec) {
  return create<sdk::Writer>(scene, spec);
}

}  // namespace shellflow::runtime
