#include "shellflow/bench/run_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

namespace shellflow::bench {

namespace fs = std::filesystem;

namespace {
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();  // a last empty cell
  return cells;
}
}  // namespace

MetricsTable::MetricsTable(std::vector<std::string> columns, std::vector<std::vector<double>> rows)
    : m_columns(std::move(columns)), m_rows(std::move(rows)) {}

MetricsTable MetricsTable::read(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw IoError("cannot read " + file.string() + ": no such file");
  std::string line;
  if (!std::getline(in, line)) return {};  // stopped before its first step
  MetricsTable table;
  table.m_columns = split(line);
  for (size_t n = 2; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    const auto cells = split(line);
    if (cells.size() != table.m_columns.size())
      throw MeasureError(file.string() + ": line " + std::to_string(n) + " has " +
                         std::to_string(cells.size()) + " cells, the header " +
                         std::to_string(table.m_columns.size()));
    std::vector<double> row(cells.size());
    for (size_t i = 0; i < cells.size(); ++i) {
      // strtod reads "nan" and "inf" as the run wrote them; an empty cell is a figure the
      // plugin did not report at that step.
      char* end = nullptr;
      row[i] = cells[i].empty() ? std::numeric_limits<double>::quiet_NaN()
                                : std::strtod(cells[i].c_str(), &end);
      if (!cells[i].empty() && end && *end != '\0')
        throw MeasureError(file.string() + ": line " + std::to_string(n) + ", column '" +
                           table.m_columns[i] + "': '" + cells[i] + "' is not a number");
    }
    table.m_rows.push_back(std::move(row));
  }
  return table;
}

bool MetricsTable::has(const std::string& column) const {
  return std::find(m_columns.begin(), m_columns.end(), column) != m_columns.end();
}

std::vector<double> MetricsTable::column(const std::string& name) const {
  const auto it = std::find(m_columns.begin(), m_columns.end(), name);
  if (it == m_columns.end()) {
    std::string list;
    for (const auto& c : m_columns) list += (list.empty() ? "" : ", ") + c;
    throw MeasureError("metrics.csv has no column '" + name + "' (columns: " + list + ")");
  }
  const size_t i = static_cast<size_t>(it - m_columns.begin());
  std::vector<double> out;
  out.reserve(m_rows.size());
  for (const auto& row : m_rows) out.push_back(row[i]);
  return out;
}

RunOutputs RunOutputs::read(const fs::path& dir) {
  RunOutputs out;
  std::ifstream in(dir / "run.json");
  if (!in) throw IoError("cannot read " + (dir / "run.json").string());
  try {
    out.run = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw IoError("cannot parse " + (dir / "run.json").string() + ": " + e.what());
  }
  out.metrics = MetricsTable::read(dir / "metrics.csv");
  return out;
}

}  // namespace shellflow::bench
