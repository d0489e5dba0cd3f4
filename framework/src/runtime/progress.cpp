#include "shellflow/runtime/progress.hpp"

#include <unistd.h>

#include <cmath>
#include <string>

namespace shellflow::runtime {

std::string clock_text(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long s = std::lround(seconds);
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%02ld:%02ld", s / 60, s % 60);
  return buf;
}

ProgressPrinter::ProgressPrinter(std::FILE* out) : ProgressPrinter(out, isatty(fileno(out)) != 0) {}
ProgressPrinter::ProgressPrinter(std::FILE* out, bool interactive)
    : m_out(out), m_interactive(interactive) {}

void ProgressPrinter::update(const Progress& p) {
  const double percent = p.frames > 0 ? 100.0 * p.frame / p.frames : 100.0;
  char line[256];
  std::snprintf(line, sizeof line,
                "frame %d/%d (%5.1f%%)  t = %.4g s  %.3g s/frame  %lld steps  ETA %s", p.frame,
                p.frames, percent, p.sim_time, p.seconds_per_frame, p.steps,
                clock_text(p.eta_seconds).c_str());
  if (m_interactive) {
    std::fprintf(m_out, "\r\033[K%s", line);
    m_line_open = true;
  } else {
    std::fprintf(m_out, "%s\n", line);
  }
  std::fflush(m_out);
}

void ProgressPrinter::finish() {
  if (m_line_open) std::fprintf(m_out, "\n");
  m_line_open = false;
  std::fflush(m_out);
}

}  // namespace shellflow::runtime
