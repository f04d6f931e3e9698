#include "mlce/map_cycle.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "mlce/numerics.hpp"

namespace mlce {

void MapCycleOptions::validate() const {
  if (!(tolerance > 0.0 && tolerance < 1.0))
    throw OptionError(fmt::format("map_cycle.tolerance = {:g}: expected 0 < value < 1", tolerance));
}

namespace {

/// |x(t + p) - x(t)| / range, the largest over the channels (constant channels left out).
double cycle_difference(const Series& s, const std::vector<double>& range, std::size_t t, std::size_t p) {
  double d = 0.0;
  for (std::size_t c = 0; c < s.channels.size(); ++c)
    if (range[c] > 0.0) d = std::max(d, std::abs(s.channels[c][t + p] - s.channels[c][t]) / range[c]);
  return d;
}

struct Line {
  double slope = 0.0, half = 0.0, r2 = 0.0;  ///< per sample; 95 % half-width
};

/// One slope, a level per phase of the cycle, through log_d from cycle `skip` on (at least two
/// cycles; kMinApproachCycles for a fixed point, p = 1, to leave a degree of freedom): the cycle's points contract at different rates within a cycle, by the same multiplier
/// over a whole one. Least squares about each phase's mean; the interval from Student's t with
/// (points - p - 1) degrees of freedom, R^2 of the variation about the phases' means.
Line phase_line(const std::vector<double>& log_d, std::size_t p, std::size_t skip) {
  const std::size_t cycles = log_d.size() / p - skip;
  const double mean_k = 0.5 * static_cast<double>(cycles - 1);
  std::vector<double> phase_mean(p, 0.0);
  for (std::size_t i = skip * p; i < log_d.size(); ++i) phase_mean[i % p] += log_d[i] / static_cast<double>(cycles);
  CompensatedSum sxy, sxx, syy;
  for (std::size_t i = skip * p; i < log_d.size(); ++i) {
    const std::size_t cycle = i / p - skip;  // whole cycles: the integer division is meant
    const double x = (static_cast<double>(cycle) - mean_k) * static_cast<double>(p);  // samples
    const double y = log_d[i] - phase_mean[i % p];
    sxy.add(x * y), sxx.add(x * x), syy.add(y * y);
  }
  Line out;
  out.slope = sxy.value() / sxx.value();
  const double residual = std::max(0.0, syy.value() - out.slope * sxy.value());
  const std::size_t dof = cycles * p - p - 1;  // >= 1 for two cycles or more, but of a 2-cycle or longer
  out.half = dof > 0 ? student_t95(dof) * std::sqrt(residual / static_cast<double>(dof) / sxx.value())
                     : std::numeric_limits<double>::infinity();
  out.r2 = syy.value() > 0.0 ? 1.0 - residual / syy.value() : 1.0;
  return out;
}

}  // namespace

MapCycle map_cycle(const Series& series, const MapCycleOptions& options) {
  options.validate();
  MapCycle out;
  out.tolerance = options.tolerance;
  const std::size_t n = series.size();
  if (n < 32) return out;
  std::vector<double> range;
  for (const auto& c : series.channels) {
    const auto [lo, hi] = std::minmax_element(c.begin(), c.end());
    range.push_back(*hi - *lo);  // finite: validate_series refuses NaN and Inf; a difference may overflow
  }
  if (std::none_of(range.begin(), range.end(), [](double r) { return r > 0.0 && std::isfinite(r); })) return out;
  for (double& r : range)
    if (!std::isfinite(r)) r = std::numeric_limits<double>::max();
  const double tol = options.tolerance;
  // First t (scanning back from the end) from which every later t repeats p samples on.
  auto settled_from = [&](std::size_t p, std::size_t stop) {
    std::size_t t = n - p;  // t + p <= n - 1
    while (t > stop && cycle_difference(series, range, t - 1, p) <= tol) --t;
    return t;
  };
  for (std::size_t p = 1; p <= n / 8; ++p) {
    const std::size_t need = std::max(n / 4, 8 * p);  // samples that must repeat, the last of them
    const std::size_t must = n - need;                 // settled_from <= must, or not a cycle
    if (settled_from(p, must) > must) continue;        // stops at `must` when it gets there
    out.period = p;
    out.from = settled_from(p, 0);
    break;
  }
  if (!out.found()) return out;
  const std::size_t p = out.period;
  const double settled = static_cast<double>(n - out.from - p);  // steps over which the repeat held
  out.rate_bound = std::log(tol / 0x1p-52) / std::max(settled, 1.0);

  // The approach, cycle by cycle back from `from`, above the written resolution: the smallest
  // non-zero difference anywhere (a double's rounding of the settled cycle, ~1e-16; a series
  // written with 6 digits: its quantum, ~1e-6 of the range).
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t + p < n; ++t)
    if (const double d = cycle_difference(series, range, t, p); d > 0.0) smallest = std::min(smallest, d);
  const double floor = std::max(tol, kResolutionFactor * smallest);
  std::vector<double> log_d;  // backwards in time while collected, reversed after
  for (std::size_t k = 0; (k + 1) * p <= out.from; ++k) {
    const std::size_t first = out.from - (k + 1) * p;
    const std::size_t kept = log_d.size();
    for (std::size_t t = first + p; t-- > first;) {
      const double d = cycle_difference(series, range, t, p);
      if (!(d > floor && d <= kApproachCeiling)) break;
      log_d.push_back(std::log(d));
    }
    if (log_d.size() < kept + p) {
      log_d.resize(kept);
      if (kept == 0) continue;  // still near the floor (the cycle's last resolved steps)
      break;                    // beyond the ceiling: the approach's nonlinear start
    }
    out.approach_first = first;
    if (kept == 0) out.approach_last = first + p - 1;
  }
  std::reverse(log_d.begin(), log_d.end());  // whole cycles in time order
  const std::size_t cycles = out.approach_cycles = log_d.size() / p;
  if (cycles < kMinApproachCycles) return out;
  const Line all = phase_line(log_d, p, 0);
  // The formal interval holds the scatter, not the approach's curvature (the multiplier's O(e)
  // change with the deviation e): widened by how far the slope of the latest half of the cycles,
  // the closest to the cycle, lies from the whole fit's.
  double half = all.half;
  half += std::abs(phase_line(log_d, p, cycles - std::max<std::size_t>(2, cycles / 2)).slope - all.slope);
  out.approach_rate = all.slope;
  out.approach_ci_low = all.slope - half;
  out.approach_ci_high = all.slope + half;
  out.approach_r2 = all.r2;
  return out;
}

}  // namespace mlce
