#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <string_view>
#include <utility>
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

namespace {

std::vector<double> gaussian_white(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  std::vector<double> x(n);
  for (double& v : x) v = g(rng);
  return x;
}

CaoResult cao_of(const std::vector<double>& x, double dt, std::size_t delay, std::size_t theiler) {
  CaoOptions o;
  o.theiler = theiler;
  return estimate_dimension_cao(make_series_with_step({x}, dt), delay, o);
}

/// The d whose E1 rises most from the d before it: where the attractor unfolds.
std::size_t largest_rise(const CaoResult& r) {
  std::size_t best = 2;
  for (std::size_t d = 2; d <= r.e1.size(); ++d)
    if (r.e1[d - 1] - r.e1[d - 2] > r.e1[best - 1] - r.e1[best - 2]) best = d;
  return best;
}

}  // namespace

TEST(Cao, NoiseLooksStochasticAndDeterministicMotionsDoNot) {
  // White noise: the value dJ on is independent of the neighbour's, at every d, so E2 = 1 up to
  // sampling (Cao 1997, eq. 5); an AR(1) process (phi = 0.9) too, its next value depending on the
  // last alone, not on how close the pair was before. A deterministic series makes the next value
  // of close pairs close (E2 < 1 at small d), or stretched alike (a map: E2 > 1).
  std::vector<double> ar(10000);
  const auto w = gaussian_white(ar.size(), 11);
  for (std::size_t i = 1; i < ar.size(); ++i) ar[i] = 0.9 * ar[i - 1] + w[i];
  for (const auto& r : {cao_of(gaussian_white(10000, 7), 1.0, 1, 0), cao_of(ar, 1.0, 10, 24)}) {
    EXPECT_TRUE(r.looks_stochastic);
    for (const double e2 : r.e2) EXPECT_NEAR(e2, 1.0, 0.05);
    EXPECT_TRUE(std::any_of(r.warnings.begin(), r.warnings.end(),
                            [](const std::string& text) { return text.find("looks stochastic") != std::string::npos; }));
  }
  std::vector<double> sine(10000);
  for (std::size_t i = 0; i < sine.size(); ++i) sine[i] = std::sin(2 * M_PI * static_cast<double>(i) / 97.3);
  for (const auto& r : {cao_of(reference::lorenz_x(10000), 0.01, 18, 171), cao_of(reference::henon_x(10000), 1.0, 1, 4),
                        cao_of(reference::logistic(10000), 1.0, 1, 4), cao_of(sine, 1.0, 22, 98)}) {
    EXPECT_FALSE(r.looks_stochastic);
    EXPECT_GT(std::abs(1.0 - r.e2[0]), 0.3);  // the map stretches its pairs: E2 > 1 there
  }
}

TEST(Cao, E1RisesMostWhereTheAttractorUnfoldsAndNeverChoosesLess) {
  // Known minimum embedding dimensions: Henon 2, a sine 2, Lorenz and Roessler 3. E1 jumps into
  // that d (before it the neighbours are false and their ratio a(i, d) is large) and approaches 1
  // after it. With the Euclidean norm the approach is gradual (a(i, d)^2 = 1 + e^2 / R_d^2 and R_d
  // grows with d), so the 0.05 rule may take a d or two more, never fewer.
  std::vector<double> sine(10000);
  for (std::size_t i = 0; i < sine.size(); ++i) sine[i] = std::sin(2 * M_PI * static_cast<double>(i) / 97.3);
  const struct {
    const char* name;
    CaoResult r;
    std::size_t dim;
  } cases[] = {{"Henon x", cao_of(reference::henon_x(10000), 1.0, 1, 4), 2},
               {"sine", cao_of(sine, 1.0, 22, 98), 2},
               {"Lorenz x", cao_of(reference::lorenz_x(10000), 0.01, 18, 171), 3},
               {"Roessler x", cao_of(reference::roessler_x(10000), 0.1, 13, 57), 3}};
  for (const auto& c : cases) {
    EXPECT_EQ(largest_rise(c.r), c.dim) << c.name;
    EXPECT_GT(c.r.e1[c.dim - 1], 0.84) << c.name;
    EXPECT_LT(c.r.e1[c.dim - 2], 0.25) << c.name;
    EXPECT_TRUE(c.r.saturated) << c.name;
    EXPECT_GE(c.r.dim, c.dim) << c.name;
    EXPECT_LE(c.r.dim, c.dim + 2) << c.name;
    for (const double e : c.r.e) EXPECT_GE(e, 1.0) << c.name;  // a(i, d) >= 1 for every pair
  }
}

TEST(Cao, ScaleOfTheSeriesDoesNotMatter) {
  // 1e-200 and 1e200 times the series: the same ratios (the series is divided by its own size first).
  const auto x = reference::henon_x(3000);
  const auto base = cao_of(x, 1.0, 1, 4);
  for (const double scale : {1e-200, 1e200}) {
    std::vector<double> y(x);
    for (double& v : y) v *= scale;
    const auto r = cao_of(y, 1.0, 1, 4);
    ASSERT_EQ(r.e1.size(), base.e1.size());
    for (std::size_t d = 0; d < r.e1.size(); ++d) {
      EXPECT_NEAR(r.e1[d], base.e1[d], 1e-9 * base.e1[d] + 1e-15) << scale << " d=" << d + 1;
      EXPECT_NEAR(r.e2[d], base.e2[d], 1e-9 * base.e2[d]) << scale << " d=" << d + 1;
    }
    EXPECT_EQ(r.dim, base.dim);
  }
}

TEST(Cao, TooShortOrBadOptionsAreClearErrors) {
  const auto x = reference::henon_x(40);
  try {
    (void)cao_of(x, 1.0, 15, 10);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("too short for Cao's method"), std::string::npos) << e.what();
  }
  CaoOptions o;
  o.max_dim = 1;  // E1(1) needs E(2)
  EXPECT_THROW(o.validate(), OptionError);
  o = {};
  o.saturation = 0.0;
  EXPECT_THROW(o.validate(), OptionError);
  EXPECT_THROW((void)estimate_dimension_cao(make_series_with_step({x}, 1.0), 0, {}), OptionError);
}

TEST(Cao, ProgressIsReportedOncePerDimensionForBothMethods) {
  // mlce fnn prints these stages on long series (10^6 samples take seconds over m = 1..10).
  const auto series = make_series_with_step({reference::henon_x(2000)}, 1.0);
  std::vector<std::pair<std::string, double>> seen;
  const auto record = [&](std::string_view stage, double fraction) { seen.emplace_back(stage, fraction); };
  CaoOptions c;
  c.max_dim = 4, c.progress = record;
  (void)estimate_dimension_cao(series, 1, c);
  FnnOptions f;
  f.max_dim = 3, f.progress = record;
  (void)estimate_dimension_fnn(series, 1, f);
  ASSERT_EQ(seen.size(), 7u);
  EXPECT_EQ(seen[0].first, "Cao's E, d = 1 of 4");
  EXPECT_DOUBLE_EQ(seen[3].second, 1.0);
  EXPECT_EQ(seen[6].first, "false nearest neighbours, m = 3 of 3");
  for (std::size_t k = 1; k < 4; ++k) EXPECT_GT(seen[k].second, seen[k - 1].second);
}
