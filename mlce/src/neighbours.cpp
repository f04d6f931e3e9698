#include "mlce/neighbours.hpp"

#include <nanoflann.hpp>

#include <cmath>
#include <limits>
#include <string>

namespace mlce {
namespace {

using Metric = nanoflann::L2_Simple_Adaptor<double, DelayEmbedding, double, std::uint32_t>;
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<Metric, DelayEmbedding, -1, std::uint32_t>;

std::size_t separation(std::size_t a, std::size_t b) { return a > b ? a - b : b - a; }

/// nanoflann result set for one nearest neighbour outside the Theiler window (eq. 20). The
/// exclusion and the skipping of zero-distance duplicates happen inside the tree search, so the
/// branch-and-bound pruning stays exact: worstDist() is the best admissible distance so far.
class TheilerNearestResultSet {
 public:
  using DistanceType = double;
  using IndexType = std::uint32_t;

  TheilerNearestResultSet(std::size_t query, std::size_t theiler) : query_(query), theiler_(theiler) {}

  void init() {}
  std::size_t size() const { return index_ == NeighbourResult::none ? 0 : 1; }
  bool full() const { return true; }
  bool addPoint(double squared_distance, std::uint32_t index) {
    if (separation(index, query_) <= theiler_) return true;  // temporally correlated: excluded
    if (squared_distance == 0.0) {  // repeated point: log(0) downstream, take the next one
      ++zero_hits_;
      return true;
    }
    if (squared_distance < best_) {
      best_ = squared_distance;
      index_ = index;
    }
    return true;
  }
  double worstDist() const { return best_; }

  std::uint32_t index() const { return index_; }
  double squared_distance() const { return best_; }
  std::size_t zero_hits() const { return zero_hits_; }

 private:
  std::size_t query_, theiler_;
  double best_ = std::numeric_limits<double>::infinity();
  std::uint32_t index_ = NeighbourResult::none;
  std::size_t zero_hits_ = 0;
};

NeighbourResult make_result(std::size_t queries) {
  NeighbourResult r;
  r.neighbour.assign(queries, NeighbourResult::none);
  r.distance.assign(queries, std::numeric_limits<double>::infinity());
  return r;
}

void finish(NeighbourResult& r) {
  for (auto idx : r.neighbour) r.without_neighbour += idx == NeighbourResult::none;
}

}  // namespace

void NeighbourOptions::validate() const {
  if (leaf_size == 0) throw OptionError("neighbours.leaf_size: expected >= 1");
  if (!(eps >= 0.0)) throw OptionError("neighbours.eps: expected >= 0");
}

NeighbourResult find_nearest_neighbours(const DelayEmbedding& embedding, const std::vector<std::uint32_t>& queries,
                                        const NeighbourOptions& options) {
  options.validate();
  NeighbourResult r = make_result(queries.size());
  if (embedding.size() < 2) {
    finish(r);
    return r;
  }
  const KdTree tree(embedding.dimension(), embedding, nanoflann::KDTreeSingleIndexAdaptorParams(options.leaf_size));
  const nanoflann::SearchParams params(32, static_cast<float>(options.eps));
  const std::size_t D = embedding.dimension();
  std::size_t zeros = 0;
  const auto nq = static_cast<std::ptrdiff_t>(queries.size());
#pragma omp parallel reduction(+ : zeros)
  {
    std::vector<double> q(D);
#pragma omp for schedule(dynamic, 512)
    for (std::ptrdiff_t k = 0; k < nq; ++k) {
      const std::size_t i = queries[static_cast<std::size_t>(k)];
      embedding.point(i, q.data());
      TheilerNearestResultSet set(i, options.theiler);
      tree.findNeighbors(set, q.data(), params);
      zeros += set.zero_hits();
      if (set.index() != NeighbourResult::none) {
        r.neighbour[static_cast<std::size_t>(k)] = set.index();
        r.distance[static_cast<std::size_t>(k)] = std::sqrt(set.squared_distance());
      }
    }
  }
  r.zero_distance_candidates = zeros;
  finish(r);
  return r;
}

NeighbourResult find_nearest_neighbours_brute_force(const DelayEmbedding& embedding,
                                                    const std::vector<std::uint32_t>& queries,
                                                    const NeighbourOptions& options) {
  NeighbourResult r = make_result(queries.size());
  for (std::size_t k = 0; k < queries.size(); ++k) {
    const std::size_t i = queries[k];
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < embedding.size(); ++j) {
      if (separation(i, j) <= options.theiler) continue;
      const double d2 = embedding.squared_distance(i, j);
      if (d2 == 0.0) {
        ++r.zero_distance_candidates;
        continue;
      }
      if (d2 < best) {
        best = d2;
        r.neighbour[k] = static_cast<std::uint32_t>(j);
      }
    }
    if (r.neighbour[k] != NeighbourResult::none) r.distance[k] = std::sqrt(best);
  }
  finish(r);
  return r;
}

}  // namespace mlce
