#include "shellflow/grid_fluid/pressure/face_apertures.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

void FaceApertures::gather(const ShellGeometry& shells, const geometry::ShellBand& band,
                           const std::array<std::vector<std::uint8_t>, 3>& closed) {
  const auto& apertures = shells.face_apertures(band);
  m_empty = true;
  for (int a = 0; a < 3; ++a) {
    m_faces[a].clear();
    for (const FaceAperture& open : apertures[a])
      if (closed[a][open.face] == 0)
        m_faces[a].push_back({open.face, open.fraction, shells.velocity_at(open.hit)[a]});
    m_empty = m_empty && m_faces[a].empty();
  }
}

void FaceApertures::clear() {
  for (auto& list : m_faces) list.clear();
  m_empty = true;
}

void FaceApertures::adjust_fluxes(const grid::UniformGrid& grid, const MacGrid& mac,
                                  Eigen::VectorXd& flux, double sign) const {
  const Eigen::Vector3i n = grid.cells();
  for (int a = 0; a < 3; ++a) {
    // The face is its + cell's min face (outward −u) and its − cell's max face (+u); the
    // + cell has the face's coordinates.
    const std::int64_t stride = a == 0 ? 1 : (a == 1 ? n.x() : std::int64_t(n.x()) * n.y());
    const double* u = mac.face_velocity(a).data();
    for (const Face& f : m_faces[a]) {
      const std::int64_t plus =
          grid.index(Location::Cell, grid.coordinates(face_location(a), f.face));
      const double change = sign * (f.fraction - 1.0) * (u[f.face] - f.shell_velocity);
      flux[plus] -= change;
      flux[plus - stride] += change;
    }
  }
}

void FaceApertures::scale_weights(int axis, std::vector<float>& weights) const {
  for (const Face& f : m_faces[axis]) weights[f.face] *= static_cast<float>(f.fraction);
}

}  // namespace shellflow::grid_fluid
