#pragma once
// The whole automatic pipeline: mean period -> AMI delay -> FNN dimension -> Rosenstein curve ->
// fit, with every parameter automatic unless given.
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mlce/ami.hpp"
#include "mlce/fit.hpp"
#include "mlce/fnn.hpp"
#include "mlce/map_cycle.hpp"
#include "mlce/mean_period.hpp"
#include "mlce/modes.hpp"
#include "mlce/progress.hpp"
#include "mlce/recurrence.hpp"
#include "mlce/rosenstein.hpp"
#include "mlce/surrogate.hpp"
#include "mlce/transient.hpp"

namespace mlce {

/// Whether neighbours are moved along their own trajectories to the reference's phase
/// (RosensteinOptions::align_phase). automatic: for sampled flows (not MeanPeriodResult::map: a mean
/// period of kMinFlowPeriod samples or more and little power at periods below 4 samples) whose plain
/// curve grows into a saturation plateau (lambda > 0).
enum class PhaseAlignment { automatic, off, on };
/// When estimate_mlce runs the surrogate test (MlceOptions::surrogates_when).
enum class SurrogateWhen { never, where_chaos_is_read, always };
/// Whether a decay that carries white measurement noise is read from the noise-compensated curve
/// (DivergenceCurve::compensated_log_distance: ln of the pairs' mean square distance, each over its
/// own mean, less the noise's share, halved) instead of eq. 23's <ln d>. automatic: when eq. 23's
/// curve is flagged as held up by noise (its first step jumps: MlceResult::noise_level), the signal
/// decays (its last third's RMS at most 1/2 of its first's, or its envelope falling by more than
/// 1 % per mean period), the curve is not phase-aligned, and the third differences are white noise
/// in every channel (white_increment_noise, which also measures it) over the record where its noise
/// is steady, the floor a decay was cut at included (when dithered, the analysed series itself), or
/// else over the analysed series' last quarter. Noise of the neighbours' own samples holds <ln d> up where a
/// decay's separations shrink towards it: e^{-0.063 t} cos 2 pi t plus noise of 1 % of its start
/// read 0.44-0.49 of its rate on 8 noise seeds, compensated 0.96-1.05 (test_estimate_systems).
/// off: eq. 23's curve always.
enum class NoiseCompensation { automatic, off };
// kMinFlowPeriod and MeanPeriodResult::map live in mean_period.hpp (the AMI delay and the fit also
// treat a map apart): a series treated as a map gets no phase alignment.

/// With an automatic Theiler window, a motion that persists (transient.hpp: persists) must span at least this many of its own mean
/// periods (1 / mean frequency; eq. 19 before rounding): otherwise no point has a neighbour on
/// another pass of the orbit, and estimate_mlce refuses it.
inline constexpr double kMinMeanPeriods = 2.0;
/// An embedding window (m-1)*delay longer than this many mean periods is flagged (estimate_mlce):
/// a delay vector should describe one state, about a mean period of the motion or less.
inline constexpr double kMaxWindowPeriods = 2.0;
/// A curve averaged over fewer neighbour pairs than this is flagged: with the default 16 batches
/// (RosensteinOptions::batches) each batch mean then holds fewer than 10 pairs, so the batch means
/// are far from normal and the 95 % interval is not to be trusted (at 1 pair the interval is the
/// formal least-squares one and says nothing about the curve's own noise).
inline constexpr std::size_t kFewPairs = 160;

/// False nearest neighbours (an automatic m) that never fall below their threshold and stay at this
/// share or more at every m tried: the series unfolds into no low-dimensional deterministic motion,
/// and estimate_mlce flags lambda as unreliable (not on a decaying signal). Stochastic series stay
/// high (10^4 samples: white noise 0.179, AR(1) with coefficient 0.9 and 0.99 0.148 and 0.156, random
/// walks 0.155-0.42, which read "limit cycle" and "chaotic" before), a deterministic signal that FNN
/// does not quite unfold lower (Roessler z 0.063): `build/test_estimate_systems
/// --gtest_filter='*NeverUnfolds*'` prints them.
inline constexpr double kStochasticFnnShare = 0.12;

/// A map whose closest neighbour pairs' one-step stretch falls by this much or more per unit ln of
/// their starting distance (StretchByDistance::closest_half_slope) carries measurement noise at the
/// scale of those distances (estimate_mlce warns and sets MlceResult::noise_level). Noise alone gives
/// -1. `build/map_bands noise` (N = 10^4, three orbits each): clean maps -0.12 at most (logistic
/// r = 4 at m = 1, whose densest points, near 0 and 1, are also its most stretched; Henon, tent,
/// Lozi about 0); white noise of 0.1 % of the standard deviation, which reads logistic, Henon, tent,
/// sine, Lozi 4-9 % low, gives -0.55 .. -0.84 at the m FNN chooses; Ikeda x with it (0.6 % low)
/// -0.06 .. -0.11, with 1 % -0.59 .. -0.67.
inline constexpr double kMapNoiseStretchSlope = -0.25;

/// A flow whose state has fewer coordinates than this settles on fixed points and limit cycles only
/// (Poincare-Bendixson), where neighbours do not keep separating up to the attractor's scale:
/// estimate_mlce widens an automatic embedding whose curve does.
inline constexpr std::size_t kMinChaoticFlowDimensions = 3;

/// Why estimate_mlce used a larger m than false nearest neighbours chose.
enum class DimensionWidening {
  none,
  growth_in_a_decay,  ///< the chosen m read lambda > 0 while the signal decays to rest
  flow_in_a_plane,    ///< the state had fewer than kMinChaoticFlowDimensions coordinates, yet its curve saturates
};

struct MlceOptions {
  std::optional<std::size_t> delay;    ///< J; automatic: AMI first minimum
  std::optional<std::size_t> dim;      ///< m; automatic: FNN
  std::optional<std::size_t> theiler;  ///< automatic: mean period (eq. 19)
  /// Curve length in samples. Automatic: starts at max(8 T, 32) and doubles (up to a third of
  /// the embedded points) until the fit rule sees the curve's end (plateau, floor).
  std::optional<std::size_t> horizon;
  MeanPeriodOptions mean_period;
  AmiOptions ami;
  FnnOptions fnn;
  FitOptions fit;
  /// What repeats as a map's settled cycle (map_cycle.hpp); maps only (MeanPeriodResult::map).
  MapCycleOptions map_cycle;
  /// When the surrogate test of the divergence against linear noise runs (surrogate.hpp; a joint
  /// embedding of several channels takes multivariate surrogates). Default where_chaos_is_read: wherever the curve alone would read "chaotic" -- the
  /// one claim that linear noise through a lightly damped mode fakes (an AR(2) resonance read so on 6
  /// of 8 series, bench/surrogate_power) -- with `surrogates` as below: 19 surrogates of the series'
  /// first 4096 samples, 30 IAAFT passes each, curves of at most 2000 references, which keeps the
  /// test to about 0.09 s (Lorenz x: 26-43 standard deviations above its surrogates, AR(2) resonances
  /// and a noise-driven mode within 3). never: no test; always: on every estimate with a fit region, with
  /// `surrogates` as given (`mlce estimate --surrogates K`: K of the whole part analysed, 200 passes).
  SurrogateWhen surrogates_when = SurrogateWhen::where_chaos_is_read;
  SurrogateOptions surrogates{.count = 19, .iterations = 30, .max_samples = 4096, .max_references = 2000};
  /// Reference points of the curve, evenly strided; 0 = all. The default keeps the statistical
  /// error of the mean curve negligible while bounding the cost for very long series.
  std::size_t max_references = 20000;
  double eps = 0.0;
  PhaseAlignment phase_alignment = PhaseAlignment::automatic;
  /// How an aligned neighbour is read between samples (RosensteinOptions::Interpolation). linear by
  /// default: cubic removes the segment's error, which matters when a loop of the motion spans few
  /// samples (Lorenz x at dt = 0.05, ~13 samples per loop: 28 -> 32 of 32 within 5 %), but the
  /// fit rule reads Roessler x at dt = 0.1 about 2 % higher with it (README, "sampling").
  RosensteinOptions::Interpolation phase_interpolation = RosensteinOptions::Interpolation::linear;
  NoiseCompensation noise_compensation = NoiseCompensation::automatic;
  /// A motion that persists (transient.hpp: persists) and whose start does not recur
  /// (recurrence.hpp: its first windows find their nearest neighbours only among themselves) is
  /// analysed from where it does: the start is a transient, not the attractor, and everything
  /// (mean period, embedding, curve) is estimated again on the rest, with a warning. false = keep
  /// it (the CLI's --keep-start, and whenever the user gives --from).
  bool skip_nonrecurrent_start = true;
  RecurrenceOptions recurrence;
  /// Width A of uniform noise in [-A/2, A/2) added to every sample of every channel before
  /// anything else, in the channels' units; 0 = none. A quantised signal (coarse printed digits,
  /// ADC counts) repeats its points and its distances jump in steps of the quantum; dithering by one
  /// quantum makes them continuous, at the price of noise of that size. Deterministic: the noise
  /// comes from splitmix64 seeded with dither_seed (a rerun gives the same lambda).
  double dither = 0.0;
  std::uint64_t dither_seed = 1;
  /// A series that decays into a noise/underflow floor below this fraction of its largest RMS, or
  /// into white measurement noise below 0.1 of it (its last quarter or that quarter's increments
  /// white), is analysed only up to the floor (detect_floor;
  /// paper 001 Fig. 6: otherwise the estimate drifts with the run length). 0 = never cut.
  double floor_ratio = 1e-6;
  /// When the series is a window cut from a longer record (the CLI's --from / --to): each channel's
  /// largest deviation from its mean over that record (peak_deviations, series.hpp), one per
  /// channel. A window whose every channel's RMS deviation lies below floor_ratio of it, and whose
  /// amplitude does not itself decay, holds only the floor of a decay that ended before the window
  /// (solver tolerance and rounding), which the whole record's analysis would have cut off: flagged
  /// (MlceResult::in_decay_floor), since lambda then measures that residue (the ad-hoc run of
  /// Hammond's isotropic rotor at 200 rpm from 20 s on, about 1e-10 of its start, read +0.3..+0.9
  /// 1/s, "chaotic"). A window that ends in such a floor is cut at it, the floor judged against this
  /// scale (detect_floor; it must hold its level), as the whole record's analysis cuts it (the same
  /// run from 10 to 60 s: -1.179 1/s, Floquet -1.1828, where the floor read with the decay gave
  /// -0.09, "lightly damped"); with less than two mean periods of decay above it, the window is read
  /// as the floor. Empty: the series is the whole record.
  std::vector<double> record_deviation;
  /// The record's damped modes (MlceResult::record_modes), identified where the divergence curve
  /// cannot tell the stability, on the analysed samples (not dithered): the identification's options
  /// (its progress is this struct's). Their cost is interval_replicates identifications of a pencil
  /// of up to max_columns columns, which a noisy record fills (0.35 s on a fuzzer's input of 500
  /// samples, where the curve itself took 0.04 s); fewer replicates give a rougher interval, 0 none,
  /// and without an interval the modes read nothing. nullopt: never identified.
  std::optional<ModalOptions> record_modes = ModalOptions{};
  ProgressCallback progress;
};

/// The check of MlceOptions::record_deviation against a series of `channels` channels: empty, or one
/// value per channel; else OptionError.
void validate_record_deviation(const MlceOptions& options, std::size_t channels);

struct MlceResult {
  double lambda = 0.0;             ///< per time unit (1/s for MBDyn); natural log
  double lambda_per_sample = 0.0;  ///< per sample
  double ci95_low = 0.0, ci95_high = 0.0;  ///< per time unit
  double lyapunov_time = 0.0;      ///< 1/lambda in time units when lambda > 0, else +inf
  double r2 = 0.0;
  std::size_t delay = 1, dim = 1, theiler = 1, horizon = 0;
  std::size_t n_points = 0;
  double dt = 1.0;
  std::string time_unit;
  MeanPeriodResult mean_period;
  std::optional<AmiResult> ami;  ///< when the delay was automatic
  std::optional<FnnResult> fnn;  ///< when the dimension was automatic
  /// The m FNN chose, when a larger m was used instead (estimate_mlce's widening; fnn->dim is that
  /// m too), and why; nullopt otherwise.
  std::optional<std::size_t> dim_widened_from;
  DimensionWidening dim_widened_because = DimensionWidening::none;
  DivergenceCurve curve;  ///< the curve fitted (phase-aligned when curve.phase_aligned)
  FitResult fit;
  /// The options the fit rule read the curve with (the fit period, the signal's own rates, whether a
  /// floor was cut): a second curve of the same analysed samples (Kantz's, kantz.hpp) is fitted alike.
  FitOptions fit_options;
  /// lambda of the plain curve when the reported one comes from the phase-aligned curve; NaN otherwise
  double unaligned_lambda = std::numeric_limits<double>::quiet_NaN();
  /// lambda of the plain curve (eq. 23) when the reported one comes from the noise-compensated
  /// curve (NoiseCompensation); NaN otherwise
  double uncompensated_lambda = std::numeric_limits<double>::quiet_NaN();
  /// the reported curve is the noise-compensated one (ln <d^2> / 2 less the noise's share)
  bool noise_compensated = false;
  /// the plain curve's mean_log_distance when the reported curve is phase-aligned or
  /// noise-compensated; empty otherwise
  std::vector<double> plain_curve;
  /// The analysed signal's own amplitude change, per sample (envelope_rate; NaN when too short):
  /// what tells a decay to rest from neighbours converging onto a motion that persists.
  double envelope_rate = std::numeric_limits<double>::quiet_NaN();
  /// envelope_rate's formal standard error, per sample (EnvelopeRates::whole_stderr)
  double envelope_rate_stderr = std::numeric_limits<double>::quiet_NaN();
  /// The same over the signal's second half: whether it still grows at its end, as a linear
  /// instability's response does and a growth that settles on a limit cycle does not.
  double end_envelope_rate = std::numeric_limits<double>::quiet_NaN();
  /// The amplitude's change between the run's first and last whole periods, per sample
  /// (ends_amplitude_rate, transient.hpp): the reading's rate on a run too short for envelope_rate.
  double ends_amplitude_rate = std::numeric_limits<double>::quiet_NaN();
  /// On that short run, how closely the record repeats itself one period on, scaled (scaled_repeat,
  /// transient.hpp), over the same period: whether its amplitude's rate is one mode's.
  ScaledRepeat short_run_repeat;
  /// RMS of the analysed signal's last third over its first third's (amplitude_ratio, transient.hpp):
  /// ~1 for a motion that persists; NaN when the first third has zero RMS.
  double amplitude_ratio = std::numeric_limits<double>::quiet_NaN();
  /// How closely the analysed signal's last third repeats itself one period on (end_repeat,
  /// mean_period.hpp): a motion that ends periodic is no chaotic attractor (reading.hpp).
  EndRepeat end_repeat;
  /// A map's series (MeanPeriodResult::map) that ends repeating a cycle (map_cycle.hpp): its
  /// nearest neighbours are the cycle's other points, which never separate. When the record shows
  /// the approach to the cycle (MapCycle::approach_measured), lambda, lambda_per_sample, ci95 and r2
  /// are the approach's, the cycle's exponent, and curve_lambda keeps the curve's slope; otherwise
  /// they are the curve's, which measures no divergence (the reading says so). period 0: not found
  /// (a flow, or a map that does not settle on a cycle).
  MapCycle map_cycle;
  /// A steady carrier over a growing mode (found only where the curve never separates for good:
  /// CurveEnd::bounded or flat): one undamped oscillation holds most of the record, and beneath it a
  /// mode grows that the neighbours, which the carrier keeps close, never show. A rotating part's
  /// absolute coordinate carries the rotation so: blade 2's hinge node:12:y of the bundled growing
  /// MBDyn run read "neutral, limit cycle" (lambda 0.459, bounded curve) over a hub growing at
  /// +0.3 1/s. Judged on the record's damped modes (identify_modes, modes.hpp), the reading's
  /// evidence of the growth (reading.hpp: unstable).
  struct SteadyCarrier {
    /// A carrier holds at least this share of the record's sum of squares.
    static constexpr double kMinShare = 0.9;
    double frequency = 0.0;         ///< the carrier's, cycles per time unit
    double share = 0.0;             ///< its share of the record's sum of squares
    double growth_rate = 0.0;       ///< the growing mode's sigma, per time unit
    double growth_frequency = 0.0;  ///< cycles per time unit
    double growth_peak_share = 0.0;  ///< its largest share over the record's quarters (Mode::peak_share)
  };
  std::optional<SteadyCarrier> carrier;
  /// The record's damped modes (identify_modes, modes.hpp, with lambda's 95 % interval), identified on
  /// the part analysed where the divergence curve cannot tell the motion's stability: a run of fewer
  /// than kFewPeriods mean periods (too few returns for neighbours from other passes: the curve swings
  /// with the pairs' phase), or where the curve's own reading (default ReadingOptions) is one the modes
  /// may replace (curve_cannot_tell, reading.hpp: undetermined, as lambda > 0 while the amplitude
  /// decays — two decaying modes beating read +0.215 —, or light damping, a slow growth). Not on a map,
  /// a window in a decay's floor, or a series a warning calls unreliable. The reading (reading.hpp)
  /// reads the stability from them where the curve's own reading is undetermined or neutral and they
  /// describe the record closely (RecordModes::describes_record); lambda stays the curve's slope.
  struct RecordModes {
    static constexpr double kFewPeriods = 8.0;
    /// The modes describe the record closely: what they leave is at most this share of it (RMS)...
    static constexpr double kCloseResidual = 1e-2;
    double lambda = 0.0;     ///< the least damped mode's sigma (ModalResult::lambda), per time unit
    double ci95_low = std::numeric_limits<double>::quiet_NaN();   ///< its 95 % interval; NaN: none
    double ci95_high = std::numeric_limits<double>::quiet_NaN();
    double frequency = 0.0;  ///< that mode's, cycles per time unit
    double share = 0.0;      ///< that mode's share of the record (Mode::share; 0 when read from a half)
    std::size_t count = 0;   ///< modes, a pair once, offsets left out
    double residual = 0.0;   ///< RMS of what the modes leave over the record's (ModalResult::residual)
    bool noise_left = false;  ///< ... or it is white measurement noise (ModalResult::noise_left)
    bool linear = false;      ///< ModalResult::linear
    bool halves_agree = true;  ///< the record's halves read the same rate (ModalResult::halves_agree)
    bool leading_part = false;  ///< a growth read over a leading part only (ModalResult::leading_part)
    bool few_periods = false;  ///< identified because the run spans fewer than kFewPeriods mean periods
    std::string why;  ///< why they were identified: "a run of 2.71 mean periods", "lambda > 0 while ..."
    /// A sum of modes to the record's end, closely, with an interval, whose halves agree: the reading's
    /// evidence.
    bool describes_record() const {
      return linear && !leading_part && halves_agree && (residual <= kCloseResidual || noise_left) &&
             std::isfinite(ci95_low) && std::isfinite(ci95_high);
    }
  };
  std::optional<RecordModes> record_modes;
  /// The surrogate test (MlceOptions::surrogates_when, surrogates), where it ran: the reading
  /// (reading.hpp) claims chaos only when it distinguishes the divergence from linear noise.
  std::optional<SurrogateTest> surrogates;
  /// The divergence curve's fitted slope per time unit when lambda is a map cycle's approach; NaN
  /// otherwise.
  double curve_lambda = std::numeric_limits<double>::quiet_NaN();
  /// Why lambda does not measure the motion's divergence, when one of the warnings says so (the
  /// first such): a series that drifts, an angle that wraps, an embedding window of several mean
  /// periods, a curve that reaches its plateau within one embedding window (uncorrelated noise),
  /// fewer than two mean periods of a motion that persists (estimated only under a given window),
  /// a resolution as coarse as the neighbour distances (DivergenceCurve::coarse_resolution) unless
  /// the curve falls on a signal that decays. Empty otherwise. The reading (reading.hpp) is then undetermined, except for a window in the
  /// floor of a decay (floor_window_ratio): stable, the motion decayed to rest before the window.
  std::string unreliable;
  /// When the series is a window cut from a record (MlceOptions::record_deviation): the largest over
  /// the channels of the window's RMS deviation over the record's largest deviation; NaN otherwise.
  /// Below MlceOptions::floor_ratio, with an amplitude that does not decay within the window (or with
  /// less than two mean periods of it above the record's floor, or wholly within 10x of that floor:
  /// Floor::whole), the window lies in the floor of a decay that ended before it (in_decay_floor),
  /// and `unreliable` says so.
  double floor_window_ratio = std::numeric_limits<double>::quiet_NaN();
  bool in_decay_floor = false;
  /// When the curve's first step flags measurement noise (kNoiseJump): an upper estimate of its
  /// standard deviation, white noise assumed, in units of the signal's standard deviation; when a
  /// map's closest pairs flag it (kMapNoiseStretchSlope): the same reading of their distance one
  /// step on, within a factor 2 (0.6-1.2 x the noise added in bench/map_bands noise); when the
  /// curve is noise-compensated, the noise measured from the increments (RMS over the channels);
  /// NaN when neither.
  double noise_level = std::numeric_limits<double>::quiet_NaN();
  /// When the curve is noise-compensated: the relative standard error of the noise's measured mean
  /// square (sqrt(4.62 / k), k third differences), and lambda's standard error from it, per time unit
  /// (the first-order change of the fitted slope, DivergenceCurve::compensated_noise_share); ci95 includes
  /// it. NaN otherwise.
  double noise_variance_error = std::numeric_limits<double>::quiet_NaN();
  double noise_lambda_stderr = std::numeric_limits<double>::quiet_NaN();
  /// Samples left out at the start because they do not recur (skip_nonrecurrent_start); the
  /// result describes the rest (n_points counts it, the curve starts there).
  std::size_t skipped_start = 0;
  RecurrenceResult recurrence;  ///< the test's windows (empty when it was not run)
  /// The level's drift beneath the curve's neighbour pairs (neighbour_drift, recurrence.hpp).
  NeighbourDrift neighbour_drift;
  std::vector<std::string> warnings;  ///< every stage's warnings, in pipeline order
};

MlceResult estimate_mlce(const Series& series, const MlceOptions& options);

/// The estimator's embedding, for the commands that need it without an estimate (stsp, fnn):
/// Theiler window = options.theiler or `mean_period.mean_period` (eq. 20 with eq. 19); delay =
/// options.delay or the first AMI minimum (eqs. 15-17; a map's only within its rule period, else 1:
/// AmiOptions::mean_period and ::map, set from `mean_period`); dimension = options.dim or FNN with
/// that window. The AMI/FNN results (and their warnings) are kept when computed.
struct Embedding {
  std::size_t delay = 1, dim = 1, theiler = 1;
  std::optional<AmiResult> ami;
  std::optional<FnnResult> fnn;
};
Embedding choose_embedding(const Series& series, const MlceOptions& options, const MeanPeriodResult& mean_period);

}  // namespace mlce
