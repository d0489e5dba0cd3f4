#pragma once
// Reading validated parameters in plugins.

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>

namespace shellflow::sdk {

/// A "vec3" parameter (validated by the schema as three finite numbers).
inline Eigen::Vector3d json_vec3(const nlohmann::json& j) {
  return Eigen::Vector3d(j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>());
}
inline Eigen::Vector3d json_vec3(const nlohmann::json& object, const std::string& key) {
  return json_vec3(object.at(key));
}

}  // namespace shellflow::sdk
