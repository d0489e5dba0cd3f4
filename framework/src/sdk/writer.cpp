#include "shellflow/sdk/writer.hpp"

#include "shellflow/sdk/error.hpp"

namespace shellflow::sdk {

std::string subfolder_problem(const std::string& folder) {
  const std::string allowed =
      "a writer's folder is a sub-folder of the run's output folder: a relative path "
      "without '..' (such as \"meshes\" or \"previews/front\")";
  if (folder.empty()) return "the folder is empty; " + allowed;
  const std::filesystem::path path(folder);
  if (path.is_absolute() || path.has_root_path())
    return "'" + folder + "' is an absolute path; " + allowed;
  for (const auto& part : path)
    if (part == "..") return "'" + folder + "' holds a '..' component; " + allowed;
  return "";
}

void check_subfolder(const std::string& folder, const std::string& json_path) {
  if (const std::string problem = subfolder_problem(folder); !problem.empty())
    throw ConfigError(json_path, problem);
}

std::filesystem::path make_output_subfolder(const RunInfo& info, const std::string& name) {
  if (const std::string problem = subfolder_problem(name); !problem.empty())
    throw IoError((info.out_dir / name).string() + ": " + problem);
  const std::filesystem::path folder = info.out_dir / name;
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec || !std::filesystem::is_directory(folder))
    throw IoError(folder.string() + ": cannot create the output folder (" +
                  (ec ? ec.message() : std::string("a file of that name exists")) + ")");
  return folder;
}

}  // namespace shellflow::sdk
