#include "mlce/fnn.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

#include "mlce/embedding.hpp"
#include "mlce/neighbours.hpp"

namespace mlce {

void FnnOptions::validate() const {
  if (max_dim < 1 || max_dim > 64) throw OptionError("fnn.max_dim = " + std::to_string(max_dim) + ": expected 1..64");
  if (!(rtol > 0.0)) throw OptionError("fnn.rtol: expected > 0");
  if (!(atol > 0.0)) throw OptionError("fnn.atol: expected > 0");
  if (!(threshold > 0.0 && threshold < 1.0)) throw OptionError("fnn.threshold: expected 0 < value < 1");
  validate_repeat_resolution(repeat_resolution, "fnn.repeat_resolution");
  if (max_points != 0 && max_points < 2) throw OptionError("fnn.max_points = " + std::to_string(max_points) + ": expected 0 (all) or >= 2");
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

FnnResult estimate_dimension_fnn(const Series& series, std::size_t delay, const FnnOptions& options) {
  options.validate();
  validate_series(series);
  if (delay == 0) throw OptionError("fnn: delay must be >= 1");
  const Series s = scaled_to_unit_deviation(series);
  const std::size_t n = s.size();
  std::vector<std::span<const double>> channels;
  for (const auto& c : s.channels) channels.emplace_back(c);
  // Kennel's R_A: the attractor size, the standard deviation of the data (1 per channel after scaling).
  const double ra = std::sqrt(static_cast<double>(s.channel_count()));
  FnnResult r;
  NeighbourOptions nopt;
  nopt.theiler = options.theiler;
  nopt.repeat_resolution = options.repeat_resolution;
  nopt.repeat_ceiling = kRepeatCeilingInDeviations;  // the channels are in standard deviations
  for (std::size_t m = 1; m <= options.max_dim; ++m) {
    const std::size_t span = m * delay;  // the (m+1)-th coordinate must exist
    if (n <= span || n - span < options.theiler + 2) {
      r.warnings.push_back("FNN stopped at m = " + std::to_string(m - 1) + ": the series is too short for m = " +
                           std::to_string(m) + " with delay " + std::to_string(delay));
      break;
    }
    const std::size_t points = options.max_points ? std::min(n - span, options.max_points) : n - span;
    const DelayEmbedding emb(channels, m, delay, points);
    const auto queries = strided_indices(points, options.max_queries);
    const NeighbourResult nn = find_nearest_neighbours(emb, queries, nopt);
    std::size_t tested = 0, false_count = 0;
    for (std::size_t k = 0; k < queries.size(); ++k) {
      if (nn.neighbour[k] == NeighbourResult::none) continue;
      const std::size_t i = queries[k], j = nn.neighbour[k];
      double extra2 = 0.0;
      for (const auto& c : s.channels) {
        const double e = c[i + span] - c[j + span];
        extra2 += e * e;
      }
      const double rm = nn.distance[k];
      ++tested;
      const bool false_by_ratio = std::sqrt(extra2) > options.rtol * rm;                     // Kennel criterion 1
      const bool false_by_size = std::sqrt(rm * rm + extra2) > options.atol * ra;           // Kennel criterion 2
      false_count += (false_by_ratio || false_by_size);
    }
    r.zero_distance_pairs += nn.zero_distance_candidates + nn.near_repeat_candidates;
    r.queries.push_back(tested);
    r.points.push_back(points);
    r.capped = r.capped || points < n - span;
    r.fraction.push_back(tested ? static_cast<double>(false_count) / static_cast<double>(tested) : 1.0);
    if (options.stop_at_choice && r.fraction.back() < options.threshold) break;
  }
  if (r.fraction.empty())
    throw InputError("series too short for FNN: " + std::to_string(n) + " samples, but delay " + std::to_string(delay) +
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
  if (r.zero_distance_pairs > 0)
    r.warnings.push_back(fmt::format("FNN: {} candidates repeating their point (at zero distance or within {:g} of "
                                     "its size and {:g} standard deviations: a periodic or quantised signal) were "
                                     "passed over",
                                     r.zero_distance_pairs, options.repeat_resolution, kRepeatCeilingInDeviations));
  return r;
}

}  // namespace mlce
