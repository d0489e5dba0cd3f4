#include "shellflow/grid_fluid/grid_fluid_solver.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/json_helpers.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

grid::UniformGrid make_grid(const nlohmann::json& params) {
  const auto& domain = params.at("domain");
  const Eigen::Vector3d lo = sdk::json_vec3(domain, "min");
  const Eigen::Vector3d hi = sdk::json_vec3(domain, "max");
  const Eigen::Vector3d extent = hi - lo;
  if ((extent.array() <= 0.0).any())
    throw ConfigError("/domain/max", "every coordinate of max must exceed min's");
  const int resolution = params.at("resolution").get<int>();
  const double dx = extent.maxCoeff() / resolution;
  Eigen::Vector3i cells;
  for (int a = 0; a < 3; ++a) cells[a] = std::max(1, static_cast<int>(std::lround(extent[a] / dx)));
  const Eigen::Vector3d upper = lo + dx * cells.cast<double>();
  if ((upper - hi).cwiseAbs().maxCoeff() > 1e-9 * extent.maxCoeff())
    spdlog::info(
        "grid_fluid: domain max moved from ({}, {}, {}) to ({}, {}, {}) to fit "
        "cubic cells of {} m",
        hi.x(), hi.y(), hi.z(), upper.x(), upper.y(), upper.z(), dx);
  return grid::UniformGrid(lo, dx, cells);
}

double ambient_of(const nlohmann::json& params) {
  return params.at("smoke").at("ambient_temperature").get<double>();
}

ProjectionSettings projection_settings(const nlohmann::json& params) {
  const auto& p = params.at("pressure");
  ProjectionSettings s;
  s.solver = p.at("solver").get<std::string>() == "cholmod" ? PressureSolver::Cholmod
                                                            : PressureSolver::Pcg;
  s.preconditioner = p.at("preconditioner").get<std::string>() == "mic0"
                         ? PressurePreconditioner::Mic0
                         : PressurePreconditioner::Multigrid;
  s.tolerance = p.at("tolerance").get<double>();
  s.max_iterations = p.at("max_iterations").get<int>();
  return s;
}

}  // namespace

GridFluid::GridFluid(const nlohmann::json& params, const sdk::Context& context)
    : m_context(context),
      m_mac(make_grid(params)),
      m_transfer(m_mac.grid()),
      m_advector(m_mac.grid(), ambient_of(params)),
      m_forces(m_mac.grid()),
      m_refill(m_mac.grid(), ambient_of(params)),
      m_projection(m_mac.grid(), projection_settings(params)),
      m_band(m_mac.grid()) {
  if (params.contains("boundary")) m_boundary = DomainBoundary(params.at("boundary"), "/boundary");
  m_epsilon = params.at("epsilon").get<double>() * m_mac.dx();
  const bool water = params.contains("water") && !params.at("water").is_null();
  m_density = params.contains("density") && !params.at("density").is_null()
                  ? params.at("density").get<double>()
                  : (water ? 1000.0 : 1.0);
  m_coupling_tolerance = params.at("pressure").at("coupling_tolerance").get<double>();
  const auto& smoke = params.at("smoke");
  m_buoyancy.ambient_temperature = smoke.at("ambient_temperature").get<double>();
  m_buoyancy.density_alpha = smoke.at("density_buoyancy").get<double>();
  m_buoyancy.temperature_beta = smoke.at("temperature_buoyancy").get<double>();
  if (smoke.contains("up") && !smoke.at("up").is_null()) {
    m_buoyancy.up = sdk::json_vec3(smoke, "up");
    if (m_buoyancy.up.norm() == 0.0) throw ConfigError("/smoke/up", "must not be zero");
  } else if (context.gravity.norm() > 0.0) {
    m_buoyancy.up = -context.gravity.normalized();
  }
  m_buoyancy.up.normalize();
  m_vorticity = smoke.at("vorticity_confinement").get<double>();
  const auto& sources = params.at("sources");
  if (params.contains("water") && !params.at("water").is_null()) {
    if (!sources.empty())
      throw ConfigError("/sources",
                        "smoke emitters in a water scene: put water emitters in "
                        "/water/sources");
    m_liquid = std::make_unique<Liquid>(params.at("water"), m_mac.grid(), m_buoyancy.up,
                                        context.fps, m_boundary, context.gravity);
    if (m_liquid->cut_cells()) m_cut_water = std::make_unique<CutCellWater>(m_mac.grid());
    m_refill.track_cells();  // φ's samples the shells sweep
  }
  for (size_t i = 0; i < sources.size(); ++i) {
    const std::string path = "/sources/" + std::to_string(i);
    m_sources.emplace_back(sources[i], path);
    m_sources.back().require_in_domain(m_mac.grid(), path, "it would never set any smoke");
    m_temperature = m_temperature || m_sources.back().temperature().has_value();
  }
  if (params.contains("prescribed_velocity") && !params.at("prescribed_velocity").is_null()) {
    if (!m_liquid)
      throw ConfigError("/prescribed_velocity",
                        "a prescribed velocity carries water: add a /water block (smoke is "
                        "always solved for)");
    if (!m_liquid->sources().empty())
      throw ConfigError("/water/sources",
                        "emitters set their own velocity, which a prescribed velocity would "
                        "overwrite: leave /water/sources empty with /prescribed_velocity");
    if (params.contains("initial_velocity") && !params.at("initial_velocity").is_null())
      throw ConfigError("/initial_velocity",
                        "the prescribed velocity is the velocity at every time: leave "
                        "/initial_velocity out");
    m_prescribed.emplace(params.at("prescribed_velocity"), m_mac.grid(), "/prescribed_velocity");
    m_initial_phi = m_liquid->level_set().phi();
  }
  m_probes = FluidProbes(params.at("probes"), "/probes", m_mac.grid());
  m_nodes = NodeFields(m_mac.grid(), m_buoyancy.ambient_temperature, m_liquid == nullptr,
                       m_temperature);  // no temperature field unless a source sets one
  if (!m_prescribed) m_next = m_nodes;  // what the solved step advects into
  if (params.contains("initial_velocity") && !params.at("initial_velocity").is_null()) {
    // Faces only: advect() transfers them to the nodes before its first step (§4.2).
    AnalyticVelocity(params.at("initial_velocity"), m_mac.grid()).fill(m_mac);
    m_nodes_current = false;
  }
  if (m_prescribed) {
    sample_prescribed(0.0);  // the field as it is: the walls do not change it
    // Every kind is fastest at t = 0 (steady, or LeVeque's cos(πt/T)): the CFL speed of
    // every step, also of those that start where the deformation stops (t = T/2).
    m_prescribed_speed = m_mac.max_face_speed();
  } else {
    apply_boundary_velocities(m_mac, m_boundary);
  }
  const Eigen::Vector3i c = m_mac.grid().cells();
  if (m_liquid) {
    spdlog::info(
        "grid_fluid: water, {}x{}x{} cells, dx = {} m, eps = {} m, {} emitter(s), "
        "volume {} m^3",
        c.x(), c.y(), c.z(), m_mac.dx(), m_epsilon, m_liquid->sources().size(),
        m_liquid->initial_volume());
  } else {
    spdlog::info("grid_fluid: {}x{}x{} cells, dx = {} m, eps = {} m, {} source(s), temperature {}",
                 c.x(), c.y(), c.z(), m_mac.dx(), m_epsilon, m_sources.size(),
                 m_temperature ? "on" : "off");
  }
}

std::vector<sdk::Positions> GridFluid::velocities_of(sdk::ShellSet shells) {
  std::vector<sdk::Positions> v;
  v.reserve(shells.size());
  for (const auto& s : shells) v.push_back(s.velocities);
  return v;
}

bool GridFluid::ensure_geometry(std::unique_ptr<ShellGeometry>& cache, sdk::ShellSet shells) const {
  if (!cache || !cache->same_positions(shells)) {
    cache = std::make_unique<ShellGeometry>(shells, m_epsilon);
    return true;
  }
  cache->set_velocities(velocities_of(shells));
  return false;
}

void GridFluid::build_band(sdk::ShellSet shells_n, sdk::ShellSet shells_np1, double margin) {
  if (m_band_used) m_band.clear();
  m_band_used = false;
  for (size_t s = 0; s < shells_np1.size(); ++s) {
    if (shells_np1[s].triangle_count() == 0) continue;
    const geometry::TriangleMesh end(shells_np1[s]);
    if (s < shells_n.size() && shells_n[s].triangle_count() == shells_np1[s].triangle_count()) {
      m_band.add_swept(geometry::TriangleMesh(shells_n[s]), end, margin);
    } else {
      m_band.add(end, margin);
    }
    m_band_used = true;
  }
}

void GridFluid::refresh_nodes(sdk::ShellSet shells) {
  ensure_geometry(m_geometry_n, shells);
  build_band(shells, shells, 2.0 * m_mac.dx());
  m_transfer.faces_to_nodes(m_mac, m_nodes, *m_geometry_n, m_band_used ? &m_band : nullptr,
                            cut_faces());
  m_nodes_current = true;
}

double GridFluid::max_flow_speed() const {
  const double faces = m_mac.max_face_speed();
  // Water in a far part moves with its fragments alone.
  return m_cut_water ? std::max(faces, max_fragment_speed(m_cut_water->fragments())) : faces;
}

double GridFluid::stable_dt(double cfl) const {
  double speed = std::max(m_prescribed ? m_prescribed_speed : max_flow_speed(), m_shell_speed);
  for (const auto& s : m_sources)
    if (s.velocity() && s.active(m_time)) speed = std::max(speed, s.velocity()->norm());
  if (m_liquid)
    for (const auto& s : m_liquid->sources())
      if (s.velocity() && s.active(m_time)) speed = std::max(speed, s.velocity()->norm());
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side)
      if (m_boundary.side(a, side).type == BoundaryType::Inflow)
        speed = std::max(speed, m_boundary.side(a, side).velocity.norm());
  // A body force f changes u by f Δt: allow for it over one cell (Bridson 2008, §3.1);
  // water falls under gravity from the first step on.
  const double force = m_liquid && !m_prescribed
                           ? std::max(m_stats.max_force, m_context.gravity.norm())
                           : m_stats.max_force;
  speed += std::sqrt(m_mac.dx() * force);
  return speed > 0.0 ? cfl * m_mac.dx() / speed : kInf;
}

void GridFluid::start(double dt, sdk::ShellSet shells,
                      std::span<const sdk::Positions> effective_velocity) {
  // §6's loop projects each step against the shells' next motion; before the first step
  // nothing had, and water at rest beside a shell that already moves (a shaken cup, a cloth
  // sagging under a pool) stayed put for a step while the shell moved on: the gap was
  // refilled from the water's side (§3), water made or taken. The projection gives it the
  // motion's pressure impulse: a one-way shell's whole first-step velocity; a two-way
  // shell's only what it gains over the step from its own forces, since the fluid's share
  // of the velocity it starts with (its added mass, §5.1) is the coupling's to settle and
  // here the shell could not pay for it (energy out of nothing).
  // Nothing to do where nothing would move.
  if (m_prescribed || shells.empty()) return;
  std::vector<sdk::Positions> impulse(shells.size());
  bool moving = false;
  for (size_t s = 0; s < shells.size(); ++s) {
    impulse[s] = sdk::Positions::Zero(shells[s].positions.rows(), 3);
    if (s >= effective_velocity.size() || effective_velocity[s].rows() != impulse[s].rows())
      continue;
    if (!shells[s].receives_fluid_forces)
      impulse[s] = effective_velocity[s];
    else if (shells[s].velocities.rows() == impulse[s].rows())
      impulse[s] = effective_velocity[s] - shells[s].velocities;
    moving = moving || !impulse[s].isZero(0.0);
  }
  if (!moving) return;
  // The water settles among the shells before its first projection (cut cells find their
  // parts there, with the water as it will stay).
  ensure_geometry(m_geometry_n, shells);
  build_band(shells, shells, 2.0 * m_mac.dx());
  settle_water(*m_geometry_n, m_band_used ? &m_band : nullptr);
  project_against(m_geometry_n, dt, shells, impulse);
}

void GridFluid::settle_water(const ShellGeometry& shells, const geometry::ShellBand* band) {
  // The volume water_volume_change counts from: measured as water_volume is, against the
  // shells of the first step (a film on a shell counts only with them).
  if (m_liquid && !m_liquid->initial_volume_measured()) {
    m_liquid->settle_among_shells(shells, band);
    m_liquid->measure_initial_volume(&shells, band);
  }
}

void GridFluid::advect(double t, double dt, sdk::ShellSet shells_n, sdk::ShellSet shells_np1) {
  m_stats = StepStats{};
  m_time = t;
  const bool shells = !shells_n.empty() || !shells_np1.empty();
  ShellGeometry none;
  if (shells) {
    if (ensure_geometry(m_geometry_n, shells_n)) m_nodes_current = false;
  } else {
    m_geometry_n.reset();
  }
  const ShellGeometry& geom_n = m_geometry_n ? *m_geometry_n : none;

  // Shell band: every node whose ray (≤ Δt max|u|) or stencil may reach a shell (§3, §4.1).
  double speed = max_flow_speed();
  for (const auto& s : shells_n)
    if (s.velocities.rows() > 0) speed = std::max(speed, s.velocities.rowwise().norm().maxCoeff());
  build_band(shells_n, shells_np1, m_advector.band_margin(dt, speed));
  const geometry::ShellBand* band = m_band_used ? &m_band : nullptr;
  m_stats.band_nodes = band ? static_cast<std::int64_t>(band->samples(Location::Node).size()) : 0;
  settle_water(geom_n, band);
  if (m_cut_water && shells)  // the parts are the last projection's but at the first step
    m_cut_water->update(shells_n, geom_n, nullptr, m_mac, m_liquid->level_set(),
                        m_liquid->fraction());

  if (m_prescribed) {
    // The field at the middle of the step carries φ and the particles; nothing else moves.
    sample_prescribed(t + 0.5 * dt);
    m_liquid->advect(t, m_mac, dt, m_mac.max_face_speed(), geom_n, band);
  } else {
    // 1. §4.2 faces → nodes (already done at the end of the last projection, same shells).
    if (!m_nodes_current) m_transfer.faces_to_nodes(m_mac, m_nodes, geom_n, band, cut_faces());

    // 2. §4.1 semi-Lagrangian advection with visibility (water: φ along the same rays).
    m_advector.advect(
        m_nodes, m_next, dt, geom_n, band,
        m_liquid ? m_liquid->velocity_nodes(t, dt, speed) : std::span<const std::uint8_t>());
    if (m_liquid) m_liquid->advect(t, m_mac, dt, speed, geom_n, band);
    std::swap(m_nodes, m_next);  // m_next keeps the fields at n: u^n for step 5

    // 3. Water: gravity on the nodes (§4.1), emitters; smoke: sources and body forces.
    if (m_liquid)
      advect_water_forces(t, dt);
    else
      add_smoke_forces(t, dt, geom_n, band);
  }

  // 4. The shells move n → n+1: swept nodes invalidated and refilled (§3).
  if (shells) {
    ensure_geometry(m_geometry_np1, shells_np1);
    m_stats.refill = m_refill.run(geom_n, *m_geometry_np1, m_nodes);
  }
  const ShellGeometry& geom_np1 = m_geometry_np1 && shells ? *m_geometry_np1 : none;
  if (m_liquid) {  // §4.4.1: φ refilled, then a signed distance again, against shells^{n+1}
    m_liquid->refill(shells ? m_refill.swept_cells() : std::span<const std::int64_t>(), dt, geom_n,
                     geom_np1);
    m_liquid->reinitialize(geom_n, geom_np1, band, t + dt);
  }

  if (m_prescribed) return;  // the faces are sampled at n+1 in project()
  // 5. §4.2 increments back to the persistent faces, with visibility at n+1.
  static const std::array<std::vector<std::uint8_t>, 3> no_faces;
  m_transfer.increments_to_faces(
      m_mac, m_nodes, m_next.velocities(),
      shells ? m_refill.node_valid_before() : std::span<const std::uint8_t>(),
      shells ? m_refill.face_swept() : no_faces, geom_np1, band, m_boundary, cut_faces());
  apply_boundary_velocities(m_mac, m_boundary);
  m_nodes_current = false;
}

void GridFluid::advect_water_forces(double t, double dt) {
  const Eigen::Vector3d g = m_context.gravity;
  for (int a = 0; a < 3; ++a) {
    if (g[a] == 0.0) continue;
    auto& u = m_nodes.velocity(a);
    const std::int64_t n = static_cast<std::int64_t>(u.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) u[i] += dt * g[a];
  }
  m_stats.max_force = g.norm();
  m_liquid->add_sources(t, m_boundary);
  m_stats.source_nodes = m_liquid->stats().source_nodes;
}

void GridFluid::sample_prescribed(double t) {
  const grid::UniformGrid& g = m_mac.grid();
  const std::int64_t n = m_nodes.size();
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    const Eigen::Vector3d u = m_prescribed->velocity(g.position(Location::Node, i), t);
    for (int a = 0; a < 3; ++a) m_nodes.velocity(a)[i] = u[a];
  }
  m_prescribed->fill(m_mac, t);
  m_nodes_current = true;
}

void GridFluid::add_smoke_forces(double t, double dt, const ShellGeometry& geom_n,
                                 const geometry::ShellBand* band) {
  for (const auto& s : m_sources)
    m_stats.source_nodes += s.apply(t, m_mac.grid(), m_nodes, m_temperature);
  // Held on the faces through this step's pressure solves; the emitters add volume only
  // where an open side lets it out (a closed box keeps its volume).
  for (int a = 0; a < 3; ++a) {
    std::vector<SourceFace> faces;
    for (const auto& s : m_sources)
      s.append_faces(t, m_mac.grid(), a, m_boundary.has_open_side(), faces);
    m_boundary.set_source_faces(a, std::move(faces));
  }
  if (m_buoyancy.density_alpha != 0.0 || (m_temperature && m_buoyancy.temperature_beta != 0.0))
    m_stats.max_force = m_forces.add_buoyancy(m_nodes, dt, m_buoyancy, m_temperature);
  if (m_vorticity > 0.0)
    m_stats.max_force = std::max(m_stats.max_force, m_forces.add_vorticity_confinement(
                                                        m_nodes, dt, m_vorticity, geom_n, band));
}

CouplingPressure& GridFluid::coupling_pressure() {
  if (!m_coupling) {
    const auto& p = m_projection.settings();
    m_coupling = std::make_unique<CouplingPressure>(
        m_mac.grid(), CouplingSettings{m_density, m_coupling_tolerance, p.max_iterations},
        m_projection.scratch());
  }
  return *m_coupling;
}

void GridFluid::coupling_forces(double dt, sdk::ShellSet shells,
                                std::span<sdk::TriangleVectors> triangle_forces) {
  m_stats.coupling = CouplingStats{};
  bool two_way = false;
  for (const auto& s : shells) two_way = two_way || s.receives_fluid_forces;
  if (!m_logged_coupling) {
    if (two_way)
      spdlog::info("grid_fluid: two-way coupling (§5.1 coupling pressure every step{})",
                   m_liquid ? ", over the water's cells" : "");
    else
      spdlog::info("grid_fluid: one-way coupling (no shell receives fluid forces)");
    m_logged_coupling = true;
  }
  // Skip what the scene does not need: no second solve (a prescribed flow pushes nothing).
  if (!two_way || m_prescribed) return;
  if (m_cut_water)
    throw Error(
        "/fluid/water/cut_cells: a shell receives the fluid's forces (two-way), which cut cells "
        "do not couple yet (docs/cut-cells.md, C4). Set /fluid/water/cut_cells to false.");
  // Same positions as advect's n+1 shells: its band (margin >= 2Δx) still covers them.
  if (ensure_geometry(m_geometry_np1, shells) || !m_band_used)
    build_band(shells, shells, 2.0 * m_mac.dx());
  // Water: the surface the projection will see (same shells), air cells at p = 0.
  const FreeSurface* surface = m_liquid ? &m_liquid->surface() : nullptr;
  m_stats.coupling = coupling_pressure().compute(m_mac, dt, m_boundary, *m_geometry_np1, m_band,
                                                 shells, triangle_forces, surface);
}

void GridFluid::project(double dt, sdk::ShellSet shells,
                        std::span<const sdk::Positions> effective_velocity) {
  m_shell_speed = 0.0;
  for (const auto& v : effective_velocity)
    if (v.rows() > 0) m_shell_speed = std::max(m_shell_speed, v.rowwise().norm().maxCoeff());
  if (m_prescribed) {  // nothing to solve: the field at n+1
    if (!shells.empty()) ensure_geometry(m_geometry_np1, shells);
    sample_prescribed(m_time + dt);
    std::swap(m_geometry_n, m_geometry_np1);
    m_time += dt;
    return;
  }
  project_against(m_geometry_np1, dt, shells, effective_velocity);
  std::swap(m_geometry_n, m_geometry_np1);
  m_time += dt;
}

void GridFluid::project_against(std::unique_ptr<ShellGeometry>& geometry, double dt,
                                sdk::ShellSet shells,
                                std::span<const sdk::Positions> boundary_velocity) {
  ShellGeometry none;
  const bool have_shells = !shells.empty();
  if (have_shells) {
    ensure_geometry(geometry, shells);
    geometry->set_velocities(boundary_velocity);  // §4.3: the effective velocity
    build_band(shells, shells, 2.0 * m_mac.dx());
  } else {
    geometry.reset();
    build_band(shells, shells, 0.0);
  }
  const geometry::ShellBand* band = m_band_used ? &m_band : nullptr;
  const ShellGeometry& geom = have_shells ? *geometry : none;
  const auto start = std::chrono::steady_clock::now();
  const bool parts = m_cut_water && have_shells;
  if (parts) {
    // The shells moved since the parts were found for m_geometry_n (the step's start).
    const ShellGeometry* previous = &geometry != &m_geometry_n ? m_geometry_n.get() : nullptr;
    m_cut_water->update(shells, geom, previous, m_mac, m_liquid->level_set(), m_liquid->fraction());
    const FreeSurface& surface = m_liquid->surface();
    const auto& part_phi = m_cut_water->part_phi(geom, surface.cell_phi, m_liquid->fraction());
    m_stats.projection = m_projection.project_parts(
        m_mac, m_cut_water->fragments(), dt, m_boundary, geom, m_cut_water->parts(),
        {surface.cell_phi, part_phi, surface.ghost_fluid}, m_cut_water->shell_flux(geom));
  } else {
    m_stats.projection = m_projection.project(m_mac, dt, m_boundary, geom, band,
                                              m_liquid ? &m_liquid->surface() : nullptr);
  }
  m_t_pressure = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // §4.4: velocities across the surface, against the effective velocity of the shells.
  if (m_liquid) m_liquid->extrapolate(m_mac, m_projection, geom, band);
  if (parts) m_cut_water->extrapolate_fragments(m_mac, m_liquid->level_set().phi());

  // Nodes for writers and for the next step (§4.2), against the shells' own velocities.
  if (have_shells) geometry->set_velocities(velocities_of(shells));
  m_transfer.faces_to_nodes(m_mac, m_nodes, geom, band, cut_faces());
  m_nodes_current = true;
}

std::optional<sdk::DomainView> GridFluid::domain() const {
  sdk::DomainView d;
  d.lower = m_mac.grid().origin();
  d.upper = m_mac.grid().upper();
  for (int axis = 0; axis < 3; ++axis)
    for (int max_side = 0; max_side < 2; ++max_side) {
      const BoundaryType type = m_boundary.side(axis, max_side).type;
      d.sides[2 * axis + max_side] = type == BoundaryType::Wall   ? sdk::DomainView::Side::Wall
                                     : type == BoundaryType::Open ? sdk::DomainView::Side::Open
                                                                  : sdk::DomainView::Side::Inflow;
    }
  return d;
}

std::vector<sdk::FieldView> GridFluid::fields() const {
  const auto& g = m_mac.grid();
  const auto view = [&](const char* name, sdk::FieldView::Location loc, Location gl,
                        std::array<const double*, 3> data, int components) {
    sdk::FieldView v;
    v.name = name;
    v.location = loc;
    v.origin = g.position(gl, Eigen::Vector3i::Zero());
    v.dx = g.dx();
    const Eigen::Vector3i n = g.counts(gl);
    v.dims = {n.x(), n.y(), n.z()};
    v.components = components;
    v.data = data;
    return v;
  };
  using L = sdk::FieldView::Location;
  std::vector<sdk::FieldView> out;
  if (m_liquid)
    out.push_back(view("phi", L::Cell, Location::Cell,
                       {m_liquid->level_set().phi().data(), nullptr, nullptr}, 1));
  else
    out.push_back(
        view("density", L::Node, Location::Node, {m_nodes.density().data(), nullptr, nullptr}, 1));
  if (m_temperature)
    out.push_back(view("temperature", L::Node, Location::Node,
                       {m_nodes.temperature().data(), nullptr, nullptr}, 1));
  out.push_back(view(
      "velocity", L::Node, Location::Node,
      {m_nodes.velocity(0).data(), m_nodes.velocity(1).data(), m_nodes.velocity(2).data()}, 3));
  out.push_back(
      view("pressure", L::Cell, Location::Cell, {m_mac.pressure().data(), nullptr, nullptr}, 1));
  return out;
}

std::vector<sdk::ParticleView> GridFluid::particles() const {
  if (!m_liquid || !m_liquid->particles().enabled()) return {};
  const ParticleLevelSet& pls = m_liquid->particles();
  // The shells at the end of the last step (m_geometry_n since project()'s swap) are those
  // the nodes were last transferred with.
  static const ShellGeometry none;
  const ShellGeometry& shells = m_geometry_n ? *m_geometry_n : none;
  const geometry::ShellBand* band = m_band_used ? &m_band : nullptr;
  const NodeFields& velocity = m_liquid->particle_velocity(m_mac);
  pls.gather(-1, velocity, shells, band, m_marker_views[0]);
  pls.gather(+1, velocity, shells, band, m_marker_views[1]);
  pls.gather(-1, velocity, shells, band, m_marker_views[2], &m_liquid->level_set());
  return {pls.spray().view("spray"), m_marker_views[2].view("escaped_water"),
          m_marker_views[0].view("water_particles"), m_marker_views[1].view("air_particles")};
}

std::optional<std::string> GridFluid::find_nonfinite() const {
  const auto scan = [](const std::vector<double>& v) -> std::int64_t {
    for (size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i])) return static_cast<std::int64_t>(i);
    return -1;
  };
  static const char* kFace[3] = {"face velocity u (FaceX)", "face velocity v (FaceY)",
                                 "face velocity w (FaceZ)"};
  for (int a = 0; a < 3; ++a)
    if (const auto i = scan(m_mac.face_velocity(a)); i >= 0) {
      const Eigen::Vector3i ijk = m_mac.grid().coordinates(face_location(a), i);
      return std::string(kFace[a]) + " at (" + std::to_string(ijk.x()) + ", " +
             std::to_string(ijk.y()) + ", " + std::to_string(ijk.z()) + ")";
    }
  const auto node_report = [&](const char* name, std::int64_t i) {
    const Eigen::Vector3i ijk = m_mac.grid().coordinates(Location::Node, i);
    return std::string(name) + " at node (" + std::to_string(ijk.x()) + ", " +
           std::to_string(ijk.y()) + ", " + std::to_string(ijk.z()) + ")";
  };
  if (const auto i = scan(m_nodes.density()); i >= 0) return node_report("density", i);
  if (m_liquid)
    if (const auto i = scan(m_liquid->level_set().phi()); i >= 0) {
      const Eigen::Vector3i ijk = m_mac.grid().coordinates(Location::Cell, i);
      return "level set phi at cell (" + std::to_string(ijk.x()) + ", " + std::to_string(ijk.y()) +
             ", " + std::to_string(ijk.z()) + ")";
    }
  if (const auto i = scan(m_nodes.temperature()); i >= 0) return node_report("temperature", i);
  if (const auto i = scan(m_mac.pressure()); i >= 0) return "pressure at cell " + std::to_string(i);
  return std::nullopt;
}

}  // namespace shellflow::grid_fluid
