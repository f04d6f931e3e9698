#include "report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <unistd.h>

namespace mlce::cli {
namespace {

nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

std::string rate_unit(const MlceResult& r) { return r.time_unit.empty() ? "1/sample" : "1/" + r.time_unit; }

}  // namespace

nlohmann::json to_json(const AmiResult& r) {
  return {{"delay", r.delay},           {"rule", to_string(r.rule)}, {"bins", r.bins},
          {"binning", "equal-width over the range; Sturges ceil(log2 N)+1 unless given"},
          {"units", "nats"},            {"noise_floor", r.noise_floor}, {"scatter", r.scatter}, {"ami", r.ami},
          {"smoothing", r.smoothing},   {"smoothed", r.smoothed},     {"channel_delay", r.channel_delay}, {"warnings", r.warnings}};
}

nlohmann::json to_json(const FnnResult& r) {
  return {{"dim", r.dim},
          {"fraction", r.fraction},
          {"queries", r.queries},
          {"points", r.points},  // kd-tree size per m: the series' first FnnOptions::max_points
          {"reached_threshold", r.reached_threshold},
          {"warnings", r.warnings}};
}

nlohmann::json to_json(const CaoResult& r) {
  return {{"dim", r.dim},
          {"e", r.e},
          {"e1", r.e1},
          {"e2", r.e2},
          {"pairs", r.queries},
          {"saturated", r.saturated},
          {"looks_stochastic", r.looks_stochastic},
          {"warnings", r.warnings}};
}

nlohmann::json to_json(const MlceResult& r) {
  nlohmann::json j;
  j["lambda"] = finite_or_null(r.lambda);
  j["lambda_unit"] = rate_unit(r);
  j["lambda_per_sample"] = finite_or_null(r.lambda_per_sample);
  j["ci95"] = {finite_or_null(r.ci95_low), finite_or_null(r.ci95_high)};
  j["lyapunov_time"] = finite_or_null(r.lyapunov_time);
  j["log_base"] = "e";
  j["delay"] = r.delay;
  j["dim"] = r.dim;
  j["theiler"] = r.theiler;
  j["horizon"] = r.horizon;
  j["fit"] = {r.fit.first, r.fit.last};
  j["fit_rule"] = r.fit.rule;
  j["fit_automatic"] = r.fit.automatic;
  j["curve_end"] = to_string(r.fit.end);
  j["attractor_log_distance"] = finite_or_null(r.curve.attractor_log_distance);
  j["phase_aligned"] = r.curve.phase_aligned;
  if (r.curve.phase_aligned) j["mean_phase_shift"] = r.curve.mean_phase_shift;
  if (r.curve.phase_aligned) j["phase_interpolation"] = r.curve.cubic_pairs > 0 ? "cubic" : "linear";
  j["unaligned_lambda"] = finite_or_null(r.unaligned_lambda);
  j["noise_compensated"] = r.noise_compensated;
  j["uncompensated_lambda"] = finite_or_null(r.uncompensated_lambda);
  j["envelope_rate"] = finite_or_null(r.envelope_rate / r.dt);  // per time unit, like lambda
  j["envelope_rate_stderr"] = finite_or_null(r.envelope_rate_stderr / r.dt);
  j["end_envelope_rate"] = finite_or_null(r.end_envelope_rate / r.dt);  // the second half's (FitOptions::signal_end_rate)
  j["ends_amplitude_rate"] = finite_or_null(r.ends_amplitude_rate / r.dt);  // first vs last whole periods (reading, short runs)
  // On a short run: how closely it repeats itself one period on, scaled (transient.hpp, scaled_repeat).
  j["short_run_repeat"] = {{"period", finite_or_null(r.short_run_repeat.period)},
                           {"scale", finite_or_null(r.short_run_repeat.scale)},
                           {"difference", finite_or_null(r.short_run_repeat.difference)}};
  j["skipped_start"] = r.skipped_start;  // samples left out because they do not recur
  // The recurrence test's windows (recurrence.hpp), when it ran: their length and scores.
  if (!r.recurrence.ratio.empty()) {
    j["start_recurrence"] = {{"window", r.recurrence.window}, {"scores", r.recurrence.ratio}};
    // The distance test's ratios (recurrence.hpp, RecurrenceOptions::far), when it ran.
    if (!r.recurrence.distance_ratio.empty()) {
      j["start_recurrence"]["distance_ratios"] = r.recurrence.distance_ratio;
      j["start_recurrence"]["decided_by_distance"] = r.recurrence.by_distance;
    }
  }
  // The level's creep beneath the neighbour pairs (recurrence.hpp, neighbour_drift): its share of the
  // pairs' squared initial distance, the channel (1-based) and the creep the pairs see, per time unit.
  j["neighbour_drift"] = {{"share", r.neighbour_drift.share},
                          {"channel", r.neighbour_drift.channel + 1},
                          {"rate", finite_or_null(r.neighbour_drift.rate_per_sample / r.dt)}};
  j["noise_level"] = finite_or_null(r.noise_level);  // of the signal's standard deviation
  // Compensated: the noise estimate's relative error (of its mean square) and lambda's standard error
  // from it (per time unit, within ci95), and the noise's share of the pairs' mean square at the fit's
  // first and last step.
  j["noise_variance_error"] = finite_or_null(r.noise_variance_error);
  j["noise_lambda_stderr"] = finite_or_null(r.noise_lambda_stderr);
  if (r.noise_compensated && !r.curve.compensated_noise_share.empty())
    j["noise_share"] = {r.curve.compensated_noise_share[r.fit.first], r.curve.compensated_noise_share[r.fit.last]};
  j["unreliable"] = r.unreliable.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.unreliable);
  // A window cut by --from / --to: its RMS over the record's largest deviation (estimate.hpp).
  j["floor_window_ratio"] = finite_or_null(r.floor_window_ratio);
  j["in_decay_floor"] = r.in_decay_floor;  // lambda is then the solver's residue, not the motion's
  j["r2"] = finite_or_null(r.r2);
  j["n_points"] = r.n_points;
  j["dt"] = r.dt;
  j["time_unit"] = r.time_unit;
  j["mean_frequency"] = r.mean_period.mean_frequency;
  j["mean_period"] = r.mean_period.mean_period;
  j["fast_share"] = r.mean_period.fast_share;
  j["taper_mean_share"] = r.mean_period.taper_mean_share;
  j["taper_weighted_mean"] = r.mean_period.taper_weighted_mean;
  j["treated_as_map"] = r.mean_period.map;
  // The surrogate test (surrogate.hpp): null when not run (by default it runs where the curve alone
  // reads chaos; --surrogates K always, 0 never). samples from first_sample: the segment it ran on
  // (several channels: the one whose ends meet, end_jump; null for one channel). channels: the
  // surrogates' (several: multivariate IAAFT).
  if (const auto& t = r.surrogates)
    j["surrogates"] = {{"count", t->surrogate_slopes.size()},
                       {"series_slope", t->series_slope},
                       {"surrogate_slopes", t->surrogate_slopes},
                       {"p_value", t->p_value},
                       {"sigmas", finite_or_null(t->sigmas)},  // null: the surrogates' slopes all equal
                       {"distinguished", t->distinguished},
                       {"steps", {t->first, t->last}},
                       {"first_sample", t->first_sample},
                       {"samples", t->samples},
                       {"end_jump", finite_or_null(t->end_jump)},
                       {"channels", t->channels}};
  else
    j["surrogates"] = nullptr;
  // A steady carrier over a growing mode (MlceResult::carrier): null when none.
  if (const auto& c = r.carrier)
    j["carrier"] = {{"frequency", c->frequency},
                    {"share", c->share},
                    {"growth_rate", c->growth_rate},
                    {"growth_frequency", c->growth_frequency},
                    {"growth_peak_share", c->growth_peak_share}};
  else
    j["carrier"] = nullptr;
  // The record's damped modes where the curve cannot tell (MlceResult::record_modes): null when not
  // identified; the reading takes its stability from them when `describes_record`.
  if (const auto& m = r.record_modes)
    j["record_modes"] = {{"why", m->why},
                         {"lambda", m->lambda},
                         {"ci95", {finite_or_null(m->ci95_low), finite_or_null(m->ci95_high)}},
                         {"frequency", m->frequency},
                         {"share", m->share},
                         {"count", m->count},
                         {"residual", m->residual},
                         {"noise_left", m->noise_left},
                         {"linear", m->linear},
                         {"halves_agree", m->halves_agree},
                         {"leading_part", m->leading_part},
                         {"describes_record", m->describes_record()}};
  else
    j["record_modes"] = nullptr;
  // A map's settled cycle (map_cycle.hpp): null when none; lambda is its approach's rate when measured.
  if (const MapCycle& c = r.map_cycle; c.found())
    j["map_cycle"] = {{"period", c.period},
                      {"from", c.from},
                      {"approach_rate", finite_or_null(c.approach_rate)},
                      {"approach_ci95", {finite_or_null(c.approach_ci_low), finite_or_null(c.approach_ci_high)}},
                      {"approach_samples", c.approach_measured() ? nlohmann::json{c.approach_first, c.approach_last}
                                                                 : nlohmann::json(nullptr)},
                      {"rate_bound", finite_or_null(c.rate_bound)},
                      {"curve_lambda", finite_or_null(r.curve_lambda)}};
  else
    j["map_cycle"] = nullptr;
  if (r.ami) j["delay_rule"] = to_string(r.ami->rule);
  if (r.fnn) j["fnn_fraction"] = r.fnn->fraction;
  if (r.dim_widened_from) {
    j["dim_widened_from"] = *r.dim_widened_from;
    j["dim_widened_because"] =
        r.dim_widened_because == DimensionWidening::flow_in_a_plane ? "flow_in_a_plane" : "growth_in_a_decay";
  }
  if (r.fnn) j["fnn_points"] = r.fnn->points;  // kd-tree size per m (capped on long series)
  j["pairs"] = r.curve.pairs;
  j["references"] = r.curve.references;
  j["reading"] = reading_json(r);
  j["warnings"] = r.warnings;
  return j;
}

nlohmann::json reading_json(const MlceResult& r) {
  // What the exponent says about the motion (reading.hpp): paper 001's reading of its sign.
  const Reading reading = read_stability(r);
  return {{"stability", to_string(reading.stability)},
          {"motion", reading.motion},
          {"amplitude", to_string(reading.amplitude)},
          {"amplitude_ratio", finite_or_null(r.amplitude_ratio)},
          // How closely the last third repeats itself one period on (mean_period.hpp, end_repeat).
          {"end_repeat", {{"difference", finite_or_null(r.end_repeat.difference)},
                          {"period", finite_or_null(r.end_repeat.period)}}},
          {"mean_period_time", finite_or_null(reading.mean_period)},
          {"lambda_per_period", finite_or_null(reading.lambda_per_period)},
          {"ci95_per_period", {finite_or_null(reading.ci_low_per_period), finite_or_null(reading.ci_high_per_period)}},
          {"neutral_per_period", reading.neutral_per_period},
          {"summary", reading.summary}};
}

std::string to_text(const MlceResult& r) {
  std::string s;
  const std::string u = rate_unit(r);
  s += fmt::format("MLCE            {:.6g} {}  (95 % CI {:.6g} .. {:.6g})\n", r.lambda, u, r.ci95_low, r.ci95_high);
  s += fmt::format("                {:.6g} per sample", r.lambda_per_sample);
  if (std::isfinite(r.lyapunov_time))
    s += fmt::format(", Lyapunov time {:.6g} {}", r.lyapunov_time, r.time_unit.empty() ? "samples" : r.time_unit);
  s += "\n";
  s += "reading         " + read_stability(r).summary + "\n";
  s += fmt::format("series          {} samples, dt = {:.6g} {}\n", r.n_points, r.dt,
                   r.time_unit.empty() ? "(per sample)" : r.time_unit);
  s += fmt::format("mean period     {} samples (mean frequency {:.6g} per {}){}{}{}\n", r.mean_period.mean_period,
                   r.mean_period.mean_frequency, r.time_unit.empty() ? "sample" : r.time_unit,
                   r.mean_period.clamped ? ", clamped" : "",
                   r.mean_period.taper_weighted_mean ? ", taper-weighted mean removed (a strong decay or growth)" : "",
                   r.mean_period.map && r.mean_period.mean_period >= kMinFlowPeriod
                       ? fmt::format("; a map: {:.1f} % of the power at periods below 4 samples",
                                     100.0 * r.mean_period.fast_share)
                       : std::string());
  s += fmt::format("delay           {} samples{}\n", r.delay, r.ami ? fmt::format(" ({})", to_string(r.ami->rule)) : " (given)");
  s += fmt::format("dimension       {}{}\n", r.dim,
                   r.dim_widened_from ? fmt::format(" (false nearest neighbours chose {}, {})", *r.dim_widened_from,
                                                    r.dim_widened_because == DimensionWidening::flow_in_a_plane
                                                        ? "too few coordinates for a flow that diverges"
                                                        : "which read lambda > 0 in a decay")
                   : r.fnn            ? std::string(" (false nearest neighbours)")
                                      : std::string(" (given)"));
  if (r.fnn) {
    s += "  FNN fraction ";
    for (std::size_t m = 0; m < r.fnn->fraction.size(); ++m) s += fmt::format(" m={}:{:.3f}", m + 1, r.fnn->fraction[m]);
    if (r.fnn->capped) s += fmt::format(" (over the first {} points)", r.fnn->points.front());
    s += "\n";
  }
  s += fmt::format("Theiler window  {} samples\n", r.theiler);
  s += fmt::format("curve           steps 0..{}, {} pairs ({} references)\n", r.horizon, r.curve.pairs, r.curve.references);
  if (r.curve.phase_aligned)
    s += fmt::format("phase aligned   neighbours moved along their trajectories by {:.3f} samples on average{}{}\n",
                     r.curve.mean_phase_shift,
                     r.curve.cubic_pairs > 0 ? fmt::format(", read on cubics ({} pairs)", r.curve.cubic_pairs) : "",
                     std::isfinite(r.unaligned_lambda) ? fmt::format(" (plain curve: {:.6g} {})", r.unaligned_lambda, u) : "");
  if (r.noise_compensated) {
    s += fmt::format("noise           compensated: white noise of {:.2g} % of the signal's deviation taken out of the "
                     "mean square distances (plain curve: {:.6g} {})\n",
                     100.0 * r.noise_level, r.uncompensated_lambda, u);
    if (!r.curve.compensated_noise_share.empty())
      s += fmt::format("                its share of the pairs' mean square {:.2f} .. {:.2f} over the fit; its mean square "
                       "measured to {:.2g} %, which moves lambda by {:.3g} {} (1 standard error, within the interval)\n",
                       r.curve.compensated_noise_share[r.fit.first], r.curve.compensated_noise_share[r.fit.last],
                       100.0 * r.noise_variance_error, r.noise_lambda_stderr, u);
  }
  s += fmt::format("fit             steps {}..{}, R^2 = {:.4f}; {}\n", r.fit.first, r.fit.last, r.r2, r.fit.rule);
  if (const auto& t = r.surrogates)
    s += fmt::format("surrogates      slope {:.6g} per step over {}..{}{}; {} IAAFT surrogates' {:.6g} .. {:.6g}: p = {:.3g}, "
                     "{:.3g} standard deviations above their mean: {}\n",
                     t->series_slope, t->first, t->last,
                     segment_words(*t).empty() ? std::string() : " on the " + segment_words(*t),
                     t->surrogate_slopes.size(),
                     *std::min_element(t->surrogate_slopes.begin(), t->surrogate_slopes.end()),
                     *std::max_element(t->surrogate_slopes.begin(), t->surrogate_slopes.end()), t->p_value, t->sigmas,
                     t->distinguished ? "told from linear noise" : "not told from linear noise");
  for (const auto& w : r.warnings) s += "warning: " + w + "\n";
  return s;
}

std::string to_text(const AmiResult& r) {
  std::string s = fmt::format(
      "# average mutual information (nats), {} equal-width bins; smoothed: centred {}-lag moving average\n"
      "# tau ami smoothed\n",
      r.bins, r.smoothing);
  for (std::size_t t = 0; t < r.ami.size(); ++t) s += fmt::format("{} {:.6g} {:.6g}\n", t, r.ami[t], r.smoothed[t]);
  s += fmt::format("# delay = {} ({})\n", r.delay, to_string(r.rule));
  if (r.scatter > 0.0)  // the rise the minimum needed above the curve's own scatter (AmiOptions::noise_rise)
    s += fmt::format("# the raw curve scatters by {:.3g} nats about its trend there\n", r.scatter);
  for (const auto& w : r.warnings) s += "# warning: " + w + "\n";
  return s;
}

std::string to_text(const FnnResult& r) {
  std::string s = "# false nearest neighbours\n# m fraction tested tree_points\n";
  for (std::size_t m = 0; m < r.fraction.size(); ++m)
    s += fmt::format("{} {:.6f} {} {}\n", m + 1, r.fraction[m], r.queries[m], r.points[m]);
  s += fmt::format("# dim = {}{}\n", r.dim, r.reached_threshold ? "" : " (threshold not reached)");
  for (const auto& w : r.warnings) s += "# warning: " + w + "\n";
  return s;
}

std::string to_text(const CaoResult& r) {
  std::string s = "# Cao's averaged false neighbours (Euclidean norm)\n# d E E1 E2 pairs\n";
  for (std::size_t d = 0; d < r.e.size(); ++d)
    s += d < r.e1.size() ? fmt::format("{} {:.6f} {:.6f} {:.6f} {}\n", d + 1, r.e[d], r.e1[d], r.e2[d], r.queries[d])
                         : fmt::format("{} {:.6f} - - {}\n", d + 1, r.e[d], r.queries[d]);
  s += fmt::format("# dim = {}{}\n", r.dim, r.saturated ? " (first d with E1 saturated)" : " (E1 never saturated)");
  s += r.looks_stochastic ? "# E2 = 1 at every d: looks stochastic\n" : "# E2 away from 1 at some d: deterministic\n";
  for (const auto& w : r.warnings) s += "# warning: " + w + "\n";
  return s;
}

std::string ami_csv(const AmiResult& r) {
  std::string s = "tau,ami,smoothed\n";
  for (std::size_t t = 0; t < r.ami.size(); ++t) s += fmt::format("{},{:.10g},{:.10g}\n", t, r.ami[t], r.smoothed[t]);
  return s;
}

std::string fnn_csv(const FnnResult& r) {
  std::string s = "m,false_fraction,tested,tree_points\n";
  for (std::size_t m = 0; m < r.fraction.size(); ++m)
    s += fmt::format("{},{:.10g},{},{}\n", m + 1, r.fraction[m], r.queries[m], r.points[m]);
  return s;
}

std::string cao_csv(const CaoResult& r) {
  std::string s = "d,E,E1,E2,pairs\n";
  for (std::size_t d = 0; d < r.e.size(); ++d)
    s += d < r.e1.size() ? fmt::format("{},{:.10g},{:.10g},{:.10g},{}\n", d + 1, r.e[d], r.e1[d], r.e2[d], r.queries[d])
                         : fmt::format("{},{:.10g},,,{}\n", d + 1, r.e[d], r.queries[d]);
  return s;
}

namespace {
/// step,time,mean_log_distance,terms,in_fit,fit_line of curve step i (no line break).
std::string curve_row(const MlceResult& r, std::size_t i) {
  const bool in = i >= r.fit.first && i <= r.fit.last;
  return fmt::format("{},{:.10g},{:.10g},{},{},{:.10g}", i, r.dt * static_cast<double>(i), r.curve.mean_log_distance[i],
                     r.curve.terms[i], in ? 1 : 0, r.fit.intercept + r.fit.slope * static_cast<double>(i));
}

/// ",local_slope" of every curve step: per time unit over one mean period (MeanPeriodResult::rule_period; local_slopes), an empty
/// field within half a period of either end, where no centred window fits.
std::vector<std::string> local_slope_fields(const MlceResult& r, bool* any = nullptr) {
  const std::vector<double> slope = local_slopes(r.curve.mean_log_distance, r.mean_period.rule_period());
  std::vector<std::string> fields;
  fields.reserve(slope.size());
  for (const double s : slope) fields.push_back(std::isfinite(s) ? fmt::format(",{:.10g}", s / r.dt) : ",");
  if (any) *any = std::any_of(slope.begin(), slope.end(), [](double s) { return std::isfinite(s); });
  return fields;
}
}  // namespace

CurveTable curve_table(const MlceResult& r) {
  // A phase-aligned or noise-compensated curve is followed by the plain one (same pairs), then by
  // the local slope.
  CurveTable t;
  const bool plain = r.plain_curve.size() == r.curve.mean_log_distance.size();
  const auto& share = r.curve.compensated_noise_share;
  const bool shares = r.noise_compensated && share.size() == r.curve.mean_log_distance.size();
  t.plain_column = plain ? 7 : 0;
  t.slope_column = plain ? 8 : 7;
  const std::vector<std::string> slope = local_slope_fields(r, &t.any_slope);
  t.csv = std::string("step,time,mean_log_distance,terms,in_fit,fit_line") + (plain ? ",plain_mean_log_distance" : "") +
          ",local_slope" + (shares ? ",noise_share" : "") + "\n";
  for (std::size_t i = 0; i < r.curve.mean_log_distance.size(); ++i)
    t.csv += curve_row(r, i) + (plain ? fmt::format(",{:.10g}", r.plain_curve[i]) : "") + slope[i] +
             (shares ? fmt::format(",{:.6g}", share[i]) : "") + "\n";
  return t;
}

std::string curve_csv(const MlceResult& r) { return curve_table(r).csv; }

namespace {
nlohmann::json optional_json(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(); }
}  // namespace

nlohmann::json to_json(const ModalResult& r) {
  nlohmann::json modes = nlohmann::json::array();
  for (const Mode& m : r.modes)
    modes.push_back({{"sigma", m.sigma},
                     {"frequency", m.frequency},
                     {"damping_ratio", m.damping_ratio},
                     {"share", m.share},
                     {"peak_share", m.peak_share},
                     {"offset", m.offset},
                     {"nyquist", m.nyquist}});
  const std::string rate = r.time_unit.empty() ? "1/sample" : "1/" + r.time_unit;
  const std::string cycles = r.time_unit.empty() ? "cycles/sample" : "cycles/" + r.time_unit;
  return {{"method", "matrix pencil"},
          {"lambda", optional_json(r.lambda)},
          {"lambda_per_sample", optional_json(r.lambda_per_sample)},
          {"ci95", r.lambda_low ? nlohmann::json::array({*r.lambda_low, *r.lambda_high}) : nlohmann::json()},
          {"lambda_spread", r.lambda_spread},
          {"interval_replicates", r.interval_replicates},
          {"replicates_without_lambda", r.replicates_without_lambda},
          {"lambda_mode", r.lambda_mode ? nlohmann::json(*r.lambda_mode) : nlohmann::json()},
          {"lambda_mode_frequency", r.lambda_mode_frequency},
          {"lambda_from_second_half", r.lambda_from_second_half},
          {"leading_part", r.leading_part},
          {"first_half_lambda", optional_json(r.first_half_lambda)},
          {"second_half_lambda", optional_json(r.second_half_lambda)},
          {"halves_agree", r.halves_agree},
          {"linear", r.linear},
          {"reading", r.reading},
          {"stability", to_string(r.stability)},
          {"modes", modes},
          {"order", r.order},
          {"order_automatic", r.order_automatic},
          {"order_capped", r.order_capped},
          {"rank_deficient", r.rank_deficient},
          {"residual", r.residual},
          {"residual_correlation", r.residual_correlation},
          {"noise_left", r.noise_left},
          {"channel_residual", r.channel_residual},
          {"map", r.map},
          {"singular_values", r.singular_values},
          {"noise_floor", r.noise_floor},
          {"stride", r.stride},
          {"columns", r.columns},
          {"rows", r.rows},
          {"n_points", r.n_points},
          {"floor_start", r.floor_start},
          {"dt", r.dt},
          {"time_unit", r.time_unit},
          {"units", {{"sigma", rate}, {"frequency", cycles}}},
          {"warnings", r.warnings}};
}

std::string to_text(const ModalResult& r) {
  const std::string rate = r.time_unit.empty() ? "1/sample" : "1/" + r.time_unit;
  const std::string freq = r.time_unit.empty() ? "cycles/sample" : (r.time_unit == "s" ? "Hz" : "cycles/" + r.time_unit);
  std::string s = fmt::format("# modes by the matrix pencil: order {}{}, stride {} samples, {} x {} Hankel matrix\n", r.order,
                              r.order_automatic ? " (automatic)" : "", r.stride, r.rows, r.columns);
  s += fmt::format("# {:>14} {:>14} {:>10} {:>10} {:>10}\n", "sigma (" + rate + ")", "freq (" + freq + ")", "zeta", "share",
                   "peak share");
  for (std::size_t k = 0; k < r.modes.size(); ++k) {
    const Mode& m = r.modes[k];
    s += fmt::format("  {:>14.7g} {:>14.7g} {:>10.4g} {:>10.3g} {:>10.3g}{}{}\n", m.sigma, m.frequency, m.damping_ratio, m.share,
                     m.peak_share, m.offset ? "  offset" : (m.nyquist ? "  at the strided Nyquist frequency" : ""),
                     r.lambda_mode && *r.lambda_mode == k ? "  <- lambda" : "");
  }
  s += fmt::format("residual        {:.3g} of the record (RMS){}\n", r.residual,
                   r.noise_left ? fmt::format(", white (lag-one correlation {:.2f}): measurement noise", r.residual_correlation)
                                : std::string());
  if (r.lambda)
    s += fmt::format("lambda          {:.7g} {} ({:.7g} per sample): the least damped mode{}\n", *r.lambda, rate,
                     *r.lambda_per_sample,
                     r.lambda_from_second_half ? ", from the record's second half"
                                               : (r.leading_part ? fmt::format(", over the growth's first {} samples", r.n_points) : ""));
  if (r.lambda_low)
    s += fmt::format("interval        [{:.7g}, {:.7g}] {} (95 %: lambda +- 1.96 x the spread of {} records of these modes and "
                     "noise like the residual)\n", *r.lambda_low, *r.lambda_high, rate, r.interval_replicates);
  const auto half_text = [](const std::optional<double>& v) { return v ? fmt::format("{:.7g}", *v) : std::string("-"); };
  if (r.first_half_lambda || r.second_half_lambda)
    s += fmt::format("halves          {} and {} {}{}\n", half_text(r.first_half_lambda), half_text(r.second_half_lambda), rate,
                     r.halves_agree ? "" : " (they differ)");
  s += "reading         " + r.reading + "\n";
  for (const auto& w : r.warnings) s += "warning: " + w + "\n";
  return s;
}

std::string modes_csv(const ModalResult& r) {
  std::string s = "sigma,frequency,damping_ratio,share,peak_share,offset\n";
  for (const Mode& m : r.modes)
    s += fmt::format("{:.10g},{:.10g},{:.10g},{:.6g},{:.6g},{}\n", m.sigma, m.frequency, m.damping_ratio, m.share, m.peak_share,
                     m.offset ? 1 : 0);
  return s;
}

nlohmann::json to_json(const SpaceTimeResult& r, double dt, const std::string& time_unit) {
  nlohmann::json contours = nlohmann::json::object();
  for (std::size_t k = 0; k < r.fractions.size(); ++k) contours[fmt::format("{:g}", r.fractions[k])] = r.contour[k];
  return {{"dim", r.dim},
          {"delay", r.delay},
          {"separation", r.separation},
          {"time_unit", time_unit},
          {"dt", dt},
          {"fractions", r.fractions},
          {"contours", contours},
          {"distance_unit", "embedded Euclidean distance in units of each channel's standard deviation"},
          {"pairs", r.pairs},
          {"plateau", r.plateau},
          {"decorrelation", r.decorrelation},
          {"decorrelation_time", dt * static_cast<double>(r.decorrelation)},
          {"decorrelation_level", r.decorrelation_level},
          {"mean_period", r.mean_period},
          {"amplitude_ratio", finite_or_null(r.amplitude_ratio)},
          {"stationary", r.stationary},
          {"warnings", r.warnings}};
}

std::string to_text(const SpaceTimeResult& r, double dt, const std::string& time_unit) {
  const std::string unit = time_unit.empty() ? "samples" : time_unit;
  std::string s = fmt::format(
      "# space-time separation plot, m = {}, delay = {}: distance (standard deviations) below which a fraction of the "
      "pairs of points D samples apart lie\n# D time",
      r.dim, r.delay);
  for (const double f : r.fractions) s += fmt::format(" {:g}", f);
  s += " pairs\n";
  for (std::size_t k = 0; k < r.separation.size(); ++k) {
    s += fmt::format("{} {:.6g}", r.separation[k], dt * static_cast<double>(r.separation[k]));
    for (const auto& c : r.contour) s += fmt::format(" {:.6g}", c[k]);
    s += fmt::format(" {}\n", r.pairs[k]);
  }
  s += fmt::format("# decorrelation = {} samples ({:.6g} {}): the {:g} contour reaches {:g} x its plateau ({:.6g})\n",
                   r.decorrelation, dt * static_cast<double>(r.decorrelation), unit, r.fractions.front(),
                   r.decorrelation_level, r.plateau);
  s += fmt::format("# mean period = {} samples (the automatic Theiler window)\n", r.mean_period);
  for (const auto& w : r.warnings) s += "# warning: " + w + "\n";
  return s;
}

std::string space_time_csv(const SpaceTimeResult& r, double dt) {
  std::string s = "separation,time";
  for (const double f : r.fractions) s += fmt::format(",contour_{:g}", f);
  s += ",pairs\n";
  for (std::size_t k = 0; k < r.separation.size(); ++k) {
    s += fmt::format("{},{:.10g}", r.separation[k], dt * static_cast<double>(r.separation[k]));
    for (const auto& c : r.contour) s += fmt::format(",{:.10g}", c[k]);
    s += fmt::format(",{}\n", r.pairs[k]);
  }
  return s;
}

nlohmann::json to_json(const ConvergenceResult& r, const std::string& unit) {
  nlohmann::json points = nlohmann::json::array();
  for (const auto& p : r.points) {
    nlohmann::json j{{"samples", p.samples}, {"t_end", p.t_end}, {"estimated", p.estimated}};
    if (p.estimated) {
      j["lambda"] = finite_or_null(p.lambda);
      j["ci95"] = {finite_or_null(p.ci95_low), finite_or_null(p.ci95_high)};
      j["delay"] = p.delay, j["dim"] = p.dim, j["theiler"] = p.theiler, j["warnings"] = p.warnings;
      j["stability"] = to_string(p.stability), j["motion"] = p.motion, j["in_decay_floor"] = p.in_decay_floor;
    } else {
      j["error"] = p.error;
    }
    points.push_back(j);
  }
  return {{"points", points},
          {"lambda_unit", unit},
          {"converged", r.converged},
          {"reading_settled", r.reading_settled},
          {"tolerance_floor", r.tolerance_floor},
          {"warnings", r.warnings}};
}

std::string to_text(const ConvergenceResult& r, const std::string& unit) {
  std::string s = fmt::format("# MLCE of the run's leading parts (lambda in {}, natural log)\n"
                              "# samples t_end lambda ci95_low ci95_high delay dim theiler warnings stability\n",
                              unit);
  for (const auto& p : r.points) {
    if (p.estimated)
      s += fmt::format("{} {:.6g} {:.6g} {:.6g} {:.6g} {} {} {} {} {}\n", p.samples, p.t_end, p.lambda, p.ci95_low,
                       p.ci95_high, p.delay, p.dim, p.theiler, p.warnings, to_string(p.stability));
    else
      s += fmt::format("# {} samples (to {:.6g}): not estimated: {}\n", p.samples, p.t_end, p.error);
  }
  if (r.converged)
    s += fmt::format("settled: every part of at least half the run is within the larger 95 % half-width, or {:.3g} {}, "
                     "of the whole run's lambda, and they do not drift one way beyond that\n",
                     r.tolerance_floor, unit);
  else
    s += "NOT settled (see the warnings)\n";
  if (!r.points.empty()) {
    const auto& whole = r.points.back();
    s += r.reading_settled ? fmt::format("reading settled: {} ({}) on every part of at least half the run\n",
                                         to_string(whole.stability), whole.motion)
                           : fmt::format("reading NOT settled: the whole run reads {} ({}), a part of at least half of it otherwise (see "
                                         "the warnings)\n",
                                         to_string(whole.stability), whole.motion);
  }
  for (const auto& w : r.warnings) s += "warning: " + w + "\n";
  return s;
}

std::string convergence_csv(const ConvergenceResult& r) {
  std::string s = "samples,t_end,lambda,ci95_low,ci95_high,delay,dim,theiler,warnings,stability,motion,in_decay_floor\n";
  for (const auto& p : r.points) {
    s += fmt::format("{},{:.10g}", p.samples, p.t_end);
    s += p.estimated ? fmt::format(",{:.10g},{:.10g},{:.10g},{},{},{},{},{},{},{}\n", p.lambda, p.ci95_low, p.ci95_high,
                                   p.delay, p.dim, p.theiler, p.warnings, to_string(p.stability), p.motion,
                                   p.in_decay_floor ? 1 : 0)
                     : std::string(",,,,,,,,,,\n");
  }
  return s;
}

OutputTarget output_target(const std::string& path) {
  namespace fs = std::filesystem;
  // /dev/stdout, /dev/fd/N, /proc/self/fd/N name an open descriptor: redirected to a regular file
  // they resolve to it, and a rename onto it would leave the shell writing to the unlinked one.
  if (path.starts_with("/dev/") || path.starts_with("/proc/")) return {path, true};
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);  // through symbolic links
  if (!ec && fs::exists(st) && !fs::is_regular_file(st) && !fs::is_directory(st)) return {path, true};
  if (fs::is_symlink(fs::symlink_status(path, ec))) {
    const fs::path target = fs::canonical(path, ec);
    if (!ec) return {target.string(), false};
    return {path, true};  // a dangling link: opening it creates its target
  }
  return {path, false};
}

std::string OutputTarget::scratch(const std::string& suffix) const {
  if (!in_place) return path + suffix;
  static std::atomic<int> count{0};  // outputs may be written from several threads (sweep jobs)
  return (std::filesystem::temp_directory_path() /
          ("mlce-" + std::to_string(::getpid()) + "-" + std::to_string(++count) + suffix)).string();
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), target_(output_target(path_)) {
  if (!target_.in_place) {
    tmp_ = target_.scratch(".tmp-mlce");
    scratch_.add(tmp_);
  }
  out_.open(target_.in_place ? target_.path : tmp_, std::ios::binary | std::ios::trunc);
  if (!out_) throw std::runtime_error(path_ + ": cannot write the file");
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  out_.close();
  std::error_code ec;
  if (!tmp_.empty()) std::filesystem::remove(tmp_, ec);
}

void AtomicFile::commit() {
  out_.close();
  std::error_code ec;
  if (!out_) {
    if (!tmp_.empty()) std::filesystem::remove(tmp_, ec);
    committed_ = true;
    throw std::runtime_error(path_ + ": write failed");
  }
  committed_ = true;
  if (tmp_.empty()) return;  // written in place
  std::filesystem::rename(tmp_, target_.path, ec);
  if (ec) {
    std::filesystem::remove(tmp_, ec);
    throw std::runtime_error(path_ + ": cannot write the file");
  }
}

void write_file_atomically(const std::string& path, const std::string& content) {
  AtomicFile f(path);
  f.stream() << content;
  f.commit();
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string q = "\"";
  for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

nlohmann::json to_json(const Agreement& a) {
  return {{"agree", a.agree},
          {"gap", finite_or_null(a.gap)},
          {"common_interval", std::isfinite(a.common_low) ? nlohmann::json{a.common_low, a.common_high} : nlohmann::json(nullptr)},
          {"median_lambda", finite_or_null(a.median_lambda)},
          {"tolerance", finite_or_null(a.tolerance_floor)}};
}

std::string agreement_text(const Agreement& a, std::size_t estimates, const std::string& rate_unit) {
  if (estimates < 2) return "not judged: fewer than two estimates that measure a divergence (the warnings say why)";
  if (a.gap <= 0.0)
    return fmt::format("yes: the {} intervals share {:.6g} .. {:.6g} {} (median lambda {:.6g})", estimates, a.common_low,
                       a.common_high, rate_unit, a.median_lambda);
  return fmt::format("{}: the intervals farthest apart are {:.3g} {} apart (resolution {:.3g}; median lambda {:.6g})",
                     a.agree ? "yes, within the resolution" : "NO", a.gap, rate_unit, a.tolerance_floor, a.median_lambda);
}

nlohmann::json to_json(const EachChannelResult& r) {
  nlohmann::json channels = nlohmann::json::array();
  for (const auto& c : r.channels) {
    nlohmann::json j = c.result ? to_json(*c.result) : nlohmann::json{{"error", c.error}};
    j["channel"] = c.name;
    channels.push_back(std::move(j));
  }
  nlohmann::json j = to_json(r.verdict);
  j["channels"] = channels;
  j["estimated"] = r.estimated;
  j["compared"] = r.compared;
  j["warnings"] = r.warnings;
  return j;
}

std::string to_text(const EachChannelResult& r, double t0) {
  const MlceResult* any = nullptr;
  std::size_t width = 7;  // "channel"
  for (const auto& c : r.channels) {
    if (c.result && !any) any = &*c.result;
    width = std::max(width, c.name.size());
  }
  // estimate_each_channel throws when no channel could be estimated
  if (!any) throw std::logic_error("to_text: no channel was estimated");
  const std::string u = rate_unit(*any);
  std::string s = fmt::format("{:<{}}  {:>12}  {:^28}  {:>10} {:>5} {:>3} {:>7} {:>11} {:>6}  {}\n", "channel", width,
                              "lambda " + u, "95 % interval", "from", "delay", "dim", "theiler", "fit", "R^2", "reading");
  for (const auto& c : r.channels) {
    if (!c.result) {
      s += fmt::format("{:<{}}  not estimated (why: the warning below)\n", c.name, width);
      continue;
    }
    const MlceResult& e = *c.result;
    const double from = t0 + static_cast<double>(e.skipped_start) * e.dt;
    const Reading reading = read_stability(e);  // reading.hpp: stability and the kind of motion
    s += fmt::format("{:<{}}  {:>12.6g}  {:>12.6g} .. {:<12.6g}  {:>10.6g} {:>5} {:>3} {:>7} {:>11} {:>6.4f}  {} ({})\n",
                     c.name, width, e.lambda, e.ci95_low, e.ci95_high, from, e.delay, e.dim, e.theiler,
                     fmt::format("{}..{}", e.fit.first, e.fit.last), e.r2, to_string(reading.stability), reading.motion);
  }
  s += "agreement       " + agreement_text(r.verdict, r.compared, u) + "\n";
  for (const auto& c : r.channels)
    if (c.result)
      for (const auto& w : c.result->warnings) s += "warning: " + c.name + ": " + w + "\n";
  for (const auto& w : r.warnings) s += "warning: " + w + "\n";
  return s;
}

std::string each_channel_curves_csv(const EachChannelResult& r) {
  std::string s = "channel,index,step,time,mean_log_distance,terms,in_fit,fit_line,local_slope\n";
  for (std::size_t k = 0; k < r.channels.size(); ++k) {
    if (!r.channels[k].result) continue;
    const MlceResult& e = *r.channels[k].result;
    const std::string prefix = fmt::format("{},{},", csv_field(r.channels[k].name), k);
    const std::vector<std::string> slope = local_slope_fields(e);
    for (std::size_t i = 0; i < e.curve.mean_log_distance.size(); ++i) s += prefix + curve_row(e, i) + slope[i] + "\n";
  }
  return s;
}

namespace {
std::string rate_unit(const KantzResult& r) { return r.time_unit.empty() ? "1/sample" : "1/" + r.time_unit; }
}  // namespace

nlohmann::json to_json(const KantzResult& r) {
  nlohmann::json j;
  j["method"] = "kantz";
  j["lambda"] = finite_or_null(r.lambda);
  j["lambda_unit"] = rate_unit(r);
  j["lambda_per_sample"] = finite_or_null(r.lambda_per_sample);
  j["lambda_range"] = {finite_or_null(r.lambda_low), finite_or_null(r.lambda_high)};
  j["log_base"] = "e";
  j["rosenstein_lambda"] = finite_or_null(r.rosenstein_lambda);
  j["reported_curve"] = r.reported_curve;
  j["rosenstein_curve"] = r.rosenstein_curve;
  j["phase_aligned"] = r.phase_aligned;
  j["reported_lambda"] = finite_or_null(r.reported_lambda);
  j["agrees"] = r.agrees;
  j["neutral_band"] = finite_or_null(r.neutral_band);
  j["delay"] = r.delay;
  j["dim"] = r.dim;
  j["theiler"] = r.theiler;
  j["horizon"] = r.horizon;
  j["nearest_distance"] = finite_or_null(r.nearest_distance);
  j["n_points"] = r.n_points;
  j["first_sample"] = r.first_sample;
  j["dt"] = r.dt;
  nlohmann::json radii = nlohmann::json::array();
  for (const auto& k : r.radii)
    radii.push_back({{"radius", k.kantz.radius},
                     {"references", k.kantz.curve.pairs},
                     {"mean_neighbours", k.kantz.mean_neighbours},
                     {"thinned", k.kantz.thinned},
                     {"lambda", finite_or_null(k.lambda)},
                     {"ci95", {finite_or_null(k.ci95_low), finite_or_null(k.ci95_high)}},
                     {"fit", {k.fit.first, k.fit.last}},
                     {"fit_rule", k.fit.rule},
                     {"curve_end", to_string(k.fit.end)}});
  j["radii"] = std::move(radii);
  j["warnings"] = r.warnings;
  return j;
}

std::string to_text(const KantzResult& r) {
  const std::string unit = rate_unit(r);
  std::string s = fmt::format(
      "Kantz's curves   m = {}, delay {}, Theiler window {}, horizon {} samples; median nearest-neighbour distance {:.4g}{}\n"
      "# radius refs neighbours fit lambda({}) ci95_low ci95_high end\n",
      r.dim, r.delay, r.theiler, r.horizon, r.nearest_distance, r.phase_aligned ? "; neighbours phase-aligned" : "", unit);
  for (const auto& k : r.radii)
    s += fmt::format("{:.4g} {} {:.1f} {}..{} {:.6g} {:.6g} {:.6g} {}\n", k.kantz.radius, k.kantz.curve.pairs,
                     k.kantz.mean_neighbours, k.fit.first, k.fit.last, k.lambda, k.ci95_low, k.ci95_high, to_string(k.fit.end));
  s += fmt::format("lambda (Kantz)  {:.6g} {} (median over {} radii; {:.6g} .. {:.6g})\n", r.lambda, unit, r.radii.size(),
                   r.lambda_low, r.lambda_high);
  s += fmt::format("Rosenstein      {:.6g} {} ({} curve, as the neighbourhoods{})\n", r.rosenstein_lambda, unit,
                   r.rosenstein_curve,
                   r.reported_curve != r.rosenstein_curve
                       ? fmt::format("; the estimate reports {:.6g} from the {} curve", r.reported_lambda, r.reported_curve)
                       : "");
  s += fmt::format("agree           {}\n", r.agrees ? "yes" : "NO: Kantz's neighbourhoods and Rosenstein's nearest pairs read differently");
  for (const auto& w : r.warnings) s += "warning: " + w + "\n";
  return s;
}

std::string kantz_csv(const KantzResult& r, bool with_step) {
  std::string s = with_step ? "step,time" : "time";
  for (const auto& k : r.radii) s += fmt::format(",S_radius_{:.4g}", k.kantz.radius);
  s += "\n";
  const std::size_t steps = r.radii.empty() ? 0 : r.radii.front().kantz.curve.mean_log_distance.size();
  for (std::size_t i = 0; i < steps; ++i) {
    s += with_step ? fmt::format("{},{:.10g}", i, r.dt * static_cast<double>(i)) : fmt::format("{:.10g}", r.dt * static_cast<double>(i));
    for (const auto& k : r.radii) s += fmt::format(",{:.10g}", k.kantz.curve.mean_log_distance[i]);
    s += "\n";
  }
  return s;
}

}  // namespace mlce::cli
