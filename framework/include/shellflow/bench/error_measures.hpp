#pragma once
// Error measures: named, documented functions of a run's outputs (metrics.csv, run.json)
// whose exact value is known (an analytic answer, published data, or a conserved
// quantity). A bench spec names them under "measures"; each returns one non-negative
// number per run, 0 for an exact run.
//
// Each measure is a plain function of metrics columns (tested on hand-made tables) plus
// a registry entry that reads its parameters, fills in the columns from the scene's
// instance names and calls it.

#include <array>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "shellflow/bench/run_outputs.hpp"
#include "shellflow/sdk/schema.hpp"

namespace shellflow::bench {

// --- The measures as functions of columns (one value per step) ---------------------------

/// Largest |u| of a fluid that should stay still [m/s]: max over steps of `speed`
/// (grid_fluid's max_speed, the largest face speed). Known answer: 0 (still water under
/// gravity, §4.3 hydrostatics; still air about a static shell).
double still_fluid_speed(const std::vector<double>& speed);

/// Largest relative divergence after projection: max over steps of `divergence`
/// (grid_fluid's max_divergence, |∇·u| Δx / max|u| after the solve). Known answer: 0.
double max_relative_divergence(const std::vector<double>& divergence);

/// Water volume drift: max over steps of |V(t) − V(0)| / V(0), with V(0) = volume − change
/// of the first row (grid_fluid's water_volume and water_volume_change). Known answer: 0
/// (incompressible water in a closed tank keeps its volume).
double water_volume_drift(const std::vector<double>& volume, const std::vector<double>& change);
/// The same for a run whose emitters add water and whose open sides let it out (grid_fluid's
/// water_volume_added and water_volume_outflow, cumulative): max over steps of
/// |V(t) − V(0) − added(t) + outflow(t)| over the most water the run should have held,
/// max over steps of V(0) + added(t) − outflow(t). Without either, the one above.
double water_volume_drift(const std::vector<double>& volume, const std::vector<double>& change,
                          const std::vector<double>& added, const std::vector<double>& outflow);
/// The symmetric difference of the last and first water over the first water's volume.
double water_shape_error(double symmetric_difference, double initial_volume);

/// Free fall against the parabola h(t) = h0 + v0 t − g t² / 2: max over steps of
/// |h − h(t)| divided by the drop g T² / 2 at the last time T.
double free_fall_error(const std::vector<double>& time, const std::vector<double>& height,
                       double h0, double v0, double g);

/// A scripted straight-line motion: max over steps of |x − (x0 + v t)| divided by the
/// distance |v| T travelled by the last time T. Known answer: 0 up to round-off.
double linear_motion_error(const std::vector<double>& time, const std::vector<double>& position,
                           double x0, double v);
/// The largest relative change of an edge's length over steps. Known answer: 0 for a rigid
/// motion, up to round-off.
double edge_strain(const std::vector<double>& strain);

/// Leak across a sealed shell: max over steps of `far` / `total` (smoke on the side of the
/// shell it never reaches, over all smoke). Known answer: 0 (§3–4: nothing crosses a shell).
double leak_fraction(const std::vector<double>& far, const std::vector<double>& total);

/// One point of Martin and Moyce (1952), Table 2: T = t √(2g/a), Z = front / a.
struct FrontSample {
  double T = 0.0;
  double Z = 0.0;
};
/// Reads T,Z rows of a CSV (lines starting '#' and the header skipped).
/// @throw IoError, MeasureError.
std::vector<FrontSample> read_front_data(const std::filesystem::path& file);

/// Dam-break front against data: max over the data points with T in [T_from, T_to] (and
/// within the run) of |Z_sim(T − δ) − Z| / Z, Z_sim interpolated linearly in T between steps;
/// `front` is the front's distance from the back wall [m], `a` the column's width [m]. δ = 0,
/// or with `take_out_release_delay` the experiment's release delay: the mean over their
/// points before T_from of T − T_sim(Z), T_sim(Z) when the simulated front first reaches Z.
double dam_break_front_error(const std::vector<double>& time, const std::vector<double>& front,
                             double a, double g, const std::vector<FrontSample>& data,
                             double T_from, double T_to, bool take_out_release_delay = false);

/// Standing wave's period against linear theory, ω² = g k tanh(k h) with k = 2π/λ:
/// |P − P_theory| / P_theory, P from the zero crossings of `surface` − `depth` (linear
/// between steps, half a period apart). Needs at least two crossings.
double standing_wave_period_error(const std::vector<double>& time,
                                  const std::vector<double>& surface, double depth,
                                  double wavelength, double g);

/// A floating body's draft against Archimedes: the mean over the run's last `window`
/// seconds (weighted by each step's Δt) of `level` − `lowest`, the water's surface height
/// beside the body minus the height of its lowest point, against d = M/(ρ A), the depth at
/// which the water it keeps out weighs its mass: |d_mean − d| / d. The window covers the
/// heave, which a mean over whole periods cancels.
double archimedes_draft_error(const std::vector<double>& time, const std::vector<double>& level,
                              const std::vector<double>& lowest, double draft, double window);

/// One projection's error against a manufactured solution: the first step's value of a
/// grid_fluid "velocity_error" probe column (|u − w| relative to w, the divergence-free part
/// of a field made of w plus a gradient, analytic_velocity.hpp). The first step only: later
/// steps add advection's error. Its Δt must be short, as its advection moves the field by
/// |u| Δt before the projection. Known answer: 0 (an exact projection returns w).
double projection_error(const std::vector<double>& velocity_error);

/// Kinetic energy against an exact solution that keeps it (inviscid Euler: the
/// Taylor–Green vortex while it stays smooth): |K(T) − K0| / K0 with K(T) the last step's
/// `kinetic` and K0 the analytic initial energy. Semi-Lagrangian advection dissipates, so it
/// is the energy lost. Known answer: 0.
double kinetic_energy_loss(const std::vector<double>& kinetic, double initial);

/// A free body's momentum against the impulses the fluid gave it (§5.1, §6): with the
/// body's momentum p_n and the fluid's total coupling force F_n and step Δt_n at each row n
/// (three components each), max over n of |(p_n − p_1) − Σ_{k=2..n} F_k Δt_k| / max_n |p_n|.
/// The coupling loop hands each step's impulse F Δt to the solids whatever step they take
/// (impulse-matched forces), so without gravity or other forces the balance is exact.
/// Known answer: 0 (round-off). Needs two rows.
double momentum_balance(const std::vector<double>& dt,
                        const std::array<std::vector<double>, 3>& force,
                        const std::array<std::vector<double>, 3>& momentum);

/// A strip of length L hanging from its top edge under its own weight: linear elasticity
/// gives a strain ρ g (L − s) / E at distance s below the top, so its centre of mass drops by
/// ρ g L² / (3E) (ρ: mass per area, E: uniaxial modulus per width [N/m]). Error:
/// |(rest − h_end) − ρ g L² / (3E)| / (ρ g L² / (3E)), h the centre's height column at the
/// last step (the run must have come to rest).
double hanging_strip_stretch(const std::vector<double>& center_height, double rest_height,
                             double length, double density, double modulus, double g);

/// Work a scene does not need ("cost follows need"): max over steps of a counter a plugin
/// reports (grid_fluid's band_nodes with no shells, coupling_faces with no two-way shell,
/// level_set_cells in smoke, smoke_nodes in water, ...). Known answer: 0.
double idle_work(const std::vector<double>& counter);

// --- The registry that bench specs name -------------------------------------------------

struct ErrorMeasure {
  std::string name;
  std::string doc;        ///< what it measures and the known answer
  std::string reference;  ///< where the answer comes from: analytic, data (file), conserved
  std::string unit;       ///< of the value ("1" for a ratio)
  sdk::Schema params;     ///< its parameters (besides "measure" and "label")
  /// Fills in what depends on the scene (the fluid's instance name ...); `params` are
  /// validated against `params`. Returns what is wrong, or "".
  std::function<std::string(nlohmann::json& params, const nlohmann::json& resolved_scene)> bind;
  /// The measure of one run. @throw MeasureError when the outputs lack what it needs.
  std::function<double(const RunOutputs& run, const nlohmann::json& params)> evaluate;
  /// When true, `evaluate` gives a value, not an error: the bench compares it with the
  /// value of the finest run of the sweep (finest_reference.hpp).
  bool against_finest = false;
};

/// Every measure, in the order they are documented.
const std::vector<ErrorMeasure>& error_measures();
/// By name, or null.
const ErrorMeasure* find_error_measure(const std::string& name);

}  // namespace shellflow::bench
