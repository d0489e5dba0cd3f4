#pragma once
// Documentation of plugins' parameters, for `shellflow plugins` and docs/plugins.md.

#include <string>

#include "shellflow/sdk/schema.hpp"

namespace shellflow::runtime {

/// One line per parameter: "  name: a number >= 0 [kg/m^2], default 1 — doc", nested
/// objects indented, variant options listed.
std::string format_schema_docs(const sdk::Schema::Json& schema, int indent = 2);

/// The same lines as a nested Markdown list (`shellflow plugins --markdown`).
std::string format_schema_markdown(const sdk::Schema::Json& schema);

}  // namespace shellflow::runtime
