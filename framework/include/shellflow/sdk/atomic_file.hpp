#pragma once
// Complete files or none: a file is written under a hidden temporary name in its own
// folder and renamed over the final name (rename(2) is atomic within one file system),
// so a run stopped at any moment never leaves half a file behind. Every writer and the
// runtime's run.json go through here.

#include <filesystem>
#include <functional>
#include <ostream>

namespace shellflow::sdk {

/// Calls `write` with the path of a temporary file next to `file` (for libraries that
/// open files themselves, such as OpenVDB), then renames it to `file`. @throw IoError
/// naming `file` when the rename fails; the temporary is removed on any failure and
/// exceptions from `write` propagate after that clean-up.
void replace_file_atomically(const std::filesystem::path& file,
                             const std::function<void(const std::filesystem::path&)>& write);

/// Calls `body` with a binary stream to a temporary file next to `file`, then renames it
/// to `file`. @throw IoError naming `file` when the temporary cannot be created, a write
/// fails (disk full, stream left in a failed state) or the rename fails.
void write_file_atomically(const std::filesystem::path& file,
                           const std::function<void(std::ostream&)>& body);

}  // namespace shellflow::sdk
