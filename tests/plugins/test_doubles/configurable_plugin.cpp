// A small solid whose descriptor fields are set by compile definitions, so one source
// yields every bad plugin the loader tests need. As a solid it is a single triangle
// moving at constant velocity; with "nan_after_steps" > 0 it turns non-finite then, with
// "kill_after_steps" > 0 it kills its own process then (SIGKILL, as the kernel's OOM killer
// would: no handler runs, no core is dumped), and "reject": true makes its constructor throw
// a ConfigError at /reject.

#include <csignal>

#include "shellflow/sdk/json_helpers.hpp"
#include "shellflow/sdk/plugin.hpp"

#ifndef TD_ABI_MAJOR
#define TD_ABI_MAJOR SHELLFLOW_ABI_MAJOR
#endif
#ifndef TD_ABI_MINOR
#define TD_ABI_MINOR SHELLFLOW_ABI_MINOR
#endif
#ifndef TD_SIGNATURE
#define TD_SIGNATURE SHELLFLOW_BUILD_SIGNATURE
#endif

namespace {

using namespace shellflow;

class TestTriangle final : public sdk::SolidSolver {
 public:
  static sdk::Schema schema() {
    return sdk::Schema::object("test double: one triangle moving at constant velocity")
        .field("velocity", sdk::Schema::vec3(1, 0, 0).unit("m/s"))
        .field("nan_after_steps", sdk::Schema::integer(0).min(0))
        .field("kill_after_steps", sdk::Schema::integer(0).min(0))
        .field("reject", sdk::Schema::boolean(false))
        .field("stable_dt", sdk::Schema::number(1e30).min(0.0, false).unit("s"));
  }
  TestTriangle(const nlohmann::json& params, const sdk::Context& context)
      : m_velocity(sdk::json_vec3(params, "velocity")),
        m_nan_after(params["nan_after_steps"]),
        m_kill_after(params["kill_after_steps"]),
        m_stable_dt(params["stable_dt"]) {
    if (params["reject"].get<bool>()) throw ConfigError("/reject", "rejected on purpose");
    sdk::Triangles tris(1, 3);
    tris << 0, 1, 2;
    m_surface.name = context.instance_name;
    m_surface.triangles = std::make_shared<const sdk::Triangles>(tris);
    m_surface.positions.resize(3, 3);
    m_surface.positions << 0, 0, 0, 1, 0, 0, 0, 1, 0;
    m_surface.velocities = m_surface.positions.rowwise().replicate(1);
    for (int i = 0; i < 3; ++i) m_surface.velocities.row(i) = m_velocity.transpose();
    m_surface.surface_density = Eigen::VectorXd::Ones(1);
  }
  std::span<const sdk::ShellSurface> surfaces() const override { return {&m_surface, 1}; }
  double stable_dt() const override { return m_stable_dt; }
  void advance(double, double dt, std::span<const sdk::TriangleVectors>) override {
    ++m_steps;
    m_surface.positions.rowwise() += (m_velocity * dt).transpose();
    if (m_nan_after > 0 && m_steps >= m_nan_after) m_surface.positions(1, 1) = std::nan("");
    if (m_kill_after > 0 && m_steps >= m_kill_after) std::raise(SIGKILL);
  }
  void save(sdk::StateWriter& out) const override {
    out.write(m_steps);
    out.write_matrix(m_surface.positions);
  }
  void restore(sdk::StateReader& in) override {
    m_steps = in.read<long long>();
    in.read_matrix(m_surface.positions);
  }

 private:
  sdk::ShellSurface m_surface;
  Eigen::Vector3d m_velocity;
  long long m_nan_after;
  long long m_kill_after;
  double m_stable_dt;
  long long m_steps = 0;
};

}  // namespace

SHELLFLOW_PLUGIN_DESCRIPTOR(TestTriangle, ::shellflow::sdk::SolidSolver, SHELLFLOW_KIND_SOLID,
                            TD_NAME, "0.0.1", TD_ABI_MAJOR, TD_ABI_MINOR, TD_SIGNATURE)
