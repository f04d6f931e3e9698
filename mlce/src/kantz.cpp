#include "mlce/kantz.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "mlce/embedding.hpp"
#include "mlce/neighbours.hpp"
#include "mlce/numerics.hpp"

namespace mlce {

void KantzOptions::validate() const {
  if (dim < 1) throw OptionError("kantz.dim = 0: expected >= 1");
  if (delay < 1) throw OptionError("kantz.delay = 0: expected >= 1");
  if (horizon < 1) throw OptionError("kantz.horizon = 0: expected >= 1");
  if (batches < 2) throw OptionError("kantz.batches: expected >= 2");
  validate_repeat_resolution(repeat_resolution, "kantz.repeat_resolution");
  if (radii.empty()) {
    if (radius_count < 1) throw OptionError("kantz.radius_count = 0: expected >= 1 (or radii given)");
    if (!(radius_factor > 1.0 && std::isfinite(radius_factor)))
      throw OptionError("kantz.radius_factor: expected a finite factor > 1");
  }
  for (std::size_t k = 0; k < radii.size(); ++k) {
    if (!(radii[k] > 0.0 && std::isfinite(radii[k])))
      throw OptionError(fmt::format("kantz.radii[{}] = {}: expected a finite radius > 0", k, radii[k]));
    if (k > 0 && !(radii[k] > radii[k - 1]))
      throw OptionError(fmt::format("kantz.radii[{}] = {}: expected radii in increasing order", k, radii[k]));
  }
}

namespace {

/// The curve of one radius: per batch of contiguous references, the sums of ln of each
/// neighbourhood's mean distance i steps on, computed batch by batch (the result does not depend on
/// the thread count).
KantzCurve follow_neighbourhoods(const Series& s, const KantzOptions& o, const NeighbourIndex& index,
                                 const DelayEmbedding& every, const std::vector<std::uint32_t>& refs,
                                 std::size_t admissible, double radius) {
  const std::size_t H = o.horizon, m = o.dim, J = o.delay, span = H + (m - 1) * J;
  const std::size_t B = std::min(o.batches, refs.size());
  std::vector<std::vector<double>> batch_sum(B, std::vector<double>(H + 1, 0.0));
  std::vector<std::vector<std::size_t>> batch_terms(B, std::vector<std::size_t>(H + 1, 0));
  const bool align = o.phase_alignment == PhaseAlignment::on;
  std::size_t with_neighbourhood = 0, neighbours = 0, thinned = 0, zero_terms = 0, repeats = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : with_neighbourhood, neighbours, thinned, zero_terms, repeats)
  for (std::ptrdiff_t bb = 0; bb < static_cast<std::ptrdiff_t>(B); ++bb) {
    const auto b = static_cast<std::size_t>(bb);
    std::vector<CompensatedSum> sum(H + 1);
    std::vector<std::size_t> terms(H + 1, 0);
    std::vector<std::uint32_t> ball, kept;
    std::vector<double> e2(span + 1), distance_sum(H + 1);
    const std::size_t k0 = b * refs.size() / B, k1 = (b + 1) * refs.size() / B;
    for (std::size_t k = k0; k < k1; ++k) {
      const std::size_t n = refs[k];
      repeats += index.within(refs[k], radius, admissible, ball);
      if (ball.empty()) continue;
      const std::vector<std::uint32_t>* members = &ball;
      if (o.max_neighbours > 0 && ball.size() > o.max_neighbours) {
        kept.clear();
        for (std::size_t q = 0; q < o.max_neighbours; ++q) kept.push_back(ball[q * ball.size() / o.max_neighbours]);
        members = &kept;
        ++thinned;
      }
      ++with_neighbourhood;
      neighbours += members->size();
      std::fill(distance_sum.begin(), distance_sum.end(), 0.0);
      for (const std::uint32_t j : *members) {
        std::fill(e2.begin(), e2.end(), 0.0);
        // The neighbour moved along its own trajectory to the reference's phase (phase_alignment on).
        const SegmentPhase p = align ? closest_phase_on_segments(every, n, j, H) : SegmentPhase{j, 0.0};
        const double f = p.fraction;
        for (const auto& x : s.channels)
          for (std::size_t t = 0; t <= span; ++t) {
            const double e = x[n + t] - (f > 0.0 ? (1.0 - f) * x[p.base + t] + f * x[p.base + 1 + t] : x[p.base + t]);
            e2[t] += e * e;
          }
        for (std::size_t i = 0; i <= H; ++i) {
          double d2 = 0.0;
          for (std::size_t lag = 0; lag < m; ++lag) d2 += e2[i + lag * J];
          distance_sum[i] += std::sqrt(d2);
        }
      }
      const auto count = static_cast<double>(members->size());
      for (std::size_t i = 0; i <= H; ++i) {
        const double mean = distance_sum[i] / count;
        if (mean > 0.0) {
          sum[i].add(std::log(mean));
          ++terms[i];
        } else {
          ++zero_terms;  // the whole neighbourhood coincides with the reference: no log(0), left out
        }
      }
    }
    for (std::size_t i = 0; i <= H; ++i) batch_sum[b][i] = sum[i].value(), batch_terms[b][i] = terms[i];
  }
  KantzCurve out;
  out.radius = radius;
  out.thinned = thinned;
  out.mean_neighbours = with_neighbourhood ? static_cast<double>(neighbours) / static_cast<double>(with_neighbourhood) : 0.0;
  DivergenceCurve& c = out.curve;
  c.dt = s.dt;
  c.references = refs.size();
  c.pairs = with_neighbourhood;
  c.admissible_points = admissible;
  c.zero_distance_terms = zero_terms;
  c.zero_distance_candidates = repeats;
  if (with_neighbourhood == 0) return out;
  if (const auto empty = mean_over_batches(batch_sum, batch_terms, c))
    throw InputError(fmt::format("every neighbourhood within {:.4g} coincides with its reference {} steps ahead: the "
                                 "series repeats itself exactly (periodic or quantised); no divergence to measure",
                                 radius, *empty));
  if (zero_terms > 0)
    c.warnings.push_back(fmt::format("{} neighbourhood means at zero distance were left out (never log 0): the "
                                     "trajectories coincide there", zero_terms));
  return out;
}

}  // namespace

KantzCurves kantz_curves(const Series& series, const KantzOptions& options) {
  options.validate();
  validate_series(series);
  const std::size_t n = series.size();
  const std::size_t needed = (options.dim - 1) * options.delay + options.horizon + options.theiler + 2;
  if (n < needed)
    throw InputError(fmt::format("series too short for Kantz's curves: {} samples, but m = {}, delay = {}, horizon = {} "
                                 "and Theiler window = {} need at least {} ((m-1)*delay + horizon + theiler + 2)",
                                 n, options.dim, options.delay, options.horizon, options.theiler, needed));
  const Series s = scaled_to_unit_deviation(series);
  std::vector<std::span<const double>> channels(s.channels.begin(), s.channels.end());
  const std::size_t M = DelayEmbedding::max_points(n, options.dim, options.delay);  // eq. 17
  const std::size_t admissible = M - options.horizon;  // points whose trajectory can be followed for H steps
  const DelayEmbedding points(channels, options.dim, options.delay, admissible);
  NeighbourOptions no;
  no.theiler = options.theiler;
  no.repeat_resolution = options.repeat_resolution;
  no.repeat_ceiling = kRepeatCeilingInDeviations;  // the channels are in standard deviations
  const NeighbourIndex index(points, no);
  const std::vector<std::uint32_t> refs = strided_indices(admissible, options.max_references);

  KantzCurves out;
  std::vector<double> radii = options.radii;
  {
    const NeighbourResult nearest = index.nearest(refs, admissible);
    std::vector<double> found;
    for (const double d : nearest.distance)
      if (std::isfinite(d)) found.push_back(d);
    if (found.empty())
      throw InputError(fmt::format("no reference point has a neighbour outside the Theiler window of {} samples: the "
                                   "series is too short for it", options.theiler));
    out.nearest_distance = median(found);
  }
  // The base radius: the median nearest-neighbour distance rounded up to two significant digits. Not
  // the median itself, which is the distance of one reference to its neighbour: that neighbour would
  // sit on the ball's edge, and the rounding of the series' scaling (x 1e-200, x 1e200) would move it
  // in or out, and the curve with it.
  if (radii.empty()) {
    const double unit = std::pow(10.0, std::floor(std::log10(out.nearest_distance)) - 1.0);
    const double base = std::ceil(out.nearest_distance / unit) * unit;
    for (std::size_t k = 0; k < options.radius_count; ++k)
      radii.push_back(base * std::pow(options.radius_factor, static_cast<double>(k)));
  }

  const DelayEmbedding every(channels, options.dim, options.delay, M);
  const double attractor = attractor_log_distance(every, options.theiler);
  for (std::size_t k = 0; k < radii.size(); ++k) {
    KantzCurve c = follow_neighbourhoods(s, options, index, every, refs, admissible, radii[k]);
    if (options.progress)
      options.progress(fmt::format("Kantz radius {} of {}", k + 1, radii.size()),
                       static_cast<double>(k + 1) / static_cast<double>(radii.size()));
    if (c.curve.pairs == 0) {
      out.warnings.push_back(fmt::format("radius {:.4g}: no reference point has a neighbour within it (outside the "
                                         "Theiler window); no curve", radii[k]));
      continue;
    }
    c.curve.attractor_log_distance = attractor;
    out.curves.push_back(std::move(c));
  }
  if (out.curves.empty())
    throw InputError(fmt::format("no radius up to {:.4g} gives any reference point a neighbourhood (the nearest "
                                 "neighbours lie {:.4g} away in the median): give larger radii",
                                 radii.back(), out.nearest_distance));
  return out;
}

KantzResult estimate_kantz(const Series& series, const MlceResult& estimate, KantzOptions options) {
  validate_series(series);
  if (estimate.skipped_start + estimate.n_points > series.size())
    throw std::logic_error("estimate_kantz: the estimate analysed samples beyond the series");
  options.dim = estimate.dim, options.delay = estimate.delay, options.theiler = estimate.theiler;
  options.horizon = estimate.horizon;
  if (options.phase_alignment == PhaseAlignment::automatic)
    options.phase_alignment = estimate.curve.phase_aligned ? PhaseAlignment::on : PhaseAlignment::off;
  Series analysed = leading_samples(series, estimate.skipped_start + estimate.n_points);
  if (estimate.skipped_start > 0) {
    analysed.t0 = series.time(estimate.skipped_start);
    for (auto& c : analysed.channels) c.erase(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(estimate.skipped_start));
  }
  KantzCurves curves = kantz_curves(analysed, options);

  KantzResult r;
  r.dim = options.dim, r.delay = options.delay, r.theiler = options.theiler, r.horizon = options.horizon;
  r.first_sample = estimate.skipped_start, r.n_points = estimate.n_points;
  r.dt = series.dt, r.time_unit = series.time_unit;
  r.nearest_distance = curves.nearest_distance;
  r.phase_aligned = options.phase_alignment == PhaseAlignment::on;
  r.warnings = std::move(curves.warnings);
  std::vector<double> lambdas;
  // The estimate's fit options, but the region extended to the whole min_periods: the stop before a
  // bend (FitOptions::extension_straightness) was measured on Rosenstein's curve of one neighbour, and
  // the log of a neighbourhood's mean distance bends otherwise: with it, Kantz's median radius read
  // Lorenz x within 5 % on 69 of 128 series (mean 1.050) where it reads 101 (mean 1.011) without
  // (`build/kantz_vs_rosenstein`).
  FitOptions fit_options = estimate.fit_options;
  fit_options.extension_straightness = 0.0;
  for (auto& c : curves.curves) {
    KantzRadius k;
    k.fit = fit_divergence(c.curve, fit_options);
    k.lambda = k.fit.slope / series.dt;
    k.ci95_low = k.fit.ci_low / series.dt, k.ci95_high = k.fit.ci_high / series.dt;
    for (const auto& w : c.curve.warnings) r.warnings.push_back(fmt::format("radius {:.4g}: {}", c.radius, w));
    for (const auto& w : k.fit.warnings) r.warnings.push_back(fmt::format("radius {:.4g}: {}", c.radius, w));
    if (c.curve.pairs < kFewPairs)
      r.warnings.push_back(fmt::format("radius {:.4g}: only {} reference points have a neighbourhood (fewer than {}): "
                                       "its curve and interval rest on too few", c.radius, c.curve.pairs, kFewPairs));
    k.kantz = std::move(c);
    lambdas.push_back(k.lambda);
    r.radii.push_back(std::move(k));
  }
  r.lambda = median(lambdas);
  r.lambda_per_sample = r.lambda * series.dt;
  r.lambda_low = *std::min_element(lambdas.begin(), lambdas.end());
  r.lambda_high = *std::max_element(lambdas.begin(), lambdas.end());
  // Rosenstein's curve treated as the neighbourhoods were: phase-aligned or plain, never
  // noise-compensated (Kantz's mean distances carry the noise as eq. 23's do). Its interval is known
  // only when it is the reported curve.
  r.reported_lambda = estimate.lambda;
  r.reported_curve = estimate.curve.phase_aligned ? "phase-aligned" : estimate.noise_compensated ? "noise-compensated" : "plain";
  r.rosenstein_lambda = estimate.lambda;
  r.rosenstein_curve = estimate.curve.phase_aligned ? "phase-aligned" : "plain";
  double estimate_half_width = 0.5 * (estimate.ci95_high - estimate.ci95_low);
  if (estimate.curve.phase_aligned && !r.phase_aligned && std::isfinite(estimate.unaligned_lambda)) {
    r.rosenstein_lambda = estimate.unaligned_lambda, estimate_half_width = 0.0, r.rosenstein_curve = "plain";
  } else if (estimate.noise_compensated && std::isfinite(estimate.uncompensated_lambda)) {
    r.rosenstein_lambda = estimate.uncompensated_lambda, estimate_half_width = 0.0;
  }
  // The median radius' interval (of the middle two, the upper), beside the estimate's; two rates
  // within the reading's neutral band of 0 (ReadingOptions::neutral_per_period per mean period) both
  // read neutral whatever their ratio (a limit cycle's estimates near 0).
  const KantzRadius& middle = r.radii[r.radii.size() / 2];
  const double f = estimate.mean_period.mean_frequency;  // cycles per time unit
  r.neutral_band = f > 0.0 && std::isfinite(f) ? ReadingOptions{}.neutral_per_period * f : 0.0;
  const double half_widths = estimate_half_width + 0.5 * (middle.ci95_high - middle.ci95_low);
  const double tolerance =
      std::max({half_widths, 0.05 * std::max(std::abs(r.lambda), std::abs(r.rosenstein_lambda)), 2.0 * r.neutral_band});
  r.agrees = std::abs(r.lambda - r.rosenstein_lambda) <= tolerance;
  const double spread = r.lambda_high - r.lambda_low;
  if (spread > 2.0 * r.neutral_band && spread > 0.25 * std::max(std::abs(r.lambda_high), std::abs(r.lambda_low)))
    r.warnings.push_back(fmt::format("the radii's slopes differ by more than 25 % ({:.4g} .. {:.4g}): their curves do not "
                                     "run parallel, and the region is not one of exponential divergence at every radius",
                                     r.lambda_low, r.lambda_high));
  return r;
}

}  // namespace mlce
