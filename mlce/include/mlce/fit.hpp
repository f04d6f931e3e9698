#pragma once
// Least-squares slope of the divergence curve over its linear region (paper 001 eq. 22-23).
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mlce/mean_period.hpp"
#include "mlce/rosenstein.hpp"

namespace mlce {

/// A divergence curve that grows into a plateau or decays into a floor, and whose first step rises
/// by at least kNoiseJump (natural log) and by at least kNoiseJumpRatio x its fitted slope per step,
/// is flagged as dominated by measurement noise, with an estimate of the noise level
/// (estimate.cpp). Deterministic curves rise at about their slope in their first step (up to 6x
/// where the start-up is quick); noise of 1 % makes it 60x. Other curves (first_step_jumps_to_level)
/// must also be level after the jump, and are judged only on a decaying signal (estimate.cpp).
inline constexpr double kNoiseJump = 0.25;
inline constexpr double kNoiseJumpRatio = 10.0;

/// Does curve y's first step jump as measurement noise makes it (kNoiseJump, kNoiseJumpRatio),
/// against a slope of `slope_per_step`?
bool first_step_jumps(const std::vector<double>& y, double slope_per_step);

/// A curve that does not grow to a plateau (a decay, a limit cycle: slope ~0) is judged by the
/// jump's shape instead: noise is matched at step 0 and fresh at every later step, so the curve
/// jumps in one step and is level after it (the next two steps each move by at most
/// kNoiseLevelShare x the jump: e^{-zeta w t} sin w t plus 1-3 % noise, 0.25-1.27 then below 0.04
/// in scratch runs);
/// the selection of the best-matching pass on a noise-free limit cycle relaxes over several steps
/// (Hammond at 224 rpm, blade 3 inoperative: 0.31, then 0.25).
inline constexpr double kNoiseLevelShare = 0.2;
bool first_step_jumps_to_level(const std::vector<double>& y, double slope_per_step);

enum class CurveEnd { none, saturation, floor, flat, bounded };


struct FitOptions {
  /// Explicit fit range [first, last] in steps of the curve (overrides the rule).
  std::optional<std::pair<std::size_t, std::size_t>> range;
  /// Samples per oscillation of the curve (the mean period): sets the shortest segment and the
  /// local-slope window. 0 = 1.
  std::size_t period = 0;
  /// Straight pieces the part before the plateau/floor is split into: start-up transient, linear
  /// region and the bend towards the plateau (which may need two pieces).
  std::size_t pieces = 4;
  /// Adjacent segments whose slopes differ by less than this fraction of the larger are one line.
  double merge_tolerance = 0.25;
  /// A final segment whose slope is below this fraction of the fitted slope is the saturation
  /// plateau (lambda > 0) or the noise/underflow floor (lambda < 0).
  double end_tolerance = 0.2;
  /// A curve whose highest point stays more than this (natural log units) below the attractor
  /// scale (DivergenceCurve::attractor_log_distance), after it has stopped rising, is bounded:
  /// the neighbours never separate (limit cycle, torus) and lambda is ~0, not the start-up rise.
  double bounded_margin = 2.0;
  /// ... unless it rose from its first step by more than this (natural log units, a factor e^4 ~
  /// 55): pairs that a search picked drift apart by its selection bias, by a factor of a few, while
  /// this is an exponential divergence that saturates short of the attractor scale. The bands of a
  /// banded chaotic map do that: the logistic map at r = 3.58 visits four bands in turn, its pairs
  /// separate within their band, from -10.6 to -2.9 at the orbit's exponent, and level off 2.2
  /// below the scale of the whole attractor (`build/map_bands`).
  double bounded_max_rise = 4.0;
  /// ... and a curve that comes back down, after its highest point, to within this share of its rise
  /// of its first step's level is bounded however close to the attractor scale it rose (0 turns this
  /// off). Divergence saturates and stays at the scale; a record of a periodic motion too short for
  /// neighbours one period apart pairs points at a phase offset instead, and their distance parts and
  /// closes again every half period: a lightly damped sine over 2-3 periods of 500 samples rose to
  /// 1.1 below the scale and fell back to 0.09 of its rise, and read +0.54 1/s, "chaotic"
  /// (`mlce estimate` on `build/make_series oscillator 1000 0.002 0.01 6.2832`).
  double bounded_return = 0.25;
  /// The chosen region is straight when the slope of its second half is at least this fraction of
  /// its first half's; otherwise it reaches into the bend and its last quarter is dropped (repeated
  /// while the region is at least 4 minimum pieces long). 1 would trim any concave region. 0.97
  /// (was 0.9): Henon x at N = 10^4 within 2 % on 19 of 32 random series at 0.9 (the region
  /// reached ~6 iterations into the bend), 32 at 0.97 with the slow-first-step rule; Roessler x rms
  /// error 8.7 -> 6.7 %, Lorenz x unchanged (build/finite_time_spread).
  double straightness = 0.97;
  /// `straightness` for the curve of a map (`period` below kMinFlowPeriod; an unset period, 0,
  /// counts as 1 sample, as everywhere in the fit, so a bare curve is judged as a map's). A flow's curve
  /// breathes with the orbit, so the slopes of its halves differ by a few per cent on a straight
  /// stretch; a map's curve does not, and at 0.97 its region kept ~2 iterations of the bend into
  /// the plateau (Henon x: the last two steps of a 1..13 region rose at 0.97 and 0.92 lambda,
  /// reading 0.4 % low on average). `build/finite_time_spread maps`, 256 series: Henon x within
  /// 2 % 247 -> 250 (the own exponents: 250), rms from the own exponent 0.005 -> 0.002; logistic
  /// 256 of 256 at both, rms 0.0028 -> 0.0020. Flows keep 0.97 (Roessler x 114 -> 111 of 128
  /// within 10 % at 0.985, Lorenz x unchanged).
  double map_straightness = 0.99;
  /// Curves that grow into a saturation plateau: a piece after the start-up whose slope is below
  /// this fraction of the steepest piece before it is the bend into the plateau, never the linear
  /// region, however long (Lorenz x at N = 5000: 32 random series 0.397..1.302 lambda_1, rms error
  /// 15.8 % without; 0.707..1.302, 12.8 % with, 0.746..1.302, 12.4 % since the concave-growth join
  /// of fit_divergence's rule 2; unchanged at N >= 10^4: `build/finite_time_spread
  /// lengths`). 0 = off.
  double bend_ratio = 0.5;
  /// Curves that grow into a saturation plateau: the region spans at least this many periods
  /// (`period`) when the curve reaches that far before the plateau. A flow's curve oscillates at
  /// the signal's mean frequency (the pairs' separation breathes with the orbit), and a slope over
  /// less than about one and a half of its periods takes the phase of that oscillation for growth:
  /// Lorenz x read 1.11..1.24 lambda_1 on regions of 0.7..1.0 periods. 1.5 (`build/fit_end_rules`,
  /// Lorenz x at N = 10^4: 98 -> 107 of 128 seeded series within 5 %, 25 -> 28 of 35 from typed
  /// starts; `build/finite_time_spread segments`: 72 -> 78 of 100; Roessler x unchanged, its
  /// regions being longer; 1.2 and 1.6 do about as well). Not when the curve's first step
  /// jumps as measurement noise makes it (first_step_jumps): the noise floor lifts the curve's
  /// start and a longer region reads lower still (`build/finite_time_spread noise`: with 1 % and
  /// 3 % noise the same estimates with the minimum on and off). 0 = off.
  double min_periods = 1.5;
  /// Curves that grow into a saturation plateau, fitted by the rule: when the region's second half
  /// rises at less than this fraction of its first half's slope, a warning says that the curve bends
  /// within the region (it has no straight stretch; the exponent then depends on the region more than
  /// its batch-means interval says). Nothing else changes. At 0.65, before extension_straightness,
  /// `build/finite_time_spread starts` listed 2 of its 128 Lorenz x series (0.846 and 0.976 lambda_1)
  /// and `build/other_flows` 4 of its 6 Chua x series (0.81-0.86 of their own exponents but one); since,
  /// none of either (the extension no longer bends the region), two Lorenz x series of N = 5000
  /// (`lengths`). 0 = never warn.
  double bend_warning = 0.65;
  /// The extension to min_periods stops before it bends the region: it is cut back while the extended
  /// region's second half rises at less than this fraction of its first half's slope, unless the region
  /// before the extension did so already. Chua's x (`build/other_flows`), whose mean period of 111..116
  /// samples is set by the slow switching between its scrolls, read 0.81..0.86 of its own exponent on
  /// 5 of 6 series over regions carried into the flattening; 0.90..0.98 on 5 (1.19 on the sixth,
  /// fitted from its first step, 1.02 before). Lorenz x (`build/finite_time_spread`): within 5 % of
  /// 128 `starts` 107 -> 109, of 100 `segments` 78 -> 79; at dt = 0.05 (N = 2000) 10 -> 14 of 32;
  /// Roessler x and the maps unchanged. Between the bend warning (0.65: 106 of 128 `starts`) and the
  /// straightness trim (0.9); 0.7 and 0.8 read 108 and 107. 0 = extend to min_periods always.
  double extension_straightness = 0.75;
  /// Rate at which the analysed signal's own amplitude changes, per sample (envelope_rate; NaN =
  /// unknown). A curve that falls into a floor while the signal decays less than persist_share x
  /// as fast does not measure a decay to rest: its neighbours converge onto a motion that persists
  /// (a limit cycle: the fall is a contracting exponent, lambda_2), and a bounded motion that does
  /// not come to rest has lambda_1 >= 0 (the flow direction's exponent is 0). The level the curve
  /// settles at is then fitted (Hammond at 300 rpm, blade 3 inoperative, from lag rate 1 rad/s: its
  /// limit cycle read -0.094 1/s on the fall, +0.005 on the level).
  double signal_rate = std::numeric_limits<double>::quiet_NaN();
  double persist_share = 0.5;
  /// The same rate over the signal's second half (per sample; NaN = unknown): a signal that still
  /// grows at its end grows on its own (late_growth_share).
  double signal_end_rate = std::numeric_limits<double>::quiet_NaN();
  /// The analysed signal ends at a floor of its own (estimate.cpp sets it when a noise, underflow or
  /// solver-tolerance floor was cut off the series). A falling curve that flattens into a floor
  /// (stage 1) may then have reached it with its pairs' distances, and its early steep part is the
  /// decay (stage 2). A curve that shows no floor, or falls on a signal without one, without zero
  /// distances (quantisation) and whose first step does not jump as measurement noise makes it
  /// (first_step_jumps), has no floor to bend into: it flattens only as its faster modes die out,
  /// and is fitted late (late_decay_share). `build/decay_modes`, its 54 two-mode decays with 0.1 %
  /// white noise: within 5 % / 10 % 34 / 38, rms error 40 % (stage 2 throughout: 22 / 26, rms 92 %);
  /// 18 / 28 before detect_floor read the noise from increments (f9f6749's bench).
  bool signal_floor = false;
  /// Decays of a signal without a floor: the exponent is the least negative one, the least damped
  /// mode, which the curve follows only once the faster modes have died out (with close
  /// frequencies they beat with it first: the curve oscillates at the difference frequency). The
  /// region is the last late_decay_share of the fall, from the curve's highest point (the pairs'
  /// selection-bias rise) to its end: shorter regions take the phase of the beat for the trend,
  /// longer ones the faster modes. 0.75: `build/decay_modes`, 54 two-mode decays e^{-0.3 t} cos 2 pi t
  /// plus a mode of rate -0.5, -1 or -3 at 0.45, 1.37 or 3.3 Hz, amplitude ratios 0.2, 1 and 5, 2000
  /// and 4000 samples (dt 0.01): 48 within 5 % of -0.3, 0.893..1.163 x (the rule before, share 0: 33,
  /// up to 3.75 x). In a scratch comparison on their curves (and two three-mode decays) the whole fall
  /// and its second half did worse (max error 34 % and 87 %). 0 = off (the growth rule fits decays too).
  double late_decay_share = 0.75;
  /// Growths of a signal whose amplitude grows on its own (signal_end_rate x the curve's steps >= 0.5:
  /// it still grows at its end, a linear instability's response, not a growth that settles on a
  /// bounded attractor): the exponent is the largest rate, the fastest-growing mode, which the curve
  /// follows only once it dominates the others (with close frequencies they beat first). Such a curve
  /// has no saturation plateau (the pairs' distances grow with the signal), and a level that still
  /// rises at persist_share x the signal's end rate is a beat or a slower mode, not a plateau. The
  /// region is the last late_growth_share of the rise from the curve's lowest point in its first half
  /// to its end. 0.75, as for decays: `build/decay_modes`, growths section, 11 of 12 within 5 % (the
  /// growth rule's region 8, up to 3.1 x). 0 = off (the growth rule's region).
  double late_growth_share = 0.75;
  /// A noise-compensated curve (DivergenceCurve::compensated_noise_share; estimate.cpp sets this
  /// when it compensates): the relative standard error of the measured noise's mean square
  /// (MlceResult::noise_variance_error). 0 = exact or unknown.
  double noise_variance_error = 0.0;
  /// A noise-compensated decay is fitted late (stage 2b'), over the last late_decay_share of the
  /// fall to an end chosen so that the noise level's error (noise_variance_error, one standard
  /// error) moves the slope by at most this share of it (noise_level_sensitivity): the latest such
  /// end, or where it moves it least. The noise's share of the pairs' mean square grows along a
  /// decay, and its error with it, by share / (1 - share). 0.05 (`build/noisy_decays`, the
  /// compensated series of its three studies, within 10 %: 49 -> 44 of 56, 40 -> 43 of 57, 32 -> 47
  /// of 68 against the growth rule's region, which took short early pieces; rms error 0.089 -> 0.093,
  /// 0.207 -> 0.098, 1.18 -> 0.46; at 0.03 the ends left fell into those pieces again, grid rms
  /// 0.34). 1 = to the curve's end.
  double noise_slope_error = 0.05;
  void validate() const;
};

struct FitResult {
  std::size_t first = 0, last = 0;  ///< fit region, curve steps (inclusive)
  double slope = 0.0;               ///< per sample (natural log)
  double intercept = 0.0;
  double r2 = 0.0;
  double ci_low = 0.0, ci_high = 0.0;  ///< 95 % interval of the slope, per sample
  CurveEnd end = CurveEnd::none;       ///< what stops the region on the right
  std::size_t end_index = 0;           ///< where the plateau/floor starts (when end != none)
  bool automatic = true;
  std::string rule;                    ///< one-line account of how the region was chosen
  std::vector<std::string> warnings;
};

/// The rule (deterministic), in two stages. Pieces are optimal least-squares segmentations (dynamic
/// programming over the breakpoints), each piece at least max(3, period/2 + 1) steps, adjacent
/// pieces with slopes equal within merge_tolerance joined.
///  0. A curve whose total range is below 0.25 (distances change by less than e^0.25) is flat
///     (lambda ~ 0): the whole curve is fitted.
///  0b. A curve that never comes within bounded_margin of the attractor scale, starts in the lower
///     half of its range (a decay starts at the top), rises by at most bounded_max_rise and has settled (over its second half its
///     least-squares line changes by less than 0.25, or by less than 0.4 of the curve's range, which a straight rise does not) is
///     bounded: pairs selected as nearest neighbours drift apart by the selection bias of the
///     search and then wander without separating (limit cycle, torus, paper 001 §5.2's LCOs). No
///     exponential region exists; its second half is fitted, whose slope tends to lambda = 0 as
///     the horizon grows (the estimator then uses the longest horizon). So is such a curve whose
///     second half falls back by more than that tolerance (a growth saturates and never falls; a
///     limit cycle that has not fully settled closes in again as its residual decaying mode dies
///     out): it is fitted from where it first reached its final level, rise and fall together.
///     Not when the signal's own amplitude decays at least persist_share x as fast as that second
///     half falls (signal_rate): a decay to rest whose curve rose over its start-up (a short record
///     of a slow decay starts low in its range) goes on to stage 1.
///     So is a curve that comes back down after its highest point to its start level (bounded_return),
///     however near the attractor scale it rose: divergence saturates and stays, while pairs of a
///     periodic motion at a phase offset part and close again. Fitted from its first step to its
///     last return to that level; not when that fit drifts by more than half the rise, nor on a signal
///     with a floor of its own (signal_floor), nor when the signal decays at least persist_share x as
///     fast as that fit falls (swings riding on a trend are a rate).
///  1. Three pieces; the piece explaining the largest change |slope| x length is the growth (or
///     decay); a later piece with |slope| < end_tolerance x that slope is the saturation plateau
///     (lambda > 0) or the noise/underflow floor (lambda < 0, paper 001 Fig. 6): the curve is cut there.
///     When the signal is known to decay less than persist_share x as fast as the fall
///     (signal_rate), the floor is the motion the neighbours converged onto: the region is from the
///     floor to the curve's end, and the end is reported as bounded divergence (no stage 2).
///  2. The part before the cut is split into `pieces` pieces (start-up transient, linear region,
///     bend into the plateau). A first piece steeper than the next and no longer than it is the
///     start-up transient and is skipped (of a growth, when longer than two periods, only the first
///     of its two optimal parts if that one is the steeper); when the cut is a saturation plateau, a piece less than
///     bend_ratio x as steep as a piece before it is the bend and so is everything after it; the
///     linear region is the remaining piece of largest |slope| x length, or an earlier piece at
///     least a period (2 minimum pieces) long with a slope of the same sign and at least as large
///     in magnitude (the bend only lowers the slope). When the pick is not the first piece after the
///     start-up and every piece from there to it is steeper than the next (a growth that only
///     flattens, with no straight stretch), the region starts at the start-up's end: the pick alone
///     would be the growth's flattest part. A region that starts
///     at step 0 loses that step when it changes the curve by less than 0.9 x the second step (the
///     separation still shrinking along the contracting directions; maps align within one
///     iteration, below the shortest piece). While the region's second half has less than
///     `straightness` x its first half's slope, its last quarter is dropped. A region of a curve
///     that saturates is then extended to min_periods periods when it is shorter and the curve
///     reaches that far before the plateau, but not into a bend: the extension is cut back while
///     the extended region's second half has less than `extension_straightness` x its first half's
///     slope (unless the region before it already had).
///  2b. Instead of 2, when the curve falls (the largest change of stage 1), and neither stage 1 found a
///     floor on a signal with a floor of its own (signal_floor), nor has the curve zero distances or a
///     noise jump at its first step: the last
///     late_decay_share of the fall from the curve's highest point in its first half to the cut; a
///     stage-1 floor that still falls by more than 1 is a slower mode and the fall runs to the
///     curve's end. A warning when the fall's second half is less than 0.8 x as steep as its first.
///  2b'. Instead of 2 and 2b, on a noise-compensated curve that falls: the noise floor is taken out,
///     the first step's jump is the search's selection (step 0 is the plain mean square), and the
///     decay is fitted late as in 2b, but the fall ends where the measured noise level's error moves
///     the slope by at most noise_slope_error of it (the latest end, tried every quarter period back
///     from the curve's end; or the one where it moves it least).
///  2c. Instead of 2, when the curve rises (the largest change of stage 1) on a signal that still grows
///     at its end (signal_end_rate x the curve's steps >= 0.5) and no saturation plateau was cut, or
///     the cut level still rises at persist_share x signal_end_rate: the last late_growth_share of
///     the rise from the curve's lowest point in its first half to the curve's end.
/// The 95 % interval comes from batch means: the slope of each batch's curve over the same region,
/// t-distributed over the batches.
FitResult fit_divergence(const DivergenceCurve& curve, const FitOptions& options);

/// Local slope of a divergence curve y (eq. 23), per step, for reading it by eye beside the fit:
/// the centred difference (y[i + w] - y[i - w]) / (2 w) over one oscillation period of the curve,
/// 2 w = `period` rounded up to an even count (w >= 1; period 0 or 1, a map's curve: w = 1). A
/// flow's curve oscillates with its orbit (FitOptions::period); a difference over a whole period
/// cancels an oscillation of that period exactly, so the local slope of a straight stretch is flat
/// at its growth rate where a step-to-step difference swings by more than it. The first and last w
/// steps have no centred window: NaN there (written as empty fields by the CLI).
std::vector<double> local_slopes(const std::vector<double>& y, std::size_t period);

const char* to_string(CurveEnd end);

}  // namespace mlce
