#include "mlce/neighbours.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace mlce {
namespace {

/// Points [first, first + count) of an embedding as a nanoflann dataset: a long series is split
/// into parts whose kd-trees are built side by side (nanoflann 1.4 builds one tree on one thread).
/// With `map`, the dataset's point k is the embedding's point map[k] (one point per class of
/// repeats, RepeatClasses), and first/count count entries of the map.
class EmbeddingRange {
 public:
  EmbeddingRange(const DelayEmbedding& embedding, std::size_t first, std::size_t count,
                 const std::uint32_t* map = nullptr)
      : embedding_(&embedding), first_(first), count_(count), map_(map) {}
  std::size_t first() const { return first_; }
  /// The embedding's index of the range's first point.
  std::size_t first_point() const { return map_ ? map_[first_] : first_; }
  std::size_t kdtree_get_point_count() const { return count_; }
  double kdtree_get_pt(std::size_t i, std::size_t d) const {
    return embedding_->coordinate(map_ ? map_[first_ + i] : first_ + i, d);
  }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const { return false; }

 private:
  const DelayEmbedding* embedding_;
  std::size_t first_, count_;
  const std::uint32_t* map_;
};

using Metric = nanoflann::L2_Simple_Adaptor<double, EmbeddingRange, double, std::uint32_t>;
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<Metric, EmbeddingRange, -1, std::uint32_t>;

std::size_t separation(std::size_t a, std::size_t b) { return a > b ? a - b : b - a; }

/// The embedding's points grouped by equal delay vectors (every coordinate ==). An exactly periodic
/// or quantised series repeats each point many times, and a kd-tree search passes over every
/// repeat of its query (they are closer than any neighbour): N / P repeats per query for a
/// period of P samples, O(N^2 / P) in all (the period-3 orbit of the logistic map at r = 3.83,
/// 3 x 10^4 samples: 35 s). Searched over one point per class, each class is offered once and
/// its members are counted and chosen by index arithmetic (the same result: test
/// `Neighbours.RepeatedPointsAreSearchedOncePerClassWithTheSameResult`).
struct RepeatClasses {
  std::vector<std::uint32_t> first;    ///< per class, its earliest point; ascending
  std::vector<std::uint32_t> offsets;  ///< class c's points: points[offsets[c] .. offsets[c + 1])
  std::vector<std::uint32_t> points;   ///< ascending within a class
};

RepeatClasses group_repeats(const DelayEmbedding& e) {
  const std::size_t n = e.size(), D = e.dimension();
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
  const auto less = [&](std::uint32_t a, std::uint32_t b) {
    for (std::size_t d = 0; d < D; ++d) {
      const double x = e.coordinate(a, d), y = e.coordinate(b, d);
      if (x != y) return x < y;
    }
    return a < b;  // equal points in time order
  };
  std::sort(order.begin(), order.end(), less);
  const auto same = [&](std::uint32_t a, std::uint32_t b) {
    for (std::size_t d = 0; d < D; ++d)
      if (e.coordinate(a, d) != e.coordinate(b, d)) return false;
    return true;
  };
  std::vector<std::pair<std::size_t, std::size_t>> runs;  // [begin, end) of order, one per class
  for (std::size_t k = 0; k < n;) {
    std::size_t end = k + 1;
    while (end < n && same(order[k], order[end])) ++end;
    runs.emplace_back(k, end);
    k = end;
  }
  std::sort(runs.begin(), runs.end(), [&](const auto& a, const auto& b) { return order[a.first] < order[b.first]; });
  RepeatClasses c;
  c.offsets.push_back(0);
  for (const auto& [begin, end] : runs) {
    c.first.push_back(order[begin]);
    c.points.insert(c.points.end(), order.begin() + static_cast<std::ptrdiff_t>(begin),
                    order.begin() + static_cast<std::ptrdiff_t>(end));
    c.offsets.push_back(static_cast<std::uint32_t>(c.points.size()));
  }
  return c;
}

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
  /// The trees hold one point per class of repeats: a local index names a class.
  void set_classes(const RepeatClasses* classes) { classes_ = classes; }

  void init() {}
  std::size_t size() const { return index_ == NeighbourResult::none ? 0 : 1; }
  bool full() const { return true; }
  bool addPoint(double squared_distance, std::uint32_t local_index) {
    if (classes_ == nullptr) {
      const std::size_t index = offset_ + local_index;
      if (index >= limit_) return true;                        // beyond the points searched
      if (separation(index, query_) <= theiler_) return true;  // temporally correlated: excluded
      add(squared_distance, index, 1);
      return true;
    }
    // Every point of the class is at this distance: the earliest admissible one stands for them
    // all, and a repeat counts each admissible one, as the search over every point would.
    const std::size_t c = offset_ + local_index;
    const std::uint32_t* begin = classes_->points.data() + classes_->offsets[c];
    const std::uint32_t* end = std::lower_bound(begin, classes_->points.data() + classes_->offsets[c + 1], limit_);
    const std::uint32_t* window_begin = std::lower_bound(begin, end, query_ > theiler_ ? query_ - theiler_ : 0);
    const std::uint32_t* window_end = std::upper_bound(window_begin, end, query_ + theiler_);
    const auto admissible = static_cast<std::size_t>((window_begin - begin) + (end - window_end));
    if (admissible == 0) return true;
    add(squared_distance, window_begin != begin ? *begin : *window_end, admissible);
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
  /// An admissible candidate (the earliest of `count` at this distance).
  void add(double squared_distance, std::size_t index, std::size_t count) {
    if (squared_distance <= repeat_squared_) {  // repeated point: log(0) downstream, take the next one
      (squared_distance == 0.0 ? zero_hits_ : near_hits_) += count;
      repeat_ = std::min(repeat_, static_cast<std::uint32_t>(index));
      return;
    }
    // Equal distances go to the earlier point, whatever order the trees visit them in.
    if (squared_distance < best_ || (squared_distance == best_ && index < index_)) {
      best_ = squared_distance;
      worst_ = std::nextafter(best_, std::numeric_limits<double>::infinity());
      index_ = static_cast<std::uint32_t>(index);
    }
  }

  const RepeatClasses* classes_ = nullptr;
  std::size_t query_, theiler_, limit_, offset_ = 0;
  double repeat_squared_;
  double best_ = std::numeric_limits<double>::infinity(), worst_ = std::numeric_limits<double>::infinity();
  std::uint32_t index_ = NeighbourResult::none;
  std::size_t zero_hits_ = 0, near_hits_ = 0;
  std::uint32_t repeat_ = NeighbourResult::none;
};

/// nanoflann result set for every point within a radius outside the Theiler window (Kantz's
/// neighbourhoods): the exclusion and the repeats are applied inside the search, as for the nearest
/// neighbour. worstDist() is the squared radius, so the search prunes at the ball.
class TheilerBallResultSet {
 public:
  using DistanceType = double;
  using IndexType = std::uint32_t;

  TheilerBallResultSet(std::size_t query, std::size_t theiler, std::size_t limit, double radius_squared,
                       double repeat_squared, std::vector<std::uint32_t>& out)
      : query_(query), theiler_(theiler), limit_(limit), radius_squared_(radius_squared),
        repeat_squared_(repeat_squared), out_(&out) {}
  void set_offset(std::size_t first) { offset_ = first; }
  void init() {}
  std::size_t size() const { return out_->size(); }
  bool full() const { return true; }
  bool addPoint(double squared_distance, std::uint32_t local_index) {
    const std::size_t index = offset_ + local_index;
    if (index >= limit_ || separation(index, query_) <= theiler_ || !(squared_distance < radius_squared_)) return true;
    if (squared_distance <= repeat_squared_) {
      ++repeats_;  // a repeat of the query (zero or within the resolution): not a neighbour
      return true;
    }
    out_->push_back(static_cast<std::uint32_t>(index));
    return true;
  }
  double worstDist() const { return radius_squared_; }
  std::size_t repeats() const { return repeats_; }

 private:
  std::size_t query_, theiler_, limit_, offset_ = 0;
  double radius_squared_, repeat_squared_;
  std::vector<std::uint32_t>* out_;
  std::size_t repeats_ = 0;
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
  RepeatClasses classes;  ///< empty: the trees hold every point
};

namespace {

/// The kd-trees over `count` points (the embedding's first `count`, or the points `map` names),
/// split in two halves built side by side from options.split_tree_points on.
void build_trees(NeighbourIndex::Trees& t, const DelayEmbedding& embedding, std::size_t count,
                 const std::uint32_t* map, const NeighbourOptions& options) {
  const std::size_t parts = options.split_tree_points > 0 && count >= options.split_tree_points ? 2 : 1;
  for (std::size_t p = 0; p < parts; ++p)
    t.ranges.emplace_back(embedding, p * count / parts, (p + 1) * count / parts - p * count / parts, map);
  t.trees.resize(parts);
  std::vector<std::exception_ptr> failures(parts);  // an exception must not leave an OpenMP region
  const auto build = [&](std::size_t p) {
    try {
      t.trees[p] = std::make_unique<KdTree>(embedding.dimension(), t.ranges[p],
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

/// The queries' nearest neighbours among points [0, limit) through the trees `t`. With `stop_when_crowded`,
/// gives up (nullopt) once a query has passed over more than NeighbourIndex::kCrowdedRepeats repeats
/// of its point: the trees should be regrouped.
std::optional<NeighbourResult> search(const NeighbourIndex::Trees& t, const DelayEmbedding& embedding,
                                      const NeighbourOptions& options, const std::vector<std::uint32_t>& queries,
                                      std::size_t limit, bool stop_when_crowded) {
  NeighbourResult r = make_result(queries.size());
  const nanoflann::SearchParams params(32, static_cast<float>(options.eps));
  const std::size_t D = embedding.dimension();
  const RepeatClasses* classes = t.classes.first.empty() ? nullptr : &t.classes;
  std::size_t zeros = 0, near = 0;
  std::atomic<bool> crowded{false};
  const auto nq = static_cast<std::ptrdiff_t>(queries.size());
#pragma omp parallel reduction(+ : zeros, near)
  {
    std::vector<double> q(D);
#pragma omp for schedule(dynamic, 512)
    for (std::ptrdiff_t k = 0; k < nq; ++k) {
      if (stop_when_crowded && crowded.load(std::memory_order_relaxed)) continue;
      const std::size_t i = queries[static_cast<std::size_t>(k)];
      embedding.point(i, q.data());
      TheilerNearestResultSet set(i, options.theiler, limit, repeat_squared(q.data(), D, options));
      set.set_classes(classes);
      for (std::size_t p = 0; p < t.trees.size(); ++p) {
        if (t.ranges[p].first_point() >= limit) break;
        set.set_offset(t.ranges[p].first());
        t.trees[p]->findNeighbors(set, q.data(), params);
      }
      if (stop_when_crowded && set.zero_hits() + set.near_hits() > NeighbourIndex::kCrowdedRepeats)
        crowded.store(true, std::memory_order_relaxed);
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
  if (crowded.load()) return std::nullopt;
  r.zero_distance_candidates = zeros;
  r.near_repeat_candidates = near;
  finish(r);
  return r;
}

}  // namespace

NeighbourIndex::NeighbourIndex(const DelayEmbedding& embedding, const NeighbourOptions& options)
    : embedding_(&embedding), options_(options), trees_(std::make_unique<Trees>()) {
  options.validate();
  if (embedding.size() < 2) return;
  build_trees(*trees_, embedding, embedding.size(), nullptr, options);
}

NeighbourIndex::~NeighbourIndex() = default;

NeighbourResult NeighbourIndex::nearest(const std::vector<std::uint32_t>& queries, std::size_t limit) const {
  limit = std::min(limit, embedding_->size());
  if (limit < 2 || trees_->trees.empty()) {
    NeighbourResult r = make_result(queries.size());
    finish(r);
    return r;
  }
  if (!grouped_) {
    if (auto r = search(*trees_, *embedding_, options_, queries, limit, !grouping_tried_)) return *std::move(r);
    grouping_tried_ = true;
    RepeatClasses classes = group_repeats(*embedding_);
    if (classes.first.size() == embedding_->size())  // repeats within the resolution, none exact: no help
      return *search(*trees_, *embedding_, options_, queries, limit, false);
    grouped_ = std::make_unique<Trees>();
    grouped_->classes = std::move(classes);
    build_trees(*grouped_, *embedding_, grouped_->classes.first.size(), grouped_->classes.first.data(), options_);
  }
  return *search(*grouped_, *embedding_, options_, queries, limit, false);
}

std::size_t NeighbourIndex::within(std::uint32_t query, double radius, std::size_t limit,
                                   std::vector<std::uint32_t>& out) const {
  out.clear();
  limit = std::min(limit, embedding_->size());
  if (trees_->trees.empty() || !(radius > 0.0)) return 0;
  const std::size_t D = embedding_->dimension();
  std::vector<double> q(D);
  embedding_->point(query, q.data());
  TheilerBallResultSet set(query, options_.theiler, limit, radius * radius, repeat_squared(q.data(), D, options_), out);
  const nanoflann::SearchParams params(32, static_cast<float>(options_.eps));
  for (std::size_t p = 0; p < trees_->trees.size(); ++p) {
    if (trees_->ranges[p].first_point() >= limit) break;
    set.set_offset(trees_->ranges[p].first());
    trees_->trees[p]->findNeighbors(set, q.data(), params);
  }
  std::sort(out.begin(), out.end());  // the trees' visiting order is theirs, not time's
  return set.repeats();
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
