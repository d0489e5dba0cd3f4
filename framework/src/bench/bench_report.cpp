#include "shellflow/bench/bench_report.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "shellflow/bench/error_measures.hpp"
#include "shellflow/sdk/atomic_file.hpp"

namespace shellflow::bench {

using Json = nlohmann::json;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string number(double x, const char* format = "%.6g") {
  if (std::isnan(x)) return "";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, x);
  return buf;
}

/// A swept value as a cell: strings without their quotes.
std::string value_text(const Json& v) {
  return v.is_string() ? v.get<std::string>() : v.dump();
}

std::string csv_quoted(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c == '\n' ? ' ' : c;
  }
  return out + "\"";
}

std::string markdown_cell(std::string text) {
  for (auto& c : text)
    if (c == '|' || c == '\n') c = ' ';
  if (text.size() > 120) text = text.substr(0, 117) + "...";
  return text;
}

/// h of a run along a refinement axis.
double spacing_of(const SweepAxis& axis, const Json& value) {
  if (!value.is_number()) return kNaN;
  const double v = value.get<double>();
  return axis.spacing == Spacing::Inverse ? 1.0 / v : v;
}

}  // namespace

double log_log_slope(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (size_t i = 0; i < x.size() && i < y.size(); ++i) {
    if (!(x[i] > 0.0) || !(y[i] > 0.0) || !std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
    ++n;
  }
  const double denominator = n * sxx - sx * sx;
  if (n < 2 || std::abs(denominator) < 1e-300) return kNaN;
  return (n * sxy - sx * sy) / denominator;
}

std::vector<ConvergenceFit> convergence_fits(const BenchSpec& spec,
                                             const std::vector<RunRecord>& records) {
  std::vector<ConvergenceFit> fits;
  for (size_t a = 0; a < spec.axes.size(); ++a) {
    const SweepAxis& axis = spec.axes[a];
    if (axis.spacing == Spacing::None) continue;
    // Group the runs by the values of the other axes.
    std::map<std::string, std::vector<const RunRecord*>> groups;
    for (const auto& r : records) {
      std::string key;
      for (size_t b = 0; b < spec.axes.size(); ++b)
        if (b != a)
          key += (key.empty() ? "" : ", ") + spec.axes[b].label + " = " +
                 value_text(r.point.values[b]);
      groups[key].push_back(&r);
    }
    for (size_t m = 0; m < spec.measures.size(); ++m)
      for (const auto& [fixed, runs] : groups) {
        std::vector<double> h, wall, error;
        for (const RunRecord* r : runs) {
          if (r->outcome != RunOutcome::Completed) continue;
          h.push_back(spacing_of(axis, r->point.values[a]));
          wall.push_back(r->run_seconds);
          error.push_back(r->errors[m]);
        }
        ConvergenceFit fit;
        fit.measure = spec.measures[m].label;
        fit.axis = axis.label;
        fit.fixed = fixed;
        for (size_t i = 0; i < error.size(); ++i)
          if (error[i] > 0.0 && std::isfinite(error[i])) ++fit.points;
        fit.order = log_log_slope(h, error);
        // Only where the cost changes along the axis: a spread of timings below 1.5x is
        // mostly noise (a loaded machine), and its slope would say nothing.
        const auto [lo, hi] = std::minmax_element(wall.begin(), wall.end());
        fit.cost_slope =
            wall.size() >= 2 && *lo > 0.0 && *hi / *lo >= 1.5 ? log_log_slope(wall, error) : kNaN;
        fits.push_back(fit);
      }
  }
  return fits;
}

void write_results_csv(const std::filesystem::path& file, const BenchSpec& spec,
                       const std::vector<RunRecord>& records) {
  sdk::write_file_atomically(file, [&](std::ostream& out) {
    out << "run";
    for (const auto& axis : spec.axes) out << ',' << csv_quoted(axis.label);
    out << ",status,exit_code,wall_s,run_s,steps,s_per_step,peak_mb,sim_time,energy_change";
    for (const auto& m : spec.measures) out << ',' << csv_quoted(m.label);
    out << ",message\n";
    for (const auto& r : records) {
      out << r.point.id;
      for (const auto& v : r.point.values) out << ',' << csv_quoted(value_text(v));
      out << ',' << to_string(r.outcome) << ',' << r.exit_code << ','
          << number(r.wall_seconds, "%.4f") << ',' << number(r.run_seconds, "%.4f") << ','
          << r.steps << ',' << number(r.seconds_per_step(), "%.6g") << ','
          << number(r.peak_mb, "%.1f") << ',' << number(r.sim_time) << ','
          << number(r.energy_change, "%+.4g");
      for (const double e : r.errors) out << ',' << number(e, "%.6e");
      out << ',' << csv_quoted(r.message) << '\n';
    }
  });
}

void write_results_markdown(const std::filesystem::path& file, const BenchSpec& spec,
                            const std::vector<RunRecord>& records, const std::string& conditions) {
  sdk::write_file_atomically(file, [&](std::ostream& out) {
    out << "# Bench " << spec.name << "\n\n";
    if (!spec.description.empty()) out << spec.description << "\n\n";
    out << "Base scene `" << spec.scene_file.filename().string() << "`";
    if (spec.frames) out << ", " << *spec.frames << " frames per run";
    out << ".";
    if (!conditions.empty()) out << " " << conditions;
    if (!spec.measures.empty()) out << " Errors:";
    for (const auto& m : spec.measures) {
      const ErrorMeasure* d = find_error_measure(m.measure);
      out << "\n- `" << m.label << "` (" << m.measure << ", " << d->unit << "): " << d->doc
          << "; reference: " << d->reference;
    }
    out << "\n\n|";
    for (const auto& axis : spec.axes) out << " " << markdown_cell(axis.pointer) << " |";
    out << " status | run [s] | steps | s/step | peak [MB] |";
    bool energy = false;
    for (const auto& r : records) energy = energy || !std::isnan(r.energy_change);
    if (energy) out << " ΔE / max K |";
    for (const auto& m : spec.measures) out << " " << markdown_cell(m.label) << " |";
    out << "\n|";
    const size_t columns = spec.axes.size() + 5 + (energy ? 1 : 0) + spec.measures.size();
    for (size_t c = 0; c < columns; ++c) out << "---|";
    out << "\n";
    for (const auto& r : records) {
      out << "|";
      for (const auto& v : r.point.values) out << " " << markdown_cell(value_text(v)) << " |";
      out << " " << to_string(r.outcome) << " | " << number(r.run_seconds, "%.2f") << " | "
          << r.steps << " | " << number(r.seconds_per_step(), "%.3g") << " | "
          << number(r.peak_mb, "%.0f") << " |";
      if (energy) out << " " << number(r.energy_change, "%+.3g") << " |";
      for (const double e : r.errors) out << " " << number(e, "%.3g") << " |";
      out << "\n";
    }
    const auto fits = convergence_fits(spec, records);
    if (!fits.empty()) {
      out << "\nObserved order p (error ~ h^p, least squares over the completed runs) and what "
             "a doubling of the run's wall time buys (error × 2^s, error ~ time^s; '-' where the "
             "times spread less than 1.5x):\n\n"
             "| error | refined along | other axes | runs | order p | error × per 2× cost |\n"
             "|---|---|---|---|---|---|\n";
      for (const auto& f : fits)
        out << "| " << f.measure << " | " << f.axis << " | " << (f.fixed.empty() ? "-" : f.fixed)
            << " | " << f.points << " | " << (std::isnan(f.order) ? "-" : number(f.order, "%.2f"))
            << " | "
            << (std::isnan(f.cost_slope) ? "-" : number(std::pow(2.0, f.cost_slope), "%.3g"))
            << " |\n";
    }
    const auto failed = std::count_if(records.begin(), records.end(), [](const RunRecord& r) {
      return r.outcome != RunOutcome::Completed;
    });
    if (failed > 0) {
      out << "\nRuns that did not complete:\n";
      for (const auto& r : records)
        if (r.outcome != RunOutcome::Completed)
          out << "- " << r.point.id << " (" << describe_point(spec, r.point)
              << "): " << to_string(r.outcome) << ": " << markdown_cell(r.message) << "\n";
    }
  });
}

}  // namespace shellflow::bench
