#include "shellflow/grid_fluid/water/particle_level_set.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>

#include "shellflow/geometry/swept_point.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

namespace {

/// Escaped by more than this many radii, an air particle is removed (PhysBAM's
/// PARTICLE_LEVELSET_UNIFORM::Identify_And_Remove_Escaped_Particles, radius_fraction 1.5).
constexpr double kAirRemovedBeyondRadii = 1.5;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// A well-mixed 64-bit seed from the run's seed, the seeding round and the cell
/// (splitmix64's finaliser), so a cell's particles do not depend on the thread order.
std::uint64_t mix(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  std::uint64_t z = a * 0x9E3779B97F4A7C15ull ^
                    (b + 0x632BE59BD9B4E019ull) * 0xBF58476D1CE4E5B9ull ^
                    (c + 0x94D049BB133111EBull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// §4.4.2: the normal component of a water particle's velocity at least the object's, so
/// that the particle gets no nearer to it.
void clamp_normal_velocity(Eigen::Vector3d& u, const ShellContact& contact) {
  const double shortfall = contact.velocity.dot(contact.normal) - u.dot(contact.normal);
  if (shortfall > 0.0) u += shortfall * contact.normal;
}

/// The earliest time in [0, 1] at which a point moving linearly from p0 to p1 meets one of
/// the triangles of `start` moving linearly to `end` (the point's motion is taken off the
/// triangle's: a fixed point against corners moving from x^n to x^{n+1} − (p1 − p0)), with
/// the triangle; none if the path meets none.
struct SweptHit {
  double time = 2.0;
  int triangle = -1;
};
SweptHit first_swept_hit(const geometry::SweptTriangleBvh& swept, const Eigen::Vector3d& p0,
                         const Eigen::Vector3d& p1, double tolerance) {
  SweptHit hit;
  const geometry::Aabb path =
      geometry::Aabb(p0.cwiseMin(p1), p0.cwiseMax(p1)).inflated(tolerance);
  const Eigen::Vector3d motion = p1 - p0;
  swept.triangles_overlapping(path, [&](int t) {
    const geometry::TriangleCorners a = swept.start().corners(t);
    geometry::TriangleCorners b = swept.end().corners(t);
    for (auto& c : b) c -= motion;
    const auto time = geometry::triangle_sweeps_point(p0, a, b, tolerance);
    if (time && *time < hit.time) {
      hit.time = *time;
      hit.triangle = t;
    }
    return false;
  });
  return hit;
}

}  // namespace

sdk::Schema ParticleLevelSet::schema() {
  using sdk::Schema;
  return Schema::object(
             "the particle level set (§4.4.2; Enright et al. 2002, 2005): marker particles "
             "of both signs within 3Δx of the surface that restore the water the level set "
             "alone loses in thin films and sharp features")
      .field("per_cell",
             Schema::integer(0).min(0).max(256).doc(
                 "particles seeded per band cell (PhysBAM: 64 in 3D by default, 8 in the "
                 "paper's water scenes, Thin_Shells_Test_Water); 0, the default for now, is "
                 "the level set alone: a still pool cut by a tilted plate moves at up to "
                 "0.03 m/s with 16 particles per cell (1e-8 m/s without)"))
      .field("reseed_every",
             Schema::integer(10).min(1).unit("frames").doc(
                 "frames between reseedings (§4.4.2: every 10–20; the paper's scenes: 10)"))
      .field("seed", Schema::integer(0).min(0).doc("random seed of the particle positions"));
}

ParticleLevelSet::ParticleLevelSet(const nlohmann::json& params, const grid::UniformGrid& domain,
                                   double fps, const Eigen::Vector3d& gravity)
    : m_grid(LevelSet::cell_centre_lattice(domain)),
      m_domain(domain),
      m_sampler(m_grid),
      m_gravity(gravity) {
  m_per_cell = params.at("per_cell").get<int>();
  m_reseed_every = params.at("reseed_every").get<int>();
  m_seed = params.at("seed").get<std::uint64_t>();
  m_fps = fps;
  const double dx = domain.dx();
  m_band = 3.0 * dx;
  m_r_min = 0.1 * dx;
  m_r_max = 0.5 * dx;
}

std::optional<double> ParticleLevelSet::phi_at(const LevelSet& phi, const Eigen::Vector3d& p,
                                               const ShellGeometry& shells) const {
  if (shells.empty()) return phi.sample(p);
  // None when p sees no node of its cell: it lies in a shell's wedge, on no side.
  return m_sampler.sample_visible(phi.phi(), p, shells);
}

Eigen::Vector3d ParticleLevelSet::velocity_at(const NodeFields& velocity, const Eigen::Vector3d& p,
                                              const ShellGeometry& shells, bool rays) const {
  const NodeStencil st = node_stencil(m_grid, p);
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for (int c = 0; c < 8; ++c) {
    const double w = st.weight(c);
    if (w == 0.0) continue;
    const std::int64_t corner = st.corner(m_grid, c);
    if (rays) {
      const Eigen::Vector3d y = m_grid.position(Location::Node, corner);
      if (!shells.visible(p, y)) {
        u += w * shells.object_velocity(p, y);  // §4.1: the object's velocity behind it
        continue;
      }
    }
    u += w * velocity.velocity_at(corner);
  }
  return u;
}

bool ParticleLevelSet::in_cell_band(std::span<const std::uint8_t> node_flags,
                                    const Eigen::Vector3d& x) const {
  return node_flags[node_stencil(m_grid, x).corner(m_grid, 0)] != 0;
}

std::int64_t ParticleLevelSet::cell_of(std::int64_t i) const {
  const Eigen::Vector3d f =
      (Eigen::Vector3d(m_x[i], m_y[i], m_z[i]) - m_domain.origin()) / m_domain.dx();
  const Eigen::Vector3i n = m_domain.cells();
  Eigen::Vector3i c;
  for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>(std::floor(f[a])), 0, n[a] - 1);
  return m_domain.index(Location::Cell, c);
}

std::size_t ParticleLevelSet::particle_bytes() const {
  std::size_t bytes = m_sign.capacity() * sizeof(std::int8_t);
  for (const std::vector<double>* a :
       {&m_x, &m_y, &m_z, &m_radius, &m_collision, &m_x0, &m_y0, &m_z0, &m_u, &m_v, &m_w})
    bytes += a->capacity() * sizeof(double);
  return bytes;
}

void ParticleLevelSet::compact(const std::vector<std::uint8_t>& keep) {
  const bool paths = m_x0.size() == m_x.size();  // start positions kept in step with them
  const bool velocities = m_u.size() == m_x.size();
  size_t out = 0;
  for (size_t i = 0; i < m_x.size(); ++i) {
    if (keep[i] == 0) continue;
    m_x[out] = m_x[i];
    m_y[out] = m_y[i];
    m_z[out] = m_z[i];
    m_radius[out] = m_radius[i];
    m_collision[out] = m_collision[i];
    m_sign[out] = m_sign[i];
    if (paths) {
      m_x0[out] = m_x0[i];
      m_y0[out] = m_y0[i];
      m_z0[out] = m_z0[i];
    }
    if (velocities) {
      m_u[out] = m_u[i];
      m_v[out] = m_v[i];
      m_w[out] = m_w[i];
    }
    ++out;
  }
  for (auto* v : {&m_x, &m_y, &m_z, &m_radius, &m_collision}) v->resize(out);
  if (paths)
    for (auto* v : {&m_x0, &m_y0, &m_z0}) v->resize(out);
  if (velocities)
    for (auto* v : {&m_u, &m_v, &m_w}) v->resize(out);
  m_sign.resize(out);
}

void ParticleLevelSet::seed(const LevelSet& phi, const ShellGeometry& shells) {
  if (!enabled()) return;
  compact(std::vector<std::uint8_t>(m_x.size(), 0));  // afresh
  seed_cells(phi, shells, false, nullptr);
  m_stats.negative = std::count(m_sign.begin(), m_sign.end(), std::int8_t(-1));
  m_stats.positive = size() - m_stats.negative;
}

void ParticleLevelSet::top_up(const LevelSet& phi, const ShellGeometry& shells,
                              const grid::IndexBox& nodes) {
  if (!enabled() || nodes.empty()) return;
  const auto start = std::chrono::steady_clock::now();
  grid::IndexBox cells{
      nodes.lo.cwiseMax(0),
      (nodes.hi - Eigen::Vector3i::Ones()).cwiseMin(m_domain.cells() - Eigen::Vector3i::Ones())};
  seed_cells(phi, shells, true, &cells);
  m_stats.seconds += seconds_since(start);
}

void ParticleLevelSet::drop_air_in_water(const LevelSet& phi, const grid::IndexBox& nodes) {
  if (!enabled() || nodes.empty()) return;
  const Eigen::Vector3d lo = m_domain.position(Location::Node, nodes.lo);
  const Eigen::Vector3d hi = m_domain.position(Location::Node, nodes.hi);
  std::vector<std::uint8_t> keep(m_x.size(), 1);
  bool any = false;
  for (std::int64_t i = 0; i < size(); ++i) {
    const Eigen::Vector3d x = position(i);
    if (m_sign[i] < 0 || (x.array() < lo.array()).any() || (x.array() > hi.array()).any()) continue;
    if (phi.sample(x) <= 0.0) {
      keep[i] = 0;
      any = true;
    }
  }
  if (any) compact(keep);
}

void ParticleLevelSet::seed_cells(const LevelSet& phi, const ShellGeometry& shells, bool top_up,
                                  const grid::IndexBox* within) {
  const Eigen::Vector3i n = m_domain.cells();
  const std::int64_t cells = m_domain.size(Location::Cell);
  // Particles per cell now (a reseed tops cells up to per_cell and trims them to twice).
  std::vector<int> count(cells, 0);
  std::vector<std::uint8_t> keep(m_x.size(), 1);
  if (top_up)
    for (std::int64_t i = 0; i < size(); ++i) {
      int& c = count[cell_of(i)];
      if (++c > 2 * m_per_cell) keep[i] = 0;
    }
  compact(keep);
  const std::int64_t before = size();
  const double dx = m_grid.dx();
  // A band cell: one of its corners within 3Δx of the surface (Enright et al. 2002).
  std::vector<std::int64_t> band;
  const grid::IndexBox all{Eigen::Vector3i::Zero(), n - Eigen::Vector3i::Ones()};
  const grid::IndexBox& box = within ? *within : all;
  for (int k = box.lo.z(); k <= box.hi.z(); ++k)
    for (int j = box.lo.y(); j <= box.hi.y(); ++j)
      for (int i = box.lo.x(); i <= box.hi.x(); ++i) {
        const std::int64_t cell = m_domain.index(Location::Cell, i, j, k);
        if (count[cell] >= m_per_cell) continue;
        double nearest = std::numeric_limits<double>::infinity();
        for (int c = 0; c < 8; ++c) {
          const Eigen::Vector3i corner(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2));
          // The corners' φ as the lattice interpolates it (continued beyond the outer
          // centres), so that the strips along the walls are seeded too.
          nearest =
              std::min(nearest, std::abs(phi.sample(m_domain.position(Location::Node, corner))));
        }
        if (nearest < m_band) band.push_back(cell);
      }
  for (const std::int64_t cell : band) {
    const Eigen::Vector3d lo =
        m_domain.position(Location::Node, m_domain.coordinates(Location::Cell, cell));
    std::mt19937_64 rng(mix(m_seed, static_cast<std::uint64_t>(m_round), cell));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int s = count[cell]; s < m_per_cell; ++s) {
      Eigen::Vector3d x = lo + dx * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
      const double collision = dx * (0.1 + 0.9 * unit(rng));  // §4.4.2: once, in [0.1Δx, Δx]
      // Seeded ignoring the object, the sign then read from the side the particle is on; a
      // water particle starts its collision distance off the shells, as collide() keeps it.
      std::optional<double> seen = phi_at(phi, x, shells);
      if (seen && *seen <= 0.0 && !shells.empty())
        if (const auto out = off_shells(x, x, collision, shells)) {
          x = *out;
          seen = phi_at(phi, x, shells);
        }
      if (!seen || std::abs(*seen) > m_band) continue;
      const double value = *seen;
      m_x.push_back(x.x());
      m_y.push_back(x.y());
      m_z.push_back(x.z());
      m_sign.push_back(value <= 0.0 ? -1 : 1);
      m_radius.push_back(std::clamp(std::abs(value), m_r_min, m_r_max));
      m_collision.push_back(collision);
    }
  }
  ++m_round;
  m_stats.reseeded += size() - before;
}

bool ParticleLevelSet::stop_at_shells(std::int64_t i, const ShellGeometry& shells) {
  const Eigen::Vector3d start(m_x0[i], m_y0[i], m_z0[i]);
  const Eigen::Vector3d end(m_x[i], m_y[i], m_z[i]);
  const auto hit = shells.first_hit(start, end);
  if (!hit) return true;
  if (m_sign[i] > 0) return false;  // an air particle that crosses a shell is deleted
  // A water particle goes back to its own side, its collision distance off the shell.
  const geometry::TriangleMesh& mesh = shells.mesh(hit->shell);
  const Eigen::Vector3i t = mesh.triangle(hit->triangle);
  const Eigen::Vector3d a = mesh.node(t[0]), b = mesh.node(t[1]), c = mesh.node(t[2]);
  Eigen::Vector3d normal = (b - a).cross(c - a);
  if (normal.norm() == 0.0) return false;
  normal.normalize();
  const Eigen::Vector3d point = start + hit->s * (end - start);
  if (normal.dot(start - point) < 0.0) normal = -normal;
  const Eigen::Vector3d back = point + m_collision[i] * normal;
  if (!shells.visible(start, back)) return false;
  m_x[i] = back.x();
  m_y[i] = back.y();
  m_z[i] = back.z();
  return true;
}

void ParticleLevelSet::advance_spray(double dt, const ShellGeometry& shells) {
  const std::int64_t count = m_spray.size();
  if (count == 0) return;
  const Eigen::Vector3d lower = m_domain.origin(), upper = m_domain.upper();
  std::vector<std::uint8_t> flying(static_cast<size_t>(count), 1);
  std::int64_t landed = 0;
#pragma omp parallel for schedule(static) reduction(+ : landed)
  for (std::int64_t i = 0; i < count; ++i) {
    const Eigen::Vector3d x = m_spray.x(i), u = m_spray.u(i);
    // Exact for constant gravity: free fall between steps.
    const Eigen::Vector3d x1 = x + dt * u + 0.5 * dt * dt * m_gravity;
    const Eigen::Vector3d u1 = u + dt * m_gravity;
    const bool inside = (x1.array() >= lower.array()).all() && (x1.array() <= upper.array()).all();
    if (!inside || (!shells.empty() && shells.first_hit(x, x1))) {
      flying[i] = 0;  // left the domain, or landed on a shell
      ++landed;
      continue;
    }
    for (int a = 0; a < 3; ++a) {
      m_spray.position[a][i] = x1[a];
      m_spray.velocity[a][i] = u1[a];
    }
  }
  if (landed > 0) m_spray.keep(flying);
  m_stats.landed += landed;
}

void ParticleLevelSet::gather(int sign, const NodeFields& velocity, const ShellGeometry& shells,
                              const geometry::ShellBand* band, ParticleArrays& out,
                              const LevelSet* escaped_from) const {
  std::vector<std::uint8_t> take(static_cast<size_t>(size()), 0);
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < size(); ++i) {
    if (m_sign[i] != sign) continue;
    if (escaped_from == nullptr) {
      take[i] = 1;
    } else {
      const std::optional<double> value = phi_at(*escaped_from, position(i), shells);
      take[i] = value && m_sign[i] * *value < -m_radius[i] ? 1 : 0;
    }
  }
  std::vector<std::int64_t> chosen;
  for (std::int64_t i = 0; i < size(); ++i)
    if (take[i] != 0) chosen.push_back(i);
  const std::int64_t n = static_cast<std::int64_t>(chosen.size());
  out.resize(n);
  const std::span<const std::uint8_t> in_band =
      band && !shells.empty() ? LevelSet::band_flags(*band, m_grid) : std::span<const std::uint8_t>();
#pragma omp parallel for schedule(static)
  for (std::int64_t s = 0; s < n; ++s) {
    const Eigen::Vector3d x = position(chosen[s]);
    const bool rays = !in_band.empty() && in_cell_band(in_band, x);
    const Eigen::Vector3d u = velocity_at(velocity, x, shells, rays);
    for (int a = 0; a < 3; ++a) {
      out.position[a][s] = x[a];
      out.velocity[a][s] = u[a];
    }
    out.radius[s] = m_radius[chosen[s]];
  }
}

void ParticleLevelSet::advect(const NodeFields& velocity, double dt, const ShellGeometry& shells_n,
                              const geometry::ShellBand* band) {
  if (!enabled()) return;
  const auto start = std::chrono::steady_clock::now();
  m_stats = ParticleStats{};
  advance_spray(dt, shells_n);
  const std::int64_t count = size();
  m_x0 = m_x;
  m_y0 = m_y;
  m_z0 = m_z;
  for (auto* v : {&m_u, &m_v, &m_w}) v->resize(count);
  const std::span<const std::uint8_t> in_band =
      band && !shells_n.empty() ? LevelSet::band_flags(*band, m_grid) : std::span<const std::uint8_t>();
  const Eigen::Vector3d lower = m_domain.origin(), upper = m_domain.upper();
  std::vector<std::uint8_t> keep(count, 1);
  std::int64_t deleted = 0;
#pragma omp parallel for schedule(static) reduction(+ : deleted)
  for (std::int64_t i = 0; i < count; ++i) {
    const Eigen::Vector3d x(m_x[i], m_y[i], m_z[i]);
    const bool rays = !in_band.empty() && in_cell_band(in_band, x);
    // §4.4.2: forward against the stationary object, the velocity there, averaged.
    const auto sample = [&](const Eigen::Vector3d& p) {
      return velocity_at(velocity, p, shells_n, rays);
    };
    Eigen::Vector3d u1 = sample(x);
    // §4.4.2: a water particle within its collision distance of the object does not close on it.
    const bool water = rays && m_sign[i] < 0;
    const std::optional<ShellContact> near =
        water ? shells_n.nearest(x, m_collision[i], x) : std::nullopt;
    if (near) clamp_normal_velocity(u1, *near);
    Eigen::Vector3d x1 = (x + dt * u1).cwiseMax(lower).cwiseMin(upper);
    bool collided = false;
    if (rays) {
      const Eigen::Vector3d clipped = shells_n.clip(x, x1, shells_n.epsilon());
      collided = clipped != x1;
      x1 = clipped;
    }
    const Eigen::Vector3d u2 = sample(x1);
    Eigen::Vector3d u = 0.5 * (u1 + u2);
    if (water && (near || collided)) {
      // ... and neither does the averaged velocity, if it was near or its forward move met
      // the object (then the contact where it stopped).
      const std::optional<ShellContact> contact =
          near ? near : shells_n.nearest(x1, m_grid.dx(), x);
      if (contact) clamp_normal_velocity(u, *contact);
    }
    Eigen::Vector3d x2 = (x + dt * u).cwiseMax(lower).cwiseMin(upper);
    if (m_sign[i] < 0) keep_off_walls(x, x2, m_collision[i]);
    m_u[i] = u.x();
    m_v[i] = u.y();
    m_w[i] = u.z();
    m_x[i] = x2.x();
    m_y[i] = x2.y();
    m_z[i] = x2.z();
    if (rays && !stop_at_shells(i, shells_n)) {
      keep[i] = 0;
      ++deleted;
    }
  }
  m_stats.deleted_at_shells += deleted;
  if (deleted > 0) compact(keep);
  m_stats.seconds += seconds_since(start);
}

void ParticleLevelSet::keep_off_walls(const Eigen::Vector3d& from, Eigen::Vector3d& to,
                                      double collision) const {
  // A wall node's velocity has no normal part: a water particle that reached a wall's plane
  // stayed there for good and held a film of water on the wall. Kept its collision distance
  // off, or no nearer than it was, as PhysBAM's Adjust_Particle_For_Domain_Boundaries does.
  const Eigen::Vector3d lower = m_domain.origin(), upper = m_domain.upper();
  for (int a = 0; a < 3; ++a) {
    if (m_walls[2 * a]) {
      const double keep = std::max(std::min(collision, from[a] - lower[a]), m_r_min);
      to[a] = std::max(to[a], lower[a] + keep);
    }
    if (m_walls[2 * a + 1]) {
      const double keep = std::max(std::min(collision, upper[a] - from[a]), m_r_min);
      to[a] = std::min(to[a], upper[a] - keep);
    }
  }
}

bool ParticleLevelSet::stop_at_moving_shells(
    std::int64_t i, const ShellGeometry& shells_n, const ShellGeometry& shells_np1,
    const std::vector<geometry::SweptTriangleBvh>& swept) {
  const Eigen::Vector3d p0(m_x0[i], m_y0[i], m_z0[i]);
  const Eigen::Vector3d p1(m_x[i], m_y[i], m_z[i]);
  // Above the positions' round-off, far below the wedge (as the §3 swept invalidation).
  const double tolerance = 1e-3 * shells_np1.epsilon();
  const auto earliest = [&](const Eigen::Vector3d& to) {
    std::pair<int, SweptHit> best{-1, SweptHit{}};
    for (int s = 0; s < static_cast<int>(swept.size()); ++s) {
      const SweptHit h = first_swept_hit(swept[s], p0, to, tolerance);
      if (h.triangle >= 0 && h.time < best.second.time) best = {s, h};
    }
    return best;
  };
  const auto [shell, hit] = earliest(p1);
  if (shell < 0) return true;
  if (m_sign[i] > 0) return false;  // an air particle that crosses a shell is deleted
  // A water particle goes back to the side of the triangle it started on, its collision
  // distance off the triangle's plane at n+1.
  const geometry::TriangleCorners a = shells_n.mesh(shell).corners(hit.triangle);
  const geometry::TriangleCorners b = shells_np1.mesh(shell).corners(hit.triangle);
  const Eigen::Vector3d n0 = shells_n.mesh(shell).scaled_normal(hit.triangle);
  const Eigen::Vector3d n1 = shells_np1.mesh(shell).scaled_normal(hit.triangle);
  const double side = n0.dot(p0 - a[0]);
  if (side == 0.0 || n1.norm() == 0.0) return false;  // on the plane: no side to go back to
  const Eigen::Vector3d normal = (side > 0.0 ? 1.0 : -1.0) * n1.normalized();
  const Eigen::Vector3d on_plane = p1 - normal.dot(p1 - b[0]) * normal;
  const Eigen::Vector3d back =
      (on_plane + m_collision[i] * normal).cwiseMax(m_domain.origin()).cwiseMin(m_domain.upper());
  if (earliest(back).first >= 0) return false;  // the corrected path still crosses
  m_x[i] = back.x();
  m_y[i] = back.y();
  m_z[i] = back.z();
  return true;
}

std::optional<Eigen::Vector3d> ParticleLevelSet::off_shells(const Eigen::Vector3d& p,
                                                            const Eigen::Vector3d& side,
                                                            double collision,
                                                            const ShellGeometry& shells) const {
  const std::optional<ShellContact> c = shells.nearest(p, collision, side);
  if (!c || c->distance >= collision) return std::nullopt;
  const Eigen::Vector3d target =
      (c->point + collision * c->normal).cwiseMax(m_domain.origin()).cwiseMin(m_domain.upper());
  // The move is tested from outside the wedge of the triangle it leaves: if it would cross
  // a shell (another sheet, a fold), the particle stays where it is (§4.4.2).
  const Eigen::Vector3d from = c->point + std::max(c->distance, shells.epsilon()) * c->normal;
  if (!shells.visible(from, target)) return std::nullopt;
  return target;
}

void ParticleLevelSet::collide(const LevelSet& phi, const ShellGeometry& shells_n,
                               const ShellGeometry& shells_np1, const geometry::ShellBand* band) {
  if (!enabled() || shells_np1.empty()) return;
  const auto start = std::chrono::steady_clock::now();
  // The swept test needs the same meshes at both ends of the step.
  std::vector<geometry::SweptTriangleBvh> swept;
  // Shells that did not move need no swept hierarchy: the segment test at n+1 is exact.
  bool same = !shells_n.empty() && shells_n.shell_count() == shells_np1.shell_count();
  bool moved = false;
  for (int s = 0; same && s < shells_np1.shell_count(); ++s) {
    same = shells_n.mesh(s).same_topology(shells_np1.mesh(s));
    moved = moved || (same && shells_n.mesh(s).positions() != shells_np1.mesh(s).positions());
  }
  const bool moving = same && moved;
  if (moving)
    for (int s = 0; s < shells_np1.shell_count(); ++s)
      swept.emplace_back(shells_n.mesh(s), shells_np1.mesh(s));
  const std::span<const std::uint8_t> in_band =
      band ? LevelSet::band_flags(*band, m_grid) : std::span<const std::uint8_t>();
  const std::int64_t count = size();
  std::vector<std::uint8_t> keep(count, 1);
  std::int64_t deleted = 0, kept_off = 0;
#pragma omp parallel for schedule(dynamic, 4096) reduction(+ : deleted, kept_off)
  for (std::int64_t i = 0; i < count; ++i) {
    // Only particles whose cell the band of the shells (at n and n+1) covers can meet one.
    if (!in_band.empty() && !in_cell_band(in_band, position(i)))
      continue;
    const bool stays = moving ? stop_at_moving_shells(i, shells_n, shells_np1, swept)
                              : stop_at_shells(i, shells_np1);
    if (!stays) {
      keep[i] = 0;
      ++deleted;
      continue;
    }
    if (m_sign[i] > 0) continue;
    const std::optional<Eigen::Vector3d> out =
        off_shells(position(i), Eigen::Vector3d(m_x0[i], m_y0[i], m_z0[i]), m_collision[i],
                   shells_np1);
    // Not out of the water by more than its radius: such a move would make it an escaped
    // particle, water where there was none (a still pool cut by a tilted plate stirred).
    const std::optional<double> there = out ? phi_at(phi, *out, shells_np1) : std::nullopt;
    if (there && *there <= m_radius[i]) {
      m_x[i] = out->x();
      m_y[i] = out->y();
      m_z[i] = out->z();
      ++kept_off;
    }
  }
  m_stats.deleted_at_shells += deleted;
  m_stats.kept_off_shells += kept_off;
  if (deleted > 0) compact(keep);
  m_stats.seconds += seconds_since(start);
}

std::int64_t ParticleLevelSet::correct(LevelSet& level_set, const ShellGeometry& shells) {
  if (!enabled()) return 0;
  const auto start = std::chrono::steady_clock::now();
  auto& phi = level_set.phi();
  const std::int64_t count = size();
  std::vector<std::int64_t> escaped;
  {
    std::vector<std::uint8_t> flag(count, 0);
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < count; ++i) {
      const std::optional<double> value = phi_at(level_set, position(i), shells);
      flag[i] = value && m_sign[i] * *value < -m_radius[i] ? 1 : 0;  // wrong side by > r
    }
    for (std::int64_t i = 0; i < count; ++i)
      if (flag[i] != 0) escaped.push_back(i);
  }
  m_stats.escaped += static_cast<std::int64_t>(escaped.size());
  if (m_touched.size() != phi.size()) {
    m_touched.assign(phi.size(), 0);
    m_plus.resize(phi.size());
    m_minus.resize(phi.size());
  }
  std::vector<std::int64_t> touched;
  for (const std::int64_t i : escaped) {
    const Eigen::Vector3d x = position(i);
    const NodeStencil st = node_stencil(m_grid, x);
    for (int c = 0; c < 8; ++c) {
      const std::int64_t node = st.corner(m_grid, c);
      const Eigen::Vector3d y = m_grid.position(Location::Node, node);
      if (!shells.visible(x, y)) continue;  // only nodes the particle sees
      if (m_touched[node] == 0) {
        m_touched[node] = 1;
        m_plus[node] = m_minus[node] = phi[node];
        touched.push_back(node);
      }
      const double sphere = m_sign[i] * (m_radius[i] - (y - x).norm());
      if (m_sign[i] > 0)
        m_plus[node] = std::max(m_plus[node], sphere);
      else
        m_minus[node] = std::min(m_minus[node], sphere);
    }
  }
  std::int64_t changed = 0;
  for (const std::int64_t node : touched) {
    const double value =
        std::abs(m_plus[node]) <= std::abs(m_minus[node]) ? m_plus[node] : m_minus[node];
    changed += value != phi[node] ? 1 : 0;
    phi[node] = value;
    m_touched[node] = 0;
  }
  m_stats.corrected_nodes += changed;
  m_stats.seconds += seconds_since(start);
  return changed;
}

void ParticleLevelSet::adjust(const LevelSet& level_set, const ShellGeometry& shells) {
  if (!enabled()) return;
  const auto start = std::chrono::steady_clock::now();
  {
    // Spray drops back in water have landed.
    std::vector<std::uint8_t> flying(static_cast<size_t>(m_spray.size()), 1);
    std::int64_t landed = 0;
#pragma omp parallel for schedule(static) reduction(+ : landed)
    for (std::int64_t i = 0; i < m_spray.size(); ++i) {
      const std::optional<double> value = phi_at(level_set, m_spray.x(i), shells);
      if (value && *value <= 0.0) {
        flying[i] = 0;
        ++landed;
      }
    }
    if (landed > 0) m_spray.keep(flying);
    m_stats.landed += landed;
  }
  const std::int64_t count = size();
  std::vector<std::uint8_t> keep(count, 1);
  std::vector<std::uint8_t> to_spray(count, 0);
  std::int64_t removed = 0;
#pragma omp parallel for schedule(static) reduction(+ : removed)
  for (std::int64_t i = 0; i < count; ++i) {
    const std::optional<double> value = phi_at(level_set, position(i), shells);
    if (!value) continue;  // in a wedge: left as it is
    const double signed_distance = m_sign[i] * *value;
    if (signed_distance > m_band) {
      keep[i] = 0;  // deep on its own side: no longer near the surface
    } else if (signed_distance < -(m_sign[i] > 0 ? kAirRemovedBeyondRadii * m_radius[i]
                                                  : m_grid.dx())) {
      // Escaped further than the grid can hold. An air particle is dropped beyond 1.5
      // radii: the pressure keeps no bubble, so left in the water it carved the same pocket
      // every step that the flow closed again (PhysBAM's water examples drop them too:
      // removed positive particles unused). A water particle goes as spray beyond a cell: a
      // correction leaves φ at it near 0.6Δx − r, and taken at 1.5 radii as well, the water
      // of sharp features went with them.
      keep[i] = 0;
      removed += m_sign[i] < 0 ? 1 : 0;
      to_spray[i] = m_sign[i] < 0 ? 1 : 0;
    } else {
      m_radius[i] = std::clamp(signed_distance, m_r_min, m_r_max);
    }
  }
  m_stats.removed += removed;
  const bool velocities = m_u.size() == m_x.size();  // else (just restored) the drop rests
  for (std::int64_t i = 0; i < count; ++i)
    if (to_spray[i] != 0)
      m_spray.push_back(
          position(i),
          velocities ? Eigen::Vector3d(m_u[i], m_v[i], m_w[i]) : Eigen::Vector3d::Zero(),
          m_radius[i]);
  m_stats.spray = m_spray.size();
  compact(keep);
  m_stats.seconds += seconds_since(start);
}

void ParticleLevelSet::reseed_if_due(double t, const LevelSet& phi, const ShellGeometry& shells) {
  if (!enabled()) return;
  const auto start = std::chrono::steady_clock::now();
  const std::int64_t frame = static_cast<std::int64_t>(std::floor(t * m_fps + 1e-9));
  if (frame >= m_last_frame + m_reseed_every) {
    m_last_frame = frame;
    seed_cells(phi, shells, true, nullptr);
  }
  m_stats.negative = std::count(m_sign.begin(), m_sign.end(), std::int8_t(-1));
  m_stats.positive = size() - m_stats.negative;
  m_stats.seconds += seconds_since(start);
}

void ParticleLevelSet::save(sdk::StateWriter& out) const {
  const auto write = [&](const std::vector<double>& v) {
    out.write_column(v.data(), static_cast<std::int64_t>(v.size()));
  };
  out.write(m_round);
  out.write(m_last_frame);
  for (const auto* v : {&m_x, &m_y, &m_z, &m_radius, &m_collision}) write(*v);
  Eigen::Matrix<std::int8_t, Eigen::Dynamic, 1> sign =
      Eigen::Map<const Eigen::Matrix<std::int8_t, Eigen::Dynamic, 1>>(m_sign.data(), m_sign.size());
  out.write_matrix(sign);
  m_spray.save(out);
}

void ParticleLevelSet::restore(sdk::StateReader& in) {
  const auto read = [&](std::vector<double>& v) {
    Eigen::VectorXd m;
    in.read_matrix(m);
    v.assign(m.data(), m.data() + m.size());
  };
  m_round = in.read<std::int64_t>();
  m_last_frame = in.read<std::int64_t>();
  for (auto* v : {&m_x, &m_y, &m_z, &m_radius, &m_collision}) read(*v);
  Eigen::Matrix<std::int8_t, Eigen::Dynamic, 1> sign;
  in.read_matrix(sign);
  m_sign.assign(sign.data(), sign.data() + sign.size());
  if (m_sign.size() != m_x.size())
    throw Error("grid_fluid restore(): the saved particles are inconsistent");
  m_x0.clear();
  for (auto* v : {&m_u, &m_v, &m_w}) v->clear();
  m_spray.restore(in);
}

}  // namespace shellflow::grid_fluid
