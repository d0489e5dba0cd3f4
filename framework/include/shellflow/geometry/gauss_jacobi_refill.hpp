#pragma once
// GaussJacobiRefill: gives valid values to invalid grid samples (§3, Guendelman et al.
// 2005). Each iteration, every invalid sample with at least one valid *visible*
// one-ring neighbour takes the average of those neighbours and becomes valid; the new
// values are written only after the sweep (Jacobi), so the result does not depend on
// the order of the samples or on threads. Samples that no valid visible neighbour
// reaches (folds, enclosed pockets) are then iterated again with *object values*
// standing in for each neighbour that is not visible: the object velocity, zero
// density, ambient temperature, the distance to the object ... (§3, §4.1).
//
// Generic over the value type T (double, float, Eigen::Vector3d, ...: anything with
// T + T and T * double) and over the grid location (nodes, cells, faces): the one-ring
// of a sample is its six axis neighbours of the same location, reached through
// UniformGrid::index. Visibility and object values come as callables so that the
// caller decides the ray (WedgeCaster::classify, usually) and the stand-in value.

#include <algorithm>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "shellflow/geometry/wedge_caster.hpp"
#include "shellflow/grid/uniform_grid.hpp"

namespace shellflow::geometry {

struct RefillStats {
  int neighbour_iterations = 0;      ///< Gauss–Jacobi sweeps over valid visible neighbours
  int object_iterations = 0;         ///< sweeps that also used object values
  std::int64_t from_neighbours = 0;  ///< samples filled from valid visible neighbours only
  std::int64_t from_object = 0;      ///< samples filled in the object-value sweeps
  std::int64_t isolated = 0;         ///< samples left after both, set to object_value(i, i)
};

class GaussJacobiRefill {
 public:
  /// `max_iterations` bounds each of the two phases (a sweep fills one more layer).
  GaussJacobiRefill(const grid::UniformGrid& grid, grid::Location location, int max_iterations = 32)
      : m_grid(grid), m_location(location), m_max_iterations(max_iterations) {}

  /// Refills `values` (indexed by flat sample index: a span over the grid, or a
  /// grid::SparseSamples holding the candidates and their neighbours) where `valid` is 0,
  /// looking only at the samples listed in
  /// `candidates` (flat indices; e.g. the invalid list of SweptPointInvalidator or a
  /// ShellBand list; entries that are valid are ignored). On return every candidate is
  /// valid.
  ///   visible(from, to) -> bool : is neighbour `to` visible from `from`?
  ///   object_value(from, to) -> T : the value used for a neighbour that is not visible
  ///   (and, with from == to, for an isolated sample).
  /// Both callables are called concurrently from several threads.
  template <class Values, class Visible, class ObjectValue>
  RefillStats run(Values&& values, std::span<std::uint8_t> valid,
                  std::span<const std::int64_t> candidates, Visible&& visible,
                  ObjectValue&& object_value) const {
    using T = std::remove_cvref_t<decltype(values[std::int64_t{0}])>;
    RefillStats stats;
    std::vector<std::int64_t> pending;
    pending.reserve(candidates.size());
    for (const std::int64_t index : candidates) {
      if (valid[index] == 0) pending.push_back(index);
    }
    // Duplicated candidates would be filled twice; drop them.
    std::sort(pending.begin(), pending.end());
    pending.erase(std::unique(pending.begin(), pending.end()), pending.end());

    std::vector<T> next(pending.size());
    std::vector<std::uint8_t> filled(pending.size());
    const Eigen::Vector3i n = m_grid.counts(m_location);
    const std::int64_t stride[3] = {1, n.x(), std::int64_t{n.x()} * n.y()};

    // One Jacobi sweep; `use_object` selects the second phase. Returns samples filled.
    const auto sweep = [&](bool use_object) {
      const std::int64_t count = static_cast<std::int64_t>(pending.size());
      std::int64_t done = 0;
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : done)
      for (std::int64_t s = 0; s < count; ++s) {
        const std::int64_t index = pending[s];
        const Eigen::Vector3i ijk = m_grid.coordinates(m_location, index);
        T sum = zero<T>();
        int terms = 0;
        for (int axis = 0; axis < 3; ++axis) {
          for (const int side : {-1, 1}) {
            const int c = ijk[axis] + side;
            if (c < 0 || c >= n[axis]) continue;
            const std::int64_t neighbour = index + side * stride[axis];
            if (!visible(index, neighbour)) {
              if (use_object) {
                sum = sum + object_value(index, neighbour);
                ++terms;
              }
            } else if (valid[neighbour] != 0) {
              sum = sum + values[neighbour];
              ++terms;
            }
          }
        }
        filled[s] = terms > 0 ? 1 : 0;
        if (terms > 0) {
          next[s] = sum * (1.0 / terms);
          ++done;
        }
      }
      // Write after the sweep (Jacobi) and compact the pending list.
      std::size_t keep = 0;
      for (std::size_t s = 0; s < pending.size(); ++s) {
        if (filled[s] != 0) {
          values[pending[s]] = next[s];
          valid[pending[s]] = 1;
        } else {
          pending[keep++] = pending[s];
        }
      }
      pending.resize(keep);
      return done;
    };

    for (int it = 0; it < m_max_iterations && !pending.empty(); ++it) {
      const std::int64_t done = sweep(false);
      if (done == 0) break;
      ++stats.neighbour_iterations;
      stats.from_neighbours += done;
    }
    for (int it = 0; it < m_max_iterations && !pending.empty(); ++it) {
      const std::int64_t done = sweep(true);
      if (done == 0) break;
      ++stats.object_iterations;
      stats.from_object += done;
    }
    for (const std::int64_t index : pending) {
      values[index] = object_value(index, index);
      valid[index] = 1;
      ++stats.isolated;
    }
    return stats;
  }

  /// visible(from, to) through wedge ray casts between the two sample positions.
  auto wedge_visibility(const WedgeCaster& caster) const {
    return [&caster, grid = m_grid, location = m_location](std::int64_t from, std::int64_t to) {
      return caster.classify(grid.position(location, from), grid.position(location, to)) ==
             Visibility::Visible;
    };
  }

 private:
  template <class T>
  static T zero() {
    if constexpr (std::is_arithmetic_v<T>) {
      return T(0);
    } else {
      return T::Zero();
    }
  }

  grid::UniformGrid m_grid;
  grid::Location m_location;
  int m_max_iterations;
};

}  // namespace shellflow::geometry
