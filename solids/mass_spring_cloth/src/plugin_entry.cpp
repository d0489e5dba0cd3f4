// Registers the "mass_spring_cloth" solid plugin (shellflow_mass_spring_cloth.so).
#include "mass_spring_cloth/mass_spring_cloth.hpp"
#include "shellflow/sdk/plugin.hpp"

SHELLFLOW_SOLID_PLUGIN(shellflow::cloth::MassSpringCloth, "mass_spring_cloth")
