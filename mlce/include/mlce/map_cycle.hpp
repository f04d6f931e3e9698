#pragma once
// A map's orbit that settles on a periodic cycle: found in the samples themselves, and its exponent
// read from the approach.
//
// A flow's periodic orbit has the exponent 0 along the flow (paper 001 sec. 3, the paragraph after
// eq. 9); a map's has no such direction. Its exponent is (1/p) ln |mu| of the cycle's multiplier
// mu = prod f'(x_i) over the p points, negative when the cycle attracts: the logistic map at r = 3.2
// settles on a 2-cycle with mu = 4 + 2r - r^2 = 0.16, lambda = ln(0.16)/2 = -0.916 per iteration.
// Once settled the series repeats itself exactly, and Rosenstein's nearest neighbours (eq. 20) are
// the cycle's other points: their curve has no divergence to show, and the records of
// `build/make_series logistic 10000 R` read "neutral, limit cycle" (r = 3.5, 3.74) or undetermined
// (r = 3.2, 3.83: lambda 0 and +0.234 per sample) before this rule. Before it settles, a deviation e from
// the cycle shrinks by mu every p iterations, and so does the difference of the series one cycle
// on, x(t + p) - x(t) = (mu - 1) e(t) + O(e^2): ln |x(t + p) - x(t)| falls at lambda per sample.
//
// The rule (map_cycle), on every channel:
//  - Period p: the smallest p <= size / 8 for which the series' last max(size / 4, 8 p) samples
//    repeat p samples on to within `tolerance` of each channel's range (max - min); `from`: the
//    first sample from which every later one does.
//  - Approach: d(t) = max over the channels of |x(t + p) - x(t)| / range, t < from. Whole cycles
//    [from - (k+1) p, from - k p), k = 0, 1, ..., taken while every d of the cycle lies within
//    (floor, kApproachCeiling]: the floor max(tolerance, kResolutionFactor x the smallest non-zero
//    d of the record), above the written resolution (a double's rounding of the settled cycle,
//    ~1e-16; 6 written digits, ~1e-6), where d jumps in its steps; the ceiling where the
//    multiplier's change with the deviation is still small (a first version cutting at 1e-2, one
//    mean per cycle, read the logistic map's cycles 4-10 % off in a scratch build; 1e-4 within 0.1 %).
//    ln d fitted by one slope (per sample) and a level for each phase
//    of the cycle: its points contract at different rates within a cycle, by the same multiplier
//    over a whole one. The 95 % interval: Student's t with (points - p - 1) degrees of freedom,
//    widened by how far the slope over the latest half of the cycles (at least two; the closest to
//    the cycle) lies from the whole fit's, the approach's remaining curvature. At least
//    kMinApproachCycles cycles, else no rate (a record that starts on the cycle shows no approach).
//  - rate_bound: an upper bound on the exponent from the settled stretch alone. A cycle computed in
//    double precision is perturbed by ~1e-16 of its size each step; had it lambda > 0, the
//    perturbation would outgrow the tolerance within ln(tolerance / 2^-52) / lambda steps. Over the
//    settled stretch of S steps, lambda <= ln(tolerance / 2^-52) / S.
#include <cstddef>
#include <limits>

#include "mlce/series.hpp"

namespace mlce {

struct MapCycleOptions {
  /// Two samples repeat when they differ by at most this share of their channel's range (max - min).
  /// 1e-9: far above a double's rounding of a settled cycle (1e-16), far below what a chaotic orbit
  /// repeats over a quarter of its record. A series written with 6 digits repeats its settled cycle
  /// exactly.
  double tolerance = 1e-9;
  void validate() const;  ///< throws OptionError naming the option
};

inline constexpr double kApproachCeiling = 1e-4;   ///< d above this share of the range: not yet linear enough
inline constexpr double kResolutionFactor = 100.0;  ///< the approach's floor over the record's resolution
inline constexpr std::size_t kMinApproachCycles = 3;

struct MapCycle {
  std::size_t period = 0;  ///< samples; 0: the series does not end on a cycle
  std::size_t from = 0;    ///< the first sample from which every later one repeats one period on
  double tolerance = 0.0;  ///< MapCycleOptions::tolerance, as found with
  /// The approach's slope of ln |x(t + p) - x(t)| per sample, its 95 % interval and R^2 (about the
  /// phases' means); NaN when fewer than kMinApproachCycles cycles lie within its levels.
  double approach_rate = std::numeric_limits<double>::quiet_NaN();
  double approach_ci_low = std::numeric_limits<double>::quiet_NaN();
  double approach_ci_high = std::numeric_limits<double>::quiet_NaN();
  double approach_r2 = std::numeric_limits<double>::quiet_NaN();
  std::size_t approach_first = 0, approach_last = 0;  ///< the samples fitted (t of d(t)), when a rate
  std::size_t approach_cycles = 0;                    ///< the cycles' means fitted
  /// Upper bound on the exponent per sample from the settled stretch (see above); NaN without a cycle.
  double rate_bound = std::numeric_limits<double>::quiet_NaN();
  [[nodiscard]] bool found() const { return period > 0; }
  [[nodiscard]] bool approach_measured() const { return approach_rate == approach_rate; }  // not NaN
};

MapCycle map_cycle(const Series& series, const MapCycleOptions& options = {});

}  // namespace mlce
