#include "shellflow/sdk/context.hpp"

#include "shellflow/sdk/plugin.hpp"

namespace shellflow::sdk {

nlohmann::json context_to_json(const Context& c) {
  return {{"instance_name", c.instance_name},
          {"scene_file", c.scene_file.string()},
          {"gravity", {c.gravity.x(), c.gravity.y(), c.gravity.z()}},
          {"fps", c.fps}};
}

Context context_from_json(const nlohmann::json& j) {
  Context c;
  c.instance_name = j.at("instance_name").get<std::string>();
  c.scene_file = j.at("scene_file").get<std::string>();
  const auto g = j.at("gravity").get<std::vector<double>>();
  c.gravity = Eigen::Vector3d(g.at(0), g.at(1), g.at(2));
  c.fps = j.at("fps").get<double>();
  return c;
}

}  // namespace shellflow::sdk
