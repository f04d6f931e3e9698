#pragma once
// A dynamical system as the Jacobian-based methods (spectrum/) see it: dx/dt = f(x, t), optionally
// its analytic Jacobian and a complex-arithmetic right-hand side (for complex-step
// differentiation). Type-erased so that models and methods meet at one small boundary; a model
// only fills what it has, and the methods say clearly when something they need is missing.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace mlce::ode {

struct DynamicalSystem {
  int dimension = 0;
  /// dx/dt = f(x, t).
  std::function<void(const Eigen::VectorXd& x, Eigen::VectorXd& dxdt, double t)> rhs;
  /// df/dx (optional).
  std::function<Eigen::MatrixXd(const Eigen::VectorXd& x, double t)> jacobian;
  /// f in complex arithmetic, analytic in x (optional; enables complex-step Jacobians).
  std::function<void(const Eigen::VectorXcd& x, Eigen::VectorXcd& dxdt, double t)> rhs_complex;
  /// Smallest period of the explicit time dependence; 0 = autonomous.
  double period = 0.0;
  std::vector<std::string> state_names;
};

/// A one-parameter family of systems: make(value) is the system at that parameter value.
/// `scale` sets the size of the perturbations (relative parameter steps are taken on value/scale).
struct ParameterFamily {
  std::string name;
  double nominal = 0.0;
  double scale = 1.0;
  std::function<DynamicalSystem(double value)> make;
};

}  // namespace mlce::ode
