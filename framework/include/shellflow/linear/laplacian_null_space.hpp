#pragma once
// The null space of a GridLaplacian read from its graph: each connected component of its
// active unknowns (a nonzero diagonal) that reaches no p = 0 (no Dirichlet conductance, no
// domain face of weight > 0) is singular, with the constant as its null vector (§4.3: an
// enclosed region, Guendelman et al. 2005). Cut cells' extra parts join their components
// through their links, so a pocket under a plate is found whatever cells its parts lie in.

#include "shellflow/linear/constant_null_space.hpp"
#include "shellflow/linear/grid_laplacian.hpp"

namespace shellflow::linear {

/// The constants of the singular components of `a`, numbered in the order of their first unknown.
ConstantNullSpace null_space_of(const GridLaplacian& a);

}  // namespace shellflow::linear
