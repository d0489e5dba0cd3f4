// Registers BulletRigidSolver as the solid plugin "bullet_rigid" (shellflow_bullet_rigid.so).
#include "shellflow/sdk/plugin.hpp"
#include "shellflow/bullet_rigid/bullet_rigid_solver.hpp"

SHELLFLOW_SOLID_PLUGIN(shellflow::bullet_rigid::BulletRigidSolver, "bullet_rigid")
