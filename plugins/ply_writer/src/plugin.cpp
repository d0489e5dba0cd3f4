// Registers the ply_writer writer (shellflow_ply_writer.so).
#include "shellflow/sdk/plugin.hpp"
#include "shellflow/ply_writer/ply_writer.hpp"

SHELLFLOW_WRITER_PLUGIN(shellflow::ply_writer::PlyWriter, "ply_writer")
