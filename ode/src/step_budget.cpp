#include "mlce/ode/step_budget.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace mlce::ode {
namespace {

/// |h lambda| <= this for every scheme here to be stable (see the header).
constexpr double kStabilityRadius = 4.0;

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

Eigen::MatrixXd jacobian_at(const DynamicalSystem& sys, const State& x, double t) {
  if (sys.jacobian) return sys.jacobian(x, t);
  // Forward differences: the size of the eigenvalues is all that is needed here.
  const Eigen::Index n = x.size();
  State f0(n), f1(n), y = x;
  sys.rhs(x, f0, t);
  Eigen::MatrixXd J(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double d = std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, std::abs(x(j)));
    y(j) = x(j) + d;
    sys.rhs(y, f1, t);
    J.col(j) = (f1 - f0) / d;
    y(j) = x(j);
  }
  return J;
}

}  // namespace

StepBudgetEstimate estimate_step_budget(const DynamicalSystem& sys, const State& x0, double t0, double span,
                                        std::size_t calls, const IntegratorOptions& opt, const std::string& what) {
  StepBudgetEstimate e;
  const double per_call = span / static_cast<double>(std::max<std::size_t>(calls, 1));
  State f(x0.size());
  for (int k = 0; k < 8; ++k) {
    const double t = t0 + (sys.period > 0 ? sys.period : 0.0) * k / 8.0;
    sys.rhs(x0, f, t);
    const Eigen::MatrixXd J = jacobian_at(sys, x0, t);
    if (!f.allFinite() || !J.allFinite())
      throw IntegrationError(what + ": the model's right-hand side or its Jacobian is not finite at the initial state "
                                    "(a parameter beyond the range of a double?)");
    const Eigen::EigenSolver<Eigen::MatrixXd> es(J, false);
    if (es.info() == Eigen::Success) e.fastest_rate = std::max(e.fastest_rate, es.eigenvalues().cwiseAbs().maxCoeff());
    if (sys.period <= 0) break;
  }
  const bool adaptive = opt.scheme != Scheme::rk4 && !opt.fixed_step;
  if (adaptive) e.minimum_steps = per_call * e.fastest_rate / kStabilityRadius;
  else if (opt.h_fixed > 0) e.minimum_steps = std::ceil(per_call / opt.h_fixed - 1e-9);
  return e;
}

void require_step_budget(const DynamicalSystem& sys, const State& x0, double t0, double span, std::size_t calls,
                         const IntegratorOptions& opt, const std::string& what) {
  const StepBudgetEstimate e = estimate_step_budget(sys, x0, t0, span, calls, opt, what);
  if (!(e.minimum_steps <= static_cast<double>(opt.max_steps))) {
    const bool adaptive = opt.scheme != Scheme::rk4 && !opt.fixed_step;
    const std::string per = calls > 1 ? " per interval of " + number(span / static_cast<double>(calls))
                                      : " over a span of " + number(span);
    throw IntegrationError(
        what + ": " +
        (adaptive ? "the fastest mode (|eigenvalue| " + number(e.fastest_rate) + " per unit time) needs at least " +
                        number(e.minimum_steps) + " steps" + per + " (stable only while |h eigenvalue| <= 4)"
                  : "the fixed step h = " + number(opt.h_fixed) + " makes " + number(e.minimum_steps) + " steps" + per) +
        ", more than the budget of " + std::to_string(opt.max_steps) + " steps: " +
        (adaptive ? "check the parameters and their units, or shorten the run" : "raise h, or shorten the run"));
  }
}

}  // namespace mlce::ode
