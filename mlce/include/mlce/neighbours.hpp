#pragma once
// Exact nearest neighbour of each reference point with temporal separation |j - jhat| > w
// (paper 001 eq. 20, the Theiler window), via a kd-tree whose result set applies the exclusion
// inside the search.
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "mlce/embedding.hpp"
#include "mlce/series.hpp"

namespace mlce {

/// The kd-trees' leaf size: points per leaf, scanned one by one. nanoflann's default is 10; 40
/// builds a shallower tree (peak memory at N = 10^7 469 -> 399 MB) and searches as fast or faster:
/// 10 -> 40 took nearest neighbours at N = 10^6 from 134 to 113 ms (m = 3) and 236 to 200 ms
/// (m = 8), Kantz's balls from 243 to 201 ms (`bench_estimator --benchmark_filter=LeafSize`).
/// The search is exact at any leaf size: the neighbours, and the estimate, do not change.
inline constexpr std::size_t kDefaultLeafSize = 40;

struct NeighbourOptions {
  /// Theiler window w: candidates with |j - jhat| <= w are skipped.
  std::size_t theiler = 0;
  /// kd-tree leaf size (kDefaultLeafSize).
  std::size_t leaf_size = kDefaultLeafSize;
  /// 0 = exact search. eps > 0 accepts neighbours within (1+eps) of the true distance (faster;
  /// for the speed/accuracy study only).
  double eps = 0.0;
  /// Embeddings with at least this many points are searched through two kd-trees over their two
  /// halves, built in parallel (nanoflann 1.4 builds a tree on one thread: at 10^6-10^7 points the
  /// builds were most of the estimate's time; 2^18: estimate at 10^6 1.09 -> 0.71 s, at 10^7
  /// 6.11 -> 4.00 s, bench/scaling.sh). 0 = always one tree. The split is fixed, and equal
  /// distances go to the earlier point, so the result depends on neither the split nor the
  /// thread count.
  std::size_t split_tree_points = std::size_t{1} << 18;
  /// Candidates within repeat_resolution x |x_i| of the query point x_i (|.| the Euclidean norm of
  /// its delay vector) count as repeats of it, as exact zeros do: passed over and counted in
  /// zero_distance_candidates. Two states that agree to that many digits of their own size differ
  /// by the data's rounding, not by the motion: an exactly periodic signal written to 17 digits
  /// repeats to ~1e-13, and a ratio of two roundings (FNN's Kennel test) is noise. 0 = exact
  /// zeros only (the divergence curve's neighbours: a repeat at rounding level just reads neutral).
  double repeat_resolution = 0.0;
  /// ...but never a candidate farther than repeat_ceiling x sqrt(D) (D coordinates, in the
  /// embedding's units). A point's size counts the level the signal rides on: on 1e10 + Lorenz x
  /// 1e-10 of it is ~1 in the signal's units, more than the motion's own neighbour distances, and
  /// every neighbour was passed over as a "repeat" (lambda 0.39 for 0.95; at 1e11 a search over
  /// every point). Infinity: no ceiling.
  double repeat_ceiling = std::numeric_limits<double>::infinity();
  void validate() const;
};

/// The repeat ceiling (NeighbourOptions::repeat_ceiling) of the estimators, whose embeddings are
/// in units of each channel's standard deviation: 1e-8 of it. Far below the motion's neighbour
/// distances at any length a series has (Henon's attractor, dimension 1.26, ~3e-6 at N = 10^7),
/// and above the rounding of a signal riding on up to ~1e8 of its deviations (17 digits).
inline constexpr double kRepeatCeilingInDeviations = 1e-8;

/// The check of a repeat resolution (NeighbourOptions::repeat_resolution) wherever an estimator's
/// options carry one: 0 <= value < 1e-3, else OptionError naming `option`.
void validate_repeat_resolution(double value, const char* option);

struct NeighbourResult {
  static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> neighbour;  ///< per query; `none` when every candidate was excluded
  std::vector<double> distance;          ///< Euclidean, not squared; +inf for `none`
  /// Per query: 1 when a candidate at zero distance (or within NeighbourOptions::repeat_resolution)
  /// was passed over (the point repeats outside the Theiler window: a periodic or quantised
  /// signal), else 0.
  std::vector<std::uint8_t> repeated;
  /// Per query: the earliest candidate passed over as its repeat, `none` if there was none
  /// (does the series repeat whole stretches, periodic, or only single points, quantised?).
  std::vector<std::uint32_t> repeat_of;
  /// Candidates at exactly zero distance (repeated points) that were passed over: they would give
  /// log(0). The nearest neighbour at a positive distance is returned instead.
  std::size_t zero_distance_candidates = 0;
  /// Candidates at a positive distance within NeighbourOptions::repeat_resolution of the point's
  /// size, passed over as repeats too (a signal periodic to the rounding, not quantised).
  std::size_t near_repeat_candidates = 0;
  std::size_t without_neighbour = 0;
};

/// The kd-tree(s) over an embedding's points (which must outlive it), built once and searched
/// many times: the adaptive horizon's doublings search the same points up to a shrinking limit.
class NeighbourIndex {
 public:
  NeighbourIndex(const DelayEmbedding& embedding, const NeighbourOptions& options);
  ~NeighbourIndex();
  NeighbourIndex(const NeighbourIndex&) = delete;
  NeighbourIndex& operator=(const NeighbourIndex&) = delete;
  /// Nearest neighbour of each query among the points [0, limit) (the same result as an index
  /// over those points only). Runs the queries on all cores (OpenMP); the result does not depend
  /// on the thread count. Not to be called from two threads at once: a query that passes over
  /// more than kCrowdedRepeats repeats of its point (a periodic or quantised series) makes the
  /// index regroup its points by equal delay vectors, once, and search one point per group.
  NeighbourResult nearest(const std::vector<std::uint32_t>& queries, std::size_t limit) const;

  /// Every point among [0, limit) closer than `radius` (Euclidean, strictly) to point `query` and
  /// more than the Theiler window from it, at a positive distance beyond the repeat resolution (a
  /// repeat of the query would enter a neighbourhood's mean at zero), ascending by index, into `out`
  /// (cleared first). Returns the repeats passed over. Kantz's neighbourhoods (kantz.hpp). Searches
  /// the index's own trees, never the regrouped ones, so it may run from several threads at once.
  std::size_t within(std::uint32_t query, double radius, std::size_t limit, std::vector<std::uint32_t>& out) const;

  static constexpr std::size_t kCrowdedRepeats = 64;

  struct Trees;  ///< kd-trees and the points they hold (neighbours.cpp)

 private:
  const DelayEmbedding* embedding_;
  NeighbourOptions options_;
  std::unique_ptr<Trees> trees_;
  mutable std::unique_ptr<Trees> grouped_;  ///< over one point per class of repeats, once needed
  mutable bool grouping_tried_ = false;     ///< grouped_ was built, or found no two equal points
};

/// Nearest neighbour among the embedding's points of each point in `queries` (indices into the
/// embedding). Runs the queries on all cores (OpenMP); the result does not depend on the thread count.
NeighbourResult find_nearest_neighbours(const DelayEmbedding& embedding, const std::vector<std::uint32_t>& queries,
                                        const NeighbourOptions& options);

/// The kd-tree over an embedding's points [first, first + count) (the embedding must outlive it),
/// built once and asked many times: the distance from query points (indices into the embedding)
/// to their nearest point of that range, exact, no Theiler window (a query inside the range finds
/// itself, at 0). Does a part of the series come near another part again? (recurrence.hpp's
/// distance test).
class RangeIndex {
 public:
  RangeIndex(const DelayEmbedding& embedding, std::size_t first, std::size_t count, std::size_t leaf_size = kDefaultLeafSize);
  ~RangeIndex();
  RangeIndex(const RangeIndex&) = delete;
  RangeIndex& operator=(const RangeIndex&) = delete;
  /// Runs the queries on all cores; the result does not depend on the thread count.
  std::vector<double> distances(const std::vector<std::uint32_t>& queries) const;

 private:
  struct Tree;
  const DelayEmbedding* embedding_;
  std::unique_ptr<Tree> tree_;
};

/// `max_count` indices evenly spread over [0, count) (all of them when max_count is 0 or >= count).
std::vector<std::uint32_t> strided_indices(std::size_t count, std::size_t max_count);

/// O(M^2) reference implementation with the same contract (tests and tiny series).
NeighbourResult find_nearest_neighbours_brute_force(const DelayEmbedding& embedding,
                                                    const std::vector<std::uint32_t>& queries,
                                                    const NeighbourOptions& options);

}  // namespace mlce
