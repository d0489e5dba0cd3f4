// GridFluid::schema(): the "fluid" block of a scene, its parts' own schemas gathered.
#include "shellflow/grid_fluid/grid_fluid_solver.hpp"

namespace shellflow::grid_fluid {

sdk::Schema GridFluid::schema() {
  using sdk::Schema;
  return Schema::object(
             "smoke on a uniform MAC grid that never leaks through thin shells (§3, §4.1–4.3, "
             "Guendelman et al. 2005), two-way coupled to shells that receive fluid forces "
             "(§5.1)")
      .field("domain",
             Schema::object("the simulated box")
                 .field("min", Schema::vec3(0.0, 0.0, 0.0).unit("m").doc("lower corner"))
                 .field("max", Schema::vec3(1.0, 1.0, 1.0)
                                   .unit("m")
                                   .doc("upper corner (moved to fit cubic cells if needed)")))
      .field("resolution", Schema::integer(32).min(2).max(1024).doc(
                               "cells along the longest side of the domain; Δx follows"))
      .field("density", Schema::number()
                            .min(0.0, false)
                            .unit("kg/m^3")
                            .optional()
                            .doc("fluid density ρ: sets the fluid's inertia against two-way shells "
                                 "and the water's pressure on them (§5.1). Default: 1 for smoke "
                                 "(PhysBAM's; air at 20 °C: 1.2), 1000 with a \"water\" block"))
      .field("boundary", DomainBoundary::schema())
      .field("epsilon", Schema::number(1e-3)
                            .min(1e-9, false)
                            .max(0.1)
                            .unit("Δx")
                            .doc("wedge thickness ε of the shells in units of Δx (§3; PhysBAM: "
                                 "1e-3); semi-Lagrangian rays use 2ε (§4.1)"))
      .field(
          "pressure",
          Schema::object("the §4.3 pressure solve")
              .field("solver", Schema::string("pcg")
                                   .one_of({"pcg", "cholmod"})
                                   .doc("pcg: conjugate gradients with MIC(0); cholmod: direct "
                                        "SuiteSparse factorisation (reference, small grids)"))
              .field("preconditioner",
                     Schema::string("multigrid")
                         .one_of({"multigrid", "mic0"})
                         .doc("of pcg. multigrid: a V-cycle (McAdams et al. 2010), iterations "
                              "nearly independent of the grid (plume to 1e-5: 5 per step at 32^3 "
                              "and 64^3 where MIC(0) takes 24 and 43), parallel; the default, as "
                              "the plume's projection is 2x faster at 32^3 and 5x at 64^3 even "
                              "on one thread (bench_grid_fluid). mic0: modified incomplete "
                              "Cholesky (Bridson 2008), sequential triangular solves"))
              .field("tolerance", Schema::number(1e-6)
                                      .min(0.0, false)
                                      .max(0.1)
                                      .doc("relative residual |b − Ap|/|b| of PCG; the largest "
                                           "cell divergence is also kept below tolerance × "
                                           "max|u*|"))
              .field("max_iterations",
                     Schema::integer(2000).min(1).doc("PCG iteration cap per region"))
              .field("coupling_tolerance",
                     Schema::number(1e-4)
                         .min(0.0, false)
                         .max(0.1)
                         .doc("relative residual of the §5.1 coupling-pressure solve (two-way "
                              "shells only); it sets forces, not the velocity field, so it can be "
                              "looser than the projection's")))
      .field("smoke",
             Schema::object("smoke physics (§4.1, Fedkiw et al. 2001)")
                 .field("ambient_temperature", Schema::number(298.0).min(0.0).unit("K").doc("T_a"))
                 .field("density_buoyancy", Schema::number(0.0).min(0.0).unit("m/s^2").doc(
                                                "α in f = −αρz + β(T − T_a)z (smoke sinks "
                                                "with density)"))
                 .field("temperature_buoyancy",
                        Schema::number(0.001).min(0.0).unit("m/s^2/K").doc(
                            "β in f = −αρz + β(T − T_a)z (PhysBAM default 0.001); active "
                            "only when a source sets a temperature"))
                 .field("up", Schema::vec3().optional().doc(
                                  "upward direction z (left out: −gravity, or +y without "
                                  "gravity)"))
                 .field("vorticity_confinement",
                        Schema::number(0.0).min(0.0).max(10.0).doc(
                            "ε_vc in f = ε_vc Δx (N × ω) (PhysBAM smoke: 0.3); 0 turns it "
                            "off")))
      .field("sources", Schema::array(SmokeSource::schema())
                            .default_value(Schema::Json::array())
                            .doc("smoke emitters (spheres and boxes)"))
      .field("water", Liquid::schema().optional())
      .field("initial_velocity",
             AnalyticVelocity::schema().optional().doc(
                 "the velocity at t = 0 (default: at rest): an analytic field for known "
                 "answers (Taylor–Green's decay, a manufactured projection)"))
      .field("prescribed_velocity",
             AnalyticVelocity::schema().optional().doc(
                 "water only: the water is carried by this field at every step instead of "
                 "a solved velocity (no gravity, pressure or extrapolation; shells still "
                 "block the rays): the level set's transport tests (Zalesak's slotted "
                 "sphere in a rigid_rotation, LeVeque's deformation). Adds the column "
                 "water_symmetric_difference, the volume where the water differs from its "
                 "shape at t = 0"))
      .field("probes", FluidProbes::schema());
}

}  // namespace shellflow::grid_fluid
