#include "mlce/estimate.hpp"
#include "mlce/modes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>

#include <boost/math/special_functions/digamma.hpp>

#include "mlce/embedding.hpp"
#include "mlce/numerics.hpp"
#include "mlce/reading.hpp"
#include "mlce/recurrence.hpp"
#include "mlce/transient.hpp"

namespace mlce {
namespace {

void report(const MlceOptions& o, std::string_view stage, double fraction) {
  if (o.progress) o.progress(stage, fraction);
}

void append(std::vector<std::string>& to, const std::vector<std::string>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

/// The first step at which a curve that saturates comes within a tenth of its rise of the plateau
/// level (the mean over the plateau piece), or nullopt when it does not saturate.
std::optional<std::size_t> plateau_reached(const DivergenceCurve& curve, const FitResult& fit) {
  const auto& y = curve.mean_log_distance;
  if (fit.end != CurveEnd::saturation || fit.end_index >= y.size()) return std::nullopt;
  CompensatedSum sum;
  for (std::size_t i = fit.end_index; i < y.size(); ++i) sum.add(y[i]);
  const double level = sum.value() / static_cast<double>(y.size() - fit.end_index);
  const double near = level - 0.1 * (level - y[0]);
  std::size_t i = 0;
  while (i < fit.end_index && y[i] < near) ++i;
  return i;
}

/// A signal whose envelope falls by at least this factor over the series decays to rest (the adaptive
/// horizon follows its curve past a "saturation" the signal has not fallen through; a stationary
/// motion's envelope changes by far less).
constexpr double kRecordDecay = 10.0;

/// Does the analysed signal decay: its last third's RMS at most 1/kPersistentAmplitude of its first's,
/// or its envelope falling by more than 1 % per mean period (the reading's default neutral band)?
bool signal_decays(const MlceResult& r) {
  const double f = r.mean_period.mean_frequency;
  const double period = f > 0.0 ? 1.0 / f : std::numeric_limits<double>::quiet_NaN();  // time units
  constexpr double kDecayPerPeriod = 0.01;
  return r.amplitude_ratio <= 1.0 / kPersistentAmplitude || r.envelope_rate / r.dt * period < -kDecayPerPeriod;
}

/// In a decay to rest the least damped mode sets both the signal's late envelope and the rate the
/// neighbours converge at (every separation of a linear motion is a sum of its modes). Neighbours
/// converging much faster than the signal decays over its second half measure something else: two
/// modes of like damping whose beat is longer than the curve's horizon (e^{-0.2 t}(cos 2 pi t +
/// cos 2.2 pi t) over 30 s, three beats: the curve follows one beat, and its falling half read
/// -0.39 for -0.2, the envelope -0.22), or a region in the curve's bend. A growth, the mirror: the
/// fastest growing mode sets both once it leads, but the envelope lags it while slower modes hold
/// the signal (build/decay_modes: a mode of 0.3 under one of 0.1 read 0.27 with the envelope at
/// 0.17), so only twice its larger rate (whole run or second half) is said (the same beat growing,
/// e^{0.1 t}: 0.75 for 0.1). Said, not changed.
void warn_about_rate_beyond_envelope(MlceResult& r) {
  constexpr double kFasterThanDecay = 1.5, kFasterThanGrowth = 2.0;
  const std::size_t steps = r.curve.mean_log_distance.size() - 1;
  if (r.fit.slope < 0.0 && r.end_envelope_rate < 0.0 && signal_decays(r) &&
      r.fit.slope < kFasterThanDecay * r.end_envelope_rate) {
    r.warnings.push_back(fmt::format(
        "the neighbours converge {:.3g} x as fast as the signal's own envelope decays over its second half ({:.4g} "
        "against {:.4g} per sample): in a decay to rest the least damped mode sets both, so the fit region measures "
        "something else, such as modes of like damping that beat over more than the curve's {} steps (analyse a "
        "longer run) or the curve's bend (--fit A:B)",
        r.fit.slope / r.end_envelope_rate, r.fit.slope, r.end_envelope_rate, steps));
    return;
  }
  const double grows_at = std::max(r.envelope_rate, r.end_envelope_rate);
  // Only a signal whose amplitude grows outright (its last third's RMS kPersistentAmplitude x its
  // first's or more): a nonlinear motion that has stopped growing may be chaotic, and its envelope's
  // slow drift bounds nothing (Hammond's rotor without dampers at 150 rpm after 30 s: 0.28 1/s on
  // an envelope rising at 0.02).
  if (r.fit.slope > 0.0 && grows_at > 0.0 && r.amplitude_ratio >= kPersistentAmplitude &&
      r.fit.slope > kFasterThanGrowth * grows_at)
    r.warnings.push_back(fmt::format(
        "the neighbours separate {:.3g} x as fast as the signal's own envelope grows ({:.4g} against {:.4g} per "
        "sample): in a growth of linear modes the fastest growing one sets both once it leads, so the fit region may "
        "measure something else, such as modes of like rate that beat over more than the curve's {} steps or the "
        "pairs' start-up (analyse a longer run, or --fit A:B)",
        r.fit.slope / grows_at, r.fit.slope, grows_at, steps));
}

/// Warnings about what the curve can measure (sets r.noise_level): a plateau reached within one
/// embedding window (uncorrelated noise), and a first step that jumps (measurement noise); returns
/// the index in r.warnings of the latter's warning, nullopt when the curve is not flagged noisy.
std::optional<std::size_t> flag_noise(MlceResult& r, std::size_t channels) {
  // Delay vectors (m - 1) x delay + 1 steps after the match share no sample with the matched ones.
  // Uncorrelated noise separates to the attractor scale exactly then, as those shared samples slide
  // out of the window: the curve's rise measures the window, not a divergence (white noise, m = 5,
  // delay 1: plateau at step 5, "lambda" = 0.16 per sample). A chaotic signal keeps rising after it
  // (Henon: window 2 steps, plateau from ~15; Lorenz x: 37 and ~600).
  const std::size_t window = (r.dim - 1) * r.delay + 1;
  if (const auto reached = plateau_reached(r.curve, r.fit); r.fit.automatic && reached && *reached <= window) {
    if (r.unreliable.empty()) r.unreliable = "the curve does not resolve a divergence (plateau within one embedding window)";
    r.warnings.push_back("divergence not resolved: the curve reaches its plateau at step " + std::to_string(*reached) +
                         ", within one embedding window ((m-1)*delay + 1 = " + std::to_string(window) +
                         " samples), as uncorrelated noise does; lambda measures the window, not an exponential "
                         "divergence (a noise-dominated signal, or a sampling too coarse for the motion)");
  }
  // White measurement noise is matched at step 0 (the search picks the smallest distance, noise
  // included) and fresh one step later: the curve jumps by the noise's share at once, while a
  // deterministic curve rises at about its slope per step (Lorenz x: 0.013 at a slope of 0.010 per
  // step; Henon 0.30 at 0.42; Lorenz x at dt = 0.05, whose start-up is quick: 6 x the slope). Lorenz x
  // with noise of 1 %, 10 %, 30 % of its standard deviation jumps by 0.56, 1.30, 1.40 (63 to 180 x its
  // slope) and reads 0.882, 0.713, 1.468 instead of 0.906. The jump then also gives the noise level:
  // after it the distance of two independent noise vectors of n = m x channels coordinates, each
  // N(0, s^2), is sqrt(2) s chi_n, and E[ln chi_n] = (psi(n/2) + ln 2) / 2, so
  // ln s = y(1) - ln 2 - psi(n/2) / 2 (an upper bound: y(1) holds the deterministic separation too).
  // A curve that grows to a plateau or falls into a floor is judged by the jump alone. Any other
  // (a decay without a floor, a flat or bounded curve) only on a signal whose amplitude decays (its
  // last third's RMS at most 1/kPersistentAmplitude of its first's, or an envelope falling by more
  // than 1 % per mean period), and only if the curve is level after the jump: a lightly damped
  // oscillation whose per-cycle amplitude change is below the noise is held level by it
  // (e^{-0.025 t} cos 2 pi t plus 1 % noise, 16000 samples: lambda -0.0024 for -0.0251 1/s), and
  // the reading then takes the decay from the amplitude (reading.hpp). On a limit cycle the same
  // shape also comes from motion the embedding does not resolve, decorrelating within one sample
  // (Hammond at 290 rpm, blade 3 inoperative, sampled every 0.02 s: 0.648, then level; every
  // 0.005 s it relaxes over 6 steps, as at 224 rpm: 0.31, 0.25, ...): not flagged there.
  const bool measures_rate = r.fit.end == CurveEnd::saturation || r.fit.end == CurveEnd::floor;
  if (const auto& y = r.curve.mean_log_distance; y.size() > 3) {
    const bool decays = signal_decays(r);
    if (measures_rate ? first_step_jumps(y, r.fit.slope) : decays && first_step_jumps_to_level(y, r.fit.slope)) {
      const double jump = y[1] - y[0];
      const std::size_t n = r.dim * channels;
      r.noise_level = std::exp(y[1] - std::numbers::ln2 - 0.5 * boost::math::digamma(0.5 * static_cast<double>(n)));
      char text[600];
      std::snprintf(text, sizeof text,
                    "the curve jumps by %.3g in its first step (%.3g x its fitted slope per step)%s: the neighbour "
                    "distances are dominated by measurement noise of up to about %.2g %% of the signal's standard "
                    "deviation (white-noise estimate); %s",
                    jump, jump / std::max(std::abs(r.fit.slope), std::numeric_limits<double>::min()),
                    measures_rate ? "" : " and is level after it", 100.0 * r.noise_level,
                    measures_rate ? "a noise floor bends the curve, and lambda is biased"
                                  : "the noise (or motion the embedding does not resolve at this sampling) holds "
                                    "the curve level, so a decay slower than the noise resolves reads closer to 0 "
                                    "than it is (lambda biased towards 0)");
      r.warnings.push_back(text);
      return r.warnings.size() - 1;
    }
  }
  return std::nullopt;
}

/// Measurement noise on a map (sets r.noise_level, warns): flag_noise's first-step jump never shows
/// there, since a map's curve rises by about its slope per step from the first step on (logistic
/// r = 4 with noise of 1 % of its standard deviation read 0.89 of ln 2, Henon 0.84 of its exponent,
/// neither flagged). What does show is how the pairs' first step depends on their distance
/// (stretch_by_distance): a map stretches its closest pairs like the others, while noise sets the
/// distance of a pair one step on, whatever it was chosen at, and the closest pairs' stretch climbs
/// as 1/d. The closest half of the pairs' stretch falling by kMapNoiseStretchSlope or more per unit
/// ln d is the flag; the noise's level is then read from the closest group's distance one step on
/// as flag_noise reads y(1). Not an upper estimate here: with delay 1 all but one coordinate of that
/// step were compared by the search, which picked them small, while the map's image of the pair's
/// own separation adds to it; 0.6-1.2 x the noise added on the maps of bench/map_bands noise. Only on a
/// curve that saturates with lambda > 0, the chaotic map noise biases, and not on an estimate already
/// unreliable: a map's periodic orbit repeats, its pairs are judged by the repeat tests, and what
/// neighbours it has left are far apart (Henon at a = 1.24, a period-7 window, read "undetermined"
/// at +0.44, its closest pairs 0.97 standard deviations apart one step on).
void flag_map_noise(const Series& series, const RosensteinOptions& ro, const NeighbourPairs& pairs, MlceResult& r) {
  if (!r.mean_period.map || r.fit.end != CurveEnd::saturation || !(r.fit.slope > 0.0) || std::isfinite(r.noise_level) ||
      !r.unreliable.empty())
    return;
  const StretchByDistance stretch = stretch_by_distance(series, ro, pairs);
  if (!(stretch.closest_half_slope <= kMapNoiseStretchSlope)) return;
  // flag_noise's white-noise reading of a distance, on the closest group one step on.
  const double n = static_cast<double>(r.dim * series.channels.size());
  r.noise_level = std::exp(stretch.log_next.front() - std::numbers::ln2 - 0.5 * boost::math::digamma(0.5 * n));
  r.warnings.push_back(fmt::format(
      "the closest neighbour pairs stretch the more in their first step the closer they start ({:+.2f} of ln stretch per "
      "unit ln distance over the closest half of {} pairs; a map stretches them alike, measurement noise as 1/d): "
      "measurement noise of about {:.2g} % of the signal's standard deviation (white-noise estimate, within a factor 2) "
      "sets their distances, and lambda is biased low (a lower bound)",
      stretch.closest_half_slope, stretch.pairs, 100.0 * r.noise_level));
}

/// The part of the input that is analysed: `raw` dithered (MlceOptions::dither) and cut at the
/// noise/underflow floor a decay ends in (detect_floor). Held in `storage` when it differs from
/// `raw`; what was done is said in `warnings` (dither first, then the floor); `part` tells whether
/// the floor was cut off (FitOptions::signal_floor) or holds nearly the whole window.
struct AnalysedPart {
  bool floor_cut = false;
  /// A window cut from a record (MlceOptions::record_deviation) whose part above the record's floor
  /// spans fewer than kMinMeanPeriods of its own mean periods, or that lies wholly within 10x of
  /// that floor (Floor::whole): too little of the decay to measure, so nothing is cut and the window
  /// is read as the floor (warn_about_floor_window).
  bool floor_holds_window = false;
  /// The floor is the resolution the values were written with (Floor::resolution): a window lies in
  /// it below kResolutionFloorShare of the record's deviation, not MlceOptions::floor_ratio.
  bool resolution_floor = false;
};
const Series& analysed_part(const Series& raw, const MlceOptions& options, Series& storage,
                            std::vector<std::string>& warnings, AnalysedPart& part) {
  if (!(options.dither >= 0.0) || !std::isfinite(options.dither)) throw OptionError("dither: expected a finite width >= 0");
  if (!(options.floor_ratio >= 0.0 && options.floor_ratio < 1.0)) throw OptionError("floor_ratio: expected [0, 1)");
  part = {};
  if (options.dither > 0.0) {
    storage = raw;
    std::uint64_t state = options.dither_seed;
    for (auto& c : storage.channels)
      for (double& v : c) v += options.dither * (uniform01(state) - 0.5);
    validate_series(storage);  // a width beyond the double range would leave infinities
    char text[200];
    std::snprintf(text, sizeof text, "dithered: uniform noise of width %.6g added to every sample (seed %llu)",
                  options.dither, static_cast<unsigned long long>(options.dither_seed));
    warnings.push_back(text);
  }
  const Series& input = options.dither > 0.0 ? storage : raw;
  validate_record_deviation(options, input.channel_count());
  const Floor floor = detect_floor(input, options.floor_ratio, options.record_deviation);
  part.resolution_floor = floor.resolution;
  if (floor.index == 0) {
    part.floor_holds_window = floor.whole;  // a window wholly within the record's floor: nothing to cut
    return input;
  }
  // A decay into the noise/underflow floor is analysed up to the floor only.
  // A noise-free decay has no floor, but past 1e-6 of its largest RMS a solver's tolerance or
  // rounding may already hold it: a trial rule that kept decays still falling at their end (not
  // committed) moved Hammond's at 155-170 rpm (studies/fig4_5) up to 0.6 % further from their
  // Floquet exponents. The warning names both.
  // Measurement noise is a floor at any level: a decay that sinks into it leaves pairs whose
  // distances are the noise's, and the curve flattens (e^{-0.314 t} cos 2 pi t with 0.1 % noise,
  // 8000 samples: +3.24 1/s uncut, -0.3167 cut; test_estimate_systems prints both).
  const std::size_t f = floor.index;
  Series cut = leading_samples(input, f);
  // Cut late in a decay (the ad-hoc isotropic rotor at 200 rpm from 16 s: 88 samples above the
  // record's floor, 1.2 of their mean periods), the window is its floor but for a start too short
  // to measure; the refusal of too short a motion would then name those few samples, not the window.
  if (floor.against_record) {
    auto periods_above = [&] {  // the mean frequency needs 4 samples
      if (f < 4) return 0.0;
      const MeanPeriodResult above = estimate_mean_period(cut, options.mean_period);
      const double f_per_sample = above.mean_frequency_per_sample;
      return f_per_sample > 0.0 ? static_cast<double>(f) * f_per_sample
                                : static_cast<double>(f) / static_cast<double>(above.mean_period);
    };
    if (periods_above() < kMinMeanPeriods) {
      part.floor_holds_window = true;
      return input;
    }
  }
  warnings.push_back(
      floor.resolution
          ? fmt::format("the signal decays to the resolution it was written with from sample {} (t = {:g}) ({}): analysed "
                        "up to there ({} floor samples left out)",
                        f, input.time(f), floor_evidence(floor, options.floor_ratio), input.size() - f)
      : floor.white_noise
          ? fmt::format("the signal decays into white measurement noise ({}) from sample {} (t = {:g}): analysed up to "
                        "there, where it is still 5x the noise ({} floor samples left out)",
                        floor_evidence(floor, options.floor_ratio), f, input.time(f), input.size() - f)
          : fmt::format("the signal decays into a noise/underflow floor from sample {} (t = {:g}), or so far ({}) that "
                        "solver tolerance and rounding dominate there: analysed up to there ({} floor samples left out)",
                        f, input.time(f), floor_evidence(floor, options.floor_ratio), input.size() - f));
  storage = std::move(cut);  // `input` may be `storage` (dithered): it is not read after this
  part.floor_cut = true;
  return storage;
}

/// Warnings about the analysed series itself (MlceResult::unreliable set with them): a random walk
/// (steps of white noise), a drift (a quantity that keeps growing) and an angle that wraps by whole
/// turns. Returns the walk's or the drift's warning ("" when none): the short-run refusal names it,
/// and the rest after a left-out start is judged again.
std::string warn_about_series(const Series& series, MlceResult& r) {
  const WrappedAngle wrapped = wrapped_angle(series);
  // A wrapping angle's steps are a constant and rare whole turns, which a portmanteau test can take
  // for white: the wrap is the finding then.
  const WhiteSteps walk = wrapped.count > 0 ? WhiteSteps{} : white_steps(series);
  std::string series_warning;
  if (walk.found) {
    series_warning = fmt::format(
        "{} is a random walk: its steps are white noise (Ljung-Box Q = {:.3g} over lags 1..{}, below the 99.9 % point "
        "{:.3g} of white steps) while its variance is {:.3g} x theirs: integrated noise, or a "
        "relaxation so slow that its steps look so; it comes back near its past states only by chance, and its "
        "deterministic part x[t+1] = x[t] has exponent 0, which no divergence curve measures: analyse a channel of the "
        "motion itself, or its steps (a rate) if they carry one",
        channel_name(series, walk.channel), walk.statistic, walk.lags, walk.critical, walk.variance_ratio);
    r.warnings.push_back(series_warning);
    r.unreliable = "a random walk (its steps are white noise)";
  } else if (const Drift d = linear_drift(series); d.share > kDriftShare) {
    // Delay vectors of a series that keeps drifting never come back near each other: the nearest
    // neighbours are then whatever lies closest across the drift, and the spectrum's mean period is
    // the drift's (a rotor azimuth of 10^4 samples: "1.06 mean periods").
    series_warning = fmt::format(
        "the series drifts: a straight line through time explains {:.0f} % of {}'s variance (a quantity that keeps "
        "growing, such as a rotation angle or a position?); the exponent assumes a motion that comes back near its past "
        "states: analyse a stationary channel (a rate, a relative angle) or remove the drift first",
        100.0 * d.share, channel_name(series, d.channel));
    r.warnings.push_back(series_warning);
    r.unreliable = "the series drifts";
  }
  if (wrapped.count > 0) {
    r.warnings.push_back(fmt::format(
        "{} jumps by {:.6g} between samples {} and {} (t = {:.6g}), and {} time(s) in all, by a whole turn: an angle "
        "that wraps at +-{}; its delay vectors straddle the jumps and the exponent is meaningless: analyse a relative "
        "angle (rel:A:B:AXIS, unwrapped), a rate, or unwrap it first",
        channel_name(series, wrapped.channel), wrapped.jump, wrapped.sample - 1, wrapped.sample,
        series.time(wrapped.sample), wrapped.count, wrapped.degrees ? "180 deg" : "pi"));
    if (r.unreliable.empty()) r.unreliable = "an angle that wraps by whole turns";
  }
  return series_warning;
}

}  // namespace

void validate_record_deviation(const MlceOptions& options, std::size_t channels) {
  if (!options.record_deviation.empty() && options.record_deviation.size() != channels)
    throw OptionError(fmt::format("record_deviation: {} value(s) for {} channel(s); expected one per channel",
                                  options.record_deviation.size(), channels));
}

namespace {

/// A window cut from a longer record (MlceOptions::record_deviation) that lies wholly in the floor
/// its decay ended in before it: every channel's RMS deviation below floor_ratio of the record's
/// largest deviation, and the window's own amplitude does not decay (its last third's RMS above half
/// its first third's). The whole record's analysis cuts that floor off (detect_floor); a window of it
/// alone has no larger part to tell it by. A window that still decays is the decay itself, however
/// far below the record's scale: the real MBDyn run of the isotropic rotor at 200 rpm keeps decaying
/// cleanly to 3e-10 of its start, and `node:2:x` from 8-15 s reads -1.18 1/s, the slowest eigenvalue.
/// `floor_holds_window` (AnalysedPart): the part above the record's floor is too short to measure, and
/// the window is read as floor though its start still decays. A floor of the resolution the values
/// were written with (AnalysedPart::resolution_floor) lies higher: below kResolutionFloorShare of the
/// record's deviation instead of floor_ratio.
void warn_about_floor_window(const Series& series, const MlceOptions& options, const AnalysedPart& part,
                             MlceResult& r) {
  // options.record_deviation was validated against the channels by analysed_part.
  if (options.record_deviation.empty() || !(options.floor_ratio > 0.0)) return;
  const std::vector<double> window = rms_deviations(series);
  double largest = 0.0;  // the largest ratio over the channels
  std::size_t channel = 0;
  for (std::size_t c = 0; c < window.size(); ++c) {
    const double record = options.record_deviation[c];
    if (!(record > 0.0) || !std::isfinite(record)) return;  // a constant channel: nothing to compare
    if (const double ratio = window[c] / record; !(ratio <= largest)) largest = ratio, channel = c;
  }
  r.floor_window_ratio = largest;
  // A floor of the written resolution lies higher than rounding and tolerance (its quanta).
  const double limit = part.resolution_floor ? kResolutionFloorShare : options.floor_ratio;
  if (!(largest < limit)) return;
  if (!part.floor_holds_window && r.amplitude_ratio <= 1.0 / kPersistentAmplitude) return;
  r.in_decay_floor = true;
  r.warnings.push_back(fmt::format(
      "the analysed window lies in the floor of a decay that ended before it: {}'s RMS deviation is {:.2g} of its "
      "largest deviation over the record it was cut from (below {:g}: {}, paper 001 Fig. 6); the motion had decayed "
      "to rest, and lambda measures that residue, not the motion: analyse the decay (an earlier --from)",
      channel_name(series, channel), largest, limit,
      part.resolution_floor ? "a few repeating values of the resolution it was written with"
                            : "solver tolerance and rounding"));
  if (r.unreliable.empty()) r.unreliable = "a window in the floor a decay ended in before it";
}

/// A level that drifts beneath the neighbour pairs (neighbour_drift): only for a motion that
/// persists, since a decay onto a level or a growth moves its level as part of what it measures, and
/// only where the pairs separate (a curve that is neither flat nor bounded): a limit cycle's curve
/// stays level with the offset or without it (van der Pol x plus 0.01 t or 0.05 t: shares 0.90 and
/// 0.88, and still lambda ~2e-5 and -2e-4), and its reading, neutral, is the same. The real limit
/// cycle of c3zero_242rpm_cyhalf_lco, still settling, shows 0.038 on blade 4's lag and reads neutral.
void warn_about_neighbour_drift(const Series& series, bool persisting, MlceResult& r) {
  const NeighbourDrift& d = r.neighbour_drift;
  const bool level_curve = r.fit.end == CurveEnd::flat || r.fit.end == CurveEnd::bounded;
  if (!persisting || level_curve || !(d.share > kNeighbourDriftShare) || !r.unreliable.empty()) return;
  const char* unit = series.time_unit.empty() ? "sample" : series.time_unit.c_str();
  r.warnings.push_back(fmt::format(
      "the level of {} creeps beneath the neighbour pairs: the part of their separations that grows with their time "
      "apart makes {:.0f} % of the pairs' squared initial distance (above {:.0f} %; a stationary motion's stays below 1 %); the "
      "pairs see a creep of {:+.3g} per {} ({:+.2g} standard deviations over the series; a lower bound, since the "
      "search prefers pairs whose own separation offsets it). That offset neither grows nor decays, so lambda reads "
      "low (Roessler x plus 0.0002 t, 4 % of a deviation over the run: 20 % low): analyse a channel without the creep "
      "(a rate, a relative coordinate) or a run in which it has settled; removing a line fitted through the whole "
      "series is no sure cure: on a chaotic motion its slope is mostly the motion's own slow swings (stationary Lorenz "
      "x so treated reads 15 % low)",
      channel_name(series, d.channel), 100.0 * d.share, 100.0 * kNeighbourDriftShare, d.rate_per_sample / series.dt,
      unit, d.over_run_in_deviations));
}

/// How many of its own mean periods (the spectrum's, not the clamped one: a series of 1.5 periods
/// clamped to N/4 would otherwise be said to span 4) the series spans, and that period in samples.
struct Span {
  double own_period;  ///< samples
  double periods;
};
Span span_of(const Series& series, const MeanPeriodResult& mean_period) {
  const double f = mean_period.mean_frequency_per_sample;
  const double own_period = f > 0.0 ? 1.0 / f : static_cast<double>(mean_period.mean_period);
  return {own_period, static_cast<double>(series.size()) / own_period};
}

/// A series of fewer than 20 mean periods is warned about. Rosenstein's neighbours come from another
/// pass of the orbit, more than a mean period away (eq. 20). A motion that persists (neither decays
/// nor grows: its last third's RMS within a factor kPersistentAmplitude of its first third's) over
/// less than two of its mean periods has no second pass: the automatic window would be cut below
/// the period, and the "neighbours" are then points of the same pass (van der Pol over 1.5 cycles
/// read +0.43 1/s on its limit cycle, over 1.8 cycles -0.14). Refused rather than estimated. A decay
/// or a growth is a spiral whose later turns are the neighbours, and is estimated (a strongly damped
/// oscillator reaches its noise floor within 1.7 of its mean periods); an explicit window is the
/// user's decision.
void check_span(const Series& series, const MlceOptions& options, const Span& span, bool persisting,
                const std::string& series_warning, MlceResult& r) {
  if (r.mean_period.clamped || series.size() < 20 * r.mean_period.mean_period) {
    char text[160];
    std::snprintf(text, sizeof text, "the series spans only %.3g mean periods (%.0f samples each)", span.periods,
                  std::ceil(span.own_period));
    r.warnings.push_back(std::string(text) + ": too few for a reliable exponent; analyse a longer run");
  }
  if (options.theiler && span.periods < kMinMeanPeriods && persisting) {
    // The user's window stands, but what the refusal below guards against still holds: the
    // reading is not given on it (a decay dominated by a slow overdamped mode over 1.1 of its
    // "periods" read as a neutral limit cycle at lambda x period = -3.7).
    if (r.unreliable.empty()) r.unreliable = "fewer than two mean periods of a motion that persists";
    return;
  }
  if (span.periods < kMinMeanPeriods && persisting) {
    // The record's damped modes (modes.hpp) need no second pass: a linear motion's rate reads from a
    // period or less (bench/modal_accuracy short), which the analyst can still have.
    const std::string text = fmt::format(
        "series too short: {} samples span only {:.3g} mean periods ({:.0f} samples each, eq. 19) of a motion that "
        "persists; the nearest neighbours must come from another pass, more than a mean period away (eq. 20): at "
        "least {:.0f} samples needed (give --theiler N to override; the damped modes of a linear motion read its rate "
        "from so short a run: mlce modes)",
        series.size(), span.periods, std::ceil(span.own_period), std::ceil(kMinMeanPeriods * span.own_period));
    throw InputError(series_warning.empty() ? text : text + "; but " + series_warning);
  }
}

/// A delay vector should span about a mean period or less (the window (m-1)J that the AMI delay
/// and FNN dimension give: Lorenz x 36 samples of 171, Roessler x 0.5 of a period, maps 1-2
/// samples). Far beyond it, on a chaotic motion its first and last coordinates are as good as
/// independent: distances mix unrelated states, the neighbours are poor, and the curve can read
/// flat (Lorenz x with m = 100: 10 mean periods, "lambda" 0.015 against 0.91). Said, not changed.
void warn_about_window(MlceResult& r, double own_period) {
  const double window = static_cast<double>((r.dim - 1) * r.delay);
  if (window <= kMaxWindowPeriods * own_period) return;
  if (r.unreliable.empty()) r.unreliable = "an embedding window of several mean periods";
  r.warnings.push_back(fmt::format(
      "the embedding window (m-1)*delay = {:.0f} samples spans {:.3g} mean periods ({:.0f} samples each): its "
      "coordinates are too far apart in time to describe one state, and the exponent is unreliable; choose m and "
      "the delay so that (m-1)*delay is about one mean period or less",
      window, window / own_period, std::ceil(own_period)));
}

/// False nearest neighbours that stay at kStochasticFnnShare or more at every m: no deterministic
/// motion of up to FnnOptions::max_dim dimensions was reconstructed, and the pairs' separation is
/// that of a stochastic process (a random walk's curve rises and levels off as chaos does: "chaotic"
/// was read). Said, and lambda marked unreliable. Not on a signal that decays (signal_decays): a
/// decay's points shrink towards rest, Kennel's criteria judge them against the whole record's size,
/// and the decaying lags of the isotropic MBDyn run stay at 13.7-19.8 % false (its FNN warnings)
/// while the curve reads their eigenvalue (-1.178 for -1.183 1/s).
void warn_about_unfolding(MlceResult& r) {
  if (!r.fnn || r.fnn->reached_threshold || r.fnn->fraction.empty() || signal_decays(r)) return;
  const auto lowest = std::min_element(r.fnn->fraction.begin(), r.fnn->fraction.end());
  if (*lowest < kStochasticFnnShare) return;
  r.warnings.push_back(fmt::format(
      "false nearest neighbours stay at {:.3g} % or more at every m up to {} (lowest at m = {}): the series unfolds "
      "into no low-dimensional deterministic motion (noise, a stochastic process such as a random walk, or a motion "
      "of more dimensions than that), and lambda does not measure a divergence",
      100.0 * *lowest, r.fnn->fraction.size(), lowest - r.fnn->fraction.begin() + 1));
  if (r.unreliable.empty()) r.unreliable = "no low-dimensional deterministic reconstruction (false neighbours stay)";
}

/// The fit rule's period (FitOptions::period: its segments' and region's length) for a series of
/// several channels embedded jointly: the median of the channels' own mean periods (eq. 19 per
/// channel; of the two middle ones, their mean), while the Theiler window keeps eq. 19's fastest
/// channel. The rule's lengths were set on one channel's curve, whose period is its own; the state
/// (x, y, z) of Lorenz has eq. 19's period from z (77 samples, twice x's frequency by the attractor's
/// symmetry, against x's 171), over which the region stayed in the curve's steep start: 12 / 19 of 32
/// within 5 / 10 %, mean 1.087 lambda_1 (`build/finite_time_spread channels`, "embedded jointly");
/// with the median 25 / 31, mean 1.014, as x alone reads (in scratch builds, the slowest channel's
/// period read 18 / 30, mean 0.952, and the mean frequency's 20 / 26, mean 1.039). One channel: its
/// own period.
/// Never above the cap eq. 19's period is clamped to (MeanPeriodOptions::max_fraction of the
/// series); a period eq. 19 had to clamp already (the series spans few periods) is kept.
std::size_t fit_period(const MeanPeriodResult& mp, const MeanPeriodOptions& options, const Series& series,
                       std::size_t period) {
  std::vector<double> periods;  // samples, unrounded
  for (double f : mp.channel_frequency)
    if (f > 0.0 && std::isfinite(f)) periods.push_back(1.0 / (f * series.dt));
  if (periods.size() < 2 || mp.clamped) return period;
  std::sort(periods.begin(), periods.end());
  const std::size_t k = periods.size();
  const double middle = k % 2 == 1 ? periods[k / 2] : 0.5 * (periods[k / 2 - 1] + periods[k / 2]);
  const double cap = std::max(1.0, std::floor(options.max_fraction * static_cast<double>(series.size())));
  return std::max(period, static_cast<std::size_t>(std::min(std::ceil(middle - 1e-9), cap)));
}

/// The fit's options with what the series tells (sets r.envelope_rate, r.end_envelope_rate): its mean
/// period (fit_period); does the signal itself decay? (a curve that falls while it does not measures a contraction
/// onto a motion that persists, not lambda_1: FitOptions::signal_rate); does it still grow at its end?
/// (then its pairs have no attractor to saturate on: FitOptions::signal_end_rate); was a floor of its
/// own cut off? (FitOptions::signal_floor). Values the user set are kept.
FitOptions fit_options_for(const Series& series, const MlceOptions& options, std::size_t period, bool floor_cut,
                           MlceResult& r) {
  FitOptions fo = options.fit;
  if (fo.period == 0)  // a map's curve separates within iterations: its rule period (MeanPeriodResult::rule_period)
    fo.period = r.mean_period.map ? r.mean_period.rule_period() : fit_period(r.mean_period, options.mean_period, series, period);
  const EnvelopeRates envelope = envelope_rates(series, period);
  r.envelope_rate = envelope.whole, r.end_envelope_rate = envelope.end, r.envelope_rate_stderr = envelope.whole_stderr;
  if (std::isnan(r.envelope_rate)) {  // fewer than 8 mean periods: the reading's rate (reading.cpp, short_run_rate)
    const double repeats_every = whole_record_repeat(series).period;
    const double whole_period =
        std::isfinite(repeats_every) ? repeats_every : 1.0 / r.mean_period.mean_frequency_per_sample;
    r.ends_amplitude_rate = ends_amplitude_rate(series, whole_period);
    r.short_run_repeat = scaled_repeat(series, whole_period);
  }
  if (std::isnan(fo.signal_rate)) fo.signal_rate = r.envelope_rate;
  if (std::isnan(fo.signal_end_rate)) fo.signal_end_rate = r.end_envelope_rate;
  fo.signal_floor = fo.signal_floor || floor_cut;
  return fo;
}

/// White measurement noise per channel, in units of the analysed series' standard deviation (the
/// curve's units), from the third differences (white_increment_noise).
struct MeasuredNoise {
  std::vector<double> deviation;
  double level = 0.0;     ///< root mean square over the channels
  const char* where = "";  ///< over which stretch, in words
  /// Relative standard error of the measured mean square, sqrt(4.62 / k) for k third differences
  /// (kThirdDifferenceVarianceFactor).
  double variance_error = 0.0;
};

/// The noise the compensated curve takes out, measured over as much of the record as carries it at
/// one level: the record the analysed part was cut from (`record`: the floor a decay was cut at
/// included, where the noise is plainest) from steady_noise_start to its end, when that stretch is at
/// least the analysed part's last quarter long and its third differences are white; else over the
/// analysed part's last quarter, where the signal is least. The more samples, the closer: the
/// estimate's relative error falls as 1/sqrt(samples), and an error of the noise's share magnifies in
/// the compensated curve by share / (1 - share) (bench/noisy_decays, 64 slow noisy decays: 43 / 57
/// within 5 / 10 % over the record, 32 / 50 over the analysed part's last quarter alone). nullopt when
/// neither stretch is white.
std::optional<MeasuredNoise> measure_noise(const Series& record, const Series& analysed) {
  const std::size_t n = analysed.size(), N = record.size();
  MeasuredNoise out;
  std::vector<double> divisors;
  std::optional<IncrementNoise> noise;
  const std::size_t from = steady_noise_start(record);
  std::size_t differences = 0;
  if (N - from >= n / 4) noise = white_increment_noise(record, from, N, WhitenessTest::third_differences);
  if (noise) {
    differences = N - from - 4;  // N - from samples: N - from - 1 increments, 3 fewer third differences
    divisors = unit_deviation_divisors(analysed);
    out.where = from == 0 ? "the whole record's third differences" : "the record's third differences where they are steady";
  } else {
    // In the curve's units already: the test's leakage (omega dt)^6 is then relative to the same scale.
    noise = white_increment_noise(scaled_to_unit_deviation(analysed), n - n / 4, n, WhitenessTest::third_differences);
    if (!noise) return std::nullopt;
    differences = n / 4 - 4;
    divisors.assign(analysed.channels.size(), 1.0);
    out.where = "the last quarter's third differences";
  }
  double square = 0.0;
  for (std::size_t c = 0; c < divisors.size(); ++c) {
    out.deviation.push_back(noise->deviation[c] / divisors[c]);
    square += out.deviation.back() * out.deviation.back();
  }
  if (!(square > 0.0) || !std::isfinite(square)) return std::nullopt;
  out.level = std::sqrt(square / static_cast<double>(divisors.size()));
  out.variance_error = std::sqrt(kThirdDifferenceVarianceFactor / static_cast<double>(differences));
  return out;
}

/// The batch-means interval of a compensated curve's slope leaves out the error of the noise's measured
/// level: every batch's curve is compensated with the same level. Its part (r.noise_lambda_stderr) is
/// the slope's first-order change per relative error of the noise's mean square over the fit region
/// (noise_level_sensitivity) times that error's standard error; the interval's half-width becomes the
/// root sum of squares of the batches' and 1.96 of it (normal: the error is an average over thousands
/// of differences).
void widen_for_noise_error(double variance_error, MlceResult& r) {
  const double stderr_per_sample = std::abs(noise_level_sensitivity(r.curve, r.fit.first, r.fit.last)) * variance_error;
  r.noise_variance_error = variance_error;
  r.noise_lambda_stderr = stderr_per_sample / r.curve.dt;
  const double batches = 0.5 * (r.fit.ci_high - r.fit.ci_low);
  const double half = std::hypot(batches, 1.96 * stderr_per_sample);
  r.fit.ci_low = r.fit.slope - half;
  r.fit.ci_high = r.fit.slope + half;
}

/// A decay whose plain curve flag_noise found held up by measurement noise (its warning
/// r.warnings[flagged], r.noise_level set), when the noise is white (NoiseCompensation): the curve of
/// the same pairs recomputed noise-compensated (DivergenceCurve::compensated_log_distance), with the
/// noise measured by measure_noise over `record` (the input before the floor cut; the analysed series
/// itself when dithered, since the dither is part of its noise), and fitted late (fit.hpp's stage 2b',
/// its end set by the noise level's error, FitOptions::noise_variance_error).
/// follow_pairs computes eq. 23's curve again on the way (one more pass over the pairs, on flagged
/// noisy decays only).
/// The plain curve and its lambda are kept (plain_curve, uncompensated_lambda) and the flag's warning
/// says what was done instead of leaving lambda biased.
void compensate_noise(const Series& record, const Series& series, const MlceOptions& options,
                      const RosensteinOptions& ro, const NeighbourPairs& pairs, const FitOptions& fo,
                      std::size_t flagged_warning, MlceResult& r) {
  if (options.noise_compensation == NoiseCompensation::off || ro.align_phase || !signal_decays(r)) return;
  const auto noise = measure_noise(record, series);
  if (!noise) return;
  const double level = noise->level;
  RosensteinOptions with_noise = ro;
  with_noise.noise_deviation = noise->deviation;
  report(options, "noise-compensated curve", 0.0);
  DivergenceCurve c = follow_pairs(series, with_noise, pairs);
  std::string& flagged = r.warnings.at(flagged_warning);
  if (c.compensated_log_distance.empty()) {
    flagged += fmt::format(
        "; the noise measured from {} ({:.2g} % of the signal's standard deviation) exceeds the pairs' mean square "
        "distance at step {}: the curve cannot be compensated for it",
        noise->where, 100.0 * level, c.compensation_failed_step.value_or(0));
    return;
  }
  const double plain = r.fit.slope / series.dt;
  r.uncompensated_lambda = plain;
  r.plain_curve = std::move(r.curve.mean_log_distance);
  c.mean_log_distance = std::move(c.compensated_log_distance);
  c.batch_mean = std::move(c.compensated_batch_mean);
  c.compensated_log_distance.clear();
  c.compensated_batch_mean.clear();
  r.curve = std::move(c);
  FitOptions compensated = fo;
  compensated.noise_variance_error = noise->variance_error;
  r.fit = fit_divergence(r.curve, compensated);
  r.noise_compensated = true;
  r.noise_level = level;
  widen_for_noise_error(noise->variance_error, r);
  flagged = fmt::format(
      "plain curve (eq. 23, lambda {:.6g}): {}. The noise is white ({}: {:.2g} % of the "
      "signal's standard deviation), and lambda is read from the noise-compensated curve instead: the log of the "
      "pairs' mean square distance (each pair over its own mean along the curve) less the noise's share, halved "
      "(--noise-compensation off keeps the plain curve)",
      plain, flagged, noise->where, 100.0 * level);
}

/// The fitted slope per sample as lambda per time unit (eq. 23: y(i) / dt), with its interval, R^2 and
/// Lyapunov time; a slope beyond a double per time unit is an error naming the sampling step.
void express_per_time(MlceResult& r, double dt) {
  r.lambda_per_sample = r.fit.slope;
  r.lambda = r.fit.slope / dt;
  r.ci95_low = r.fit.ci_low / dt;
  r.ci95_high = r.fit.ci_high / dt;
  if (!std::isfinite(r.lambda) || !std::isfinite(r.ci95_low) || !std::isfinite(r.ci95_high)) {
    char what[200];
    std::snprintf(what, sizeof what,
                  "sampling step %.6g: the exponent, %.6g per sample, is beyond a double per unit time; give the "
                  "time in a larger unit",
                  dt, r.fit.slope);
    throw InputError(what);
  }
  r.r2 = r.fit.r2;
  r.lyapunov_time = r.lambda > 0 ? 1.0 / r.lambda : std::numeric_limits<double>::infinity();
}

/// A map settled on a cycle (map_cycle.hpp): lambda from its approach when the record shows it,
/// and a warning either way (the curve's neighbours are the cycle's other points).
void take_map_cycle(MlceResult& r) {
  const MapCycle& c = r.map_cycle;
  if (!c.found()) return;
  const std::string settled = fmt::format(
      "the series settles on a cycle of {} sample(s), repeating it from sample {} to its end (to {:g} of its range): "
      "a map's periodic orbit, whose nearest neighbours are the cycle's other points",
      c.period, c.from, c.tolerance);
  if (!c.approach_measured()) {
    r.warnings.push_back(fmt::format(
        "{}; the record shows no approach to it ({} whole cycle(s) between {:g} of the range and its resolution), so "
        "its exponent is not measured: lambda ({:.6g} per sample) is the divergence curve's and measures no "
        "divergence. A cycle computed in floating point that holds over {} steps is no unstable one (exponent at most "
        "{:.3g} per sample); start the record before the orbit settles to measure it",
        settled, c.approach_cycles, kApproachCeiling, r.lambda_per_sample, r.n_points - c.from - c.period,
        c.rate_bound));
    if (r.unreliable.empty()) r.unreliable = "a map settled on a cycle, with no approach to it in the record";
    return;
  }
  r.curve_lambda = r.lambda;
  r.lambda_per_sample = c.approach_rate;
  r.lambda = c.approach_rate / r.dt;
  r.ci95_low = c.approach_ci_low / r.dt;
  r.ci95_high = c.approach_ci_high / r.dt;
  r.r2 = c.approach_r2;
  r.lyapunov_time = r.lambda > 0 ? 1.0 / r.lambda : std::numeric_limits<double>::infinity();
  r.warnings.push_back(fmt::format(
      "{}; lambda is the cycle's exponent, read from the approach: ln |x(t + {}) - x(t)| falls at {:.6g} per sample "
      "(R^2 = {:.4f}) over samples {}..{} ({} whole cycles; a deviation from the cycle shrinks by its multiplier every "
      "cycle), not the divergence curve's slope ({:.6g} per sample)",
      settled, c.period, c.approach_rate, c.approach_r2, c.approach_first, c.approach_last, c.approach_cycles,
      r.curve_lambda * r.dt));
}

}  // namespace

Embedding choose_embedding(const Series& series, const MlceOptions& options, const MeanPeriodResult& mean_period) {
  Embedding e;
  e.theiler = options.theiler.value_or(mean_period.mean_period);  // eq. 20 with T from eq. 19
  if (options.delay) {
    e.delay = *options.delay;
  } else {
    report(options, "AMI delay", 0.0);
    AmiOptions ao = options.ami;
    ao.stop_at_minimum = true;
    if (ao.mean_period == 0) ao.mean_period = mean_period.rule_period(), ao.map = ao.map || mean_period.map;
    e.ami = estimate_delay_ami(series, ao);
    e.delay = e.ami->delay;
  }
  if (options.dim) {
    e.dim = *options.dim;
  } else {
    report(options, "FNN dimension", 0.0);
    FnnOptions fo = options.fnn;
    fo.stop_at_choice = true;
    if (fo.theiler == 0) fo.theiler = e.theiler;
    e.fnn = estimate_dimension_fnn(series, e.delay, fo);
    e.dim = e.fnn->dim;
  }
  return e;
}

namespace {
MlceResult estimate_once(const Series& raw, const MlceOptions& options);

/// lambda > 0 while the signal decays to rest: the reading's contradiction (reading.cpp), which in a
/// decay means neighbours that were never near in the motion's state.
bool grows_while_decaying(const MlceResult& r) {
  if (!(r.lambda > 0.0) || !r.unreliable.empty()) return false;
  const Reading reading = read_stability(r);
  return reading.stability == Stability::undetermined && reading.amplitude == AmplitudeTrend::decays;
}
}  // namespace

namespace {
MlceResult estimate_widened(const Series& raw, const MlceOptions& options);

/// The samples the estimate analysed: `raw` from its left-out start (MlceResult::skipped_start),
/// n_points long (up to a floor), every channel, not dithered.
Series analysed_samples(const Series& raw, const MlceResult& r) {
  Series s;
  s.dt = raw.dt, s.time_unit = raw.time_unit, s.names = raw.names, s.t0 = raw.time(r.skipped_start);
  const auto first = static_cast<std::ptrdiff_t>(r.skipped_start);
  for (const auto& c : raw.channels)
    s.channels.emplace_back(c.begin() + first, c.begin() + first + static_cast<std::ptrdiff_t>(r.n_points));
  return s;
}

/// The surrogate test (surrogate.hpp) on the part the estimate analysed: the raw series up to a
/// floor, from a left-out start (estimate_once); with the estimate's embedding and fit region. Not
/// dithered (MlceOptions::dither): the surrogates take the series' own values.
void test_against_surrogates(const Series& raw, const MlceOptions& options, MlceResult& r) {
  if (r.map_cycle.approach_measured()) {
    r.warnings.push_back("the surrogate test reads the divergence curve, and lambda is a map cycle's approach here; not run");
    return;
  }
  if (r.fit.last <= r.fit.first) {
    r.warnings.push_back("the surrogate test needs the divergence curve's fit region of two steps or more; not run");
    return;
  }
  const Series analysed = analysed_samples(raw, r);
  SurrogateSetup setup;
  setup.dim = r.dim, setup.delay = r.delay, setup.theiler = r.theiler;
  setup.first = r.fit.first, setup.last = r.fit.last, setup.max_references = options.max_references;
  setup.align_phase = r.curve.phase_aligned;
  if (options.surrogates.max_references > 0)
    setup.max_references = setup.max_references == 0 ? options.surrogates.max_references
                                                     : std::min(setup.max_references, options.surrogates.max_references);
  r.surrogates = surrogate_test(analysed, setup, options.surrogates, options.progress);
  append(r.warnings, r.surrogates->warnings);
}

/// Whether estimate_mlce tests the divergence against surrogates (MlceOptions::surrogates_when):
/// always, or where the curve alone would read chaos on a series the test can take (a fit region of
/// the curve, no map cycle's approach); never otherwise.
bool surrogate_test_wanted(const MlceOptions& options, const MlceResult& r) {
  switch (options.surrogates_when) {
    case SurrogateWhen::never:
      return false;
    case SurrogateWhen::always:
      return true;
    case SurrogateWhen::where_chaos_is_read:
      return !r.map_cycle.approach_measured() && r.fit.last > r.fit.first &&
             read_stability(r).motion == "chaotic";
  }
  return false;
}
}  // namespace

namespace {
/// MlceResult::carrier: the record's modes (no interval) when the automatic fit found a curve that
/// never separates for good on a sampled flow. A carrier holds SteadyCarrier::kMinShare of the record and
/// changes by at most kCarrierChange over it (|sigma| x the record's length: a limit cycle's
/// oscillation is as steady); the mode beneath grows at least kCarrierGrowth-fold over the record and
/// holds kCarrierGrowthShare of some quarter of it (ModalOptions::warn_share: below that a pole may be
/// the fit's). On the bundled and shared MBDyn runs (every node coordinate, the lags) only the
/// growing run's rotating blade coordinates have one; the 30 s limit-cycle run's 76 channels, the
/// ad-hoc limit cycles at 241, 249, 280, 300 rpm and with nonlinear dampers, van der Pol and a torus
/// have none (docs/checks.md, "Steady carrier").
constexpr double kCarrierChange = 0.1;
constexpr double kCarrierGrowth = 4.0;
constexpr double kCarrierGrowthShare = 1e-3;

std::optional<MlceResult::SteadyCarrier> steady_carrier(const Series& series, const MlceResult& r) {
  if (!r.fit.automatic || (r.fit.end != CurveEnd::bounded && r.fit.end != CurveEnd::flat) || r.mean_period.map)
    return std::nullopt;
  ModalOptions o;
  o.interval_replicates = 0;       // the modes, not lambda's interval
  o.read_leading_growth = false;   // nor a saturating growth's leading part
  ModalResult modal;
  try {
    modal = identify_modes(series, o);
  } catch (const InputError&) {  // too short for a pencil: no carrier to tell
    return std::nullopt;
  }
  if (!modal.linear) return std::nullopt;
  const double record = static_cast<double>(series.size()) * series.dt;
  const Mode* carrier = nullptr;
  for (const Mode& m : modal.modes)
    if (!m.offset && !m.nyquist && (!carrier || m.share > carrier->share)) carrier = &m;
  if (!carrier || carrier->frequency <= 0.0 || carrier->share < MlceResult::SteadyCarrier::kMinShare ||
      std::abs(carrier->sigma) * record > kCarrierChange)
    return std::nullopt;
  const Mode* growth = nullptr;
  for (const Mode& m : modal.modes)
    if (&m != carrier && !m.offset && !m.nyquist && m.sigma * record >= std::log(kCarrierGrowth) &&
        m.peak_share >= kCarrierGrowthShare && (!growth || m.peak_share > growth->peak_share))
      growth = &m;
  if (!growth) return std::nullopt;
  return MlceResult::SteadyCarrier{carrier->frequency, carrier->share, growth->sigma, growth->frequency,
                                   growth->peak_share};
}

/// MlceResult::record_modes: the analysed part's modes, with lambda's interval, where the curve cannot
/// tell the stability (a run of few mean periods; lambda against the amplitude's own change).
std::optional<MlceResult::RecordModes> modes_where_the_curve_cannot_tell(const Series& series, const MlceResult& r,
                                                                         const MlceOptions& options) {
  if (!options.record_modes || r.mean_period.map || r.in_decay_floor || !r.unreliable.empty()) return std::nullopt;
  const double periods = mean_periods_spanned(r);
  std::string why;
  if (periods < MlceResult::RecordModes::kFewPeriods) {
    why = fmt::format("a run of {:.3g} mean periods", periods);
  } else {
    // Only where the curve's own reading (default options) is one the modes may replace: a limit
    // cycle's lambda ~ 0 over an envelope that creeps either way (Hammond's in its unstable band, 10
    // of 34 points of `mlce sweep scenes/c3zero_242rpm.scene --param rpm=151:349:6`) is told already.
    const Reading curve = read_stability(r);
    const bool unconfirmed = neutral_unconfirmed(r, curve);
    if (!curve_cannot_tell(curve) && !unconfirmed) return std::nullopt;
    const AmplitudeTrend a = curve.amplitude;
    if (unconfirmed)
      why = "a neutral reading the curve does not confirm (a limit cycle that does not repeat itself)";
    else if (r.lambda > 0.0 && a == AmplitudeTrend::decays)
      why = "lambda > 0 while the amplitude decays";
    else if (r.lambda < 0.0 && a == AmplitudeTrend::grows)
      why = "lambda < 0 while the amplitude grows";
    else
      why = fmt::format("the divergence curve reads {}, {}", to_string(curve.stability), curve.motion);
  }
  ModalOptions o = *options.record_modes;
  o.progress = options.progress;  // lambda's interval: interval_replicates identifications
  ModalResult modal;
  try {
    modal = identify_modes(series, o);
  } catch (const InputError&) {  // too short for a pencil, or within a floor: nothing to tell
    return std::nullopt;
  }
  if (!modal.lambda) return std::nullopt;
  MlceResult::RecordModes m;
  m.lambda = *modal.lambda;
  if (modal.lambda_low && modal.lambda_high) m.ci95_low = *modal.lambda_low, m.ci95_high = *modal.lambda_high;
  m.frequency = modal.lambda_mode_frequency;
  if (modal.lambda_mode) m.share = modal.modes[*modal.lambda_mode].share;
  for (const Mode& mode : modal.modes) m.count += mode.offset ? 0 : 1;
  m.residual = modal.residual;
  m.noise_left = modal.noise_left;
  m.linear = modal.linear;
  m.halves_agree = modal.halves_agree;
  m.leading_part = modal.leading_part;
  m.few_periods = periods < MlceResult::RecordModes::kFewPeriods;
  m.why = std::move(why);
  return m;
}
}  // namespace

/// The estimate (estimate_widened: estimate_once at the automatic m, or at a wider one), a steady
/// carrier where its curve never separates, the surrogate test of its divergence when asked for
/// (MlceOptions::surrogates), then the record's modes where the curve cannot tell the stability.
MlceResult estimate_mlce(const Series& raw, const MlceOptions& options) {
  MlceResult r = estimate_widened(raw, options);
  const Series analysed = analysed_samples(raw, r);
  r.carrier = steady_carrier(analysed, r);
  if (surrogate_test_wanted(options, r)) test_against_surrogates(raw, options, r);
  // After the surrogate test, which the curve's reading takes into account.
  r.record_modes = modes_where_the_curve_cannot_tell(analysed, r, options);
  return r;
}

namespace {
/// FNN is Kennel's heuristic, and a decay of several modes can pass its threshold in fewer
/// dimensions than its modes need: two modes of like damping beating over 93.6 s (e^{-0.2 t}(cos 2 pi t
/// + cos 2.2 pi t)) leave 3.3 % false at m = 3, and there points of the same amplitude and another
/// beat phase are matched, separate to their common scale, and read lambda = +0.68 for -0.2. A
/// decay to rest cannot have neighbours that separate: when the automatic m reads lambda > 0 while
/// the signal decays, m + 1 .. m + kExtraDimensions are tried (the same delay), and the first that
/// reads no such contradiction is kept, with a warning; none: the first result stands.
///
/// Likewise a flow's attractor in fewer than three state dimensions is a fixed point or a limit
/// cycle (Poincare-Bendixson: no chaos in a plane), where neighbours do not keep separating. When the
/// automatic m gives a sampled flow (not MeanPeriodResult::map) a state of m x channels < 3
/// coordinates and its curve grows into a saturation plateau (lambda > 0), the estimate is redone
/// with the smallest m that gives three, with a warning. FNN's 5 % threshold passed m = 1 on 10 of
/// 32 jointly embedded Roessler (x, y) states (3.9-5.0 % false; `build/finite_time_spread channels`),
/// m = 2 on one Roessler x at c = 14 (`build/other_flows`) and on Lorenz x rounded to integers.
MlceResult estimate_widened(const Series& raw, const MlceOptions& options) {
  MlceResult r = estimate_once(raw, options);
  if (options.dim || !r.fnn) return r;
  // The estimate at m (the same delay), or nullopt when the series is too short for it.
  auto at_dimension = [&](std::size_t m) -> std::optional<MlceResult> {
    MlceOptions wider = options;
    wider.delay = r.delay;
    wider.dim = m;
    try {
      return estimate_once(raw, wider);
    } catch (const InputError&) {
      return std::nullopt;
    }
  };
  // The wider estimate t reported with FNN's own curves, the m FNN chose and why it was not used.
  auto widened = [&](MlceResult t, DimensionWidening why, std::string warning) {
    t.ami = std::move(r.ami), t.fnn = std::move(r.fnn), t.dim_widened_from = r.dim;
    t.dim_widened_because = why;
    t.warnings.insert(t.warnings.begin(), std::move(warning));
    return t;
  };
  if (const std::size_t channels = raw.channels.size();
      r.dim * channels < kMinChaoticFlowDimensions && !r.mean_period.map &&
      r.fit.end == CurveEnd::saturation && r.lambda_per_sample > 0.0) {
    const std::size_t m = (kMinChaoticFlowDimensions + channels - 1) / channels;
    if (m > options.fnn.max_dim) return r;  // beyond the largest m asked for, as the decay's widening
    auto t = at_dimension(m);
    if (!t) return r;  // too short for a larger m: the first result stands
    return widened(std::move(*t), DimensionWidening::flow_in_a_plane,
                   fmt::format("m = {} (false nearest neighbours) gives a state of {} coordinate(s), and its neighbours "
                               "separate up to the attractor's scale (lambda = {:+.4g} per sample): a flow of fewer "
                               "than 3 dimensions settles on fixed points and limit cycles only, where neighbours "
                               "do not keep separating (Poincare-Bendixson); m = {} used",
                               r.dim, r.dim * channels, r.lambda_per_sample, m));
  }
  if (!grows_while_decaying(r)) return r;
  constexpr std::size_t kExtraDimensions = 3;
  for (std::size_t m = r.dim + 1; m <= std::min(r.dim + kExtraDimensions, options.fnn.max_dim); ++m) {
    auto t = at_dimension(m);
    if (!t) break;  // too short for a larger m: the first result stands
    if (grows_while_decaying(*t)) continue;
    return widened(std::move(*t), DimensionWidening::growth_in_a_decay,
                   fmt::format("m = {} (false nearest neighbours) read lambda = {:+.4g} per sample while the signal "
                               "decays to rest: neighbours that separate in a decay were never near in its state, "
                               "a reconstruction too small for its modes; m = {} used",
                               r.dim, r.lambda_per_sample, m));
  }
  return r;
}
}  // namespace

namespace {
MlceResult estimate_once(const Series& raw, const MlceOptions& options) {
  validate_series(raw);
  MlceResult r;
  Series storage;
  AnalysedPart part;
  const Series& series = analysed_part(raw, options, storage, r.warnings, part);
  try {
    validate_series(series);
  } catch (const InputError& e) {  // a step onto a constant is "a floor": say which part is constant
    if (!part.floor_cut) throw;
    throw InputError(fmt::format("{} (the part analysed, samples 0..{}, ends where the floor rule cut the record: {})",
                                 e.what(), series.size() - 1, r.warnings.back()),
                     e.index());
  }
  if (options.delay && *options.delay == 0) throw OptionError("delay = 0: expected >= 1");
  if (options.dim && *options.dim == 0) throw OptionError("dim = 0: expected >= 1");
  if (options.horizon && *options.horizon < 2) throw OptionError("horizon: expected >= 2");
  if (options.record_modes) options.record_modes->validate();  // before the estimate, not after it
  r.n_points = series.size();
  const std::string series_warning = warn_about_series(series, r);
  // Neither decays nor grows: its last third's RMS within a factor kPersistentAmplitude of its
  // first third's (transient.hpp). Read by the floor-window test, the short-run refusal and the
  // recurrence test.
  r.amplitude_ratio = amplitude_ratio(series);
  warn_about_floor_window(series, options, part, r);
  const std::size_t input_warnings = r.warnings.size();  // about the input, before any stage
  r.dt = series.dt;
  r.time_unit = series.time_unit;

  report(options, "mean period", 0.0);
  r.mean_period = estimate_mean_period(series, options.mean_period);
  append(r.warnings, r.mean_period.warnings);
  const std::size_t period = r.mean_period.mean_period;
  const Span span = span_of(series, r.mean_period);
  r.end_repeat = end_repeat(series);
  if (r.mean_period.map) r.map_cycle = map_cycle(series, options.map_cycle);
  const bool persisting = persists(r.amplitude_ratio);
  check_span(series, options, span, persisting, series_warning, r);
  Embedding e = choose_embedding(series, options, r.mean_period);
  r.theiler = e.theiler, r.delay = e.delay, r.dim = e.dim;
  r.ami = std::move(e.ami), r.fnn = std::move(e.fnn);

  // A start that does not recur is a transient, not the attractor (recurrence.hpp): left out, and
  // the whole estimate (mean period, embedding, curve) redone on the rest, as with --from. Only
  // for a motion that persists: a decay's or a growth's turns are each visited once, and are what
  // it measures. Judged on the first curve's neighbour pairs (no search of its own).
  // Not a map's approach to its cycle: that approach is what measures the cycle's exponent.
  const bool judge_start = options.skip_nonrecurrent_start && persisting && !r.map_cycle.found();
  auto estimate_without_start = [&](const NeighbourPairs& first_pairs) -> std::optional<MlceResult> {
    const std::size_t admissible = DelayEmbedding::max_points(series.size(), r.dim, r.delay) - first_pairs.horizon;
    std::vector<std::span<const double>> channels(series.channels.begin(), series.channels.end());
    const DelayEmbedding embedding(std::move(channels), r.dim, r.delay, admissible);
    RecurrenceResult rec = recurrent_start(first_pairs, admissible, options.recurrence, &embedding);
    if (rec.start == 0) {
      r.recurrence = std::move(rec);
      return std::nullopt;
    }
    Series rest;
    rest.dt = series.dt, rest.time_unit = series.time_unit, rest.names = series.names;
    rest.t0 = series.time(rec.start);
    for (const auto& c : series.channels) rest.channels.emplace_back(c.begin() + static_cast<std::ptrdiff_t>(rec.start), c.end());
    MlceOptions again = options;
    again.skip_nonrecurrent_start = false;
    again.dither = 0.0;  // already dithered
    MlceResult out;
    try {
      // Not estimate_mlce: the surrogate test and the carrier are judged once, on the whole
      // estimate's analysed samples (estimate_mlce); they ran twice here before.
      out = estimate_widened(rest, again);
    } catch (const InputError& too_short) {  // the rest (at least half) re-embedded may still be refused
      r.warnings.push_back("the first " + std::to_string(rec.start) +
                           " samples do not recur, but the rest alone cannot be estimated (" + too_short.what() +
                           "): the whole series is analysed, start-up included");
      r.recurrence = std::move(rec);
      return std::nullopt;
    }
    // Why: the scores' reason (neighbours among themselves) or the distance test's.
    const std::string why =
        rec.by_distance
            ? fmt::format("the series' second half comes no nearer to them than {:.3g} times its typical distance",
                          *std::min_element(rec.distance_ratio.begin(), rec.distance_ratio.end() - 1))
            : std::string("their nearest neighbours lie among themselves");
    const std::string text = fmt::format(
        "the first {} samples (to t = {:.6g}) do not recur: {} (a start-up transient, not the attractor); analysed "
        "from there (the start's first window scores {:.2f}, 1 on the attractor; --keep-start keeps them)",
        rec.start, rest.t0, why, rec.ratio.front());
    // The input's warnings once; the drift is judged again on the rest, which is what is analysed.
    std::vector<std::string> warnings;
    for (std::size_t w = 0; w < input_warnings; ++w)
      if (r.warnings[w] != series_warning) warnings.push_back(r.warnings[w]);
    warnings.push_back(text);
    append(warnings, out.warnings);
    out.warnings = std::move(warnings);
    out.skipped_start = rec.start;
    out.recurrence = std::move(rec);
    return out;
  };
  if (r.ami) append(r.warnings, r.ami->warnings);
  if (r.fnn) append(r.warnings, r.fnn->warnings);
  warn_about_window(r, span.own_period);

  RosensteinOptions ro;
  ro.dim = r.dim;
  ro.delay = r.delay;
  ro.theiler = r.theiler;
  ro.max_references = options.max_references;
  ro.eps = options.eps;
  const FitOptions fo = fit_options_for(series, options, period, part.floor_cut, r);
  r.fit_options = fo;

  const std::size_t M = DelayEmbedding::max_points(series.size(), r.dim, r.delay);
  NeighbourPairs pairs;  // of the last curve: the phase-aligned curve follows the same pairs
  if (options.horizon) {
    ro.horizon = *options.horizon;
    report(options, "divergence curve", 0.0);
    pairs = find_pairs(series, ro);
    if (judge_start)
      if (auto rest = estimate_without_start(pairs)) return std::move(*rest);
    r.curve = follow_pairs(series, ro, pairs);
    r.fit = fit_divergence(r.curve, fo);
  } else {
    // Adaptive horizon: double until the fit rule sees the curve's end, within a third of the points.
    const std::size_t room = M > r.theiler + 2 ? (M - r.theiler - 2) / 3 : 0;
    const std::size_t h_max = std::min(room, std::max<std::size_t>(64 * period, 256));
    constexpr std::size_t h_min = 8;
    if (h_max < h_min) {
      throw InputError("series too short: " + std::to_string(series.size()) + " samples, but m = " +
                       std::to_string(r.dim) + ", delay = " + std::to_string(r.delay) + " and Theiler window = " +
                       std::to_string(r.theiler) + " leave room for a divergence curve of only " +
                       std::to_string(h_max) + " steps (at least " + std::to_string(h_min) + " needed: about " +
                       std::to_string((r.dim - 1) * r.delay + 3 * h_min + r.theiler + 2) + " samples)");
    }
    std::size_t h = std::clamp<std::size_t>(8 * period, 32, h_max);
    ro.horizon = h;
    const PairFinder finder(series, ro);  // one kd-tree for every doubling
    // A signal that decays to rest by more than kRecordDecay over the series (and signal_decays): its
    // pairs converge with it, and a curve that "saturates" within a horizon over which the signal
    // itself has not fallen by an e-fold shows only its start-up and the beat of its modes, not a
    // divergence that saturated (Hammond at 124 rpm, blade 3 inoperative, y_h from 0 to 60 s: a plateau
    // at step 120 of 640, read undetermined at -0.75 1/s; at 1280 steps -0.247, Floquet -0.2285).
    // Such a curve is followed further, as one that shows no end. A stationary motion's envelope
    // (chaos, a limit cycle) changes by far less than kRecordDecay over its record.
    const double record_decay = -fo.signal_rate * static_cast<double>(series.size());
    const bool decays_to_rest = signal_decays(r) && record_decay >= std::log(kRecordDecay);
    for (int pass = 0;; ++pass) {
      ro.horizon = h;
      report(options, "divergence curve", static_cast<double>(h) / static_cast<double>(h_max));
      pairs = finder.find(h);
      if (pass == 0 && judge_start)
        if (auto rest = estimate_without_start(pairs)) return std::move(*rest);
      r.curve = follow_pairs(series, ro, pairs);
      r.fit = fit_divergence(r.curve, fo);
      const bool decay_unresolved = decays_to_rest && r.fit.end == CurveEnd::saturation &&
                                    -fo.signal_rate * static_cast<double>(h) < 1.0;
      // A bounded curve is read at the longest horizon: its slope tends to 0 as the horizon grows.
      if (options.fit.range || (r.fit.end != CurveEnd::none && r.fit.end != CurveEnd::bounded && !decay_unresolved) ||
          h >= h_max)
        break;
      h = std::min(2 * h, h_max);
    }
    if (r.fit.end == CurveEnd::none && r.fit.slope > 0 && r.fit.last + 1 >= r.curve.mean_log_distance.size())
      r.warnings.push_back("the divergence curve still rises at the largest horizon (" + std::to_string(h_max) +
                           " steps): no saturation seen, the slope may underestimate lambda");
  }
  // Sampled flows: the part of a neighbour's initial separation along the flow belongs to the
  // flow's zero exponent and aligns with the unstable direction only at the rate lambda_1 - 0, so
  // where lambda_1 is small against the saturation (Roessler) it holds the whole curve's slope below
  // lambda_1. A curve that grows into a saturation plateau is therefore recomputed, at the same
  // horizon, with every neighbour moved along its own trajectory to the sub-sample phase closest to
  // its reference (RosensteinOptions::align_phase), and fitted by the same rule. Limit cycles and
  // decays keep the plain curve: their separation is mostly along the flow, which is what they measure.
  const bool sampled_flow = !r.mean_period.map;
  const bool align = options.phase_alignment == PhaseAlignment::on ||
                     (options.phase_alignment == PhaseAlignment::automatic && sampled_flow && !options.fit.range &&
                      r.fit.end == CurveEnd::saturation && r.fit.slope > 0.0);
  if (align) {
    r.unaligned_lambda = r.fit.slope / series.dt;
    r.plain_curve = r.curve.mean_log_distance;
    ro.align_phase = true;
    ro.interpolation = options.phase_interpolation;
    report(options, "phase-aligned curve", 0.0);
    r.curve = follow_pairs(series, ro, pairs);
    r.fit = fit_divergence(r.curve, fo);
  }
  r.horizon = ro.horizon;
  r.neighbour_drift = neighbour_drift(series, pairs);
  warn_about_neighbour_drift(series, persisting, r);
  if (r.curve.pairs < kFewPairs)
    r.warnings.push_back("the divergence curve averages only " + std::to_string(r.curve.pairs) +
                         " neighbour pair(s) (fewer than " + std::to_string(kFewPairs) +
                         "): its mean log distance and the 95 % interval rest on too few pairs; " +
                         (options.max_references > 0 && options.max_references < kFewPairs
                              ? "use more reference points (--refs)"
                              : "analyse a longer series"));
  if (const auto flagged = flag_noise(r, series.channels.size()))
    compensate_noise(options.dither > 0.0 ? series : raw, series, options, ro, pairs, fo, *flagged, r);
  append(r.warnings, r.curve.warnings);
  // Distances that jump in steps of the series' quantum measure the quantisation, not a divergence:
  // the real MBDyn isotropic run's rel:11:4:z from 10 s, steps of its written 1e-5 deg about 0, read
  // "chaotic" at +201 1/s before its resolution floor was known; from 8 s, the last of the decay and
  // then those steps, it reads +214 1/s: undetermined by this rule. Not a curve that falls on a
  // signal that decays: quanta do not make distances shrink with the amplitude, and the decay is read
  // (a quantised e^{-t/2} sin 2 pi t a few quanta above 0 still reads -0.495 1/s).
  if (r.curve.coarse_resolution && r.unreliable.empty() && !(r.fit.slope < 0.0 && signal_decays(r)))
    r.unreliable = "a resolution (quantum or printed digits) as coarse as the neighbour distances";
  append(r.warnings, r.fit.warnings);
  warn_about_unfolding(r);  // after the curve's own verdicts, which name the cause more closely
  flag_map_noise(series, ro, pairs, r);  // after every verdict that makes lambda unreliable
  warn_about_rate_beyond_envelope(r);
  express_per_time(r, series.dt);
  take_map_cycle(r);
  report(options, "done", 1.0);
  return r;
}
}  // namespace

}  // namespace mlce
