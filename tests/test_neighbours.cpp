#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <utility>

#include "mlce/neighbours.hpp"
#include "reference_systems.hpp"

using namespace mlce;

namespace {
/// The kd-tree search, as one tree and split into two (NeighbourOptions::split_tree_points, which
/// long series use), with one point per leaf, nanoflann's 10, ours and leaves larger than the
/// embedding, against the brute force: the same distance and, equal distances going to the earlier
/// point, the same neighbour.
void expect_same_as_brute_force(const std::vector<double>& x, std::size_t dim, std::size_t delay, std::size_t theiler,
                                double repeat_resolution = 0.0,
                                double repeat_ceiling = std::numeric_limits<double>::infinity()) {
  const std::size_t M = DelayEmbedding::max_points(x.size(), dim, delay);
  const DelayEmbedding emb({std::span<const double>(x)}, dim, delay, M);
  std::vector<std::uint32_t> q;
  for (std::size_t i = 0; i < M; i += 7) q.push_back(static_cast<std::uint32_t>(i));
  NeighbourOptions o;
  o.theiler = theiler;
  o.repeat_resolution = repeat_resolution;
  o.repeat_ceiling = repeat_ceiling;
  const auto slow = find_nearest_neighbours_brute_force(emb, q, o);
  for (std::size_t split : {std::size_t{0}, std::size_t{1}}) {
    for (std::size_t leaf : {std::size_t{1}, std::size_t{10}, kDefaultLeafSize, std::size_t{100000}}) {
      o.split_tree_points = split;
      o.leaf_size = leaf;
      SCOPED_TRACE(testing::Message() << "split " << split << ", leaf size " << leaf);
      const auto fast = find_nearest_neighbours(emb, q, o);
      ASSERT_EQ(fast.neighbour.size(), slow.neighbour.size());
      for (std::size_t k = 0; k < q.size(); ++k) {
        EXPECT_EQ(fast.distance[k], slow.distance[k]) << "query " << q[k] << ", split " << split;  // exact search
        EXPECT_EQ(fast.neighbour[k], slow.neighbour[k]) << "query " << q[k] << ", split " << split;
        EXPECT_EQ(fast.repeated[k], slow.repeated[k]) << "query " << q[k] << ", split " << split;
        EXPECT_EQ(fast.repeat_of[k], slow.repeat_of[k]) << "query " << q[k] << ", split " << split;
        const std::size_t j = fast.neighbour[k];
        EXPECT_GT(j > q[k] ? j - q[k] : q[k] - j, theiler);  // eq. 20
      }
      EXPECT_EQ(fast.zero_distance_candidates, slow.zero_distance_candidates) << "split " << split;
      EXPECT_EQ(fast.near_repeat_candidates, slow.near_repeat_candidates) << "split " << split;
      EXPECT_EQ(fast.without_neighbour, slow.without_neighbour) << "split " << split;
    }
  }
}
}  // namespace

TEST(Neighbours, KdTreeMatchesBruteForceOnRandomData) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> x(3000);
  for (double& v : x) v = u(rng);
  for (std::size_t dim : {1u, 2u, 5u}) expect_same_as_brute_force(x, dim, 1, 0);
  expect_same_as_brute_force(x, 3, 2, 25);
}

TEST(Neighbours, KdTreeMatchesBruteForceOnEmbeddedData) {
  const auto x = reference::lorenz_x(3000);
  for (std::size_t w : {0u, 10u, 100u}) expect_same_as_brute_force(x, 3, 17, w);
  expect_same_as_brute_force(reference::henon_x(3000), 2, 1, 3);
  // Quantised to integers: many neighbours at equal distances (and some at zero, passed over).
  auto coarse = x;
  for (double& v : coarse) v = std::round(v);
  expect_same_as_brute_force(coarse, 3, 17, 10);
}

TEST(Neighbours, EmbeddingIsAViewWithIndexArithmetic) {
  std::vector<double> x(50);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<double>(i);
  const std::vector<double> y(x.rbegin(), x.rend());
  const DelayEmbedding emb({std::span<const double>(x), std::span<const double>(y)}, 3, 4, 42);
  EXPECT_EQ(emb.dimension(), 6u);
  EXPECT_EQ(DelayEmbedding::max_points(50, 3, 4), 42u);  // eq. 17
  double p[6];
  emb.point(5, p);
  EXPECT_DOUBLE_EQ(p[0], 5);
  EXPECT_DOUBLE_EQ(p[1], 9);
  EXPECT_DOUBLE_EQ(p[2], 13);
  EXPECT_DOUBLE_EQ(p[3], 44);
  EXPECT_DOUBLE_EQ(p[5], 36);
}

TEST(Neighbours, RepeatedPointsAreSkippedNotReturnedAtZeroDistance) {
  // A periodic, quantised signal: every point repeats exactly one period later.
  std::vector<double> x;
  for (int rep = 0; rep < 40; ++rep)
    for (int i = 0; i < 10; ++i) x.push_back(static_cast<double>((i * 7) % 10));
  const std::size_t M = DelayEmbedding::max_points(x.size(), 2, 1);
  const DelayEmbedding emb({std::span<const double>(x)}, 2, 1, M);
  std::vector<std::uint32_t> q(M);
  for (std::size_t i = 0; i < M; ++i) q[i] = static_cast<std::uint32_t>(i);
  NeighbourOptions o;
  o.theiler = 3;
  const auto r = find_nearest_neighbours(emb, q, o);
  EXPECT_GT(r.zero_distance_candidates, 0u);
  for (std::size_t k = 0; k < q.size(); ++k) EXPECT_GT(r.distance[k], 0.0);
  // Every point has its exact repeat a period (10 samples, beyond the window of 3) away: flagged.
  ASSERT_EQ(r.repeated.size(), q.size());
  for (std::size_t k = 0; k < q.size(); ++k) EXPECT_EQ(r.repeated[k], 1) << k;
  // A window of 390: the only candidates lie 391..398 samples away, none a whole number of periods.
  o.theiler = 390;
  const auto far = find_nearest_neighbours(emb, q, o), far_slow = find_nearest_neighbours_brute_force(emb, q, o);
  EXPECT_EQ(far.zero_distance_candidates, 0u);
  for (std::size_t k = 0; k < q.size(); ++k) EXPECT_EQ(far.repeated[k] + far_slow.repeated[k], 0) << k;
  EXPECT_NE(far.neighbour.front(), NeighbourResult::none);  // neighbours found, none a repeat
}

// A series that repeats exactly: every query passes over the repeats of its point (1000 of them for
// the period-3 orbit below), so the index regroups its points by equal delay vectors and searches
// one per group (NeighbourIndex::kCrowdedRepeats), with the same neighbours, distances, repeats and
// counts as the brute force over every point, within a Theiler window, under a repeat resolution,
// and up to a limit.
TEST(Neighbours, RepeatedPointsAreSearchedOncePerClassWithTheSameResult) {
  const auto orbit = reference::logistic(3000, 0.1234567, 3.83);  // settled on its period-3 cycle
  ASSERT_EQ(orbit[2000], orbit[2003]);
  std::vector<double> table(20), tabled, coarse = reference::lorenz_x(3000);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double& v : table) v = u(rng);
  for (std::size_t i = 0; i < 3000; ++i) tabled.push_back(table[i % 20]);  // period 20, exact
  for (double& v : coarse) v = std::round(2.0 * v) / 2.0;                    // quantised: some repeats
  for (std::size_t dim : {1u, 3u}) {
    expect_same_as_brute_force(orbit, dim, 1, 0);
    expect_same_as_brute_force(orbit, dim, 1, 5);
    expect_same_as_brute_force(tabled, dim, 3, 100);
    expect_same_as_brute_force(tabled, dim, 3, 7, 1e-10);
    expect_same_as_brute_force(coarse, dim, 17, 10);
  }
  expect_same_as_brute_force(tabled, 2, 1, 2990);  // a window that leaves most points no candidate
  // Up to a limit, as the adaptive horizon searches (the groups hold points beyond it too).
  const std::size_t M = DelayEmbedding::max_points(tabled.size(), 2, 3), L = M - 700;
  const DelayEmbedding all({std::span<const double>(tabled)}, 2, 3, M), first({std::span<const double>(tabled)}, 2, 3, L);
  std::vector<std::uint32_t> q;
  for (std::size_t i = 0; i < L; i += 3) q.push_back(static_cast<std::uint32_t>(i));
  NeighbourOptions o;
  o.theiler = 30;
  const NeighbourIndex index(all, o);
  for (int pass = 0; pass < 2; ++pass) {  // the first pass regroups, the second searches the groups
    const auto limited = index.nearest(q, L);
    const auto alone = find_nearest_neighbours_brute_force(first, q, o);
    EXPECT_EQ(limited.neighbour, alone.neighbour) << "pass " << pass;
    EXPECT_EQ(limited.distance, alone.distance) << "pass " << pass;
    EXPECT_EQ(limited.repeat_of, alone.repeat_of) << "pass " << pass;
    EXPECT_EQ(limited.zero_distance_candidates, alone.zero_distance_candidates) << "pass " << pass;
    EXPECT_GT(limited.zero_distance_candidates, q.size() * NeighbourIndex::kCrowdedRepeats);  // the case at hand
  }
}

TEST(Neighbours, PointsThatRepeatToRoundingAreRepeatsUnderARepeatResolution) {
  // sin(2 pi i / 100) repeats every 100 samples, not to the bit: sin of a large argument rounds
  // differently, so a point's repeats lie ~1e-13 away, every other candidate at least a sample of
  // phase (~0.06) away. With exact zeros only the repeats are the neighbours; with a repeat
  // resolution of 1e-10 they are passed over (counted, flagged) and the neighbours are a sample of
  // phase off, the same in the kd-tree as in the brute force.
  std::vector<double> x(3000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(2 * M_PI * static_cast<double>(i) / 100.0);
  const std::size_t M = DelayEmbedding::max_points(x.size(), 2, 19);
  const DelayEmbedding emb({std::span<const double>(x)}, 2, 19, M);
  std::vector<std::uint32_t> q;
  for (std::size_t i = 0; i < M; i += 5) q.push_back(static_cast<std::uint32_t>(i));
  NeighbourOptions o;
  o.theiler = 100;
  const auto exact_zeros = find_nearest_neighbours(emb, q, o);
  o.repeat_resolution = 1e-10;
  const auto resolved = find_nearest_neighbours(emb, q, o);
  std::size_t rounding_level = 0;
  for (std::size_t k = 0; k < q.size(); ++k) {
    rounding_level += exact_zeros.distance[k] < 1e-10;
    EXPECT_GT(resolved.distance[k], 0.04) << "query " << q[k];  // one sample of phase: 0.0628 x 0.79..1.21
    EXPECT_LT(resolved.distance[k], 0.08) << "query " << q[k];
    EXPECT_EQ(resolved.repeated[k], 1) << "query " << q[k];
  }
  EXPECT_GT(rounding_level, q.size() / 2);
  EXPECT_GT(resolved.near_repeat_candidates, 0u);  // counted apart from the exact zeros
  EXPECT_EQ(resolved.zero_distance_candidates, exact_zeros.zero_distance_candidates);
  EXPECT_EQ(exact_zeros.near_repeat_candidates, 0u);
  expect_same_as_brute_force(x, 2, 19, 100, 1e-10);
  expect_same_as_brute_force(reference::lorenz_x(3000), 3, 17, 10, 1e-10);  // no repeats: the plain search
  o.repeat_resolution = 1e-3;
  EXPECT_THROW(o.validate(), OptionError);
  o.repeat_resolution = 1e-10, o.repeat_ceiling = -1.0;
  EXPECT_THROW(o.validate(), OptionError);
}

TEST(Neighbours, RepeatsOfASignalRidingFarFromZeroAreJudgedAtTheCeilingNotAtItsLevel) {
  // Lorenz x on a level of 1e10: a point's size is ~1.7e10, and 1e-10 of it (1.7) is more than the
  // motion's own neighbour distances (~0.05 at N = 3000). Under a ceiling of 1e-3 the search finds
  // the neighbours it finds without the level (distances to the level's rounding, 1.9e-6), and the
  // kd-tree still agrees with the brute force.
  const auto x = reference::lorenz_x(3000);
  auto raised = x;
  for (double& v : raised) v += 1e10;
  const std::size_t M = DelayEmbedding::max_points(x.size(), 3, 17);
  const DelayEmbedding plain({std::span<const double>(x)}, 3, 17, M), high({std::span<const double>(raised)}, 3, 17, M);
  std::vector<std::uint32_t> q;
  for (std::size_t i = 0; i < M; i += 7) q.push_back(static_cast<std::uint32_t>(i));
  NeighbourOptions o;
  o.theiler = 10, o.repeat_resolution = 1e-10;
  const auto reference = find_nearest_neighbours(plain, q, o);
  EXPECT_EQ(reference.near_repeat_candidates, 0u);
  const auto uncapped = find_nearest_neighbours(high, q, o);
  EXPECT_GT(uncapped.near_repeat_candidates, q.size());  // more candidates lost to the level than references
  o.repeat_ceiling = 1e-3;
  const auto capped = find_nearest_neighbours(high, q, o);
  EXPECT_EQ(capped.near_repeat_candidates, 0u);
  std::size_t same = 0;
  for (std::size_t k = 0; k < q.size(); ++k) {
    EXPECT_NEAR(capped.distance[k], reference.distance[k], 1e-5) << "query " << q[k];
    same += capped.neighbour[k] == reference.neighbour[k];
  }
  EXPECT_GE(same, q.size() - q.size() / 100);  // ties within the rounding may swap a few
  expect_same_as_brute_force(raised, 3, 17, 10, 1e-10, 1e-3);
}

TEST(Neighbours, WindowLargerThanSeriesLeavesNoNeighbour) {
  std::vector<double> x{1, 2, 3, 4, 5, 6};
  const DelayEmbedding emb({std::span<const double>(x)}, 1, 1, 6);
  NeighbourOptions o;
  o.theiler = 10;
  const auto r = find_nearest_neighbours(emb, {0, 1, 2}, o);
  EXPECT_EQ(r.without_neighbour, 3u);
}

TEST(Neighbours, AnIndexSearchedUpToALimitIsAnIndexOverThosePointsOnly) {
  // The adaptive horizon searches one index up to a shrinking limit (rosenstein PairFinder).
  const auto x = reference::lorenz_x(4000);
  const std::size_t M = DelayEmbedding::max_points(x.size(), 3, 17), L = M - 700;
  const DelayEmbedding all({std::span<const double>(x)}, 3, 17, M), first({std::span<const double>(x)}, 3, 17, L);
  std::vector<std::uint32_t> q;
  for (std::size_t i = 0; i < L; i += 5) q.push_back(static_cast<std::uint32_t>(i));
  for (std::size_t split : {std::size_t{0}, std::size_t{1}}) {
    NeighbourOptions o;
    o.theiler = 50;
    o.split_tree_points = split;
    const auto limited = NeighbourIndex(all, o).nearest(q, L);
    const auto alone = find_nearest_neighbours_brute_force(first, q, o);
    EXPECT_EQ(limited.neighbour, alone.neighbour) << "split " << split;
    EXPECT_EQ(limited.distance, alone.distance) << "split " << split;
    for (const auto j : limited.neighbour) EXPECT_LT(j, L);
  }
}

// The distance test of recurrence.hpp asks how near a part of the series comes to another part:
// the kd-tree over the points [first, first + count) against the brute force over the same points.
TEST(Neighbours, DistancesToARangeMatchBruteForce) {
  const auto x = reference::lorenz_x(3000);
  const std::size_t dim = 3, delay = 17, M = DelayEmbedding::max_points(x.size(), dim, delay);
  const DelayEmbedding emb({std::span<const double>(x)}, dim, delay, M);
  std::vector<std::uint32_t> q;
  for (std::size_t i = 0; i < M; i += 13) q.push_back(static_cast<std::uint32_t>(i));
  for (const auto& [first, count] : {std::pair<std::size_t, std::size_t>{M / 2, M - M / 2}, {0, M}, {100, 1}}) {
    for (const std::size_t leaf : {std::size_t{1}, kDefaultLeafSize, std::size_t{100000}}) {
      const auto fast = RangeIndex(emb, first, count, leaf).distances(q);
      ASSERT_EQ(fast.size(), q.size());
      for (std::size_t k = 0; k < q.size(); ++k) {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t j = first; j < first + count; ++j) best = std::min(best, emb.squared_distance(q[k], j));
        EXPECT_EQ(fast[k], std::sqrt(best)) << "query " << q[k] << ", points from " << first << ", leaf size " << leaf;
        if (q[k] >= first && q[k] < first + count) {
          EXPECT_EQ(fast[k], 0.0);  // no Theiler window: itself
        }
      }
    }
  }
  EXPECT_THROW(RangeIndex(emb, M - 10, 11), OptionError);
  EXPECT_THROW(RangeIndex(emb, 0, 0), OptionError);
}

TEST(Neighbours, BallSearchMatchesBruteForceWithTheilerWindowLimitAndRepeats) {
  // Kantz's neighbourhoods (NeighbourIndex::within) against every pair checked by hand: Lorenz x
  // embedded in m = 3, with a periodic stretch copied in so that some points repeat exactly; one
  // tree and two halves, our leaf size and one point per leaf, a limit below the embedding's size.
  std::vector<double> x = reference::lorenz_x(3000, 0.01);
  std::copy(x.begin() + 100, x.begin() + 300, x.begin() + 2000);  // exact repeats of 200 samples
  const std::size_t dim = 3, delay = 12, theiler = 40;
  const std::size_t M = DelayEmbedding::max_points(x.size(), dim, delay), limit = M - 50;
  const DelayEmbedding emb({std::span<const double>(x)}, dim, delay, M);
  NeighbourOptions o;
  o.theiler = theiler;
  std::size_t compared = 0, repeats_seen = 0;
  for (std::size_t variant = 0; variant < 4; ++variant) {
    const std::size_t split = variant % 2;
    o.split_tree_points = split;
    o.leaf_size = variant < 2 ? kDefaultLeafSize : 1;
    const NeighbourIndex index(emb, o);
    std::vector<std::uint32_t> fast;
    for (std::size_t q = 0; q < limit; q += 37) {
      for (const double radius : {0.5, 2.0, 6.0}) {
        const std::size_t repeats = index.within(static_cast<std::uint32_t>(q), radius, limit, fast);
        std::vector<std::uint32_t> slow;
        std::size_t zeros = 0;
        for (std::size_t j = 0; j < limit; ++j) {
          if ((j > q ? j - q : q - j) <= theiler) continue;
          const double d2 = emb.squared_distance(q, j);
          if (d2 == 0.0) ++zeros;
          else if (d2 < radius * radius) slow.push_back(static_cast<std::uint32_t>(j));
        }
        EXPECT_EQ(fast, slow) << "query " << q << ", radius " << radius << ", split " << split << ", leaf size "
                              << o.leaf_size;
        EXPECT_EQ(repeats, zeros) << "query " << q << ", radius " << radius;
        compared += slow.size();
        repeats_seen += zeros;
      }
    }
  }
  EXPECT_GT(compared, 10000u);  // the balls are not empty
  EXPECT_GT(repeats_seen, 0u);  // and the copied stretch was met
}
