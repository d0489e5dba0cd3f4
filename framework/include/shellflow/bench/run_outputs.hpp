#pragma once
// What a finished run left in its folder, as the error measures read it: metrics.csv
// (one row per step) and run.json (status, resolved scene, totals).

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "shellflow/sdk/error.hpp"

namespace shellflow::bench {

/// A run's outputs lack what a measure needs (a column, a row, a setting).
class MeasureError : public Error {
 public:
  using Error::Error;
};

/// metrics.csv in memory: columns by name, one row per step; an empty cell is NaN.
class MetricsTable {
 public:
  MetricsTable() = default;
  MetricsTable(std::vector<std::string> columns, std::vector<std::vector<double>> rows);

  /// @throw IoError (unreadable), MeasureError (a row with another number of cells).
  static MetricsTable read(const std::filesystem::path& file);

  const std::vector<std::string>& columns() const { return m_columns; }
  size_t rows() const { return m_rows.size(); }
  bool has(const std::string& column) const;
  /// The column's values, one per step. @throw MeasureError naming the columns there are.
  std::vector<double> column(const std::string& name) const;

 private:
  std::vector<std::string> m_columns;
  std::vector<std::vector<double>> m_rows;
};

struct RunOutputs {
  MetricsTable metrics;
  nlohmann::json run;  ///< run.json

  /// Reads `dir`/metrics.csv and `dir`/run.json. @throw IoError, MeasureError.
  static RunOutputs read(const std::filesystem::path& dir);
};

}  // namespace shellflow::bench
