#pragma once
// Every channel of a run estimated on its own, and whether they agree. The observables of one
// motion share its exponents (a generic observable of a chaotic attractor carries lambda_1: the
// basis of the delay embedding, paper 001 §3.2), so an analyst who can choose among channels
// (four blade lags, the hub's x and y) should estimate several and see their 95 % intervals
// overlap. One that stands apart carries something the others do not: a start-up transient, a
// noise floor, too few periods of the motion, or (for a decay) not the least damped mode, which a
// channel does not see when the mode's shape does not move it.
#include <optional>
#include <string>
#include <vector>

#include "mlce/convergence.hpp"
#include "mlce/estimate.hpp"

namespace mlce {

struct EachChannelOptions {
  /// Options of every estimate (every channel alone; parameters left automatic are chosen per
  /// channel, as they would be for a file holding that channel only).
  MlceOptions estimate;
  /// Verdict: the channels agree when the gap between their intervals, max(low) - min(high), is at
  /// most max(relative_tolerance x |median lambda|, frequency_tolerance x the largest mean
  /// frequency), per time unit: the same resolution as ConvergenceOptions (an exponent ~0 is
  /// resolved only to an amplitude change of ~1 % per cycle; narrow intervals of 5 % apart are one
  /// exponent read through two observables).
  double relative_tolerance = 0.05;
  double frequency_tolerance = 0.01;
  void validate() const;
};

/// Whether several estimates of one exponent agree (the channels of a run, or one channel of two
/// runs: mlce compare --mlce): the gap between the two 95 % intervals farthest apart, max(low) -
/// min(high), is at most max(relative_tolerance x |median lambda|, frequency_tolerance x the
/// largest mean frequency), per time unit.
struct Agreement {
  double gap = 0.0;  ///< <= 0: every interval holds [common_low, common_high]; NaN with fewer than 2 estimates
  double common_low = 0.0, common_high = 0.0;  ///< NaN when gap > 0 (or is NaN)
  double median_lambda = 0.0;
  double tolerance_floor = 0.0;
  bool agree = false;         ///< gap <= tolerance_floor, over at least two estimates
  std::size_t highest_low = 0, lowest_high = 0;  ///< indices of the two intervals farthest apart
};
/// With no estimate every number is NaN and agree false.
Agreement judge_agreement(const std::vector<const MlceResult*>& estimates, double relative_tolerance = 0.05,
                          double frequency_tolerance = 0.01);

struct ChannelEstimate {
  std::string name;                  ///< the series' channel name ("channel K" when it has none)
  std::optional<MlceResult> result;  ///< nullopt: `error` says why (a channel too short, constant, ...)
  std::string error;
};

struct EachChannelResult {
  std::vector<ChannelEstimate> channels;  ///< in the series' order
  std::size_t estimated = 0;              ///< channels with a result
  /// Estimated channels whose lambda measures a divergence (MlceResult::unreliable empty): the ones
  /// the verdict compares; a warning names each one left out and why.
  std::size_t compared = 0;
  /// Over the compared channels (indices into them, not into `channels`), with the options'
  /// tolerances; gap and common part NaN when fewer than two were compared (every number NaN when
  /// none was).
  Agreement verdict;
  std::vector<std::string> warnings;  ///< the verdict's (each channel's own are in its result)
};

/// Throws OptionError on bad options and InputError when no channel can be estimated (the first
/// channel's error); a channel that cannot be estimated while others can is recorded, not thrown.
EachChannelResult estimate_each_channel(const Series& series, const EachChannelOptions& options);

}  // namespace mlce
