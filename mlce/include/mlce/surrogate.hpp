#pragma once
// Is the divergence more than linear noise gives? A test of the chaotic reading by surrogate data
// (Theiler, Eubank, Longtin, Galdrikian and Farmer 1992; Schreiber and Schmitz 1996, 2000).
//
// A linear stochastic process -- a lightly damped mode driven by noise, a rotor in turbulence --
// has delay vectors whose nearest neighbours separate as the noise decorrelates them, and its
// divergence curve rises and saturates as a chaotic one does: an AR(2) resonance (x_t = 2 r cos(w)
// x_{t-1} - r^2 x_{t-2} + e_t, r = 0.99, w = 0.2) reads lambda = +0.028 per sample at FNN's m = 5,
// "unstable, chaotic" (6 of 8 series of bench/surrogate_power), while its dynamics are a stable
// linear filter.
// Nothing in one curve tells them apart. The null hypothesis "a Gaussian linear process observed
// through a static monotone function" is tested instead: surrogates with the series' power spectrum
// and amplitude distribution and nothing else (IAAFT: iterated amplitude-adjusted Fourier
// transform) are estimated as the series is, and the series' divergence must exceed every one.
//
// The rule (surrogate_test):
//  - Each surrogate: the series' values shuffled (splitmix64, seed + k), then alternately given the
//    series' Fourier amplitudes (phases kept) and its values in the rank order of the result, until
//    the ranks stop changing or `iterations` passes; it ends on the exact values (their spectrum
//    then within a fraction of a per cent of the series').
//  - Several channels embedded jointly (hub x and y): multivariate IAAFT (Schreiber and Schmitz
//    2000, sec. 6.2), each channel its own values and amplitudes, and the channels' phases the
//    series' own turned by one angle per frequency, so that the cross-spectra -- how the channels
//    move together, which a joint embedding's neighbours see -- are the series' too; on the
//    segment whose ends meet (match_ends, below) rather than the leading one. Until 2026-12-07 the
//    test took one channel, and a joint embedding of a noise-driven mode's displacement and
//    velocity read "unstable, chaotic" untested (32 of 32 series).
//  - The statistic: the slope of the divergence curve (eq. 23) per sample over the estimate's own
//    fit region [first, last], with the estimate's m, delay, Theiler window and phase alignment (a
//    sampled flow's neighbours moved to their references' phase, as the estimate's were: the curve
//    whose slope is lambda), followed to step `last` (later steps do not enter the slope); for the
//    series and for each surrogate alike (fit_line): the test speaks to the slope that is lambda.
//    (Until 2026-12-07 the plain curve, followed to the estimate's whole horizon.)
//  - On at most `max_samples` of the series, its first ones (0: all): the test's cost is K IAAFT
//    surrogates (each pass an FFT pair and a sort of the segment) and K curves, and it grows with
//    the segment while the question -- does this motion's divergence exceed linear noise's? --
//    does not need the whole of a long record. The segment keeps at least 8 times the samples the
//    fit region spans with its embedding window, (m - 1) delay + last + 1, so that its curve has
//    references enough.
//  - Rank test, one-sided: p = (1 + #{surrogates whose slope >= the series'}) / (1 + K). With the
//    default K = 19, p = 0.05 when the series' slope exceeds all of them. And its distance from
//    the surrogates' mean in their standard deviations (Theiler et al.'s significance S), at least
//    min_sigmas: under the null the rank test alone passes 1 series in 20 (AR(2) at r = 0.995 read
//    "chaotic" and passed it by 0.4 %, bench/surrogate_power), while chaos leaves its surrogates far
//    behind (Lorenz x: slopes 0.0079-0.0097 per sample against at most 0.0005 on 8 series). Both: the
//    divergence is "distinguished" from linear noise.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "mlce/progress.hpp"
#include "mlce/series.hpp"

namespace mlce {

struct SurrogateOptions {
  /// K surrogates (19: p = 0.05 when the series beats all); at least 1. Whether estimate_mlce runs
  /// the test at all: MlceOptions::surrogates_when.
  std::size_t count = 19;
  std::size_t iterations = 200;  ///< IAAFT passes at most (each: two FFTs and a sort)
  /// The test on the series' first max_samples (at least 8 x ((m - 1) delay + last + 1)); 0: all.
  std::size_t max_samples = 0;
  /// Reference points of each curve at most (estimate_mlce: also at most the estimate's own cap,
  /// MlceOptions::max_references); 0: the estimate's cap.
  std::size_t max_references = 0;
  /// Several channels: the segment whose ends meet (match_ends) among those starting in the first
  /// tenth (at most kEndMatchStarts samples) and up to a fifth (at most kEndMatchLengths) shorter,
  /// instead of the leading one. One channel: always the leading segment.
  bool match_ends = true;
  std::uint64_t seed = 1;        ///< surrogate k shuffles with splitmix64 from seed + k
  double significance = 0.05;    ///< p at most this, and
  double min_sigmas = 3.0;       ///< S at least this: the series' divergence is distinguished
  void validate() const;         ///< throws OptionError naming the option
};

struct SurrogateTest {
  double series_slope = 0.0;             ///< the statistic on the series, per sample
  std::vector<double> surrogate_slopes;  ///< on each surrogate, per sample
  std::size_t at_least = 0;              ///< surrogates whose slope is at least the series'
  double p_value = 1.0;                  ///< (1 + at_least) / (1 + K)
  /// (series_slope - the surrogates' mean) / their standard deviation; +inf when they all agree
  /// and the series lies above them
  double sigmas = 0.0;
  bool distinguished = false;            ///< p_value <= significance and sigmas >= min_sigmas
  double significance = 0.0, min_sigmas = 0.0;  ///< the options' bounds, as tested against
  std::size_t first = 0, last = 0;       ///< the curve steps the slopes span (the estimate's fit)
  double mean_passes = 0.0;               ///< IAAFT passes per surrogate, on average (at most `iterations`)
  std::size_t first_sample = 0;          ///< the segment the test ran on: from this sample (0 but where ends were matched)
  std::size_t samples = 0;               ///< the segment's samples
  std::size_t of_samples = 0;            ///< of the series' samples
  /// Where the segment's ends were matched (several channels): match_ends' jump; else NaN.
  double end_jump = std::numeric_limits<double>::quiet_NaN();
  /// Channels the surrogates were made of: one, IAAFT; several, multivariate IAAFT (their
  /// cross-spectra kept too).
  std::size_t channels = 1;
  std::vector<std::string> warnings;
};

/// "first N of M samples" where the test ran on a leading segment (SurrogateOptions::max_samples),
/// "samples A..B of M" where on an end-matched one, else empty: the words the reading and the report
/// both put after the test's figures.
std::string segment_words(const SurrogateTest& t);

/// An IAAFT surrogate of x: x's values, in an order whose power spectrum is x's to within the
/// passes' convergence. x of at least 4 values, not all equal.
/// `passes`, when given, receives the passes made (below `iterations`: the ranks stopped changing).
std::vector<double> iaaft_surrogate(const std::vector<double>& x, std::uint64_t seed, std::size_t iterations,
                                    std::size_t* passes = nullptr);

/// A multivariate IAAFT surrogate of the channels x[0..C-1] (equal lengths, at least 4 values, none
/// constant): each channel's values, in an order whose power spectrum is that channel's and whose
/// cross-spectra with the other channels are the series', to within the passes' convergence. One
/// channel: iaaft_surrogate's, bit for bit. `passes` as there (all channels' ranks stop changing).
std::vector<std::vector<double>> iaaft_surrogates(const std::vector<std::vector<double>>& x, std::uint64_t seed,
                                                  std::size_t iterations, std::size_t* passes = nullptr);

/// A Fourier surrogate is periodic: it steps from its last sample back to its first as from any
/// sample to the next, and a record whose ends do not meet gets that jump spread over every frequency
/// as fine-scale noise. Where channels are tied by an exact relation (a coordinate and its own rate,
/// which a multibody solver writes side by side) the relation holds across the record but not
/// across the jump, and the surrogates' channels carry a small part at the finest scale the other
/// does not explain: a noise-driven mode's displacement and velocity, jointly, read 0.72 standard
/// deviations above their surrogates on average on the leading 4096 samples, one of 32 series by
/// 3.93, and 0.27 on the segment whose ends meet, none above 1.9 (`build/surrogate_power 32 "(q, v)"`;
/// its q alone reads no such excess, the "mode + noise" rows). So for several channels the
/// segment is chosen whose ends meet: the one of at most `length` and at least `min_length`
/// samples, starting within the first max(1, length / 10) samples (at most kEndMatchStarts) and at
/// most min(length / 5, kEndMatchLengths) shorter, with a sample after it, that minimises
/// jump = sum over channels of (x[start + samples] - x[start])^2 / (the channel's mean squared step
/// over the leading `length` samples): the step the wrap takes, x[start + samples] -> x[start]
/// instead of the record's own next sample, in steps of the channel's own size. A first sample 0 and
/// `length` samples (jump +inf) when there is no choice (length <= min_length). `length` may be the
/// whole series: the segments then end before its last sample.
struct EndMatch {
  std::size_t first = 0, samples = 0;
  double jump = 0.0;
};
inline constexpr std::size_t kEndMatchStarts = 1000;
inline constexpr std::size_t kEndMatchLengths = 2000;
EndMatch match_ends(const std::vector<std::vector<double>>& x, std::size_t length, std::size_t min_length);

/// Where the statistic is read: the estimate's embedding, Theiler window and fit region.
struct SurrogateSetup {
  std::size_t dim = 1, delay = 1, theiler = 1;
  std::size_t first = 0, last = 0;  ///< curve steps, last > first
  std::size_t max_references = 20000;
  /// The estimate's phase alignment (DivergenceCurve::phase_aligned): the statistic's curves, the
  /// series' and each surrogate's, move each neighbour to its reference's phase as the estimate did.
  bool align_phase = false;
};

/// The test above on a series of one or more channels (the part an estimate analysed). Reports its progress
/// through `progress` when given.
SurrogateTest surrogate_test(const Series& series, const SurrogateSetup& setup, const SurrogateOptions& options,
                             const ProgressCallback& progress = {});

}  // namespace mlce
