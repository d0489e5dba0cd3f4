#pragma once
// What every plugin instance is told about the scene it lives in, besides its own params.

#include <Eigen/Core>
#include <filesystem>
#include <string>

namespace shellflow::sdk {

struct Context {
  std::string instance_name;         ///< the scene's "name" for this plugin instance
  std::filesystem::path scene_file;  ///< absolute path of the scene file
  Eigen::Vector3d gravity{0.0, -9.81, 0.0};  ///< scene /gravity [m/s^2]
  double fps = 24.0;                 ///< scene /time/fps
};

}  // namespace shellflow::sdk
