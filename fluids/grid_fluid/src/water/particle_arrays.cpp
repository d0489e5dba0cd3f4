#include "shellflow/grid_fluid/water/particle_arrays.hpp"

#include "shellflow/sdk/error.hpp"

namespace shellflow::grid_fluid {

void ParticleArrays::clear() {
  resize(0);
}

void ParticleArrays::resize(std::int64_t n) {
  for (int a = 0; a < 3; ++a) {
    position[a].resize(n);
    velocity[a].resize(n);
  }
  radius.resize(n);
}

void ParticleArrays::push_back(const Eigen::Vector3d& x, const Eigen::Vector3d& u, double r) {
  for (int a = 0; a < 3; ++a) {
    position[a].push_back(x[a]);
    velocity[a].push_back(u[a]);
  }
  radius.push_back(r);
}

void ParticleArrays::keep(const std::vector<std::uint8_t>& keep) {
  size_t out = 0;
  for (size_t i = 0; i < radius.size(); ++i) {
    if (keep[i] == 0) continue;
    for (int a = 0; a < 3; ++a) {
      position[a][out] = position[a][i];
      velocity[a][out] = velocity[a][i];
    }
    radius[out] = radius[i];
    ++out;
  }
  resize(static_cast<std::int64_t>(out));
}

sdk::ParticleView ParticleArrays::view(const std::string& name) const {
  sdk::ParticleView v;
  v.name = name;
  v.count = size();
  for (int a = 0; a < 3; ++a) {
    v.position[a] = position[a].data();
    v.velocity[a] = velocity[a].data();
  }
  v.radius = radius.data();
  return v;
}

void ParticleArrays::save(sdk::StateWriter& out) const {
  const auto write = [&](const std::vector<double>& v) {
    out.write_column(v.data(), static_cast<std::int64_t>(v.size()));
  };
  for (int a = 0; a < 3; ++a) write(position[a]);
  for (int a = 0; a < 3; ++a) write(velocity[a]);
  write(radius);
}

void ParticleArrays::restore(sdk::StateReader& in) {
  const auto read = [&](std::vector<double>& v) {
    Eigen::VectorXd m;
    in.read_matrix(m);
    v.assign(m.data(), m.data() + m.size());
  };
  for (int a = 0; a < 3; ++a) read(position[a]);
  for (int a = 0; a < 3; ++a) read(velocity[a]);
  read(radius);
  for (int a = 0; a < 3; ++a)
    if (position[a].size() != radius.size() || velocity[a].size() != radius.size())
      throw Error("grid_fluid restore(): the saved particle arrays are inconsistent");
}

}  // namespace shellflow::grid_fluid
