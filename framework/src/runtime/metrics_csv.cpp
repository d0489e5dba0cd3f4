#include "shellflow/runtime/metrics_csv.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "shellflow/sdk/error.hpp"

namespace shellflow::runtime {

MetricsCsv::MetricsCsv(const std::filesystem::path& file) : m_file(file) {
  m_out = std::fopen(file.c_str(), "w");
  if (!m_out) throw IoError("cannot create " + file.string());
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
