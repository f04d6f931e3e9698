#include "mlce/spectrum/qr_spectrum.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "mlce/ode/step_budget.hpp"
#include "mlce/spectrum/liouville.hpp"
#include "variational.hpp"

namespace mlce::spectrum {

void QrOptions::validate() const {
  if (!std::isfinite(t0) || !std::isfinite(t_end) || !(t_end > t0))
    throw std::invalid_argument("t_end: expected a finite end time after t0");
  if (!(step > 0.0) || !std::isfinite(step)) throw std::invalid_argument("qr step: expected a positive interval");
  if (!(transient >= 0.0) || !(transient < t_end - t0))
    throw std::invalid_argument("transient: expected 0 <= transient < t_end - t0");
  if (!((t_end - t0) / step <= 1e9)) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "run length / qr step = %.3g / %.3g = %.3g QR intervals: expected at most 1e9 (a longer step or a shorter run)",
                  t_end - t0, step, (t_end - t0) / step);
    throw std::invalid_argument(buf);
  }
  if (merge == MergeRule::tolerance && !(merge_tolerance > 0.0))
    throw std::invalid_argument("merge tolerance: expected > 0");
  integrator.validate();
}

namespace {

/// Q R = Z with r_ii >= 0 (paper 001 sec. 3.1: flip row i of R and column i of Q). Z is n x m
/// (m <= n): Q is n x m with orthonormal columns (thin QR), R is m x m.
void positive_qr(const Eigen::MatrixXd& Z, Eigen::MatrixXd& Q, Eigen::MatrixXd& R) {
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(Z);
  const Eigen::Index n = Z.rows(), m = Z.cols();
  R = qr.matrixQR().topRows(m).triangularView<Eigen::Upper>();
  Q = qr.householderQ() * Eigen::MatrixXd::Identity(n, m);
  for (Eigen::Index i = 0; i < m; ++i)
    if (R(i, i) < 0) R.row(i) *= -1.0, Q.col(i) *= -1.0;
}

/// Whether the log-sums of QR columns a and b, sampled over the second half of the averaging
/// window, have separated: D(t) = S_a(t) - S_b(t) grows like (lambda_a - lambda_b) t for distinct
/// exponents and stays bounded (oscillating) for a multiple one. Unresolved: the change of the
/// least-squares line of D across the window is no larger than the range of D about that line.
bool unresolved(const std::vector<double>& times, const std::vector<Eigen::VectorXd>& sums, int a, int b) {
  const std::size_t m = times.size();
  if (m < 3) return false;
  double st = 0, sd = 0;
  for (std::size_t k = 0; k < m; ++k) st += times[k], sd += sums[k](a) - sums[k](b);
  const double tm = st / static_cast<double>(m), dm = sd / static_cast<double>(m);
  double stt = 0, std_ = 0;
  for (std::size_t k = 0; k < m; ++k) {
    const double dt = times[k] - tm;
    stt += dt * dt, std_ += dt * (sums[k](a) - sums[k](b) - dm);
  }
  const double slope = stt > 0 ? std_ / stt : 0.0;
  double lo = 0, hi = 0;
  for (std::size_t k = 0; k < m; ++k) {
    const double r = sums[k](a) - sums[k](b) - dm - slope * (times[k] - tm);
    lo = std::min(lo, r), hi = std::max(hi, r);
  }
  return std::abs(slope) * (times.back() - times.front()) <= hi - lo;
}

/// Groups of neighbours (sorted order) to average.
std::vector<std::vector<int>> merge_groups(const Eigen::VectorXd& sorted, const std::vector<int>& order,
                                           const std::vector<double>& times, const std::vector<Eigen::VectorXd>& sums,
                                           const QrOptions& o) {
  const int n = static_cast<int>(sorted.size());
  std::vector<std::vector<int>> groups;
  for (int i = 0; i < n;) {
    std::vector<int> g{i};
    while (i + 1 < n) {
      const bool join = o.merge == MergeRule::tolerance
                            ? sorted(i) - sorted(i + 1) <= o.merge_tolerance
                            : unresolved(times, sums, order[static_cast<std::size_t>(i)], order[static_cast<std::size_t>(i) + 1]);
      if (!join) break;
      g.push_back(++i);
    }
    ++i;
    groups.push_back(g);
  }
  return groups;
}

}  // namespace

QrResult qr_spectrum(const ode::DynamicalSystem& sys, const Eigen::VectorXd& x0, const QrOptions& o,
                     const std::vector<ode::ParameterFamily>& parameters) {
  o.validate();
  if (x0.size() != sys.dimension)
    throw std::invalid_argument("initial state has " + std::to_string(x0.size()) + " values, the model " +
                                std::to_string(sys.dimension));
  if (!x0.allFinite()) throw std::invalid_argument("initial state: expected finite values");
  if (o.count > static_cast<std::size_t>(sys.dimension))
    throw std::invalid_argument("count: " + std::to_string(o.count) + " exponents requested, but the model has " +
                                std::to_string(sys.dimension) + " states");
  // count < n: one tangent vector more than reported, so that a complex pair straddling the last
  // reported exponent is seen and averaged (merge) instead of reported as half a pair, whose
  // estimate only converges like ln(cond)/t (Hammond at 200 rpm, 150 s: -0.0818 alone, the
  // pair's -0.0868 with one vector more).
  const std::size_t computed = o.count == 0 ? 0 : std::min<std::size_t>(o.count + 1, static_cast<std::size_t>(sys.dimension));
  const detail::VariationalSystem vs(sys, o.jacobian, parameters, static_cast<Eigen::Index>(computed));
  const Eigen::Index n = vs.n(), m = vs.columns();  // states, exponents computed
  const std::size_t P = vs.parameters();
  Eigen::VectorXd X = Eigen::VectorXd::Zero(vs.size());
  X.head(n) = x0;
  Eigen::Map<Eigen::MatrixXd>(X.data() + n, n, m).setIdentity();

  QrResult res;
  for (const auto& p : parameters) res.parameters.push_back(p.name);
  std::vector<CompensatedSum> logs(static_cast<std::size_t>(m)), sens(P * static_cast<std::size_t>(m));
  Eigen::MatrixXd Z(n, m), Q(n, m), R(m, m), B(m, m), C(m, m), W(m, m);
  // The averaging window [t_start, t_end]: after the transient and, for a periodic system, a
  // whole number of periods long (a partial period leaves an O(1/t) bias from the periodic part).
  double t_start = o.t0 + o.transient;
  if (o.whole_periods && sys.period > 0.0) {
    const double periods = std::floor((o.t_end - t_start) / sys.period + 1e-9);
    if (periods >= 1.0) t_start = o.t_end - periods * sys.period;
    else res.warnings.push_back("the averaging time is shorter than one period of the system");
  }
  // Two uniform grids, [t0, t_start] and [t_start, t_end], intervals no longer than `step`.
  const auto j_first = static_cast<std::size_t>(t_start > o.t0 ? std::ceil((t_start - o.t0) / o.step - 1e-9) : 0.0);
  const auto averaged = static_cast<std::size_t>(std::max(1.0, std::ceil((o.t_end - t_start) / o.step - 1e-9)));
  const std::size_t J = j_first + averaged;
  // The budget holds for the whole run (its steps are counted over all intervals), so the bound is
  // that of the whole span.
  ode::require_step_budget(sys, x0, o.t0, o.t_end - o.t0, 1, o.integrator, "QR spectrum");
  auto grid = [&](std::size_t j) {
    if (j <= j_first) return j == j_first ? t_start : o.t0 + (t_start - o.t0) * static_cast<double>(j) / static_cast<double>(j_first);
    return j == J ? o.t_end : t_start + (o.t_end - t_start) * static_cast<double>(j - j_first) / static_cast<double>(averaged);
  };
  const std::size_t every = std::max<std::size_t>(1, averaged / std::max<std::size_t>(1, o.history_points));
  std::vector<Eigen::VectorXd> hist, hist_s;
  // Log-sums over the second half of the averaging window (at most ~20000 samples) for merging.
  std::vector<double> half_times;
  std::vector<Eigen::VectorXd> half_sums;
  Eigen::VectorXd running(m);
  const double t_half = t_start + 0.5 * (o.t_end - t_start);
  const std::size_t half_every = std::max<std::size_t>(1, averaged / 40000);
  double h = 0.0;
  const std::size_t progress_every = std::max<std::size_t>(1, J / 100);

  // Each tangent column's error is controlled relative to its own size (VariationalSystem::error_scale).
  ode::IntegratorOptions integrator = o.integrator;
  integrator.error_scale = [&vs, atol = o.integrator.atol, rtol = o.integrator.rtol](
                               const Eigen::VectorXd& x, const Eigen::VectorXd& x_new, Eigen::ArrayXd& sc) {
    vs.error_scale(x, x_new, atol, rtol, sc);
  };
  double divergence_at_start = 0.0;  // D (integral of tr A) at t_start
  // The step budget holds for the whole run (res.stats accumulates over the intervals), and each
  // interval is too short for the integrator's own watch: this one sees the steps of the run.
  ode::BudgetWatch watch(res.stats, o.t0);
  for (std::size_t j = 0; j < J; ++j) {
    const double ta = grid(j), tb = grid(j + 1);
    if (j == j_first) divergence_at_start = X(vs.divergence_index());
    ode::integrate_to(vs, X, ta, tb, integrator, h, res.stats);
    watch.check(res.stats, integrator, tb, o.t_end);
    Z = Eigen::Map<const Eigen::MatrixXd>(X.data() + n, n, m);
    positive_qr(Z, Q, R);
    for (Eigen::Index i = 0; i < m; ++i)
      if (!(R(i, i) >= detail::VariationalSystem::kColumnFloor) || !std::isfinite(R(i, i))) {
        // r_ii is the growth of the i-th direction over one QR step. Below the floor its error
        // control stops following it (VariationalSystem::error_scale): r_ii is then noise, and 0
        // once it underflows; inf when it overflowed, nan when the integration failed.
        const double r = R(i, i);
        char buf[256];
        std::snprintf(buf, sizeof buf, "QR: the tangent space collapsed at t = %.10g: r(%d,%d) = %g over one QR step of %g (%s)",
                      tb, static_cast<int>(i + 1), static_cast<int>(i + 1), r, tb - ta,
                      std::isnan(r) ? "the tangent integration failed: tighten rtol"
                      : r > 1       ? "growth beyond the range of a double: shorten the QR step"
                                    : "the direction was lost: it contracted beyond 1e-280, or beyond 1/rtol relative to "
                                      "the leading ones, within one step: shorten the QR step");
        throw std::runtime_error(buf);
      }
    const bool average = j >= j_first;
    if (average)
      for (Eigen::Index i = 0; i < m; ++i) logs[static_cast<std::size_t>(i)].add(std::log(R(i, i)));
    for (std::size_t k = 0; k < P; ++k) {
      Eigen::Map<Eigen::MatrixXd> Zp(X.data() + vs.offset(k) + n, n, m);
      B.noalias() = Q.transpose() * Zp;
      // C = B R^-1 by back-substitution (eq. 20), W_L = stril(C), W = W_L - W_L^T (eq. 19/24).
      C = R.transpose().triangularView<Eigen::Lower>().solve(B.transpose()).transpose();
      W = C.triangularView<Eigen::StrictlyLower>();
      W -= Eigen::MatrixXd(W.transpose());
      if (average) {
        // R_j/p = B - W R_j (eq. 25): only its diagonal enters eq. 12.
        for (Eigen::Index i = 0; i < m; ++i)
          sens[k * static_cast<std::size_t>(m) + static_cast<std::size_t>(i)].add((B(i, i) - W.row(i).dot(R.col(i))) / R(i, i));
      }
      // Q_j/p, the next interval's start: Q_j W (eq. 21) for the whole tangent space. With m < n
      // columns Q_j^T Q_j/p = W still, but Q_j/p also has a part outside span(Q_j), the part of
      // Z_/p R_j^-1 that Q_j does not hold: Q_j/p = Q_j W + (I - Q_j Q_j^T) Z_/p R_j^-1 = Q_j (W - C) + Z_/p R_j^-1.
      if (m == n) {
        Zp.noalias() = Q * W;
      } else {
        const Eigen::MatrixXd outside = R.transpose().triangularView<Eigen::Lower>().solve(Zp.transpose()).transpose();
        Zp.noalias() = Q * (W - C);
        Zp += outside;
      }
    }
    Eigen::Map<Eigen::MatrixXd>(X.data() + n, n, m) = Q;
    ++res.intervals;
    if (average && tb >= t_half && o.merge == MergeRule::unresolved && ((j - j_first) % half_every == 0 || j + 1 == J)) {
      for (Eigen::Index i = 0; i < m; ++i) running(i) = logs[static_cast<std::size_t>(i)].value();
      half_times.push_back(tb);
      half_sums.push_back(running);
    }
    if (j % 1000 == 0 || j + 1 == J)
      res.orthogonality_error = std::max(res.orthogonality_error,
                                         (Q.transpose() * Q - Eigen::MatrixXd::Identity(m, m)).cwiseAbs().maxCoeff());
    if (average && ((j - j_first) % every == 0 || j + 1 == J)) {
      const double span = tb - t_start;
      Eigen::VectorXd row(m), srow(static_cast<Eigen::Index>(P) * m);
      for (Eigen::Index i = 0; i < m; ++i) row(i) = logs[static_cast<std::size_t>(i)].value() / span;
      for (std::size_t k = 0; k < P; ++k)
        for (Eigen::Index i = 0; i < m; ++i)
          srow(static_cast<Eigen::Index>(k) * m + i) =
              sens[k * static_cast<std::size_t>(m) + static_cast<std::size_t>(i)].value() / span / parameters[k].scale;
      res.history_time.push_back(tb);
      hist.push_back(row);
      hist_s.push_back(srow);
    }
    if (o.progress && (j % progress_every == 0 || j + 1 == J)) o.progress(static_cast<double>(j + 1) / static_cast<double>(J));
  }
  res.final_state = X.head(n);
  res.averaging_time = o.t_end - t_start;
  res.averaging_start = t_start;
  res.mean_divergence = m == n ? (X(vs.divergence_index()) - divergence_at_start) / res.averaging_time
                               : std::numeric_limits<double>::quiet_NaN();

  // Sort by the final estimate, descending; history and sensitivities follow.
  const Eigen::VectorXd final_row = hist.back();
  std::vector<int> order(static_cast<std::size_t>(m));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return final_row(a) > final_row(b); });
  const auto rows = static_cast<Eigen::Index>(hist.size());
  res.history.resize(rows, m);
  res.history_sensitivities.resize(rows, static_cast<Eigen::Index>(P) * m);
  for (Eigen::Index r = 0; r < rows; ++r)
    for (Eigen::Index i = 0; i < m; ++i) {
      res.history(r, i) = hist[static_cast<std::size_t>(r)](order[static_cast<std::size_t>(i)]);
      for (std::size_t k = 0; k < P; ++k)
        res.history_sensitivities(r, static_cast<Eigen::Index>(k) * m + i) =
            hist_s[static_cast<std::size_t>(r)](static_cast<Eigen::Index>(k) * m + order[static_cast<std::size_t>(i)]);
    }
  res.raw_exponents = res.history.row(rows - 1).transpose();
  Eigen::MatrixXd raw_sens(static_cast<Eigen::Index>(P), m);
  for (std::size_t k = 0; k < P; ++k)
    raw_sens.row(static_cast<Eigen::Index>(k)) = res.history_sensitivities.row(rows - 1).segment(static_cast<Eigen::Index>(k) * m, m);

  res.exponents = res.raw_exponents;
  res.sensitivities = raw_sens;
  // Liouville: sum_i log r_ii over an interval is log det of its tangent flow, which is the
  // integral of tr A over it; only the integration of the tangent matrix (and rounding in the QR
  // factors) can make them differ.
  CompensatedSum total;
  for (Eigen::Index i = 0; i < m; ++i) total.add(res.raw_exponents(i));
  res.exponent_sum = total.value();
  if (m == n) {
    if (auto w = liouville_mismatch(res.raw_exponents, res.mean_divergence,
                                    "the tangent vectors were not integrated accurately; tighten rtol/atol or shorten the QR step"))
      res.warnings.push_back(*w);
  }
  // Over one QR step the last direction shrinks by e^-(lambda_1 - lambda_m) step relative to the
  // first. In a coupled system its column Z_m = Y q_m keeps parts along the growing directions, of
  // the size of the column, and its own part is what is left after they are projected out: once
  // that ratio passes 1/rtol, the integration error of the column may exceed it and the smallest
  // exponents are then not resolved (how far the parts stay apart depends on the coupling: the
  // isotropic rotor with 3e5 N m s/rad lag dampers still gives -285.399 at e^-28.5 per step, and
  // loses the direction at e^-57; a decoupled system is always spared).
  {
    const double resolvable = std::log(1.0 / std::max(o.integrator.rtol, std::numeric_limits<double>::epsilon()));
    const double spread = res.raw_exponents.maxCoeff() - res.raw_exponents.minCoeff();
    if (spread * o.step > resolvable) {
      char buf[400];
      std::snprintf(buf, sizeof buf,
                    "the exponents span %.4g: over one QR step of %g the last direction contracts by e^-%.3g relative to "
                    "the first, beyond what the integration is sure to resolve (1/rtol = e^%.3g): the smallest exponents "
                    "may be lost in the integration error of their columns (unless the system is decoupled); check them "
                    "with a QR step below %.3g",
                    spread, o.step, spread * o.step, resolvable, resolvable / spread);
      res.warnings.push_back(buf);
    }
  }
  if (o.merge != MergeRule::none) {
    const auto groups = merge_groups(res.raw_exponents, order, half_times, half_sums, o);
    for (const auto& g : groups) {
      if (g.size() < 2) continue;
      res.groups.push_back(g);
      double mean = 0.0;
      for (int i : g) mean += res.raw_exponents(i);
      mean /= static_cast<double>(g.size());
      for (int i : g) res.exponents(i) = mean;
      for (std::size_t k = 0; k < P; ++k) {
        double s = 0.0;
        for (int i : g) s += raw_sens(static_cast<Eigen::Index>(k), i);
        s /= static_cast<double>(g.size());
        for (int i : g) res.sensitivities(static_cast<Eigen::Index>(k), i) = s;
      }
    }
  }
  if (o.count > 0 && static_cast<Eigen::Index>(o.count) < m) {  // the extra vector is not reported
    const auto k = static_cast<Eigen::Index>(o.count);
    res.exponents.conservativeResize(k);
    res.sensitivities = Eigen::MatrixXd(res.sensitivities.leftCols(k));
  }
  if (res.averaging_time < 50.0 * o.step)
    res.warnings.push_back("fewer than 50 QR intervals were averaged: the exponents have not converged");
  return res;
}

}  // namespace mlce::spectrum
