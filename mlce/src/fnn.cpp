#include "mlce/fnn.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>

#include "mlce/embedding.hpp"
#include "mlce/neighbours.hpp"
#include "mlce/numerics.hpp"

namespace mlce {

void DimensionSearchOptions::validate_search(const std::string& method) const {
  validate_repeat_resolution(repeat_resolution, (method + ".repeat_resolution").c_str());
  if (max_points != 0 && max_points < 2)
    throw OptionError(method + ".max_points = " + std::to_string(max_points) + ": expected 0 (all) or >= 2");
}

void FnnOptions::validate() const {
  if (max_dim < 1 || max_dim > 64) throw OptionError("fnn.max_dim = " + std::to_string(max_dim) + ": expected 1..64");
  if (!(rtol > 0.0)) throw OptionError("fnn.rtol: expected > 0");
  if (!(atol > 0.0)) throw OptionError("fnn.atol: expected > 0");
  if (!(threshold > 0.0 && threshold < 1.0)) throw OptionError("fnn.threshold: expected 0 < value < 1");
  validate_search("fnn");
}

void CaoOptions::validate() const {
  if (max_dim < 2 || max_dim > 64) throw OptionError("cao.max_dim = " + std::to_string(max_dim) + ": expected 2..64");
  if (!(saturation > 0.0 && saturation < 1.0)) throw OptionError("cao.saturation: expected 0 < value < 1");
  if (!(stochastic_tolerance > 0.0 && stochastic_tolerance < 1.0))
    throw OptionError("cao.stochastic_tolerance: expected 0 < value < 1");
  validate_search("cao");
}

std::vector<std::uint32_t> strided_indices(std::size_t count, std::size_t max_count) {
  std::vector<std::uint32_t> idx;
  if (max_count == 0 || count <= max_count) {
    idx.resize(count);
    for (std::size_t i = 0; i < count; ++i) idx[i] = static_cast<std::uint32_t>(i);
    return idx;
  }
  idx.reserve(max_count);
  for (std::size_t k = 0; k < max_count; ++k)
    idx.push_back(static_cast<std::uint32_t>((k * count) / max_count));  // deterministic, evenly spread
  return idx;
}

namespace {

/// What Kennel's and Cao's tests are both computed from: at dimension m, the nearest neighbour
/// (outside the Theiler window, repeats passed over) of each query point of the delay embedding,
/// its distance R_m and the distance the (m+1)-th delay coordinate adds to the pair.
struct DimensionPairs {
  std::vector<double> distance;  ///< R_m(i) > 0, Euclidean, of each pair that has a neighbour
  std::vector<double> added;     ///< |x(i + mJ) - x(j + mJ)| over the channels (Euclidean)
  std::size_t points = 0;        ///< points in the kd-tree
  bool capped = false;           ///< the tree held only the series' first max_points points
  std::size_t repeats = 0;       ///< candidates passed over as repeats of their point
};

/// The pairs at dimension m of a series scaled to unit deviation; nullopt when the series is too
/// short for the (m+1)-th coordinate and the Theiler window.
std::optional<DimensionPairs> dimension_pairs(const Series& unit, std::size_t m, std::size_t delay, const DimensionSearchOptions& search) {
  const std::size_t n = unit.size(), span = m * delay;  // the (m+1)-th coordinate must exist
  if (n <= span || n - span < search.theiler + 2) return std::nullopt;
  std::vector<std::span<const double>> channels;
  for (const auto& c : unit.channels) channels.emplace_back(c);
  NeighbourOptions nopt;
  nopt.theiler = search.theiler;
  nopt.repeat_resolution = search.repeat_resolution;
  nopt.repeat_ceiling = kRepeatCeilingInDeviations;  // the channels are in standard deviations
  DimensionPairs p;
  p.points = search.max_points ? std::min(n - span, search.max_points) : n - span;
  p.capped = p.points < n - span;
  const DelayEmbedding emb(channels, m, delay, p.points);
  const auto queries = strided_indices(p.points, search.max_queries);
  const NeighbourResult nn = find_nearest_neighbours(emb, queries, nopt);
  p.repeats = nn.zero_distance_candidates + nn.near_repeat_candidates;
  for (std::size_t k = 0; k < queries.size(); ++k) {
    if (nn.neighbour[k] == NeighbourResult::none || !(nn.distance[k] > 0.0)) continue;
    const std::size_t i = queries[k], j = nn.neighbour[k];
    double added2 = 0.0;
    for (const auto& c : unit.channels) {
      const double e = c[i + span] - c[j + span];
      added2 += e * e;
    }
    p.distance.push_back(nn.distance[k]);
    p.added.push_back(std::sqrt(added2));
  }
  return p;
}

std::string too_short_for(std::size_t m, std::size_t delay) {
  return "the series is too short for m = " + std::to_string(m) + " with delay " + std::to_string(delay);
}

std::string repeats_warning(const char* method, std::size_t repeats, double resolution) {
  return fmt::format("{}: {} candidates repeating their point (at zero distance or within {:g} of its size and {:g} "
                     "standard deviations: a periodic or quantised signal) were passed over",
                     method, repeats, resolution, kRepeatCeilingInDeviations);
}

}  // namespace

FnnResult estimate_dimension_fnn(const Series& series, std::size_t delay, const FnnOptions& options) {
  options.validate();
  validate_series(series);
  if (delay == 0) throw OptionError("fnn: delay must be >= 1");
  const Series s = scaled_to_unit_deviation(series);
  // Kennel's R_A: the attractor size, the standard deviation of the data (1 per channel after scaling).
  const double ra = std::sqrt(static_cast<double>(s.channel_count()));
  FnnResult r;
  for (std::size_t m = 1; m <= options.max_dim; ++m) {
    const auto pairs = dimension_pairs(s, m, delay, options);
    if (!pairs) {
      r.warnings.push_back("FNN stopped at m = " + std::to_string(m - 1) + ": " + too_short_for(m, delay));
      break;
    }
    std::size_t false_count = 0;
    for (std::size_t k = 0; k < pairs->distance.size(); ++k) {
      const double rm = pairs->distance[k], extra = pairs->added[k];
      const bool false_by_ratio = extra > options.rtol * rm;                         // Kennel criterion 1
      const bool false_by_size = std::sqrt(rm * rm + extra * extra) > options.atol * ra;  // Kennel criterion 2
      false_count += (false_by_ratio || false_by_size);
    }
    const std::size_t tested = pairs->distance.size();
    r.zero_distance_pairs += pairs->repeats;
    r.queries.push_back(tested);
    r.points.push_back(pairs->points);
    r.capped = r.capped || pairs->capped;
    r.fraction.push_back(tested ? static_cast<double>(false_count) / static_cast<double>(tested) : 1.0);
    if (options.progress)
      options.progress(fmt::format("false nearest neighbours, m = {} of {}", m, options.max_dim),
                       static_cast<double>(m) / static_cast<double>(options.max_dim));
    if (options.stop_at_choice && r.fraction.back() < options.threshold) break;
  }
  if (r.fraction.empty())
    throw InputError("series too short for FNN: " + std::to_string(s.size()) + " samples, but delay " + std::to_string(delay) +
                     " and Theiler window " + std::to_string(options.theiler) + " need at least " +
                     std::to_string(delay + options.theiler + 2));
  const auto first_ok = std::find_if(r.fraction.begin(), r.fraction.end(),
                                     [&](double f) { return f < options.threshold; });
  if (first_ok != r.fraction.end()) {
    r.dim = static_cast<std::size_t>(first_ok - r.fraction.begin()) + 1;
  } else {
    r.reached_threshold = false;
    r.dim = static_cast<std::size_t>(std::min_element(r.fraction.begin(), r.fraction.end()) - r.fraction.begin()) + 1;
    std::ostringstream os;
    os << "FNN fraction never fell below " << options.threshold * 100 << " % up to m = " << r.fraction.size()
       << " (lowest " << r.fraction[r.dim - 1] * 100 << " % at m = " << r.dim
       << "): noise, a motion of higher dimension, or a delay long enough to fold the reconstruction "
          "(compare a smaller --delay) keeps neighbours false; m taken at the lowest fraction";
    r.warnings.push_back(os.str());
  }
  if (r.zero_distance_pairs > 0) r.warnings.push_back(repeats_warning("FNN", r.zero_distance_pairs, options.repeat_resolution));
  return r;
}

CaoResult estimate_dimension_cao(const Series& series, std::size_t delay, const CaoOptions& options) {
  options.validate();
  validate_series(series);
  if (delay == 0) throw OptionError("cao: delay must be >= 1");
  const Series s = scaled_to_unit_deviation(series);
  CaoResult r;
  std::vector<double> e_star;  // E*(d), Cao's eq. 4
  for (std::size_t d = 1; d <= options.max_dim; ++d) {
    const auto pairs = dimension_pairs(s, d, delay, options);
    if (!pairs || pairs->distance.empty()) {
      r.warnings.push_back("Cao's E stopped at d = " + std::to_string(d - 1) + ": " + too_short_for(d, delay));
      break;
    }
    // Each term divided by the count before it is summed: the mean of ratios up to ~1e308 (pairs
    // far closer than their next coordinates differ) stays finite.
    const auto count = static_cast<double>(pairs->distance.size());
    CompensatedSum ratio, added;
    for (std::size_t k = 0; k < pairs->distance.size(); ++k) {
      const double rd = pairs->distance[k], extra = pairs->added[k];
      ratio.add(std::hypot(1.0, extra / rd) / count);  // a(i, d), eq. 1: |y(d+1) pair| / |y(d) pair| >= 1
      added.add(extra / count);
    }
    r.e.push_back(ratio.value());  // eq. 2
    e_star.push_back(added.value());
    if (!std::isfinite(r.e.back()))
      throw InputError(fmt::format("Cao's method: at d = {} a neighbour pair's distance is too small against its next "
                                   "coordinate's difference for their ratio (a(i, d) overflows)", d));
    r.queries.push_back(pairs->distance.size());
    r.zero_distance_pairs += pairs->repeats;
    if (options.progress)
      options.progress(fmt::format("Cao's E, d = {} of {}", d, options.max_dim),
                       static_cast<double>(d) / static_cast<double>(options.max_dim));
  }
  if (r.e.size() < 2)
    throw InputError("series too short for Cao's method: " + std::to_string(s.size()) + " samples, but delay " +
                     std::to_string(delay) + " and Theiler window " + std::to_string(options.theiler) +
                     " need at least " + std::to_string(2 * delay + options.theiler + 2) + " for E1(1)");
  for (std::size_t d = 1; d < r.e.size(); ++d) {
    r.e1.push_back(r.e[d] / r.e[d - 1]);  // eq. 3
    // E*(d) is 0 only when every pair's next coordinate agrees exactly: the ratio is then 1 (no
    // information either way), never 0/0.
    r.e2.push_back(e_star[d - 1] > 0.0 ? e_star[d] / e_star[d - 1] : 1.0);  // eq. 5
  }
  const auto off_one = [](double v) { return std::abs(1.0 - v); };
  const auto first_saturated =
      std::find_if(r.e1.begin(), r.e1.end(), [&](double v) { return off_one(v) <= options.saturation; });
  if (first_saturated != r.e1.end()) {
    r.dim = static_cast<std::size_t>(first_saturated - r.e1.begin()) + 1;
  } else {
    r.saturated = false;
    r.dim = static_cast<std::size_t>(
                std::min_element(r.e1.begin(), r.e1.end(), [&](double a, double b) { return off_one(a) < off_one(b); }) -
                r.e1.begin()) + 1;
    r.warnings.push_back(fmt::format("Cao's E1 never came within {:g} of 1 up to d = {} (closest {:.3f} at d = {}): "
                                     "noise or a motion of higher dimension; d taken where E1 is closest to 1",
                                     options.saturation, r.e1.size(), r.e1[r.dim - 1], r.dim));
  }
  r.looks_stochastic =
      std::all_of(r.e2.begin(), r.e2.end(), [&](double v) { return off_one(v) <= options.stochastic_tolerance; });
  if (r.looks_stochastic)
    r.warnings.push_back(fmt::format("Cao's E2 stays within {:g} of 1 at every d up to {}: the next value does not "
                                     "depend on the past more in any dimension, as for noise; the series looks stochastic",
                                     options.stochastic_tolerance, r.e2.size()));
  if (r.zero_distance_pairs > 0) r.warnings.push_back(repeats_warning("Cao", r.zero_distance_pairs, options.repeat_resolution));
  return r;
}

}  // namespace mlce
