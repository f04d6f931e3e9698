#pragma once
// Linear modal identification of a record: its damped modes (decay rate, frequency, damping ratio,
// share of the motion) by the matrix pencil method (Y. Hua, T. K. Sarkar, IEEE Trans. ASSP 38(5),
// 814-824, 1990; the shift-invariant subspace form of S. Y. Kung et al. 1983, as in ERA), with one set
// of poles shared by every channel.
//
// Why beside Rosenstein's curve: a linearised motion (paper 001 sections 4-5: Hammond's model about its
// equilibrium, the ground-resonance decays and growths an analyst first meets) is a sum of damped modes
// x(t) = c + sum_k a_k e^{sigma_k t} cos(omega_k t + phi_k), and its MLCE is max sigma_k, the
// eigenvalues' largest real part of the linearised problem (paper 000 section 2: for a constant Jacobian
// the Lyapunov exponents are the real parts of its eigenvalues). A record of a few periods, or of two modes
// beating (README's known limitations: +0.215 from Rosenstein for e^{-0.02t} cos 2t + e^{-0.05t} cos 2.4t),
// holds too few passes for neighbours, yet is fitted exactly by its modes. Where the motion is not a
// sum of few modes (a limit cycle's harmonics still are; chaos is not) the fit says so by what it leaves
// (`residual`), and Rosenstein's estimate is the one to read.
//
// The method, in the record's own sampling (dt, time unit):
//  1. Each channel less its mean, in units of its RMS deviation (every channel weighs alike; the scale of
//     the data never enters: x and 1e200 x give the same poles).
//  2. Hankel matrix H, rows k = 0, r, 2r, ... (all k when they fit in max_rows), columns x(k + jD),
//     j = 0..L-1, the channels' rows stacked: a mode is a column pattern z^{jD} whatever k or channel,
//     whatever a row's weight (RowWeighting).
//     D (`stride`) puts samples_per_mean_period columns in the spectrum's mean period (eq. 19), and fewer
//     when power above the strided Nyquist frequency would fold (alias_share): poles of a finely sampled
//     record are otherwise crowded near z = 1, where their rates are ill-conditioned.
//  3. H's singular values s_1 >= ... >= s_L (Householder QR, then the SVD of R -- BDCSVD, or JacobiSVD where R
//     is rank-deficient to rounding (modes.cpp: right_singular) -- never H^T H, whose squared
//     condition would hide modes below 1e-8 of the strongest). The order n counts the singular values above
//     max(noise_factor x the median of the lower half -- white noise's floor, nearly flat there --,
//     rank_tolerance x s_1), at most max_order; `--order N` overrides.
//  4. Poles: the right singular vectors V_n, shifted by one column, V_2 = V_1 A (least squares), the
//     eigenvalues mu of A are z^D; s = ln(mu) / (D dt), principal branch: frequencies are read modulo the
//     strided sampling rate 1 / (D dt) (aliasing leaves the rates exact).
//  5. Amplitudes: least squares of the record on e^{sigma (t - t_ref)} cos(omega t), ... sin(omega t) (t_ref
//     the end for a growing mode, the start for a decaying one: no overflow at any rate or length), on at
//     most max_fit_samples evenly strided samples. A mode's share is its part's sum of squares over
//     the record's (less its mean); `residual` is sqrt(sum of squares left / record's), 0 for an exact fit.
//  6. lambda = the largest sigma among the modes holding min_share of a quarter of the record, leaving out
//     offsets: real poles that change by less than offset_change over the record (what is left of the
//     mean removal and of a static equilibrium: not motion).
//  7. Each half of a record the modes describe identified on its own (same D): its own lambda. The second
//     half's replaces the whole's when larger by more than second_half_margin (a motion ends with its
//     least damped mode; a large, fast or nonlinear start hides it from the whole record's strongest
//     modes: Hammond's hub with nonlinear lag dampers, whose start's modes decay at -2.5 .. -3.9 1/s, reads
//     -2.48 over the whole run, -3.16 over its first half, -0.3416 over its second, the linearisation's
//     -0.3413); halves that differ beyond halves_tolerance are named in the reading (a rate that changes
//     with the amplitude, a nonlinear damper, or a mode that emerges late).
//  8. lambda's 95 % interval (interval_replicates > 0): the stretch lambda was read from (the whole record, or
//     its second half when step 7 took it there) rebuilt as its fitted modes plus Gaussian noise of the
//     spectrum the fit left there (each channel's residual periodogram smoothed over 33 bins, drawn
//     independently per channel), identified again as the stretch was (same stride, same order rule);
//     lambda +- 1.96 x the replicates' standard deviation (a parametric bootstrap, normal interval). It
//     measures what noise like the residual does to lambda (measurement noise, the integrator's error, a
//     small misfit); it says nothing of a model the modes miss (no interval where `linear` is false) or of a
//     mode the record does not yet show. bench/modal_accuracy's `coverage` counts how often it holds the true
//     rate (37-39 of 40 at 1-3 % white noise, 35 of 38 at 3 % red noise, 33 of 40 at 10 % white noise).
//  9. A growth the modes do not describe to the record's end (not `linear`, its second half no sum of modes, or
//     its halves' rates differing with the second's the smaller: a ground resonance saturating into a limit
//     cycle, van der Pol released near its origin) is read over the record's leading half, quarter or
//     eighth, the longest whose halves both read one growth (within halves_tolerance): the motion is linear
//     while it is small, and the linearisation's rate is read there (`leading_part`). A growth its modes
//     describe to the end (one that emerges late under a decay, or a linear one) keeps the whole record's.
// A record that decays into a floor (rounding, the solver's tolerance, white measurement noise) is
// analysed up to it (detect_floor, as the estimate): the floor is no motion of the modes.
// Units: sigma and lambda per time unit (1/s for MBDyn output; per sample without a time axis), frequency
// in cycles per time unit (Hz), natural log. Damping ratio zeta = -sigma / |s|.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mlce/progress.hpp"
#include "mlce/series.hpp"
#include "mlce/stability.hpp"

namespace mlce {

/// How the Hankel matrix's rows weigh (step 2): `energy`, as the record gives them (least squares on the
/// samples: the most accurate in white noise, bench/modal_accuracy: rms error 0.31 % against 0.56 % at 3 %
/// noise); `amplitude`, each row scaled to unit norm down to a noise floor (a decay over many decades --
/// simulation output written with relative precision -- weighs its late, least damped part as much as its
/// start); `automatic`, amplitude when the rows' norms span more than ModalOptions::amplitude_range.
enum class RowWeighting { automatic, energy, amplitude };

struct ModalOptions {
  /// Model order n (poles, a complex pair counting 2); nullopt = automatic (step 3 above).
  std::optional<std::size_t> order;
  std::size_t max_order = 40;          ///< the automatic order's cap (and --order's)
  std::size_t max_columns = 160;       ///< L at most (pencil parameter); L = min(this, strided samples / 3)
  std::size_t max_rows = 6000;         ///< Hankel rows over all channels at most (rows strided by r)
  RowWeighting weighting = RowWeighting::automatic;
  /// The largest row norm over their 10th percentile above which `automatic` weighs by amplitude: two
  /// decades (a noisy record of steady amplitude spans a few times; Hammond's release with nonlinear dampers
  /// seven decades).
  double amplitude_range = 100.0;
  /// Strided samples per mean period (D = max(1, floor(mean period / this))); 0 = no striding (D = 1).
  /// 20: components up to 10 x the mean frequency are below the strided Nyquist frequency.
  std::size_t samples_per_mean_period = 20;
  /// ... and no more than lets the strided Nyquist frequency stand 1.25 x above the band edge below which
  /// all but this share of the power lies (band_edge_frequency): what lies above it folds.
  double alias_share = 1e-3;
  /// Singular values above noise_factor x the median of the lower half count as signal. White noise's
  /// singular values of an M x L Hankel matrix lie within (1 +- sqrt(L / M)) of their median; 4 leaves
  /// room for a coloured floor.
  double noise_factor = 4.0;
  /// Singular values below rank_tolerance x s_1 never count (the rounding of a record written with 6-7
  /// digits sits near 1e-7 of it; of an exact double record near 1e-15).
  double rank_tolerance = 1e-10;
  std::size_t max_fit_samples = 8192;  ///< samples of the amplitude fit at most, evenly strided
  /// A mode setting lambda holds at least this share of a quarter of the record (peak_share): 5 %, about a
  /// fifth of the motion's amplitude there. A weaker mode that grows faster is named in a warning, not taken:
  /// an over-fitted record puts small modes beside a strong one to follow a rate that changes (the bundled
  /// growing MBDyn run's lag, whose growth quickens as its amplitude passes 0.4 rad: 0.298 1/s and,
  /// holding 0.5 % of a quarter, 0.91).
  double min_share = 0.05;
  /// Weaker modes down to this peak_share that grow faster than lambda are named in a warning.
  double warn_share = 1e-3;
  /// A real pole whose e^{sigma t} changes by less than this (relative) over the record is an offset.
  double offset_change = 0.1;
  /// The fit describes the record (the reading's "linear") when residual <= max_residual, or when what it
  /// leaves is measurement noise: residual <= max_noise_residual and the lag-one autocorrelation of what it
  /// leaves, on the fit's samples, <= max_residual_correlation (white noise ~0; the residual of a motion the
  /// modes miss, a smooth signal, near 1: Lorenz x's 0.9 and more).
  double max_residual = 0.05;
  double max_noise_residual = 0.3;
  double max_residual_correlation = 0.3;
  /// The halves' lambdas agree within max(this x the larger magnitude, the neutral band).
  double halves_tolerance = 0.2;
  /// The second half's lambda replaces the whole record's when larger by more than this share of its
  /// magnitude and a tenth of the neutral band (step 7).
  double second_half_margin = 0.01;
  /// |sigma| x the mode's period within this reads neutral (ReadingOptions::neutral_per_period's band).
  double neutral_per_period = 0.01;
  bool check_halves = true;
  /// Step 9: a growth no sum of modes to its end is read over its leading part (needs check_halves).
  bool read_leading_growth = true;
  /// A record that decays into a floor is analysed up to it (detect_floor, transient.hpp; as
  /// MlceOptions::floor_ratio and record_deviation): below floor_ratio of its largest RMS (rounding, the
  /// solver's tolerance) or into white noise below 0.1 of it. 0 = never cut.
  double floor_ratio = 1e-6;
  std::vector<double> record_deviation;
  /// Replicates of step 8's interval (0 = no interval). 100: their standard deviation within ~7 %; each
  /// costs one identification and one inverse FFT per channel, run on all cores.
  std::size_t interval_replicates = 100;
  std::uint64_t interval_seed = 1;  ///< the replicates' noise: the same interval on every run
  /// Called with "lambda's interval: k of N replicates" every tenth replicate (from one thread at a time).
  ProgressCallback progress;
  void validate() const;
};

struct Mode {
  double sigma = 0.0;        ///< decay rate (real part of s), per time unit
  double frequency = 0.0;    ///< cycles per time unit (|omega| / 2 pi), 0 for a real pole
  double damping_ratio = 0.0;  ///< -sigma / |s| (1 for a real decaying pole, -1 growing; 0 undamped)
  double share = 0.0;        ///< the mode's sum of squares over the record's (less its mean), all channels
  /// The largest share over the record's four quarters (the mode's sum of squares there over the
  /// record's there, each about its mean), counting only quarters where the mode's RMS is 3x what the fit
  /// leaves there: a growing mode holds little of a record that starts with a larger decay, and most of
  /// its end; a pole fitted to a quiet quarter's floor no more than that floor. A mode sets lambda when
  /// this reaches ModalOptions::min_share.
  double peak_share = 0.0;
  bool offset = false;       ///< a real pole that hardly changes over the record (step 6)
  bool nyquist = false;      ///< at the strided Nyquist frequency (a negative real mu): its frequency is ambiguous
  /// The mode's part of channel c: e^{sigma (t - reference_time)} (cos_coefficient[c] cos(2 pi f t) +
  /// sin_coefficient[c] sin(2 pi f t)), t from the record's first sample, in the channel's units
  /// (reference_time: the record's end for a growing mode, its start otherwise).
  double reference_time = 0.0;
  std::vector<double> cos_coefficient, sin_coefficient;
};

struct ModalResult {
  std::vector<Mode> modes;     ///< largest share first; a complex pair once (frequency >= 0)
  std::size_t order = 0;       ///< n, poles (a pair counts 2)
  bool order_automatic = true;
  bool order_capped = false;   ///< more singular values above the floor than max_order
  /// The Hankel matrix's R had a diagonal entry below 1e-10 of its largest (fewer modes than columns to
  /// rounding: a noiseless record of few modes, an exactly repeating one); its SVD was then one-sided
  /// Jacobi, BDCSVD otherwise (step 3).
  bool rank_deficient = false;
  std::vector<double> singular_values;  ///< of the Hankel matrix, relative to s_1
  double noise_floor = 0.0;    ///< the median of the lower half, relative to s_1
  std::size_t stride = 1;      ///< D, samples
  std::size_t columns = 0;     ///< L
  std::size_t rows = 0;        ///< Hankel rows used (all channels)
  double residual = 0.0;       ///< sqrt(sum of squares left / record's), all channels
  /// Lag-one autocorrelation of what the fit leaves, on the fit's samples: ~0 white noise, ~1 motion.
  double residual_correlation = 0.0;
  bool noise_left = false;     ///< the residual is measurement noise (ModalOptions::max_noise_residual)
  bool map = false;            ///< mean period (eq. 19) under kMinFlowPeriod samples: a map, no reading
  std::vector<double> channel_residual;
  /// The largest sigma among the modes that hold min_share and are no offset (per time unit, per sample);
  /// nullopt when no mode does.
  std::optional<double> lambda, lambda_per_sample;
  std::optional<std::size_t> lambda_mode;  ///< its index in modes (empty when lambda_from_second_half)
  /// lambda's 95 % interval (step 8: lambda +- 1.96 lambda_spread); nullopt without lambda, without replicates,
  /// or when more than 2.5 % of them find no mode holding min_share (warned).
  std::optional<double> lambda_low, lambda_high;
  double lambda_spread = 0.0;             ///< the replicates' standard deviation (per time unit)
  std::size_t interval_replicates = 0;    ///< replicates run (0 = none)
  std::size_t replicates_without_lambda = 0;
  /// Each half's own lambda (step 7), when its modes describe it (residual <= max_residual) and it spans two
  /// periods of that mode (one e-fold of a real one).
  std::optional<double> first_half_lambda, second_half_lambda;
  /// The second half's lambda exceeds the whole record's by more than second_half_margin and is taken: the
  /// least damped mode emerges late (lambda_mode is then empty, no mode of `modes` being it;
  /// lambda_mode_frequency is its frequency).
  bool lambda_from_second_half = false;
  double lambda_mode_frequency = 0.0;  ///< cycles per time unit
  /// The halves' lambdas within max(halves_tolerance x the larger magnitude, the neutral band).
  bool halves_agree = true;
  /// Step 9: the growth was read over the record's leading half, quarter or eighth (n_points samples), the whole
  /// record being no sum of modes to its end (warned, with the whole record's lambda).
  bool leading_part = false;
  /// The record is a sum of `modes`: residual <= max_residual, or what is left is white noise (noise_left);
  /// never on a map.
  bool linear = false;
  /// "stable, decaying modes", "unstable, growing mode", "neutral, undamped mode", or "undetermined: ...".
  std::string reading;
  Stability stability = Stability::undetermined;  ///< the reading's first word, for scripts and sweeps
  double dt = 1.0;
  std::string time_unit;
  std::size_t n_points = 0;    ///< samples analysed (from the first; up to the floor when one was cut)
  std::size_t floor_start = 0; ///< first sample of the floor cut off; 0 = none
  std::vector<double> channel_mean;  ///< each channel's mean, which the modes' parts are added to
  std::vector<std::string> warnings;
};

/// Throws InputError on what validate_series refuses (channels of unequal length, a bad dt, a non-finite
/// sample, a constant channel), a series too short for the pencil (fewer than 3 x 4 strided samples) or one
/// that lies within a decay's floor; OptionError on bad options.
ModalResult identify_modes(const Series& series, const ModalOptions& options = {});

/// The record as the identified modes give it: channel c at samples 0..n_points-1, the channel's mean plus
/// every mode's part (offsets included), in the channel's units.
std::vector<std::vector<double>> modal_reconstruction(const ModalResult& result);

}  // namespace mlce
