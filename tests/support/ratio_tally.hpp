#pragma once
// Ratios of estimates to a known exponent, tallied for the accuracy studies of bench/
// (finite_time_spread, decay_modes): how many within a tight and a loose tolerance, range, mean,
// rms error, and optionally the series' own exponents and the estimates' 95 % intervals.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mlce/estimate.hpp"

namespace mlce::bench {

/// Ratios to the known exponent: how many within the tight / loose tolerance, range, mean, rms
/// error; with the series' own exponents also the rms from them and the correlation with them (does
/// an estimator track the trajectory it was given, or scatter independently of it?).
struct Tally {
  double tight = 0.05, loose = 0.10;
  int digits = 3;
  int within_tight = 0, within_loose = 0;
  double sum = 0, err2 = 0, own_err2 = 0, lo = 1e300, hi = -1e300;
  std::vector<double> values, owns;
  void add(double q) {
    within_tight += std::abs(q - 1) <= tight, within_loose += std::abs(q - 1) <= loose;
    sum += q, err2 += (q - 1) * (q - 1), lo = std::min(lo, q), hi = std::max(hi, q);
    values.push_back(q);
  }
  void add(double q, double own) {
    add(q);
    own_err2 += (q - own) * (q - own);
    owns.push_back(own);
  }
  /// With the estimate's 95 % interval [lo, hi] (also / lambda_1): is the interval honest? It should
  /// hold lambda_1 on about 95 % of the series.
  int intervals = 0, holds_known = 0, holds_own = 0;
  double half_width_sum = 0;
  void add(double q, double own, double ci_lo, double ci_hi) {
    add(q, own);
    ++intervals, holds_known += ci_lo <= 1 && 1 <= ci_hi, holds_own += ci_lo <= own && own <= ci_hi;
    half_width_sum += (ci_hi - ci_lo) / 2;
  }
  /// Series a clean signal should never have flagged: "measurement noise" (first-step jump) or
  /// "divergence not resolved" (plateau within one embedding window); and series whose start the
  /// estimator left out as not recurring (none should be: the transient is discarded). Printed
  /// when any was.
  int flagged_noisy = 0, skipped_start = 0;
  std::string bends;  // the values (/ known) of the series whose curve bends within its fit region
  void check_flags(const mlce::MlceResult& r) {
    skipped_start += r.skipped_start > 0;
    for (const auto& w : r.warnings)
      if (w.find("bends within the fit region") != std::string::npos) {  // FitOptions::bend_warning
        char item[16];
        std::snprintf(item, sizeof item, " %.3f", values.empty() ? 0.0 : values.back());
        bends += item;
        break;
      }
    for (const auto& w : r.warnings)
      if (w.find("measurement noise") != std::string::npos || w.find("divergence not resolved") != std::string::npos) {
        ++flagged_noisy;
        break;
      }
  }
  double correlation_with_own() const {
    const double n = static_cast<double>(values.size());
    double mq = 0, mo = 0;
    for (std::size_t k = 0; k < values.size(); ++k) mq += values[k] / n, mo += owns[k] / n;
    double sqo = 0, sqq = 0, soo = 0;
    for (std::size_t k = 0; k < values.size(); ++k)
      sqo += (values[k] - mq) * (owns[k] - mo), sqq += (values[k] - mq) * (values[k] - mq), soo += (owns[k] - mo) * (owns[k] - mo);
    return sqq > 0 && soo > 0 ? sqo / std::sqrt(sqq * soo) : 1.0;
  }
  void print(const char* what) const {
    const int n = static_cast<int>(values.size());
    std::printf("  %-30s within %g %% %2d / %g %% %2d of %d, %.*f..%.*f, mean %.*f, rms error %.*f", what, 100 * tight,
                within_tight, 100 * loose, within_loose, n, digits, lo, digits, hi, digits, sum / n, digits,
                std::sqrt(err2 / n));
    if (owns.size() == values.size())
      std::printf(", rms from own %.3f, correlation with own %+.2f", std::sqrt(own_err2 / n), correlation_with_own());
    if (flagged_noisy > 0) std::printf("\n  %-30s %d flagged as noise-dominated or unresolved", "", flagged_noisy);
    if (skipped_start > 0) std::printf("\n  %-30s %d with a start that does not recur, left out", "", skipped_start);
    if (!bends.empty()) std::printf("\n  %-30s curve bends within its fit region (warned) on:%s", "", bends.c_str());
    if (intervals > 0)
      std::printf("\n  %-30s 95 %% interval holds the known exponent on %d of %d (the own exponent on %d), mean half-width %.*f",
                  "", holds_known, intervals, holds_own, digits, half_width_sum / intervals);
    std::printf("\n");
  }
};

}  // namespace mlce::bench
