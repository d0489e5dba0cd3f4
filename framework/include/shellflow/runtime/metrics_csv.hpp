#pragma once
// metrics.csv: one row per step. The columns are fixed by the first row (the runtime's
// own columns, then every plugin's reported figures as "<instance>.<key>"); a figure a
// plugin starts reporting later is left out with one warning, and a missing one is empty.

#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace shellflow::runtime {

class MetricsCsv {
 public:
  explicit MetricsCsv(const std::filesystem::path& file);
  /// Continues the metrics.csv of a resumed run: keeps its header and its first `rows`
  /// rows (the steps before the checkpoint), drops the rest, and appends after them.
  /// @throw IoError when the file holds fewer rows (then it does not fit the checkpoint).
  MetricsCsv(const std::filesystem::path& file, long long rows);
  ~MetricsCsv();
  MetricsCsv(const MetricsCsv&) = delete;
  MetricsCsv& operator=(const MetricsCsv&) = delete;

  /// Appends a row and flushes it, so a stopped run keeps every finished step.
  void write_row(const std::vector<std::pair<std::string, double>>& row);
  const std::vector<std::string>& columns() const { return m_columns; }

 private:
  std::filesystem::path m_file;
  std::FILE* m_out = nullptr;
  std::vector<std::string> m_columns;
  std::vector<std::string> m_warned;
};

}  // namespace shellflow::runtime
