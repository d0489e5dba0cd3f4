#pragma once
// Human-readable documentation of plugins' parameters, for `shellflow plugins`.

#include <string>

#include "shellflow/sdk/schema.hpp"

namespace shellflow::runtime {

/// One line per parameter: "  name: a number >= 0 [kg/m^2], default 1 — doc", nested
/// objects indented, variant options listed.
std::string format_schema_docs(const sdk::Schema::Json& schema, int indent = 2);

}  // namespace shellflow::runtime
