#include "shellflow/grid_fluid/pressure/rigid_shell_coupling.hpp"

namespace shellflow::grid_fluid {

BodyVector RigidShellFaces::impulse(const Eigen::Ref<const Eigen::VectorXd>& q) const {
  BodyVector k = BodyVector::Zero();
  for (size_t f = 0; f < jumps.size(); ++f) k -= jumps[f].of(q) * rows[f];
  return k;
}

void RigidShellFaces::add_transpose(const BodyVector& w, Eigen::VectorXd& y) const {
  for (size_t f = 0; f < jumps.size(); ++f) jumps[f].scatter(-rows[f].dot(w), y);
}

double RigidShellOperator::multiply_and_dot(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  double dot = m_laplacian.multiply_and_dot(x, y);
  for (const RigidShellFaces& body : m_bodies) {
    const BodyVector k = body.impulse(x);
    const BodyVector w = m_cell_mass * (body.inverse_mass * k);
    body.add_transpose(w, y);
    dot += k.dot(w);  // xᵀ Kᵀ w
  }
  return dot;
}

double RigidShellOperator::residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                                    Eigen::VectorXd& r) const {
  m_laplacian.residual(b, x, r);
  for (const RigidShellFaces& body : m_bodies) {
    const BodyVector w = m_cell_mass * (body.inverse_mass * body.impulse(x));
    body.add_transpose(-w, r);  // r −= Kᵀ w
  }
  return r.squaredNorm();
}

}  // namespace shellflow::grid_fluid
