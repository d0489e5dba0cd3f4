// Registers the preview_writer writer (shellflow_preview_writer.so).
#include "shellflow/sdk/plugin.hpp"
#include "shellflow/preview_writer/preview_writer.hpp"

SHELLFLOW_WRITER_PLUGIN(shellflow::preview_writer::PreviewWriter, "preview_writer")
