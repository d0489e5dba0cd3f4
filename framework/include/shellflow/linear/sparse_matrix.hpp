#pragma once
// The sparse matrix type every shellflow linear solver takes: compressed row storage
// (CSR) with sorted column indices, double precision, int indices. The pressure
// matrices of the MAC-grid projection (§4.3, Guendelman et al. 2005) are symmetric
// positive definite, or positive semidefinite for an all-Neumann region; the solvers
// expect the FULL symmetric pattern (both triangles stored).

#include <Eigen/SparseCore>

namespace shellflow::linear {

/// Symmetric positive (semi)definite matrix, both triangles stored, compressed.
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

}  // namespace shellflow::linear
