#pragma once
// All Lyapunov characteristic exponents of dx/dt = f(x, t) along the trajectory from x0 by the
// discrete QR method (paper 000 sec. 2.3, eqs. 7-11; paper 001 sec. 3.1, eqs. 10-14), and their
// sensitivity to model parameters (paper 000 secs. 2.4-2.7, eqs. 12, 18-28), in one pass.
//
// Per interval [t_{j-1}, t_j]: Z = Y_j Q_{j-1} is integrated from Z = Q_{j-1} together with x
// (and x_/p, Z_/p = Y_j/p Q_{j-1} + Y_j Q_{(j-1)/p} from Q_{(j-1)/p}); Z = Q_j R_j with
// r_ii > 0 (Householder, signs fixed); lambda_i = sum log r_ii / (t - t_transient), natural log,
// in 1/(the model's time unit). With count = k < n: k tangent vectors, thin QR (Q is n x k), the k
// largest exponents. Sensitivity: W_L = stril(Q_j^T Z_/p R_j^-1) (eqs. 19-20, 24),
// W = W_L - W_L^T, R_j/p = Q_j^T Z_/p - W R_j (eq. 25), Q_j/p = Q_j W (eq. 21),
// lambda_i/p = sum (r_ii/p / r_ii) / (t - t_transient) (eq. 12).
// The sums are compensated (Neumaier), so 1e7 intervals accumulate without drift.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "mlce/ode/runge_kutta.hpp"
#include "mlce/ode/system.hpp"
#include "mlce/spectrum/tangent.hpp"

namespace mlce::spectrum {

/// How exponents that converge to the same value (complex-conjugate pairs: multiplicity, paper
/// 000 sec. 3.1) are averaged.
enum class MergeRule {
  none,       ///< report every exponent as computed
  unresolved,  ///< average neighbours (in the sorted order) that have not separated: over the second
               ///< half of the averaging window the difference of their log-sums changes less
               ///< along its least-squares line than it oscillates about it. Distinct exponents
               ///< drift apart linearly; a complex-conjugate pair only oscillates.
  tolerance,  ///< average neighbours closer than merge_tolerance
};

struct QrOptions {
  double t0 = 0.0;
  double t_end = 0.0;       ///< end time (> t0), required
  double step = 0.0;        ///< re-orthonormalisation interval t_j - t_{j-1} (> 0), required
  double transient = 0.0;   ///< time after t0 before the sums start (tangent vectors align first)
  /// How many exponents, the largest first: k + 1 tangent vectors instead of n (thin QR), so the
  /// tangent work scales with k (the MLCE alone: k = 1). 0 = all n. The k leading exponents do
  /// not depend on the others (the first columns of the QR process evolve on their own), nor do
  /// their sensitivities (with the part of Q_/p outside span(Q)). The one extra vector lets the
  /// merge rule see a complex pair straddling the k-th exponent. No Liouville check when k + 1 < n.
  std::size_t count = 0;
  /// Periodic systems (period > 0): start the sums later so that they span a whole number of
  /// periods, which removes the bias of a partial period from exponents and sensitivities.
  bool whole_periods = true;
  JacobianMethod jacobian = JacobianMethod::analytic;
  ode::IntegratorOptions integrator;  ///< for the whole augmented state
  MergeRule merge = MergeRule::unresolved;  ///< as the CLI's --merge auto
  double merge_tolerance = 0.0;       ///< for MergeRule::tolerance (1/time)
  std::size_t history_points = 1000;  ///< running estimates kept (evenly spaced)
  std::function<void(double fraction)> progress;
  void validate() const;  ///< throws std::invalid_argument naming the option
};

struct QrResult {
  Eigen::VectorXd exponents;       ///< sorted descending; merged groups carry their average (count of them)
  /// Every computed exponent, sorted descending, before merging: with count = k < n, k + 1 of
  /// them (history, groups and the sum refer to these).
  Eigen::VectorXd raw_exponents;
  std::vector<std::vector<int>> groups;  ///< indices (into exponents) averaged together, size > 1 only
  std::vector<std::string> parameters;
  Eigen::MatrixXd sensitivities;   ///< parameters x exponents: d lambda_i / d p (per unit of p)
  std::vector<double> history_time;
  Eigen::MatrixXd history;         ///< rows: history_time; columns: running estimates in sorted order
  Eigen::MatrixXd history_sensitivities;  ///< rows: history_time; columns (p, i) p-major
  Eigen::VectorXd final_state;
  double averaging_start = 0.0;    ///< where the sums start (t0 + transient, or later: whole periods)
  double averaging_time = 0.0;     ///< t_end - averaging_start
  std::size_t intervals = 0;
  double orthogonality_error = 0.0;  ///< max |Q^T Q - I| seen over the run
  /// Sum of raw_exponents, and the mean of tr A = div f over the same window (integrated with the
  /// trajectory; NaN when count < n). Liouville's formula makes them equal; their difference is
  /// the error of the tangent integration, reported as a warning when it exceeds
  /// kLiouvilleTolerance (liouville.hpp).
  double exponent_sum = 0.0;
  double mean_divergence = 0.0;
  ode::IntegrationStats stats;
  std::vector<std::string> warnings;
};

QrResult qr_spectrum(const ode::DynamicalSystem& sys, const Eigen::VectorXd& x0, const QrOptions& options,
                     const std::vector<ode::ParameterFamily>& parameters = {});

/// Neumaier's compensated sum.
struct CompensatedSum {
  double sum = 0.0, c = 0.0;
  void add(double v) {
    const double t = sum + v;
    c += std::abs(sum) >= std::abs(v) ? (sum - t) + v : (v - t) + sum;
    sum = t;
  }
  double value() const { return sum + c; }
};

}  // namespace mlce::spectrum
