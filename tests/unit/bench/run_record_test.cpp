// How a child run is recorded: its outcome from the exit and run.json, its energy change
// from metrics.csv (hand-made, so the answer is known), its errors only when it completed.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>

#include "shellflow/bench/run_record.hpp"

namespace shellflow::bench {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class RecordRun : public ::testing::Test {
 protected:
  void SetUp() override {
    m_dir = fs::temp_directory_path() /
            ("shellflow_record_" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
             std::to_string(::getpid()));
    fs::create_directories(m_dir);
    // K = 2, 4, 1 and P = 0, −1, 0.5: E = 2, 3, 1.5, so (E_end − E_first) / max K = −0.125.
    std::ofstream(m_dir / "metrics.csv")
        << "step,frame,time,dt,a.kinetic_energy,a.potential_energy\n"
           "1,0,0.1,0.1,2,0\n2,0,0.2,0.1,4,-1\n3,0,0.3,0.1,1,0.5\n";
  }
  void TearDown() override { fs::remove_all(m_dir); }
  RunRecord record(const std::string& run_json, ChildOutcome child = {}) {
    if (!run_json.empty()) std::ofstream(m_dir / "run.json") << run_json;
    RunRecord r;
    record_run(m_spec, child, m_dir, m_dir / "log.txt", r);
    return r;
  }
  fs::path m_dir;
  BenchSpec m_spec;  // no measures
};

TEST_F(RecordRun, CompletedRunWithItsEnergyChange) {
  ChildOutcome child;
  child.exit_code = 0;
  const auto r = record(R"({"status": "completed", "steps": 3, "wall_seconds": 0.5})", child);
  EXPECT_EQ(r.outcome, RunOutcome::Completed);
  EXPECT_EQ(r.steps, 3);
  EXPECT_DOUBLE_EQ(r.seconds_per_step(), 0.5 / 3);
  EXPECT_DOUBLE_EQ(r.energy_change, -0.125);
  EXPECT_DOUBLE_EQ(r.sim_time, 0.3);
}

TEST_F(RecordRun, TheGuardAndNonFiniteValuesAreTold) {
  ChildOutcome child;
  child.exit_code = 3;
  EXPECT_EQ(record(R"({"status": "numerical_failure", "message": "unstable at step 2 ..."})", child)
                .outcome,
            RunOutcome::GuardStopped);
  EXPECT_EQ(record(R"({"status": "numerical_failure", "message": "non-finite value in a"})", child)
                .outcome,
            RunOutcome::NonFinite);
}

TEST_F(RecordRun, SignalIsACrashAndNoRunJsonAFailureWithTheLogsWords) {
  ChildOutcome killed;
  killed.signal = SIGSEGV;
  const auto crash = record(R"({"status": "running"})", killed);
  EXPECT_EQ(crash.outcome, RunOutcome::Crashed);
  EXPECT_THAT(crash.message, HasSubstr("signal 11"));

  fs::remove(m_dir / "run.json");
  std::ofstream(m_dir / "log.txt") << "[info] loading\nerror: cannot read scene file x\n\n";
  ChildOutcome failed;
  failed.exit_code = 1;
  const auto r = record("", failed);
  EXPECT_EQ(r.outcome, RunOutcome::Failed);
  EXPECT_EQ(r.message, "error: cannot read scene file x");
}

}  // namespace
}  // namespace shellflow::bench
