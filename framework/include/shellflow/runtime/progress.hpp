#pragma once
// Progress of a run on a terminal: one line rewritten in place on a TTY, plain lines
// (one per frame) otherwise, so logs and CI output stay readable.

#include <cstdio>
#include <string>

namespace shellflow::runtime {

/// A duration as "mm:ss", or "h:mm:ss" from an hour on; "--:--" when unknown (negative or
/// not finite): the ETA of runs and of bench sweeps.
std::string clock_text(double seconds);

struct Progress {
  int frame = 0;                   ///< frames done
  int frames = 0;                  ///< frames requested
  double sim_time = 0.0;           ///< [s]
  double seconds_per_frame = 0.0;  ///< wall time of the last frame
  double eta_seconds = 0.0;
  long long steps = 0;
};

class ProgressPrinter {
 public:
  /// `interactive` false forces plain lines; by default: is `out` a terminal?
  explicit ProgressPrinter(std::FILE* out);
  ProgressPrinter(std::FILE* out, bool interactive);
  void update(const Progress& p);
  /// Ends the in-place line (before other output and at the end of a run).
  void finish();

 private:
  std::FILE* m_out;
  bool m_interactive;
  bool m_line_open = false;
};

}  // namespace shellflow::runtime
