#include "shellflow/runtime/output_folder.hpp"

#include "shellflow/sdk/error.hpp"

namespace shellflow::runtime {

namespace fs = std::filesystem;

void prepare_output_folder(const fs::path& dir, bool overwrite) {
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec))
      throw IoError("output path " + dir.string() +
                    " exists and is not a folder; choose another --out");
    const bool empty = fs::is_empty(dir, ec);
    const bool holds_run = fs::exists(dir / "run.json", ec);
    if (!empty && !holds_run)
      throw IoError("output folder " + dir.string() +
                    " is not empty and holds no shellflow run (no run.json); shellflow will not "
                    "write into it: choose another --out");
    if (holds_run && !overwrite)
      throw IoError("output folder " + dir.string() +
                    " already holds a run (see its run.json); pass --overwrite to replace it, or "
                    "--out DIR to write elsewhere");
    if (holds_run) {
      for (const auto& entry : fs::directory_iterator(dir, ec)) fs::remove_all(entry.path(), ec);
      if (ec) throw IoError("cannot clear " + dir.string() + " for --overwrite: " + ec.message());
    }
  }
  fs::create_directories(dir, ec);
  if (ec) throw IoError("cannot create output folder " + dir.string() + ": " + ec.message());
}

}  // namespace shellflow::runtime
