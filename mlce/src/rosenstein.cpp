#include "mlce/rosenstein.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include <boost/math/tools/minima.hpp>

#include "mlce/embedding.hpp"
#include "mlce/neighbours.hpp"
#include "mlce/numerics.hpp"

namespace mlce {

void RosensteinOptions::validate() const {
  if (dim < 1) throw OptionError("rosenstein.dim = 0: expected >= 1");
  if (delay < 1) throw OptionError("rosenstein.delay = 0: expected >= 1");
  if (horizon < 1) throw OptionError("rosenstein.horizon = 0: expected >= 1");
  if (batches < 2) throw OptionError("rosenstein.batches: expected >= 2");
  if (!(eps >= 0.0)) throw OptionError("rosenstein.eps: expected >= 0");
  validate_repeat_resolution(repeat_resolution, "rosenstein.repeat_resolution");
  for (const double v : noise_deviation)
    if (!(v >= 0.0 && std::isfinite(v))) throw OptionError("rosenstein.noise_deviation: expected finite values >= 0");
}

double attractor_log_distance(const DelayEmbedding& points, std::size_t theiler) {
  const std::size_t M = points.size();
  if (M < theiler + 2) return std::numeric_limits<double>::quiet_NaN();
  std::uint64_t state = 0x6D6C6365ull;  // "mlce"
  CompensatedSum sum;
  std::size_t n = 0;
  const std::size_t wanted = std::min<std::size_t>(20000, 4 * M);
  for (std::size_t trial = 0; trial < 4 * wanted && n < wanted; ++trial) {
    const std::size_t a = splitmix64(state) % M, b = splitmix64(state) % M;
    if ((a > b ? a - b : b - a) <= theiler) continue;
    const double d2 = points.squared_distance(a, b);
    if (d2 > 0.0) sum.add(0.5 * std::log(d2)), ++n;
  }
  return n ? sum.value() / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN();
}

namespace {

/// Squared distance from embedded point j to the cubic through the embedded points around the
/// continuous index u (floor(u) - 1 .. floor(u) + 2, all of them points of `points`).
double cubic_squared_distance(const DelayEmbedding& points, std::size_t j, double u) {
  const auto a = static_cast<std::size_t>(std::floor(u));
  const auto w = lagrange_cubic_weights(u - static_cast<double>(a));
  double sum = 0.0;
  for (std::size_t d = 0, D = points.dimension(); d < D; ++d) {
    const double e = points.coordinate(j, d) - (w[0] * points.coordinate(a - 1, d) + w[1] * points.coordinate(a, d) +
                                                w[2] * points.coordinate(a + 1, d) + w[3] * points.coordinate(a + 2, d));
    sum += e * e;
  }
  return sum;
}

}  // namespace

std::size_t minimum_length(const RosensteinOptions& o) { return (o.dim - 1) * o.delay + o.horizon + o.theiler + 2; }

namespace {
void require_length(std::size_t n, const RosensteinOptions& o) {
  if (n < minimum_length(o))
    throw InputError("series too short: " + std::to_string(n) + " samples, but m = " + std::to_string(o.dim) +
                     ", delay = " + std::to_string(o.delay) + ", horizon = " + std::to_string(o.horizon) +
                     " and Theiler window = " + std::to_string(o.theiler) + " need at least " +
                     std::to_string(minimum_length(o)) + " ((m-1)*delay + horizon + theiler + 2)");
}
}  // namespace

struct PairFinder::State {
  Series scaled;
  std::unique_ptr<DelayEmbedding> embedding;  // the points admissible at the shortest horizon
  std::unique_ptr<NeighbourIndex> index;
};

PairFinder::PairFinder(const Series& series, const RosensteinOptions& options)
    : options_(options), state_(std::make_unique<State>()) {
  options.validate();
  validate_series(series);
  const std::size_t n = series.size();
  require_length(n, options);
  state_->scaled = scaled_to_unit_deviation(series);
  std::vector<std::span<const double>> channels;
  for (const auto& c : state_->scaled.channels) channels.emplace_back(c);
  points_ = DelayEmbedding::max_points(n, options.dim, options.delay);  // eq. 17
  state_->embedding = std::make_unique<DelayEmbedding>(channels, options.dim, options.delay, points_ - options.horizon);
  NeighbourOptions nopt;
  nopt.theiler = options.theiler;
  nopt.eps = options.eps;
  nopt.repeat_resolution = options.repeat_resolution;
  nopt.repeat_ceiling = kRepeatCeilingInDeviations;  // the channels are in standard deviations
  state_->index = std::make_unique<NeighbourIndex>(*state_->embedding, nopt);
}

PairFinder::~PairFinder() = default;

NeighbourPairs PairFinder::find(std::size_t horizon) const {
  if (horizon < options_.horizon) throw std::logic_error("PairFinder::find: a horizon shorter than the one it was built for");
  RosensteinOptions o = options_;
  o.horizon = horizon;
  require_length(state_->scaled.size(), o);
  const std::size_t L = points_ - horizon;  // points whose trajectory can be followed for H steps
  NeighbourPairs pairs;
  pairs.references = strided_indices(L, options_.max_references);
  pairs.dim = o.dim, pairs.delay = o.delay, pairs.horizon = horizon, pairs.theiler = o.theiler;
  pairs.nearest = state_->index->nearest(pairs.references, L);  // eq. 18 with eq. 20
  return pairs;
}

NeighbourPairs find_pairs(const Series& series, const RosensteinOptions& options) {
  return PairFinder(series, options).find(options.horizon);
}

namespace {
/// DivergenceCurve::compensated_log_distance (and its batch curves) from each batch's sums over its
/// pairs of d^2 / w_j and of the noise's expected share / w_j, and its count of pairs (those whose
/// mean square w_j along the curve is positive).
void compensated_curve_from_sums(DivergenceCurve& curve, const std::vector<std::vector<double>>& batch_square,
                      const std::vector<std::vector<double>>& batch_noise, const std::vector<std::size_t>& batch_pairs) {
  const std::size_t H = curve.mean_log_distance.size() - 1, B = batch_square.size();
  std::vector<double> y(H + 1), share(H + 1);
  std::vector<std::vector<double>> batches(B, std::vector<double>(H + 1, std::nan("")));
  for (std::size_t i = 0; i <= H; ++i) {
    CompensatedSum square, noise;
    std::size_t pairs = 0;
    for (std::size_t b = 0; b < B; ++b) {
      square.add(batch_square[b][i]);
      noise.add(batch_noise[b][i]);
      const double rest = batch_square[b][i] - batch_noise[b][i];
      const std::size_t n = batch_pairs[b];
      if (rest > 0.0 && n > 0) batches[b][i] = 0.5 * std::log(rest / static_cast<double>(n));
      pairs += n;
    }
    const double rest = square.value() - noise.value();
    if (!(rest > 0.0) || pairs == 0) {
      curve.compensation_failed_step = i;
      return;
    }
    y[i] = 0.5 * std::log(rest / static_cast<double>(pairs));
    share[i] = noise.value() / square.value();
  }
  curve.compensated_noise_share = std::move(share);
  curve.compensated_log_distance = std::move(y);
  curve.compensated_batch_mean = std::move(batches);
}
}  // namespace

std::vector<double> noise_level_shift(const DivergenceCurve& curve) {
  std::vector<double> shift;
  shift.reserve(curve.compensated_noise_share.size());
  for (const double s : curve.compensated_noise_share) shift.push_back(-0.5 * s / (1.0 - s));
  return shift;
}

double noise_level_sensitivity(const DivergenceCurve& curve, std::size_t first, std::size_t last) {
  if (curve.compensated_noise_share.empty()) return 0.0;
  if (first >= last || last >= curve.compensated_noise_share.size())
    throw std::logic_error("noise_level_sensitivity: the region is not within the curve");
  return fit_line(noise_level_shift(curve).data(), first, last).slope;
}

namespace {

/// The pairs were found for the options' m, delay and horizon, one neighbour per reference.
void require_pairs_for(const char* who, const RosensteinOptions& options, const NeighbourPairs& pairs) {
  if (pairs.dim != options.dim || pairs.delay != options.delay || pairs.horizon != options.horizon ||
      pairs.references.size() != pairs.nearest.neighbour.size())
    throw std::logic_error(std::string(who) + ": the pairs were found for other options (m, delay, horizon)");
}

}  // namespace

SegmentPhase closest_phase_on_segments(const DelayEmbedding& all, std::size_t j, std::size_t jn, std::size_t horizon) {
  const std::size_t M = all.size();
  SegmentPhase out{jn, 0.0};
  double best = all.squared_distance(j, jn);
  for (const std::size_t a : {jn - 1, jn}) {
    if ((a == jn - 1 && jn == 0) || a + 1 + horizon >= M) continue;  // both ends followed for the horizon
    const double d00 = all.squared_distance(a, a + 1);
    if (!(d00 > 0.0)) continue;
    // |p_j - p_a - f (p_{a+1} - p_a)|^2 is least at f = (p_j - p_a).(p_{a+1} - p_a) / |p_{a+1} - p_a|^2.
    const double dot = 0.5 * (all.squared_distance(j, a) + d00 - all.squared_distance(j, a + 1));
    const double f = std::clamp(dot / d00, 0.0, 1.0);
    const double d2 = all.squared_distance_between(j, a, f);
    if (d2 < best) best = d2, out = {a, f};
  }
  return out;
}

namespace {

/// neighbour_phases over the embedding of the series in unit-deviation coordinates (follow_pairs has
/// built it already).
NeighbourPhases neighbour_phases(const DelayEmbedding& all, const RosensteinOptions& options, const NeighbourPairs& pairs) {
  const std::size_t H = options.horizon, M = all.size();
  const auto& refs = pairs.references;
  const NeighbourResult& nn = pairs.nearest;
  // Neighbour positions along their own trajectories: base sample and fraction of the way to the
  // next one (align_phase), chosen on the two segments around the neighbour by least squares.
  NeighbourPhases out;
  auto& base = out.base;
  auto& fraction = out.fraction;
  auto& cubic = out.cubic;
  base.assign(refs.size(), 0);
  fraction.assign(refs.size(), 0.0);
  cubic.assign(refs.size(), 0);
  CompensatedSum shift;
  for (std::size_t k = 0; k < refs.size(); ++k) {
    if (nn.neighbour[k] == NeighbourResult::none) continue;
    base[k] = nn.neighbour[k];
    if (!options.align_phase) continue;
    const std::size_t j = refs[k], jn = nn.neighbour[k];
    const SegmentPhase phase = closest_phase_on_segments(all, j, jn, H);
    base[k] = phase.base, fraction[k] = phase.fraction;
    if (options.interpolation == RosensteinOptions::Interpolation::cubic && jn >= 2 && jn + H + 3 <= M) {
      // On the cubic through the samples around it the neighbour's closest phase differs from the
      // segment's: searched over [jn - 1, jn + 1), and compared with the segment's choice, which
      // is kept if the search (it assumes one minimum there) lands higher.
      const double linear_u = static_cast<double>(base[k]) + fraction[k];
      double best_u = linear_u, best_d2 = cubic_squared_distance(all, j, linear_u);
      // Brent's minimiser to 2^-26 of a sample (boost/math/tools/minima.hpp), below jn + 1 so
      // that floor(u) <= jn (the pair's followed span checked above).
      const auto [u, d2] = boost::math::tools::brent_find_minima(
          [&](double v) { return cubic_squared_distance(all, j, v); }, static_cast<double>(jn) - 1.0,
          std::nextafter(static_cast<double>(jn) + 1.0, 0.0), 26);
      if (d2 < best_d2) best_u = u;
      base[k] = std::min(static_cast<std::size_t>(std::floor(best_u)), jn);  // u < jn + 1
      fraction[k] = best_u - static_cast<double>(base[k]);
      cubic[k] = true;
    }
    shift.add(std::abs(static_cast<double>(base[k]) + fraction[k] - static_cast<double>(jn)));
  }
  out.shift_sum = shift.value();
  return out;
}

/// The delay vectors of every point (eq. 17) of `scaled`, the series in the curve's unit-deviation
/// coordinates, which must outlive them.
DelayEmbedding every_point(const Series& scaled, const RosensteinOptions& options) {
  std::vector<std::span<const double>> channels(scaled.channels.begin(), scaled.channels.end());
  return {std::move(channels), options.dim, options.delay, DelayEmbedding::max_points(scaled.size(), options.dim, options.delay)};
}
}  // namespace

NeighbourPhases neighbour_phases(const Series& series, const RosensteinOptions& options, const NeighbourPairs& pairs) {
  options.validate();
  validate_series(series);
  require_pairs_for("neighbour_phases", options, pairs);
  const Series s = scaled_to_unit_deviation(series);
  return neighbour_phases(every_point(s, options), options, pairs);
}

namespace {
/// How far a repeated stretch may part within it, as a multiple of the repeat's own tolerance: a
/// stable periodic orbit of a map stretches a near repeat within each period before it contracts it
/// (the logistic map's period-3 orbit at r = 3.84 by ~10x: its near repeats, 1e-10 of a point's
/// size, part to ~1e-9 and were read as a quantum, "lambda unreliable", until this margin). A
/// quantised series' equal points part by a quantum, orders of magnitude more; a chaotic map's near
/// repeats part beyond it within tens of its iterations (the stretch runs a horizon, >= 32).
constexpr double kStretchSpread = 1e3;

/// Share of the references whose repeat (NeighbourResult::repeat_of) stays a repeat for the next
/// `steps` samples, every channel equal to within kStretchSpread x `resolution` of its size or of its
/// standard deviation (up to 200 references, evenly taken): ~1 for a periodic series, ~0 for a
/// quantised aperiodic one whose equal points part at once.
double share_repeating_stretches(const Series& s, const NeighbourResult& nn, const std::vector<std::uint32_t>& refs,
                                 std::size_t steps, double resolution) {
  std::vector<std::size_t> with_repeat;
  for (std::size_t k = 0; k < refs.size(); ++k)
    if (nn.repeat_of[k] != NeighbourResult::none) with_repeat.push_back(k);
  if (with_repeat.empty()) return 0.0;
  const std::size_t sample = std::min<std::size_t>(with_repeat.size(), 200), n = s.size();
  std::size_t stay = 0;
  for (std::size_t t = 0; t < sample; ++t) {
    const std::size_t k = with_repeat[t * with_repeat.size() / sample];
    const std::size_t i = refs[k], j = nn.repeat_of[k], last = std::min(steps, n - 1 - std::max(i, j));
    bool same = true;
    for (std::size_t step = 1; same && step <= last; ++step)
      for (const auto& c : s.channels) {
        const double a = c[i + step], b = c[j + step];
        // Channels are in units of their standard deviation: the 1 is a floor for values that
        // cross 0 (sin(pi) written as 1.2e-16 one period, -2.4e-16 the next).
        // The same ceiling as the neighbour search's (a signal riding far from zero).
        const double repeat = std::min(resolution * (std::abs(a) + std::abs(b) + 1.0), kRepeatCeilingInDeviations);
        if (std::abs(a - b) > kStretchSpread * repeat) {
          same = false;
          break;
        }
      }
    stay += same;
  }
  return static_cast<double>(stay) / static_cast<double>(sample);
}
}  // namespace

std::optional<std::size_t> mean_over_batches(const std::vector<std::vector<double>>& batch_sum,
                                             const std::vector<std::vector<std::size_t>>& batch_terms,
                                             DivergenceCurve& curve) {
  const std::size_t B = batch_sum.size(), steps = B > 0 ? batch_sum.front().size() : 0;
  curve.mean_log_distance.assign(steps, 0.0);
  curve.terms.assign(steps, 0);
  curve.batch_mean.assign(B, std::vector<double>(steps, std::nan("")));
  for (std::size_t i = 0; i < steps; ++i) {
    CompensatedSum total;
    for (std::size_t b = 0; b < B; ++b) {
      total.add(batch_sum[b][i]);
      curve.terms[i] += batch_terms[b][i];
      if (batch_terms[b][i] > 0) curve.batch_mean[b][i] = batch_sum[b][i] / static_cast<double>(batch_terms[b][i]);
    }
    if (curve.terms[i] == 0) return i;
    curve.mean_log_distance[i] = total.value() / static_cast<double>(curve.terms[i]);
  }
  return std::nullopt;
}

DivergenceCurve follow_pairs(const Series& series, const RosensteinOptions& options, const NeighbourPairs& pairs) {
  options.validate();
  validate_series(series);
  if (!options.noise_deviation.empty() && options.noise_deviation.size() != series.channels.size())
    throw std::logic_error("follow_pairs: noise_deviation needs one value per channel");
  require_pairs_for("follow_pairs", options, pairs);
  const Series s = scaled_to_unit_deviation(series);
  const std::size_t H = options.horizon;
  const DelayEmbedding all = every_point(s, options);
  const std::size_t M = all.size();  // eq. 17
  const auto& refs = pairs.references;
  const NeighbourResult& nn = pairs.nearest;

  DivergenceCurve curve;
  curve.dt = s.dt;
  curve.admissible_points = M - H;
  curve.references = refs.size();
  curve.zero_distance_candidates = nn.zero_distance_candidates;
  curve.pairs = refs.size() - nn.without_neighbour;
  if (curve.pairs == 0)
    throw InputError("no reference point has a neighbour outside the Theiler window of " +
                     std::to_string(options.theiler) + " samples: the series is too short for it");

  const NeighbourPhases phases = neighbour_phases(all, options, pairs);
  const std::vector<std::size_t>& base = phases.base;
  const std::vector<double>& fraction = phases.fraction;
  const std::vector<char>& cubic = phases.cubic;
  curve.phase_aligned = options.align_phase;
  curve.cubic_pairs = static_cast<std::size_t>(std::count(cubic.begin(), cubic.end(), 1));
  if (options.align_phase && curve.pairs > 0) curve.mean_phase_shift = phases.shift_sum / static_cast<double>(curve.pairs);

  // Per batch of contiguous references: sums of ln d_j(i) (eq. 22), computed batch by batch so the
  // result is the same whatever the thread count.
  const std::size_t B = std::min(options.batches, refs.size());
  std::vector<std::vector<double>> batch_sum(B, std::vector<double>(H + 1, 0.0));
  std::vector<std::vector<std::size_t>> batch_terms(B, std::vector<std::size_t>(H + 1, 0));
  std::size_t zero_terms = 0;
  const std::size_t m = options.dim, J = options.delay, span = H + (m - 1) * J;
  // Noise compensation (DivergenceCurve::compensated_log_distance): per batch, the sums over its
  // pairs of d^2 and of the noise's expected share of it. The noise one coordinate of a pair adds
  // with unit interpolation weights: the sum over channels of s_c^2.
  const bool compensate = !options.noise_deviation.empty();
  double coordinate_noise = 0.0;
  for (const double v : options.noise_deviation) coordinate_noise += v * v;
  // Coordinates at step i whose samples carry fresh noise: all m but, at i = k J (k < m), the m - k
  // whose samples the search compared.
  auto fresh_coordinates = [&](std::size_t i) { return i % J == 0 && i / J < m ? i / J : m; };
  std::vector<std::vector<double>> batch_square(compensate ? B : 0, std::vector<double>(H + 1, 0.0));
  std::vector<std::vector<double>> batch_noise(compensate ? B : 0, std::vector<double>(H + 1, 0.0));
  std::vector<std::size_t> batch_pairs(B, 0);
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : zero_terms)
  for (std::ptrdiff_t bb = 0; bb < static_cast<std::ptrdiff_t>(B); ++bb) {
    const auto b = static_cast<std::size_t>(bb);
    // sum_j ln d_j(i) = ln prod_j d_j(i)^2 / 2, the product kept as mantissa x 2^exponent: the
    // running product is renormalised (frexp) whenever it leaves [2^-600, 2^600], and a factor
    // outside [2^-400, 2^400] enters by its mantissa, so no product under- or overflows. One log
    // per step instead of one per term; n factors carry a relative rounding error of at most
    // ~n x 1.1e-16, i.e. an absolute error of that size in the sum of n logs (1e-13 for 1250 terms).
    std::vector<double> mantissa(H + 1, 1.0);
    std::vector<long long> exponent(H + 1, 0);
    std::vector<std::size_t> terms(H + 1, 0);
    // Squared differences of the two trajectories' samples, summed over channels: the squared
    // distance of the embedded points i steps on is the sum of m of them, J apart (eq. 16).
    std::vector<double> e2(span + 1), pair_square(H + 1);
    const std::size_t k0 = b * refs.size() / B, k1 = (b + 1) * refs.size() / B;
    for (std::size_t k = k0; k < k1; ++k) {
      if (nn.neighbour[k] == NeighbourResult::none) continue;
      const std::size_t j = refs[k], jn = base[k];
      const double f = fraction[k];
      std::fill(e2.begin(), e2.end(), 0.0);
      // 1 + the sum of the neighbour's interpolation weights squared: the noise variance of the
      // difference of the two points' coordinates in units of one sample's.
      double weights_square = 1.0;
      for (const auto& x : s.channels) {
        if (f > 0.0 && cubic[k]) {
          const auto w = lagrange_cubic_weights(f);
          weights_square = 1.0 + w[0] * w[0] + w[1] * w[1] + w[2] * w[2] + w[3] * w[3];
          for (std::size_t t = 0; t <= span; ++t) {
            const double e = x[j + t] - (w[0] * x[jn + t - 1] + w[1] * x[jn + t] + w[2] * x[jn + t + 1] + w[3] * x[jn + t + 2]);
            e2[t] += e * e;
          }
        } else if (f > 0.0) {
          weights_square = 1.0 + (1.0 - f) * (1.0 - f) + f * f;
          for (std::size_t t = 0; t <= span; ++t) {
            const double e = x[j + t] - ((1.0 - f) * x[jn + t] + f * x[jn + t + 1]);
            e2[t] += e * e;
          }
        } else {
          weights_square = 2.0;
          for (std::size_t t = 0; t <= span; ++t) {
            const double e = x[j + t] - x[jn + t];
            e2[t] += e * e;
          }
        }
      }
      for (std::size_t i = 0; i <= H; ++i) {
        double& d2 = pair_square[i];
        d2 = 0.0;
        for (std::size_t lag = 0; lag < m; ++lag) d2 += e2[i + lag * J];
      }
      if (compensate) {
        // Each pair enters by its squared distances over their own mean over the curve, as every
        // pair enters <ln d> with the same weight: unweighted, ln <d^2> would follow the pairs of
        // largest amplitude alone (a decay's first turns, where a faster mode still lives).
        CompensatedSum total;
        for (const double d2 : pair_square) total.add(d2);
        const double scale = total.value() / static_cast<double>(H + 1);
        if (scale > 0.0) {
          for (std::size_t i = 0; i <= H; ++i) {
            batch_square[b][i] += pair_square[i] / scale;
            batch_noise[b][i] += weights_square * coordinate_noise * static_cast<double>(fresh_coordinates(i)) / scale;
          }
          ++batch_pairs[b];
        }
      }
      for (std::size_t i = 0; i <= H; ++i) {
        const double d2 = pair_square[i];
        if (d2 > 0.0) {
          double& p = mantissa[i];
          int e = 0;
          if (d2 > 0x1p-400 && d2 < 0x1p400) {
            p *= d2;  // p in [2^-600, 2^600] before: the product stays a normal number
          } else {
            p *= std::frexp(d2, &e);  // an extreme (e.g. subnormal) factor enters by its mantissa
            exponent[i] += e;
          }
          if (!(p > 0x1p-600 && p < 0x1p600)) {
            p = std::frexp(p, &e);
            exponent[i] += e;
          }
          ++terms[i];
        } else {
          ++zero_terms;  // the pair's trajectories coincide: no log(0), term left out
        }
      }
    }
    for (std::size_t i = 0; i <= H; ++i) {
      batch_sum[b][i] = 0.5 * (std::log(mantissa[i]) + static_cast<double>(exponent[i]) * std::numbers::ln2);
      batch_terms[b][i] = terms[i];
    }
  }
  curve.zero_distance_terms = zero_terms;
  curve.attractor_log_distance = attractor_log_distance(all, options.theiler);
  if (const auto empty = mean_over_batches(batch_sum, batch_terms, curve))
    throw InputError("every neighbour pair is at zero distance " + std::to_string(*empty) +
                     " steps ahead: the series repeats itself exactly (periodic or quantised); no divergence to measure");
  if (compensate) compensated_curve_from_sums(curve, batch_square, batch_noise, batch_pairs);
  if (nn.near_repeat_candidates > 0)
    curve.warnings.push_back(fmt::format(
        "{} neighbour candidates within {:g} of their reference point's size and {:g} standard deviations (the point "
        "repeats to the rounding: a signal periodic to the last digits) were passed over; the nearest neighbour beyond "
        "was used",
        nn.near_repeat_candidates, options.repeat_resolution, kRepeatCeilingInDeviations));
  if (nn.zero_distance_candidates > 0) {
    curve.warnings.push_back(std::to_string(nn.zero_distance_candidates) +
                             " zero-distance neighbour candidates (repeated points: periodic or quantised signal) were "
                             "passed over; the nearest neighbour at a positive distance was used");
    // As many repeats as references: the series' resolution (its quantum, or the digits it was
    // printed with) is as coarse as the nearest-neighbour distances, which then jump in steps of it
    // (Lorenz x rounded to 1 read 1.84 lambda_1; to 0.01, as unrounded) -- unless the repeats are
    // of whole stretches: a periodic motion written with few digits (a limit cycle locked to an
    // output step that divides its period) repeats every period, and its neighbours a sample of
    // phase away read it as it is.
    const bool as_many_as_references = nn.zero_distance_candidates >= refs.size();
    const double stretches =
        as_many_as_references ? share_repeating_stretches(s, nn, refs, H, options.repeat_resolution) : 0.0;
    if (as_many_as_references && stretches >= 0.9)
      curve.warnings.push_back(fmt::format(
          "the series repeats whole stretches ({:.0f} % of the repeated points' next {} samples repeat too): a motion "
          "periodic at its written digits, not a coarse resolution; the neighbours are the nearest points of the "
          "other phases",
          100.0 * stretches, H));
    curve.coarse_resolution = as_many_as_references && stretches < 0.9;
    if (curve.coarse_resolution)
      curve.warnings.push_back("the series repeats its points " +
                               std::to_string(nn.zero_distance_candidates / std::max<std::size_t>(refs.size(), 1)) +
                               " times per reference point on average: its resolution (quantum or printed digits) is as "
                               "coarse as the neighbour distances and lambda is unreliable; write it with more digits, "
                               "or dither it by one quantum (--dither)");
  }
  if (zero_terms > 0)
    curve.warnings.push_back(std::to_string(zero_terms) +
                             " zero distances along the followed pairs were left out of the mean log-distance "
                             "(never log 0); the trajectories coincide there");
  if (nn.without_neighbour > 0)
    curve.warnings.push_back(std::to_string(nn.without_neighbour) +
                             " reference points had no neighbour outside the Theiler window");
  return curve;
}

DivergenceCurve divergence_curve(const Series& series, const RosensteinOptions& options) {
  return follow_pairs(series, options, find_pairs(series, options));
}

StretchByDistance stretch_by_distance(const Series& series, const RosensteinOptions& options, const NeighbourPairs& pairs,
                                      std::size_t groups) {
  options.validate();
  validate_series(series);
  require_pairs_for("stretch_by_distance", options, pairs);
  const Series s = scaled_to_unit_deviation(series);
  const DelayEmbedding all = every_point(s, options);
  std::vector<std::pair<double, double>> logs;  // (ln d(0), ln d(1)) per pair
  logs.reserve(pairs.references.size());
  for (std::size_t k = 0; k < pairs.references.size(); ++k) {
    const std::uint32_t j = pairs.references[k], nb = pairs.nearest.neighbour[k];
    if (nb == NeighbourResult::none) continue;
    const double d0 = all.squared_distance(j, nb), d1 = all.squared_distance(j + 1, nb + 1);
    if (d0 > 0.0 && d1 > 0.0) logs.emplace_back(0.5 * std::log(d0), 0.5 * std::log(d1));  // never log 0
  }
  StretchByDistance out;
  out.pairs = logs.size();
  groups = std::min(groups, logs.size() / kMinStretchGroupPairs);
  if (groups < 2) return out;
  std::sort(logs.begin(), logs.end());
  for (std::size_t g = 0; g < groups; ++g) {
    const std::size_t first = g * logs.size() / groups, end = (g + 1) * logs.size() / groups;
    double sum0 = 0.0, sum1 = 0.0;
    for (std::size_t k = first; k < end; ++k) sum0 += logs[k].first, sum1 += logs[k].second;
    out.log_distance.push_back(sum0 / static_cast<double>(end - first));
    out.log_next.push_back(sum1 / static_cast<double>(end - first));
  }
  const std::size_t half = std::max<std::size_t>(2, groups / 2);
  std::vector<double> stretch(half);
  for (std::size_t g = 0; g < half; ++g) stretch[g] = out.log_next[g] - out.log_distance[g];
  if (out.log_distance[half - 1] > out.log_distance.front())  // groups of one distance have no slope
    out.closest_half_slope = fit_line(out.log_distance.data(), stretch.data(), half).slope;
  return out;
}

}  // namespace mlce
