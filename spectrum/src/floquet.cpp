#include "mlce/spectrum/floquet.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>

#include "mlce/ode/step_budget.hpp"
#include "mlce/spectrum/liouville.hpp"
#include "variational.hpp"

namespace mlce::spectrum {
namespace {

using cd = std::complex<double>;

/// Eigen-decomposition with left eigenvectors (rows of U^-1) for first-order eigenvalue
/// sensitivities d(value_i) = (U^-1 dM U)_ii.
struct Decomposition {
  Eigen::VectorXcd values;
  Eigen::MatrixXcd U, Uinv;
  double condition = 0.0;
  explicit Decomposition(const Eigen::MatrixXd& M) {
    const Eigen::EigenSolver<Eigen::MatrixXd> es(M);
    if (es.info() != Eigen::Success) throw std::runtime_error("eigenvalue computation did not converge");
    values = es.eigenvalues();
    U = es.eigenvectors();
    const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(U);
    Uinv = lu.inverse();
    condition = U.cwiseAbs().colwise().sum().maxCoeff() * Uinv.cwiseAbs().colwise().sum().maxCoeff();
  }
  cd derivative(Eigen::Index i, const Eigen::MatrixXd& dM) const { return Uinv.row(i) * dM.cast<cd>() * U.col(i); }
};

LinearSpectrum sorted(LinearSpectrum s, const Eigen::MatrixXd& sens) {
  const Eigen::Index n = s.exponents.size();
  std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  // Descending real part; a conjugate pair lists its positive frequency first.
  std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) {
    if (s.exponents(a) != s.exponents(b)) return s.exponents(a) > s.exponents(b);
    return s.frequencies(a) > s.frequencies(b);
  });
  LinearSpectrum out = s;
  out.sensitivities.resize(sens.rows(), n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index k = order[static_cast<std::size_t>(i)];
    out.exponents(i) = s.exponents(k), out.frequencies(i) = s.frequencies(k), out.values(i) = s.values(k);
    out.sensitivities.col(i) = sens.col(k);
  }
  return out;
}

void condition_warning(LinearSpectrum& s) {
  if (!s.parameters.empty() && s.eigenvector_condition > 1e8)
  {
    char buf[192];
    std::snprintf(buf, sizeof buf,
                  "eigenvectors nearly dependent (condition %.3g): repeated eigenvalues, the sensitivities of the merging "
                  "ones are unreliable",
                  s.eigenvector_condition);
    s.warnings.push_back(buf);
  }
}

}  // namespace

LinearSpectrum linear_eigen(const Eigen::MatrixXd& A, const std::vector<Eigen::MatrixXd>& dA,
                            const std::vector<std::string>& names) {
  if (A.rows() != A.cols() || A.rows() == 0) throw std::invalid_argument("linear_eigen: expected a square matrix");
  if (!A.allFinite()) throw std::invalid_argument("linear_eigen: the matrix has non-finite entries");
  const Decomposition d(A);
  const Eigen::Index n = A.rows();
  LinearSpectrum s;
  s.values = d.values;
  s.exponents = d.values.real();
  s.frequencies = d.values.imag();
  s.parameters = names;
  s.eigenvector_condition = d.condition;
  Eigen::MatrixXd sens(static_cast<Eigen::Index>(dA.size()), n);
  for (std::size_t k = 0; k < dA.size(); ++k)
    for (Eigen::Index i = 0; i < n; ++i) sens(static_cast<Eigen::Index>(k), i) = d.derivative(i, dA[k]).real();
  s = sorted(s, sens);
  s.mean_divergence = A.trace();
  condition_warning(s);
  if (auto w = liouville_mismatch(s.exponents, s.mean_divergence, "the eigenvalue solver lost accuracy")) s.warnings.push_back(*w);
  return s;
}

LinearSpectrum floquet(const ode::DynamicalSystem& sys, const FloquetOptions& o,
                       const std::vector<ode::ParameterFamily>& parameters) {
  const Eigen::Index n = sys.dimension;
  const Eigen::VectorXd x0 = o.orbit ? *o.orbit : Eigen::VectorXd::Zero(n);
  if (x0.size() != n) throw std::invalid_argument("orbit state: expected " + std::to_string(n) + " values");
  if (o.orbit && !parameters.empty())
    throw std::invalid_argument("sensitivities are computed about the trivial solution only (no --orbit)");
  require(sys, o.jacobian);
  const double T = o.period > 0 ? o.period : sys.period;
  std::vector<std::string> names;
  for (const auto& p : parameters) names.push_back(p.name);
  // Trivial solution: it must be a solution (f(0, t) = 0) for the linearisation to mean anything.
  // Rounding leaves |f(0, t)| of order eps times the size of the terms that cancel, which grows
  // with the Jacobian (Omega^2 at a high rotor speed): the tolerance is relative to it.
  if (!o.orbit) {
    Eigen::VectorXd f(n);
    double worst = 0.0, scale = 1.0;
    for (int k = 0; k < 8; ++k) {
      const double t = o.t0 + (T > 0 ? T : 1.0) * k / 8.0;
      sys.rhs(x0, f, t);
      const Eigen::MatrixXd A = jacobian(sys, o.jacobian, x0, t);
      if (!f.allFinite() || !A.allFinite())
        throw std::invalid_argument("the model's right-hand side or Jacobian at x = 0 is not finite (a parameter beyond the range of a double?)");
      worst = std::max(worst, f.cwiseAbs().maxCoeff());
      scale = std::max(scale, A.cwiseAbs().rowwise().sum().maxCoeff());
    }
    if (worst > 1e-9 * scale) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "x = 0 is not a solution of this model (|f(0, t)| = %.3g, above the %.3g that rounding explains): give --orbit",
                    worst, 1e-9 * scale);
      throw std::invalid_argument(buf);
    }
  }
  if (!(T > 0)) {
    // Autonomous: the exponents of the linearisation at the equilibrium are eigenvalues of A.
    std::vector<Eigen::MatrixXd> dA;
    for (const auto& p : parameters) {
      const double d = detail::VariationalSystem::kParameterStep * p.scale;
      dA.push_back((jacobian(p.make(p.nominal + d), o.jacobian, x0, o.t0) - jacobian(p.make(p.nominal - d), o.jacobian, x0, o.t0)) / (2.0 * d));
    }
    LinearSpectrum s = linear_eigen(jacobian(sys, o.jacobian, x0, o.t0), dA, names);
    s.warnings.push_back("the system is autonomous (no period): exponents are eigenvalues of the Jacobian at x0");
    return s;
  }
  {
    char what[64];
    std::snprintf(what, sizeof what, "Floquet: one period T = %.6g", T);
    ode::require_step_budget(sys, x0, o.t0, T, 1, o.integrator, what);
  }
  const detail::VariationalSystem vs(sys, o.jacobian, parameters);
  Eigen::VectorXd X = Eigen::VectorXd::Zero(vs.size());
  X.head(n) = x0;
  Eigen::Map<Eigen::MatrixXd>(X.data() + n, n, n).setIdentity();
  double h = 0.0;
  ode::IntegrationStats st;
  ode::integrate_to(vs, X, o.t0, o.t0 + T, o.integrator, h, st);
  const Eigen::MatrixXd Phi = Eigen::Map<const Eigen::MatrixXd>(X.data() + n, n, n);
  const Decomposition d(Phi);
  LinearSpectrum s;
  s.period = T;
  s.parameters = names;
  s.values = d.values;
  s.eigenvector_condition = d.condition;
  s.exponents.resize(n), s.frequencies.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double m = std::abs(d.values(i));
    if (!(m > 0.0)) throw std::runtime_error("Floquet: a multiplier underflowed to 0 over one period (exponent below about -700/T)");
    s.exponents(i) = std::log(m) / T;
    s.frequencies(i) = std::arg(d.values(i)) / T;
  }
  Eigen::MatrixXd sens(static_cast<Eigen::Index>(parameters.size()), n);
  if (!parameters.empty()) {
    Eigen::VectorXd fT(n);
    sys.rhs(X.head(n), fT, o.t0 + T);
    const Eigen::MatrixXd A_T = jacobian(sys, o.jacobian, X.head(n), o.t0 + T);
    for (std::size_t k = 0; k < parameters.size(); ++k) {
      const auto& p = parameters[k];
      const double dd = detail::VariationalSystem::kParameterStep * p.scale;
      const double Tp = (p.make(p.nominal + dd).period - p.make(p.nominal - dd).period) / (2.0 * dd);
      // Total derivative of Phi(T(p), p): the variational part plus the moved end time.
      const Eigen::MatrixXd Phi_p = Eigen::Map<const Eigen::MatrixXd>(X.data() + vs.offset(k) + n, n, n) / p.scale + A_T * Phi * Tp;
      for (Eigen::Index i = 0; i < n; ++i)
        sens(static_cast<Eigen::Index>(k), i) = (d.derivative(i, Phi_p) / d.values(i)).real() / T - s.exponents(i) * Tp / T;
    }
  }
  if (o.orbit) {
    const double gap = (X.head(n) - x0).norm() / std::max(1.0, x0.norm());
    if (gap > 1e-6) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "the orbit does not close over one period (relative gap %.3g)", gap);
      s.warnings.push_back(buf);
    }
  }
  s = sorted(s, sens);
  // Multipliers below the integration error of Phi are noise: say which exponents lie below that.
  const double phi_norm = Phi.cwiseAbs().rowwise().sum().maxCoeff();
  const double phi_error = std::max({o.integrator.rtol * phi_norm, o.integrator.atol,
                                     std::numeric_limits<double>::epsilon() * phi_norm});
  s.resolution_floor = std::log(phi_error) / T;
  Eigen::Index first_below = n;
  while (first_below > 0 && s.exponents(first_below - 1) < s.resolution_floor) --first_below;
  if (first_below < n) {
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "exponents %d..%d lie below %.4g, the resolution of the monodromy matrix (its multipliers are "
                  "under its integration error %.2g): they are not resolved; the QR spectrum (mlce spectrum) "
                  "or, for an isotropic rotor, mlce eigen resolves them",
                  static_cast<int>(first_below + 1), static_cast<int>(n), s.resolution_floor, phi_error);
    s.warnings.push_back(buf);
  }
  s.mean_divergence = X(vs.divergence_index()) / T;
  condition_warning(s);
  if (auto w = liouville_mismatch(s.exponents, s.mean_divergence,
                                  "the monodromy matrix was not integrated accurately (tighten rtol/atol) or its "
                                  "multipliers span too many orders of magnitude for the eigenvalue solver"))
    s.warnings.push_back(*w);
  return s;
}

}  // namespace mlce::spectrum
