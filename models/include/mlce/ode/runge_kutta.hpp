#pragma once
// Explicit Runge-Kutta integration in the style of Boost.Odeint: a system is a callable
// f(x, dxdt, t); a scheme is a Butcher tableau; integrate_uniform() advances with the scheme's own
// steps (adaptive for the embedded pairs) and hands the observer the state at uniformly spaced
// output times taken from the dense output - the step is never shortened to hit an output time.
//
//   bs23  Bogacki-Shampine 3(2), FSAL, cubic Hermite dense output (MATLAB's ode23)
//   dp45  Dormand-Prince 5(4), FSAL, Hairer's 4th-order continuous extension (ode45/dopri5)
//   rk4   classical fixed-step 4th order, cubic Hermite dense output
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace mlce::ode {

using State = Eigen::VectorXd;

enum class Scheme { bs23, dp45, rk4 };

/// "rk23"/"bs23"/"ode23", "rk45"/"dp45"/"ode45", "rk4"; throws std::invalid_argument otherwise.
Scheme scheme_from_name(const std::string& name);
const char* scheme_name(Scheme s);

struct IntegratorOptions {
  Scheme scheme = Scheme::dp45;
  double rtol = 1e-8;   ///< relative tolerance of the local error (embedded pairs)
  double atol = 1e-10;  ///< absolute tolerance of the local error
  double h_initial = 0.0;  ///< first step; 0 = Hairer's automatic choice
  double h_max = 0.0;      ///< largest step; 0 = unlimited
  double h_fixed = 0.0;    ///< rk4 step (or any scheme's when fixed_step); 0 = output step / 4
  bool fixed_step = false; ///< run an embedded pair with the fixed step h_fixed (order studies)
  std::size_t max_steps = 10'000'000;
  void validate() const;
};

struct IntegrationStats {
  std::size_t steps = 0, rejected = 0, evaluations = 0;
};

/// Error raised when the integration cannot continue (step underflow, non-finite state).
class IntegrationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace detail {

struct Tableau {
  int stages;
  std::vector<std::vector<double>> a;
  std::vector<double> b, b_low, c;
  int order;      ///< of the propagated solution
  int low_order;  ///< of the embedded one (0 = none)
  bool fsal;
};
const Tableau& tableau(Scheme s);

/// Hairer's dopri5 dense-output coefficients (contd5).
constexpr double kDopriD[7] = {-12715105075.0 / 11282082432.0, 0.0, 87487479700.0 / 32700410799.0,
                               -10690763975.0 / 1880347072.0, 701980252875.0 / 199316789632.0,
                               -1453857185.0 / 822651844.0, 69997945.0 / 29380423.0};

}  // namespace detail

/// Integrates dx/dt = f(x, t) from (t0, x0) and calls observer(k, t_k, x(t_k)) for
/// t_k = t0 + k dt_out, k = 0..n_out-1. Throws IntegrationError on step-size underflow or a
/// non-finite state; the observer may throw to stop.
template <class System, class Observer>
IntegrationStats integrate_uniform(System&& f, State x, double t0, double dt_out, std::size_t n_out,
                                   const IntegratorOptions& opt, Observer&& observer) {
  opt.validate();
  if (!(dt_out > 0.0)) throw std::invalid_argument("output step must be positive");
  const auto& T = detail::tableau(opt.scheme);
  const Eigen::Index n = x.size();
  IntegrationStats st;
  std::vector<State> k(static_cast<std::size_t>(T.stages), State(n));
  State xs(n), x_new(n), f_new(n), err(n), r2(n), r3(n), r4(n), rc5(n);
  auto eval = [&](const State& y, State& dy, double t) {
    f(y, dy, t);
    ++st.evaluations;
  };
  double t = t0;
  eval(x, k[0], t);
  std::size_t next = 0;
  const double t_end = t0 + dt_out * static_cast<double>(n_out == 0 ? 0 : n_out - 1);
  if (n_out > 0) observer(std::size_t{0}, t0, static_cast<const State&>(x)), next = 1;
  if (n_out <= 1) return st;

  const bool adaptive = T.low_order > 0 && !opt.fixed_step;
  double h = 0.0;
  if (!adaptive) {
    h = opt.h_fixed > 0 ? opt.h_fixed : dt_out / 4.0;
  } else if (opt.h_initial > 0) {
    h = opt.h_initial;
  } else {  // Hairer, Norsett & Wanner, Solving ODEs I, II.4: starting step size
    const State sc = (opt.atol + opt.rtol * x.array().abs()).matrix();
    const double d0 = std::sqrt((x.array() / sc.array()).square().mean());
    const double d1 = std::sqrt((k[0].array() / sc.array()).square().mean());
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    h0 = std::min(h0, dt_out);
    xs = x + h0 * k[0];
    eval(xs, f_new, t + h0);
    const double d2 = std::sqrt((((f_new - k[0]).array()) / sc.array()).square().mean()) / h0;
    const double h1 = std::max(d1, d2) <= 1e-15 ? std::max(1e-6, h0 * 1e-3)
                                               : std::pow(0.01 / std::max(d1, d2), 1.0 / (T.order));
    h = std::min(100.0 * h0, h1);
  }
  if (opt.h_max > 0) h = std::min(h, opt.h_max);
  const double h_min_rel = 16.0 * std::numeric_limits<double>::epsilon();

  while (next < n_out) {
    if (st.steps + st.rejected >= opt.max_steps)
      throw IntegrationError("more than " + std::to_string(opt.max_steps) + " steps before t = " + std::to_string(t_end) +
                             " (stiff problem? loosen rtol, or use rk4 with a step h)");
    if (h < h_min_rel * std::max(1.0, std::abs(t)))
      throw IntegrationError("step size underflow at t = " + std::to_string(t) + " (stiff or singular problem?)");
    // Stages.
    for (int s = 1; s < T.stages; ++s) {
      xs = x;
      for (int j = 0; j < s; ++j)
        if (T.a[s][j] != 0.0) xs.noalias() += (h * T.a[s][j]) * k[j];
      eval(xs, k[s], t + T.c[s] * h);
    }
    x_new = x;
    for (int s = 0; s < T.stages; ++s)
      if (T.b[s] != 0.0) x_new.noalias() += (h * T.b[s]) * k[s];
    double err_norm = 0.0;
    if (adaptive) {
      err.setZero();
      for (int s = 0; s < T.stages; ++s)
        if (T.b[s] != T.b_low[s]) err.noalias() += (h * (T.b[s] - T.b_low[s])) * k[s];
      const auto sc = opt.atol + opt.rtol * x.array().abs().max(x_new.array().abs());
      err_norm = std::sqrt((err.array() / sc).square().mean());
      if (!std::isfinite(err_norm)) err_norm = 1e10;
    }
    if (adaptive && err_norm > 1.0) {
      ++st.rejected;
      h *= std::max(0.2, 0.9 * std::pow(err_norm, -1.0 / (T.low_order + 1)));
      continue;
    }
    if (!x_new.allFinite())
      throw IntegrationError("non-finite state at t = " + std::to_string(t + h) + " (the solution diverged)");
    // f at the new point (FSAL: the last stage already is).
    if (T.fsal) f_new = k[static_cast<std::size_t>(T.stages - 1)];
    else eval(x_new, f_new, t + h);
    // Dense output for every output time inside (t, t+h]; its coefficients are formed once per
    // step, and only for steps that hold an output time.
    const double t_new = t + h;
    bool dense_ready = false;
    while (next < n_out) {
      const double to = t0 + dt_out * static_cast<double>(next);
      if (to > t_new + 1e-12 * std::abs(t_new)) break;
      const double th = std::clamp((to - t) / h, 0.0, 1.0);
      if (opt.scheme == Scheme::dp45) {
        // y(th) = y0 + th (r2 + (1-th)(r3 + th (r4 + (1-th) r5))), Hairer's contd5
        if (!dense_ready) {
          r2 = x_new - x;
          r3 = h * k[0] - r2;
          r4 = r2 - h * f_new - r3;
          rc5.setZero();
          for (int s = 0; s < 7; ++s)
            if (detail::kDopriD[s] != 0.0) rc5.noalias() += (h * detail::kDopriD[s]) * k[s];
          dense_ready = true;
        }
        xs = x + th * (r2 + (1.0 - th) * (r3 + th * (r4 + (1.0 - th) * rc5)));
      } else {  // cubic Hermite on (x, f) at both ends
        const double h00 = (1 + 2 * th) * (1 - th) * (1 - th), h10 = th * (1 - th) * (1 - th);
        const double h01 = th * th * (3 - 2 * th), h11 = th * th * (th - 1);
        xs = h00 * x + (h10 * h) * k[0] + h01 * x_new + (h11 * h) * f_new;
      }
      observer(next, to, static_cast<const State&>(xs));
      ++next;
    }
    t = t_new;
    x.swap(x_new);
    k[0] = f_new;
    ++st.steps;
    if (adaptive) {
      const double fac = err_norm > 0 ? 0.9 * std::pow(err_norm, -1.0 / (T.low_order + 1)) : 5.0;
      h *= std::clamp(fac, 0.2, 5.0);
      if (opt.h_max > 0) h = std::min(h, opt.h_max);
    }
  }
  return st;
}

}  // namespace mlce::ode
