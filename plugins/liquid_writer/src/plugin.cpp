// Registers the liquid_writer writer (shellflow_liquid_writer.so).
#include "shellflow/sdk/plugin.hpp"
#include "shellflow/liquid_writer/liquid_writer.hpp"

SHELLFLOW_WRITER_PLUGIN(shellflow::liquid_writer::LiquidWriter, "liquid_writer")
