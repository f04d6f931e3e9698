#pragma once
// Average mutual information I(tau) and the reconstruction delay J of paper 001 eqs. 15-17.
#include <string>
#include <vector>

#include "mlce/mean_period.hpp"
#include "mlce/series.hpp"

namespace mlce {

enum class DelayRule { first_minimum, autocorrelation_1e, map_iteration };

struct AmiOptions {
  /// Largest delay evaluated. 0 = automatic: min((N-1)/4, 1000). A larger value than N/2 is
  /// clamped to N/2, with a warning.
  std::size_t max_delay = 0;
  /// Number of equal-width bins over the channel's range. 0 = Sturges' rule, ceil(log2 N) + 1,
  /// clamped to [4, 64].
  std::size_t bins = 0;
  /// Width (odd, lags) of the centred moving average applied before the minimum search. 0 = automatic:
  /// the histogram's own ripple spacing T/(pi B) for the mean period T (`mean_period`, samples) and B
  /// bins, rounded down to odd, at least 3; 3 when the period is unknown or the series is a map.
  /// Why: a motion of period T sweeps the joint histogram's cells as its delay coordinates' ellipse
  /// widens, and the estimate ripples by a few per cent of its drop every ~T/(pi B) lags (the
  /// ellipse's width 2 sin(pi tau / T) x the amplitude crosses one more bin width 2 / B x the
  /// amplitude). Over a few periods of a lightly damped oscillation that ripple has minima deeper than
  /// a 3-lag average removes, at lags that move with B: e^{-0.005 t} cos t over 2000 samples of 0.01
  /// took delay 14 (12 bins; 11 with 16, 21 with 8) for its quarter period of 157, and read
  /// lambda = +0.07 for -0.005. A box of the ripple's own width nulls the first ripples and leaves
  /// about a third of those near T/4, where their spacing has grown 1.4-fold (the ripples sit at
  /// T/pi arcsin(k/B)). Lorenz x at dt = 0.01 (T ~ 140..220 samples, B = 15 at N = 10^4) keeps 3.
  /// The coarse-sampling search (coarse_first_lag) reaches 2 x 3 lags whatever this width.
  std::size_t smoothing = 0;
  /// A local minimum of the smoothed curve counts only if the curve rises after it (within as many
  /// lags again) by at least
  ///  - max(significance x b, 0.01 x (I(0) - I(min))) when I(min) < floor_zone x b, b = (B-1)^2 / (2 n)
  ///    being the bias of the histogram estimator for independent samples: wiggles of a curve that
  ///    has decayed into its noise floor (maps, noise) are not minima;
  ///  - relative_rise x (I(0) - I(min)) when I(min) >= floor_zone x b: there b is an offset shared
  ///    by neighbouring lags, not a fluctuation, and the smooth curve of a sampled flow may have a
  ///    shallow first minimum (Lorenz x at N = 10^4: a rise of ~1 % of the drop, < 2 b).
  /// An accepted minimum below significance x b (the level of independent samples: the series
  /// decorrelates completely and the rise is its next recurrence, as for the spikes of Roessler z)
  /// is moved back to the first lag whose smoothed value is within b of it: the end of the decline.
  double significance = 2.0;
  double floor_zone = 10.0;
  /// 0.004 since the depth is measured from I(0) as documented (until commit 7b1fe79 the code
  /// measured it from the mean of I(0..2), ~30 % less, with 0.005): at 0.005 one of 200 Lorenz x
  /// series still got the deep minimum at 61 samples (build/start_variants, part 2).
  double relative_rise = 0.004;
  /// A minimum counts only if its rise also exceeds this many standard errors of the difference of
  /// two smoothed values, sigma x sqrt(2 / w): sigma is the raw curve's own scatter about its trend,
  /// 1.4826 x the median |third difference| / sqrt(20) (robust; a third difference of independent
  /// errors has variance 20 sigma^2 and leaves a quadratic trend out), over lags candidate / 2 ..
  /// the newest. Why: a sine's histogram estimate zigzags by several per cent of its drop from lag
  /// to lag (the delay coordinates' ellipse crosses the bins; worst when the period is a whole number
  /// of samples, so that each lag sees the same few points), and the relative_rise (0.4 % of the
  /// drop, for Lorenz's shallow minimum) took the zigzag's first minima: a sine of 200 samples per
  /// period over 10^5 samples took delay 6 for its quarter period of 50 (now 40). Lorenz x's curve
  /// scatters by 4..8 x 10^-4 nats about its trend at dt = 0.01 (data/lorenz_x.txt: 6.1 x 10^-4; its
  /// smoothed curve rises 100..200 such standard errors within twice its lag) and 2..5 x 10^-3 at
  /// dt = 0.02 (12..26): 2, not 3, keeps every Lorenz x delay of `build/finite_time_spread sampling`,
  /// one of whose dt = 0.02 series' minimum passed its other rise at between 2 and 3 (scratch build).
  /// 0 = off (the rule before 2026-12-05).
  double noise_rise = 2.0;
  /// A curve that loses more than this fraction of I(0) at lag 1 may be coarsely sampled: its
  /// first 2 x 3 lags are searched for a minimum without the smoothing as well (see
  /// ami.cpp and README "The delay rule"). Lorenz x loses 0.62 at dt = 0.1 and 0.47 at dt = 0.05; a
  /// sine of 126 samples per period 0.24.
  double coarse_first_lag = 0.4;
  /// The series' mean period in samples (eq. 19; 0 = unknown). When it is below kMinFlowPeriod (a
  /// map), a minimum later than this period is not taken for the delay: the delay is then the
  /// autocorrelation 1/e time, as when there is no minimum, with a warning. A map decorrelates
  /// within a few iterations; a curve that settles above its floor instead, with a minimum or a
  /// shoulder dozens of iterations on, carries a component that never decorrelates. The bands of a
  /// banded chaotic map, visited in a fixed cycle, do that: the logistic map at r = 3.6 alternates
  /// between two bands, its AMI levels off near ln 2 = 0.69 nats, and the shoulder rule took lag
  /// 26 (mean period 3), where FNN needed m = 5 and the estimate read 0.90 of the orbit's own
  /// exponent (r = 3.58..3.67: 0.79..1.34), against 0.998 at delay 1 (`build/map_bands`).
  std::size_t mean_period = 0;
  /// Treated as a map whatever `mean_period` (MeanPeriodResult::map: a spectrum with a share of its
  /// power at periods below 4 samples). A map's delay, when its AMI has no minimum or its minimum
  /// lies beyond min(mean_period, kMinFlowPeriod - 1), is 1: a map's iterate is its own time step.
  /// The Duffing (Holmes) map x' = y, y' = -0.2 x + 2.75 y - y^3 stays on one lobe for dozens of
  /// iterations; its AMI keeps that memory (no minimum up to 1000), its autocorrelation falls to 1/e
  /// only after 171 iterations, and with that delay FNN took m = 9 and the estimate read 0.09 of the
  /// orbit's exponent.
  bool map = false;
  /// Stop at the first accepted minimum (the estimator's use); off: whole curve (the `ami` command).
  bool stop_at_minimum = false;
  void validate() const;
};

struct AmiResult {
  /// I(tau) in nats (natural log), tau = 0..; channel 0 when the series has several channels.
  std::vector<double> ami;
  std::vector<double> smoothed;
  /// Chosen delay in samples: first significant local minimum of the smoothed curve; when there
  /// is none (maps, whose AMI decays into the noise floor; monotonically decorrelating series),
  /// or a map's lies beyond its mean period (AmiOptions::mean_period), the first tau at which the
  /// autocorrelation falls to 1/e; for a map (AmiOptions::map, or a mean period below
  /// kMinFlowPeriod) 1.
  std::size_t delay = 1;
  DelayRule rule = DelayRule::first_minimum;
  std::size_t bins = 0;
  std::size_t smoothing = 0;  ///< width of the moving average used (AmiOptions::smoothing resolved)
  double noise_floor = 0.0;  ///< b, nats
  /// The raw curve's scatter sigma about its trend where the minimum was accepted (nats; see
  /// AmiOptions::noise_rise); 0 when the delay is not a first minimum of the smoothed curve.
  double scatter = 0.0;
  std::vector<std::size_t> channel_delay;
  std::vector<std::string> warnings;
};

AmiResult estimate_delay_ami(const Series& series, const AmiOptions& options);

/// Autocorrelation 1/e time of one standardized channel (samples, >= 1), searched up to max_lag.
std::size_t autocorrelation_time(const std::vector<double>& x, std::size_t max_lag);

const char* to_string(DelayRule rule);

}  // namespace mlce
