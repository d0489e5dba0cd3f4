// Registers the kinematic_shell solid (shellflow_kinematic_shell.so).
#include "shellflow/sdk/plugin.hpp"
#include "shellflow/kinematic_shell/kinematic_shell.hpp"

SHELLFLOW_SOLID_PLUGIN(shellflow::kinematic_shell::KinematicShell, "kinematic_shell")
