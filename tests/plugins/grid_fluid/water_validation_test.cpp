// Water against known answers (issue 11's validation cases; §4.3, §4.4, Guendelman et al.
// 2005): a standing wave's period against linear theory, and a dam break's front against
// Martin and Moyce (1952). Both tanks are thin in z, so the flows are two-dimensional.
// Each test prints its figures (period error, amplitude decay, volume drift, front error and
// the early-time offset) and records them as test properties.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "grid_fluid_test_support.hpp"
#include "test_paths.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

constexpr double kGravity = 9.81;

using test::surface_height;

/// One step at the CFL number `cfl` without shells; returns Δt.
double step(GridFluid& f, double t, double cfl, double t_end) {
  const double dt = std::min(f.stable_dt(cfl), t_end - t);
  f.advect(t, dt, {}, {});
  f.project(dt, {}, {});
  return dt;
}

void report(const char* key, double value) {
  std::printf("[  figure  ] %s = %.6g\n", key, value);
  ::testing::Test::RecordProperty(key, std::to_string(value));
}

// --- Standing wave ---------------------------------------------------------------------

struct StandingWave {
  double period = 0.0;            ///< measured [s]
  double period_theory = 0.0;     ///< 2π/ω, ω² = g k tanh(k h) [s]
  double error = 0.0;             ///< (period − period_theory) / period_theory
  double decay_per_period = 0.0;  ///< 1 − amplitude ratio over one period (< 0: it grew)
  double volume_drift = 0.0;      ///< (V(t_end) − V(0)) / V(0) / t_end [1/s]
  int crossings = 0;
};

/// A standing wave of wavelength λ = 1 m = `cells_per_wavelength` Δx in a closed tank half a
/// wavelength long (its walls at the antinodes), two cells thin in z, mean depth h, initial
/// surface η = h + A cos(kx) at rest (k = π/L), A = `amplitude` Δx, run at CFL 0.9 (the
/// scenes' step) for `periods` linear periods. The signal is the mode's amplitude
/// D(t) = (2/L) ∫ η cos(kx) dx over the node columns, which leaves out the mean level (so
/// volume drift) and the other modes; the period is from its zero crossings. `trace`: the
/// water's "trace" (which velocity φ's rays follow).
StandingWave run_standing_wave(int cells_per_wavelength, double h, double amplitude, double periods,
                               const char* trace = "midpoint", const char* layout = "fraction") {
  const double dx = 1.0 / cells_per_wavelength;
  const int nx = cells_per_wavelength / 2;  // L = λ/2
  const double length = nx * dx;
  const double a = amplitude * dx;
  // Tank height: the surface plus the level set's band (6Δx) of air above it.
  const int ny = static_cast<int>(std::ceil(h / dx)) + 7;
  const nlohmann::json params = {
      {"domain", {{"min", {0, 0, 0}}, {"max", {length, ny * dx, 2.0 * dx}}}},
      {"resolution", std::max(nx, ny)},
      {"pressure", {{"tolerance", 1e-8}}},
      {"water",
       test::water_core(layout, {{"trace", trace}, {"initial", {{{"type", "pool"}, {"height", h}}}}})}};
  auto fluid = test::make_fluid(params);

  // φ = y − η: a signed distance to O((kA)²) ≈ 1e-3, clamped to the band like the solver's.
  const double k = std::numbers::pi / length;
  auto& ls = fluid->liquid()->level_set();
  auto& phi = ls.phi();
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i) {
    const Eigen::Vector3d p = ls.grid().position(Location::Node, i);
    phi[i] = std::clamp(p.y() - h - a * std::cos(k * p.x()), -ls.band(), ls.band());
  }
  // With a volume fraction, F is the wave's water: fitted to φ as set here.
  std::vector<double> scratch;
  if (fluid->liquid()->fraction().enabled()) fluid->liquid()->fraction().fit(ls, scratch);
  const double v0 = fluid->liquid()->volume(nullptr, nullptr);

  StandingWave out;
  out.period_theory = 2.0 * std::numbers::pi / std::sqrt(kGravity * k * std::tanh(k * h));
  const double t_end = periods * out.period_theory;
  auto signal = [&] {
    double sum = 0.0;
    for (int i = 0; i <= nx; ++i)
      sum += (i == 0 || i == nx ? 0.5 : 1.0) * surface_height(*fluid, i * dx, dx) *
             std::cos(k * i * dx);
    return 2.0 * sum * dx / length;
  };
  std::vector<double> ts{0.0}, ds{signal()};
  double t = 0.0;
  while (t < t_end - 1e-12) {
    t += step(*fluid, t, 0.9, t_end);
    ts.push_back(t);
    ds.push_back(signal());
  }
  out.volume_drift = (fluid->liquid()->volume(nullptr, nullptr) - v0) / v0 / t;

  // Zero crossings by linear interpolation, half a period apart.
  std::vector<double> zeros;
  for (size_t s = 1; s < ds.size(); ++s)
    if ((ds[s - 1] > 0.0) != (ds[s] > 0.0))
      zeros.push_back(ts[s - 1] + (ts[s] - ts[s - 1]) * ds[s - 1] / (ds[s - 1] - ds[s]));
  out.crossings = static_cast<int>(zeros.size());
  if (zeros.size() < 2) return out;
  out.period = 2.0 * (zeros.back() - zeros.front()) / static_cast<double>(zeros.size() - 1);
  out.error = (out.period - out.period_theory) / out.period_theory;

  // |D| at each extreme between two crossings (the vertex of a parabola through the largest
  // sample and its neighbours: ~16 steps a period); decay from a least-squares line through
  // log|D| against the half-period index.
  std::vector<double> logs;
  for (size_t c = 0; c + 1 < zeros.size(); ++c) {
    size_t best = 0;
    for (size_t s = 1; s + 1 < ds.size(); ++s)
      if (ts[s] > zeros[c] && ts[s] < zeros[c + 1] &&
          (best == 0 || std::abs(ds[s]) > std::abs(ds[best])))
        best = s;
    if (best == 0) continue;
    const double y0 = std::abs(ds[best - 1]), y1 = std::abs(ds[best]), y2 = std::abs(ds[best + 1]);
    const double curvature = y0 - 2.0 * y1 + y2;
    const double u = curvature < 0.0 ? 0.5 * (y0 - y2) / curvature : 0.0;
    logs.push_back(std::log(y1 - 0.25 * (y0 - y2) * u));
  }
  if (logs.size() >= 2) {
    const double n = static_cast<double>(logs.size());
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    for (size_t i = 0; i < logs.size(); ++i) {
      sx += i;
      sy += logs[i];
      sxx += double(i) * i;
      sxy += i * logs[i];
    }
    const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);  // per half period
    out.decay_per_period = 1.0 - std::exp(2.0 * slope);
  }
  return out;
}

/// The standing wave with its mean level at eight sub-cell positions, h = λ/4 + (j/8) Δx for
/// j = 0..7 (kh ≈ 1.6, between shallow and deep water), A = 0.25Δx (kA ≤ 0.05: the
/// frequency's amplitude correction, O((kA)²) (Tadjbakhsh and Keller 1960), is of order 0.2%
/// or less), six periods. Returns the largest |period error|.
double standing_wave_sweep(int cells_per_wavelength, const char* name,
                           const char* layout = "fraction") {
  const double dx = 1.0 / cells_per_wavelength;
  double worst = 0.0, decay = 0.0, drift = 0.0;
  for (int j = 0; j < 8; ++j) {
    const double h = (cells_per_wavelength / 4 + j / 8.0) * dx;
    const StandingWave w = run_standing_wave(cells_per_wavelength, h, 0.25, 6.0, "midpoint", layout);
    EXPECT_GE(w.crossings, 11) << "h = " << h;  // six periods: twelve crossings
    std::printf(
        "[  figure  ] %d cells/wavelength, h = %.4f m (+%.3fΔx): period %.4f s, "
        "theory %.4f s (%+.2f%%), decay %+.2f%%/period, volume %+.2e/s\n",
        cells_per_wavelength, h, j / 8.0, w.period, w.period_theory, 100.0 * w.error,
        100.0 * w.decay_per_period, w.volume_drift);
    if (std::abs(w.error) > std::abs(worst)) worst = w.error;
    decay += w.decay_per_period / 8.0;
    drift = std::abs(w.volume_drift) > std::abs(drift) ? w.volume_drift : drift;
  }
  const std::string key = std::string("standing_wave_") + name;
  report((key + "_worst_period_error").c_str(), worst);
  report((key + "_mean_decay_per_period").c_str(), decay);
  report((key + "_largest_volume_drift_per_s").c_str(), drift);
  return worst;
}

/// The known answers below hold on the level set alone ("cells") and with a volume fraction
/// ("fraction", the default), with the same bounds.
class WaterValidation : public ::testing::TestWithParam<const char*> {
 protected:
  std::string key(const char* name) const { return std::string(name) + "_" + GetParam(); }
};

INSTANTIATE_TEST_SUITE_P(Layouts, WaterValidation, ::testing::Values("cells", "fraction"),
                         [](const auto& info) { return std::string(info.param); });

TEST_P(WaterValidation, StandingWavePeriodFollowsLinearTheoryAt32CellsPerWavelength) {
  // The bound: the period within 2% of ω² = g k tanh(k h) at 32 cells per wavelength.
  // Measured: −0.46 to +0.66% over the sweep (−0.55 to +0.50% with the sample's own velocity
  // along φ's rays). With the paper's constant extrapolation
  // (∇φ·∇u = 0, "extrapolation_profile": "constant") the period depended on where the mean
  // surface sits in its cell, +0.5, +1.6, +2.8, +3.3, +2.6, +1.4, +0.2, +0.0% for
  // h = 8, 8.125, ..., 8.875Δx: a surface a fraction s of a cell above the last liquid face
  // moved with that face's velocity, an error k s Δx (kΔx = 0.2) of its speed. The fitted
  // amplitude change over six periods is −5.0 to −1.2% per period (mean −2.8%: it grows
  // slightly, a beat with other modes; −1.2% with constant extrapolation); the volume
  // drifts by at most 5.5e-4 of itself per second (1.4e-3 while φ's rays followed the
  // sample's own velocity, whose traced water grows in irrotational flow).
  EXPECT_LT(std::abs(standing_wave_sweep(32, key("32").c_str(), GetParam())), 0.02);
}

TEST(WaterValidationSlow, StandingWavePeriodFollowsLinearTheoryAt64CellsPerWavelength) {
  // The 2% bound at twice its resolution (measured: −0.47 to +0.18% over the sweep,
  // −0.49 to +0.14% with the sample's own velocity along φ's rays,
  // −0.2 to +1.5% with constant extrapolation; the volume drift at most 1.3e-4 of itself
  // per second, 2.9e-4 with the sample's own velocity along φ's rays).
  EXPECT_LT(std::abs(standing_wave_sweep(64, "64")), 0.02);
}

TEST_P(WaterValidation, StandingWaveOneCellHighKeepsItsVolume) {
  // The same wave one cell high (kA = 0.2), six periods at 32 cells per wavelength, the mean
  // level 0.375Δx above a plane of faces. Water is incompressible: its volume is constant.
  // φ's semi-Lagrangian ray back along the sample's own velocity (Euler, the paper's) is the
  // map x → x − u dt, whose Jacobian is 1 + dt² det(∇u) + O(dt³) for a divergence-free u;
  // in irrotational flow det(∇u) = −|∇u|²/2 in 2D, so the traced water grows by
  // O(dt |∇u|²) a second. Measured: +1.83e-2 a second with the Euler ray, +1.6e-3 with the
  // midpoint's velocity (halving the step: +8.8e-3 and +2.4e-3). Bounds: the midpoint's
  // drift below 3e-3 a second (the measured and about half again), and the Euler ray's
  // at least four times it (the cause, shown).
  const double h = (32 / 4 + 0.375) / 32.0;
  const StandingWave midpoint = run_standing_wave(32, h, 1.0, 6.0, "midpoint", GetParam());
  const StandingWave euler = run_standing_wave(32, h, 1.0, 6.0, "euler", GetParam());
  std::printf(
      "[  figure  ] standing wave one cell high, 32 cells/wavelength: volume %+.2e/s traced "
      "from the midpoint, %+.2e/s along the sample's own velocity\n",
      midpoint.volume_drift, euler.volume_drift);
  report(key("standing_wave_one_cell_volume_drift_per_s").c_str(), midpoint.volume_drift);
  EXPECT_LT(std::abs(midpoint.volume_drift), 3e-3);
  // With a volume fraction both are round-off: F, not φ's ray, holds the water.
  if (std::string(GetParam()) != "fraction") {
    EXPECT_GT(euler.volume_drift, 4.0 * std::abs(midpoint.volume_drift));
  }
}

// --- Dam break ---------------------------------------------------------------------------

struct Sample {
  double T = 0.0, Z = 0.0;
};

/// Martin and Moyce (1952), Table 2 (n² = 2): see the citation in the file.
std::vector<Sample> martin_moyce() {
  std::ifstream in(shellflow::test_paths::source_dir() + "/tests/data/martin_moyce_1952.csv");
  std::vector<Sample> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 'T') continue;
    Sample s;
    char comma = 0;
    std::istringstream(line) >> s.T >> comma >> s.Z;
    rows.push_back(s);
  }
  return rows;
}

/// Front of the water along the floor: the largest x where row `row` of φ's samples (0: the
/// floor's, or on cells the first centres') in their middle plane of z is water (φ <= 0),
/// interpolated to φ = 0 towards the next sample.
double front_x(const GridFluid& f, int row) {
  const auto& phi = f.liquid()->level_set().phi();
  const grid::UniformGrid& grid = f.liquid()->level_set().grid();
  const Eigen::Vector3i n = grid.counts(Location::Node);
  const int k = n.z() / 2;
  for (int i = n.x() - 1; i >= 0; --i) {
    const double p = phi[grid.index(Location::Node, i, row, k)];
    if (p > 0.0) continue;
    const double x = grid.position(Location::Node, Eigen::Vector3i(i, row, k)).x();
    if (i == n.x() - 1) return x;
    const double q = phi[grid.index(Location::Node, i + 1, row, k)];
    return x + grid.dx() * p / (p - q);
  }
  return 0.0;
}

/// Linear interpolation of y(x) on increasing xs.
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
  if (x <= xs.front()) return ys.front();
  for (size_t i = 1; i < xs.size(); ++i)
    if (x <= xs[i]) return ys[i - 1] + (ys[i] - ys[i - 1]) * (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
  return ys.back();
}

/// The first T at which Z reaches `z` (linear between the samples), or −1 if it never does.
double first_reach(const std::vector<double>& Ts, const std::vector<double>& Zs, double z) {
  for (size_t i = 1; i < Zs.size(); ++i)
    if (Zs[i] >= z) return Ts[i - 1] + (Ts[i] - Ts[i - 1]) * (z - Zs[i - 1]) / (Zs[i] - Zs[i - 1]);
  return -1.0;
}

struct DamBreak {
  std::vector<double> T, Z, volume;      ///< per step: T = t√(2g/a), Z = x_front/a, V [m^3]
  double worst_error = 0.0;              ///< (Z − Z_MM)/Z_MM of largest size over T in [1.5, 3]
  double early_offset = 0.0;             ///< mean T_MM − T_sim at the same Z, T_MM < 1.5
  double delayed_worst_error = 0.0;      ///< worst_error with the front read early_offset later
  double lead = 0.0;                     ///< the same over T_MM in [1.5, 3]
  double speed = 0.0, speed_data = 0.0;  ///< least-squares dZ/dT over T_MM in [1.5, 3]
  double volume_drift = 0.0;             ///< (V(t_end) − V(0)) / V(0) / t_end [1/s]
};

/// configs/verify/water_dam_break.json: a column a = 0.25 m wide and 2a high against the −x
/// wall of a closed tank 1 × 0.625 × 0.0625 m (4a long) at `resolution` cells across, PCG to
/// 1e-5, run at CFL `cfl` until T = t√(2g/a) = 3 (the front then nears the far wall, Z = 4);
/// the front read on node row `row`. Prints the comparison with Martin and Moyce.
DamBreak run_dam_break(int resolution, int row, double cfl, const char* layout = "fraction") {
  const double a = 0.25;
  const nlohmann::json params = {
      {"domain", {{"min", {0, 0, 0}}, {"max", {1.0, 0.625, 0.0625}}}},
      {"resolution", resolution},
      {"pressure", {{"tolerance", 1e-5}}},
      {"water",
       test::water_core(layout, {{"initial", {{{"type", "box"},
                                               {"min", {-1, -1, -1}},
                                               {"max", {a, 2.0 * a, 1}}}}}})}};
  auto fluid = test::make_fluid(params);
  const double time_scale = std::sqrt(2.0 * kGravity / a);
  const double t_end = 3.0 / time_scale;
  const double v0 = fluid->liquid()->volume(nullptr, nullptr);

  DamBreak out;
  out.T = {0.0};
  out.Z = {front_x(*fluid, row) / a};
  out.volume = {v0};
  double t = 0.0;
  while (t < t_end - 1e-12) {
    t += step(*fluid, t, cfl, t_end);
    out.T.push_back(t * time_scale);
    out.Z.push_back(front_x(*fluid, row) / a);
    out.volume.push_back(fluid->liquid()->volume(nullptr, nullptr));
  }
  out.volume_drift = (out.volume.back() - v0) / v0 / t;

  int early = 0;
  std::vector<double> fit_t, fit_sim, fit_data;
  for (const Sample& s : martin_moyce()) {
    if (s.T > out.T.back()) continue;
    // How much earlier the simulated front reaches the measured Z.
    const double t_sim = first_reach(out.T, out.Z, s.Z);
    if (s.T >= 1.5) {
      const double z = interpolate(out.T, out.Z, s.T);
      const double error = (z - s.Z) / s.Z;
      std::printf(
          "[  figure  ] T = %.2f: Z = %.3f, Martin and Moyce %.2f (%+.1f%%); "
          "reached at T = %.3f (%+.3f)\n",
          s.T, z, s.Z, 100.0 * error, t_sim, t_sim - s.T);
      if (std::abs(error) > std::abs(out.worst_error)) out.worst_error = error;
      fit_t.push_back(s.T);
      fit_sim.push_back(z);
      fit_data.push_back(s.Z);
      out.lead += s.T - t_sim;
    } else {
      std::printf("[  figure  ] Z = %.2f: reached at T = %.3f, Martin and Moyce %.2f (%+.3f)\n",
                  s.Z, t_sim, s.T, t_sim - s.T);
      out.early_offset += s.T - t_sim;
      ++early;
    }
  }
  if (!fit_t.empty()) out.lead /= static_cast<double>(fit_t.size());
  auto slope = [&](const std::vector<double>& y) {
    const double n = static_cast<double>(fit_t.size());
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    for (size_t i = 0; i < fit_t.size(); ++i) {
      sx += fit_t[i];
      sy += y[i];
      sxx += fit_t[i] * fit_t[i];
      sxy += fit_t[i] * y[i];
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
  };
  if (fit_t.size() >= 2) {
    out.speed = slope(fit_sim);
    out.speed_data = slope(fit_data);
  }
  if (early > 0) out.early_offset /= early;
  // The experiment's release delay taken out: their front at T against the simulated one at
  // T − early_offset, the delay measured on their points before T = 1.5 alone, so the
  // comparison over [1.5, 3] is a prediction, not a fit.
  for (const Sample& s : martin_moyce()) {
    if (s.T < 1.5 || s.T > out.T.back()) continue;
    const double z = interpolate(out.T, out.Z, s.T - out.early_offset);
    const double error = (z - s.Z) / s.Z;
    std::printf(
        "[  figure  ] T = %.2f, release delay %.3f out: Z = %.3f, Martin and Moyce %.2f "
        "(%+.1f%%)\n",
        s.T, out.early_offset, z, s.Z, 100.0 * error);
    if (std::abs(error) > std::abs(out.delayed_worst_error)) out.delayed_worst_error = error;
  }
  return out;
}

// The bound, the front within 10% of Martin and Moyce over T in [1.5, 3] at 64 cells
// across the tank, with the experiment's release delay taken out ("early times run ahead of
// the experiment, whose gate took time to lift: say by how much"). An instant release of an
// inviscid column on a free-slip floor reaches their Z = 1.22 ... 1.67 0.18 to 0.29 sooner
// in T and their first point (Z = 1.11, where the floor's front node has only just started
// to move) 0.10 later: a delay of 0.16 in T on average (9 ms at their a = 2.25 in), which
// Lethe's Martin–Moyce example (chaos-polymtl/lethe, examples/multiphysics/dam-break) puts
// at 0.175. Read that much later, the front stays within 10% after T = 1.5 (+6.6% at
// T = 1.63 at most, measured; +2.9 to +6.3% after); without it, it leads by up to 16.4%
// there (the test below prints both).
TEST_P(WaterValidation, DamBreakFrontFollowsMartinAndMoyceOnceTheirReleaseDelayIsOut) {
  ASSERT_GE(martin_moyce().size(), 13u);
  const DamBreak d = run_dam_break(64, 0, 0.9, GetParam());
  report(key("dam_break_release_delay_T").c_str(), d.early_offset);
  report(key("dam_break_worst_front_error_T_1.5_3_delay_out").c_str(), d.delayed_worst_error);
  // The delay is the experiment's: positive (they release later than an instant start),
  // and no more than twice what Lethe's example takes out for the same data (0.175).
  EXPECT_GT(d.early_offset, 0.0);
  EXPECT_LT(d.early_offset, 2.0 * 0.175);
  EXPECT_LT(std::abs(d.delayed_worst_error), 0.10);
}

TEST_P(WaterValidation, DamBreakFrontSpeedFollowsMartinAndMoyce) {
  ASSERT_GE(martin_moyce().size(), 13u);
  const DamBreak d = run_dam_break(64, 0, 0.9, GetParam());
  if (const char* path = std::getenv("SHELLFLOW_DAM_BREAK_CSV")) {
    // The front history for scripts/plot_dam_break.py (the README's figure).
    std::ofstream csv(path);
    csv << "T,Z,volume\n";
    for (size_t s = 0; s < d.T.size(); ++s)
      csv << d.T[s] << ',' << d.Z[s] << ',' << d.volume[s] << '\n';
  }
  report(key("dam_break_worst_front_error_T_1.5_3").c_str(), d.worst_error);
  report(key("dam_break_early_offset_T").c_str(), d.early_offset);
  report(key("dam_break_lead_T_1.5_3").c_str(), d.lead);
  report(key("dam_break_speed_dZ_dT").c_str(), d.speed);
  report(key("dam_break_speed_martin_moyce_dZ_dT").c_str(), d.speed_data);
  report(key("dam_break_volume_drift_per_s").c_str(), d.volume_drift);
  report(key("dam_break_steps").c_str(), static_cast<double>(d.T.size() - 1));
  // The 10% taken to the front's speed over T in [1.5, 3] (least-squares slopes of
  // Z against T at their sample times), which the experiment's release delay leaves alone
  // (measured: 1.35 against their 1.32).
  EXPECT_NEAR(d.speed, d.speed_data, 0.10 * d.speed_data);
  EXPECT_GT(d.lead, 0.0);  // the simulation runs ahead, never behind, over T in [1.5, 3]
}

}  // namespace
}  // namespace shellflow::grid_fluid
