#include "mass_spring_cloth/block_jacobi_preconditioner.hpp"

#include <Eigen/LU>

#include "shellflow/sdk/error.hpp"

namespace shellflow::cloth {

namespace {

constexpr int kParallelRows = 8192;

}  // namespace

void BlockJacobiPreconditioner::compute(const BlockSparseMatrix& a) {
  const int n = a.node_count();
  m_inverse.resize(n);
  bool singular = false;
#pragma omp parallel for schedule(static) reduction(|| : singular) if (n >= kParallelRows)
  for (int i = 0; i < n; ++i) {
    const Eigen::Matrix3d block = a.block(a.diagonal(i));
    bool invertible = false;
    double determinant = 0.0;
    block.computeInverseAndDetWithCheck(m_inverse[i], determinant, invertible);
    singular = singular || !invertible || !(determinant > 0.0);
  }
  if (singular)
    throw NumericalError(
        "mass_spring_cloth: a diagonal block of the implicit system is not positive "
        "definite; lower the stiffness or the step (solver/max_substep)");
}

void BlockJacobiPreconditioner::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  const int n = static_cast<int>(m_inverse.size());
  z.resize(3 * n);
#pragma omp parallel for schedule(static) if (n >= kParallelRows)
  for (int i = 0; i < n; ++i) z.segment<3>(3 * i) = m_inverse[i] * r.segment<3>(3 * i);
}

}  // namespace shellflow::cloth
