#pragma once
// Mean frequency of the power spectrum and the mean period (paper 001 eq. 19), the default
// Theiler window of the neighbour search (eq. 20).
#include <limits>
#include <string>
#include <vector>

#include "mlce/series.hpp"

namespace mlce {

enum class SpectralWindow { rectangular, hann };

struct MeanPeriodOptions {
  /// Taper applied before the FFT. Hann (default) limits leakage of strong low-frequency
  /// content; for a sinusoid on a Fourier bin both windows give its exact frequency.
  SpectralWindow window = SpectralWindow::hann;
  /// Upper clamp of the mean period as a fraction of the series length (a window wider than this
  /// leaves too few neighbour candidates). Clamping is reported as a warning.
  double max_fraction = 0.25;
  /// A series with at least this share of its power at periods shorter than 4 samples (above a
  /// quarter of the sampling rate) is treated as a map whatever its mean period (MeanPeriodResult::map).
  /// A sampled flow's spectrum falls off well before that: Lorenz x at dt = 0.1 (6.5 samples per
  /// loop) puts 1.2 % of its power there, Roessler x at dt = 0.8 2.5 %, Lorenz x (dt = 0.01) with
  /// white noise of 30 % of its deviation 4.1 %. Maps whose orbit switches slowly between two lobes
  /// have a long mean period from that switching and 6.6-16 % there (the Duffing / Holmes map, the
  /// cubic map x -> a x - x^3). All measured by `build/map_bands switching`.
  double map_fast_share = 0.05;
  void validate() const;
};

/// A series whose mean period (eq. 19) is shorter than this many samples is treated as a map (or a
/// flow sampled too coarsely to interpolate between samples): no phase alignment (estimate.hpp),
/// its curve held to FitOptions::map_straightness (fit.hpp), and no AMI minimum beyond its mean
/// period taken for the delay (AmiOptions::mean_period). So is a series whose spectrum holds
/// MeanPeriodOptions::map_fast_share of its power at periods below 4 samples (MeanPeriodResult::map).
inline constexpr std::size_t kMinFlowPeriod = 8;

/// The mean period of a white spectrum (mean frequency a quarter of the sampling rate), in samples.
inline constexpr std::size_t kWhitePeriod = 4;

/// Above this share of the tapered series' energy, the plain mean left beneath the Hann taper is a bump
/// that holds the periodogram's lowest bins, and the taper-weighted mean is removed instead
/// (MeanPeriodResult::taper_mean_share). Stationary motions stay far below: Lorenz x at most 0.035,
/// Roessler x 1.1e-5 over the 128 series each of `build/finite_time_spread starts` (which prints them); a damped
/// oscillator at zeta = 0.2 over 20 periods holds 0.56, at zeta = 0.5 1.00.
inline constexpr double kTaperMeanShare = 0.1;

struct MeanPeriodResult {
  /// Power-weighted mean frequency sum(P_k f_k)/sum(P_k) over the one-sided periodogram of the
  /// mean-removed series (the plain mean, or the taper-weighted one: taper_weighted_mean), DC bin
  /// excluded; in cycles per time unit. For several channels, the
  /// largest of the channels' values (eq. 19: max over the columns).
  double mean_frequency = 0.0;
  double mean_frequency_per_sample = 0.0;   ///< cycles per sample
  std::vector<double> channel_frequency;    ///< per channel, cycles per time unit
  /// ceil(fs / mean_frequency) in samples (eq. 19), after clamping to [1, max_fraction * N].
  std::size_t mean_period = 1;
  bool clamped = false;
  /// The energy that the plain mean, left beneath the Hann taper, would hold in the tapered series, as a
  /// share of that series' energy (r^2 sum w^2 / sum w^2 (x - mean)^2, r the taper-weighted mean of x -
  /// mean); for several channels the largest. Above kTaperMeanShare the taper-weighted mean is removed
  /// instead (taper_weighted_mean): a decay or growth the taper sees only where it is small, whose bump
  /// would heap the power into the lowest bins. 0 for the rectangular window.
  double taper_mean_share = 0.0;
  bool taper_weighted_mean = false;  ///< some channel had its taper-weighted mean removed
  /// Share of the power at frequencies above a quarter of the sampling rate (periods shorter than 4
  /// samples) over the same periodogram, DC excluded; for several channels the largest.
  double fast_share = 0.0;
  /// Treated as a map: mean_period < kMinFlowPeriod, or fast_share >= MeanPeriodOptions::map_fast_share
  /// (a map whose orbit switches slowly between lobes: its mean period is the switching's, not its
  /// iteration's).
  bool map = false;
  /// The period the estimator's rules see (the AMI's map rule, the fit's segments, straightness and
  /// region, the local slopes): the mean period, except for a map by its spectrum whose mean period
  /// is a flow's (kMinFlowPeriod or more, set by its slow switching): kWhitePeriod, the mean period
  /// of a white spectrum, as its pairs separate within iterations. With its 27 samples the Duffing
  /// map's fit took segments of 14 steps and never trimmed its region's bend (0.927 of the orbit's
  /// exponent in a scratch build), with 4 samples 0.974 (test_estimate_systems). The Theiler window
  /// stays eq. 19's mean period.
  [[nodiscard]] std::size_t rule_period() const { return map && mean_period >= kMinFlowPeriod ? kWhitePeriod : mean_period; }
  std::vector<std::string> warnings;
};

MeanPeriodResult estimate_mean_period(const Series& series, const MeanPeriodOptions& options);

/// The lowest frequency below which `share` of the power above a white floor lies (cycles per sample; the
/// Hann-tapered one-sided periodogram of each channel less its mean, DC excluded, less 10 x the floor's
/// mean, the median of the upper half of the band over ln 2; the largest over the channels): how coarsely
/// the series may be subsampled before a signal's power folds (modes.hpp's stride); white noise folds
/// onto itself. 0.5 when no power stands above the floor.
double band_edge_frequency(const Series& series, double share);

/// How closely the end of a series repeats itself one period on: over its last third (at most
/// kEndRepeatMaxSamples), D(L) = mean over t of (x[t + L] - x[t])^2 over the variance, per channel
/// (each about its own mean; channels of zero variance left out) and averaged over the channels,
/// for lags L = 1 .. third / 3 (the stretch compared spans two periods or more; the cross sums by
/// FFTW, the squares by prefix sums). The period P
/// is the first local minimum of D beyond its first rise to 0.5 (the signal has decorrelated
/// half-way there: a smooth signal's D is small at small lags, whatever the motion) within 1.25 x
/// the least plus 1e-4, each refined by the parabola through its neighbours (a period between two samples; a
/// multiple of it may fall closer to a whole lag); difference = sqrt(D(P)), the RMS of
/// x(t + P) - x(t) over the RMS deviation: 0 for a motion periodic to the data's precision, ~sqrt 2
/// for white noise. On the chaotic flows of `bench/other_flows` (with Lorenz x, and Roessler x near
/// the onset of chaos) 0.136-1.41;
/// on Hammond's limit cycle, blade 3 inoperative, with its settling in the last 10 s of a 30 s run,
/// 0.003-0.036 (reading.hpp, ReadingOptions::periodic_end). NaN when the third has fewer than 16
/// samples, no channel varies, or D has no local minimum beyond its rise to 0.5 within a third of
/// the third.
struct EndRepeat {
  double difference = std::numeric_limits<double>::quiet_NaN();
  double period = std::numeric_limits<double>::quiet_NaN();  ///< samples
};
inline constexpr std::size_t kEndRepeatMaxSamples = std::size_t{1} << 18;
EndRepeat end_repeat(const Series& series);
/// The same rule over the whole record (at most its first kEndRepeatMaxSamples), lags up to half
/// of it: the period at which a record of a few periods repeats itself, its fundamental where the
/// spectrum's mean period is not (a van der Pol cycle's harmonics shorten its mean period), for
/// ends_amplitude_rate's whole periods (transient.hpp). NaN as end_repeat, for fewer than 16 samples.
EndRepeat whole_record_repeat(const Series& series);

}  // namespace mlce
