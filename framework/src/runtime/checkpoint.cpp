#include "shellflow/runtime/checkpoint.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <utility>

#include "shellflow/sdk/atomic_file.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::runtime {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

constexpr char kMagic[8] = {'S', 'F', 'C', 'K', 'P', 'T', '0', '1'};
constexpr const char* kPrefix = "step_";
constexpr const char* kExtension = ".ckpt";

std::uint64_t fnv1a(const std::uint8_t* data, size_t n,
                    std::uint64_t h = 14695981039346656037ull) {  // h: to continue a hash
  for (size_t i = 0; i < n; ++i) {
    h ^= data[i];
    h *= 1099511628211ull;
  }
  return h;
}

/// The step of a checkpoint file name, or -1 when it is not one.
long long step_of(const fs::path& file) {
  const std::string name = file.filename().string();
  if (name.rfind(kPrefix, 0) != 0 || file.extension() != kExtension) return -1;
  const std::string digits = file.stem().string().substr(std::strlen(kPrefix));
  if (digits.empty() || !std::all_of(digits.begin(), digits.end(), ::isdigit)) return -1;
  return std::stoll(digits);
}

}  // namespace

fs::path checkpoint_folder(const fs::path& run_dir) {
  return run_dir / "checkpoints";
}

fs::path write_checkpoint(const fs::path& run_dir, const CheckpointMeta& meta,
                          const std::function<void(sdk::StateWriter&)>& save, int keep) {
  const fs::path dir = checkpoint_folder(run_dir);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError("cannot create " + dir.string() + ": " + ec.message());
  char name[64];
  std::snprintf(name, sizeof name, "%s%012lld%s", kPrefix, meta.step, kExtension);
  const fs::path file = dir / name;

  const Json j = {{"step", meta.step},
                  {"next_frame", meta.next_frame},
                  {"time", meta.time},
                  {"frames_written", meta.frames_written},
                  {"last_frame", meta.last_frame},
                  {"metrics_rows", meta.metrics_rows}};
  const std::string text = j.dump();
  // Magic, the metadata and the state's length, then the state itself, then the checksum of
  // all of it. The state is measured first and then streamed to the file from where it
  // lives: assembling it in memory would add a large grid's whole state to the run's peak.
  sdk::StateSizes sizes;
  {
    sdk::StateWriter count(sizes);
    save(count);
  }
  sdk::StateBuffer head;
  sdk::StateWriter out(head);
  std::array<char, sizeof kMagic> magic;
  std::copy(std::begin(kMagic), std::end(kMagic), magic.begin());
  out.write(magic);
  out.write_bytes(sdk::StateBuffer(text.begin(), text.end()));
  out.write<std::uint64_t>(sizes.bytes);
  sdk::write_file_atomically(file, [&](std::ostream& stream) {
    stream.write(reinterpret_cast<const char*>(head.data()),
                 static_cast<std::streamsize>(head.size()));
    std::uint64_t checksum = fnv1a(head.data(), head.size());
    sdk::StateWriter state(
        [&](const std::uint8_t* data, size_t n) {
          stream.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(n));
          checksum = fnv1a(data, n, checksum);
        },
        sizes);
    save(state);
    if (state.size() != sizes.bytes)
      throw Error("checkpoint: the state changed length between the counting pass (" +
                  std::to_string(sizes.bytes) + " bytes) and the write (" +
                  std::to_string(state.size()) + ")");
    stream.write(reinterpret_cast<const char*>(&checksum), sizeof checksum);
  });

  const auto all = list_checkpoints(run_dir);
  for (size_t i = static_cast<size_t>(std::max(keep, 1)); i < all.size(); ++i) {
    fs::remove(all[i], ec);
    if (ec) spdlog::warn("cannot remove the old checkpoint {}: {}", all[i].string(), ec.message());
  }
  return file;
}

std::vector<fs::path> list_checkpoints(const fs::path& run_dir) {
  std::vector<std::pair<long long, fs::path>> found;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(checkpoint_folder(run_dir), ec)) {
    const long long step = step_of(entry.path());
    if (step >= 0 && entry.is_regular_file(ec)) found.emplace_back(step, entry.path());
  }
  std::sort(found.begin(), found.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<fs::path> files;
  for (auto& [_, f] : found) files.push_back(std::move(f));
  return files;
}

Checkpoint read_checkpoint(const fs::path& file) {
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) throw IoError("cannot open checkpoint " + file.string());
  // One buffer the size of the file: the state is cut out of it in place, never copied
  // (336 MB for Fig. 2 at the paper's size, which the solvers' own arrays already hold).
  const std::streamoff size = in.tellg();
  if (size < 0) throw IoError("cannot read checkpoint " + file.string());
  sdk::StateBuffer bytes(static_cast<size_t>(size));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())))
    throw IoError("cannot read checkpoint " + file.string());
  const auto bad = [&](const std::string& why) {
    return IoError("checkpoint " + file.string() + " cannot be used: " + why);
  };
  if (bytes.size() < sizeof kMagic + 3 * sizeof(std::uint64_t) ||
      std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw bad("not a shellflow checkpoint (or cut short)");
  std::uint64_t stored = 0;
  const size_t body_end = bytes.size() - sizeof stored;
  std::memcpy(&stored, bytes.data() + body_end, sizeof stored);
  if (stored != fnv1a(bytes.data(), body_end))
    throw bad("its checksum does not match (the file is damaged or cut short)");
  // Reads a u64 length at `offset` and checks that many bytes follow before the checksum.
  const auto block = [&](size_t offset) {
    std::uint64_t n = 0;
    if (offset + sizeof n > body_end) throw bad("cut short");
    std::memcpy(&n, bytes.data() + offset, sizeof n);
    if (n > body_end - offset - sizeof n) throw bad("a block runs past the end of the file");
    return std::pair{offset + sizeof n, static_cast<size_t>(n)};
  };
  Checkpoint c;
  c.file = file;
  const auto [meta_at, meta_size] = block(sizeof kMagic);
  const auto [state_at, state_size] = block(meta_at + meta_size);
  if (state_at + state_size != body_end) throw bad("trailing bytes after the state");
  try {
    const Json j = Json::parse(bytes.begin() + static_cast<std::ptrdiff_t>(meta_at),
                               bytes.begin() + static_cast<std::ptrdiff_t>(meta_at + meta_size));
    c.meta.step = j.at("step").get<long long>();
    c.meta.next_frame = j.at("next_frame").get<int>();
    c.meta.time = j.at("time").get<double>();
    c.meta.frames_written = j.at("frames_written").get<int>();
    c.meta.last_frame = j.at("last_frame").get<int>();
    c.meta.metrics_rows = j.at("metrics_rows").get<long long>();
  } catch (const std::exception& e) {
    throw bad(e.what());
  }
  bytes.resize(body_end);
  bytes.erase(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(state_at));
  c.state = std::move(bytes);
  return c;
}

}  // namespace shellflow::runtime
