#include "mlce/space_time.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>

#include "mlce/embedding.hpp"
#include "mlce/mean_period.hpp"
#include "mlce/neighbours.hpp"
#include "mlce/numerics.hpp"
#include "mlce/transient.hpp"

namespace mlce {

namespace {

constexpr std::size_t kMinPairs = 100;    // fewest pairs at the largest separation: a 1 % contour needs 1 below it
constexpr std::size_t kTargetRows = 200;  // separations plotted with the automatic step
constexpr double kMinBelowLowest = 10;    // pairs below the lowest contour for a usable quantile

std::string shortest(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

}  // namespace

void SpaceTimeOptions::validate() const {
  if (dim < 1) throw OptionError("space_time.dim = 0: expected >= 1");
  if (delay < 1) throw OptionError("space_time.delay = 0: expected >= 1");
  if (max_separation == 1) throw OptionError("space_time.max_separation = 1: expected 0 (automatic) or >= 2");
  if (fractions.empty()) throw OptionError("space_time.fractions: expected at least one contour level");
  for (const double f : fractions)
    if (!(f > 0.0 && f < 1.0))
      throw OptionError("space_time.fractions: " + shortest(f) + " is not a fraction in (0, 1)");
  if (!(decorrelation_level > 0.0 && decorrelation_level < 1.0))
    throw OptionError("space_time.decorrelation_level: expected a value in (0, 1)");
}

SpaceTimeResult space_time_separation(const Series& series, const SpaceTimeOptions& options) {
  options.validate();
  validate_series(series);  // finite, non-constant channels
  const Series s = scaled_to_unit_deviation(series);
  SpaceTimeResult r;
  r.dim = options.dim, r.delay = options.delay;
  r.fractions = options.fractions;
  r.decorrelation_level = options.decorrelation_level;
  std::sort(r.fractions.begin(), r.fractions.end());
  r.fractions.erase(std::unique(r.fractions.begin(), r.fractions.end()), r.fractions.end());
  r.mean_period = options.mean_period > 0 ? options.mean_period : estimate_mean_period(series, {}).mean_period;

  const std::size_t n = series.size();
  const std::size_t M = DelayEmbedding::max_points(n, options.dim, options.delay);  // eq. 17
  std::size_t max_sep = options.max_separation;
  if (max_sep == 0) max_sep = std::min(4 * r.mean_period, M / 2);
  if (M < kMinPairs + 1 || max_sep + kMinPairs > M || max_sep < 2)
    throw InputError("series too short: " + std::to_string(n) + " samples, but m = " + std::to_string(options.dim) +
                     ", delay = " + std::to_string(options.delay) + " and separations up to " +
                     std::to_string(max_sep) + " need at least " +
                     std::to_string((options.dim - 1) * options.delay + std::max<std::size_t>(max_sep, 2) + kMinPairs) +
                     " ((m-1)*delay + largest separation + " + std::to_string(kMinPairs) + " pairs; largest separation >= 2)");
  const std::size_t step = options.step > 0 ? options.step : (max_sep + kTargetRows - 1) / kTargetRows;
  for (std::size_t d = step; d <= max_sep; d += step) r.separation.push_back(d);
  if (r.separation.size() < 2)
    throw OptionError("space_time.step = " + std::to_string(step) + ": fewer than 2 separations up to " +
                      std::to_string(max_sep));

  std::vector<std::span<const double>> channels;
  for (const auto& c : s.channels) channels.emplace_back(c);
  const DelayEmbedding points(channels, options.dim, options.delay, M);

  const std::size_t S = r.separation.size(), K = r.fractions.size();
  r.contour.assign(K, std::vector<double>(S, 0.0));
  r.pairs.assign(S, 0);
#pragma omp parallel
  {
    std::vector<double> d2;
#pragma omp for schedule(dynamic, 4)
    for (std::size_t k = 0; k < S; ++k) {
      const std::size_t D = r.separation[k];
      const auto first = strided_indices(M - D, options.max_pairs);  // points i with i + D < M
      d2.resize(first.size());
      for (std::size_t p = 0; p < first.size(); ++p) d2[p] = points.squared_distance(first[p], first[p] + D);
      r.pairs[k] = d2.size();
      // Ascending fractions: each order statistic is selected in the part above the previous one.
      auto from = d2.begin();
      for (std::size_t f = 0; f < K; ++f) {
        const auto rank = static_cast<std::ptrdiff_t>(std::floor(r.fractions[f] * static_cast<double>(d2.size() - 1)));
        const auto at = d2.begin() + rank;
        std::nth_element(from, at, d2.end());
        r.contour[f][k] = std::sqrt(*at);
        from = at;
      }
    }
  }

  const std::size_t fewest = *std::min_element(r.pairs.begin(), r.pairs.end());
  const double below = r.fractions.front() * static_cast<double>(fewest);
  if (below < kMinBelowLowest)
    r.warnings.push_back("the lowest contour (" + shortest(r.fractions.front()) + ") rests on " +
                         std::to_string(static_cast<std::size_t>(below)) + " pair(s) of " + std::to_string(fewest) +
                         ": too few for a quantile; use more pairs per separation");

  // Decorrelation of the lowest contour (Provenzale et al.: the time after which the contours stop
  // rising, aside from oscillations).
  const auto& low = r.contour.front();
  r.plateau = upper_median(std::vector<double>(low.begin() + static_cast<std::ptrdiff_t>(S / 2), low.end()));
  const auto reached = std::find_if(low.begin(), low.end(),
                                    [&](double c) { return c >= options.decorrelation_level * r.plateau; });
  r.decorrelation = r.separation[static_cast<std::size_t>(reached - low.begin())];  // the median is reached
  // The plot describes a stationary motion (an attractor); a decay or growth makes points far
  // apart in time differ by their amplitudes, and its contours follow the envelope.
  r.amplitude_ratio = amplitude_ratio(series);
  r.stationary = persists(r.amplitude_ratio);
  if (!r.stationary)
    r.warnings.push_back((std::isnan(r.amplitude_ratio)
                              ? std::string("the series rests in its first third and moves later")
                              : "the motion's RMS changes by a factor " + shortest(r.amplitude_ratio) +
                                    " from the first third of the series to the last") +
                         ": the plot assumes a stationary motion, and its contours here follow the amplitude, not the "
                         "correlation in time");
  else if (r.decorrelation > r.mean_period)
    r.warnings.push_back("pairs of points stay closer than unrelated ones up to a separation of " +
                         std::to_string(r.decorrelation) + " samples, beyond the mean period (" +
                         std::to_string(r.mean_period) +
                         " samples, the automatic Theiler window): neighbours that close in time may share a passage; "
                         "give a Theiler window of at least " + std::to_string(r.decorrelation));
  return r;
}

}  // namespace mlce
