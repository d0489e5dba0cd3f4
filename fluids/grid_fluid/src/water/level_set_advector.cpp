#include "shellflow/grid_fluid/water/level_set_advector.hpp"

#include <omp.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "shellflow/geometry/gauss_jacobi_refill.hpp"
#include "shellflow/grid_fluid/water/level_set.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
}  // namespace

void LevelSetAdvector::advect(std::span<const double> in, const NodeFields& velocity, double dt,
                              const ShellGeometry& shells, const geometry::ShellBand* band,
                              std::span<double> out, std::vector<std::int64_t>& invalid,
                              const BoundaryPhi* ghost, double reach) {
  const std::int64_t count = m_grid.size(Location::Node);
  if (!m_maccormack) {
    trace(in, velocity, dt, shells, band, out, nullptr, invalid, ghost, reach);
    return;
  }
  // Selle et al. 2008: forward, then back from the result; half the round trip's error
  // corrects the forward value, clamped to the values its stencil interpolated (no new
  // extremum: water appears only where a visible node of the stencil held some).
  m_range.resize(2 * count);
  m_back.resize(count);
  const std::size_t first_invalid = invalid.size();
  m_clamped.clear();
  trace(in, velocity, dt, shells, band, out, m_range.data(), invalid, ghost, reach, &m_clamped);
  m_back_invalid.clear();
  trace(out, velocity, -dt, shells, band, m_back, nullptr, m_back_invalid, ghost, reach,
        &m_clamped);
  // No correction where either trace saw no visible node, or left the lattice: a ray
  // clamped at a wall makes no round trip, and half its change "corrected" lost the water
  // piling against the wall (on cells, whose first centres move with the water's normal
  // velocity).
  for (std::size_t k = first_invalid; k < invalid.size(); ++k) m_range[2 * invalid[k]] = kNan;
  for (const std::int64_t node : m_back_invalid) m_range[2 * node] = kNan;
  for (const std::int64_t node : m_clamped) m_range[2 * node] = kNan;
#pragma omp parallel for schedule(static)
  for (std::int64_t node = 0; node < count; ++node) {
    const double lo = m_range[2 * node], hi = m_range[2 * node + 1];
    if (std::isnan(lo)) continue;  // invalid: refilled later
    out[node] = std::clamp(out[node] + 0.5 * (in[node] - m_back[node]), lo, hi);
  }
}

void LevelSetAdvector::trace(std::span<const double> in, const NodeFields& velocity, double dt,
                             const ShellGeometry& shells, const geometry::ShellBand* band,
                             std::span<double> out, double* range,
                             std::vector<std::int64_t>& invalid, const BoundaryPhi* ghost,
                             double reach, std::vector<std::int64_t>* clamped) const {
  const std::span<const std::uint8_t> in_band =
      band && !shells.empty() ? LevelSet::band_flags(*band, m_grid) : std::span<const std::uint8_t>();
  const Eigen::Vector3d lower = m_grid.origin();
  const Eigen::Vector3d upper = m_grid.upper();
  const double eps_prime = geometry::WedgeCaster::kSemiLagrangianFactor * shells.epsilon();
  const double midpoint_reach = 3.0 * m_grid.dx();
  const Eigen::Vector3i nodes = m_grid.counts(Location::Node);
  const std::int64_t sy = nodes.x(), sz = std::int64_t(nodes.x()) * nodes.y();
  // With a ghost, the nodes within `reach` of a side (in nodes) are traced whatever φ.
  const int side_nodes =
      ghost == nullptr || !std::isfinite(reach)
          ? 0
          : static_cast<int>(std::min<double>(std::ceil(reach / m_grid.dx()), nodes.maxCoeff()));
  const auto near_side = [&](int i, int j, int k) {
    const Eigen::Vector3i ijk(i, j, k);
    return ((ijk.array() < side_nodes) || (ijk.array() >= nodes.array() - side_nodes)).any();
  };
  std::vector<std::vector<std::int64_t>> per_thread(omp_get_max_threads());
  std::vector<std::vector<std::int64_t>> clamped_per_thread(clamped ? omp_get_max_threads() : 0);
  // Row by row, the corners by offsets (no index arithmetic per corner).
#pragma omp parallel
  {
    std::vector<std::int64_t>& mine = per_thread[omp_get_thread_num()];
#pragma omp for collapse(2) schedule(static)
    for (int k = 0; k < nodes.z(); ++k)
      for (int j = 0; j < nodes.y(); ++j)
        for (int i = 0; i < nodes.x(); ++i) {
          const std::int64_t node = i + sy * j + sz * k;
          const Eigen::Vector3d x = m_grid.position(Location::Node, Eigen::Vector3i(i, j, k));
          const bool banded = !in_band.empty() && in_band[node] != 0;
          if (std::abs(in[node]) > reach && !banded && !near_side(i, j, k)) {
            out[node] = in[node];
            if (range) range[2 * node] = range[2 * node + 1] = kNan;  // nothing to correct
            continue;
          }
          const std::optional<ShellContact> contact =
              banded ? air_contact(x, in[node], shells) : std::nullopt;
          Eigen::Vector3d u = velocity.velocity_at(node);
          if (contact) u = off_shells(x, u, in[node], *contact, in, dt, shells);
          // The midpoint only near the surface: farther than the node's own move and three
          // cells the step cannot change φ's sign, and reinitialisation sets every other
          // value there anew (the Euler ray is as good there, and cheaper).
          if (m_trace == Trace::Midpoint &&
              std::abs(in[node]) < midpoint_reach + std::abs(dt) * u.norm())
            u = midpoint_velocity(x, u, velocity, in, node, dt,
                                  banded ? in_band : std::span<const std::uint8_t>(),
                                  contact ? &*contact : nullptr, shells, eps_prime);
          const Eigen::Vector3d back = x - dt * u;
          const Eigen::Vector3d departure = back.cwiseMax(lower).cwiseMin(upper);
          double* node_range = range ? range + 2 * node : nullptr;
          if (!banded && ghost != nullptr && departure != back) {
            double lo, hi;
            out[node] = ghost->sample(in, back, lo, hi);
            if (node_range) node_range[0] = lo, node_range[1] = hi;
            continue;
          }
          if (clamped != nullptr && departure != back)
            clamped_per_thread[omp_get_thread_num()].push_back(node);
          if (!banded) {
            const NodeStencil st = node_stencil(m_grid, departure);
            const std::int64_t first = st.base.x() + sy * st.base.y() + sz * st.base.z();
            double v = 0.0, lo = kInf, hi = -kInf;
            for (int c = 0; c < 8; ++c) {
              const double value = in[first + m_corner_offset[c]];
              v += st.weight(c) * value;
              lo = std::min(lo, value);
              hi = std::max(hi, value);
            }
            out[node] = v;
            if (node_range) node_range[0] = lo, node_range[1] = hi;
            continue;
          }
          // §4.1 clipped ray, then one secondary ray per cell node (§4.4.1). A ray the
          // shell cuts short slides along it instead: the node velocities next to a shell
          // average faces it closes per axis, so their normal part is not the water's, and
          // a ray stopped at the shell read the film's dry nodes. Where even the slid path
          // is blocked (a fold, a corner), the node takes what lies at the shell, continued
          // constantly: continued linearly, a field flowing off a shell makes water behind it.
          Eigen::Vector3d base = departure;
          bool linear = true;
          if (!shells.visible(x, departure, eps_prime)) {
            if (const auto slid = slide_along_shell(x, departure, dt, shells, eps_prime)) {
              base = *slid;
            } else {
              base = shells.clip(x, departure, eps_prime);
              linear = base == departure;
            }
          }
          const std::optional<double> v = sample_visible(in, base, shells, node_range, linear);
          if (!v) {
            out[node] = in[node];
            mine.push_back(node);
            continue;
          }
          out[node] = *v;
        }
  }
  for (const auto& list : per_thread) invalid.insert(invalid.end(), list.begin(), list.end());
  for (const auto& list : clamped_per_thread) clamped->insert(clamped->end(), list.begin(), list.end());
}

Eigen::Vector3d LevelSetAdvector::midpoint_velocity(
    const Eigen::Vector3d& x, const Eigen::Vector3d& u, const NodeFields& velocity,
    std::span<const double> phi, std::int64_t node, double dt,
    std::span<const std::uint8_t> in_band, const ShellContact* contact, const ShellGeometry& shells,
    double epsilon) const {
  const bool banded = !in_band.empty();
  const Eigen::Vector3d mid = (x - 0.5 * dt * u).cwiseMax(m_grid.origin()).cwiseMin(m_grid.upper());
  if (banded && !shells.visible(x, mid, epsilon)) return u;
  // The nodes near the surface take this path: the corners by offsets from the first (no
  // index arithmetic per corner).
  const NodeStencil st = node_stencil(m_grid, mid);
  const std::int64_t first = st.corner(m_grid, 0);
  const double* v[3] = {velocity.velocity(0).data(), velocity.velocity(1).data(),
                        velocity.velocity(2).data()};
  double sum[3] = {0.0, 0.0, 0.0}, weights = 0.0;
  for (int c = 0; c < 8; ++c) {
    const std::int64_t corner = first + m_corner_offset[c];
    if (banded && in_band[corner] != 0 &&
        !shells.visible(mid, m_grid.position(Location::Node, corner)))
      continue;
    const double w = st.weight(c);
    for (int a = 0; a < 3; ++a) sum[a] += w * v[a][corner];
    weights += w;
  }
  if (!(weights > 0.0)) return u;
  const Eigen::Vector3d at_mid = Eigen::Vector3d(sum[0], sum[1], sum[2]) / weights;
  return contact ? off_shells(x, at_mid, phi[node], *contact, phi, dt, shells) : at_mid;
}

std::optional<ShellContact> LevelSetAdvector::air_contact(const Eigen::Vector3d& x, double p,
                                                          const ShellGeometry& shells) const {
  if (p <= 0.0) return std::nullopt;
  auto contact = shells.nearest(x, m_grid.dx(), x);
  if (!contact || contact->on_open_edge) return std::nullopt;
  return contact;
}

Eigen::Vector3d LevelSetAdvector::off_shells(const Eigen::Vector3d& x, const Eigen::Vector3d& u,
                                             double p, const ShellContact& contact,
                                             std::span<const double> phi, double dt,
                                             const ShellGeometry& shells) const {
  const double normal = (u - contact.velocity).dot(contact.normal);
  // > 0: u moves x off the shell (for dt < 0, the forward trace: onto it).
  const double off = dt > 0.0 ? normal : -normal;
  if (off == 0.0 || (off < 0.0 && !film_beneath(x, p, contact, phi, shells))) return u;
  return u - normal * contact.normal;
}

bool LevelSetAdvector::film_beneath(const Eigen::Vector3d& x, double p, const ShellContact& contact,
                                    std::span<const double> phi,
                                    const ShellGeometry& shells) const {
  // φ a cell further off the shell, on x's side: larger, and its line through x falls
  // below zero before the shell.
  const Eigen::Vector3d further = x + m_grid.dx() * contact.normal;
  if ((further.array() < m_grid.origin().array()).any() ||
      (further.array() > m_grid.upper().array()).any() || !shells.visible(x, further))
    return false;
  const std::optional<double> there = sample_visible(phi, further, shells);
  if (!there || *there <= p) return false;
  return p - (*there - p) / m_grid.dx() * contact.distance < 0.0;
}

std::optional<Eigen::Vector3d> LevelSetAdvector::slide_along_shell(const Eigen::Vector3d& x,
                                                                   const Eigen::Vector3d& departure,
                                                                   double dt,
                                                                   const ShellGeometry& shells,
                                                                   double epsilon) const {
  const auto hit = shells.first_hit(x, departure);
  if (!hit) return std::nullopt;
  Eigen::Vector3d normal = shells.mesh(hit->shell).scaled_normal(hit->triangle);
  if (normal.norm() == 0.0) return std::nullopt;
  normal.normalize();
  // The path back is x − dt·u; without u's normal part relative to the shell, it keeps
  // only the shell's: x − dt·(u − ((u − u_s)·n) n).
  const Eigen::Vector3d back = departure - x;
  const Eigen::Vector3d relative = back + dt * shells.velocity_at(*hit);
  const Eigen::Vector3d slid = (departure - relative.dot(normal) * normal)
                                   .cwiseMax(m_grid.origin())
                                   .cwiseMin(m_grid.upper());
  if (!shells.visible(x, slid, epsilon)) return std::nullopt;
  return slid;
}

unsigned LevelSetAdvector::seen_corner_values(std::span<const double> phi, const Eigen::Vector3d& p,
                                              const NodeStencil& st, const ShellGeometry& shells,
                                              double value[8], bool linear) const {
  unsigned visible = 0;
  for (int c = 0; c < 8; ++c) {
    const std::int64_t corner = st.corner(m_grid, c);
    value[c] = phi[corner];
    if (shells.visible(p, m_grid.position(Location::Node, corner))) visible |= 1u << c;
  }
  if (visible == 0 || visible == 0xffu) return visible;
  const Eigen::Vector3i nodes = m_grid.counts(Location::Node);
  double ghost[8];
  for (int c = 0; c < 8; ++c) {
    if ((visible >> c & 1u) != 0) continue;
    // p's side continued linearly across the shell: through each visible corner d of the
    // nearest ring (an edge, then a face diagonal, then the cell's diagonal away) whose
    // mirror node 2d − c beyond it is seen from p too, 2φ(d) − φ(2d − c), averaged. A film
    // thinner than the shell's distance to the next row of nodes has no wet node on its
    // side; the dry node above it holds less than its distance to the shell, and this
    // continuation is what says the water is there.
    const Eigen::Vector3i node = st.base + corner_step(c);
    double sum = 0.0;
    int terms = 0;
    for (int ring = 1; ring <= 3 && terms == 0 && linear; ++ring)
      for (int d = 0; d < 8; ++d) {
        if ((visible >> d & 1u) == 0 || std::popcount(unsigned(c ^ d)) != ring) continue;
        const Eigen::Vector3i mirror = 2 * (st.base + corner_step(d)) - node;
        if ((mirror.array() < 0).any() || (mirror.array() >= nodes.array()).any()) continue;
        if (!shells.visible(p, m_grid.position(Location::Node, mirror))) continue;
        sum += 2.0 * value[d] - phi[m_grid.index(Location::Node, mirror)];
        ++terms;
      }
    const double continued = terms > 0 ? sum / terms : kInf;
    // The mean of its nearest ring of visible corners (constant continuation).
    sum = 0.0;
    terms = 0;
    for (int ring = 1; ring <= 3 && terms == 0; ++ring)
      for (int d = 0; d < 8; ++d)
        if ((visible >> d & 1u) != 0 && std::popcount(unsigned(c ^ d)) == ring) {
          sum += value[d];
          ++terms;
        }
    // The wetter of the two. Constant continuation erases a film on the shell; linear
    // continuation dries water against a moving wall, whose nodes fast marching holds at
    // a small |φ| (water ending at the wall).
    ghost[c] = std::min(sum / terms, continued);
  }
  for (int c = 0; c < 8; ++c)
    if ((visible >> c & 1u) == 0) value[c] = ghost[c];
  return visible;
}

std::optional<double> LevelSetAdvector::sample_visible(std::span<const double> phi,
                                                       const Eigen::Vector3d& base,
                                                       const ShellGeometry& shells, double* range,
                                                       bool linear) const {
  const NodeStencil st = node_stencil(m_grid, base);
  double value[8];
  if (seen_corner_values(phi, base, st, shells, value, linear) == 0) return std::nullopt;
  double v = 0.0, lo = kInf, hi = -kInf;
  for (int c = 0; c < 8; ++c) {
    v += st.weight(c) * value[c];
    lo = std::min(lo, value[c]);
    hi = std::max(hi, value[c]);
  }
  if (range) range[0] = lo, range[1] = hi;
  return v;
}

void LevelSetAdvector::refill(std::span<double> phi, std::span<std::uint8_t> valid,
                              std::span<const std::int64_t> invalid,
                              const ShellGeometry& shells) const {
  if (invalid.empty()) return;
  const geometry::GaussJacobiRefill refill(m_grid, Location::Node);
  const auto visible = [&](std::int64_t from, std::int64_t to) {
    return shells.visible(m_grid.position(Location::Node, from),
                          m_grid.position(Location::Node, to));
  };
  const auto object_value = [&](std::int64_t from, std::int64_t to) {
    // The positive distance to the object (§4.4.1): air against the shell.
    const Eigen::Vector3d a = m_grid.position(Location::Node, from);
    const Eigen::Vector3d b = m_grid.position(Location::Node, to);
    const auto hit = shells.first_hit(a, b);
    const double d = hit ? hit->s * (b - a).norm() : 0.0;
    return std::max(d, shells.epsilon());
  };
  refill.run(phi, valid, invalid, visible, object_value);
}

}  // namespace shellflow::grid_fluid
