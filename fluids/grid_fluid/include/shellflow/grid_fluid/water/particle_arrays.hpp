#pragma once
// ParticleArrays: particles as flat arrays, one per coordinate (structure of arrays):
// positions [m], velocities [m/s] and radii [m]. What writers see of the spray and of the
// marker particles (sdk::ParticleView), and the spray's own storage.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "shellflow/sdk/fluid_solver.hpp"
#include "shellflow/sdk/state_buffer.hpp"

namespace shellflow::grid_fluid {

struct ParticleArrays {
  std::array<std::vector<double>, 3> position;
  std::array<std::vector<double>, 3> velocity;
  std::vector<double> radius;

  std::int64_t size() const { return static_cast<std::int64_t>(radius.size()); }
  Eigen::Vector3d x(std::int64_t i) const {
    return {position[0][i], position[1][i], position[2][i]};
  }
  Eigen::Vector3d u(std::int64_t i) const {
    return {velocity[0][i], velocity[1][i], velocity[2][i]};
  }
  void clear();
  void resize(std::int64_t n);
  void push_back(const Eigen::Vector3d& x, const Eigen::Vector3d& u, double r);
  /// Keeps the particles with keep[i] != 0, in order.
  void keep(const std::vector<std::uint8_t>& keep);
  /// A view named `name` of these arrays (valid until they change).
  sdk::ParticleView view(const std::string& name) const;

  void save(sdk::StateWriter& out) const;
  /// @throw Error when the saved arrays have different lengths.
  void restore(sdk::StateReader& in);
};

}  // namespace shellflow::grid_fluid
