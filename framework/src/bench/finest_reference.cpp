#include "shellflow/bench/finest_reference.hpp"

#include <cmath>
#include <limits>
#include <map>

#include "shellflow/bench/error_measures.hpp"

namespace shellflow::bench {

void compare_with_finest(const BenchSpec& spec, std::vector<RunRecord>& records) {
  size_t axis = spec.axes.size();
  for (size_t a = 0; a < spec.axes.size() && axis == spec.axes.size(); ++a)
    if (spec.axes[a].spacing != Spacing::None) axis = a;
  for (size_t m = 0; m < spec.measures.size(); ++m) {
    if (!find_error_measure(spec.measures[m].measure)->against_finest) continue;
    if (axis == spec.axes.size()) continue;  // load_bench_spec refuses such a spec
    // Group by the other axes' values.
    std::map<std::string, std::vector<RunRecord*>> groups;
    for (auto& r : records) {
      std::string key;
      for (size_t b = 0; b < spec.axes.size(); ++b)
        if (b != axis) key += r.point.values[b].dump() + "|";
      groups[key].push_back(&r);
    }
    for (auto& [key, runs] : groups) {
      RunRecord* finest = nullptr;
      double finest_h = std::numeric_limits<double>::infinity();
      for (RunRecord* r : runs) {
        if (r->outcome != RunOutcome::Completed || !std::isfinite(r->errors[m])) continue;
        const double v = r->point.values[axis].get<double>();
        const double h = spec.axes[axis].spacing == Spacing::Inverse ? 1.0 / v : v;
        if (h < finest_h) {
          finest_h = h;
          finest = r;
        }
      }
      if (!finest) continue;
      const double reference = finest->errors[m];
      for (RunRecord* r : runs) {
        if (r == finest) continue;
        const double v = r->errors[m];
        r->errors[m] = reference != 0.0 ? std::abs(v - reference) / std::abs(reference)
                                        : std::abs(v - reference);
      }
      finest->errors[m] = std::numeric_limits<double>::quiet_NaN();
      finest->message += (finest->message.empty() ? "" : "; ") + spec.measures[m].label +
                         ": the reference (finest run)";
    }
  }
}

}  // namespace shellflow::bench
