#include "shellflow/grid_fluid/water/fast_marching.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace shellflow::grid_fluid {

using grid::Location;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

FastMarching::FastMarching(const grid::UniformGrid& grid) : m_grid(grid) {}

FastMarchingStats FastMarching::reinitialize(std::span<double> phi, double band,
                                             const ShellGeometry& shells,
                                             const geometry::ShellBand* shell_band) {
  FastMarchingStats stats;
  const std::int64_t count = m_grid.size(Location::Node);
  const Eigen::Vector3i n = m_grid.counts(Location::Node);
  const std::int64_t stride[3] = {1, n.x(), std::int64_t(n.x()) * n.y()};
  const double dx = m_grid.dx();
  if (m_hidden.size() != static_cast<size_t>(count)) {
    m_hidden.assign(count, 0);
    m_distance.resize(count);
    m_accepted.resize(count);
    m_held.resize(count);
  }
  for (const std::int64_t i : m_hidden_list) m_hidden[i] = 0;
  m_hidden_list.clear();

  // Which axis neighbours each shell-band node cannot see (rays only there).
  if (shell_band != nullptr && !shells.empty()) {
    const auto list = shell_band->samples(Location::Node);
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
    double inverse_sum = 0.0;
    bool found = false;
    const bool held = m_hidden[i] != 0;
    for (int a = 0; a < 3; ++a) {
      double d = kInf;
      for (int side = 0; side < 2; ++side) {
        const int c = ijk[a] + (side == 0 ? -1 : 1);
        if (c < 0 || c >= n[a]) continue;
        const std::int64_t j = i + (side == 0 ? -stride[a] : stride[a]);
        if ((m_hidden[i] >> (2 * a + side) & 1u) != 0) continue;  // no crossing across it
        if ((phi[j] <= 0.0) != water) d = std::min(d, dx * p / (p - phi[j]));  // > 0
      }
      if (d < kInf) {
        found = true;
        d = std::max(d, 1e-12 * dx);
        inverse_sum += 1.0 / (d * d);
      }
    }
    double dist = found ? 1.0 / std::sqrt(inverse_sum) : kInf;
    if (held) dist = std::min(dist, std::abs(p));
    m_accepted[i] = found ? 1 : 0;
    m_held[i] = (!found && held) ? 1 : 0;
    m_distance[i] = dist;
    interface_nodes += found ? 1 : 0;
  }
  stats.interface_nodes = interface_nodes;

  // March outwards in |φ| from the interface, each sign on its own side.
  using Entry = std::pair<double, std::int64_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> heap;
  const auto update = [&](std::int64_t i) {
    const Eigen::Vector3i ijk = m_grid.coordinates(Location::Node, i);
    const bool water = phi[i] <= 0.0;
    double a[3];
    for (int ax = 0; ax < 3; ++ax) {
      a[ax] = kInf;
      for (int side = 0; side < 2; ++side) {
        const int c = ijk[ax] + (side == 0 ? -1 : 1);
        if (c < 0 || c >= n[ax]) continue;
        if ((m_hidden[i] >> (2 * ax + side) & 1u) != 0) continue;  // never across a shell
        const std::int64_t j = i + (side == 0 ? -stride[ax] : stride[ax]);
        if (m_accepted[j] == 0 || (phi[j] <= 0.0) != water) continue;
        a[ax] = std::min(a[ax], m_distance[j]);
      }
    }
    std::sort(a, a + 3);
    if (a[0] == kInf) return;
    // Upwind quadratic Σ (d − a_k)^2 = dx^2 over the k smallest a that lie below d.
    double d = a[0] + dx;
    if (d > a[1]) {
      const double s = a[0] + a[1];
      const double disc = s * s - 2.0 * (a[0] * a[0] + a[1] * a[1] - dx * dx);
      d = 0.5 * (s + std::sqrt(std::max(disc, 0.0)));
      if (d > a[2]) {
        const double s3 = a[0] + a[1] + a[2];
        const double q = a[0] * a[0] + a[1] * a[1] + a[2] * a[2] - dx * dx;
        const double disc3 = s3 * s3 - 3.0 * q;
        d = (s3 + std::sqrt(std::max(disc3, 0.0))) / 3.0;
      }
    }
    if (d < m_distance[i]) {
      m_distance[i] = d;
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
    if (m_held[i] != 0) heap.push({m_distance[i], i});  // tentative: the march may lower it
  for (std::int64_t i = 0; i < count; ++i)
    if (m_accepted[i] != 0)
      neighbours(i, [&](std::int64_t j) {
        if (m_accepted[j] == 0 && (phi[j] <= 0.0) == (phi[i] <= 0.0)) update(j);
      });
  std::int64_t marched = 0;
  while (!heap.empty()) {
    const auto [d, i] = heap.top();
    heap.pop();
    if (m_accepted[i] != 0 || d > m_distance[i]) continue;  // stale entry
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
    const double d = m_accepted[i] != 0 ? std::min(m_distance[i], band) : band;
    phi[i] = phi[i] <= 0.0 ? -d : d;
  }
  return stats;
}

}  // namespace shellflow::grid_fluid
