#include "shellflow/grid_fluid/water/fast_marching.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <queue>

#include "shellflow/grid_fluid/water/level_set.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
/// |∇φ| − 1 left uncorrected at an interface node: the central differences' own error on a
/// signed distance whose surface curves with radius 2.5Δx (see reinitialize()).
constexpr double kGradientSlack = 0.05;
}

FastMarching::FastMarching(const grid::UniformGrid& grid) : m_grid(grid) {}

FastMarchingStats FastMarching::reinitialize(std::span<double> phi, double band,
                                             const ShellGeometry& shells,
                                             const geometry::ShellBand* shell_band,
                                             std::vector<double>* scratch) {
  FastMarchingStats stats;
  const std::int64_t count = m_grid.size(Location::Node);
  const Eigen::Vector3i n = m_grid.counts(Location::Node);
  const std::int64_t stride[3] = {1, n.x(), std::int64_t(n.x()) * n.y()};
  const double dx = m_grid.dx();
  if (m_hidden.size() != static_cast<size_t>(count)) {
    m_hidden.assign(count, 0);
    m_accepted.resize(count);
    m_held.resize(count);
  }
  std::vector<double>& distance_of = scratch != nullptr ? *scratch : m_distance;
  distance_of.resize(count);
  for (const std::int64_t i : m_hidden_list) m_hidden[i] = 0;
  m_hidden_list.clear();

  // Which axis neighbours each shell-band node cannot see (rays only there).
  if (shell_band != nullptr && !shells.empty()) {
    const auto list = LevelSet::band_samples(*shell_band, m_grid);
    const std::int64_t m = static_cast<std::int64_t>(list.size());
#pragma omp parallel for schedule(dynamic, 256)
    for (std::int64_t s = 0; s < m; ++s) {
      const std::int64_t i = list[s];
      m_hidden[i] = shells.hidden_axis_neighbours(m_grid, m_grid.coordinates(Location::Node, i));
    }
    for (const std::int64_t i : list)
      if (m_hidden[i] != 0) m_hidden_list.push_back(i);
  }

  // Interface nodes (see the header), accepted at their initial distance; nodes next to
  // a shell are held at no more than their own |φ|.
  std::int64_t interface_nodes = 0;
#pragma omp parallel for schedule(static) reduction(+ : interface_nodes)
  for (std::int64_t i = 0; i < count; ++i) {
    const Eigen::Vector3i ijk = m_grid.coordinates(Location::Node, i);
    const double p = phi[i];
    const bool water = p <= 0.0;
    bool found = false;
    const bool held = m_hidden[i] != 0;
    double nearest_crossing = kInf;  // along an axis: an upper bound on the distance
    double difference[3] = {0.0, 0.0, 0.0};  // φ's difference over the visible neighbours
    int span[3] = {0, 0, 0};                 // over how many cells
    for (int a = 0; a < 3; ++a) {
      double next_to_shell = kInf;  // the difference towards a neighbour next to a shell
      for (int side = 0; side < 2; ++side) {
        const int c = ijk[a] + (side == 0 ? -1 : 1);
        if (c < 0 || c >= n[a]) {
          // Beyond an open or inflow side whose flow comes in: air (BoundaryPhi).
          if (water && m_ghost != nullptr && m_ghost->pulls(2 * a + side, ijk)) {
            found = true;
            nearest_crossing = std::min(nearest_crossing, -BoundaryPhi::pulled_away(p, 0.0, dx));
          }
          continue;
        }
        if ((m_hidden[i] >> (2 * a + side) & 1u) != 0) continue;  // nothing across it
        const std::int64_t j = i + (side == 0 ? -stride[a] : stride[a]);
        if ((phi[j] <= 0.0) != water) {
          found = true;
          nearest_crossing = std::min(nearest_crossing, dx * p / (p - phi[j]));  // > 0
        }
        // A neighbour across the surface and next to a shell holds its |φ| (below), which
        // may be its distance to the shell rather than to the surface: it enters the slope
        // only where nothing else does (left out altogether, more of a film on cloth went).
        if (m_hidden[j] != 0 && (phi[j] <= 0.0) != water) {
          next_to_shell = side == 0 ? p - phi[j] : phi[j] - p;
          continue;
        }
        // A neighbour on this side at the band's end holds no distance (the first φ's deep
        // water next to a shell, which the march sets): it says nothing of the slope.
        if (water && phi[j] <= -band) continue;
        difference[a] += side == 0 ? p - phi[j] : phi[j] - p;
        ++span[a];
      }
      if (span[a] == 0 && next_to_shell != kInf) {
        difference[a] = next_to_shell;
        span[a] = 1;
      }
    }
    // |φ|/|∇φ|: the distance to the zero of φ's linearisation, no farther than the nearest
    // crossing (a thin sheet's φ has no gradient across it). Central differences read |∇φ|
    // low where the surface curves, and divided by every step they pushed the surface out:
    // so |∇φ| within kGradientSlack of 1 counts as 1, and larger departures only beyond it.
    double dist = kInf;
    if (found) {
      double gradient_squared = 0.0;
      for (int a = 0; a < 3; ++a)
        if (span[a] > 0) {
          const double slope = difference[a] / (span[a] * dx);
          gradient_squared += slope * slope;
        }
      const double gradient = std::sqrt(gradient_squared);
      const double departure = gradient - 1.0;
      const double slack = std::copysign(std::min(std::abs(departure), kGradientSlack), departure);
      const double corrected = gradient - slack;
      dist = corrected * nearest_crossing > std::abs(p) ? std::abs(p) / corrected : nearest_crossing;
      dist = std::max(dist, 1e-12 * dx);
    }
    if (held) dist = std::min(dist, std::abs(p));
    m_accepted[i] = found ? 1 : 0;
    m_held[i] = (!found && held) ? 1 : 0;
    distance_of[i] = dist;
    interface_nodes += found ? 1 : 0;
  }
  stats.interface_nodes = interface_nodes;

  // March outwards in |φ| from the interface, each sign on its own side.
  using Entry = std::pair<double, std::int64_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> heap;
  // Second-order upwind (Sethian 1999): along an axis whose two nodes upwind are accepted
  // and ordered, ∂φ ≈ (3d − 4a1 + a2)/(2Δx) = (3/2)(d − (4a1 − a2)/3)/Δx; otherwise first
  // order, (d − a1)/Δx. Second-order values leave the interface nodes' next |φ|/|∇φ|
  // unpolluted (first-order ones overstate |φ| a cell out, and the surface drifted).
  const auto update = [&](std::int64_t i) {
    const Eigen::Vector3i ijk = m_grid.coordinates(Location::Node, i);
    const bool water = phi[i] <= 0.0;
    // The accepted distance of from's neighbour (`from` at index `at` along ax), signed for
    // this side (an interface node across the surface counts negative: the signed distance
    // is smooth across it); +inf where there is none, it lies across a shell, or (unless
    // `across`) it is across.
    const auto upwind = [&](std::int64_t from, int at, int ax, int side, bool across) -> double {
      const int c = at + (side == 0 ? -1 : 1);
      if (c < 0 || c >= n[ax]) return kInf;
      if ((m_hidden[from] >> (2 * ax + side) & 1u) != 0) return kInf;  // never across a shell
      const std::int64_t j = from + (side == 0 ? -stride[ax] : stride[ax]);
      if (m_accepted[j] == 0) return kInf;
      // Second order never reaches through a node next to a shell (its |φ| is held).
      if (across && m_hidden[j] != 0) return kInf;
      if ((phi[j] <= 0.0) == water) return distance_of[j];
      return across ? -distance_of[j] : kInf;
    };
    std::array<std::pair<double, double>, 3> terms;  // (upwind value ã, weight)
    int used = 0;
    for (int ax = 0; ax < 3; ++ax) {
      double best = kInf, weight = 1.0, shifted = kInf;
      for (int side = 0; side < 2; ++side) {
        const double a1 = upwind(i, ijk[ax], ax, side, false);
        if (a1 == kInf) continue;
        double a = a1, w = 1.0;
        const int step = side == 0 ? -1 : 1;
        const double a2 = upwind(i + step * stride[ax], ijk[ax] + step, ax, side, true);
        if (a2 <= a1) {
          a = (4.0 * a1 - a2) / 3.0;
          w = 2.25;
        }
        if (a1 < best) {
          best = a1;
          shifted = a;
          weight = w;
        }
      }
      if (best < kInf) terms[used++] = {shifted, weight};
    }
    if (used == 0) return;
    std::sort(terms.begin(), terms.begin() + used);
    // Σ w_k (d − ã_k)^2 = Δx^2 over the k smallest ã that lie below d.
    double d = kInf;
    double sw = 0.0, swa = 0.0, swa2 = 0.0;
    for (int k = 0; k < used; ++k) {
      const auto [a, w] = terms[k];
      if (k > 0 && d <= a) break;
      sw += w;
      swa += w * a;
      swa2 += w * a * a;
      const double disc = swa * swa - sw * (swa2 - dx * dx);
      d = (swa + std::sqrt(std::max(disc, 0.0))) / sw;
    }
    if (d < distance_of[i]) {
      distance_of[i] = d;
      heap.push({d, i});
    }
  };
  const auto neighbours = [&](std::int64_t i, auto&& f) {
    const Eigen::Vector3i ijk = m_grid.coordinates(Location::Node, i);
    for (int ax = 0; ax < 3; ++ax)
      for (int side = 0; side < 2; ++side) {
        const int c = ijk[ax] + (side == 0 ? -1 : 1);
        if (c < 0 || c >= n[ax]) continue;
        if ((m_hidden[i] >> (2 * ax + side) & 1u) != 0) continue;
        f(i + (side == 0 ? -stride[ax] : stride[ax]));
      }
  };
  for (const std::int64_t i : m_hidden_list)
    if (m_held[i] != 0) heap.push({distance_of[i], i});  // tentative: the march may lower it
  for (std::int64_t i = 0; i < count; ++i)
    if (m_accepted[i] != 0)
      neighbours(i, [&](std::int64_t j) {
        if (m_accepted[j] == 0 && (phi[j] <= 0.0) == (phi[i] <= 0.0)) update(j);
      });
  std::int64_t marched = 0;
  while (!heap.empty()) {
    // Plain names, not a structured binding: the lambda below captures i (clang 14, which
    // the fuzzer and sanitizer builds use, cannot capture structured bindings).
    const double d = heap.top().first;
    const std::int64_t i = heap.top().second;
    heap.pop();
    if (m_accepted[i] != 0 || d > distance_of[i]) continue;  // stale entry
    if (d > band) break;
    m_accepted[i] = 1;
    ++marched;
    neighbours(i, [&](std::int64_t j) {
      if (m_accepted[j] == 0 && (phi[j] <= 0.0) == (phi[i] <= 0.0)) update(j);
    });
  }
  stats.marched_nodes = marched;

#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < count; ++i) {
    const double d = m_accepted[i] != 0 ? std::min(distance_of[i], band) : band;
    phi[i] = phi[i] <= 0.0 ? -d : d;
  }
  return stats;
}

}  // namespace shellflow::grid_fluid
