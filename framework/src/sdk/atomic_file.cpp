#include "shellflow/sdk/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>

#include "shellflow/sdk/error.hpp"

namespace shellflow::sdk {

void replace_file_atomically(const std::filesystem::path& file,
                             const std::function<void(const std::filesystem::path&)>& write) {
  // Hidden, per-process temporary in the same folder (rename across file systems is not
  // atomic); a crashed run may leave one, never a truncated file under the final name.
  std::string temporary_name = ".";  // appended piecewise: GCC 12 warns on "." + string
  temporary_name.append(file.filename().string()).append(".tmp").append(std::to_string(::getpid()));
  const auto temporary = file.parent_path() / temporary_name;
  try {
    write(temporary);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(temporary, file, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw IoError(file.string() + ": cannot move the finished file into place (" + ec.message() +
                  ")");
  }
}

void write_file_atomically(const std::filesystem::path& file,
                           const std::function<void(std::ostream&)>& body) {
  replace_file_atomically(file, [&](const std::filesystem::path& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out)
      throw IoError(file.string() + ": cannot create the file (" + std::strerror(errno) + ")");
    body(out);
    out.flush();
    if (!out) throw IoError(file.string() + ": write failed (disk full?)");
    out.close();
    if (out.fail())
      throw IoError(file.string() + ": write failed while closing the file (disk full?)");
  });
}

}  // namespace shellflow::sdk
