// Errors against the finest run of a sweep: hand-made values v(h) = 1 + h², so each error
// is known exactly; the reference run's own error is left empty and so marked.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "shellflow/bench/finest_reference.hpp"

namespace shellflow::bench {
namespace {

using ::testing::HasSubstr;

TEST(FinestReference, EachRunAgainstTheFinestOfItsGroup) {
  BenchSpec spec;
  spec.axes.push_back(
      {"/fluid/resolution", {8, 16, 32}, "/sweep/0/values", Spacing::Inverse, "resolution"});
  spec.axes.push_back({"/time/cfl", {0.5, 1.0}, "/sweep/1/values", Spacing::None, "cfl"});
  spec.measures.push_back({"/measures/0", "against_finest", "energy", {}});
  std::vector<RunRecord> records;
  for (const int n : {8, 16, 32})
    for (const double cfl : {0.5, 1.0}) {
      RunRecord r;
      r.point.values = {n, cfl};
      r.outcome = RunOutcome::Completed;
      const double h = 1.0 / n;
      r.errors = {1.0 + h * h + (cfl == 1.0 ? 1.0 : 0.0)};  // the cfl groups differ by 1
      records.push_back(r);
    }
  compare_with_finest(spec, records);
  // Exact in binary: 1 + 1/64, 1 + 1/256, 1 + 1/1024 (and 2 + ...).
  const double ref_a = 1.0 + 1.0 / 1024, ref_b = 2.0 + 1.0 / 1024;
  EXPECT_DOUBLE_EQ(records[0].errors[0], (1.0 / 64 - 1.0 / 1024) / ref_a);
  EXPECT_DOUBLE_EQ(records[1].errors[0], (1.0 / 64 - 1.0 / 1024) / ref_b);
  EXPECT_DOUBLE_EQ(records[2].errors[0], (1.0 / 256 - 1.0 / 1024) / ref_a);
  for (const size_t finest : {4u, 5u}) {
    EXPECT_TRUE(std::isnan(records[finest].errors[0]));
    EXPECT_THAT(records[finest].message, HasSubstr("the reference (finest run)"));
  }
}

TEST(FinestReference, RunsThatDidNotCompleteAreNeitherReferenceNorCompared) {
  BenchSpec spec;
  spec.axes.push_back(
      {"/time/max_dt", {0.1, 0.05, 0.025}, "/sweep/0/values", Spacing::Value, "max_dt"});
  spec.measures.push_back({"/measures/0", "against_finest", "x", {}});
  std::vector<RunRecord> records(3);
  const double values[3] = {2.0, 1.5, NAN};
  for (int i = 0; i < 3; ++i) {
    records[i].point.values = {spec.axes[0].values[i]};
    records[i].outcome = i == 2 ? RunOutcome::NonFinite : RunOutcome::Completed;
    records[i].errors = {values[i]};
  }
  compare_with_finest(spec, records);
  EXPECT_DOUBLE_EQ(records[0].errors[0], 0.5 / 1.5);  // against dt = 0.05, the finest completed
  EXPECT_TRUE(std::isnan(records[1].errors[0]));
  EXPECT_TRUE(std::isnan(records[2].errors[0]));
}

}  // namespace
}  // namespace shellflow::bench
