#pragma once
// What an estimated MLCE says about the motion, in the terms of paper 001 sec. 3 (the paragraph
// after eq. 9): all exponents negative, the solution is exponentially stable; one positive, it is
// unstable or on a chaotic attractor; the largest zero, a limit cycle (several zero: a torus).
//
// The rule (read_stability), deterministic, on the estimate's own numbers:
//  - Rates are compared per mean period T = 1 / mean frequency of the spectrum (eq. 19, the
//    unclamped period, in the series' time unit): lambda T is the log change of a perturbation over
//    one oscillation, a scale-free number for a flow, a map or a rotor alike.
//  - Stability from the 95 % interval against a neutral band |lambda T| <= neutral_per_period:
//    stable when the whole interval lies below -band, unstable when it lies above +band, neutral
//    otherwise (the interval reaches into the band: zero is not excluded at the estimate's own
//    precision).
//  - The signal's own amplitude (AmplitudeTrend) tells a growth from chaos and a decay from a
//    contraction onto a persisting motion: it grows when its last third's RMS is at least
//    kPersistentAmplitude x its first third's or its envelope rate (on a run too short for its
//    windows, the change between its first and last whole periods) at least persist_share x lambda
//    (lambda > 0); it decays in the mirror case, and also where it falls beyond the band against
//    lambda > 0, when the fall is the signal's (its envelope line 4 standard errors below zero, or
//    the last third's RMS at most 1/sqrt 2 of the first's: a chaotic amplitude wanders less than
//    that, bench/chaos_readings.sh); it is steady when neither and the rate is below
//    steady_share x |lambda| (or below the band); otherwise it changes. Unstable + grows: a growing
//    oscillation (an instability such as ground resonance); unstable + steady: chaos, when the curve
//    comes within chaos_scale_margin of the attractor scale (else diverging: a growth beneath a steady
//    carrier, as a rotating part's absolute coordinates, is not told from chaos), and when the
//    motion does not end periodic (else a limit cycle: chaos never repeats itself; periodic_end); unstable +
//    changes: diverging, growth and chaos not told apart. A curve that falls while the amplitude is
//    steady measures the neighbours converging onto a limit cycle, whose largest exponent is 0
//    (paper 001 Fig. 4): neutral.
//  - Neutral while the amplitude decays is light damping, unless the decay stops: the second half's
//    envelope rate at most 0.1 of the run's and the last third repeating itself (periodic_end), a
//    limit cycle the motion decayed onto.
//  - A window cut from a record after its decay ended (MlceResult::in_decay_floor) is stable: the
//    motion decayed to rest before it, and lambda measures the solver's residue.
//  - A curve the fit rule found bounded or flat (the neighbours never separate to the attractor
//    scale) on a motion that does not decay is a limit cycle or torus: neutral, whatever residual
//    slope was fitted. Except on a run of fewer than 8 mean periods that is one mode (it repeats
//    itself one period on, scaled: ScaledRepeat::difference below 0.1): there the slope is the
//    residue of the curve's swing, and the amplitude's change between the first and last whole
//    periods (MlceResult::ends_amplitude_rate) beyond the band decides: stable when it decays,
//    unstable (a growing oscillation) when it grows.
//  - lambda > 0 on a steady amplitude over fewer than 8 mean periods is undetermined, not chaos:
//    too few returns to show an attractor, and a torus over a few periods reads so.
//  - A curve held level by measurement noise (flagged, MlceResult::noise_level, on a curve that
//    grows to no plateau) cannot show a decay slower than the noise: when the amplitude decays
//    and the interval does not already say stable, the motion, itself a perturbation of its
//    equilibrium, dies out: stable. Not when the estimator compensated the curve for the noise
//    (MlceResult::noise_compensated): lambda is then the decay's rate, read as any other.
//  - With the surrogate test run (MlceResult::surrogates, surrogate.hpp), lambda > 0 on a steady
//    amplitude is undetermined unless the test tells the divergence from linear noise's.
//  - A map settled on a cycle (MlceResult::map_cycle, map_cycle.hpp) is a periodic orbit without a
//    neutral direction: with its approach in the record, lambda is the approach's rate and the
//    interval decides (stable below the band, neutral within it); without it the cycle holds through
//    the record's rounding, so it is no unstable one, and a map's cycle is neutral only at isolated
//    parameters: stable, its rate unmeasured.
//  - Undetermined when a warning says lambda does not measure the motion's divergence
//    (MlceResult::unreliable: a drifting series, a wrapping angle, an embedding window of several
//    mean periods, a plateau within one embedding window as uncorrelated noise gives, a resolution
//    as coarse as the neighbour distances on a curve that does not fall with a decay), when
//    lambda > 0 while the amplitude decays, or lambda < 0 while it grows (or ends larger than it began). Measurement noise flagged by the curve's first step is named in the summary (it
//    biases lambda, it does not make a clear sign unclear).
//  - Where the curve cannot tell, the record's damped modes (MlceResult::record_modes: identified on a
//    run of fewer than 8 mean periods, or where lambda and the amplitude disagree in sign) read it:
//    when they describe the record (RecordModes::describes_record) and their rate's 95 % interval per
//    mean period lies wholly below, above or within the band, stable, unstable (growing oscillation)
//    or neutral (limit cycle) replaces a curve's reading that is undetermined, neutral while the
//    amplitude decays or grows (curve_cannot_tell), or of another stability on a run of fewer than 8
//    mean periods (the same stability stands, a neutral one in its own words). lambda stays the
//    curve's slope; the summary gives the modes' rate and what the curve alone read. A neutral reading
//    the curve does not confirm (neutral_unconfirmed: over fewer than 8 mean periods, or a limit cycle
//    that does not repeat itself) whose record the modes do not describe either is undetermined.
#include <string>

#include "mlce/estimate.hpp"
#include "mlce/stability.hpp"

namespace mlce {

/// The amplitude of the analysed signal over the run.
enum class AmplitudeTrend { decays, persists, grows, changes, unknown };

const char* to_string(AmplitudeTrend a);

struct ReadingOptions {
  /// Half-width of the neutral band, in log change per mean period (0.01: a perturbation that
  /// grows or shrinks by less than 1 % per oscillation, an e-fold in 100 of them).
  double neutral_per_period = 0.01;
  /// An envelope rate at least this share of lambda (same sign) is the amplitude's own growth or
  /// decay (FitOptions::persist_share).
  double persist_share = 0.5;
  /// An envelope rate below this share of |lambda| (or below the neutral band per mean period) is a
  /// steady amplitude: chaos, or a limit cycle the neighbours converge onto.
  double steady_share = 0.1;
  /// lambda > 0 on a steady amplitude is chaos only when the divergence curve's highest point comes
  /// within this (natural log units) of the attractor scale (DivergenceCurve::attractor_log_distance):
  /// chaos bounds the divergence by the attractor's size. Default FitOptions::bounded_margin (2), the
  /// margin by which the fit rule itself finds neighbours that never separate. Lorenz x
  /// (N = 10^4, dt 0.01) rises to 0.12 above the scale, Roessler x (dt 0.1) to 1.24 below (a thin band: its
  /// neighbours saturate across it; 1.54 on other starts, scratch); blade 2's hinge in the bundled
  /// growing MBDyn run, the rotation's steady carrier over the hub's growth, stays 3.38 below.
  double chaos_scale_margin = FitOptions{}.bounded_margin;
  /// lambda > 0 on a steady amplitude is chaos only when the motion does not end periodic: a flow
  /// whose last third repeats itself one period on to less than this (EndRepeat::difference, the
  /// RMS difference over the RMS deviation) is a limit cycle, and its neighbours separated in a
  /// transient before it settled or are false ones. 0.07: the windows of Hammond's failed-damper
  /// run that start in its growth (8-12 s) and end at 30 s, on its settling limit cycle, repeat to
  /// 0.0065-0.036, 8 of 12 read "chaotic" before this rule (test_reading prints them); the chaotic
  /// flows of bench/other_flows repeat to 0.14 at the least (Roessler at c = 4.6, near the onset of
  /// chaos). Not for maps: a banded chaotic map repeats its bands to a few per cent (Henon at
  /// a = 1.06: 0.034, scratch).
  double periodic_end = 0.07;
  void validate() const;  ///< throws OptionError naming the option
};

struct Reading {
  Stability stability = Stability::undetermined;
  AmplitudeTrend amplitude = AmplitudeTrend::unknown;
  /// What the motion is, in words: "decays to rest", "growing oscillation", "chaotic",
  /// "diverging", "limit cycle", "periodic orbit" (a map's settled cycle), "lightly damped", "slowly
  /// growing" or "undetermined" (the summary
  /// says why).
  std::string motion;
  double mean_period = 0.0;  ///< T, time units (NaN when the spectrum has no mean frequency)
  double lambda_per_period = 0.0, ci_low_per_period = 0.0, ci_high_per_period = 0.0;  ///< lambda T
  double neutral_per_period = 0.0;  ///< the band the interval was judged against (the options')
  std::string summary;  ///< one line for people
};

Reading read_stability(const MlceResult& result, const ReadingOptions& options = {});

/// How many mean periods (the spectrum's, unclamped: eq. 19) the analysed part spans.
double mean_periods_spanned(const MlceResult& r);

/// A reading of the divergence curve that the record's damped modes may replace (MlceResult::record_modes):
/// undetermined, or neutral while the amplitude decays or grows (light damping, a slow growth).
bool curve_cannot_tell(const Reading& curve);

/// A neutral reading of a flow that the curve alone does not confirm: over fewer than 8 mean periods,
/// or a "limit cycle" whose motion does not repeat itself one period on (its last third, EndRepeat, or a
/// short run's whole record, ScaledRepeat; difference above ReadingOptions::periodic_end): a torus, a
/// light damping, or chaos whose neighbours the run is too short to separate. The record's damped
/// modes (MlceResult::record_modes) tell them apart: the first two are sums of modes, chaos is not
/// (then undetermined).
bool neutral_unconfirmed(const MlceResult& r, const Reading& curve, const ReadingOptions& options = {});

}  // namespace mlce
