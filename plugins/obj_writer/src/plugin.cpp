// Registers the obj_writer writer (shellflow_obj_writer.so).
#include "shellflow/sdk/plugin.hpp"
#include "shellflow/obj_writer/obj_writer.hpp"

SHELLFLOW_WRITER_PLUGIN(shellflow::obj_writer::ObjWriter, "obj_writer")
