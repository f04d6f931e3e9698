#pragma once
// The fiducial trajectory, its tangent matrix and their parameter sensitivities as one ODE:
//   x'     = f(x, t)                                   (paper 000 eq. 1)
//   Z'     = A Z,   A = f_/x(x, t)                     (eq. 3; Z starts from Q_{j-1})
//   x_/p'  = A x_/p + f_/p                             (eq. 28)
//   Z_/p'  = A Z_/p + (dA/dp) Z,  dA/dp = A_/x x_/p + A_/p   (eqs. 26-27)
//   D'     = tr A                                      (Liouville: D(t) = ln det of the tangent
//                                                        flow, the sum of all exponents x time)
// Layout of the state: [x | Z (column-major) | x_/p1 | Z_/p1 | x_/p2 | ... | D].
// Parameters are scaled, p = p0 + scale s, and derivatives are taken with respect to s so that
// every block is of order one. The local derivatives f_/s and (dA/ds) Z are central differences
// of the model at s = +-delta along (x_/s, 1): error O(delta^2) relative, delta = 1e-4. The
// propagation of the sensitivities (eqs. 12, 18-28) is exact; only these local model derivatives
// are differenced.
#include <Eigen/Core>
#include <Eigen/LU>
#include <vector>

#include "mlce/ode/system.hpp"
#include "mlce/spectrum/tangent.hpp"

namespace mlce::spectrum::detail {

class VariationalSystem {
 public:
  static constexpr double kParameterStep = 1e-4;

  VariationalSystem(const ode::DynamicalSystem& sys, JacobianMethod method, const std::vector<ode::ParameterFamily>& params)
      : sys_(sys), method_(method), n_(sys.dimension) {
    require(sys_, method_);
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
  std::size_t parameters() const { return plus_.size(); }
  Eigen::Index block() const { return n_ + n_ * n_; }
  Eigen::Index size() const { return block() * static_cast<Eigen::Index>(1 + plus_.size()) + 1; }
  /// Index of D, the integral of tr A (the divergence of the vector field) along the trajectory.
  Eigen::Index divergence_index() const { return size() - 1; }

  template <class V> static auto x_of(V& X, Eigen::Index n) { return X.head(n); }
  template <class V> static auto Z_of(V& X, Eigen::Index n) { return Eigen::Map<Eigen::MatrixXd>(X.data() + n, n, n); }
  template <class V> static auto Zc_of(const V& X, Eigen::Index n) { return Eigen::Map<const Eigen::MatrixXd>(X.data() + n, n, n); }
  /// Offset of parameter k's block (k = 0..P-1).
  Eigen::Index offset(std::size_t k) const { return block() * static_cast<Eigen::Index>(k + 1); }

  void operator()(const Eigen::VectorXd& X, Eigen::VectorXd& dX, double t) const {
    dX.resize(X.size());
    const Eigen::Index n = n_;
    x_ = X.head(n);
    sys_.rhs(x_, f_, t);
    dX.head(n) = f_;
    const Eigen::Map<const Eigen::MatrixXd> Z(X.data() + n, n, n);
    Eigen::Map<Eigen::MatrixXd> dZ(dX.data() + n, n, n);
    // The explicit routes form A once: the products and its trace come from it. The Jacobian-free
    // route never forms A: tr A = tr(Z^-1 A Z), from the product it computes anyway (Z starts as
    // an orthonormal or identity matrix and is integrated over one QR interval or one period).
    const bool explicit_a = method_ != JacobianMethod::jacobian_free;
    if (explicit_a) a_ = jacobian(sys_, method_, x_, t);
    if (plus_.empty()) {
      if (explicit_a) dZ.noalias() = a_ * Z;
      else tangent_product(sys_, method_, x_, t, Z, dZ);
      dX(divergence_index()) = explicit_a ? a_.trace() : trace_of_similar(Z, dZ);
      return;
    }
    // One product A [Z | x_/p1 | Z_/p1 | ...] for all blocks.
    const Eigen::Index cols = (n + 1) * static_cast<Eigen::Index>(plus_.size()) + n;
    all_.resize(n, cols);
    all_.leftCols(n) = Z;
    for (std::size_t k = 0; k < plus_.size(); ++k) {
      const Eigen::Index o = offset(k), c = n + static_cast<Eigen::Index>(k) * (n + 1);
      all_.col(c) = X.segment(o, n);
      all_.middleCols(c + 1, n) = Eigen::Map<const Eigen::MatrixXd>(X.data() + o + n, n, n);
    }
    prod_.resize(n, cols);
    if (explicit_a) prod_.noalias() = a_ * all_;
    else tangent_product(sys_, method_, x_, t, all_, prod_);
    dZ = prod_.leftCols(n);
    dX(divergence_index()) = explicit_a ? a_.trace() : trace_of_similar(Z, prod_.leftCols(n));
    for (std::size_t k = 0; k < plus_.size(); ++k) {
      const Eigen::Index o = offset(k), c = n + static_cast<Eigen::Index>(k) * (n + 1);
      const auto xs = X.segment(o, n);
      constexpr double d = kParameterStep;
      // f_/s and (dA/ds) Z by central differences along (x_/s, 1).
      xa_ = x_ + d * xs;
      xb_ = x_ - d * xs;
      plus_[k].rhs(x_, fa_, t);
      minus_[k].rhs(x_, fb_, t);
      dX.segment(o, n) = prod_.col(c) + (fa_ - fb_) / (2.0 * d);
      ta_.resize(n, n), tb_.resize(n, n);
      tangent_product(plus_[k], method_, xa_, t, Z, ta_);
      tangent_product(minus_[k], method_, xb_, t, Z, tb_);
      Eigen::Map<Eigen::MatrixXd>(dX.data() + o + n, n, n) = prod_.middleCols(c + 1, n) + (ta_ - tb_) / (2.0 * d);
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
  Eigen::Index n_;
  std::vector<ode::DynamicalSystem> plus_, minus_;
  // Work space (the RHS is called from one thread per instance).
  mutable Eigen::VectorXd x_, f_, xa_, xb_, fa_, fb_;
  mutable Eigen::MatrixXd a_, all_, prod_, ta_, tb_, inverse_;
};

}  // namespace mlce::spectrum::detail
