#pragma once
// Preconditioner: z = M^{-1} r for preconditioned conjugate gradients. M must be symmetric
// positive definite (on the range of A when A is semidefinite) for CG to stay valid.
// Implementations: Mic0Preconditioner (modified incomplete Cholesky, sequential) and
// MultigridPreconditioner (geometric V-cycle on the cell grid, McAdams et al. 2010,
// parallel), chosen per scene by the grid fluid's `pressure.preconditioner`.

#include <Eigen/Core>

namespace shellflow::linear {

class Preconditioner {
 public:
  virtual ~Preconditioner() = default;
  /// Number of unknowns it was built for.
  virtual int size() const = 0;
  /// z = M^{-1} r. `z` is resized if needed; its entry value is ignored.
  virtual void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const = 0;
};

}  // namespace shellflow::linear
