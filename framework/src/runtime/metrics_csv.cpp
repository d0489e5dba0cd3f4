#include "shellflow/runtime/metrics_csv.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "shellflow/sdk/atomic_file.hpp"

#include "shellflow/sdk/error.hpp"

namespace shellflow::runtime {

MetricsCsv::MetricsCsv(const std::filesystem::path& file) : m_file(file) {
  m_out = std::fopen(file.c_str(), "w");
  if (!m_out) throw IoError("cannot create " + file.string());
}

MetricsCsv::MetricsCsv(const std::filesystem::path& file, long long rows) : m_file(file) {
  std::ifstream in(file, std::ios::binary);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  in.close();
  if (lines.empty() && rows == 0) {  // stopped before its first step: start it afresh
    m_out = std::fopen(file.c_str(), "w");
    if (!m_out) throw IoError("cannot create " + file.string());
    return;
  }
  if (lines.empty() || static_cast<long long>(lines.size()) - 1 < rows)
    throw IoError(file.string() + " holds " + std::to_string(lines.empty() ? 0 : lines.size() - 1) +
                  " rows, the checkpoint " + std::to_string(rows) +
                  ": it does not belong to this checkpoint");
  std::stringstream header(lines[0]);
  for (std::string column; std::getline(header, column, ',');) m_columns.push_back(column);
  sdk::write_file_atomically(file, [&](std::ostream& out) {
    for (long long i = 0; i <= rows; ++i) out << lines[static_cast<size_t>(i)] << '\n';
  });
  m_out = std::fopen(file.c_str(), "a");
  if (!m_out) throw IoError("cannot open " + file.string() + " to append");
}

MetricsCsv::~MetricsCsv() {
  if (m_out) std::fclose(m_out);
}

void MetricsCsv::write_row(const std::vector<std::pair<std::string, double>>& row) {
  if (m_columns.empty()) {
    for (const auto& [key, _] : row) m_columns.push_back(key);
    for (size_t i = 0; i < m_columns.size(); ++i)
      std::fprintf(m_out, "%s%s", i ? "," : "", m_columns[i].c_str());
    std::fprintf(m_out, "\n");
  }
  std::vector<const double*> values(m_columns.size(), nullptr);
  for (const auto& [key, value] : row) {
    const auto it = std::find(m_columns.begin(), m_columns.end(), key);
    if (it != m_columns.end()) {
      values[it - m_columns.begin()] = &value;
    } else if (std::find(m_warned.begin(), m_warned.end(), key) == m_warned.end()) {
      m_warned.push_back(key);
      spdlog::warn(
          "metrics.csv: '{}' was first reported after the first step; its column is left out", key);
    }
  }
  for (size_t i = 0; i < values.size(); ++i) {
    if (i) std::fputc(',', m_out);
    if (values[i]) std::fprintf(m_out, "%.17g", *values[i]);
  }
  std::fputc('\n', m_out);
  if (std::fflush(m_out) != 0) throw IoError("cannot write " + m_file.string() + " (disk full?)");
}

}  // namespace shellflow::runtime
