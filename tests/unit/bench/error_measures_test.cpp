// Each error measure on outputs whose error is known exactly: hand-made columns and a
// hand-made metrics.csv + run.json, built so that the answer is a number we can write down.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "shellflow/bench/bench_report.hpp"
#include "shellflow/bench/error_measures.hpp"
#include "shellflow/bench/run_outputs.hpp"
#include "test_paths.hpp"

namespace shellflow::bench {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// Every value below is formed from a handful of floating-point operations on numbers of
// order one: round-off, a few ulps.
constexpr double kRoundOff = 1e-12;
constexpr double kG = 9.81;

TEST(ErrorMeasures, StillFluidSpeedIsTheLargestMagnitude) {
  EXPECT_EQ(still_fluid_speed({1e-9, -3e-7, 2e-8}), 3e-7);
  EXPECT_EQ(still_fluid_speed({0.0, 0.0}), 0.0);
  // A run that wrote a non-finite value has no error to report, never a silent number.
  EXPECT_TRUE(std::isnan(still_fluid_speed({1e-9, NAN, 2e-8})));
  EXPECT_THROW(still_fluid_speed({}), MeasureError);
}

TEST(ErrorMeasures, MaxDivergenceIsTheLargestOverSteps) {
  EXPECT_EQ(max_relative_divergence({1e-6, 4e-6, 2e-6}), 4e-6);
}

TEST(ErrorMeasures, WaterVolumeDriftIsRelativeToTheInitialVolume) {
  // V(0) = 2 m³: each row holds V(t) and V(t) − V(0); the worst change is −0.05.
  const std::vector<double> change = {0.01, -0.05, 0.02};
  std::vector<double> volume;
  for (const double c : change) volume.push_back(2.0 + c);
  EXPECT_NEAR(water_volume_drift(volume, change), 0.025, kRoundOff);
}

TEST(ErrorMeasures, WaterVolumeDriftTakesOutWhatEmittersAddedAndOpenSidesLetOut) {
  // V(0) = 1 m³; an emitter adds 0.5 and 1.0 m³ by steps 2 and 3, 0.3 m³ has left by step
  // 3: the run should hold 1.5 and 1.7 m³ there. It holds 1.45 and 1.717: the worst drift
  // is 0.05 m³ over the most it should have held, 1.7 m³.
  const std::vector<double> volume = {1.0, 1.45, 1.717};
  std::vector<double> change;
  for (const double v : volume) change.push_back(v - 1.0);
  const std::vector<double> added = {0.0, 0.5, 1.0}, outflow = {0.0, 0.0, 0.3};
  EXPECT_NEAR(water_volume_drift(volume, change, added, outflow), 0.05 / 1.7, kRoundOff);
  // Without emitters and open sides: the closed tank's measure.
  const std::vector<double> none = {0.0, 0.0, 0.0};
  EXPECT_NEAR(water_volume_drift(volume, change, none, none), water_volume_drift(volume, change),
              kRoundOff);
  // A run that never held water (an emitter never on): no measure.
  const std::vector<double> empty = {0.0, 0.0, 0.0};
  EXPECT_THROW(water_volume_drift(empty, empty, empty, empty), MeasureError);
}

TEST(ErrorMeasures, WaterShapeErrorIsRelativeToTheInitialVolume) {
  // 0.3 m³ where the water differs from its 2 m³ start; NaN for a run that blew up.
  EXPECT_NEAR(water_shape_error(0.3, 2.0), 0.15, kRoundOff);
  EXPECT_TRUE(std::isnan(water_shape_error(NAN, 2.0)));
  EXPECT_THROW(water_shape_error(0.3, 0.0), MeasureError);
}

TEST(ErrorMeasures, FreeFallOfBackwardEulerIsTheStepOverTheTime) {
  // Backward Euler under gravity alone: v_n = −g n Δt exactly, h_n = h0 − g Δt² n(n+1)/2,
  // so h_n − h(t_n) = −g t_n Δt / 2; at T the error over the drop g T²/2 is Δt / T.
  const double h0 = 2.0, dt = 0.01;
  const int steps = 50;  // T = 0.5 s
  std::vector<double> t, h;
  for (int n = 1; n <= steps; ++n) {
    t.push_back(n * dt);
    h.push_back(h0 - kG * dt * dt * n * (n + 1) / 2.0);
  }
  EXPECT_NEAR(free_fall_error(t, h, h0, 0.0, kG), dt / 0.5, kRoundOff);
  // The exact parabola (thrown upwards at 1 m/s) has no error.
  for (int n = 0; n < steps; ++n) h[n] = h0 + 1.0 * t[n] - 0.5 * kG * t[n] * t[n];
  EXPECT_NEAR(free_fall_error(t, h, h0, 1.0, kG), 0.0, kRoundOff);
}

TEST(ErrorMeasures, ProjectionErrorIsTheFirstStepsOnly) {
  // Later steps add advection's error to the projection's: only the first row counts.
  EXPECT_EQ(projection_error({4e-4, 3e-2, 5e-2}), 4e-4);
  EXPECT_TRUE(std::isnan(projection_error({NAN, 1e-3})));
  EXPECT_THROW(projection_error({}), MeasureError);
}

TEST(ErrorMeasures, KineticEnergyLossAgainstTheInitialEnergy) {
  // Taylor–Green in the unit cube at U = 1, ρ = 1: K0 = 1/8 J. Ending at 0.1 J is 20% lost;
  // only the last step counts.
  EXPECT_NEAR(kinetic_energy_loss({0.124, 0.11, 0.1}, 0.125), 0.2, kRoundOff);
  // A gain is an error of the same size (the measure is never negative).
  EXPECT_NEAR(kinetic_energy_loss({0.15}, 0.125), 0.2, kRoundOff);
  EXPECT_EQ(kinetic_energy_loss({0.125}, 0.125), 0.0);
  EXPECT_THROW(kinetic_energy_loss({0.1}, 0.0), MeasureError);
}

TEST(ErrorMeasures, MomentumBalanceOfImpulses) {
  // p_1 = (1, 0, 0.5); then impulses F Δt of (−0.1, 0.2, 0) and (0.2, 0, −0.05): a body that
  // took exactly these has no error. The first row's own impulse is not needed (p_1 is the
  // start).
  const std::vector<double> dt = {0.1, 0.1, 0.05};
  const std::array<std::vector<double>, 3> force = {
      std::vector<double>{7.0, -1.0, 4.0}, {7.0, 2.0, 0.0}, {7.0, 0.0, -1.0}};
  std::array<std::vector<double>, 3> p = {
      std::vector<double>{1.0, 0.9, 1.1}, {0.0, 0.2, 0.2}, {0.5, 0.5, 0.45}};
  EXPECT_NEAR(momentum_balance(dt, force, p), 0.0, kRoundOff);
  // 0.01 more momentum at the end than the impulses explain, over the largest |p| there.
  p[0][2] += 0.01;
  const double largest = std::sqrt(1.11 * 1.11 + 0.2 * 0.2 + 0.45 * 0.45);
  EXPECT_NEAR(momentum_balance(dt, force, p), 0.01 / largest, kRoundOff);
  EXPECT_THROW(momentum_balance({0.1}, {{{1.0}, {1.0}, {1.0}}}, {{{1.0}, {1.0}, {1.0}}}),
               MeasureError);
}

TEST(ErrorMeasures, HangingStripStretchAgainstLinearElasticity) {
  // ρ = 0.1 kg/m², E = 40 N/m, L = 1 m: the centre drops ρgL²/(3E) = 0.981/120 m. A centre
  // that ends 10% lower than that is a 0.1 error; only the last step counts.
  const double expected = 0.1 * kG / 120.0;
  EXPECT_NEAR(hanging_strip_stretch({0.4, 0.5 - 1.1 * expected}, 0.5, 1.0, 0.1, 40.0, kG), 0.1,
              kRoundOff);
  EXPECT_NEAR(hanging_strip_stretch({0.5 - expected}, 0.5, 1.0, 0.1, 40.0, kG), 0.0, kRoundOff);
  EXPECT_THROW(hanging_strip_stretch({0.5}, 0.5, 1.0, 0.1, 40.0, 0.0), MeasureError);
}

TEST(ErrorMeasures, IdleWorkIsTheLargestCount) {
  EXPECT_EQ(idle_work({0.0, 0.0, 0.0}), 0.0);
  EXPECT_EQ(idle_work({0.0, 12.0, 3.0}), 12.0);
}

TEST(ErrorMeasures, LinearMotionIsTheLargestMissOverTheDistanceTravelled) {
  // x = 1 + 0.25 t, the middle sample 0.001 off: 0.001 over 0.25 m/s × 2 s.
  EXPECT_NEAR(linear_motion_error({0.5, 1.0, 2.0}, {1.125, 1.251, 1.5}, 1.0, 0.25), 0.002,
              kRoundOff);
  EXPECT_EQ(linear_motion_error({1.0, 2.0}, {0.75, 0.5}, 1.0, -0.25), 0.0);  // exact, backwards
  EXPECT_THROW(linear_motion_error({1.0}, {1.0}, 1.0, 0.0), MeasureError);   // nothing moved
}

TEST(ErrorMeasures, EdgeStrainIsTheLargestOverSteps) {
  EXPECT_EQ(edge_strain({0.0, 3e-16, 1e-16}), 3e-16);
  EXPECT_THROW(edge_strain({}), MeasureError);
}

TEST(ErrorMeasures, LeakFractionIsTheWorstShareBeyondTheShell) {
  EXPECT_NEAR(leak_fraction({0.0, 1e-3, 2e-3}, {1.0, 1.0, 4.0}), 1e-3, kRoundOff);
  // No smoke at all (before a source starts) is no leak.
  EXPECT_EQ(leak_fraction({0.0}, {0.0}), 0.0);
}

TEST(ErrorMeasures, DamBreakFrontTenPercentAheadOfMartinAndMoyce) {
  const auto data = read_front_data(fs::path(shellflow::test_paths::source_dir()) /
                                    "tests/data/martin_moyce_1952.csv");
  ASSERT_GE(data.size(), 10u);
  // A front exactly 10% ahead of every data point (samples at their own T, so the linear
  // interpolation is exact there): the error is 0.1.
  const double a = 0.25, scale = std::sqrt(2.0 * kG / a);
  std::vector<double> t, front;
  for (const auto& s : data) {
    t.push_back(s.T / scale);
    front.push_back(1.1 * s.Z * a);
  }
  EXPECT_NEAR(dam_break_front_error(t, front, a, kG, data, 1.5, 3.0), 0.1, kRoundOff);
  // A run that ends before T = 1.5 cannot be compared.
  EXPECT_THROW(dam_break_front_error({0.01, 0.02}, {0.3, 0.31}, a, kG, data, 1.5, 3.0),
               MeasureError);
  // Their front exactly, but released 0.2 earlier in T: the delay measured on the points
  // before T = 1.5 is 0.2, and taken out the front matches (to the interpolation's round-off);
  // read at T itself it leads.
  t.clear();
  front.clear();
  for (const auto& s : data) {
    t.push_back((s.T - 0.2) / scale);
    front.push_back(s.Z * a);
  }
  EXPECT_NEAR(dam_break_front_error(t, front, a, kG, data, 1.5, 3.0, true), 0.0, kRoundOff);
  EXPECT_GT(dam_break_front_error(t, front, a, kG, data, 1.5, 3.0, false), 0.05);
}

TEST(ErrorMeasures, StandingWavePeriodFivePercentLong) {
  // η = h + A cos(2π t / P) with P 5% above linear theory for λ = 1, h = 0.25.
  const double depth = 0.25, wavelength = 1.0, k = 2.0 * std::numbers::pi / wavelength;
  const double theory = 2.0 * std::numbers::pi / std::sqrt(kG * k * std::tanh(k * depth));
  const double period = 1.05 * theory;
  std::vector<double> t, eta;
  for (int n = 0; n <= 4000; ++n) {  // four periods, 1000 samples each
    t.push_back(n * period / 1000.0);
    eta.push_back(depth + 0.01 * std::cos(2.0 * std::numbers::pi * t.back() / period));
  }
  // The crossings are interpolated linearly where cos is linear to third order: the
  // crossing times are exact to (ωΔt)³/6 ~ 4e-8 of a period.
  EXPECT_NEAR(standing_wave_period_error(t, eta, depth, wavelength, kG), 0.05, 1e-6);
  EXPECT_THROW(standing_wave_period_error({0.0, 0.1}, {0.26, 0.27}, depth, wavelength, kG),
               MeasureError);
}

TEST(ErrorMeasures, ArchimedesDraftIsTheWindowsMeanAgainstTheDraft) {
  // level − lowest = 0.16 + 0.01 sin(2π t / P) over the last two periods: the heave's mean
  // over whole periods is 0 (the sum of sin(2πn/N) over n = 1..N, right-end samples),
  // so the mean draft is 0.16 against d = 0.15, an error of 1/15. Before the window the
  // body is far off (and once non-finite): none of it counts.
  const double period = 0.5, d = 0.15;
  std::vector<double> t, level, lowest;
  for (int n = 0; n <= 400; ++n) {  // 2 s, 100 steps a period
    t.push_back(n * period / 100.0);
    level.push_back(0.5 + 0.002 * n);  // the level rises too: only the difference counts
    const double offset = t.back() < 1.0
                              ? (n == 3 ? std::nan("") : 0.4)
                              : 0.16 + 0.01 * std::sin(2.0 * std::numbers::pi * t.back() / period);
    lowest.push_back(level.back() - offset);
  }
  EXPECT_NEAR(archimedes_draft_error(t, level, lowest, d, 2.0 * period), (0.16 - d) / d, kRoundOff);
  // Half a period in the window (a trough): the heave no longer cancels; its mean over the
  // half period, −0.01 · 2/π, is what a user's too-short window adds. The right-end sum of
  // the half-wave falls (π/50)²/12 short of its integral: 1.4e-5 of the error here.
  EXPECT_NEAR(archimedes_draft_error(t, level, lowest, d, 0.5 * period),
              (0.16 - 0.02 / std::numbers::pi - d) / d, 1e-4);
  // A non-finite value inside the window: no error to give. A window longer than the run: refused.
  lowest[390] = std::nan("");
  EXPECT_TRUE(std::isnan(archimedes_draft_error(t, level, lowest, d, 2.0 * period)));
  EXPECT_THROW(archimedes_draft_error(t, level, lowest, d, 2.5), MeasureError);
}

TEST(ErrorMeasures, LogLogSlopeOfAPowerLaw) {
  EXPECT_NEAR(log_log_slope({1, 2, 4, 8}, {3, 12, 48, 192}), 2.0, kRoundOff);
  // Non-positive and non-finite points are left out; one point is no line.
  EXPECT_NEAR(log_log_slope({1, 2, 4, -1}, {5, 2.5, 1.25, 7}), -1.0, kRoundOff);
  EXPECT_TRUE(std::isnan(log_log_slope({1, 2}, {0.0, 1.0})));
}

class HandMadeRun : public ::testing::Test {
 protected:
  void SetUp() override {
    m_dir = fs::temp_directory_path() /
            ("shellflow_measures_" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
             std::to_string(::getpid()));
    fs::create_directories(m_dir);
    std::ofstream(m_dir / "run.json") << R"({"status": "completed", "steps": 3,
      "config": {"gravity": [0, -9.81, 0], "fluid": {"name": "air"}}})";
  }
  void TearDown() override { fs::remove_all(m_dir); }
  fs::path m_dir;
};

TEST_F(HandMadeRun, FreeFallThroughTheRegistryReadsGravityFromRunJson) {
  // h = 1 − g t²/2 + 0.001 at the last step: the error over the drop g T²/2 at T = 0.3.
  std::ofstream csv(m_dir / "metrics.csv");
  csv.precision(17);  // as the runtime writes them (%.17g): the values read back exactly
  csv << "step,frame,time,dt,plate.height,air.max_speed\n";
  for (int n = 1; n <= 3; ++n) {
    const double t = 0.1 * n;
    csv << n << ",0," << t << ",0.1," << (1.0 - 0.5 * kG * t * t + (n == 3 ? 1e-3 : 0.0)) << ","
        << (n == 2 ? "" : "1e-7") << "\n";
  }
  csv.close();
  const auto run = RunOutputs::read(m_dir);
  const auto* measure = find_error_measure("free_fall");
  ASSERT_NE(measure, nullptr);
  nlohmann::json params = {
      {"column", "plate.height"}, {"initial_height", 1.0}, {"initial_velocity", 0.0}};
  EXPECT_NEAR(measure->evaluate(run, params), 1e-3 / (0.5 * kG * 0.09), kRoundOff);
  // A counter the run never wrote is an error, not "no work": a misspelt column must not pass.
  EXPECT_THROW(find_error_measure("idle_work")->evaluate(run, {{"column", "air.level_set_node"}}),
               MeasureError);
  // An empty cell (a figure not reported at that step) reads as NaN: no error to give.
  params = {{"column", "air.max_speed"}};
  EXPECT_TRUE(std::isnan(find_error_measure("still_fluid_speed")->evaluate(run, params)));
}

TEST_F(HandMadeRun, VolumeDriftAtItsLargestOrAtTheEndThroughTheRegistry) {
  // V(0) = 2 m³: +0.1 m³ at step 2 (5%), −0.02 m³ at the end (1%).
  std::ofstream csv(m_dir / "metrics.csv");
  csv << "step,frame,time,dt,air.water_volume,air.water_volume_change\n"
      << "1,0,0.1,0.1,2.0,0.0\n2,0,0.2,0.1,2.1,0.1\n3,0,0.3,0.1,1.98,-0.02\n";
  csv.close();
  const auto run = RunOutputs::read(m_dir);
  const nlohmann::json scene = {{"fluid", {{"name", "air"}, {"water", nlohmann::json::object()}}}};
  const auto* drift = find_error_measure("water_volume_drift");
  ASSERT_NE(drift, nullptr);
  for (const auto& [at, expected] : {std::pair{"max", 0.05}, std::pair{"end", 0.01}}) {
    nlohmann::json params = {{"at", at}};
    ASSERT_EQ(drift->bind(params, scene), "") << at;
    EXPECT_NEAR(drift->evaluate(run, params), expected, kRoundOff) << at;
  }
}

TEST_F(HandMadeRun, ProjectionAndEnergyMeasuresThroughTheRegistry) {
  std::ofstream csv(m_dir / "metrics.csv");
  csv << "step,frame,time,dt,air.vortex.rms_error,air.vortex.max_error,air.kinetic_energy\n"
      << "1,0,0.1,0.1,0.00125,0.0025,0.12\n"
      << "2,0,0.2,0.1,0.5,0.75,0.1\n";
  csv.close();
  const auto run = RunOutputs::read(m_dir);
  // The registry's bind turns the probe's name into its column (as load_bench_spec does).
  const nlohmann::json scene = {
      {"fluid", {{"name", "air"}, {"probes", {{{"type", "velocity_error"}, {"name", "vortex"}}}}}}};
  const auto* projection = find_error_measure("projection_error");
  ASSERT_NE(projection, nullptr);
  nlohmann::json params = {{"probe", "vortex"}, {"norm", "max"}};
  ASSERT_EQ(projection->bind(params, scene), "");
  EXPECT_EQ(params["column"], "air.vortex.max_error");
  EXPECT_EQ(projection->evaluate(run, params), 0.0025);
  params = {{"probe", "vortex"}, {"norm", "rms"}};
  ASSERT_EQ(projection->bind(params, scene), "");
  EXPECT_EQ(projection->evaluate(run, params), 0.00125);
  // A probe the scene does not have is named before anything runs.
  params = {{"probe", "vortx"}, {"norm", "rms"}};
  EXPECT_THAT(projection->bind(params, scene), HasSubstr("no velocity_error probe named 'vortx'"));

  const auto* energy = find_error_measure("kinetic_energy_loss");
  ASSERT_NE(energy, nullptr);
  params = {{"initial", 0.125}};
  ASSERT_EQ(energy->bind(params, scene), "");
  EXPECT_NEAR(energy->evaluate(run, params), 0.2, kRoundOff);  // 0.1 J left of 0.125 J
}

TEST_F(HandMadeRun, ArchimedesDraftThroughTheRegistryAveragesTheSecondHalf) {
  // level − lowest: 0.2 m over the first two steps, 0.16 m over the last two (t in (0.2, 0.4]):
  // the default window, the second half of the run, sees only the latter.
  std::ofstream csv(m_dir / "metrics.csv");
  csv << "step,frame,time,dt,water.level.extent,shells.box.lowest\n"
      << "1,0,0.1,0.1,0.5,0.3\n2,0,0.2,0.1,0.5,0.3\n3,0,0.3,0.1,0.51,0.35\n4,0,0.4,0.1,0.49,0.33\n";
  csv.close();
  const auto run = RunOutputs::read(m_dir);
  const auto* measure = find_error_measure("archimedes_draft");
  ASSERT_NE(measure, nullptr);
  const nlohmann::json scene = {{"fluid", {{"name", "water"}}}, {"solids", {{{"name", "shells"}}}}};
  nlohmann::json params = {
      {"level", "water.level.extent"}, {"lowest", "shells.box.lowest"}, {"draft", 0.15}};
  ASSERT_EQ(measure->bind(params, scene), "");
  EXPECT_NEAR(measure->evaluate(run, params), 0.01 / 0.15, kRoundOff);
  params["window"] = 0.4;  // the whole run: 0.1 s at each of 0.2, 0.2, 0.16, 0.16 m
  EXPECT_NEAR(measure->evaluate(run, params), 0.03 / 0.15, kRoundOff);
  // A column of an instance the scene does not have is named before anything runs.
  params["lowest"] = "shell.box.lowest";
  EXPECT_THAT(measure->bind(params, scene), HasSubstr("the instance 'shell'"));
}

TEST_F(HandMadeRun, MissingColumnNamesTheColumnsThereAre) {
  std::ofstream(m_dir / "metrics.csv") << "step,frame,time,dt\n1,0,0.1,0.1\n";
  const auto run = RunOutputs::read(m_dir);
  try {
    run.metrics.column("plate.height");
    FAIL() << "a missing column was read";
  } catch (const MeasureError& e) {
    EXPECT_THAT(e.what(), HasSubstr("no column 'plate.height'"));
    EXPECT_THAT(e.what(), HasSubstr("step, frame, time, dt"));
  }
}

TEST(ErrorMeasureRegistry, EveryMeasureIsDocumentedAndBindsItsColumns) {
  ASSERT_GE(error_measures().size(), 7u);
  for (const auto& m : error_measures()) {
    EXPECT_FALSE(m.doc.empty()) << m.name;
    EXPECT_FALSE(m.reference.empty()) << m.name;
    EXPECT_EQ(find_error_measure(m.name), &m);
  }
  // The fluid's columns come from the scene's fluid instance name.
  nlohmann::json params = nlohmann::json::object();
  const nlohmann::json scene = {
      {"fluid", {{"name", "water"}, {"water", nlohmann::json::object()}}}};
  EXPECT_EQ(find_error_measure("still_fluid_speed")->bind(params, scene), "");
  EXPECT_EQ(params["column"], "water.max_speed");
  // A measure of the fluid in a scene without one says so.
  params = nlohmann::json::object();
  EXPECT_THAT(find_error_measure("max_divergence")->bind(params, nlohmann::json::object()),
              HasSubstr("has no \"fluid\""));
  EXPECT_EQ(find_error_measure("no_such_measure"), nullptr);
}

}  // namespace
}  // namespace shellflow::bench
