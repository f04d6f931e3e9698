#pragma once
// How many steps an explicit Runge-Kutta scheme needs at the least, known before it runs: a
// parameter in the wrong units (rpm 2.4e6 for 242.4, a spring of 1e300) makes the problem so stiff
// that the run would spend minutes reaching the step budget, or never end, without a word.
//
// Bound used: every scheme here is stable only for |h lambda| <= 4 (the stability regions of
// rk23, rk45 and rk4 reach 2.5, 3.3 and 2.8 on the negative real axis and stay inside that disc),
// so with rho the largest |eigenvalue| of df/dx, a span needs at least span rho / 4 steps. The
// eigenvalues are taken at the initial state, at 8 times over one period of a time-periodic system:
// this is a lower bound wherever the stiffness persists along the run, which holds for the bundled
// models, whose fast modes are set by their parameters (rotor speed, springs, dampers).
#include <cstddef>
#include <string>

#include "mlce/ode/runge_kutta.hpp"
#include "mlce/ode/system.hpp"

namespace mlce::ode {

struct StepBudgetEstimate {
  double fastest_rate = 0.0;   ///< rho: the largest |eigenvalue| of df/dx at x0 (1/time)
  double minimum_steps = 0.0;  ///< per integration call: span rho / 4, or span / h for a fixed step
};

/// The estimate for `calls` integration calls of span / calls each, from (t0, x0). Uses
/// sys.jacobian when there is one, forward differences of sys.rhs otherwise. Throws
/// IntegrationError naming `what` when f or its Jacobian at x0 is not finite.
StepBudgetEstimate estimate_step_budget(const DynamicalSystem& sys, const State& x0, double t0, double span,
                                        std::size_t calls, const IntegratorOptions& opt, const std::string& what);

/// Throws IntegrationError when a call would need more than opt.max_steps steps: the message
/// names `what`, the fastest rate, the steps needed and the budget.
void require_step_budget(const DynamicalSystem& sys, const State& x0, double t0, double span, std::size_t calls,
                         const IntegratorOptions& opt, const std::string& what);

}  // namespace mlce::ode
