#include "mlce/models/flapping.hpp"

#include <cmath>
#include <stdexcept>

namespace mlce::models {

void FlappingParameters::validate() const {
  if (!(gamma >= 0.0) || !std::isfinite(gamma)) throw std::invalid_argument("gamma: expected >= 0");
  if (!std::isfinite(nu)) throw std::invalid_argument("nu: expected a finite number");
  if (!(mu >= 0.0) || !std::isfinite(mu)) throw std::invalid_argument("mu: expected >= 0");
}

FlappingModel::FlappingModel(const FlappingParameters& p, bool check) : p_(p) {
  if (check) p_.validate();
}

Eigen::MatrixXd FlappingModel::jacobian(const Eigen::VectorXd&, double t) const {
  const double g8 = p_.gamma / 8.0;
  Eigen::MatrixXd J(2, 2);
  J << 0.0, 1.0, -(p_.nu * p_.nu + g8 * (4.0 / 3.0 * p_.mu * std::cos(t) + p_.mu * p_.mu * std::sin(2.0 * t))),
      -g8 * (1.0 + 4.0 / 3.0 * p_.mu * std::sin(t));
  return J;
}

void FlappingModel::operator()(const Eigen::VectorXd& x, Eigen::VectorXd& dxdt, double t) const {
  dxdt.resize(2);
  dxdt = jacobian(x, t) * x;  // linear: f = A(t) x
}

void FlappingModel::rhs(const Eigen::VectorXcd& x, Eigen::VectorXcd& dxdt, double t) const {
  dxdt = jacobian(x.real(), t).cast<std::complex<double>>() * x;
}

}  // namespace mlce::models
