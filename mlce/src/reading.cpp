#include "mlce/reading.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "mlce/series.hpp"
#include "mlce/transient.hpp"

namespace mlce {

const char* to_string(Stability s) {
  switch (s) {
    case Stability::stable: return "stable";
    case Stability::neutral: return "neutral";
    case Stability::unstable: return "unstable";
    case Stability::undetermined: break;
  }
  return "undetermined";
}

const char* to_string(AmplitudeTrend a) {
  switch (a) {
    case AmplitudeTrend::decays: return "decays";
    case AmplitudeTrend::persists: return "persists";
    case AmplitudeTrend::grows: return "grows";
    case AmplitudeTrend::changes: return "changes";
    case AmplitudeTrend::unknown: break;
  }
  return "unknown";
}

void ReadingOptions::validate() const {
  if (!(neutral_per_period >= 0.0) || !std::isfinite(neutral_per_period))
    throw OptionError("reading.neutral_per_period: expected a finite value >= 0");
  if (!(persist_share > 0.0 && persist_share < 1.0)) throw OptionError("reading.persist_share: expected (0, 1)");
  if (!(steady_share > 0.0 && steady_share < persist_share))
    throw OptionError("reading.steady_share: expected (0, persist_share)");
  if (!(chaos_scale_margin > 0.0)) throw OptionError("reading.chaos_scale_margin: expected > 0");
  if (!(periodic_end >= 0.0 && periodic_end < 1.0)) throw OptionError("reading.periodic_end: expected [0, 1)");
}

namespace {

/// A fall of the amplitude against lambda > 0 is the signal's own when its envelope line lies this many
/// standard errors below zero, or its last third's RMS is at most kClearFall of its first's (half the
/// energy). A chaotic flow's envelope windows wander: over the 280 segments of Lorenz x and Roessler x
/// of bench/chaos_readings.sh (2000-10^4 samples) the line's t lies within -2.92 .. +2.89; a decay's
/// lies hundreds of standard errors out unless a beat scatters its windows.
constexpr double kSignificantFall = 4.0;
constexpr double kClearFall = 0.7071067811865476;  // 1 / sqrt 2

/// The amplitude's rate (per time unit) on a run too short for envelope_rate's windows (fewer than
/// 8 mean periods): its change between its first and last whole periods (ends_amplitude_rate), or,
/// under 2 mean periods, the one the RMS ratio of its thirds says (their centres 2/3 of the run
/// apart). NaN when neither is known. A decay at -0.005 1/s over 8 periods (e^{-0.005 t} cos t,
/// dt = 0.005, 10^4 samples) was measured exactly by lambda and read as a limit cycle (its curve is
/// flat, and the amplitude counted as steady); a growth at +0.005 1/s over 4.8 periods likewise
/// while its rate came from the thirds, whose partial periods halve it (+0.0020; whole periods
/// +0.0050: bench/oscillator_readings.sh growths).
double short_run_rate(const MlceResult& r) {
  if (std::isfinite(r.ends_amplitude_rate)) return r.ends_amplitude_rate / r.dt;
  const double span = 2.0 / 3.0 * static_cast<double>(r.n_points) * r.dt;
  return r.amplitude_ratio > 0.0 && span > 0.0 ? std::log(r.amplitude_ratio) / span
                                               : std::numeric_limits<double>::quiet_NaN();
}

/// The amplitude's own trend over the run, judged against lambda: the RMS ratio of the run's thirds
/// catches a change over the run, the envelope rate (per time unit) one as fast as the exponent.
/// Steady: neither changes, the rate below steady_share x |lambda| or below the neutral band per
/// mean period (chaos: Lorenz x and Roessler x below 0.005 |lambda|; Hammond's limit cycles, blade 3
/// inoperative, below 0.07). Grows (decays): the ratio is kPersistentAmplitude or more (or 1/that or
/// less), or the rate is at least persist_share x lambda of the same sign (the bundled growing
/// MBDyn run's blade lags: 0.65-1.08; a decay: 1.3). In between: it changes (the same run's hub x,
/// a decaying start and a growth: 0.38, ratio 0.75).
AmplitudeTrend amplitude_trend(const MlceResult& r, double T, const ReadingOptions& o) {
  const double ratio = r.amplitude_ratio;
  const double rate = std::isfinite(r.envelope_rate) ? r.envelope_rate / r.dt  // per time unit, like lambda
                                                     : short_run_rate(r);
  const double lambda = r.lambda;
  if (std::isnan(ratio) && std::isnan(rate)) return AmplitudeTrend::unknown;
  // A rate within the neutral band per mean period is no trend, whatever lambda (a torus: lambda
  // and the rate both ~1e-4 per period).
  const bool beyond_band = std::abs(rate) * T > o.neutral_per_period;
  if (ratio >= kPersistentAmplitude || (beyond_band && lambda > 0.0 && rate >= o.persist_share * lambda))
    return AmplitudeTrend::grows;
  if (ratio <= 1.0 / kPersistentAmplitude || (beyond_band && lambda < 0.0 && rate <= o.persist_share * lambda))
    return AmplitudeTrend::decays;
  // An amplitude that falls over the run (rate beyond the band, last third smaller than the first)
  // while lambda > 0 decays, however slowly against lambda: the two disagree in sign, which the
  // reading must say rather than take the fall for "a growth or chaos". Two decaying modes beating
  // (e^{-0.02 t} cos 2t + e^{-0.05 t} cos 2.4t over 40 s: rate -0.022, ratio 0.53) read +0.215, the
  // pairs' transient growth while the modes dephase (close frequencies have nearly parallel directions
  // in delay coordinates, so the nearest neighbours are near-cancellations), and were "unstable".
  // The fall must be the signal's, not a chaotic amplitude's wander (kSignificantFall, kClearFall):
  // Lorenz x over 20-50 s tilts its envelope by -0.009..-0.065 1/s by chance and read "undetermined,
  // lambda > 0 while the amplitude decays" on 14 of 120 segments (bench/chaos_readings.sh); the
  // beating decays above keep their fall by the ratio (their line's t is -1.5: the beat scatters the
  // windows). Only here: a rate beyond steady_share x lambda within the scatter stays a change (below),
  // as an amplitude that falls and then grows again must (Hammond's failed-damper rotor, x_h over
  // 0-10 s: its straight line's t is +1.5).
  const bool significant = !(std::isfinite(r.envelope_rate_stderr) && r.envelope_rate_stderr > 0.0) ||
                           r.envelope_rate <= -kSignificantFall * r.envelope_rate_stderr;  // no scatter known: as before
  if (beyond_band && lambda > 0.0 && rate < 0.0 && ratio < 1.0 && (significant || ratio <= kClearFall))
    return AmplitudeTrend::decays;
  if (std::isnan(rate) || std::abs(rate) <= o.steady_share * std::abs(lambda) || !beyond_band)
    return AmplitudeTrend::persists;
  return AmplitudeTrend::changes;
}

/// A record that repeats itself one period on, scaled, to within this (ScaledRepeat::difference) is
/// one mode. e^{-0.02 omega t} sin(omega t) over 4.5 periods leaves the interpolation's residual,
/// 1e-4 .. 2e-3 at 20-200 samples per period; with white noise of 1 % (3 %) of its amplitude 0.025
/// (0.077) (scratch: Python-written series through mlce estimate --json). Two tones of unrelated frequencies leave 0.14 and more (sin t + a sin(r t + 0.3), r = sqrt 2,
/// golden ratio, sqrt 5, 1 / sqrt 2, a = 0.2 and 0.5, 15-40 s).
constexpr double kOneModeRepeat = 0.1;

/// A decay that stops: the envelope of the signal's second half changes at most kSettledShare of
/// the whole run's (negative) rate, and its last third repeats itself one period on
/// (ReadingOptions::periodic_end; flows only). Hammond's rotor with nonlinear dampers of zero slope
/// (scenes/nonlinear_CL0.scene, 60 s; blade 3's lag): 0.0088 of the run's rate, repeating to 0.5 %,
/// read "lightly damped" before (test_reading prints it). A linear decay keeps its rate to the end
/// (share ~1).
constexpr double kSettledShare = 0.1;
bool settles_onto_a_cycle(const MlceResult& r, const ReadingOptions& options) {
  return !r.mean_period.map && r.envelope_rate < 0.0 && std::isfinite(r.end_envelope_rate) &&
         std::abs(r.end_envelope_rate) <= kSettledShare * std::abs(r.envelope_rate) &&
         r.end_repeat.difference < options.periodic_end;
}

/// How far the curve's highest point stays below the attractor scale, natural log (NaN when either
/// is missing: NaN compares false, and the reading keeps its other rules).
double below_attractor_scale(const DivergenceCurve& curve) {
  const auto& y = curve.mean_log_distance;
  if (y.empty()) return std::numeric_limits<double>::quiet_NaN();
  return curve.attractor_log_distance - *std::max_element(y.begin(), y.end());
}

}  // namespace

namespace {
/// ", on its first N of M samples" where the surrogate test ran on a leading segment.
std::string surrogate_segment(const SurrogateTest& t) {
  const std::string words = segment_words(t);
  return words.empty() ? words : ", on its " + words;
}

/// `base` read undetermined, the summary saying why.
Reading undetermined_reading(Reading base, const std::string& why) {
  base.stability = Stability::undetermined;
  base.motion = "undetermined";
  base.summary = "undetermined: " + why;
  return base;
}

Reading read_from_curve(const MlceResult& r, const ReadingOptions& options) {
  Reading out;
  const double f = r.mean_period.mean_frequency;  // cycles per time unit, unclamped
  out.mean_period = f > 0.0 && std::isfinite(f) ? 1.0 / f : std::numeric_limits<double>::quiet_NaN();
  const double T = out.mean_period;
  out.lambda_per_period = r.lambda * T;
  out.ci_low_per_period = r.ci95_low * T;
  out.ci_high_per_period = r.ci95_high * T;
  out.amplitude = amplitude_trend(r, T, options);
  const double band = out.neutral_per_period = options.neutral_per_period;
  const std::string numbers =
      fmt::format("lambda x mean period = {:+.3g} (95 % interval {:+.3g} .. {:+.3g}; neutral within +-{:g})",
                  out.lambda_per_period, out.ci_low_per_period, out.ci_high_per_period, band);

  auto undetermined = [&](const std::string& why) { return undetermined_reading(out, why); };
  // A window cut from a record after the record's decay ended (MlceResult::in_decay_floor): the
  // motion had come to rest, by six orders of magnitude or more, before the window; its lambda
  // measures the solver's residue (Hammond's isotropic rotor at 200 rpm from 20 s on: +0.3..+0.9 1/s,
  // read "chaotic" before this clause).
  if (r.in_decay_floor) {
    out.stability = Stability::stable;
    out.motion = "decays to rest";
    out.summary = fmt::format(
        "stable: the motion had decayed to rest before the analysed window, which holds only the floor of that "
        "decay ({:.2g} of the record's largest deviation: solver tolerance, rounding or the written resolution); "
        "lambda measures that residue, not the motion (analyse the decay: an earlier --from); {}",
        r.floor_window_ratio, numbers);
    return out;
  }
  if (!std::isfinite(T)) return undetermined("the spectrum has no mean frequency to measure the rate against");
  // A map settled on a cycle (map_cycle.hpp): a periodic orbit without a neutral direction, read from
  // its approach when the record shows one. The logistic map's cycles as `build/make_series logistic
  // 10000 R` writes them read "neutral, limit cycle" at r = 3.5 and 3.74 and "undetermined" at r = 3.2
  // and 3.83 (lambda 0 and +0.234 per iteration) before this clause; the cycles' exponents are -0.916,
  // -0.873, -0.112 and -0.370 (test_map_cycle).
  if (const MapCycle& c = r.map_cycle; c.found()) {
    out.motion = "periodic orbit";
    const std::string cycle = fmt::format("a map settled on a cycle of {} sample(s) (it repeats from sample {} on)",
                                          c.period, c.from);
    if (!c.approach_measured()) {
      out.stability = Stability::stable;
      out.summary = fmt::format(
          "stable: {}; the record shows no approach to it, so the cycle's exponent is not measured and lambda, the "
          "divergence curve's, measures no divergence; but a cycle computed in floating point that holds over {} steps "
          "is no unstable one (its exponent is at most {:.3g} per sample), and a map's cycle is neutral only at "
          "isolated parameters: it attracts (start the record before the orbit settles to measure its rate)",
          cycle, r.n_points - c.from - c.period, c.rate_bound);
      return out;
    }
    const std::string from_approach = fmt::format(
        "{}; lambda is its exponent, read from the approach (ln |x(t + {}) - x(t)| over samples {}..{}); {}", cycle,
        c.period, c.approach_first, c.approach_last, numbers);
    if (out.ci_high_per_period < -band) {
      out.stability = Stability::stable;
      out.summary = "stable: the cycle attracts: " + from_approach;
    } else if (out.ci_low_per_period > band) {
      return undetermined("the approach to the cycle grows: " + from_approach);
    } else {
      out.stability = Stability::neutral;
      out.summary = "neutral: the approach is slower than the band resolves: " + from_approach;
    }
    return out;
  }
  if (!r.unreliable.empty()) return undetermined(r.unreliable + ": lambda does not measure a divergence (see the warnings)");
  // Measurement noise biases lambda (the warnings say how much) but does not make a clear sign
  // unclear: the reading stands, and says so.
  const std::string noise =
      r.noise_compensated ? fmt::format("; white measurement noise (~{:.2g} % of the signal's standard deviation) "
                                        "taken out of the divergence curve (noise-compensated)",
                                        100.0 * r.noise_level)
      : std::isfinite(r.noise_level)
          ? fmt::format("; measurement noise (~{:.2g} % of the signal's standard deviation) biases lambda",
                        100.0 * r.noise_level)
          : std::string();

  const AmplitudeTrend a = out.amplitude;
  // Noise flagged on a curve that grows to no plateau (estimate.cpp, first_step_jumps_to_level)
  // holds the curve level: a decay slower than the noise resolves reads closer to 0 than it is
  // (e^{-0.025 t} cos 2 pi t plus 1 % noise: -0.0024 1/s, within the band). Where the interval
  // does not already say stable, the signal's own decay does: the motion is itself a perturbation
  // of its equilibrium, and it dies out.
  // Not when the curve was noise-compensated (estimate.hpp, NoiseCompensation): then lambda is the rate.
  const bool held_by_noise = std::isfinite(r.noise_level) && !r.noise_compensated &&
                             r.fit.end != CurveEnd::saturation && r.fit.end != CurveEnd::floor;
  if (held_by_noise && a == AmplitudeTrend::decays && !(out.ci_high_per_period < -band)) {
    out.stability = Stability::stable;
    out.motion = "decays to rest";
    out.summary = fmt::format(
        "stable: the amplitude decays (envelope rate x mean period = {:+.3g}, the last third's RMS {:.3g} of the "
        "first's): the motion dies out; measurement noise (~{:.2g} % of the signal's standard deviation, if white) or "
        "motion the embedding does not resolve holds the divergence curve level, so lambda is biased towards 0 and is "
        "not that rate; {}",
        r.envelope_rate / r.dt * T, r.amplitude_ratio, 100.0 * r.noise_level, numbers);
    return out;
  }
  // The fit rule's own finding that the neighbours never separate for good (a bounded
  // or flat curve, fit.hpp) is the limit cycle's signature, whatever residual slope was fitted
  // (Hammond at 300 rpm, blade 3 inoperative, on its limit cycle: +0.055 per period on a bounded
  // curve). Not when the motion decays to rest, nor when it grows at a rate the interval places above
  // the band: then the interval decides. A slow growth's curve rises by less than the bounded and
  // flat tests' 0.25 over its horizon (e^{0.05 t} cos 2 pi t over 30 s: lambda 0.0500 on a "bounded"
  // curve, read neutral until this clause), and a growing oscillation is the instability itself.
  const bool never_separate = r.fit.automatic && (r.fit.end == CurveEnd::bounded || r.fit.end == CurveEnd::flat);
  // A run of a few periods (fewer than 8: no envelope rate) whose neighbours never separate has no
  // divergence to measure: its neighbours lie a fraction of a period apart and the curve swings with
  // their phase, so the fitted slope is that swing's residue, not a rate. When the record is one
  // mode (it repeats itself one period on, scaled, to within kOneModeRepeat) the amplitude's change
  // between its first and last whole periods is that mode's rate, its exponent: beyond the band it
  // decides. e^{-0.005 t} cos t over 2.4 periods read "neutral, limit cycle" with lambda = -0.42, the
  // residue (bench/oscillator_readings.sh: 8 of 560 damped records); its ends say -0.005, 0.031 per
  // period. A limit cycle repeats with scale 1 (van der Pol over 2.25 periods: 1e-6 per period); two
  // modes (a beat, a torus) do not repeat and keep the rules below.
  const double ends_rate = r.ends_amplitude_rate / r.dt * T;  // per mean period
  if (never_separate && std::isnan(r.envelope_rate) && r.short_run_repeat.difference < kOneModeRepeat &&
      std::abs(ends_rate) > band) {
    const bool grows = ends_rate > 0.0;
    out.amplitude = grows ? AmplitudeTrend::grows : AmplitudeTrend::decays;
    out.stability = grows ? Stability::unstable : Stability::stable;
    out.motion = grows ? "growing oscillation" : "decays to rest";
    out.summary = fmt::format(
        "{}: over this short run ({:.3g} mean periods) the neighbours never separate (curve end: {}), and the "
        "motion is one mode (it repeats itself one period on, scaled, to {:.2g} %) whose amplitude {} by {:+.3g} per "
        "mean period between its first and last whole periods, beyond the band: {}; lambda is the swing's residue "
        "here, not that rate; {}",
        grows ? "unstable" : "stable", mean_periods_spanned(r), to_string(r.fit.end),
        100.0 * r.short_run_repeat.difference, grows ? "grows" : "decays", ends_rate,
        grows ? "a growing oscillation (an instability)" : "it decays to rest (exponentially stable)", numbers + noise);
    return out;
  }
  const bool growth_beyond_band = a == AmplitudeTrend::grows && out.ci_low_per_period > band;
  // A curve that never separates because a steady carrier keeps the neighbours close, over a mode
  // that grows beneath it (MlceResult::carrier): the record's modes show the growth the curve and
  // the amplitude do not. The bundled growing MBDyn run's blade coordinates node:12:y and node:13:vx
  // read "neutral, limit cycle" before this clause; their modes grow at +0.306 and +0.308 1/s
  // (Floquet +0.2985).
  if (never_separate && a != AmplitudeTrend::decays && r.carrier) {
    const auto& c = *r.carrier;
    const double record = static_cast<double>(r.n_points) * r.dt;
    const std::string unit = r.time_unit.empty() ? std::string("sample") : r.time_unit;
    out.stability = Stability::unstable;  // out.amplitude stays the signal's: the carrier's, steady
    out.motion = "growth beneath a steady carrier";
    out.summary = fmt::format(
        "unstable: the neighbours never separate for good (curve end: {}), but {:.3g} % of the signal is one steady "
        "oscillation ({:.4g} cycles per {}: a rotating part's absolute coordinate carries the rotation so), and "
        "beneath it a mode grows at {:+.4g} 1/{} ({:.4g} cycles per {}), {:.3g}-fold over the record, which the "
        "carrier keeps from the curve and the amplitude (the record's damped modes: mlce modes); lambda is not that "
        "rate: analyse a channel relative to the rotating part; {}",
        to_string(r.fit.end), 100.0 * c.share, c.frequency, unit, c.growth_rate, unit, c.growth_frequency, unit,
        std::exp(c.growth_rate * record), numbers + noise);
    return out;
  }
  if (never_separate && a != AmplitudeTrend::decays && !growth_beyond_band) {
    out.stability = Stability::neutral;
    out.motion = a == AmplitudeTrend::grows ? "slowly growing" : "limit cycle";
    out.summary = std::string("neutral: the neighbours never separate for good (curve end: ") +
                  to_string(r.fit.end) + "): " +
                  (a == AmplitudeTrend::grows ? "a motion that grows towards a larger bounded one"
                                              : "a limit cycle or torus, largest exponent 0 (paper 001 Fig. 4)") +
                  "; the fitted slope is the estimate's residue; " + numbers + noise;
    return out;
  }
  if (out.ci_low_per_period > band) {
    if (a == AmplitudeTrend::decays)
      return undetermined("lambda > 0 while the amplitude decays (a transient? see the warnings; " + numbers + ")");
    // Chaos never repeats itself: a flow whose curve reads chaos while its motion ends periodic
    // (its last third repeats one period on, EndRepeat) is a limit cycle. Hammond's failed-damper run
    // from within its growth (8-12 s) to 30 s read +0.5..+4.2 1/s, "chaotic", before this clause:
    // the neighbours of its growth and settling separate, then come back together.
    const double short_of_scale = below_attractor_scale(r.curve);
    if (a == AmplitudeTrend::persists && !r.mean_period.map && !(short_of_scale > options.chaos_scale_margin) &&
        r.end_repeat.difference < options.periodic_end) {
      out.stability = Stability::neutral;
      out.motion = "limit cycle";
      const double period = r.end_repeat.period;
      out.summary = fmt::format(
          "neutral: the motion ends periodic (its last third repeats itself every {:.4g} samples{} to {:.2g} % of "
          "its deviation): a limit cycle, largest exponent 0 (paper 001 Fig. 4); chaos never repeats itself, so "
          "lambda > 0 is no chaotic attractor: the neighbours separated in a transient before the motion settled "
          "(analyse from its end: --from auto) or are false ones; ",
          period, r.time_unit.empty() ? std::string() : fmt::format(" = {:.4g} {}", period * r.dt, r.time_unit),
          100.0 * r.end_repeat.difference);
      out.summary += numbers + noise;
      return out;
    }
    // Linear noise diverges too (surrogate.hpp): when the surrogate test was run and did not set the
    // divergence apart from its surrogates', no chaos (nor divergence on a steady amplitude) is
    // claimed. An AR(2) resonance (a lightly damped mode driven by noise) read "chaotic" before.
    if (const auto& t = r.surrogates; t && !t->distinguished && a == AmplitudeTrend::persists)
      return undetermined(fmt::format(
          "lambda > 0 on a motion of steady amplitude, but its divergence is not told from linear noise's: {} "
          "surrogates with its {} diverge as fast or nearly (p = {:.2g}, {:.2g} standard "
          "deviations above their mean{}; chaos needs p <= {:g} and {:g}): a motion driven by noise through linear "
          "dynamics (a lightly damped mode excited by turbulence) reads so; {}",
          t->surrogate_slopes.size(),
          t->channels > 1 ? "channels' spectra, values and cross-spectra (multivariate IAAFT)"
                          : "spectrum and values (IAAFT)",
          t->p_value, t->sigmas, surrogate_segment(*t), t->significance, t->min_sigmas,
          numbers + noise));
    out.stability = Stability::unstable;
    if (a == AmplitudeTrend::grows) {
      out.motion = "growing oscillation";
      out.summary = "unstable: nearby motions diverge and the amplitude grows: the motion leaves its equilibrium "
                    "(paper 001: an instability, such as ground resonance); ";
    } else if (a == AmplitudeTrend::persists && short_of_scale > options.chaos_scale_margin) {
      // Chaos bounds the divergence by the attractor's size, and the curve shows it getting there; a
      // divergence that stays far below it beneath a steady amplitude may as well be a growth under
      // a steady carrier (a rotating blade's absolute coordinates: the rotation hides the hub's
      // growth from the amplitude), or chaos the horizon is too short for.
      out.motion = "diverging";
      out.summary = fmt::format(
          "unstable: nearby motions diverge on a motion of steady amplitude, but over the curve's horizon only to "
          "{:.3g} below the attractor scale (natural log): chaos is not shown; a growth beneath a steady carrier (a "
          "rotating part's absolute coordinates: analyse a channel relative to it) reads so too; ",
          short_of_scale);
    } else if (a == AmplitudeTrend::persists && std::isnan(r.envelope_rate) && !r.mean_period.map) {
      // Chaos is an attractor the motion keeps returning to; a run of fewer than 8 mean periods (too
      // short for the envelope's windows) returns too few times for neighbours from different passes,
      // and its pairs sit a fraction of a period apart. Two tones of unrelated frequencies (a torus,
      // largest exponent 0: sin t + 0.5 sin(sqrt 2 t)) over 3-6 periods read lambda = +0.07 .. +0.25
      // 1/s and "chaotic" until this clause; over 10 periods and more they read neutral.
      return undetermined(fmt::format(
          "lambda > 0 on a motion of steady amplitude over only {:.3g} mean periods (fewer than 8): too few returns "
          "to show a chaotic attractor, and a quasi-periodic motion (a torus, largest exponent 0) reads so too; "
          "analyse a longer run; {}",
          mean_periods_spanned(r), numbers + noise));
    } else if (a == AmplitudeTrend::persists) {
      out.motion = "chaotic";
      out.summary = "unstable: nearby motions diverge on a motion of steady amplitude: a chaotic attractor; ";
      out.summary += r.surrogates ? fmt::format("its divergence exceeds that of {} linear surrogates (p = {:.2g}, {:.3g} "
                                                "standard deviations above their mean{}); ",
                                                r.surrogates->surrogate_slopes.size(), r.surrogates->p_value,
                                                r.surrogates->sigmas, surrogate_segment(*r.surrogates))
                                  : std::string("(not tested against linear noise, which through a lightly damped "
                                                "mode reads so too: --surrogates 19 tests it); ");
    } else {
      out.motion = "diverging";
      out.summary = "unstable: nearby motions diverge while the amplitude changes: a growth and chaos are not told "
                    "apart over this run (a longer run shows which); ";
    }
    out.summary += numbers + noise;
    return out;
  }
  if (out.ci_high_per_period < -band) {
    if (a == AmplitudeTrend::grows)
      return undetermined("lambda < 0 while the amplitude grows (a transient towards a larger motion? see the "
                          "warnings; " + numbers + ")");
    // Nor is it a decay to rest while the signal ends larger than it began, neither growing nor
    // steady by the rules above: 150 samples of Roessler x (2.5 mean periods, last third 1.41 x the
    // first's RMS) read "stable, decays to rest" at lambda = -0.18 1/s.
    if (a == AmplitudeTrend::changes && r.amplitude_ratio > 1.0)
      return undetermined(fmt::format("lambda < 0 while the amplitude does not fall (its last third's RMS is {:.3g} x its "
                                      "first third's): no decay to rest; {}",
                                      r.amplitude_ratio, numbers + noise));
    if (a == AmplitudeTrend::persists) {  // the curve falls, the amplitude does not
      out.stability = Stability::neutral;
      out.motion = "limit cycle";
      out.summary = "neutral: the neighbours converge onto a motion of steady amplitude, a stable limit cycle or torus, "
                    "whose largest exponent is 0 (paper 001 Fig. 4); the negative slope is the contraction towards "
                    "it; " + numbers + noise;
      return out;
    }
    out.stability = Stability::stable;
    out.motion = "decays to rest";
    out.summary = "stable: perturbations decay (exponentially stable); " + numbers + noise;
    return out;
  }
  out.stability = Stability::neutral;
  switch (a) {
    case AmplitudeTrend::decays:
      if (settles_onto_a_cycle(r, options)) {
        out.motion = "limit cycle";
        out.summary = fmt::format(
            "neutral: the amplitude decays onto a steady periodic motion (its second half's envelope rate is {:.2g} of "
            "the run's, and its last third repeats itself every {:.4g} samples to {:.2g} % of its deviation): a limit "
            "cycle, largest exponent 0 (paper 001 Fig. 4); the decay before it is a transient (--from auto analyses "
            "the cycle alone); ",
            r.end_envelope_rate / r.envelope_rate, r.end_repeat.period, 100.0 * r.end_repeat.difference);
        break;
      }
      out.motion = "lightly damped";
      out.summary = "neutral within the band, while the amplitude decays: lightly damped; ";
      break;
    case AmplitudeTrend::grows:
      out.motion = "slowly growing";
      out.summary = "neutral within the band, while the amplitude grows: slowly growing; ";
      break;
    default:
      out.motion = "limit cycle";
      out.summary = "neutral: a periodic or quasi-periodic motion (limit cycle, or a torus), largest exponent 0; ";
  }
  out.summary += numbers + noise;
  return out;
}

/// The record's damped modes (MlceResult::record_modes) decide where the divergence curve cannot: its
/// reading is undetermined, or neutral on a run of few mean periods, or neutral while the amplitude
/// decays or grows (light damping, a slow growth: the curve's band is wider than the modes'). They
/// must describe the record (RecordModes::describes_record), and their rate's 95 % interval must lie
/// wholly below the band (stable), above it (unstable) or within it (neutral), per mean period as
/// the curve's. Records of one or two periods of a damped oscillator read "neutral, lightly damped"
/// or "undetermined" with lambda off by 50-2000 % before (bench/oscillator_readings.sh: 21 of 560),
/// and two decaying modes beating "undetermined" (lambda +0.215, the modes -0.02).
std::optional<Reading> read_from_modes(const MlceResult& r, const Reading& curve, const ReadingOptions& options) {
  if (!r.record_modes || !r.record_modes->describes_record()) return std::nullopt;
  const auto& m = *r.record_modes;
  const bool weak = m.few_periods || curve_cannot_tell(curve) || neutral_unconfirmed(r, curve, options);
  const double T = curve.mean_period;
  if (!weak || !std::isfinite(T)) return std::nullopt;
  const double band = options.neutral_per_period;
  const double low = m.ci95_low * T, high = m.ci95_high * T;
  Reading out = curve;
  if (high < -band) {
    out.stability = Stability::stable;
    out.motion = "decays to rest";
  } else if (low > band) {
    out.stability = Stability::unstable;
    out.motion = m.frequency > 0.0 ? "growing oscillation" : "diverging";
  } else if (low >= -band && high <= band) {
    out.stability = Stability::neutral;
    out.motion = "limit cycle";
  } else {
    return std::nullopt;  // the modes' interval reaches across the band's edge: they cannot tell either
  }
  // The same stability stands as the curve read it; a neutral one keeps its own words (light damping
  // within the band is neutral too, and no limit cycle), a growth the modes' ("diverging" over a few
  // periods is a growing oscillation).
  if (out.stability == curve.stability && (out.stability == Stability::neutral || out.motion == curve.motion))
    return std::nullopt;
  const std::string unit = r.time_unit.empty() ? std::string("sample") : r.time_unit;
  // A steady oscillation that is nearly the whole record: on a rotor, the rotation a rotating part's
  // absolute coordinate carries (the bundled 1 s isotropic run's blade coordinates: 99.99 %), which
  // hides the motion beneath it; the same as MlceResult::carrier's share.
  const std::string carrier =
      out.stability == Stability::neutral && m.count > 1 && m.share >= MlceResult::SteadyCarrier::kMinShare
          ? fmt::format("; that steady oscillation is {:.3g} % of the record: a rotating part's absolute coordinate "
                        "carries the rotation so, and hides the motion beneath it (analyse a channel relative to the "
                        "rotating part)",
                        100.0 * std::min(m.share, 1.0))
          : std::string();
  const char* verb = out.stability == Stability::stable ? "decays" : out.stability == Stability::unstable ? "grows"
                                                                                                         : "holds";
  out.summary = fmt::format(
      "{} (from the record's damped modes, where the divergence curve cannot tell: {}): the record is {} mode(s) "
      "leaving {:.2g} % of it{}; the least damped {} at {:+.4g} 1/{} ({:.4g} cycles per {}; 95 % interval {:+.4g} .. "
      "{:+.4g}), x mean period = {:+.3g} (95 % interval {:+.3g} .. {:+.3g}; neutral within +-{:g}); lambda, the "
      "curve's slope, is not that rate here (mlce modes shows the modes){}; the curve alone read {}",
      to_string(out.stability), m.why, m.count, 100.0 * m.residual,
      m.residual > MlceResult::RecordModes::kCloseResidual ? " (white measurement noise)" : "", verb, m.lambda, unit,
      m.frequency, unit, m.ci95_low, m.ci95_high, m.lambda * T, low, high, band, carrier,
      curve.stability == Stability::undetermined ? std::string("undetermined")
                                                 : fmt::format("{}, {}", to_string(curve.stability), curve.motion));
  return out;
}
}  // namespace

double mean_periods_spanned(const MlceResult& r) {
  return static_cast<double>(r.n_points) * r.dt * r.mean_period.mean_frequency;
}

bool curve_cannot_tell(const Reading& curve) {
  return curve.stability == Stability::undetermined ||
         (curve.stability == Stability::neutral && (curve.motion == "lightly damped" || curve.motion == "slowly growing"));
}

namespace {
/// How closely the motion repeats itself one period on: its last third (EndRepeat), or on a run too
/// short for that the whole record, scaled (MlceResult::short_run_repeat).
double repeat_difference(const MlceResult& r) {
  return std::isfinite(r.end_repeat.difference) ? r.end_repeat.difference : r.short_run_repeat.difference;
}
}  // namespace

bool neutral_unconfirmed(const MlceResult& r, const Reading& curve, const ReadingOptions& options) {
  if (curve.stability != Stability::neutral || r.mean_period.map) return false;
  const double difference = repeat_difference(r);
  if (std::isfinite(difference) && difference <= options.periodic_end) return false;  // it repeats: periodic
  return mean_periods_spanned(r) < MlceResult::RecordModes::kFewPeriods ||
         (curve.motion == "limit cycle" && std::isfinite(difference));
}

Reading read_stability(const MlceResult& r, const ReadingOptions& options) {
  options.validate();
  Reading curve = read_from_curve(r, options);
  if (auto modes = read_from_modes(r, curve, options)) return *modes;
  // A neutral reading over a few mean periods, or a "limit cycle" that does not repeat itself, where the
  // record is no sum of modes either: no periodic, quasi-periodic or lightly damped motion is shown.
  // Roessler x over 12-100 s (2-17 mean periods: its curve saturates within the horizon as a cycle's
  // does, bounded, or swings with the pairs' phase) read "neutral, limit cycle" or "lightly damped".
  if (neutral_unconfirmed(r, curve, options) && r.record_modes && !r.record_modes->describes_record())
    return undetermined_reading(curve, fmt::format(
        "the divergence curve alone reads {}, {}, but over {} the motion is no sum of damped modes "
        "(they leave {:.2g} % of it{}) and does not show that it repeats itself ({}): neither a limit cycle, a torus "
        "nor a light damping is shown; chaos whose neighbours this run is too short to separate reads so (a longer "
        "run); the curve's reading: {}",
        to_string(curve.stability), curve.motion,
        r.record_modes->few_periods ? r.record_modes->why : std::string("this run"),
        100.0 * r.record_modes->residual, r.record_modes->halves_agree ? "" : ", and its halves differ",
        std::isfinite(repeat_difference(r))
            ? fmt::format("it differs from itself one period on by {:.3g} % of its deviation", 100.0 * repeat_difference(r))
            : std::string("too short to compare with itself one period on"),
        curve.summary));
  return curve;
}

}  // namespace mlce
