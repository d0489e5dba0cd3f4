#include "shellflow/grid_fluid/pressure/face_apertures.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

void FaceApertures::gather(const ShellGeometry& shells, const geometry::ShellBand& band,
                           const std::array<std::vector<std::uint8_t>, 3>& closed) {
  const grid::UniformGrid& grid = band.grid();
  const auto& apertures = shells.face_apertures(band);
  for (int a = 0; a < 3; ++a) {
    m_faces[a].clear();
    for (const FaceAperture& open : apertures[a]) {
      if (closed[a][open.face] != 0) continue;
      // The + cell has the face's coordinates.
      Eigen::Vector3i c = grid.coordinates(face_location(a), open.face);
      const std::int64_t plus = grid.index(Location::Cell, c);
      c[a] -= 1;
      m_faces[a].push_back({open.face, plus, grid.index(Location::Cell, c), open.fraction,
                            shells.velocity_at(open.hit)[a]});
    }
  }
}

void FaceApertures::clear() {
  for (auto& list : m_faces) list.clear();
}

void FaceApertures::adjust_fluxes(const MacGrid& mac, Eigen::VectorXd& flux, double sign) const {
  for (int a = 0; a < 3; ++a) {
    const double* u = mac.face_velocity(a).data();
    for (const Face& f : m_faces[a]) {
      // The + cell's min face (outward −u), the − cell's max face (+u).
      const double change = sign * (f.fraction - 1.0) * (u[f.face] - f.shell_velocity);
      flux[f.plus] -= change;
      flux[f.minus] += change;
    }
  }
}

void FaceApertures::scale_weights(int axis, const grid::UniformGrid& grid,
                                  const Eigen::Vector3i& box_lo, const Eigen::Vector3i& face_counts,
                                  std::vector<float>& weights) const {
  for (const Face& f : m_faces[axis]) {
    const Eigen::Vector3i c = grid.coordinates(face_location(axis), f.face) - box_lo;
    if ((c.array() < 0).any() || (c.array() >= face_counts.array()).any()) continue;
    weights[c.x() +
            std::int64_t(face_counts.x()) * (c.y() + std::int64_t(face_counts.y()) * c.z())] *=
        static_cast<float>(f.fraction);
  }
}

}  // namespace shellflow::grid_fluid
