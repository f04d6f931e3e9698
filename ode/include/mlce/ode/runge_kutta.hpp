#pragma once
// Explicit Runge-Kutta integration in the style of Boost.Odeint: a system is a callable
// f(x, dxdt, t); a scheme is a Butcher tableau; integrate_uniform() advances with the scheme's own
// steps (adaptive for the embedded pairs) and hands the observer the state at uniformly spaced
// output times taken from the dense output - the step is never shortened to hit an output time.
//
//   bs23  Bogacki-Shampine 3(2), FSAL, cubic Hermite dense output (MATLAB's ode23)
//   dp45  Dormand-Prince 5(4), FSAL, Hairer's 4th-order continuous extension (ode45/dopri5)
//   rk4   classical fixed-step 4th order, cubic Hermite dense output
//
// integrate_to() advances to an exact end time instead, for callers that modify the state between
// intervals (the discrete QR method re-orthonormalises its tangent vectors).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
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
  /// Optional tolerance of each component's local error, scale(x, x_new, sc) with sc sized like x
  /// (> 0). Empty: atol + rtol max(|x_i|, |x_new_i|). The QR method scales atol by the size of
  /// each tangent column, so that a column contracting far below atol is still resolved.
  std::function<void(const State& x, const State& x_new, Eigen::ArrayXd& sc)> error_scale;
  /// Optional: called with the time reached every kProgressSteps accepted steps, so that a run
  /// whose output samples are far apart (or whose steps have become tiny) still reports progress.
  std::function<void(double t)> progress;
  static constexpr std::size_t kProgressSteps = 4096;
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

namespace detail {

/// Hairer, Norsett & Wanner, Solving ODEs I, II.4: automatic starting step size, at most h_cap.
template <class Eval>
double starting_step(const Tableau& T, Eval& eval, const State& x, const State& f0, double t, double h_cap,
                     const IntegratorOptions& opt) {
  const State sc = (opt.atol + opt.rtol * x.array().abs()).matrix();
  const double d0 = std::sqrt((x.array() / sc.array()).square().mean());
  const double d1 = std::sqrt((f0.array() / sc.array()).square().mean());
  double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
  h0 = std::min(h0, h_cap);
  State f1(x.size());
  eval(State(x + h0 * f0), f1, t + h0);
  const double d2 = std::sqrt((((f1 - f0).array()) / sc.array()).square().mean()) / h0;
  const double h1 = std::max(d1, d2) <= 1e-15 ? std::max(1e-6, h0 * 1e-3) : std::pow(0.01 / std::max(d1, d2), 1.0 / T.order);
  return std::min(100.0 * h0, h1);
}

/// Work space of one explicit RK scheme; attempt() tries one step of size h from (t, x), with
/// k[0] = f(x, t) already set, and leaves the result in x_new and f(x_new) in f_new when accepted.
struct StepWork {
  std::vector<State> k;
  State xs, x_new, f_new, err;
  Eigen::ArrayXd scale;  ///< for IntegratorOptions::error_scale
  StepWork(const Tableau& T, Eigen::Index n) : k(static_cast<std::size_t>(T.stages), State(n)), xs(n), x_new(n), f_new(n), err(n) {}

  /// Returns the scaled RMS local error (0 when the step is not error-controlled).
  template <class Eval>
  double attempt(const Tableau& T, Eval& eval, const State& x, double t, double h, bool adaptive,
                 const IntegratorOptions& opt) {
    for (int s = 1; s < T.stages; ++s) {
      xs = x;
      for (int j = 0; j < s; ++j)
        if (T.a[s][j] != 0.0) xs.noalias() += (h * T.a[s][j]) * k[static_cast<std::size_t>(j)];
      eval(xs, k[static_cast<std::size_t>(s)], t + T.c[s] * h);
    }
    x_new = x;
    for (int s = 0; s < T.stages; ++s)
      if (T.b[s] != 0.0) x_new.noalias() += (h * T.b[s]) * k[static_cast<std::size_t>(s)];
    if (!adaptive) return 0.0;
    err.setZero();
    for (int s = 0; s < T.stages; ++s)
      if (T.b[s] != T.b_low[s]) err.noalias() += (h * (T.b[s] - T.b_low[s])) * k[static_cast<std::size_t>(s)];
    double e;
    if (opt.error_scale) {
      opt.error_scale(x, x_new, scale);
      e = std::sqrt((err.array() / scale).square().mean());
    } else {
      const auto sc = opt.atol + opt.rtol * x.array().abs().max(x_new.array().abs());
      e = std::sqrt((err.array() / sc).square().mean());
    }
    return std::isfinite(e) ? e : 1e10;
  }
  /// f at the accepted point (FSAL: the last stage already is).
  template <class Eval>
  void finish(const Tableau& T, Eval& eval, double t_new) {
    if (T.fsal) f_new = k[static_cast<std::size_t>(T.stages - 1)];
    else eval(x_new, f_new, t_new);
  }
};

inline double step_factor(double err_norm, int low_order) {
  return err_norm > 0 ? std::clamp(0.9 * std::pow(err_norm, -1.0 / (low_order + 1)), 0.2, 5.0) : 5.0;
}

inline void check_budget(const IntegrationStats& st, const IntegratorOptions& opt, double h, double t, double t_end) {
  if (st.steps + st.rejected >= opt.max_steps)
    throw IntegrationError("more than " + std::to_string(opt.max_steps) + " steps before t = " + std::to_string(t_end) +
                           " (reached t = " + std::to_string(t) + "; stiff problem? loosen rtol, or use rk4 with a step h)");
  if (h < 16.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t)))
    throw IntegrationError("step size underflow at t = " + std::to_string(t) + " (stiff or singular problem?)");
}

}  // namespace detail

/// Stops a run whose steps have shrunk so far, and are still shrinking, that the rest of its span
/// could not fit in the step budget even several times over. The budget estimate made before a run
/// (step_budget.hpp) sees the stiffness at the initial state only; a state that grows into a stiffer
/// region (a negative spring driving a nonlinear damper, a motion about to diverge) shrinks the
/// steps along the way, and without this check such a run spends the whole budget (seconds to
/// minutes, with no output sample to report progress by) before it fails.
///
/// Every kWindow attempts, the mean advance per attempt over them projects the steps still needed
/// at the present step. Steps may grow back later (a start-up transient decays: Hammond at 10^6 rpm
/// takes 0.19 of the budget, but its first windows project more than one), so the run is stopped only when
/// the projection exceeds kFactor budgets while the steps are still shrinking, window on window.
/// A run stopped here was headed for the budget; every other run ends as it would without the
/// watch. The integrators watch each call; a caller that splits a run into many calls (the QR
/// method) watches the whole run with its own.
class BudgetWatch {
 public:
  static constexpr std::size_t kWindow = std::size_t{1} << 16;
  static constexpr double kFactor = 10.0;
  BudgetWatch(const IntegrationStats& st, double t) : mark_attempts_(st.steps + st.rejected), mark_t_(t) {}
  void check(const IntegrationStats& st, const IntegratorOptions& opt, double t, double t_end) {
    const std::size_t attempts = st.steps + st.rejected;
    if (attempts - mark_attempts_ < kWindow) return;
    const double advance = (t - mark_t_) / static_cast<double>(attempts - mark_attempts_);
    const double remaining = advance > 0.0 ? (t_end - t) / advance : std::numeric_limits<double>::infinity();
    const bool shrinking = previous_advance_ > 0.0 && advance < previous_advance_;
    if (shrinking && static_cast<double>(attempts) + remaining > kFactor * static_cast<double>(opt.max_steps)) {
      char buf[640];
      std::snprintf(buf, sizeof buf,
                    "at t = %.9g the steps have shrunk to %.3g on average over the last %zu (from %.3g over the "
                    "%zu before), so the %.9g left to t = %.9g need about %.3g more steps, far beyond the budget "
                    "of %zu (the motion grew stiffer along the run, or it is about to diverge: loosen rtol, or "
                    "end the run before t = %.9g)",
                    t, advance, attempts - mark_attempts_, previous_advance_, previous_window_, t_end - t, t_end,
                    remaining, opt.max_steps, t);
      throw IntegrationError(buf);
    }
    previous_advance_ = advance;
    previous_window_ = attempts - mark_attempts_;
    mark_attempts_ = attempts;
    mark_t_ = t;
  }

 private:
  std::size_t mark_attempts_;
  double mark_t_;
  double previous_advance_ = 0.0;  ///< 0: no window yet
  std::size_t previous_window_ = 0;
};

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
  detail::StepWork w(T, n);
  State xs(n), r2(n), r3(n), r4(n), rc5(n);
  auto eval = [&](const State& y, State& dy, double t) {
    f(y, dy, t);
    ++st.evaluations;
  };
  double t = t0;
  eval(x, w.k[0], t);
  std::size_t next = 0;
  const double t_end = t0 + dt_out * static_cast<double>(n_out == 0 ? 0 : n_out - 1);
  if (n_out > 0) observer(std::size_t{0}, t0, static_cast<const State&>(x)), next = 1;
  if (n_out <= 1) return st;

  const bool adaptive = T.low_order > 0 && !opt.fixed_step;
  double h = !adaptive ? (opt.h_fixed > 0 ? opt.h_fixed : dt_out / 4.0)
             : opt.h_initial > 0 ? opt.h_initial
                                 : detail::starting_step(T, eval, x, w.k[0], t, dt_out, opt);
  if (opt.h_max > 0) h = std::min(h, opt.h_max);

  BudgetWatch watch(st, t);
  while (next < n_out) {
    detail::check_budget(st, opt, h, t, t_end);
    watch.check(st, opt, t, t_end);
    const double err_norm = w.attempt(T, eval, x, t, h, adaptive, opt);
    if (adaptive && err_norm > 1.0) {
      ++st.rejected;
      h *= std::max(0.2, 0.9 * std::pow(err_norm, -1.0 / (T.low_order + 1)));
      continue;
    }
    if (!w.x_new.allFinite())
      throw IntegrationError("non-finite state at t = " + std::to_string(t + h) + " (the solution diverged)");
    const double t_new = t + h;
    w.finish(T, eval, t_new);
    // Dense output for every output time inside (t, t+h]; its coefficients are formed once per
    // step, and only for steps that hold an output time.
    bool dense_ready = false;
    while (next < n_out) {
      const double to = t0 + dt_out * static_cast<double>(next);
      if (to > t_new + 1e-12 * std::abs(t_new)) break;
      const double th = std::clamp((to - t) / h, 0.0, 1.0);
      if (opt.scheme == Scheme::dp45) {
        // y(th) = y0 + th (r2 + (1-th)(r3 + th (r4 + (1-th) r5))), Hairer's contd5
        if (!dense_ready) {
          r2 = w.x_new - x;
          r3 = h * w.k[0] - r2;
          r4 = r2 - h * w.f_new - r3;
          rc5.setZero();
          for (int s = 0; s < 7; ++s)
            if (detail::kDopriD[s] != 0.0) rc5.noalias() += (h * detail::kDopriD[s]) * w.k[static_cast<std::size_t>(s)];
          dense_ready = true;
        }
        xs = x + th * (r2 + (1.0 - th) * (r3 + th * (r4 + (1.0 - th) * rc5)));
      } else {  // cubic Hermite on (x, f) at both ends
        const double h00 = (1 + 2 * th) * (1 - th) * (1 - th), h10 = th * (1 - th) * (1 - th);
        const double h01 = th * th * (3 - 2 * th), h11 = th * th * (th - 1);
        xs = h00 * x + (h10 * h) * w.k[0] + h01 * w.x_new + (h11 * h) * w.f_new;
      }
      observer(next, to, static_cast<const State&>(xs));
      ++next;
    }
    t = t_new;
    x.swap(w.x_new);
    w.k[0] = w.f_new;
    ++st.steps;
    if (opt.progress && st.steps % IntegratorOptions::kProgressSteps == 0) opt.progress(t);
    if (adaptive) {
      h *= detail::step_factor(err_norm, T.low_order);
      if (opt.h_max > 0) h = std::min(h, opt.h_max);
    }
  }
  return st;
}

/// Integrates x from t0 to exactly t1 (the last step is shortened to land on t1), in place.
/// `h` carries the step size from one call to the next (<= 0: choose automatically); fixed-step
/// schemes split [t0, t1] into equal steps no longer than h_fixed (or (t1 - t0) when 0).
/// Used where the state is modified between intervals (the QR re-orthonormalisation).
template <class System>
void integrate_to(System&& f, State& x, double t0, double t1, const IntegratorOptions& opt, double& h,
                  IntegrationStats& st) {
  if (!(t1 > t0)) throw std::invalid_argument("integrate_to: expected t1 > t0");
  const auto& T = detail::tableau(opt.scheme);
  detail::StepWork w(T, x.size());
  auto eval = [&](const State& y, State& dy, double t) {
    f(y, dy, t);
    ++st.evaluations;
  };
  eval(x, w.k[0], t0);
  const bool adaptive = T.low_order > 0 && !opt.fixed_step;
  if (!adaptive) {
    const double span = t1 - t0;
    const double steps = opt.h_fixed > 0 ? std::ceil(span / opt.h_fixed - 1e-9) : 1.0;
    if (!(steps <= static_cast<double>(opt.max_steps)))  // also keeps the cast below defined
      throw IntegrationError("the fixed step " + std::to_string(opt.h_fixed) + " makes more than " +
                             std::to_string(opt.max_steps) + " steps before t = " + std::to_string(t1));
    const auto n = static_cast<std::size_t>(steps);
    const double hs = span / static_cast<double>(std::max<std::size_t>(n, 1));
    double t = t0;
    for (std::size_t i = 0; i < std::max<std::size_t>(n, 1); ++i) {
      w.attempt(T, eval, x, t, hs, false, opt);
      t = i + 1 == n ? t1 : t + hs;
      if (!w.x_new.allFinite()) throw IntegrationError("non-finite state at t = " + std::to_string(t) + " (the solution diverged)");
      w.finish(T, eval, t);
      x.swap(w.x_new);
      w.k[0] = w.f_new;
      ++st.steps;
    }
    return;
  }
  if (!(h > 0)) h = opt.h_initial > 0 ? opt.h_initial : detail::starting_step(T, eval, x, w.k[0], t0, t1 - t0, opt);
  if (opt.h_max > 0) h = std::min(h, opt.h_max);
  double t = t0;
  BudgetWatch watch(st, t);
  while (t < t1) {
    // Land on t1: shorten the last step, and stretch one that would leave a sliver behind.
    const bool last = t + h * 1.01 >= t1;
    const double hs = last ? t1 - t : h;
    detail::check_budget(st, opt, hs, t, t1);
    watch.check(st, opt, t, t1);
    const double err_norm = w.attempt(T, eval, x, t, hs, true, opt);
    if (err_norm > 1.0) {
      ++st.rejected;
      h = hs * std::max(0.2, 0.9 * std::pow(err_norm, -1.0 / (T.low_order + 1)));
      continue;
    }
    const double t_new = last ? t1 : t + hs;
    if (!w.x_new.allFinite()) throw IntegrationError("non-finite state at t = " + std::to_string(t_new) + " (the solution diverged)");
    w.finish(T, eval, t_new);
    x.swap(w.x_new);
    w.k[0] = w.f_new;
    ++st.steps;
    t = t_new;
    // The next step size follows from this step's error; a shortened last step does not shrink it.
    const double proposed = hs * detail::step_factor(err_norm, T.low_order);
    h = last ? std::max(h, proposed) : proposed;
    if (opt.h_max > 0) h = std::min(h, opt.h_max);
  }
}

}  // namespace mlce::ode
