// Registers the vdb_writer writer (shellflow_vdb_writer.so).
#include "shellflow/sdk/plugin.hpp"
#include "shellflow/vdb_writer/vdb_writer.hpp"

SHELLFLOW_WRITER_PLUGIN(shellflow::vdb_writer::VdbWriter, "vdb_writer")
