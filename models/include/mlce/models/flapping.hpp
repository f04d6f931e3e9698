#pragma once
// Rigid blade flapping in forward flight (paper 000 eq. 31), nondimensional time (azimuth):
//   beta'' + (gamma/8)(1 + 4/3 mu sin t) beta' + (nu^2 + (gamma/8)(4/3 mu cos t + mu^2 sin 2t)) beta = 0
// State [beta, beta']. Linear, time-periodic with period 2 pi.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace mlce::models {

struct FlappingParameters {
  double gamma = 8.0;  ///< Lock number (paper 000 does not state it; 8 is typical)
  double nu = 1.0;     ///< nondimensional flap frequency nu_beta (articulated blade: 1)
  double mu = 0.15;    ///< advance ratio
  void validate() const;
};

class FlappingModel {
 public:
  explicit FlappingModel(const FlappingParameters& p, bool check = true);
  const FlappingParameters& parameters() const { return p_; }
  int dimension() const { return 2; }
  void operator()(const Eigen::VectorXd& x, Eigen::VectorXd& dxdt, double t) const;
  /// The same right-hand side in complex arithmetic (complex-step differentiation).
  void rhs(const Eigen::VectorXcd& x, Eigen::VectorXcd& dxdt, double t) const;
  Eigen::MatrixXd jacobian(const Eigen::VectorXd& x, double t) const;
  std::vector<std::string> state_names() const { return {"beta", "betadot"}; }

 private:
  FlappingParameters p_;
};

}  // namespace mlce::models
