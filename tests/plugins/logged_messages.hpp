#pragma once
// What a test's code logs: spdlog's default logger, which plugins share with the runtime,
// gets a ring-buffer sink for the holder's lifetime.

#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace shellflow::testing {

class LoggedMessages {
 public:
  /// Keeps the last `capacity` messages at `level` or above.
  explicit LoggedMessages(spdlog::level::level_enum level = spdlog::level::trace,
                          size_t capacity = 64)
      : m_sink(std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(capacity)) {
    m_sink->set_level(level);
    spdlog::default_logger()->sinks().push_back(m_sink);
  }
  ~LoggedMessages() {
    auto& sinks = spdlog::default_logger()->sinks();
    sinks.erase(std::remove(sinks.begin(), sinks.end(), m_sink), sinks.end());
  }
  LoggedMessages(const LoggedMessages&) = delete;
  LoggedMessages& operator=(const LoggedMessages&) = delete;

  /// The messages kept, oldest first, each formatted as one line.
  std::vector<std::string> lines() const { return m_sink->last_formatted(); }

 private:
  std::shared_ptr<spdlog::sinks::ringbuffer_sink_mt> m_sink;
};

}  // namespace shellflow::testing
