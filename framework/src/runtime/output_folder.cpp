#include "shellflow/runtime/output_folder.hpp"

#include "shellflow/sdk/error.hpp"

namespace shellflow::runtime {

namespace fs = std::filesystem;

const OutputFolderKind& run_folder_kind() {
  static const OutputFolderKind kind{"run", "output folder", "run.json", "its run.json"};
  return kind;
}

void prepare_output_folder(const fs::path& dir, bool overwrite, const OutputFolderKind& kind) {
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec))
      throw IoError((kind.what == "run" ? std::string("output") : kind.what + " output") +
                    " path " + dir.string() + " exists and is not a folder; choose another --out");
    const bool empty = fs::is_empty(dir, ec);
    const bool holds_one = fs::exists(dir / kind.marker, ec);
    if (!empty && !holds_one)
      throw IoError(kind.label + " " + dir.string() + " is not empty and holds no shellflow " +
                    kind.what + " (no " + kind.marker +
                    "); shellflow will not write into it: choose another --out");
    if (holds_one && !overwrite)
      throw IoError(kind.label + " " + dir.string() + " already holds a " + kind.what + " (see " +
                    kind.shows + "); pass --overwrite to replace it, or --out DIR to write "
                    "elsewhere");
    if (holds_one) {
      for (const auto& entry : fs::directory_iterator(dir, ec)) fs::remove_all(entry.path(), ec);
      if (ec) throw IoError("cannot clear " + dir.string() + " for --overwrite: " + ec.message());
    }
  }
  fs::create_directories(dir, ec);
  if (ec) throw IoError("cannot create " + kind.label + " " + dir.string() + ": " + ec.message());
}

}  // namespace shellflow::runtime
