#include "shellflow/mesh_output/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>

#include "shellflow/sdk/error.hpp"

namespace shellflow::mesh_output {

void write_file_atomically(const std::filesystem::path& file,
                           const std::function<void(std::ostream&)>& body) {
  // Hidden, per-process temporary in the same folder (rename across file systems is not
  // atomic); a crashed run may leave one, never a truncated frame under the final name.
  std::string temporary_name = ".";  // appended piecewise: GCC 12 warns on "." + string
  temporary_name.append(file.filename().string()).append(".tmp").append(std::to_string(::getpid()));
  const auto temporary = file.parent_path() / temporary_name;
  auto fail = [&](const std::string& what) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw IoError(file.string() + ": " + what);
  };
  std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
  if (!out) fail(std::string("cannot create the file (") + std::strerror(errno) + ")");
  try {
    body(out);
  } catch (...) {
    out.close();
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
  out.flush();
  if (!out) fail("write failed (disk full?)");
  out.close();
  if (out.fail()) fail("write failed while closing the file (disk full?)");
  std::error_code ec;
  std::filesystem::rename(temporary, file, ec);
  if (ec) fail("cannot move the finished file into place (" + ec.message() + ")");
}

}  // namespace shellflow::mesh_output
