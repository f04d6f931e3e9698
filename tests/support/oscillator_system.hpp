#pragma once
// The damped oscillator x'' + 2 zeta w x' + w^2 x = 0 as an ode::DynamicalSystem: both Lyapunov
// exponents are -zeta w exactly (for zeta < 1), the trace is -2 zeta w.
#include <Eigen/Core>

#include "mlce/ode/system.hpp"

namespace mlce::reference {

inline ode::DynamicalSystem damped_oscillator_system(double zeta, double w) {
  Eigen::MatrixXd A(2, 2);
  A << 0, 1, -w * w, -2 * zeta * w;
  ode::DynamicalSystem s;
  s.dimension = 2;
  s.rhs = [A](const Eigen::VectorXd& x, Eigen::VectorXd& dx, double) { dx = A * x; };
  s.jacobian = [A](const Eigen::VectorXd&, double) { return A; };
  return s;
}

}  // namespace mlce::reference
