#include "mlce/neighbours.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace mlce {
namespace {

/// Points [first, first + count) of an embedding as a nanoflann dataset: a long series is split
/// into parts whose kd-trees are built side by side (nanoflann 1.4 builds one tree on one thread).
class EmbeddingRange {
 public:
  EmbeddingRange(const DelayEmbedding& embedding, std::size_t first, std::size_t count)
      : embedding_(&embedding), first_(first), count_(count) {}
  std::size_t first() const { return first_; }
  std::size_t kdtree_get_point_count() const { return count_; }
  double kdtree_get_pt(std::size_t i, std::size_t d) const { return embedding_->coordinate(first_ + i, d); }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const { return false; }

 private:
  const DelayEmbedding* embedding_;
  std::size_t first_, count_;
};

using Metric = nanoflann::L2_Simple_Adaptor<double, EmbeddingRange, double, std::uint32_t>;
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<Metric, EmbeddingRange, -1, std::uint32_t>;

std::size_t separation(std::size_t a, std::size_t b) { return a > b ? a - b : b - a; }

/// nanoflann result set for one nearest neighbour outside the Theiler window (eq. 20). The
/// exclusion and the skipping of zero-distance duplicates happen inside the tree search, so the
/// branch-and-bound pruning stays exact: worstDist() is the best admissible distance so far.
class TheilerNearestResultSet {
 public:
  using DistanceType = double;
  using IndexType = std::uint32_t;

  /// Candidates at `limit` and beyond are not points of the search (an index built for a shorter
  /// horizon than the one searched: NeighbourIndex::nearest).
  /// Candidates at a squared distance of at most `repeat_squared` (0: exact zeros only) are
  /// repeats of the query (NeighbourOptions::repeat_resolution).
  TheilerNearestResultSet(std::size_t query, std::size_t theiler, std::size_t limit, double repeat_squared)
      : query_(query), theiler_(theiler), limit_(limit), repeat_squared_(repeat_squared) {}

  /// The tree searched next holds the points from `first` on (its indices are local to it). The
  /// set carries its best distance from one tree's search to the next, which prunes it.
  void set_offset(std::size_t first) { offset_ = first; }

  void init() {}
  std::size_t size() const { return index_ == NeighbourResult::none ? 0 : 1; }
  bool full() const { return true; }
  bool addPoint(double squared_distance, std::uint32_t local_index) {
    const std::size_t index = offset_ + local_index;
    if (index >= limit_) return true;                        // beyond the points searched
    if (separation(index, query_) <= theiler_) return true;  // temporally correlated: excluded
    if (squared_distance <= repeat_squared_) {  // repeated point: log(0) downstream, take the next one
      ++(squared_distance == 0.0 ? zero_hits_ : near_hits_);
      repeat_ = std::min(repeat_, static_cast<std::uint32_t>(index));
      return true;
    }
    // Equal distances go to the earlier point, whatever order the trees visit them in.
    if (squared_distance < best_ || (squared_distance == best_ && index < index_)) {
      best_ = squared_distance;
      worst_ = std::nextafter(best_, std::numeric_limits<double>::infinity());
      index_ = static_cast<std::uint32_t>(index);
    }
    return true;
  }
  /// Just above the best distance: nanoflann offers a leaf's point only when it is strictly
  /// closer than this, and a point at the best distance must be offered for the tie rule.
  /// (Kept, not computed per call: the search asks for it at every node it visits.)
  double worstDist() const { return worst_; }

  std::uint32_t index() const { return index_; }
  double squared_distance() const { return best_; }
  std::size_t zero_hits() const { return zero_hits_; }
  std::size_t near_hits() const { return near_hits_; }
  std::uint32_t repeat() const { return repeat_; }

 private:
  std::size_t query_, theiler_, limit_, offset_ = 0;
  double repeat_squared_;
  double best_ = std::numeric_limits<double>::infinity(), worst_ = std::numeric_limits<double>::infinity();
  std::uint32_t index_ = NeighbourResult::none;
  std::size_t zero_hits_ = 0, near_hits_ = 0;
  std::uint32_t repeat_ = NeighbourResult::none;
};

NeighbourResult make_result(std::size_t queries) {
  NeighbourResult r;
  r.neighbour.assign(queries, NeighbourResult::none);
  r.distance.assign(queries, std::numeric_limits<double>::infinity());
  r.repeated.assign(queries, 0);
  r.repeat_of.assign(queries, NeighbourResult::none);
  return r;
}

void finish(NeighbourResult& r) {
  for (auto idx : r.neighbour) r.without_neighbour += idx == NeighbourResult::none;
}

/// Squared distance at or below which a candidate repeats the point `q`
/// (NeighbourOptions::repeat_resolution, capped by repeat_ceiling).
double repeat_squared(const double* q, std::size_t D, const NeighbourOptions& options) {
  if (options.repeat_resolution == 0.0) return 0.0;
  double norm2 = 0.0;
  for (std::size_t d = 0; d < D; ++d) norm2 += q[d] * q[d];
  const double ceiling2 = options.repeat_ceiling * options.repeat_ceiling * static_cast<double>(D);
  return std::min(options.repeat_resolution * options.repeat_resolution * norm2, ceiling2);
}

}  // namespace

void NeighbourOptions::validate() const {
  if (leaf_size == 0) throw OptionError("neighbours.leaf_size: expected >= 1");
  if (!(eps >= 0.0)) throw OptionError("neighbours.eps: expected >= 0");
  validate_repeat_resolution(repeat_resolution, "neighbours.repeat_resolution");
  if (!(repeat_ceiling >= 0.0)) throw OptionError("neighbours.repeat_ceiling: expected >= 0 (infinity: no ceiling)");
}

void validate_repeat_resolution(double value, const char* option) {
  if (!(value >= 0.0 && value < 1e-3))
    throw OptionError(std::string(option) + ": expected 0 <= value < 1e-3 (a relative rounding level)");
}

struct NeighbourIndex::Trees {
  std::vector<EmbeddingRange> ranges;
  std::vector<std::unique_ptr<KdTree>> trees;
};

NeighbourIndex::NeighbourIndex(const DelayEmbedding& embedding, const NeighbourOptions& options)
    : embedding_(&embedding), options_(options), trees_(std::make_unique<Trees>()) {
  options.validate();
  if (embedding.size() < 2) return;
  const std::size_t n = embedding.size(), parts = options.split_tree_points > 0 && n >= options.split_tree_points ? 2 : 1;
  auto& ranges = trees_->ranges;
  auto& trees = trees_->trees;
  for (std::size_t p = 0; p < parts; ++p) ranges.emplace_back(embedding, p * n / parts, (p + 1) * n / parts - p * n / parts);
  trees.resize(parts);
  std::vector<std::exception_ptr> failures(parts);  // an exception must not leave an OpenMP region
  const auto build = [&](std::size_t p) {
    try {
      trees[p] = std::make_unique<KdTree>(embedding.dimension(), ranges[p],
                                          nanoflann::KDTreeSingleIndexAdaptorParams(options.leaf_size));
    } catch (...) {
      failures[p] = std::current_exception();
    }
  };
#pragma omp parallel for schedule(static, 1) if (parts > 1)
  for (std::ptrdiff_t p = 0; p < static_cast<std::ptrdiff_t>(parts); ++p) build(static_cast<std::size_t>(p));
  for (const auto& failure : failures)
    if (failure) std::rethrow_exception(failure);
}

NeighbourIndex::~NeighbourIndex() = default;

NeighbourResult NeighbourIndex::nearest(const std::vector<std::uint32_t>& queries, std::size_t limit) const {
  NeighbourResult r = make_result(queries.size());
  limit = std::min(limit, embedding_->size());
  if (limit < 2 || trees_->trees.empty()) {
    finish(r);
    return r;
  }
  const auto& ranges = trees_->ranges;
  const auto& trees = trees_->trees;
  const nanoflann::SearchParams params(32, static_cast<float>(options_.eps));
  const std::size_t D = embedding_->dimension();
  std::size_t zeros = 0, near = 0;
  const auto nq = static_cast<std::ptrdiff_t>(queries.size());
#pragma omp parallel reduction(+ : zeros, near)
  {
    std::vector<double> q(D);
#pragma omp for schedule(dynamic, 512)
    for (std::ptrdiff_t k = 0; k < nq; ++k) {
      const std::size_t i = queries[static_cast<std::size_t>(k)];
      embedding_->point(i, q.data());
      TheilerNearestResultSet set(i, options_.theiler, limit, repeat_squared(q.data(), D, options_));
      for (std::size_t p = 0; p < trees.size(); ++p) {
        if (ranges[p].first() >= limit) break;
        set.set_offset(ranges[p].first());
        trees[p]->findNeighbors(set, q.data(), params);
      }
      zeros += set.zero_hits();
      near += set.near_hits();
      r.repeated[static_cast<std::size_t>(k)] = set.zero_hits() + set.near_hits() > 0;
      r.repeat_of[static_cast<std::size_t>(k)] = set.repeat();
      if (set.index() != NeighbourResult::none) {
        r.neighbour[static_cast<std::size_t>(k)] = set.index();
        r.distance[static_cast<std::size_t>(k)] = std::sqrt(set.squared_distance());
      }
    }
  }
  r.zero_distance_candidates = zeros;
  r.near_repeat_candidates = near;
  finish(r);
  return r;
}

NeighbourResult find_nearest_neighbours(const DelayEmbedding& embedding, const std::vector<std::uint32_t>& queries,
                                        const NeighbourOptions& options) {
  return NeighbourIndex(embedding, options).nearest(queries, embedding.size());
}

struct RangeIndex::Tree {
  Tree(const DelayEmbedding& embedding, std::size_t first, std::size_t count, std::size_t leaf_size)
      : range(embedding, first, count),
        tree(embedding.dimension(), range, nanoflann::KDTreeSingleIndexAdaptorParams(leaf_size)) {}
  EmbeddingRange range;  // before the tree, which keeps a reference to it
  KdTree tree;
};

RangeIndex::RangeIndex(const DelayEmbedding& embedding, std::size_t first, std::size_t count, std::size_t leaf_size)
    : embedding_(&embedding) {
  if (first > embedding.size() || count > embedding.size() - first)
    throw OptionError("RangeIndex: points [" + std::to_string(first) + ", " + std::to_string(first + count) +
                      ") outside the embedding's " + std::to_string(embedding.size()));
  if (count == 0) throw OptionError("RangeIndex: no points to measure against");
  if (leaf_size == 0) throw OptionError("RangeIndex: leaf size must be positive");
  tree_ = std::make_unique<Tree>(embedding, first, count, leaf_size);
}

RangeIndex::~RangeIndex() = default;

std::vector<double> RangeIndex::distances(const std::vector<std::uint32_t>& queries) const {
  std::vector<double> out(queries.size());
  const std::size_t D = embedding_->dimension();
  const auto nq = static_cast<std::ptrdiff_t>(queries.size());
#pragma omp parallel
  {
    std::vector<double> q(D);
#pragma omp for schedule(dynamic, 512)
    for (std::ptrdiff_t k = 0; k < nq; ++k) {
      embedding_->point(queries[static_cast<std::size_t>(k)], q.data());
      std::uint32_t index = 0;
      double squared = 0.0;
      nanoflann::KNNResultSet<double, std::uint32_t> set(1);
      set.init(&index, &squared);
      tree_->tree.findNeighbors(set, q.data(), nanoflann::SearchParams(32));
      out[static_cast<std::size_t>(k)] = std::sqrt(squared);
    }
  }
  return out;
}

NeighbourResult find_nearest_neighbours_brute_force(const DelayEmbedding& embedding,
                                                    const std::vector<std::uint32_t>& queries,
                                                    const NeighbourOptions& options) {
  NeighbourResult r = make_result(queries.size());
  std::vector<double> q(embedding.dimension());
  for (std::size_t k = 0; k < queries.size(); ++k) {
    const std::size_t i = queries[k];
    embedding.point(i, q.data());
    const double repeat = repeat_squared(q.data(), q.size(), options);
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < embedding.size(); ++j) {
      if (separation(i, j) <= options.theiler) continue;
      const double d2 = embedding.squared_distance(i, j);
      if (d2 <= repeat) {
        ++(d2 == 0.0 ? r.zero_distance_candidates : r.near_repeat_candidates);
        r.repeat_of[k] = std::min(r.repeat_of[k], static_cast<std::uint32_t>(j));
        r.repeated[k] = 1;
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
