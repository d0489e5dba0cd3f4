#pragma once
// FallingPlate: a rigid, thin rectangular plate falling under gravity and pushed by the
// fluid. It is the smallest complete solid plugin, meant to be copied: one class, its
// parameter schema, and one registration line (falling_plate.cpp).
//
// Physics: a rigid body (Hahn 1988; the paper's §5 needs nothing more) with the mass and
// inertia of a thin plate of surface density σ: m = σ a b, I = m/12 diag(b², a², a² + b²)
// in the plate's frame (x along a, y along b, z the normal). Per-triangle fluid forces
// become a force and a torque about the centre of mass (§5.1). The translation is
// integrated exactly for the constant force over a step; the rotation by a
// semi-implicit Euler step of Euler's equations and a unit-quaternion update.

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "shellflow/sdk/plugin.hpp"

namespace shellflow::template_solid {

class FallingPlate final : public sdk::SolidSolver {
 public:
  /// Parameters, declared once: the runtime validates scenes and prints docs from this.
  static sdk::Schema schema();

  FallingPlate(const nlohmann::json& params, const sdk::Context& context);

  std::span<const sdk::ShellSurface> surfaces() const override { return {&m_surface, 1}; }
  void advance(double t, double dt, std::span<const sdk::TriangleVectors> triangle_forces) override;
  void save(sdk::StateWriter& out) const override;
  void restore(sdk::StateReader& in) override;
  void report(sdk::Metrics& out) const override;

  double mass() const { return m_mass; }
  const Eigen::Matrix3d& body_inertia() const { return m_body_inertia; }

 private:
  /// Recomputes node positions and velocities from the rigid state.
  void update_surface();

  sdk::ShellSurface m_surface;
  sdk::Positions m_body_positions;  ///< nodes relative to the centre, in the plate's frame
  Eigen::Vector3d m_gravity;
  double m_mass = 0.0;
  Eigen::Matrix3d m_body_inertia = Eigen::Matrix3d::Zero();
  // Rigid state.
  Eigen::Vector3d m_center = Eigen::Vector3d::Zero();
  Eigen::Quaterniond m_orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d m_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d m_angular_velocity = Eigen::Vector3d::Zero();  ///< world frame [rad/s]
};

}  // namespace shellflow::template_solid
