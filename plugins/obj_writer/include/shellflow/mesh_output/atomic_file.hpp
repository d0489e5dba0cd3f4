#pragma once
// Complete files or none: a file is written under a temporary name in its own folder and
// renamed over the final name (rename(2) is atomic within one file system), so a run
// stopped at any moment never leaves half a frame behind.

#include <filesystem>
#include <functional>
#include <ostream>

namespace shellflow::mesh_output {

/// Calls `body` with a binary stream to a temporary file next to `file`, then renames it
/// to `file`. @throw IoError naming `file` when the temporary cannot be created, a write
/// fails (disk full, stream left in a failed state) or the rename fails; the temporary is
/// removed then. Exceptions from `body` propagate after the same clean-up.
void write_file_atomically(const std::filesystem::path& file,
                           const std::function<void(std::ostream&)>& body);

}  // namespace shellflow::mesh_output
