#include "shellflow/bench/error_measures.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>

namespace shellflow::bench {

using Json = nlohmann::json;
using sdk::Schema;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Max over the finite entries; NaN (never a silent 0) when a step holds a non-finite value,
/// since a run that produced one has no error to report.
double max_abs(const std::vector<double>& values) {
  if (values.empty()) throw MeasureError("metrics.csv has no rows (the run took no step)");
  double worst = 0.0;
  for (const double v : values) {
    if (!std::isfinite(v)) return kNaN;
    worst = std::max(worst, std::abs(v));
  }
  return worst;
}

void same_length(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) throw MeasureError("columns of different lengths");
  if (a.empty()) throw MeasureError("metrics.csv has no rows (the run took no step)");
}

double linear(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
  if (x <= xs.front()) return ys.front();
  for (size_t i = 1; i < xs.size(); ++i)
    if (x <= xs[i]) return ys[i - 1] + (ys[i] - ys[i - 1]) * (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
  return ys.back();
}

// --- Scene helpers for bind() ---------------------------------------------------------

std::vector<std::string> instance_names(const Json& scene) {
  std::vector<std::string> names;
  if (scene.contains("fluid")) names.push_back(scene["fluid"].value("name", ""));
  for (const char* list : {"solids"})
    if (scene.contains(list))
      for (const auto& s : scene[list]) names.push_back(s.value("name", ""));
  return names;
}

/// A column "<instance>.<key>" (or a runtime column without '.') must name an instance the
/// scene has: a typo is caught before anything runs.
std::string check_column(const Json& params, const std::string& key, const Json& scene) {
  const std::string column = params.at(key);
  const auto dot = column.find('.');
  if (dot == std::string::npos) return "";  // the runtime's own: time, dt, t_advect, ...
  const std::string instance = column.substr(0, dot);
  const auto names = instance_names(scene);
  if (std::find(names.begin(), names.end(), instance) != names.end()) return "";
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "'" : ", '") + n + "'";
  return "\"" + key + "\": the column '" + column + "' names the instance '" + instance +
         "', which the scene does not have (instances: " + list + ")";
}

/// Binds a measure that reads one of the fluid's columns: "fluid" (default: the scene's
/// fluid) becomes params["column"] = "<fluid>.<key>".
std::function<std::string(Json&, const Json&)> bind_fluid_column(const std::string& key) {
  return [key](Json& params, const Json& scene) -> std::string {
    if (!scene.contains("fluid"))
      return "this measure reads the fluid's '" + key +
             "' column, but the base scene has no \"fluid\"";
    const std::string fluid = scene["fluid"].value("name", "");
    if (params.contains("fluid") && params["fluid"] != fluid)
      return "\"fluid\": the scene's fluid is named '" + fluid + "', not " + params["fluid"].dump();
    params["column"] = fluid + "." + key;
    return "";
  };
}

Schema fluid_param() {
  return Schema::string().optional().doc("the fluid's instance name (default: the scene's fluid)");
}

double gravity_of(const RunOutputs& run) {
  const Json& g = run.run.at("config").at("gravity");
  return std::sqrt(g[0].get<double>() * g[0].get<double>() +
                   g[1].get<double>() * g[1].get<double>() +
                   g[2].get<double>() * g[2].get<double>());
}

std::vector<ErrorMeasure> make_registry() {
  std::vector<ErrorMeasure> r;
  r.push_back({"still_fluid_speed",
               "largest face speed of a fluid that should stay still (max over steps of "
               "<fluid>.max_speed); 0 for still water under gravity or still air",
               "analytic: 0", "m/s", Schema::object("").field("fluid", fluid_param()),
               bind_fluid_column("max_speed"), [](const RunOutputs& run, const Json& p) {
                 return still_fluid_speed(run.metrics.column(p["column"]));
               }});
  r.push_back({"max_divergence",
               "largest relative divergence after the projection (max over steps of "
               "<fluid>.max_divergence); 0 for an exact projection",
               "analytic: 0", "1", Schema::object("").field("fluid", fluid_param()),
               bind_fluid_column("max_divergence"), [](const RunOutputs& run, const Json& p) {
                 return max_relative_divergence(run.metrics.column(p["column"]));
               }});
  // Both water measures need the scene to be water: a typo'd base scene is caught early.
  const auto bind_water_column = [](const std::string& key) {
    return [key](Json& params, const Json& scene) {
      const std::string problem = bind_fluid_column(key)(params, scene);
      if (problem.empty() && !scene["fluid"].contains("water"))
        return std::string("the base scene's fluid has no \"water\" block");
      return problem;
    };
  };
  r.push_back({"water_volume_drift",
               "|V(t) − V(0)| / V(0) of the water (<fluid>.water_volume and "
               "water_volume_change): its largest over steps, or with \"at\": \"end\" at "
               "the last step (a transport test's loss after its revolution); 0 in a closed "
               "tank. With emitters or open sides, what the emitters added and the open "
               "sides let out (water_volume_added, water_volume_outflow) are taken out of "
               "V(t) − V(0), over the most water the run should have held",
               "conserved: the initial volume", "1",
               Schema::object("")
                   .field("fluid", fluid_param())
                   .field("at", Schema::string("max")
                                    .one_of({"max", "end"})
                                    .doc("'max': the largest over steps; 'end': the last step's")),
               bind_water_column("water_volume"), [](const RunOutputs& run, const Json& p) {
                 const std::string column = p["column"];
                 auto volume = run.metrics.column(column);
                 auto change = run.metrics.column(column + "_change");
                 // Runs written before the budget have no such columns.
                 const bool budget = run.metrics.has(column + "_added");
                 std::vector<double> added, outflow;
                 if (budget) {
                   added = run.metrics.column(column + "_added");
                   outflow = run.metrics.column(column + "_outflow");
                 }
                 if (p["at"] == "end" && !volume.empty()) {
                   volume = {volume.back()};
                   change = {change.back()};
                   if (budget) {
                     added = {added.back()};
                     outflow = {outflow.back()};
                   }
                 }
                 return budget ? water_volume_drift(volume, change, added, outflow)
                               : water_volume_drift(volume, change);
               }});
  r.push_back({"water_shape_error",
               "the volume where the water at the last step differs from its shape at t = 0 "
               "(<fluid>.water_symmetric_difference, written with a prescribed_velocity), "
               "over V(0): for a flow that brings every point back at its end (one "
               "rigid_rotation, LeVeque's deformation at t = T)",
               "analytic: the initial shape", "1",
               Schema::object("").field("fluid", fluid_param()),
               [bind_water_column](Json& params, const Json& scene) {
                 std::string problem = bind_water_column("water_symmetric_difference")(params,
                                                                                      scene);
                 if (problem.empty() && !scene["fluid"].contains("prescribed_velocity"))
                   problem = "the base scene's fluid has no \"prescribed_velocity\": the "
                             "water's shape at the end is then not its shape at the start";
                 return problem;
               },
               [](const RunOutputs& run, const Json& p) {
                 const std::string column = p["column"];
                 const std::string fluid = column.substr(0, column.find('.'));
                 const auto difference = run.metrics.column(column);
                 const auto volume = run.metrics.column(fluid + ".water_volume");
                 const auto change = run.metrics.column(fluid + ".water_volume_change");
                 same_length(volume, change);
                 return water_shape_error(difference.back(), volume.front() - change.front());
               }});
  r.push_back(
      {"free_fall",
       "a height column against the parabola h0 + v0 t − g t²/2 (g = |gravity| of the run): max "
       "error over steps divided by the drop g T²/2",
       "analytic: the parabola", "1",
       Schema::object("")
           .field("column", Schema::string().doc("the height column, e.g. plate.height"))
           .field("initial_height", Schema::number().unit("m").doc("h0: the height at t = 0"))
           .field("initial_velocity",
                  Schema::number(0.0).unit("m/s").doc("v0: upward velocity at t = 0")),
       [](Json& params, const Json& scene) { return check_column(params, "column", scene); },
       [](const RunOutputs& run, const Json& p) {
         return free_fall_error(run.metrics.column("time"), run.metrics.column(p["column"]),
                                p["initial_height"], p["initial_velocity"], gravity_of(run));
       }});
  r.push_back(
      {"linear_motion",
       "a position column against the straight line x0 + v t (a shell a script moves at a "
       "constant velocity, or between two linear keys): max error over steps divided by the "
       "distance |v| T travelled",
       "analytic: the scripted motion", "1",
       Schema::object("")
           .field("column", Schema::string().doc("the position column, e.g. cup.center_x"))
           .field("initial", Schema::number().unit("m").doc("x0: the position at t = 0"))
           .field("velocity", Schema::number().unit("m/s").doc("v: the constant velocity")),
       [](Json& params, const Json& scene) { return check_column(params, "column", scene); },
       [](const RunOutputs& run, const Json& p) {
         return linear_motion_error(run.metrics.column("time"), run.metrics.column(p["column"]),
                                    p["initial"], p["velocity"]);
       }});
  r.push_back(
      {"edge_strain",
       "the largest relative change of an edge's length over steps (kinematic_shell's "
       "max_edge_strain): a rigid motion keeps every edge",
       "analytic: 0 for a rigid motion (slerp keys, analytic spin and slide)", "1",
       Schema::object("").field(
           "column", Schema::string().doc("the strain column, e.g. paddle.max_edge_strain")),
       [](Json& params, const Json& scene) { return check_column(params, "column", scene); },
       [](const RunOutputs& run, const Json& p) {
         return edge_strain(run.metrics.column(p["column"]));
       }});
  r.push_back(
      {"leak_fraction",
       "largest share of the smoke found where it can never go (a region sealed off by "
       "a shell): max over steps of far / total",
       "analytic: 0", "1",
       Schema::object("")
           .field("far", Schema::string().doc("the column of the smoke beyond the shell, e.g. a "
                                              "grid_fluid probe's smoke.far.smoke_mass"))
           .field("total", Schema::string().optional().doc(
                               "the column of all smoke (default: <fluid>.smoke_mass)")),
       [](Json& params, const Json& scene) -> std::string {
         if (!params.contains("total")) {
           if (!scene.contains("fluid")) return "the base scene has no \"fluid\": give \"total\"";
           params["total"] = scene["fluid"].value("name", "") + ".smoke_mass";
         }
         if (auto problem = check_column(params, "far", scene); !problem.empty()) return problem;
         return check_column(params, "total", scene);
       },
       [](const RunOutputs& run, const Json& p) {
         return leak_fraction(run.metrics.column(p["far"]), run.metrics.column(p["total"]));
       }});
  r.push_back(
      {"dam_break_front",
       "the front of a collapsing water column against Martin and Moyce (1952): max over their "
       "points with T = t √(2g/a) in [from_T, to_T] of |Z − Z_data| / Z_data, Z = front / a",
       "data: Martin and Moyce 1952, Table 2 (tests/data/martin_moyce_1952.csv)", "1",
       Schema::object("")
           .field("front", Schema::string().doc(
                               "the column of the front's distance from the back wall [m], a "
                               "grid_fluid probe's <fluid>.<probe>.extent"))
           .field("width", Schema::number().min(0.0, false).unit("m").doc("a: the column's width"))
           .field("data", Schema::file().doc("T,Z data, relative to the spec"))
           .field("from_T",
                  Schema::number(1.5).doc("first T compared (their gate took time to "
                                          "lift: earlier fronts lag any instant release)"))
           .field("to_T", Schema::number(3.0).doc("last T compared"))
           .field("release_delay",
                  Schema::string("none").one_of({"none", "measured"}).doc(
                      "'measured': take out the experiment's release delay, the mean of "
                      "T_data − T_sim at their Z over their points before from_T, and compare "
                      "the front read that much later (a prediction over [from_T, to_T]: the "
                      "delay is measured on the earlier points alone)")),
       [](Json& params, const Json& scene) -> std::string {
         if (params["from_T"].get<double>() >= params["to_T"].get<double>())
           return "\"from_T\" must be below \"to_T\"";
         try {
           read_front_data(params["data"].get<std::string>());
         } catch (const Error& e) {
           return "\"data\": " + std::string(e.what());
         }
         return check_column(params, "front", scene);
       },
       [](const RunOutputs& run, const Json& p) {
         return dam_break_front_error(run.metrics.column("time"), run.metrics.column(p["front"]),
                                      p["width"], gravity_of(run),
                                      read_front_data(p["data"].get<std::string>()), p["from_T"],
                                      p["to_T"], p["release_delay"] == "measured");
       }});
  r.push_back(
      {"standing_wave_period",
       "a standing wave's period against linear theory ω² = g k tanh(k h), k = 2π/λ: |P − "
       "P_theory| "
       "/ P_theory with P from the zero crossings of surface − depth",
       "analytic: linear theory (Lamb 1932, §228)", "1",
       Schema::object("")
           .field("surface",
                  Schema::string().doc("the column of the surface height at one place [m]"))
           .field("depth", Schema::number().min(0.0, false).unit("m").doc("h: the still depth"))
           .field("wavelength",
                  Schema::number().min(0.0, false).unit("m").doc("λ of the standing wave")),
       [](Json& params, const Json& scene) { return check_column(params, "surface", scene); },
       [](const RunOutputs& run, const Json& p) {
         return standing_wave_period_error(run.metrics.column("time"),
                                           run.metrics.column(p["surface"]), p["depth"],
                                           p["wavelength"], gravity_of(run));
       }});
  r.push_back(
      {"archimedes_draft",
       "a floating body's draft against Archimedes' d = M/(ρ A): the mean over the last "
       "\"window\" seconds of the water level beside it minus its lowest point, |d_mean − d| / d",
       "analytic: Archimedes, d = M/(ρ A)", "1",
       Schema::object("")
           .field("level", Schema::string().doc("the column of the water's surface height beside "
                                                "the body, e.g. a vertical water_extent probe's "
                                                "water.level.extent (its segment from y = 0)"))
           .field("lowest", Schema::string().doc("the column of the body's lowest point, e.g. "
                                                 "bullet_rigid's shells.box.lowest"))
           .field("draft", Schema::number().min(0.0, false).unit("m").doc(
                               "d = M/(ρ A): the body's mass over the water's density times the "
                               "area of its waterplane"))
           .field("window", Schema::number().optional().min(0.0, false).unit("s").doc(
                                "the last seconds of the run the draft is averaged over "
                                "(default: the second half of the run); the longer, the less "
                                "the heave and the tank's sloshing that are left weigh")),
       [](Json& params, const Json& scene) {
         if (auto problem = check_column(params, "level", scene); !problem.empty()) return problem;
         return check_column(params, "lowest", scene);
       },
       [](const RunOutputs& run, const Json& p) {
         const auto time = run.metrics.column("time");
         const double window =
             p.contains("window") ? p["window"].get<double>() : 0.5 * (time.empty() ? 0.0 : time.back());
         return archimedes_draft_error(time, run.metrics.column(p["level"]),
                                       run.metrics.column(p["lowest"]), p["draft"], window);
       }});
  r.push_back(
      {"projection_error",
       "one projection of a manufactured field (the divergence-free Taylor–Green vortex plus a "
       "gradient, grid_fluid's \"initial_velocity\") against its divergence-free part: the first "
       "step's value of a grid_fluid \"velocity_error\" probe (the scene's first step must be "
       "short: its advection moves the field by |u| Δt)",
       "analytic: the divergence-free part of the manufactured field", "1",
       Schema::object("")
           .field("probe", Schema::string().doc("the name of the fluid's velocity_error probe"))
           .field("norm",
                  Schema::string("rms")
                      .one_of({"rms", "max"})
                      .doc("'rms': √(Σ e² / Σ w²) over the faces; 'max': max |e| / max |w|"))
           .field("fluid", fluid_param()),
       [](Json& params, const Json& scene) -> std::string {
         if (!scene.contains("fluid"))
           return "this measure reads a probe of the fluid, but the base scene has no \"fluid\"";
         const Json& fluid = scene["fluid"];
         const std::string probe = params["probe"];
         bool found = false;
         for (const auto& p : fluid.value("probes", Json::array()))
           found =
               found || (p.value("name", "") == probe && p.value("type", "") == "velocity_error");
         if (!found)
           return "\"probe\": the scene's fluid has no velocity_error probe named '" + probe +
                  "' (add one under /fluid/probes)";
         params["column"] = fluid.value("name", "") + "." + probe + "." +
                            params["norm"].get<std::string>() + "_error";
         return "";
       },
       [](const RunOutputs& run, const Json& p) {
         return projection_error(run.metrics.column(p["column"]));
       }});
  r.push_back(
      {"kinetic_energy_loss",
       "a fluid's kinetic energy at the end against an exact solution that keeps it (inviscid "
       "Euler: the Taylor–Green vortex): |K(T) − K0| / K0, K from <fluid>.kinetic_energy",
       "analytic: K0, the initial energy (Taylor–Green in a cube of side L: ρ U² L³ / 8)", "1",
       Schema::object("")
           .field("initial", Schema::number()
                                 .min(0.0, false)
                                 .unit("J")
                                 .doc("K0: the analytic kinetic energy at t = 0"))
           .field("fluid", fluid_param()),
       bind_fluid_column("kinetic_energy"), [](const RunOutputs& run, const Json& p) {
         return kinetic_energy_loss(run.metrics.column(p["column"]), p["initial"]);
       }});
  r.push_back(
      {"momentum_balance",
       "a free solid's momentum change against the impulses of the fluid's coupling forces: "
       "max over steps of |(p_n − p_1) − Σ_{k=2..n} F_k Δt_k| / max |p|, p from "
       "<solid>.momentum_x/y/z, F from <fluid>.coupling_force_x/y/z (no gravity)",
       "conserved: momentum exchanged through the §5.1 coupling impulses", "1",
       Schema::object("")
           .field("solid", Schema::string().doc("the solid's instance name (it reports "
                                                "momentum_x, momentum_y, momentum_z)"))
           .field("fluid", fluid_param()),
       [](Json& params, const Json& scene) -> std::string {
         if (const std::string problem = bind_fluid_column("coupling_force")(params, scene);
             !problem.empty())
           return problem;
         params["force"] = params["column"];
         params.erase("column");
         params["momentum"] = params["solid"].get<std::string>() + ".momentum";
         if (const std::string problem = check_column(params, "momentum", scene); !problem.empty())
           return problem;
         const Json& g = scene.value("gravity", Json::array({0.0, 0.0, 0.0}));
         for (const auto& c : g)
           if (c.get<double>() != 0.0)
             return "momentum_balance needs a scene without gravity (its impulse is not "
                    "reported): set \"gravity\": [0, 0, 0]";
         return "";
       },
       [](const RunOutputs& run, const Json& p) {
         std::array<std::vector<double>, 3> force, momentum;
         const char* axes[3] = {"_x", "_y", "_z"};
         for (int a = 0; a < 3; ++a) {
           force[a] = run.metrics.column(p["force"].get<std::string>() + axes[a]);
           momentum[a] = run.metrics.column(p["momentum"].get<std::string>() + axes[a]);
         }
         return momentum_balance(run.metrics.column("dt"), force, momentum);
       }});
  r.push_back(
      {"hanging_strip_stretch",
       "a strip hanging from its top edge, at rest: its centre of mass's drop against linear "
       "elasticity's ρ g L² / (3E), |drop − ρgL²/(3E)| / (ρgL²/(3E)), the drop read from a "
       "centre-height column at the last step",
       "analytic: linear elasticity of a hanging strip (its uniaxial modulus E given)", "1",
       Schema::object("")
           .field("column", Schema::string().doc("the centre's height, e.g. cloth.center_y"))
           .field("rest_height", Schema::number().unit("m").doc("the centre's height unstretched"))
           .field("length", Schema::number().min(0.0, false).unit("m").doc("L: hanging length"))
           .field("surface_density", Schema::number().min(0.0, false).unit("kg/m^2").doc("ρ"))
           .field("modulus", Schema::number()
                                 .min(0.0, false)
                                 .unit("N/m")
                                 .doc("E: the sheet's uniaxial modulus per width (force per width "
                                      "per strain, free to contract sideways)")),
       [](Json& params, const Json& scene) { return check_column(params, "column", scene); },
       [](const RunOutputs& run, const Json& p) {
         return hanging_strip_stretch(run.metrics.column(p["column"]), p["rest_height"],
                                      p["length"], p["surface_density"], p["modulus"],
                                      gravity_of(run));
       }});
  {
    ErrorMeasure m{
        "against_finest",
        "a column's last value (or its largest magnitude over steps, \"at\": \"max\") against "
        "the same of the finest run of the sweep along its refinement axis, the other axes "
        "equal: |v − v_finest| / |v_finest|",
        "the finest run of the sweep (its own error is left empty, its message says so)",
        "1",
        Schema::object("")
            .field("column", Schema::string().doc("the column, e.g. smoke.kinetic_energy"))
            .field("at", Schema::string("end")
                             .one_of({"end", "max"})
                             .doc("'end': the last step's value; 'max': the largest magnitude")),
        [](Json& params, const Json& scene) { return check_column(params, "column", scene); },
        [](const RunOutputs& run, const Json& p) {
          const auto v = run.metrics.column(p["column"]);
          if (v.empty()) throw MeasureError("metrics.csv has no rows (the run took no step)");
          return p["at"] == "max" ? max_abs(v) : v.back();
        }};
    m.against_finest = true;
    r.push_back(m);
  }
  r.push_back(
      {"idle_work",
       "work the scene does not need (cost follows need): max over steps of a counter column "
       "the plugin reports whether or not it does the work (a column the run never wrote is an "
       "error, so that a misspelt or missing counter cannot read as no work)",
       "analytic: 0 (the run plan skips the feature)", "1",
       Schema::object("").field(
           "column", Schema::string().doc("the counter, e.g. smoke.band_nodes (shell band work), "
                                          "smoke.coupling_faces, smoke.level_set_cells, "
                                          "water.smoke_nodes")),
       [](Json& params, const Json& scene) { return check_column(params, "column", scene); },
       [](const RunOutputs& run, const Json& p) {
         const std::string column = p["column"];
         return idle_work(run.metrics.column(column));
       }});
  return r;
}

}  // namespace

double still_fluid_speed(const std::vector<double>& speed) {
  return max_abs(speed);
}

double max_relative_divergence(const std::vector<double>& divergence) {
  return max_abs(divergence);
}

double water_volume_drift(const std::vector<double>& volume, const std::vector<double>& change) {
  same_length(volume, change);
  const double v0 = volume.front() - change.front();
  if (!(v0 > 0.0)) throw MeasureError("the water's initial volume is not positive");
  return max_abs(change) / v0;
}

double water_volume_drift(const std::vector<double>& volume, const std::vector<double>& change,
                          const std::vector<double>& added, const std::vector<double>& outflow) {
  same_length(volume, change);
  same_length(volume, added);
  same_length(volume, outflow);
  const double v0 = volume.front() - change.front();
  double held = 0.0, drift = 0.0;
  for (size_t i = 0; i < volume.size(); ++i) {
    held = std::max(held, v0 + added[i] - outflow[i]);
    drift = std::max(drift, std::abs(change[i] - added[i] + outflow[i]));
  }
  if (!(held > 0.0)) throw MeasureError("the run should never have held any water");
  return drift / held;
}

double water_shape_error(double symmetric_difference, double initial_volume) {
  if (!(initial_volume > 0.0)) throw MeasureError("the water's initial volume is not positive");
  return std::isfinite(symmetric_difference) ? symmetric_difference / initial_volume : kNaN;
}

double free_fall_error(const std::vector<double>& time, const std::vector<double>& height,
                       double h0, double v0, double g) {
  same_length(time, height);
  std::vector<double> error(time.size());
  for (size_t i = 0; i < time.size(); ++i)
    error[i] = height[i] - (h0 + v0 * time[i] - 0.5 * g * time[i] * time[i]);
  const double drop = 0.5 * g * time.back() * time.back();
  if (!(drop > 0.0)) throw MeasureError("free_fall: no drop (zero gravity or no time)");
  return max_abs(error) / drop;
}

double linear_motion_error(const std::vector<double>& time, const std::vector<double>& position,
                           double x0, double v) {
  same_length(time, position);
  std::vector<double> error(time.size());
  for (size_t i = 0; i < time.size(); ++i) error[i] = position[i] - (x0 + v * time[i]);
  const double distance = std::abs(v) * (time.empty() ? 0.0 : time.back());
  if (!(distance > 0.0))
    throw MeasureError("linear_motion: no distance travelled (v = 0 or no time)");
  return max_abs(error) / distance;
}

double edge_strain(const std::vector<double>& strain) {
  if (strain.empty()) throw MeasureError("metrics.csv has no rows (the run took no step)");
  return max_abs(strain);
}

double projection_error(const std::vector<double>& velocity_error) {
  if (velocity_error.empty()) throw MeasureError("metrics.csv has no rows (the run took no step)");
  return max_abs({velocity_error.front()});
}

double kinetic_energy_loss(const std::vector<double>& kinetic, double initial) {
  if (kinetic.empty()) throw MeasureError("metrics.csv has no rows (the run took no step)");
  if (!(initial > 0.0))
    throw MeasureError("kinetic_energy_loss: the initial energy is not positive");
  return max_abs({(kinetic.back() - initial) / initial});
}

double momentum_balance(const std::vector<double>& dt,
                        const std::array<std::vector<double>, 3>& force,
                        const std::array<std::vector<double>, 3>& momentum) {
  for (int a = 0; a < 3; ++a) {
    same_length(dt, force[a]);
    same_length(dt, momentum[a]);
  }
  if (dt.size() < 2) throw MeasureError("momentum_balance: needs two steps or more");
  double scale = 0.0;
  std::vector<double> residual(dt.size(), 0.0);
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero();
  const auto p = [&](size_t n) {
    return Eigen::Vector3d(momentum[0][n], momentum[1][n], momentum[2][n]);
  };
  for (size_t n = 0; n < dt.size(); ++n) {
    if (n > 0) impulse += dt[n] * Eigen::Vector3d(force[0][n], force[1][n], force[2][n]);
    residual[n] = (p(n) - p(0) - impulse).norm();
    scale = std::max(scale, p(n).norm());
  }
  if (!(scale > 0.0)) throw MeasureError("momentum_balance: the solid never moves");
  return max_abs(residual) / scale;
}

double hanging_strip_stretch(const std::vector<double>& center_height, double rest_height,
                             double length, double density, double modulus, double g) {
  if (center_height.empty()) throw MeasureError("metrics.csv has no rows (the run took no step)");
  const double expected = density * g * length * length / (3.0 * modulus);
  if (!(expected > 0.0))
    throw MeasureError("hanging_strip_stretch: no expected drop (zero gravity or density)");
  return max_abs({((rest_height - center_height.back()) - expected) / expected});
}

double idle_work(const std::vector<double>& counter) {
  return counter.empty() ? 0.0 : max_abs(counter);
}

double leak_fraction(const std::vector<double>& far, const std::vector<double>& total) {
  same_length(far, total);
  std::vector<double> share(far.size());
  for (size_t i = 0; i < far.size(); ++i) share[i] = total[i] > 0.0 ? far[i] / total[i] : 0.0;
  return max_abs(share);
}

std::vector<FrontSample> read_front_data(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw IoError("cannot read " + file.string());
  std::vector<FrontSample> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line[0] == 'T') continue;
    FrontSample s;
    char comma = 0;
    if (!(std::istringstream(line) >> s.T >> comma >> s.Z) || comma != ',')
      throw MeasureError(file.string() + ": expected rows T,Z, found '" + line + "'");
    rows.push_back(s);
  }
  if (rows.empty()) throw MeasureError(file.string() + " holds no T,Z rows");
  return rows;
}

double dam_break_front_error(const std::vector<double>& time, const std::vector<double>& front,
                             double a, double g, const std::vector<FrontSample>& data,
                             double T_from, double T_to, bool take_out_release_delay) {
  same_length(time, front);
  const double scale = std::sqrt(2.0 * g / a);
  std::vector<double> T(time.size()), Z(time.size());
  for (size_t i = 0; i < time.size(); ++i) {
    T[i] = time[i] * scale;
    Z[i] = front[i] / a;
  }
  double delay = 0.0;
  if (take_out_release_delay) {
    // T_sim at which the simulated front first reaches each of their Z before T_from.
    int count = 0;
    for (const auto& s : data) {
      if (s.T >= T_from) continue;
      for (size_t i = 1; i < Z.size(); ++i)
        if (Z[i] >= s.Z && Z[i] > Z[i - 1]) {
          delay += s.T - (T[i - 1] + (T[i] - T[i - 1]) * (s.Z - Z[i - 1]) / (Z[i] - Z[i - 1]));
          ++count;
          break;
        }
    }
    if (count == 0)
      throw MeasureError("dam_break_front: the front reaches none of the data's Z before "
                         "from_T, so no release delay can be measured");
    delay /= count;
  }
  std::vector<double> errors;
  for (const auto& s : data)
    if (s.T >= T_from && s.T <= T_to && s.T <= T.back())
      errors.push_back((linear(T, Z, s.T - delay) - s.Z) / s.Z);
  if (errors.empty())
    throw MeasureError("dam_break_front: the run ends at T = " + std::to_string(T.back()) +
                       ", before the first data point in [from_T, to_T]: run longer");
  return max_abs(errors);
}

double standing_wave_period_error(const std::vector<double>& time,
                                  const std::vector<double>& surface, double depth,
                                  double wavelength, double g) {
  same_length(time, surface);
  for (const double s : surface)
    if (!std::isfinite(s)) return kNaN;
  std::vector<double> zeros;
  for (size_t i = 1; i < time.size(); ++i) {
    const double d0 = surface[i - 1] - depth, d1 = surface[i] - depth;
    if ((d0 > 0.0) != (d1 > 0.0))
      zeros.push_back(time[i - 1] + (time[i] - time[i - 1]) * d0 / (d0 - d1));
  }
  if (zeros.size() < 2)
    throw MeasureError("standing_wave_period: the surface crossed its still depth " +
                       std::to_string(zeros.size()) + " times; run at least one period");
  const double period =
      2.0 * (zeros.back() - zeros.front()) / static_cast<double>(zeros.size() - 1);
  const double k = 2.0 * std::numbers::pi / wavelength;
  const double theory = 2.0 * std::numbers::pi / std::sqrt(g * k * std::tanh(k * depth));
  return std::abs(period - theory) / theory;
}

double archimedes_draft_error(const std::vector<double>& time, const std::vector<double>& level,
                              const std::vector<double>& lowest, double draft, double window) {
  same_length(time, level);
  same_length(time, lowest);
  // Each row holds the state at the end of its step, which stands for the step (t_{i−1}, t_i].
  const double from = time.back() - window;
  if (from < 0.0)
    throw MeasureError("archimedes_draft: the window of " + std::to_string(window) +
                       " s is longer than the run (" + std::to_string(time.back()) +
                       " s); run longer or shorten \"window\"");
  double sum = 0.0, span = 0.0;
  for (size_t i = 0; i < time.size(); ++i) {
    if (time[i] <= from) continue;
    const double offset = level[i] - lowest[i];
    if (!std::isfinite(offset)) return kNaN;
    const double dt = time[i] - std::max(i == 0 ? 0.0 : time[i - 1], from);
    sum += offset * dt;
    span += dt;
  }
  return std::abs(sum / span - draft) / draft;
}

const std::vector<ErrorMeasure>& error_measures() {
  static const std::vector<ErrorMeasure> registry = make_registry();
  return registry;
}

const ErrorMeasure* find_error_measure(const std::string& name) {
  for (const auto& m : error_measures())
    if (m.name == name) return &m;
  return nullptr;
}

}  // namespace shellflow::bench
