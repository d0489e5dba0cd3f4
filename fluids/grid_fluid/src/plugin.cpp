// Registers the grid_fluid fluid solver (shellflow_grid_fluid.so).
#include "shellflow/grid_fluid/grid_fluid_solver.hpp"
#include "shellflow/sdk/plugin.hpp"

SHELLFLOW_FLUID_PLUGIN(shellflow::grid_fluid::GridFluid, "grid_fluid")
