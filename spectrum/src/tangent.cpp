#include "mlce/spectrum/tangent.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace mlce::spectrum {

JacobianMethod jacobian_method_from_name(const std::string& n) {
  if (n == "analytic") return JacobianMethod::analytic;
  if (n == "complex-step" || n == "complex_step") return JacobianMethod::complex_step;
  if (n == "jacobian-free" || n == "jacobian_free" || n == "finite-difference") return JacobianMethod::jacobian_free;
  throw std::invalid_argument("jacobian '" + n + "': expected analytic, complex-step or jacobian-free");
}

const char* jacobian_method_name(JacobianMethod m) {
  switch (m) {
    case JacobianMethod::analytic: return "analytic";
    case JacobianMethod::complex_step: return "complex-step";
    default: return "jacobian-free";
  }
}

void require(const ode::DynamicalSystem& sys, JacobianMethod m) {
  if (!sys.rhs || sys.dimension < 1) throw std::invalid_argument("the system has no right-hand side");
  if (m == JacobianMethod::analytic && !sys.jacobian)
    throw std::invalid_argument("the model has no analytic Jacobian: use --jacobian complex-step or jacobian-free");
  if (m == JacobianMethod::complex_step && !sys.rhs_complex)
    throw std::invalid_argument("the model has no complex right-hand side: use --jacobian analytic or jacobian-free");
}

namespace {

constexpr double kComplexStep = 1e-30;

/// Central-difference step for the direction z at x: cube root of epsilon balances truncation
/// (O(e^2)) against rounding (O(eps/e)), scaled by the state and direction magnitudes.
double central_step(const Eigen::VectorXd& x, const Eigen::Ref<const Eigen::VectorXd>& z) {
  const double zn = z.norm();
  if (zn == 0.0) return 0.0;
  return std::cbrt(std::numeric_limits<double>::epsilon()) * (1.0 + x.norm()) / zn;
}

}  // namespace

void tangent_product(const ode::DynamicalSystem& sys, JacobianMethod m, const Eigen::VectorXd& x, double t,
                     const Eigen::Ref<const Eigen::MatrixXd>& Z, Eigen::Ref<Eigen::MatrixXd> AZ) {
  if (m == JacobianMethod::complex_step && Z.cols() < x.size()) {
    // Fewer directions than states (the largest exponents only): one complex evaluation per
    // direction, A z = Im f(x + i h z) / h, instead of one per state to form A.
    Eigen::VectorXcd xc(x.size()), fc(x.size());
    for (Eigen::Index k = 0; k < Z.cols(); ++k) {
      const double zn = Z.col(k).norm();
      if (!(zn > 0.0)) {
        AZ.col(k).setZero();
        continue;
      }
      const double h = kComplexStep / zn;
      xc = x.cast<std::complex<double>>() + std::complex<double>(0.0, h) * Z.col(k).cast<std::complex<double>>();
      sys.rhs_complex(xc, fc, t);
      AZ.col(k) = fc.imag() / h;
    }
    return;
  }
  if (m != JacobianMethod::jacobian_free) {
    AZ.noalias() = jacobian(sys, m, x, t) * Z;
    return;
  }
  Eigen::VectorXd xp(x.size()), fp(x.size()), fm(x.size());
  for (Eigen::Index k = 0; k < Z.cols(); ++k) {
    const double e = central_step(x, Z.col(k));
    if (e == 0.0) {
      AZ.col(k).setZero();
      continue;
    }
    xp = x + e * Z.col(k);
    sys.rhs(xp, fp, t);
    xp = x - e * Z.col(k);
    sys.rhs(xp, fm, t);
    AZ.col(k) = (fp - fm) / (2.0 * e);
  }
}

Eigen::MatrixXd jacobian(const ode::DynamicalSystem& sys, JacobianMethod m, const Eigen::VectorXd& x, double t) {
  const Eigen::Index n = x.size();
  switch (m) {
    case JacobianMethod::analytic: return sys.jacobian(x, t);
    case JacobianMethod::complex_step: {
      Eigen::MatrixXd J(n, n);
      Eigen::VectorXcd xc = x.cast<std::complex<double>>(), fc(n);
      for (Eigen::Index k = 0; k < n; ++k) {
        xc(k) += std::complex<double>(0.0, kComplexStep);
        sys.rhs_complex(xc, fc, t);
        J.col(k) = fc.imag() / kComplexStep;
        xc(k) = x(k);
      }
      return J;
    }
    default: {
      Eigen::MatrixXd J(n, n);
      tangent_product(sys, m, x, t, Eigen::MatrixXd::Identity(n, n), J);
      return J;
    }
  }
}

}  // namespace mlce::spectrum
