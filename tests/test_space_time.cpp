// Space-time separation plot against closed forms (independent Gaussian samples, an AR(1)
// process, a sine) and against a brute-force sort of every pair.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "mlce/space_time.hpp"
#include "reference_systems.hpp"

namespace {

using mlce::SpaceTimeOptions;
using mlce::space_time_separation;

std::vector<double> gaussian(std::size_t n, unsigned seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> normal;
  std::vector<double> x(n);
  for (auto& v : x) v = normal(gen);
  return x;
}

/// x[i+1] = a x[i] + e[i]: x[i] - x[i+D] is normal with variance 2 (1 - a^D) in units of var(x).
std::vector<double> ar1(std::size_t n, double a, unsigned seed) {
  auto x = gaussian(n, seed);
  for (std::size_t i = 1; i < n; ++i) x[i] += a * x[i - 1];
  return x;
}

/// Inverse of the standard normal CDF by bisection on std::erfc (test-side, independent of the code).
double normal_quantile(double p) {
  double lo = -10, hi = 10;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(-mid / std::numbers::sqrt2) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

TEST(SpaceTime, IndependentSamplesFollowTheNormalDifferenceAtEverySeparation) {
  // m = 1: x_i - x_j ~ N(0, 2), so the fraction-f contour is sqrt(2) Phi^-1((1 + f) / 2).
  // m = 2 (delay 1), D >= 2: the squared distance is 2 chi^2_2 (exponential, mean 4), contour
  // sqrt(-4 ln(1 - f)). (At D = 1 the two points share a sample and the components correlate.)
  const mlce::Series s = mlce::make_series_with_step({gaussian(100000, 3)}, 1.0);
  for (const std::size_t m : {1u, 2u}) {
    SpaceTimeOptions o;
    o.dim = m, o.max_separation = 20, o.step = 1, o.max_pairs = 0;
    o.fractions = {0.01, 0.1, 0.5};
    const auto r = space_time_separation(s, o);
    ASSERT_EQ(r.separation.size(), 20u);
    const std::vector<double> tolerance{0.1, 0.04, 0.02};  // ~3 standard errors of 10^3, 10^4, 5 10^4 order statistics
    for (std::size_t f = 0; f < 3; ++f) {
      const double p = o.fractions[f];
      const double expected = m == 1 ? std::numbers::sqrt2 * normal_quantile(0.5 * (1 + p)) : std::sqrt(-4 * std::log(1 - p));
      for (std::size_t k = m == 1 ? 0 : 1; k < r.separation.size(); ++k)
        EXPECT_NEAR(r.contour[f][k] / expected, 1.0, tolerance[f]) << "m " << m << " f " << p << " D " << r.separation[k];
    }
    EXPECT_EQ(r.pairs.front(), 100000u - (m - 1) - 1);
    EXPECT_EQ(r.decorrelation, 1u) << "independent samples are uncorrelated from the first separation";
    EXPECT_TRUE(r.stationary);
  }
}

TEST(SpaceTime, Ar1ContoursRiseWithTheAutocorrelationAndDecorrelateWhereTheClosedFormSays) {
  constexpr double a = 0.95;
  const mlce::Series s = mlce::make_series_with_step({ar1(400000, a, 5)}, 0.5);
  SpaceTimeOptions o;
  o.max_separation = 100, o.step = 1, o.max_pairs = 0;
  o.fractions = {0.1, 0.5};
  const auto r = space_time_separation(s, o);
  const auto contour = [&](double p, double D) {
    return std::sqrt(2 * (1 - std::pow(a, D))) * normal_quantile(0.5 * (1 + p));
  };
  for (const std::size_t D : {1u, 3u, 10u, 30u, 100u}) {
    EXPECT_NEAR(r.contour[1][D - 1] / contour(0.5, static_cast<double>(D)), 1.0, 0.02) << D;
    EXPECT_NEAR(r.contour[0][D - 1] / contour(0.1, static_cast<double>(D)), 1.0, 0.03) << D;
  }
  // Plateau: the median of the 0.1 contour over D = 51..100; decorrelation: the first D at which
  // sqrt(1 - a^D) >= 0.5 sqrt(1 - a^D_median), D_median ~ 75.
  EXPECT_NEAR(r.plateau / contour(0.1, 75.5), 1.0, 0.05);
  const double d_star = std::log(1 - 0.25 * (1 - std::pow(a, 75.5))) / std::log(a);  // 5.47
  EXPECT_EQ(static_cast<double>(r.decorrelation), std::ceil(d_star));  // 6 on seeds 1..8 (scratch)
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  // Asked for 0.99 of the plateau (closed form: D = 62.5), the decorrelation passes the mean period
  // (41 samples here) and the result says which Theiler window would be safe.
  o.decorrelation_level = 0.99;
  const auto late = space_time_separation(s, o);
  const double d_late = std::log(1 - 0.99 * 0.99 * (1 - std::pow(a, 75.5))) / std::log(a);
  EXPECT_NEAR(static_cast<double>(late.decorrelation), d_late, 8.0);
  ASSERT_GT(late.decorrelation, late.mean_period);
  ASSERT_EQ(late.warnings.size(), 1u);
  EXPECT_NE(late.warnings[0].find("give a Theiler window of at least " + std::to_string(late.decorrelation)),
            std::string::npos)
      << late.warnings[0];
}

TEST(SpaceTime, SineReturnsExactlyAfterOnePeriodAndOtherwiseFollowsTheArcsineLaw) {
  // x = sin(w i), std 1/sqrt(2): |x_i - x_{i+D}| / std = 2 sqrt(2) |sin(w D / 2)| |cos(w i + w D / 2)|,
  // and |cos| of a phase equidistributed mod pi has the arcsine law: the fraction-f contour is
  // 2 sqrt(2) |sin(w D / 2)| sin(pi f / 2). With a period of exactly 100 samples every pair 100
  // or 200 apart coincides.
  const auto sine = [](double period) {
    std::vector<double> x(20000);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(2 * std::numbers::pi * static_cast<double>(i) / period);
    return mlce::make_series_with_step({x}, 0.01);
  };
  SpaceTimeOptions o;
  o.max_separation = 200, o.step = 1, o.max_pairs = 0;
  const auto exact = space_time_separation(sine(100.0), o);
  EXPECT_EQ(exact.mean_period, 100u);
  for (std::size_t f = 0; f < exact.fractions.size(); ++f) {
    EXPECT_LT(exact.contour[f][99], 1e-9) << exact.fractions[f];
    EXPECT_LT(exact.contour[f][199], 1e-9) << exact.fractions[f];
  }
  const double period = 100 + std::numbers::sqrt2, w = 2 * std::numbers::pi / period;
  const auto r = space_time_separation(sine(period), o);
  for (const std::size_t D : {5u, 25u, 50u, 77u, 150u})
    for (std::size_t f = 0; f < r.fractions.size(); ++f)
      EXPECT_NEAR(r.contour[f][D - 1],
                  2 * std::numbers::sqrt2 * std::abs(std::sin(w * static_cast<double>(D) / 2)) *
                      std::sin(std::numbers::pi * r.fractions[f] / 2),
                  2e-3)
          << "D " << D << " f " << r.fractions[f];
}

TEST(SpaceTime, ContoursAreTheOrderStatisticsOfEveryPairByBruteForce) {
  // Lorenz x, m = 3, delay 10: the test embeds and standardises (standard deviation over N) on its
  // own and sorts every pair.
  const auto x = mlce::reference::lorenz_x(3000, 0.01);
  SpaceTimeOptions o;
  o.dim = 3, o.delay = 10, o.max_separation = 300, o.step = 7, o.max_pairs = 0;
  o.fractions = {0.5, 0.02, 0.2, 0.5};  // unsorted and repeated on purpose: the result lists them ascending, once
  const auto r = space_time_separation(mlce::make_series_with_step({x}, 0.01), o);
  ASSERT_EQ(r.fractions, (std::vector<double>{0.02, 0.2, 0.5}));
  long double mean = 0, var = 0;
  for (double v : x) mean += v;
  mean /= x.size();
  for (double v : x) var += (v - mean) * (v - mean);
  const double sd = std::sqrt(static_cast<double>(var / x.size()));  // over N, as the divergence curve's units
  const std::size_t M = x.size() - std::size_t{2} * 10;
  for (std::size_t k = 0; k < r.separation.size(); ++k) {
    const std::size_t D = r.separation[k];
    ASSERT_EQ(D, 7 * (k + 1));
    std::vector<double> d;
    for (std::size_t i = 0; i + D < M; ++i) {
      double s2 = 0;
      for (std::size_t c = 0; c < 3; ++c) s2 += std::pow((x[i + 10 * c] - x[i + D + 10 * c]) / sd, 2);
      d.push_back(std::sqrt(s2));
    }
    std::sort(d.begin(), d.end());
    ASSERT_EQ(r.pairs[k], d.size());
    for (std::size_t f = 0; f < 3; ++f)
      EXPECT_NEAR(r.contour[f][k], d[static_cast<std::size_t>(std::floor(r.fractions[f] * (d.size() - 1)))], 1e-9)
          << "D " << D << " f " << r.fractions[f];
  }
}

TEST(SpaceTime, FewerPairsAreEvenlyStridedAndAgreeWithAll) {
  // 2000 of ~50000 pairs per separation: the 0.5 contour of Gaussian samples within 6 %.
  const mlce::Series s = mlce::make_series_with_step({gaussian(50000, 9)}, 1.0);
  SpaceTimeOptions o;
  o.max_separation = 10, o.step = 1, o.max_pairs = 2000;
  const auto r = space_time_separation(s, o);
  for (std::size_t k = 0; k < r.separation.size(); ++k) {
    EXPECT_EQ(r.pairs[k], 2000u);
    EXPECT_NEAR(r.contour[2][k], std::numbers::sqrt2 * normal_quantile(0.75), 0.06 * 0.954);
  }
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();  // 20 pairs below the 0.01 contour
  o.max_pairs = 500;                                       // 5 below it: a quantile of nothing
  const auto few = space_time_separation(s, o);
  ASSERT_EQ(few.warnings.size(), 1u);
  EXPECT_NE(few.warnings[0].find("the lowest contour (0.01) rests on 5 pair(s) of 500"), std::string::npos)
      << few.warnings[0];
}

TEST(SpaceTime, DecayIsFlaggedAsNotStationaryInsteadOfAdvisingATheilerWindow) {
  const auto x = mlce::reference::damped_oscillator(3000, 0.01, 0.05, 2 * std::numbers::pi);
  const auto r = space_time_separation(mlce::make_series_with_step({x}, 0.01), {});
  EXPECT_FALSE(r.stationary);
  EXPECT_LT(r.amplitude_ratio, 0.5);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("stationary"), std::string::npos) << r.warnings[0];
  // At rest for its first third, then moving (a growth): flagged the same way.
  std::vector<double> late(3000, 0.0);
  for (std::size_t i = 1000; i < late.size(); ++i) late[i] = std::sin(0.1 * static_cast<double>(i));
  const auto starts = space_time_separation(mlce::make_series_with_step({late}, 0.01), {});
  EXPECT_FALSE(starts.stationary);
  EXPECT_GT(starts.amplitude_ratio, 2.0);
  ASSERT_FALSE(starts.warnings.empty());
  EXPECT_NE(starts.warnings.back().find("assumes a stationary motion"), std::string::npos) << starts.warnings.back();
}

TEST(SpaceTime, BadOptionsAndShortSeriesAreRefusedWithTheirReason) {
  const mlce::Series s = mlce::make_series_with_step({gaussian(500, 1)}, 1.0);
  SpaceTimeOptions o;
  o.fractions = {0.1, 1.0};
  EXPECT_THROW(space_time_separation(s, o), mlce::OptionError);
  o.fractions = {};
  EXPECT_THROW(space_time_separation(s, o), mlce::OptionError);
  o = {};
  o.dim = 0;
  EXPECT_THROW(space_time_separation(s, o), mlce::OptionError);
  o = {};
  o.max_separation = 1;  // a plateau needs separations to compare
  EXPECT_THROW(space_time_separation(s, o), mlce::OptionError);
  std::vector<double> flat(500, 2.0);
  EXPECT_THROW(space_time_separation(mlce::make_series_with_step({flat}, 1.0), {}), mlce::InputError);
  o = {};
  o.max_separation = 450;  // leaves 50 pairs at the largest separation: fewer than 100
  try {
    space_time_separation(s, o);
    FAIL() << "expected InputError";
  } catch (const mlce::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("series too short: 500 samples"), std::string::npos) << e.what();
  }
  o = {};
  o.max_separation = 10, o.step = 8;  // one separation only
  EXPECT_THROW(space_time_separation(s, o), mlce::OptionError);
}
