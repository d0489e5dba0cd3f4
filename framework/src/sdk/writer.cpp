#include "shellflow/sdk/writer.hpp"

#include "shellflow/sdk/error.hpp"

namespace shellflow::sdk {

std::filesystem::path make_output_subfolder(const RunInfo& info, const std::string& name) {
  const std::filesystem::path folder = info.out_dir / name;
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec || !std::filesystem::is_directory(folder))
    throw IoError(folder.string() + ": cannot create the output folder (" +
                  (ec ? ec.message() : std::string("a file of that name exists")) + ")");
  return folder;
}

}  // namespace shellflow::sdk
