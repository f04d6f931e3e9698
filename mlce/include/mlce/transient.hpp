#pragma once
// End of the initial transient of a run started from a perturbation.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "mlce/series.hpp"

namespace mlce {

struct TransientOptions {
  /// Window length in samples for the moving RMS; 0 = max(2 * period, N / 100), doubled (keeping
  /// at least 8 windows) while the last quarter's RMS scatters by more than band_max / 1.5 (a beating
  /// multi-frequency motion). Two periods keep the RMS of a periodic motion within ~2 % whatever
  /// the phase at which the window starts (the oscillating part of the mean square is at most
  /// 1/(4 pi) of it per period covered).
  std::size_t window = 0;
  /// Mean period in samples (from estimate_mean_period).
  std::size_t period = 1;
  /// Windows whose RMS lies within this relative band around the RMS of the last quarter of the
  /// series count as settled. 0 = automatic: 1.5 times the largest relative deviation of a last-
  /// quarter window RMS from their median, kept within [band_min, band_max]: a window is settled
  /// when it looks like the last quarter. A limit cycle (RMS constant to 0.1 %) is settled only
  /// once its amplitude is within 2 %; a chaotic or beating motion (RMS scattering by 10 % or more
  /// from window to window) is not cut short. The band is widened, up to band_max_irregular, to
  /// 8 robust standard deviations of the window RMS over the last quarter (1.4826 x the median
  /// |second difference| / sqrt 6, blind to a smooth trend): its few windows may agree closely by
  /// chance while the motion is irregular (chaos), and an excursion would then cut the series up to
  /// it. The drift test of the last quarter uses the band without the widening.
  double band = 0.0;
  double band_min = 0.02, band_max = 0.25, band_max_irregular = 0.5;
  /// A settled part whose RMS is below this fraction of the largest window RMS is not a motion but
  /// the noise/underflow floor a decay ends in (paper 001 Fig. 6): the signal ends there.
  double floor_ratio = 1e-6;
  void validate() const;
};

struct TransientResult {
  std::size_t end_index = 0;  ///< first sample of the settled part
  double end_time = 0.0;
  bool settled = true;  ///< false: amplitude drifts until the end (decay or growth): whole series kept
  /// A decay into the noise/underflow floor: the floor starts at this sample (0 = none); nothing
  /// is cut at the start, and the samples from here on carry no dynamics.
  std::size_t floor_index = 0;
  std::string rule;
};

/// Rule: RMS about the last quarter's mean in consecutive windows (at least 8); the transient ends at
/// the start of the first window from which every later window's RMS is within `band` of the last
/// quarter's median window RMS. If the last quarter itself drifts (its first and last window RMS differ by
/// more than `band`) the motion is a decay or a growth and nothing is cut. First, a decay into a
/// noise/underflow floor (detect_floor) cuts nothing at the start and sets floor_index.
TransientResult detect_transient(const Series& series, const TransientOptions& options);

/// The floor a decay ends in (paper 001 Fig. 6: past it the series carries no dynamics).
/// The resolution floor (detect_floor): a last quarter below this share of the largest window RMS
/// whose windows repeat a few values. MBDyn's .mov writes orientations in degrees with 7 digits, so a
/// blade's lag taken from two nodes' orientations (rel:A:B:AXIS) decays to a few quanta of
/// 1e-6..1e-4 deg: the real isotropic run's four lags sink to 1e-5..1e-4 of their largest window RMS by
/// ~10 s, 2-16 distinct values in windows of 40 samples, and the whole record read -0.47..-0.89 1/s
/// (one undetermined) where its first 10 s read the slowest eigenvalue, -1.18. The damper's own
/// angle (.jnt, relative precision) decays to underflow instead, and reads -1.18 whole.
inline constexpr double kResolutionFloorShare = 1e-3;

struct Floor {
  std::size_t index = 0;     ///< first sample of the floor; 0 = no floor
  bool white_noise = false;  ///< found by a white-noise rule (else: below floor_ratio)
  bool from_increments = false;  ///< the noise's level from the last quarter's increments (white_noise too)
  bool against_record = false;   ///< below floor_ratio of the record's largest deviation, not the series' own
  /// Found by the resolution rule: the last quarter repeats a few written values (quantised_tail)
  /// below kResolutionFloorShare of the largest window RMS.
  bool resolution = false;
  /// Against the record: every window already lies within the floor's 10x (index 0, nothing to cut):
  /// the series is that floor, whatever its amplitude does within the 10x.
  bool whole = false;
  double level = 0.0;        ///< the noise's (or last quarter's median window) RMS / the largest window RMS
};

/// The noise/underflow floor a decay ends in: RMS in 100 windows about the last quarter's mean.
/// A floor when the last quarter's median window RMS is below floor_ratio x the largest (rounding,
/// solver tolerance, underflow), or below 0.1 x the largest while the last quarter is white noise
/// at a steady level (measurement noise: the two halves' median RMS within 2x, every channel's
/// autocorrelation at lags 1-3 below 0.3 in magnitude, which a sampled smooth or periodic motion
/// never is). It starts at the first window after which every window stays within 10x that level
/// (5x for white noise: where the signal is still 5x the noise). Failing both, noise that holds
/// only the end of the last quarter is read from the quarter's increments (white: correlated -1/2,
/// 0, 0 at lags 1-3 in every channel, at a steady level; RMS from the third differences:
/// white_increment_noise): a floor when that RMS is below 0.1 x the largest window RMS, cut at 5x it.
/// Failing the underflow rule, a last quarter below kResolutionFloorShare x the largest window RMS
/// (of the record, as for underflow) whose windows repeat their values (at most
/// kQuantisedLevelShare of a window's samples distinct, the median window of the quarter, in the
/// channel that repeats least; 2 at least: one value is a constant tail) with increments as large
/// as its deviations (kQuantisedRoughness: no smooth motion) is the resolution the values were
/// written with (Floor::resolution): a floor that starts where every later window stays within 10x
/// of the quarter's largest window RMS (its steps come and go).
/// A white-noise floor needs a motion before it: when the samples kept before the cut are white too
/// (lags 1-3 as above), the record is noise throughout, only louder in places, and has no floor.
/// floor_ratio 0: never a floor.
/// `record_deviation` (empty, or one per channel): the series is a window cut from a longer record
/// whose channels deviate by up to these (MlceOptions::record_deviation); the underflow rule then
/// measures the last quarter against the largest window RMS times the record's largest deviation
/// over the series' own (least over the channels, at least 1), so that a window cut late in a decay
/// loses the same floor the whole record's analysis would. A floor found only against the record
/// must hold its level (the later half's median window RMS at least half the earlier half's: a
/// decay that goes on falling is the motion), and when every window lies within its 10x the whole
/// series is that floor (Floor::whole, index 0).
Floor detect_floor(const Series& series, double floor_ratio, const std::vector<double>& record_deviation = {});

/// Variance of the mean of k squared third differences of white Gaussian noise, over the square of
/// their mean, times k: 2 x (1 + 2 (0.75^2 + 0.3^2 + 0.05^2)) = 4.62 (third differences correlate at
/// lags 1, 2, 3 by -0.75, 0.3, -0.05). sqrt(4.62 / k) is the relative standard error of a noise's mean
/// square measured from k third differences.
inline constexpr double kThirdDifferenceVarianceFactor = 4.62;

/// White measurement noise in samples [from, to) of every channel, read from its differences.
/// WhitenessTest::increments (the floor rule's): the increments of white noise e of variance s^2
/// correlate -1/2, 0 and 0 at lags 1, 2 and 3; a finely sampled smooth motion moves by ~omega dt x
/// its amplitude per sample, so its increments drown in the noise's long before the motion itself
/// does, and the increments of a sampled periodic motion correlate cos(k theta) at lag k, which
/// cannot match all three (a lag-1 correlation within 0.2 of -1/2 puts theta in 1.88..2.35 rad,
/// where cos 3 theta > 0.7). Noise when every channel's increments correlate within 0.2 of -1/2 at
/// lag 1 and below 0.3 in magnitude at lags 2 and 3. WhitenessTest::third_differences: the third
/// differences of white noise correlate -15/20, 6/20 and -1/20 at lags 1-3, and a smooth motion
/// enters them only as (omega dt)^3 x its amplitude, so they show the noise under a motion 1/(omega
/// dt)^2 times larger than the increments do (400x at 100 samples per period); noise when every
/// channel's correlate within 0.2 of those three (a sampled sine passes only for theta within
/// ~2.58..2.62 rad, 2.4 samples per cycle). Both: at a steady level (the mean square of the third
/// differences in the stretch's two halves within 2x of each other), and the noise's standard
/// deviation is then sqrt(mean (third difference)^2 / 20) (Var of the third difference of e =
/// C(6, 3) s^2 = 20 s^2: the smooth motion leaks in as (omega dt)^6, least of the low orders). A
/// constant channel carries no noise (0). nullopt: some channel is not white noise at a steady
/// level by the test, or the stretch has fewer than 16 samples.
struct IncrementNoise {
  std::vector<double> deviation;  ///< per channel, in the channel's units
  std::vector<double> relative;   ///< per channel, over the channel's peak |x| (no square overflows)
};
enum class WhitenessTest { increments, third_differences };
std::optional<IncrementNoise> white_increment_noise(const Series& series, std::size_t from, std::size_t to,
                                                   WhitenessTest test = WhitenessTest::increments);

/// Where the white noise of a series is at one level to its end: the series in 8 windows, and the
/// longest run of them to the end none of whose windows' mean square of third differences exceeds,
/// in any channel, the run's mean by more than 3 standard errors of that difference
/// (sqrt(4.62 / w x (1 - 1 / k)) for w differences per window and k windows in the run: they
/// correlate at lags 1-3). One-sided: a leak only raises a window. A motion leaks into third
/// differences as (omega dt)^6 x its amplitude^2, most where a decay is largest: coarsely sampled
/// (omega dt = 0.31, zeta 0.005, 0.5 % noise) the leak of a whole record's first eighth raised its
/// mean square by 40-55 % and the whole record's estimate of the noise by 2-3 %, which passes the
/// whiteness test, and the noise-compensated curve, whose noise share nears 1 at its end, read 1.15
/// of the rate on two noise draws; from the second eighth, 1.05 and 1.07. Judged against the run's
/// mean, not window by window against the mean of those after it (the rule before): a last window
/// low by chance then refused every window before it (a two-channel decay's 3 % noise read 12 % low
/// from its last window alone; with 3 errors of the window's own, both ways, two of the 64 records
/// of bench/noisy_decays stopped at their last window, and read 1.19 and 0.81). Returns the first
/// sample of the steady stretch (0: all of it; 0 also for fewer than 16 samples per window).
std::size_t steady_noise_start(const Series& series);

/// What found the floor, in words: the white tail's level, or the ratio it fell below.
std::string floor_evidence(const Floor& floor, double floor_ratio);
/// The floor in words for rules and warnings: its kind and floor_evidence.
std::string describe(const Floor& floor, double floor_ratio);

/// Rate at which the signal's own amplitude changes, per sample (natural log): the least-squares
/// slope of ln RMS over consecutive windows of 2 x `period` samples against the window centre (RMS
/// about each window's own mean, channels summed, each divided by its peak |x| so that no square
/// overflows). A motion decaying to rest has the rate of its slowest mode, its least negative
/// exponent; a motion that persists (limit cycle, chaos) ~0. Windows of zero RMS are left out (no
/// log 0). NaN when fewer than 4 windows with a positive RMS fit in the series.
/// `end`: the same slope over the windows whose centre lies in the series' second half (whether the
/// signal still grows or decays at its end; NaN when fewer than 4 of them), from the same windows.
/// `whole_stderr`: the formal standard error of `whole` (the windows' scatter about the line, taken as
/// independent): how far a motion that persists, whose windows' RMS wander (chaos), tilts the line by
/// chance. A trend that bends (a decay turning into a growth) counts as scatter here.
struct EnvelopeRates {
  double whole = std::numeric_limits<double>::quiet_NaN();
  double end = std::numeric_limits<double>::quiet_NaN();
  double whole_stderr = std::numeric_limits<double>::quiet_NaN();
};
EnvelopeRates envelope_rates(const Series& series, std::size_t period);

/// RMS of the series' last third over that of its first third, both about the whole series' mean
/// (channels summed, each divided by its peak |x|): ~1 for a motion that persists, far below 1 for a
/// decay, above for a growth. Needs no period (envelope_rate needs 8 of them). NaN when the first
/// third has zero RMS or the series has fewer than 3 samples.
double amplitude_ratio(const Series& series);

/// Rate at which the signal's amplitude changes between its ends, per sample (natural log): the log
/// RMS ratio of its last k whole periods to its first k, over the N - 1 - W samples between the two
/// windows' centres (W = k x period_samples, k = the most whole periods that fit in a third, at
/// least 1, the sample that completes a fractional W weighted by its share; RMS about each window's
/// own mean, which over whole periods is the level the motion oscillates about; channels summed, each
/// divided by its peak |x|).
/// Whole periods because a window that cuts a period short weighs its phases unevenly: the thirds
/// of e^{0.005 t} cos t over 4.8 periods have an RMS ratio of 1.041, those of e^{0.005 t} sin t
/// 1.172, where the growth between their centres is e^{0.1 x 2/3} = 1.069 (test_series). For a run
/// too short for envelope_rates (fewer than 8 periods).
/// NaN when the period is not positive, two windows do not fit (fewer than 2 periods) or either
/// window has zero RMS.
double ends_amplitude_rate(const Series& series, double period_samples);

/// How closely a record repeats itself one period on, scaled: the least-squares a with
/// x(t + P) ~ a x(t) + b over the whole record (b per channel: a mode about a level c repeats with
/// b = c (1 - a); channels over their peaks and summed, x(t + P) linearly interpolated for a period
/// between two samples) and the RMS of the rest over the RMS deviation of x(t + P). A single mode,
/// decaying or growing, e^{sigma t} sin(omega t), repeats so exactly (a = e^{sigma P}, difference 0);
/// a limit cycle with a = 1; two modes of unrelated frequencies (a torus, a beat) do not:
/// sin t + 0.5 sin(sqrt 2 t + 0.3) leaves more than 0.3 at the first tone's period and more than
/// 0.1 at every lag of 1-10 s (test_series). The reading takes the amplitude's rate as the motion's on a short run only when
/// it is one mode's (reading.hpp). NaN when P is not in (0, n/2] or nothing varies.
struct ScaledRepeat {
  double period = std::numeric_limits<double>::quiet_NaN();  ///< samples, as given
  double scale = std::numeric_limits<double>::quiet_NaN();   ///< a
  double difference = std::numeric_limits<double>::quiet_NaN();
};
ScaledRepeat scaled_repeat(const Series& series, double period_samples);

/// How much of the series a straight line through time explains: the largest share of a channel's
/// variance (R^2 of its least-squares line, each channel divided by its peak |x| first so that no
/// square overflows), and that channel. Small for a motion that returns near its past states (a
/// limit cycle, chaos, a decay about a rest point: Lorenz x over 100 time units at most 0.025, over
/// 20 at most 0.24 on 32 random starts, test_estimate_systems *Drift*), ~1 for one that keeps
/// growing (a rotation angle). A trend that settles is no drift: where the line through the second
/// half rises or falls less than kSettlingSlope x as fast as the one through the first half (or the
/// other way), the channel comes to rest, as a slow overdamped mode decays (e^{-0.1 t} over 40 s:
/// R^2 0.78, halves' slopes 0.14 apart); such channels count in settling_share, not in share.
struct Drift {
  double share = 0.0;  ///< largest R^2 over the channels whose trend keeps going
  std::size_t channel = 0;
  double settling_share = 0.0;  ///< largest R^2 over the channels whose trend settles
};
Drift linear_drift(const Series& series);
/// Above this share the estimator warns that the series drifts (and says so when it refuses one).
inline constexpr double kDriftShare = 0.5;
/// A trend whose second half's slope is below this fraction of its first half's settles.
inline constexpr double kSettlingSlope = 0.5;

/// A random walk: a channel whose steps x[t+1] - x[t] are white noise while the channel itself is
/// not (Box and Pierce's portmanteau test, Ljung-Box form Q = n (n + 2) sum_k rho_k^2 / (n - k) over
/// the centred steps' autocorrelations rho_k at lags k = 1..kWhiteStepLags, against the chi-square
/// point with that many degrees of freedom that a white sequence exceeds once in 1000). Such a channel
/// is integrated noise, x_t = x_{t-1} + e_t (or a relaxation so slow that its steps look so): its
/// variance grows as t, it returns near its past states only by chance, and the exponent of its
/// deterministic part x_{t+1} = x_t is 0, which no divergence curve measures (of 60 Gaussian random
/// walks of 10^3..10^5 samples, 8 read a stability before -- a growing oscillation, a limit cycle --:
/// bench/random_walk_readings.sh, docs/checks.md). A sampled motion never passes: its steps follow each other
/// smoothly (a flow's) or by its map (a map's steps correlate with each other through the map: white
/// samples make steps of lag-1 correlation -1/2). Required besides: the channel's variance at least
/// kWalkVarianceRatio x its steps' (the steps are small against where the walk has wandered), and the
/// steps' mean smaller than their spread (a ramp printed with few digits has steps of one value plus
/// rounding: that is a drift, linear_drift's case).
/// The figures are the channel's whose Q lies lowest against its point among the channels tested
/// (those that meet the variance and mean conditions); `tested` is false when none does.
struct WhiteSteps {
  bool found = false;            ///< that channel's Q below its point: a random walk
  bool tested = false;
  std::size_t channel = 0;
  double statistic = 0.0;        ///< its Ljung-Box Q
  double critical = 0.0;         ///< the chi-square 99.9 % point a random walk's stays below
  std::size_t lags = 0;          ///< lags 1..lags tested
  double variance_ratio = 0.0;   ///< var(x) / var(steps) of that channel
};
WhiteSteps white_steps(const Series& series);
/// Lags of the portmanteau test (fewer on a short series: at most a tenth of its steps).
inline constexpr std::size_t kWhiteStepLags = 20;
/// A channel whose variance is below this multiple of its steps' is not told from white noise.
inline constexpr double kWalkVarianceRatio = 10.0;

/// An angle printed modulo a turn (MBDyn's Euler angles in degrees wrap at +-180, its rotation
/// vectors at pi; a rotating blade's or hub's azimuth wraps every revolution): a step between two
/// samples of a whole turn, 360 or 2 pi within 10 %, that also spans at least half the channel's
/// range while the median step is below 1/20 of it (a smooth signal that jumps back by a turn;
/// maps, whose every step is large, are never taken for one). The first such step of any channel;
/// count = 0 when there is none. Its delay vectors straddle the jump, so the exponent is
/// meaningless: unwrap it, or analyse a relative angle or a rate.
struct WrappedAngle {
  std::size_t count = 0;    ///< wrapping steps in that channel
  std::size_t channel = 0;  ///< 0-based
  std::size_t sample = 0;   ///< the first: from sample - 1 to sample
  double jump = 0.0;        ///< its size, signed
  bool degrees = true;      ///< a turn of 360 (else 2 pi)
};
WrappedAngle wrapped_angle(const Series& series);

/// A motion persists when its amplitude_ratio lies strictly within (1/kPersistentAmplitude,
/// kPersistentAmplitude); NaN (no first-third RMS) does not. The one test the estimator's short-run
/// refusal and the space-time plot's stationarity check share.
inline constexpr double kPersistentAmplitude = 2.0;
inline bool persists(double amplitude_ratio) {
  return amplitude_ratio > 1.0 / kPersistentAmplitude && amplitude_ratio < kPersistentAmplitude;
}

/// `--from auto`: the series from the end of its transient (detect_transient with the default
/// options and the series' mean period); the rule applied is returned in `result` if given.
Series skip_transient(const Series& series, TransientResult* result = nullptr);

}  // namespace mlce
