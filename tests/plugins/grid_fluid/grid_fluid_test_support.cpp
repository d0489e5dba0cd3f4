#include "grid_fluid_test_support.hpp"

#include "shellflow/linear/laplacian_null_space.hpp"
#include "shellflow/linear/multigrid_preconditioner.hpp"
#include "shellflow/linear/preconditioned_cg.hpp"

#include <Eigen/Geometry>
#include <memory>
#include <random>

namespace shellflow::grid_fluid::test {

sdk::ShellSurface make_plate(const Eigen::Vector3d& center, const Eigen::Vector3d& normal,
                             double size, int nodes) {
  auto mesh = geometry::make_grid(size, size, nodes, nodes, geometry::GridPattern::Alternating);
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), normal);
  sdk::ShellSurface s;
  s.name = "plate";
  s.positions = mesh.positions;
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i)
    s.positions.row(i) = (center + q * s.positions.row(i).transpose()).transpose();
  s.velocities = sdk::Positions::Zero(s.positions.rows(), 3);
  s.triangles = std::make_shared<const sdk::Triangles>(mesh.triangles);
  s.surface_density = Eigen::VectorXd::Ones(mesh.triangles.rows());
  return s;
}

CutShells::CutShells(const grid::UniformGrid& grid, std::vector<sdk::ShellSurface> surfaces)
    : shells(std::move(surfaces)), geometry(shells, 1e-3 * grid.dx()), band(grid) {
  for (const auto& shell : shells) band.add(geometry::TriangleMesh(shell), 2.0 * grid.dx());
  parts = CellParts(geometry, band);
}

void random_flow(MacGrid& mac, FragmentVelocities& fragments, double amplitude, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> speed(-amplitude, amplitude);
  const grid::UniformGrid& grid = mac.grid();
  for (int a = 0; a < 3; ++a) {
    const grid::Location loc = face_location(a);
    for (std::int64_t f = 0; f < grid.size(loc); ++f) {
      const int along = grid.coordinates(loc, f)[a];
      mac.face_velocity(a)[f] = along == 0 || along == grid.cells()[a] ? 0.0 : speed(random);
    }
    for (double& v : fragments[a]) v = speed(random);
  }
}

Eigen::VectorXd project_on_parts(const CutCellSystem& system, MacGrid& mac,
                                 FragmentVelocities& fragments) {
  Eigen::VectorXd flux;
  system.outward_flux(mac, fragments, flux);
  Eigen::VectorXd b = -flux;
  const linear::ConstantNullSpace null_space = linear::null_space_of(system.laplacian());
  null_space.project(b);
  linear::MultigridPreconditioner mg;
  mg.compute(system.laplacian());
  Eigen::VectorXd p = Eigen::VectorXd::Zero(b.size());
  const auto stats =
      linear::preconditioned_cg(system.laplacian(), mg, b, p, 1e-13, 500, &null_space);
  EXPECT_TRUE(stats.converged) << stats.relative_residual;
  system.apply_pressure(p, mac, fragments);
  return p;
}

}  // namespace shellflow::grid_fluid::test
