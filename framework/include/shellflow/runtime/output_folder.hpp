#pragma once
// The folder a run writes to, and the rule that keeps finished runs safe: a folder that
// holds another run (a run.json) is never written into unless the user says --overwrite,
// and a non-empty folder that is not a shellflow run is never touched.

#include <filesystem>
#include <string>

namespace shellflow::runtime {

/// Makes `dir` ready for a new run (created, or emptied when `overwrite` and it holds a
/// run). @throw IoError saying what is there and what to do.
void prepare_output_folder(const std::filesystem::path& dir, bool overwrite);

}  // namespace shellflow::runtime
