#pragma once
// The fiducial trajectory, its tangent matrix and their parameter sensitivities as one ODE:
//   x'     = f(x, t)                                   (paper 000 eq. 1)
//   Z'     = A Z,   A = f_/x(x, t)                     (eq. 3; Z starts from Q_{j-1}; n x k, k <= n
//                                                        columns: the k leading exponents only)
//   x_/p'  = A x_/p + f_/p                             (eq. 28)
//   Z_/p'  = A Z_/p + (dA/dp) Z,  dA/dp = A_/x x_/p + A_/p   (eqs. 26-27)
//   D'     = tr A                                      (Liouville: D(t) = ln det of the tangent
//                                                        flow, the sum of all exponents x time;
//                                                        0 when k < n: no check then)
// Layout of the state: [x | Z (column-major) | x_/p1 | Z_/p1 | x_/p2 | ... | D].
// Parameters are scaled, p = p0 + scale s, and derivatives are taken with respect to s so that
// every block is of order one. The local derivatives f_/s and (dA/ds) Z are central differences
// of the model at s = +-delta along (x_/s, 1): error O(delta^2) relative, delta = 1e-4. The
// propagation of the sensitivities (eqs. 12, 18-28) is exact; only these local model derivatives
// are differenced.
#include <Eigen/Core>
#include <algorithm>
#include <Eigen/LU>
#include <vector>

#include "mlce/ode/system.hpp"
#include "mlce/spectrum/tangent.hpp"

namespace mlce::spectrum::detail {

class VariationalSystem {
 public:
  static constexpr double kParameterStep = 1e-4;

  /// `columns` tangent vectors (0 = the system's dimension, the whole spectrum).
  VariationalSystem(const ode::DynamicalSystem& sys, JacobianMethod method, const std::vector<ode::ParameterFamily>& params,
                    Eigen::Index columns = 0)
      : sys_(sys), method_(method), n_(sys.dimension), k_(columns > 0 ? columns : sys.dimension) {
    require(sys_, method_);
    if (k_ > n_)
      throw std::invalid_argument(std::to_string(k_) + " tangent vectors requested, but the system has only " +
                                  std::to_string(n_) + " states");
    for (const auto& p : params) {
      if (!p.make) throw std::invalid_argument("parameter " + p.name + ": no model family");
      const double d = kParameterStep * p.scale;
      plus_.push_back(p.make(p.nominal + d));
      minus_.push_back(p.make(p.nominal - d));
      require(plus_.back(), method_);
      require(minus_.back(), method_);
    }
  }
  Eigen::Index n() const { return n_; }
  Eigen::Index columns() const { return k_; }
  std::size_t parameters() const { return plus_.size(); }
  Eigen::Index block() const { return n_ + n_ * k_; }
  Eigen::Index size() const { return block() * static_cast<Eigen::Index>(1 + plus_.size()) + 1; }
  /// Index of D, the integral of tr A (the divergence of the vector field) along the trajectory.
  Eigen::Index divergence_index() const { return size() - 1; }

  /// Offset of parameter k's block (k = 0..P-1).
  Eigen::Index offset(std::size_t k) const { return block() * static_cast<Eigen::Index>(k + 1); }

  /// Smallest size of a tangent column the error control follows (see error_scale).
  static constexpr double kColumnFloor = 1e-280;

  /// Tolerances of the local error for ode::IntegratorOptions::error_scale. A tangent column
  /// starts each QR interval with norm 1 and shrinks like e^(lambda t): with the plain
  /// atol + rtol |x_i| its error may grow to atol, so that a column that contracts below atol over
  /// one interval holds error, not direction, and its exponent reads ln(atol) / step whatever
  /// the truth (-234 for -1000 at step 0.1, atol 1e-10). Here atol is scaled by the column's size
  /// (max-norm, at least kColumnFloor), and a parameter column Z_/p by the size of its Z column:
  /// each direction is resolved relative to itself. The state x, x_/p and D keep atol + rtol |x_i|.
  void error_scale(const Eigen::VectorXd& X, const Eigen::VectorXd& X_new, double atol, double rtol,
                   Eigen::ArrayXd& sc) const {
    sc = rtol * X.array().abs().max(X_new.array().abs());
    const Eigen::Index n = n_, k = k_;
    sc.head(n) += atol;
    for (std::size_t q = 0; q < plus_.size(); ++q) sc.segment(offset(q), n) += atol;
    sc(divergence_index()) += atol;
    for (Eigen::Index j = 0; j < k; ++j) {
      const Eigen::Index c = n + j * n;
      const double size = std::max({X.segment(c, n).cwiseAbs().maxCoeff(), X_new.segment(c, n).cwiseAbs().maxCoeff(), kColumnFloor});
      sc.segment(c, n) += atol * size;
      for (std::size_t q = 0; q < plus_.size(); ++q) sc.segment(offset(q) + n + j * n, n) += atol * size;
    }
  }

  void operator()(const Eigen::VectorXd& X, Eigen::VectorXd& dX, double t) const {
    dX.resize(X.size());
    const Eigen::Index n = n_, k = k_;
    x_ = X.head(n);
    sys_.rhs(x_, f_, t);
    dX.head(n) = f_;
    const Eigen::Map<const Eigen::MatrixXd> Z(X.data() + n, n, k);
    Eigen::Map<Eigen::MatrixXd> dZ(dX.data() + n, n, k);
    const bool whole = k == n;  // tr A is the tangent volume's rate only for the whole tangent space
    // The explicit routes form A once: the products and its trace come from it. The Jacobian-free
    // route never forms A: tr A = tr(Z^-1 A Z), from the product it computes anyway (Z starts as
    // an orthonormal or identity matrix and is integrated over one QR interval or one period).
    // (With fewer tangent vectors than states, the complex step goes direction by direction too:
    // no trace is needed then, and k complex evaluations are cheaper than the n that form A.)
    const bool explicit_a = method_ == JacobianMethod::analytic || (method_ == JacobianMethod::complex_step && whole);
    if (explicit_a) a_ = jacobian(sys_, method_, x_, t);
    if (plus_.empty()) {
      if (explicit_a) dZ.noalias() = a_ * Z;
      else tangent_product(sys_, method_, x_, t, Z, dZ);
      dX(divergence_index()) = !whole ? 0.0 : explicit_a ? a_.trace() : trace_of_similar(Z, dZ);
      return;
    }
    // One product A [Z | x_/p1 | Z_/p1 | ...] for all blocks.
    const Eigen::Index cols = (k + 1) * static_cast<Eigen::Index>(plus_.size()) + k;
    all_.resize(n, cols);
    all_.leftCols(k) = Z;
    for (std::size_t q = 0; q < plus_.size(); ++q) {
      const Eigen::Index o = offset(q), c = k + static_cast<Eigen::Index>(q) * (k + 1);
      all_.col(c) = X.segment(o, n);
      all_.middleCols(c + 1, k) = Eigen::Map<const Eigen::MatrixXd>(X.data() + o + n, n, k);
    }
    prod_.resize(n, cols);
    if (explicit_a) prod_.noalias() = a_ * all_;
    else tangent_product(sys_, method_, x_, t, all_, prod_);
    dZ = prod_.leftCols(k);
    dX(divergence_index()) = !whole ? 0.0 : explicit_a ? a_.trace() : trace_of_similar(Z, prod_.leftCols(n));
    for (std::size_t q = 0; q < plus_.size(); ++q) {
      const Eigen::Index o = offset(q), c = k + static_cast<Eigen::Index>(q) * (k + 1);
      const auto xs = X.segment(o, n);
      constexpr double d = kParameterStep;
      // f_/s and (dA/ds) Z by central differences along (x_/s, 1).
      xa_ = x_ + d * xs;
      xb_ = x_ - d * xs;
      plus_[q].rhs(x_, fa_, t);
      minus_[q].rhs(x_, fb_, t);
      dX.segment(o, n) = prod_.col(c) + (fa_ - fb_) / (2.0 * d);
      ta_.resize(n, k), tb_.resize(n, k);
      tangent_product(plus_[q], method_, xa_, t, Z, ta_);
      tangent_product(minus_[q], method_, xb_, t, Z, tb_);
      Eigen::Map<Eigen::MatrixXd>(dX.data() + o + n, n, k) = prod_.middleCols(c + 1, k) + (ta_ - tb_) / (2.0 * d);
    }
  }

 private:
  /// tr A = tr(Z^-1 (A Z)) = sum_ij (Z^-1)_ij (AZ)_ji: one inverse (~n^3 flops), no solve.
  template <class M>
  double trace_of_similar(const Eigen::Map<const Eigen::MatrixXd>& Z, const M& AZ) const {
    inverse_ = Z.partialPivLu().inverse();
    return (inverse_.array() * AZ.transpose().array()).sum();
  }

  const ode::DynamicalSystem& sys_;
  JacobianMethod method_;
  Eigen::Index n_, k_;
  std::vector<ode::DynamicalSystem> plus_, minus_;
  // Work space (the RHS is called from one thread per instance).
  mutable Eigen::VectorXd x_, f_, xa_, xb_, fa_, fb_;
  mutable Eigen::MatrixXd a_, all_, prod_, ta_, tb_, inverse_;
};

}  // namespace mlce::spectrum::detail
