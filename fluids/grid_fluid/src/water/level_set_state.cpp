#include "shellflow/grid_fluid/water/level_set_state.hpp"

#include <algorithm>
#include <cstdint>
#include <string>

#include "shellflow/sdk/error.hpp"

namespace shellflow::grid_fluid {

namespace {

constexpr std::int64_t kNodesTag = -1;
constexpr std::int64_t kCellsTag = -2;

}  // namespace

void save_level_set(sdk::StateWriter& out, const LevelSet& level_set) {
  out.write(kCellsTag);
  const std::vector<double>& phi = level_set.phi();
  out.write_column(phi.data(), static_cast<std::int64_t>(phi.size()));
}

void restore_level_set(sdk::StateReader& in, LevelSet& level_set) {
  const auto tag = in.read<std::int64_t>();
  if (tag >= 0 || tag == kNodesTag)
    throw Error(
        "grid_fluid restore(): the saved state holds the water's level set on the grid's nodes "
        "(/fluid/water/level_set \"nodes\"), which this version no longer has: φ lives on the "
        "cell centres (docs/water-cell-centres.md). Such a state cannot be continued; start "
        "the run afresh (--overwrite)");
  if (tag != kCellsTag)
    throw Error("grid_fluid restore(): the saved level set has an unknown tag " +
                std::to_string(tag) + "; it was saved by another version of grid_fluid");
  std::vector<double>& phi = level_set.phi();
  Eigen::VectorXd m;
  in.read_matrix(m);
  if (static_cast<size_t>(m.size()) != phi.size())
    throw Error("grid_fluid restore(): the saved level set has " + std::to_string(m.size()) +
                " samples, this scene's " + std::to_string(phi.size()) +
                ": the saved state is for another grid size");
  std::copy(m.data(), m.data() + m.size(), phi.data());
}

}  // namespace shellflow::grid_fluid
