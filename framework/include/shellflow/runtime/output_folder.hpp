#pragma once
// The folder a run (or a bench sweep) writes to, and the rule that keeps finished work
// safe: a folder that holds another run (its marker file, run.json) is never written into
// unless the user says --overwrite, and a non-empty folder that is not shellflow's is
// never touched.

#include <filesystem>
#include <string>

namespace shellflow::runtime {

/// What a folder holds, for the rule and its messages.
struct OutputFolderKind {
  std::string what;    ///< "run": "holds no shellflow run", "already holds a run"
  std::string label;   ///< "output folder": how the messages name the folder
  std::string marker;  ///< "run.json": the file that says the folder is one
  std::string shows;   ///< "its run.json": where the user sees what is there
};

/// A run's folder (run.json).
const OutputFolderKind& run_folder_kind();

/// Makes `dir` ready for new work of `kind` (created, or emptied when `overwrite` and it
/// holds that kind's marker). @throw IoError saying what is there and what to do.
void prepare_output_folder(const std::filesystem::path& dir, bool overwrite,
                           const OutputFolderKind& kind = run_folder_kind());

}  // namespace shellflow::runtime
