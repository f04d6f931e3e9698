#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "mlce/fnn.hpp"
#include "reference_systems.hpp"

using namespace mlce;

TEST(Fnn, LogisticMapIsOneDimensional) {
  const auto r = estimate_dimension_fnn(make_series_with_step({reference::logistic(10000)}, 1.0), 1, {});
  EXPECT_EQ(r.dim, 1u);
  EXPECT_TRUE(r.reached_threshold);
}

TEST(Fnn, HenonNeedsTwoDimensions) {
  FnnOptions o;
  o.theiler = 3;
  const auto r = estimate_dimension_fnn(make_series_with_step({reference::henon_x(10000)}, 1.0), 1, o);
  EXPECT_EQ(r.dim, 2u);
  EXPECT_GT(r.fraction[0], 0.5);  // m = 1 folds the attractor
}

TEST(Fnn, LorenzNeedsThreeDimensions) {
  FnnOptions o;
  o.theiler = 100;
  const auto r = estimate_dimension_fnn(make_series_with_step({reference::lorenz_x(20000)}, 0.01), 17, o);
  EXPECT_EQ(r.dim, 3u);
}

TEST(Fnn, ExactlyPeriodicSineIsTwoDimensional) {
  // sin(2 pi i / 100): an ellipse in two delay coordinates, repeating every 100 samples to ~1e-13
  // (the rounding of sin's argument). Kennel's ratio of two such roundings is noise: with exact
  // zeros only as repeats it marked a quarter of the neighbours false at m = 2 (m = 4 chosen).
  std::vector<double> x(5000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(2 * M_PI * static_cast<double>(i) / 100.0);
  FnnOptions o;
  o.theiler = 100, o.max_dim = 4;
  const auto r = estimate_dimension_fnn(make_series_with_step({x}, 1.0), 19, o);
  EXPECT_EQ(r.dim, 2u);
  EXPECT_EQ(r.fraction[1], 0.0);
  EXPECT_GT(r.zero_distance_pairs, 0u);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.back().find("repeating their point"), std::string::npos) << r.warnings.back();
  o.repeat_resolution = 0.0;  // the mechanism: exact zeros only
  EXPECT_GT(estimate_dimension_fnn(make_series_with_step({x}, 1.0), 19, o).fraction[1], 0.1);
  o.repeat_resolution = 1e-3;  // not a rounding level
  EXPECT_THROW(o.validate(), OptionError);
}

TEST(Fnn, WhiteNoiseNeverReachesTheThresholdAndSaysSo) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g;
  std::vector<double> x(5000);
  for (double& v : x) v = g(rng);
  FnnOptions o;
  o.max_dim = 6;
  const auto r = estimate_dimension_fnn(make_series_with_step({x}, 1.0), 1, o);
  EXPECT_FALSE(r.reached_threshold);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.front().find("noise"), std::string::npos);
}

TEST(Fnn, NoisyHenonStillFindsALowDimension) {
  // 5 % measurement noise: the plain first-below-threshold rule may never trigger (the escape
  // criterion keeps flagging noise-separated neighbours); the fallback takes the lowest fraction,
  // which for this low-dimensional map must stay small.
  std::mt19937_64 rng(9);
  std::normal_distribution<double> g(0.0, 0.05 * 0.7);
  auto x = reference::henon_x(10000);
  for (double& v : x) v += g(rng);
  FnnOptions o;
  o.theiler = 3;
  o.max_dim = 6;
  const auto r = estimate_dimension_fnn(make_series_with_step({x}, 1.0), 1, o);
  EXPECT_GE(r.dim, 2u);
  EXPECT_LE(r.dim, 4u);
}

TEST(Fnn, CappedTreesUseTheSeriesFirstPointsAndGiveTheirFractions) {
  // With max_points, each m's kd-tree holds the first max_points points: the fractions must equal
  // those of an uncapped run on exactly those samples (criterion 1 only, which does not depend on
  // the series' scaling, while criterion 2's R_A would see the shorter series' deviation).
  const auto x = reference::henon_x(20000);
  FnnOptions capped;
  capped.max_points = 5000;
  capped.max_dim = 4;
  capped.atol = 1e9;
  const auto r = estimate_dimension_fnn(make_series_with_step({x}, 1.0), 1, capped);
  ASSERT_EQ(r.fraction.size(), 4u);
  EXPECT_TRUE(r.capped);
  for (std::size_t m = 1; m <= 4; ++m) {
    EXPECT_EQ(r.points[m - 1], 5000u);
    FnnOptions all = capped;
    all.max_points = 0;
    all.max_dim = m;
    const std::vector<double> head(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(5000 + m));
    const auto t = estimate_dimension_fnn(make_series_with_step({head}, 1.0), 1, all);
    ASSERT_EQ(t.points.at(m - 1), 5000u);
    EXPECT_FALSE(t.capped);
    EXPECT_EQ(t.fraction.at(m - 1), r.fraction[m - 1]) << "m = " << m;
    EXPECT_EQ(t.queries.at(m - 1), r.queries[m - 1]) << "m = " << m;
  }
  // Series no longer than the cap are untouched: the default cap is 10^6 points.
  const auto u = estimate_dimension_fnn(make_series_with_step({x}, 1.0), 1, {});
  EXPECT_FALSE(u.capped);
  EXPECT_EQ(u.points.front(), x.size() - 1);
}
