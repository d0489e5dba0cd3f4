#include "shellflow/grid_fluid/water/level_set_state.hpp"

#include <cstdint>
#include <string>

#include "shellflow/sdk/error.hpp"

namespace shellflow::grid_fluid {

namespace {

constexpr std::int64_t kNodesTag = -1;
constexpr std::int64_t kCellsTag = -2;

std::int64_t tag_of(LevelSet::Layout layout) {
  return layout == LevelSet::Layout::Cells ? kCellsTag : kNodesTag;
}

/// The layout in the state and a note on how it was told, before φ's column; `count`
/// receives the column's length when the state is untagged (it was that length).
LevelSet::Layout read_layout(sdk::StateReader& in, std::int64_t& count, std::string& how) {
  const auto first = in.read<std::int64_t>();
  if (first >= 0) {
    count = first;
    how = "; it was saved before the layout was recorded, and all such states are";
    return LevelSet::Layout::Nodes;
  }
  if (first != kNodesTag && first != kCellsTag)
    throw Error("grid_fluid restore(): the saved level set has an unknown layout tag " +
                std::to_string(first) + "; it was saved by another version of grid_fluid");
  count = -1;
  return first == kCellsTag ? LevelSet::Layout::Cells : LevelSet::Layout::Nodes;
}

std::string where(LevelSet::Layout layout) {
  return layout == LevelSet::Layout::Cells ? "on the cell centres" : "on the nodes";
}

}  // namespace

const char* layout_name(LevelSet::Layout layout) {
  return layout == LevelSet::Layout::Cells ? "cells" : "nodes";
}

void save_level_set(sdk::StateWriter& out, const LevelSet& level_set) {
  out.write(tag_of(level_set.layout()));
  const std::vector<double>& phi = level_set.phi();
  out.write_column(phi.data(), static_cast<std::int64_t>(phi.size()));
}

void restore_level_set(sdk::StateReader& in, LevelSet& level_set) {
  std::int64_t count = -1;
  std::string how;
  const LevelSet::Layout saved = read_layout(in, count, how);
  const LevelSet::Layout wanted = level_set.layout();
  if (saved != wanted)
    throw Error(std::string("grid_fluid restore(): the saved state holds the water's level set ") +
                where(saved) + " (/fluid/water/level_set \"" + layout_name(saved) + "\"" + how +
                ") but this scene keeps it " + where(wanted) + " (\"" + layout_name(wanted) +
                "\"); a state restores only into its own layout: set /fluid/water/level_set to \"" +
                layout_name(saved) + "\" to continue it, or start the run afresh (--overwrite)");
  std::vector<double>& phi = level_set.phi();
  const auto wrong_size = [&](std::int64_t n) {
    return Error("grid_fluid restore(): the saved level set has " + std::to_string(n) +
                 " samples, this scene's " + std::to_string(phi.size()) +
                 ": the saved state is for another grid size");
  };
  if (count < 0) {
    Eigen::VectorXd m;
    in.read_matrix(m);
    if (static_cast<size_t>(m.size()) != phi.size()) throw wrong_size(m.size());
    std::copy(m.data(), m.data() + m.size(), phi.data());
    return;
  }
  // Untagged: the rest of the column write_column() wrote (its width, then the values).
  const auto columns = in.read<std::int64_t>();
  if (columns != 1 || static_cast<size_t>(count) != phi.size()) throw wrong_size(count * columns);
  for (double& value : phi) value = in.read<double>();
}

}  // namespace shellflow::grid_fluid
