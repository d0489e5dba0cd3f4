#pragma once
// The "mass_spring_cloth" solid plugin: a ClothSimulator behind the SolidSolver interface
// (§5: the solid is a black box exposing its triangle surface). Fluid forces arrive per
// triangle and a third goes to each of its nodes.

#include <memory>
#include <nlohmann/json.hpp>

#include "mass_spring_cloth/cloth_simulator.hpp"
#include "shellflow/sdk/context.hpp"
#include "shellflow/sdk/schema.hpp"
#include "shellflow/sdk/solid_solver.hpp"

namespace shellflow::cloth {

class MassSpringCloth final : public sdk::SolidSolver {
 public:
  static sdk::Schema schema();
  MassSpringCloth(const nlohmann::json& params, const sdk::Context& context);

  std::span<const sdk::ShellSurface> surfaces() const override { return {&m_surface, 1}; }
  void set_colliders(sdk::ShellSet colliders) override;
  void advance(double t, double dt, std::span<const sdk::TriangleVectors> triangle_forces) override;
  void save(sdk::StateWriter& out) const override;
  void restore(sdk::StateReader& in) override;
  void report(sdk::Metrics& out) const override;

  ClothSimulator& simulator() { return *m_simulator; }
  const ClothSimulator& simulator() const { return *m_simulator; }

 private:
  void update_surface();

  std::unique_ptr<ClothSimulator> m_simulator;
  sdk::ShellSurface m_surface;
  sdk::ShellSet m_pending_colliders;
  std::vector<sdk::ShellSurface> m_colliders;
};

}  // namespace shellflow::cloth
