#include "shellflow/grid_fluid/water/liquid.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <limits>
#include <string_view>

#include "shellflow/grid_fluid/mac/ordered_sum.hpp"
#include "shellflow/grid_fluid/water/initial_water.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// |cos| of the angle within which a shape's face counts as lying along a shell (25°: a
/// 32-sided cup's facets turn 11° from one to the next).
constexpr double kFaceAlongShell = 0.9;

/// A hash of a field's bits: has it changed since?
size_t bytes_hash(const std::vector<double>& v) {
  return std::hash<std::string_view>{}(
      std::string_view(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double)));
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The MAC grid, once the scene is known to fit cell-centred water.
const grid::UniformGrid& water_grid(const nlohmann::json& params, const grid::UniformGrid& grid) {
  if (params.at("level_set").get<std::string>() != "cells")
    throw ConfigError("/water/level_set",
                      "the level set on the grid's nodes (\"nodes\") was removed: water's φ "
                      "lives on the cell centres, which keep water that reaches a wall "
                      "(docs/water-cell-centres.md). Delete the key, or set it to \"cells\"");
  if ((grid.cells().array() < 2).any())
    throw ConfigError("/resolution",
                      "water needs two cells along every axis of the domain: raise the "
                      "resolution or widen the domain's thin side");
  return grid;
}

/// `to`, one byte per node of a grid of `cells`: 1 where any of the node's (up to 8) cells is
/// flagged in `flags` (one byte per cell, overwritten: it and `scratch` hold the passes), the
/// flags spread one axis at a time.
void spread_to_corners(const Eigen::Vector3i& cells, std::vector<std::uint8_t>& flags,
                       std::vector<std::uint8_t>& scratch, std::vector<std::uint8_t>& to) {
  Eigen::Vector3i dims = cells;
  std::vector<std::uint8_t>* from = &flags;
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3i in = dims;
    dims[a] += 1;
    std::vector<std::uint8_t>& out = a == 2 ? to : a == 0 ? scratch : flags;
    out.resize(std::int64_t(dims.x()) * dims.y() * dims.z());
    const auto stride = [](const Eigen::Vector3i& d, int axis) {
      return axis == 0   ? std::int64_t(1)
             : axis == 1 ? std::int64_t(d.x())
                         : std::int64_t(d.x()) * d.y();
    };
    const std::int64_t in_stride = stride(in, a), out_stride = stride(dims, a);
    const int b = (a + 1) % 3, e = (a + 2) % 3;
    const std::int64_t rows = std::int64_t(dims[b]) * dims[e];
#pragma omp parallel for schedule(static)
    for (std::int64_t r = 0; r < rows; ++r) {
      // Row r along a: its other two coordinates, the same in the input and the output.
      const std::int64_t in_base = (r % dims[b]) * stride(in, b) + (r / dims[b]) * stride(in, e);
      const std::int64_t out_base =
          (r % dims[b]) * stride(dims, b) + (r / dims[b]) * stride(dims, e);
      for (int i = 0; i < dims[a]; ++i) {
        const std::uint8_t below = i > 0 ? (*from)[in_base + (i - 1) * in_stride] : 0;
        const std::uint8_t above = i < in[a] ? (*from)[in_base + i * in_stride] : 0;
        out[out_base + i * out_stride] = below | above;
      }
    }
    from = &out;
  }
}

}  // namespace

sdk::Schema Liquid::schema() {
  using sdk::Schema;
  return Schema::object(
             "water (§4.4): a level set, φ <= 0 water; its presence makes the scene a water "
             "scene (no smoke density, temperature, buoyancy or vorticity)")
      .field("level_set",
             Schema::string("cells")
                 .one_of({"nodes", "cells"})
                 .doc("where φ is sampled: cells, one sample per pressure cell, traced with the "
                      "faces' velocities (PhysBAM's); water that reaches a wall stays, and an "
                      "open or inflow side lets none in (where its face's velocity points "
                      "inward the water pulls away from it). nodes, the grid's nodes (the "
                      "paper's §4.4.1), was removed and is refused naming the change "
                      "(docs/water-cell-centres.md)"))
      .field("volume_fraction",
             Schema::boolean(true).doc(
                 "carry each cell's water fraction F beside φ, moved in conservative form "
                 "(Weymouth and Yue 2010), and move φ to F's planes every step (CLSVOF): the "
                 "water's volume changes only through the domain's sides and the emitters, "
                 "counted exactly, and a film thinner than a cell on a wall or a shell keeps "
                 "its water. Among shells F crosses a face a shell cuts through its open "
                 "share, and φ is left to the level set in the cells a shell cuts. With "
                 "particles, they correct φ's shape and F still holds the volume. One F serves "
                 "both sides of a cell a shell cuts: a light cloth moving through water lets "
                 "F's water through and can gain energy, so scenes with cloth in water set it "
                 "false until cut cells (docs/known-limits.md). false: the level set alone, "
                 "whose volume drifts (docs/water-cell-centres.md §5)"))
      .field("cut_cells",
             Schema::boolean(false).doc(
                 "give each part of a cell that shells cut its own pressure, water fraction "
                 "and face velocities (issue #52, docs/cut-cells.md), so that water on the side "
                 "of a shell away from a cell's centre, a film on a plate, keeps its own "
                 "pressure and velocity. In progress: needs volume_fraction, no particles, "
                 "one-way shells, still or moving (a two-way one is refused when the run meets "
                 "it), and no checkpoints yet"))
      .field("initial", Schema::array(initial_water_schema())
                            .default_value(Schema::Json::array())
                            .doc("bodies of water at the start, united"))
      .field("sources", Schema::array(WaterSource::schema())
                            .default_value(Schema::Json::array())
                            .doc("water emitters (streams): φ set inside, velocity held on "
                                 "their faces, volume added"))
      .field("band", Schema::number(6.0).min(3.0).max(20.0).unit("Δx").doc(
                         "half-width of the band in which fast marching keeps φ a signed "
                         "distance (beyond it φ = ±band)"))
      .field("extrapolation", Schema::number(5.0).min(1.0).max(19.0).unit("Δx").doc(
                                  "width of the band into which velocities are extrapolated "
                                  "across the surface (§4.4: 3–5 cells); below `band`"))
      .field("extrapolation_profile",
             Schema::string("linear")
                 .one_of({"linear", "constant"})
                 .doc("how velocities continue across the surface (§4.4). constant: the "
                      "paper's ∇φ·∇u = 0 throughout, so a surface between two planes of "
                      "faces moves with the last liquid face's velocity (a standing wave's "
                      "period up to 3.3% long at 32 cells per wavelength). linear: within a "
                      "cell of the surface the velocity keeps its normal slope (Aslam 2004; "
                      "that wave within 0.6%), constant beyond"))
      .field("advection",
             Schema::string("semi_lagrangian")
                 .one_of({"semi_lagrangian", "maccormack"})
                 .doc("φ along the velocity's rays (§4.4.1). semi_lagrangian: the paper's "
                      "trilinear step, which smooths φ so that curved water shrinks every "
                      "step unless particles correct it (§4.4.2). maccormack: traced forward "
                      "and back and corrected by half the round trip's error, clamped to the "
                      "stencil (Selle et al. 2008), at twice the cost; sharper where φ is "
                      "smooth (Zalesak's sphere), but on the level set alone it loses more than "
                      "the trilinear step where water runs up walls in thin sheets, and with "
                      "constant extrapolation a 64-cell dam break blew up "
                      "(docs/known-limits.md). With the volume fraction the volume is F's "
                      "either way"))
      .field("trace",
             Schema::string("midpoint")
                 .one_of({"midpoint", "euler"})
                 .doc("which velocity a sample's ray back follows when φ is advected. "
                      "midpoint: the velocity at x − u dt/2 (second order in time). euler: "
                      "the sample's own, the paper's, whose traced water grows in "
                      "irrotational flow by O(dt |∇u|²) a second (water sloshing in a tank "
                      "+3.5 % in 4 s against −0.2 %; docs/known-limits.md)"))
      .field("particles", ParticleLevelSet::schema())
      .field("volume_by_phase",
             Schema::boolean(false).doc(
                 "measure the water between the phases of each step (five more volume "
                 "measures a step) and write where water_volume_drift arose: "
                 "water_drift_advection, water_drift_shells, water_drift_reinitialization, "
                 "water_drift_between_steps"))
      .field("surface_pressure",
             Schema::string("ghost_fluid")
                 .one_of({"ghost_fluid", "first_order"})
                 .doc("air cells are p = 0 (§4.3); ghost_fluid places the surface between cell "
                      "centres at θ = φ_i/(φ_i − φ_j) (Gibou et al. 2002, second order), "
                      "first_order at the air cell's centre"));
}

Liquid::Liquid(const nlohmann::json& params, const grid::UniformGrid& grid,
               const Eigen::Vector3d& up, double fps, const DomainBoundary& boundary,
               const Eigen::Vector3d& gravity)
    : m_level_set(water_grid(params, grid), params.at("band").get<double>() * grid.dx()),
      m_advector(m_level_set.grid(), params.at("advection").get<std::string>() == "maccormack",
                 params.at("trace").get<std::string>() == "euler"
                     ? LevelSetAdvector::Trace::Euler
                     : LevelSetAdvector::Trace::Midpoint),
      m_fast_marching(m_level_set.grid()),
      m_extrapolation(grid, params.at("extrapolation_profile").get<std::string>() == "linear"),
      m_particles(params.at("particles"), grid, fps, gravity) {
  const double band = params.at("band").get<double>();
  const double width = params.at("extrapolation").get<double>();
  if (!(width < band))
    throw ConfigError("/water/extrapolation",
                      "must be below /water/band (" + std::to_string(band) +
                          "): velocities are extrapolated inside the signed-distance band");
  m_extrapolation_width = width * grid.dx();
  m_surface.ghost_fluid = params.at("surface_pressure").get<std::string>() == "ghost_fluid";
  m_by_phase = params.at("volume_by_phase").get<bool>();
  for (int s = 0; s < 6; ++s) {
    m_walls[s] = boundary.side(s / 2, s % 2).type == BoundaryType::Wall;
    m_open[s] = boundary.side(s / 2, s % 2).type == BoundaryType::Open;
  }
  m_particles.set_walls(m_walls);
  m_centre_velocity = NodeFields(m_level_set.grid(), 0.0, /*smoke=*/false, /*temperature=*/false);
  fill_initial_water(params.at("initial"), up, "/water/initial", m_level_set);
  const auto& sources = params.at("sources");
  for (size_t i = 0; i < sources.size(); ++i) {
    const std::string path = "/water/sources/" + std::to_string(i);
    m_sources.emplace_back(sources[i], path);
    m_sources.back().require_in_domain(grid, path);
  }
  m_held_flow.assign(m_sources.size(), std::numeric_limits<double>::quiet_NaN());
  m_scratch = m_level_set.phi();
  m_valid.assign(m_level_set.phi().size(), 1);
  // The pools' planes and boxes are exact distances; meshes and unions are made one (again
  // at the first step, with its shells).
  m_built = m_level_set.phi();
  m_fast_marching.reinitialize(m_level_set.phi(), m_level_set.band(), ShellGeometry(), nullptr,
                               &m_scratch);
  m_marched_hash = bytes_hash(m_level_set.phi());
  m_parts_on = params.at("cut_cells").get<bool>();
  if (m_parts_on && !params.at("volume_fraction").get<bool>())
    throw ConfigError("/water/cut_cells",
                      "needs /water/volume_fraction true: a part on the far side of a shell "
                      "from its cell's centre has no sample of φ, its water is its F "
                      "(docs/cut-cells.md). Set volume_fraction true or cut_cells false");
  if (m_parts_on && m_particles.enabled())
    throw ConfigError("/water/cut_cells",
                      "particles on cut cells are not in yet (docs/cut-cells.md, C5): set "
                      "/water/particles/per_cell to 0 or cut_cells false");
  if (params.at("volume_fraction").get<bool>()) {
    m_fraction = VolumeFraction(m_level_set);
    m_fraction.set_open(m_open);
  }
  m_initial_volume = volume(nullptr, nullptr);
  m_particles.seed(m_level_set, ShellGeometry());
}

void Liquid::forget_faces_on_shells(const ShellGeometry& shells, const geometry::ShellBand& band) {
  // The shapes' distances see no shell: a water node next to one may hold its distance to a
  // face of its shape that lies on the shell (a box of water on a shelf, a cup's water by
  // its wall), which is no surface. Fast marching holds such a node's |φ| (§4.4.1): a thin
  // layer then reads short, and a cup's wall seeds the march with its distance (still water
  // stirs). Such a node (its nearest shell point as far as its face, to a tenth of a cell:
  // a gap the grid cannot tell from none) is marched again from the surface it sees. A
  // shell that only meets the shape's surface (a plate piercing a pool) is nearer than the
  // surface to the nodes about it.
  const grid::UniformGrid& grid = m_level_set.grid();
  const double dx = grid.dx(), tolerance = 0.1 * dx, deep = m_level_set.band();
  const Eigen::Vector3i n = grid.counts(Location::Node);
  const std::vector<double>& built = m_built;  // φ reads it, and is set below
  auto& phi = m_level_set.phi();
  const auto list = LevelSet::band_samples(band, grid);
  const std::int64_t m = static_cast<std::int64_t>(list.size());
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t s = 0; s < m; ++s) {
    const std::int64_t i = list[s];
    const double p = built[i];
    if (p > 0.0) continue;  // air
    const Eigen::Vector3i ijk = grid.coordinates(Location::Node, i);
    const Eigen::Vector3d x = grid.position(Location::Node, ijk);
    const auto contact = shells.nearest(x, -p + tolerance, x);
    if (!contact) continue;
    // The surface a neighbour it sees across the surface implies: between them, where a
    // plane square to their axis through that neighbour's distance puts it (−∞: none).
    const auto surface_across = [&] {
      const std::uint32_t hidden = shells.hidden_axis_neighbours(grid, ijk);
      double across = -kInfinity;
      for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
          if ((hidden >> (2 * a + side) & 1u) != 0) continue;
          Eigen::Vector3i j = ijk;
          j[a] += side == 0 ? -1 : 1;
          if (j[a] < 0 || j[a] >= n[a]) continue;
          const double q = built[grid.index(Location::Node, j)];
          if (q > 0.0) across = std::max(across, q);
        }
      return across;
    };
    if (p <= -tolerance) {
      // Its nearest shell point as far as its nearest point of the shape: the shell touches
      // the ball of water about the node where the shape's surface does.
      if (contact->distance < -p - tolerance) continue;
    } else {
      // Within a tenth of a cell of its face any nearby shell is that near: the face must
      // lie along the shell, ahead of the node (a box's water line next to its wall is the
      // free surface; a node beyond the shell, in a sliver of the shape it cuts off, is no
      // water of this side). φ's central differences give the face's normal.
      Eigen::Vector3d gradient;
      for (int a = 0; a < 3; ++a) {
        Eigen::Vector3i lo = ijk, hi = ijk;
        lo[a] = std::max(ijk[a] - 1, 0);
        hi[a] = std::min(ijk[a] + 1, n[a] - 1);
        gradient[a] =
            hi[a] == lo[a]
                ? 0.0
                : (built[grid.index(Location::Node, hi)] - built[grid.index(Location::Node, lo)]) /
                      ((hi[a] - lo[a]) * dx);
      }
      const Eigen::Vector3d normal = gradient.normalized();
      const bool along = gradient.norm() > 0.0 && (contact->point - x).dot(normal) > 0.0 &&
                         std::abs(normal.dot(contact->normal)) >= kFaceAlongShell;
      // Where two faces meet by the shell (a cup's water line at its wall) the gradient
      // mixes them: the node keeps its φ unless a surface it sees lies nearer.
      if (!along) {
        const double across = surface_across();
        if (across != -kInfinity) phi[i] = std::min(p, across - dx);
        continue;
      }
    }
    // Deep water, unless a neighbour it sees lies across the surface (its own φ held where
    // the surface is; −band would read it next to the node).
    const double across = surface_across();
    phi[i] = across == -kInfinity ? -deep : std::min(across - dx, 0.0);
  }
}

void Liquid::settle_among_shells(const ShellGeometry& shells, const geometry::ShellBand* band) {
  if (m_built.empty()) return;
  // Unless φ was given since (a test's own field), which is then left as it is.
  if (!shells.empty() && bytes_hash(m_level_set.phi()) == m_marched_hash) {
    m_level_set.phi() = m_built;
    if (band != nullptr) forget_faces_on_shells(shells, *band);
    m_fast_marching.reinitialize(m_level_set.phi(), m_level_set.band(), shells, band, &m_scratch);
    m_particles.seed(m_level_set, shells);  // about that φ, and kept off the shells
    if (m_fraction.enabled()) fit_fraction_among_shells(shells, band);  // and F from it
  }
  std::vector<double>().swap(m_built);
}

void Liquid::fit_fraction_among_shells(const ShellGeometry& shells,
                                       const geometry::ShellBand* band) {
  // With cut cells, a cell a shell may cut keeps the shape's fraction: φ no longer shows a
  // face of the shape that lies on a shell (forget_faces_on_shells), and its fit filled the
  // cell across the shell (a box on a plate 0.18 of a cell above a plane of nodes gained that
  // much per column). Its parts share it as the level set shows the water on each side.
  std::vector<std::pair<std::int64_t, double>> kept;
  if (m_parts_on && band != nullptr) {
    const grid::UniformGrid& grid = m_level_set.grid();
    const double reach = 0.5 * std::sqrt(3.0) * grid.dx();
    for (const std::int64_t i : LevelSet::band_samples(*band, grid))
      if (shells.nearest(grid.position(Location::Node, i), reach, grid.position(Location::Node, i)))
        kept.push_back({i, m_fraction.values()[i]});
  }
  m_fraction.fit(m_level_set, m_scratch);
  for (const auto& [cell, fraction] : kept) m_fraction.values()[cell] = fraction;
}

std::span<const std::uint8_t> Liquid::velocity_nodes(double t, double dt, double max_speed) {
  const grid::UniformGrid& grid = m_level_set.mac_grid();
  const double reach = dt * max_speed + (std::sqrt(3.0) + 1.0) * grid.dx();
  const auto& phi = m_level_set.phi();
  if (reach >= m_level_set.band()) return {};  // the whole band: every node
  // A node lies within √3Δx/2 of the centres of its (up to 8) cells, and φ is a distance:
  // a node is needed where one of its cells is.
  const double node_reach = reach + 0.5 * std::sqrt(3.0) * grid.dx();
  const std::int64_t cells = grid.size(Location::Cell);
  auto& near = m_node_flags[0];
  near.resize(cells);
#pragma omp parallel for schedule(static)
  for (std::int64_t c = 0; c < cells; ++c) near[c] = phi[c] <= node_reach ? 1 : 0;
  spread_to_corners(grid.cells(), near, m_node_flags[1], m_velocity_nodes);
  for (const auto& s : m_sources) {
    if (!s.active(t)) continue;
    const grid::IndexBox box = s.bounding_nodes(grid, reach);
    for (int k = box.lo.z(); k <= box.hi.z(); ++k)
      for (int j = box.lo.y(); j <= box.hi.y(); ++j)
        for (int i = box.lo.x(); i <= box.hi.x(); ++i)
          m_velocity_nodes[grid.index(Location::Node, i, j, k)] = 1;
  }
  return m_velocity_nodes;
}

const NodeFields& Liquid::particle_velocity(const MacGrid& mac) {
  centre_velocities(mac);
  return m_centre_velocity;
}

void Liquid::advect_fraction(double t, const MacGrid& mac, double dt, double max_speed,
                             const ShellGeometry& shells, const geometry::ShellBand* band) {
  // Before the first projection F moves with the faces as they stand, the emitters on now.
  std::vector<grid::IndexBox> on;
  for (const WaterSource& s : m_sources)
    if (s.active(t)) on.push_back(emitter_cells(s));
  mark_cut_cells(shells, band);
  m_fraction.advect(mac, m_level_set, dt, max_speed, on, m_cut_cells);
  m_budget.outflow += m_fraction.stats().outflow;
  m_budget.added += m_fraction.stats().dilated;
}

grid::IndexBox Liquid::emitter_cells(const WaterSource& s) const {
  // Every cell the shape reaches: those whose centres lie within a cell of its box.
  const grid::UniformGrid& mac = m_level_set.mac_grid();
  return mac.samples_in_box(Location::Cell, s.bounds().min().array() - mac.dx(),
                            s.bounds().max().array() + mac.dx());
}

void Liquid::centre_velocities(const MacGrid& mac, double within, int side_cells) {
  const grid::UniformGrid& grid = mac.grid();
  const Eigen::Vector3i cells = grid.cells();
  const auto& phi = m_level_set.phi();
  // The faces the last projection's shells closed (extrapolate()'s 3); none before the first.
  const auto shell_face = [&](int a, const Eigen::Vector3i& f) {
    return !m_known[a].empty() && m_known[a][grid.index(face_location(a), f)] == 3;
  };
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < cells.z(); ++k)
    for (int j = 0; j < cells.y(); ++j)
      for (int i = 0; i < cells.x(); ++i) {
        const std::int64_t cell = grid.index(Location::Cell, i, j, k);
        const Eigen::Vector3i c(i, j, k);
        if (std::abs(phi[cell]) > within &&
            ((c.array() >= side_cells) && (c.array() < cells.array() - side_cells)).all())
          continue;
        for (int a = 0; a < 3; ++a) {
          const auto& u = mac.face_velocity(a);
          Eigen::Vector3i f = c;
          double lower = u[grid.index(face_location(a), f)];
          f[a] += 1;
          double upper = u[grid.index(face_location(a), f)];
          // An air cell against a wall or a shell: its φ moves with the water's velocity
          // continued, as the air's extrapolated faces carry it elsewhere; the wall's face
          // holds the wall's. (Averaged in, a layer landing on a shelf slowed its underside
          // to half its speed while its top kept falling: the layer thinned.)
          if (phi[cell] > 0.0 && cells[a] > 1) {
            const Eigen::Vector3i below = f - Eigen::Vector3i::Unit(a);
            const bool solid_below = f[a] == 1 ? m_walls[2 * a] : shell_face(a, below);
            const bool solid_above = f[a] == cells[a] ? m_walls[2 * a + 1] : shell_face(a, f);
            if (solid_below && !solid_above) lower = upper;
            if (solid_above && !solid_below) upper = lower;
          }
          m_centre_velocity.velocity(a)[cell] = 0.5 * (lower + upper);
        }
      }
}

void Liquid::advect(double t, const MacGrid& mac, double dt, double max_speed,
                    const ShellGeometry& shells, const geometry::ShellBand* band) {
  const auto start = std::chrono::steady_clock::now();
  // φ is traced only within `reach` of the water: a ray moves at most max_speed dt (the
  // centres average the faces) and its stencil reaches √3Δx beyond (2.5Δx: φ is a distance
  // only up to F's corrections). The centres' velocities are made where those rays, their
  // midpoints' stencils and the particles (within 3Δx of the water) read them; among
  // shells everywhere, and near open or inflow sides as far as the advector traces there.
  const double dx = m_level_set.grid().dx(), move = std::abs(max_speed * dt);
  const double reach = move + 2.5 * dx;
  double within = reach + 0.5 * move + 2.0 * dx;
  if (m_particles.enabled()) within = std::max(within, 5.0 * dx + move);
  const bool ruled_sides = m_walls != std::array<bool, 6>{true, true, true, true, true, true};
  if (!shells.empty())
    centre_velocities(mac);
  else
    centre_velocities(mac, within, ruled_sides ? static_cast<int>(std::ceil(within / dx)) + 1 : 0);
  const NodeFields& velocity = m_centre_velocity;
  m_stats = LiquidStats{};
  m_invalid.clear();
  if (m_by_phase) {
    m_phase_shells_n = &shells;
    m_phase_band = band;
    m_phase_budget = m_budget;
    const double start_volume = volume(&shells, band);
    if (!std::isnan(m_phase_end)) m_phase_drift.between_steps += start_volume - m_phase_end;
    m_phase_end = start_volume;
  }
  if (m_fraction.enabled()) advect_fraction(t, mac, dt, max_speed, shells, band);
  // The volume budget's flows over the step, from φ^n.
  const grid::UniformGrid& grid = m_level_set.mac_grid();
  // With a volume fraction the budget counts what F carries out and what the emitters add
  // to it, exactly (below and add_sources()).
  if (!m_fraction.enabled()) m_budget.outflow += open_side_outflow(m_level_set, mac, m_open, dt);
  // An emitter with a velocity adds its fill (its first step) and then the flow its held
  // faces impose; one without, whatever apply() sets (its water leaves by the fluid's
  // velocity and apply() tops it up).
  m_emitter_filling.assign(m_sources.size(), 1);
  for (size_t i = 0; i < m_sources.size() && !m_fraction.enabled(); ++i) {
    const WaterSource& s = m_sources[i];
    if (!s.active(t) || !s.velocity() || !emitter_has_water(m_level_set, s)) continue;
    m_emitter_filling[i] = 0;
    // The emitter and its velocity stay put: its held faces' flow once, at a time it is on.
    if (std::isnan(m_held_flow[i])) m_held_flow[i] = emitter_held_flow(grid, s, t);
    m_budget.added += m_held_flow[i] * dt;
  }
  // φ beyond an open or inflow side is air where its face's flow comes in.
  const BoundaryPhi* ghost = nullptr;
  std::array<bool, 6> ruled;  // the open and inflow sides
  for (int s = 0; s < 6; ++s) ruled[s] = !m_walls[s];
  if (ruled != std::array<bool, 6>{}) {
    m_boundary_phi.update(m_level_set.grid(), mac, ruled);
    if (m_boundary_phi.any()) ghost = &m_boundary_phi;
  }
  m_fast_marching.set_ghost(ghost);  // this step's reinitialisation reads it too
  m_advector.advect(m_level_set.phi(), velocity, dt, shells, band, m_scratch, m_invalid, ghost,
                    reach);
  std::swap(m_level_set.phi(), m_scratch);
  if (m_by_phase) end_phase(m_phase_drift.advection, &shells);  // and again after the emitters
  m_stats.t_level_set += seconds_since(start);
  m_particles.advect(velocity, dt, shells, band);
}

void Liquid::add_sources(double t, DomainBoundary& boundary) {
  const auto start = std::chrono::steady_clock::now();
  m_emitting.clear();
  m_held_sources.clear();
  for (size_t i = 0; i < m_sources.size(); ++i) {
    const WaterSource& s = m_sources[i];
    if (!s.active(t)) continue;
    m_held_sources.push_back(emitter_cells(s));
    const grid::IndexBox reach = emitter_reach(m_level_set, s);
    const bool counted = m_emitter_filling.size() <= i || m_emitter_filling[i] != 0;
    const double before = counted && !m_fraction.enabled() ? m_level_set.volume(reach) : 0.0;
    const std::int64_t nodes = s.apply(t, m_level_set);
    if (m_fraction.enabled())
      m_budget.added += m_fraction.fill(
          [&s](const Eigen::Vector3d& p) { return s.signed_distance(p); }, emitter_cells(s));
    else if (counted)
      m_budget.added += m_level_set.volume(reach) - before;
    m_stats.source_nodes += nodes;
    // Its water gets particles this step (the band's 3Δx about it), not at the next reseed,
    // and loses the air particles it now covers.
    if (nodes > 0) {
      const grid::UniformGrid& mac = m_level_set.mac_grid();  // the particles' boxes
      m_particles.drop_air_in_water(m_level_set, s.bounding_nodes(mac, 0.0));
      m_emitting.push_back(s.bounding_nodes(mac, 3.0 * mac.dx()));
    }
  }
  for (int a = 0; a < 3; ++a) {
    std::vector<SourceFace> faces;
    for (const auto& s : m_sources) s.append_faces(t, m_level_set.mac_grid(), a, faces);
    boundary.set_source_faces(a, std::move(faces));
  }
  if (m_by_phase) end_phase(m_phase_drift.advection, m_phase_shells_n);
  m_stats.t_level_set += seconds_since(start);
}

void Liquid::carry_swept_cells(std::span<const std::int64_t> swept, double dt,
                               const ShellGeometry& shells_n, const ShellGeometry& shells) {
  const NodeFields& velocity = m_centre_velocity;  // what advect() traced with
  // Swept cells hold φ from the other side of the shell (§3); they lie on the side the
  // shell moved away from. A swept cell takes φ^n where the water there came from, on its
  // side of the shell then: back along the shell by its own (refilled) velocity, and
  // across it by its nearest shell point's move over the step, which the water next to
  // the shell keeps up with, or by the water's own move where that lags. A film on a
  // shell thinner than a cell rides along (the neighbours' average, its dry nodes, erased
  // it); the shell's move along itself is left out, as it held the water's edge on a wall
  // moving away. A node with no such point (none near, beyond an open edge, another
  // topology) or nothing visible there is refilled with the others below.
  const grid::UniformGrid& grid = m_level_set.grid();
  const double reach = 3.0 * grid.dx();
  const std::span<const double> phi_n = m_scratch;  // advect() left φ^n there
  auto& phi = m_level_set.phi();
  m_swept_value.assign(swept.size(), kInfinity);  // none yet
  const std::int64_t count = static_cast<std::int64_t>(swept.size());
#pragma omp parallel for schedule(dynamic, 64)
  for (std::int64_t k = 0; k < count; ++k) {
    const std::int64_t i = swept[k];
    const Eigen::Vector3d x = grid.position(Location::Node, i);
    const auto contact = shells.nearest(x, reach, x);
    if (!contact || contact->on_open_edge) continue;  // beyond a hem: no side to keep to
    const auto from = shells_n.point_at(contact->where);
    if (!from) continue;
    const Eigen::Vector3d& normal = contact->normal;
    const Eigen::Vector3d u(velocity.velocity(0)[i], velocity.velocity(1)[i],
                            velocity.velocity(2)[i]);
    // Across the shell: its move, or the water's where that lags it, never faster into
    // it. Water that a shell outran leaves a gap (air), which the node may be in: the
    // move back then ends on the shell's place at n or beyond it, on the wrong side.
    const double moved = normal.dot(contact->point - *from);
    const double across = std::max(moved, dt * normal.dot(u));
    if (contact->distance + moved - across <= 0.0) continue;
    const Eigen::Vector3d back = across * normal + dt * (u - normal.dot(u) * normal);
    if (const auto v = m_advector.sample_visible(phi_n, x - back, shells_n)) m_swept_value[k] = *v;
  }
  for (std::int64_t k = 0; k < count; ++k) {
    if (m_swept_value[k] == kInfinity)
      m_invalid.push_back(swept[k]);
    else
      phi[swept[k]] = m_swept_value[k];
  }
}

void Liquid::refill(std::span<const std::int64_t> swept, double dt, const ShellGeometry& shells_n,
                    const ShellGeometry& shells) {
  const auto start = std::chrono::steady_clock::now();
  if (!swept.empty()) carry_swept_cells(swept, dt, shells_n, shells);
  for (const std::int64_t i : m_invalid) m_valid[i] = 0;
  m_stats.invalid_cells = static_cast<std::int64_t>(m_invalid.size());
  m_advector.refill(m_level_set.phi(), m_valid, m_invalid, shells);
  for (const std::int64_t i : m_invalid) m_valid[i] = 1;
  m_stats.t_level_set += seconds_since(start);
  if (m_by_phase) end_phase(m_phase_drift.shells, &shells);
}

void Liquid::mark_cut_cells(const ShellGeometry& shells, const geometry::ShellBand* band) {
  for (const std::int64_t c : m_cut_list) m_cut_cells[c] = 0;
  m_cut_list.clear();
  if (band == nullptr || shells.empty()) return;
  const grid::UniformGrid& mac = m_level_set.mac_grid();
  m_cut_cells.resize(mac.size(Location::Cell), 0);
  const Eigen::Vector3i cells = mac.cells();
  const auto& hits = shells.cell_face_hits(*band);
  for (int a = 0; a < 3; ++a)
    for (const auto& hit : hits[a]) {
      Eigen::Vector3i c = mac.coordinates(face_location(a), hit.face);
      for (int side = 0; side < 2; ++side, c[a] -= 1) {
        if (c[a] < 0 || c[a] >= cells[a]) continue;
        const std::int64_t cell = mac.index(Location::Cell, c);
        if (m_cut_cells[cell] == 0) m_cut_list.push_back(cell);
        m_cut_cells[cell] = 1;
      }
    }
}

void Liquid::end_phase(double& phase, const ShellGeometry* shells) {
  const double now = volume(shells, m_phase_band);
  phase += now - m_phase_end;
  m_phase_end = now;
}

void Liquid::reinitialize(const ShellGeometry& shells_n, const ShellGeometry& shells,
                          const geometry::ShellBand* band, double t_end) {
  // Enright et al. 2002: the particles correct φ before and after reinitialisation.
  m_particles.collide(m_level_set, shells_n, shells, band);
  m_particles.correct(m_level_set, shells);
  if (m_fraction.enabled()) {
    mark_cut_cells(shells, band);
    m_fraction.correct(m_level_set, m_scratch, false, m_cut_cells);
  }
  const auto start = std::chrono::steady_clock::now();
  m_stats.reinitialization =
      m_fast_marching.reinitialize(m_level_set.phi(), m_level_set.band(), shells, band, &m_scratch);
  m_stats.t_reinitialize = seconds_since(start);
  m_particles.correct(m_level_set, shells);
  m_particles.adjust(m_level_set, shells);
  for (const grid::IndexBox& box : m_emitting) m_particles.top_up(m_level_set, shells, box);
  m_particles.reseed_if_due(t_end, m_level_set, shells);
  m_stats.particles = m_particles.stats();
  // Last, so that the next step's liquid cells are F's whatever the particles made of φ: a
  // cell they made water with no F in it had its faces' outflow clipped (water made).
  if (m_fraction.enabled())
    m_fraction.correct(m_level_set, m_scratch, /*signs_only=*/true, m_cut_cells);
  if (m_by_phase) {
    end_phase(m_phase_drift.reinitialization, &shells);
    // What the budget counted this step (emitters, open sides) is no drift.
    m_phase_drift.advection -=
        (m_budget.added - m_phase_budget.added) - (m_budget.outflow - m_phase_budget.outflow);
  }
}

const FreeSurface& Liquid::surface() {
  m_surface.cell_phi = m_level_set.phi();  // read in place until the next advect()
  return m_surface;
}

double Liquid::volume(const ShellGeometry* shells, const geometry::ShellBand* band) const {
  if (m_fraction.enabled()) return m_fraction.volume();
  const double whole = m_level_set.volume();
  if (shells == nullptr || shells->empty() || band == nullptr) return whole;
  // Each cell a shell cuts counts each side's water with that side's φ (its corners
  // across the shell continued, seen_corner_values), split by the plane of the
  // shell point nearest its centre: a film on a shell thinner than the shell's distance
  // to the next row of nodes holds no wet node, and the one-φ measure missed it.
  const grid::UniformGrid& grid = m_level_set.grid();
  const auto& phi = m_level_set.phi();
  const double dx = grid.dx();
  // φ's lattice cells near the shells: those whose centres are the band's inner nodes (the
  // half-cell strips at the domain's faces hold no shell correction).
  const auto list = band->samples(Location::Node);
  const grid::UniformGrid& mac = m_level_set.mac_grid();
  const std::int64_t m = static_cast<std::int64_t>(list.size());
  const double correction = ordered_sum(m, [&](std::int64_t s) -> double {
    const Eigen::Vector3i c = mac.coordinates(Location::Node, list[s]) - Eigen::Vector3i::Ones();
    if ((c.array() < 0).any() || (c.array() >= grid.cells().array()).any()) return 0.0;
    const Eigen::Vector3d centre = grid.position(Location::Cell, c);
    const NodeStencil st{c, Eigen::Vector3d::Constant(0.5)};
    std::array<double, 8> own, seen, across, side;
    double lowest = kInfinity, highest = -kInfinity;
    for (int k = 0; k < 8; ++k) {
      own[k] = phi[st.corner(grid, k)];
      lowest = std::min(lowest, own[k]);
      highest = std::max(highest, own[k]);
    }
    // φ changes by at most √3Δx from a corner to its mirror node, so a continuation keeps
    // the sign of corners all that far from the surface: both sides dry, or both wet.
    const double reach = std::sqrt(3.0) * dx;
    if (lowest > reach || highest < -reach) return 0.0;
    // The corners the centre sees (its rays cast once, here); the first it does not see
    // that sees any stands on the far side (a corner on the shell, in its wedge, sees none).
    const unsigned near_seen = m_advector.seen_corner_values(phi, centre, st, *shells, seen.data());
    if (near_seen == 0 || near_seen == 0xffu) return 0.0;  // in a wedge, or no corner cut off
    const auto contact = shells->nearest(centre, dx, centre);
    if (!contact) return 0.0;
    unsigned far_seen = 0;
    for (int k = 0; k < 8 && far_seen == 0; ++k)
      if ((near_seen >> k & 1u) == 0)
        far_seen = m_advector.seen_corner_values(
            phi, grid.position(Location::Node, st.corner(grid, k)), st, *shells, across.data());
    if (far_seen == 0) return 0.0;
    // The plane of the shell point nearest the centre parts the cell where it parts the
    // corners as the rays do. Where it does not, a corner neither side sees (a third side:
    // a cup's wall above its bottom; a corner on the shell) or one on the wrong side of the
    // plane (a corner of the cup's polygon), the cell's water is sampled: the plane of the
    // nearer shell switches between a cup's wall and its bottom, and the cells there jumped.
    bool parted = (near_seen | far_seen) == 0xffu;
    for (int k = 0; k < 8; ++k) {
      side[k] = contact->normal.dot(grid.position(Location::Node, st.corner(grid, k)) -
                                    contact->point);  // > 0 on the centre's side
      if ((near_seen >> k & 1u) != 0 ? side[k] < 0.0 : side[k] > 0.0) parted = false;
    }
    if (!parted) return sampled_cell_fraction(c, own, *shells) - LevelSet::cell_fraction(own);
    return LevelSet::two_sided_cell_fraction(across, seen, side) - LevelSet::cell_fraction(own);
  });
  return whole + correction * dx * dx * dx;
}

double Liquid::sampled_cell_fraction(const Eigen::Vector3i& cell, const std::array<double, 8>& own,
                                     const ShellGeometry& shells) const {
  // Each point's water is a plane's through a sub-cell, φ at its centre with |∇φ| = 1
  // (exact for a plane along the lattice, and continuous in φ: the measure does not jump
  // as the surface crosses a point). A point in a wedge sees no corner and is left out.
  constexpr int kPoints = 4;
  const grid::UniformGrid& grid = m_level_set.grid();
  const double h = grid.dx() / kPoints;
  const Eigen::Vector3d low = grid.position(Location::Node, cell);
  double water = 0.0;
  int counted = 0;
  for (int k = 0; k < kPoints; ++k)
    for (int j = 0; j < kPoints; ++j)
      for (int i = 0; i < kPoints; ++i) {
        const Eigen::Vector3d q = low + h * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
        const auto value = m_advector.sample_visible(m_level_set.phi(), q, shells);
        if (!value) continue;
        water += std::clamp(0.5 - *value / h, 0.0, 1.0);
        ++counted;
      }
  return counted > 0 ? water / counted : LevelSet::cell_fraction(own);
}

void Liquid::extrapolate(MacGrid& mac, const PressureProjection& projection,
                         const ShellGeometry& shells, const geometry::ShellBand* band) {
  const auto start = std::chrono::steady_clock::now();
  const grid::UniformGrid& grid = m_level_set.mac_grid();
  const Eigen::Vector3i cells = grid.cells();
  const auto& phi = m_level_set.phi();
  // With F, the faces next to a liquid cell that the extrapolation rewrites keep the
  // projection's values for F (found in the same pass, per plane k, joined in order).
  const bool keep = m_fraction.enabled();
  std::array<std::vector<std::pair<std::int64_t, double>>, 3> kept;
  for (int a = 0; a < 3; ++a) {
    // Known: Neumann faces and the faces the projection set whose φ, the mean of their two
    // cells', is water (PhysBAM's seeds): a face whose surface lies nearer the liquid centre
    // than halfway, θ < ½, took the ghost-fluid update u −= Δp/θ, large as θ → 0, and is
    // continued from the water like the air's faces.
    const Location loc = face_location(a);
    const Eigen::Vector3i n = grid.counts(loc);
    auto& known = m_known[a];
    known.resize(grid.size(loc));
    const auto& neumann = projection.neumann(a);
    const auto& u = mac.face_velocity(a);
    std::vector<std::vector<std::pair<std::int64_t, double>>> planes(keep ? n.z() : 0);
#pragma omp parallel for schedule(static)
    for (int k = 0; k < n.z(); ++k)
      for (int j = 0; j < n.y(); ++j) {
        // The row of faces (·, j, k) and the rows of cells either side of it along a (a
        // domain face's φ is its one cell's: constant continuation).
        const Eigen::Vector3i first(0, j, k);
        Eigen::Vector3i lower = first;
        lower[a] = std::max(first[a] - 1, 0);
        const Eigen::Vector3i upper = first.cwiseMin(cells - Eigen::Vector3i::Ones());
        const std::int64_t f0 = grid.index(loc, first);
        const std::int64_t below0 = grid.index(Location::Cell, lower);
        const std::int64_t above0 = grid.index(Location::Cell, upper);
        for (int i = 0; i < n.x(); ++i) {
          const std::int64_t f = f0 + i;
          // Along x the two cells are i − 1 and i (clamped); across x, the rows' i-th.
          const std::int64_t below = a == 0 ? below0 + std::max(i - 1, 0) : below0 + i;
          const std::int64_t above = a == 0 ? above0 + std::min(i, cells.x() - 1) : above0 + i;
          const bool set = neumann[f] != 0 || phi[above] + phi[below] <= 0.0;
          // 2: a wall's, inflow side's or emitter's face, 3: a shell's.
          known[f] = neumann[f] == 2 ? 3 : neumann[f] != 0 ? 2 : set ? 1 : 0;
          // The projection's liquid cells (φ <= 0, or a film's slot with cut cells).
          if (!keep || known[f] != 0) continue;
          const int along = a == 0 ? i : first[a];
          const bool wet = (along < cells[a] && projection.fluid_cell(above)) ||
                           (along > 0 && projection.fluid_cell(below));
          if (wet) planes[k].push_back({f, u[f]});
        }
      }
    for (const auto& plane : planes) kept[a].insert(kept[a].end(), plane.begin(), plane.end());
  }
  if (keep) m_fraction.keep_projected_faces(std::move(kept), m_held_sources);
  m_stats.extrapolation =
      m_extrapolation.extrapolate(mac, m_known, m_level_set, m_extrapolation_width, shells, band);
  if (m_fraction.enabled()) {
    for (int a = 0; a < 3; ++a)
      for (const FaceApertures::Face& open : projection.apertures().faces(a))
        m_fraction.cut_face(a, open.face, open.fraction, open.shell_velocity);
  }
  m_stats.t_extrapolate = seconds_since(start);
}

}  // namespace shellflow::grid_fluid
