#pragma once
// Checkpoints of a run: the whole state a resumed run needs to continue bit for bit (the
// coupling loop with the fluid's and the solids' save(), the run's counters), written
// into <run folder>/checkpoints/ as complete files or none, the last two kept.
//
// File layout (little-endian, as the machine that wrote it):
//   8 bytes   magic "SFCKPT01"
//   u64 n, n bytes   meta: JSON text (step, frame, time, counters; see CheckpointMeta)
//   u64 m, m bytes   state: CouplingLoop::save()
//   u64       FNV-1a 64 of every byte before it
// A file that is short, has another magic or a wrong checksum fails to read, and resume
// falls back to the older one.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "shellflow/sdk/state_buffer.hpp"

namespace shellflow::runtime {

/// The run's counters at the checkpoint, besides the solvers' state.
struct CheckpointMeta {
  long long step = 0;      ///< steps taken (= metrics.csv rows after its header)
  int next_frame = 1;      ///< the frame the resumed loop works on
  double time = 0.0;       ///< sim time [s]
  int frames_written = 0;  ///< complete frames written so far, frame 0 included
  int last_frame = 0;      ///< the last complete frame
  long long metrics_rows = 0;
};

struct Checkpoint {
  std::filesystem::path file;
  CheckpointMeta meta;
  sdk::StateBuffer state;
};

/// <run folder>/checkpoints
std::filesystem::path checkpoint_folder(const std::filesystem::path& run_dir);

/// Writes checkpoints/step_<step>.ckpt atomically, then removes all but the `keep` newest.
/// The state is what `save` writes: it runs twice, once counting (sdk::StateSizes) and
/// once streaming to the file, so the state is never assembled in memory (336 MB for
/// Fig. 2 at the paper's size). @throw IoError naming the file.
std::filesystem::path write_checkpoint(const std::filesystem::path& run_dir,
                                       const CheckpointMeta& meta,
                                       const std::function<void(sdk::StateWriter&)>& save,
                                       int keep = 2);

/// The checkpoint files of a run, newest (highest step) first.
std::vector<std::filesystem::path> list_checkpoints(const std::filesystem::path& run_dir);

/// Reads one checkpoint. @throw IoError saying why it cannot be used (short, corrupt).
Checkpoint read_checkpoint(const std::filesystem::path& file);

}  // namespace shellflow::runtime
