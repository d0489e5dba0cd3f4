// The template plugin, loaded the way a run loads it: free fall, force and torque
// from per-triangle fluid forces, and save/restore.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "scratch_folder.hpp"
#include "shellflow/runtime/plugin_instance.hpp"
#include "test_paths.hpp"

namespace shellflow {
namespace {

namespace fs = std::filesystem;
const fs::path kPlugins = shellflow::test_paths::plugin_dir();

// Translation is integrated exactly for a constant force, so free fall matches the
// analytic parabola to round-off of O(1) numbers summed over ~100 steps.
constexpr double kRoundOff = 1e-12;

class FallingPlate : public testing::ScratchFolder {
 protected:
  void make(const std::string& params, const std::string& gravity = "[0, -9.81, 0]") {
    const auto file = write("scene.json", R"({"gravity": )" + gravity +
                                              R"(, "solids": [{"plugin": "template_solid", "name": "p", )" +
                                              params + "}]}");
    m_scene = runtime::load_scene(file, {kPlugins});
    m_solid = runtime::create_solid(m_scene, m_scene.solids[0]);
  }
  const sdk::ShellSurface& surface() const { return m_solid->surfaces()[0]; }
  Eigen::Vector3d centroid() const { return surface().positions.colwise().mean().transpose(); }

  runtime::Scene m_scene;
  runtime::PluginInstance<sdk::SolidSolver> m_solid;
};

TEST_F(FallingPlate, FreeFallFollowsTheParabola) {
  make(R"("transform": {"translate": [0, 10, 0]}, "velocity": [1, 2, 0])");
  const Eigen::Vector3d x0(0, 10, 0), v0(1, 2, 0), g(0, -9.81, 0);
  double t = 0.0;
  for (int k = 0; k < 100; ++k) {
    const double dt = 0.001 * (1 + k % 7);  // uneven steps: the result must not care
    m_solid->advance(t, dt, {});
    t += dt;
  }
  const Eigen::Vector3d expected = x0 + v0 * t + 0.5 * g * t * t;
  EXPECT_LT((centroid() - expected).norm(), kRoundOff * 10);
  // Node velocities are the rigid-body velocities v0 + g t.
  EXPECT_LT((surface().velocities.row(0).transpose() - (v0 + g * t)).norm(), kRoundOff * 10);
}

TEST_F(FallingPlate, UniformTriangleForcesAccelerateTheMassOnly) {
  // σ a b = 2 * 0.5 * 0.4 = 0.4 kg; no gravity so only the fluid force acts.
  make(R"("width": 0.5, "height": 0.4, "surface_density": 2.0)", "[0, 0, 0]");
  const int n = surface().triangle_count();
  sdk::TriangleVectors forces = sdk::TriangleVectors::Zero(n, 3);
  forces.col(2).setConstant(1.2 / n);  // 1.2 N along +z in total, spread evenly
  const sdk::TriangleVectors all[] = {forces};
  const double dt = 0.01;
  m_solid->advance(0.0, dt, all);
  const double a = 1.2 / 0.4;
  EXPECT_NEAR(centroid().z(), 0.5 * a * dt * dt, kRoundOff);
  // Forces at barycentres of a symmetric grid give no net torque (rigid translation).
  const auto& v = surface().velocities;
  EXPECT_LT((v.rowwise() - v.row(0)).norm(), kRoundOff);
}

TEST_F(FallingPlate, ForceCoupleGivesThePlateInertiaAngularAcceleration) {
  // A plate a x b in the x-y plane; +F_z on triangles with x > 0, -F_z on x < 0: a torque
  // about -y of magnitude F * (mean |x| of the barycentres). I_yy = m a^2 / 12.
  make(R"("width": 1.0, "height": 0.5, "nodes": 5, "surface_density": 3.0)", "[0, 0, 0]");
  const auto& tris = *surface().triangles;
  const auto& x = surface().positions;
  sdk::TriangleVectors forces = sdk::TriangleVectors::Zero(tris.rows(), 3);
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  for (int t = 0; t < tris.rows(); ++t) {
    const Eigen::Vector3d c = (x.row(tris(t, 0)) + x.row(tris(t, 1)) + x.row(tris(t, 2))).transpose() / 3.0;
    const double fz = c.x() > 1e-12 ? 0.1 : c.x() < -1e-12 ? -0.1 : 0.0;
    forces(t, 2) = fz;
    torque += c.cross(Eigen::Vector3d(0, 0, fz));
  }
  const double m = 3.0 * 1.0 * 0.5;
  const Eigen::Vector3d inertia(m * 0.25 / 12, m * 1.0 / 12, m * 1.25 / 12);
  const Eigen::Vector3d alpha = torque.cwiseQuotient(inertia);
  const sdk::TriangleVectors all[] = {forces};
  const double dt = 1e-4;
  m_solid->advance(0.0, dt, all);
  // Node at the +x edge moves with ω × r; ω = α dt after one step from rest.
  const Eigen::Vector3d omega = alpha * dt;
  for (int i = 0; i < x.rows(); ++i) {
    const Eigen::Vector3d r = surface().positions.row(i).transpose() - centroid();
    EXPECT_LT((surface().velocities.row(i).transpose() - omega.cross(r)).norm(), 1e-12)
        << "node " << i;
  }
  EXPECT_GT(std::abs(alpha.y()), 0.0);  // the couple does act
}

TEST_F(FallingPlate, SaveRestoreReproducesTheStateBitForBit) {
  make(R"("angular_velocity": [0.3, 1.0, -0.2], "velocity": [0, 1, 0])");
  const double dt = 1.0 / 24;
  m_solid->advance(0.0, dt, {});
  sdk::StateBuffer saved;
  sdk::StateWriter out(saved);
  m_solid->save(out);
  m_solid->advance(dt, dt, {});
  const sdk::Positions first = surface().positions;
  sdk::StateReader in(saved);
  m_solid->restore(in);
  m_solid->advance(dt, dt, {});
  EXPECT_EQ(std::memcmp(first.data(), surface().positions.data(), sizeof(double) * first.size()), 0);
}

}  // namespace
}  // namespace shellflow
