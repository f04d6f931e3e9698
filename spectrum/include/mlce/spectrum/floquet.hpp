#pragma once
// Floquet (characteristic) exponents of the problem linearised about the trivial solution x = 0,
// or about a periodic orbit through x0 at t0: the monodromy matrix Phi = Y(t0 + T, t0) from
// Y' = A(x(t), t) Y, Y(t0) = I; multipliers mu_i = eig(Phi); exponents log|mu_i| / T and
// frequencies arg(mu_i) / T in (-pi/T, pi/T] rad per time unit (paper 001 eq. 8; a frequency is
// only known modulo 2 pi / T). Sensitivities (trivial solution only): Phi_/p from the same
// variational system as the QR method (paper 000 eq. 26 over one period), then
// mu_i/p = (U^-1 Phi_/p U)_ii and lambda_i/p = Re(mu_i/p / mu_i) / T - lambda_i T_/p / T.
//
// Linear time-invariant problems (and autonomous systems, period 0): eigenvalues of A with
// sensitivities Re(U^-1 A_/p U)_ii (linear_eigen).
#include <Eigen/Core>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "mlce/ode/runge_kutta.hpp"
#include "mlce/ode/system.hpp"
#include "mlce/spectrum/tangent.hpp"

namespace mlce::spectrum {

struct LinearSpectrum {
  Eigen::VectorXd exponents;    ///< real parts, 1/time, sorted descending
  Eigen::VectorXd frequencies;  ///< imaginary parts, rad/time, aligned with exponents
  Eigen::VectorXcd values;      ///< eigenvalues (LTI) or multipliers (Floquet), aligned
  std::vector<std::string> parameters;
  Eigen::MatrixXd sensitivities;  ///< parameters x exponents
  double period = 0.0;            ///< Floquet: T; 0 for LTI
  double eigenvector_condition = 0.0;  ///< cond(U): large means (nearly) defective, sensitivities unreliable
  /// tr A (LTI), or its mean over the period integrated with the monodromy matrix (Floquet): what
  /// the exponents sum to (Liouville, liouville.hpp); a mismatch is reported as a warning.
  double mean_divergence = 0.0;
  /// Floquet: ln(e)/T with e the error of the monodromy matrix, max(rtol |Phi|, atol, eps |Phi|)
  /// (|.| the infinity norm). A multiplier below e is integration error, so exponents below this
  /// floor are not resolved (a warning names them). NaN for LTI.
  double resolution_floor = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::string> warnings;
};

struct FloquetOptions {
  double t0 = 0.0;
  double period = 0.0;  ///< 0: the system's own period
  std::optional<Eigen::VectorXd> orbit;  ///< a state on the periodic orbit at t0; none = x = 0
  JacobianMethod jacobian = JacobianMethod::analytic;
  ode::IntegratorOptions integrator;  ///< default rtol 1e-10, atol 1e-12 (one period only)
  FloquetOptions() { integrator.rtol = 1e-10, integrator.atol = 1e-12; }
};

LinearSpectrum floquet(const ode::DynamicalSystem& sys, const FloquetOptions& options,
                       const std::vector<ode::ParameterFamily>& parameters = {});

/// Eigenvalues of a constant matrix A, with sensitivities to the matrices dA[k] = dA/dp_k.
LinearSpectrum linear_eigen(const Eigen::MatrixXd& A, const std::vector<Eigen::MatrixXd>& dA = {},
                            const std::vector<std::string>& parameter_names = {});

}  // namespace mlce::spectrum
