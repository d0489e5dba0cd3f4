#include "preview_movie.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "shellflow/sdk/error.hpp"

namespace shellflow::app {

namespace fs = std::filesystem;

namespace {

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

fs::path find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (!path) return {};
  std::stringstream ss(path);
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    if (dir.empty()) continue;
    const fs::path candidate = fs::path(dir) / name;
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0)
      return candidate;
  }
  return {};
}

PreviewMovie encode_preview_movie(const fs::path& run_dir, std::FILE* progress) {
  const fs::path run_json = run_dir / "run.json";
  std::ifstream in(run_json);
  if (!in)
    throw IoError(run_dir.string() + " is not a shellflow run folder: it has no run.json " +
                  "(give the folder a run wrote, as out/<scene name>)");
  nlohmann::json run;
  try {
    run = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw IoError(run_json.string() + " is not valid JSON: " + e.what());
  }

  // The preview writer's folder and "every" come from the scene the run echoed.
  PreviewMovie movie;
  std::string folder = "previews";
  int every = 1;
  if (run.contains("config") && run["config"].contains("outputs"))
    for (const auto& o : run["config"]["outputs"])
      if (o.value("plugin", "") == "preview_writer") {
        folder = o.value("folder", folder);
        every = std::max(1, o.value("every", 1));
        break;
      }
  movie.previews = run_dir / folder;
  movie.fps = run.value("fps", 24.0) / every;
  movie.file = run_dir / "preview.mp4";

  std::error_code ec;
  if (fs::is_directory(movie.previews, ec))
    for (const auto& e : fs::directory_iterator(movie.previews, ec))
      if (e.is_regular_file() && e.path().extension() == ".png") ++movie.frames;
  if (movie.frames == 0) {
    movie.status = PreviewMovie::Status::NoPreviews;
    movie.message = "no PNG previews in " + movie.previews.string() +
                    " (add {\"plugin\": \"preview_writer\"} to the scene's outputs)";
    return movie;
  }
  const fs::path ffmpeg = find_on_path("ffmpeg");
  if (ffmpeg.empty()) {
    movie.status = PreviewMovie::Status::NoFfmpeg;
    movie.message =
        "ffmpeg is not on PATH, so no preview.mp4 (install it, e.g. apt-get install "
        "ffmpeg, then run `shellflow movie " +
        run_dir.string() + "`)";
    return movie;
  }

  // H.264 in yuv420p, which every player reads; yuv420p needs even sizes, so odd ones are
  // padded by a pixel. The names sort in frame order (<scene>_<frame, 4 digits>.png).
  char fps[32];
  std::snprintf(fps, sizeof fps, "%.9g", movie.fps);
  // -progress writes key=value lines ("frame=12") as it goes: the progress line; anything
  // else on the pipe is ffmpeg's error output.
  const std::string cmd =
      shell_quote(ffmpeg.string()) +
      " -nostdin -hide_banner -loglevel error -nostats -progress pipe:1 -y -framerate " + fps +
      " -pattern_type glob -i " + shell_quote((movie.previews / "*.png").string()) +
      " -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 -pix_fmt yuv420p"
      " -r " +
      fps + " " + shell_quote(movie.file.string()) + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) {
    movie.status = PreviewMovie::Status::Failed;
    movie.message = "could not start " + ffmpeg.string();
    return movie;
  }
  std::string output;
  char line[4096];
  bool progress_shown = false;
  while (std::fgets(line, sizeof line, pipe)) {
    const std::string text(line);
    const size_t eq = text.find('=');
    const bool key_value =
        eq != std::string::npos && eq > 0 &&
        std::all_of(text.begin(), text.begin() + eq,
                    [](char c) { return std::islower(static_cast<unsigned char>(c)) ||
                                        std::isdigit(static_cast<unsigned char>(c)) || c == '_'; });
    if (!key_value) {
      output += text;
    } else if (progress && text.rfind("frame=", 0) == 0) {
      std::fprintf(progress, "\rencoding %s: frame %d of %d", movie.file.filename().c_str(),
                   std::atoi(text.c_str() + 6), movie.frames);
      std::fflush(progress);
      progress_shown = true;
    }
  }
  if (progress_shown) std::fputc('\n', progress);
  const int status = ::pclose(pipe);
  if (status != 0 || !fs::is_regular_file(movie.file, ec)) {
    movie.status = PreviewMovie::Status::Failed;
    movie.message = "ffmpeg could not encode " + movie.previews.string() + " into " +
                    movie.file.string() + (output.empty() ? std::string() : ": " + output);
    while (!movie.message.empty() && movie.message.back() == '\n') movie.message.pop_back();
    return movie;
  }
  movie.status = PreviewMovie::Status::Written;
  return movie;
}

}  // namespace shellflow::app
