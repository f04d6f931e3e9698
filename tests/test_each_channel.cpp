// Every channel estimated on its own, and the verdict on whether they agree: against the exact
// exponents of damped oscillators (lambda = -zeta omega), and against estimate_mlce run on each
// channel as a series of its own.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mlce/each_channel.hpp"
#include "reference_systems.hpp"

namespace {

constexpr double kTwoPi = 6.283185307179586;

/// Velocity of reference::damped_oscillator (x = 1, v = 0 at t = 0): v = -(omega^2 / omega_d)
/// e^(-zeta omega t) sin(omega_d t), the same decay rate as the displacement.
std::vector<double> damped_velocity(std::size_t n, double dt, double zeta, double omega) {
  const double wd = omega * std::sqrt(1.0 - zeta * zeta);
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = dt * static_cast<double>(i);
    v[i] = -omega * omega / wd * std::exp(-zeta * omega * t) * std::sin(wd * t);
  }
  return v;
}

mlce::Series two_channels(std::vector<double> a, std::vector<double> b, double dt) {
  mlce::Series s = mlce::make_series_with_step({std::move(a), std::move(b)}, dt);
  s.names = {"first", "second"};
  return s;
}

}  // namespace

TEST(EachChannel, DisplacementAndVelocityOfOneDecayShareItsExponent) {
  const double dt = 0.01, zeta = 0.05, omega = kTwoPi;
  const std::size_t n = 2000;
  const auto x = mlce::reference::damped_oscillator(n, dt, zeta, omega);
  const auto v = damped_velocity(n, dt, zeta, omega);
  const mlce::EachChannelResult r = mlce::estimate_each_channel(two_channels(x, v, dt), {});
  ASSERT_EQ(r.channels.size(), 2u);
  EXPECT_EQ(r.estimated, 2u);
  EXPECT_EQ(r.channels[0].name, "first");
  EXPECT_EQ(r.channels[1].name, "second");
  for (const auto& c : r.channels) {
    ASSERT_TRUE(c.result) << c.name << ": " << c.error;
    EXPECT_NEAR(c.result->lambda, -zeta * omega, 0.03 * zeta * omega) << c.name;
  }
  EXPECT_TRUE(r.verdict.agree) << r.verdict.gap << " " << r.verdict.tolerance_floor;
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  if (r.verdict.gap <= 0.0) {
    EXPECT_LE(r.verdict.common_low, r.verdict.common_high);
    for (const auto& c : r.channels) EXPECT_TRUE(c.result->ci95_low <= r.verdict.common_low && r.verdict.common_high <= c.result->ci95_high);
  }
  // Each channel's estimate is the one of a file that holds that channel only.
  const mlce::MlceResult alone_x = mlce::estimate_mlce(mlce::make_series_with_step({x}, dt), {});
  const mlce::MlceResult alone_v = mlce::estimate_mlce(mlce::make_series_with_step({v}, dt), {});
  EXPECT_EQ(r.channels[0].result->lambda, alone_x.lambda);
  EXPECT_EQ(r.channels[1].result->lambda, alone_v.lambda);
  EXPECT_EQ(r.channels[1].result->delay, alone_v.delay);
  EXPECT_EQ(r.channels[1].result->fit.first, alone_v.fit.first);
}

TEST(EachChannel, TwoDecaysAtDifferentRatesDisagreeAndTheWarningNamesThem) {
  // Two motions in one file (a channel that does not see the least damped mode reads another rate).
  const double dt = 0.01, omega = kTwoPi;
  const std::size_t n = 2000;
  const mlce::EachChannelResult r = mlce::estimate_each_channel(
      two_channels(mlce::reference::damped_oscillator(n, dt, 0.05, omega),
                   mlce::reference::damped_oscillator(n, dt, 0.15, omega), dt),
      {});
  ASSERT_EQ(r.estimated, 2u);
  EXPECT_NEAR(r.channels[0].result->lambda, -0.05 * omega, 0.03 * 0.05 * omega);
  EXPECT_NEAR(r.channels[1].result->lambda, -0.15 * omega, 0.03 * 0.15 * omega);
  EXPECT_FALSE(r.verdict.agree);
  EXPECT_GT(r.verdict.gap, r.verdict.tolerance_floor);
  EXPECT_TRUE(std::isnan(r.verdict.common_low) && std::isnan(r.verdict.common_high));
  EXPECT_NEAR(r.verdict.median_lambda, -0.10 * omega, 0.03 * 0.10 * omega);  // the mean of two
  ASSERT_EQ(r.warnings.size(), 1u);
  for (const char* word : {"disagree", "first", "second"})
    EXPECT_NE(r.warnings[0].find(word), std::string::npos) << word << ": " << r.warnings[0];
}

TEST(EachChannel, AChannelOfNoiseIsLeftOutOfTheVerdictAndNamed) {
  // A constrained coordinate holds the solver's rounding (node:2:y of the bundled MBDyn runs): white
  // noise, whose curve plateaus within one embedding window. Its "lambda" measures the window, not a
  // divergence; it must not make the channels that do carry the decay disagree.
  const double dt = 0.01, zeta = 0.05, omega = kTwoPi;
  const std::size_t n = 2000;
  std::mt19937_64 gen(20261127);
  std::normal_distribution<double> white(0.0, 1e-22);
  std::vector<double> noise(n);
  for (auto& e : noise) e = white(gen);
  mlce::Series s = mlce::make_series_with_step(
      {mlce::reference::damped_oscillator(n, dt, zeta, omega), damped_velocity(n, dt, zeta, omega), noise}, dt);
  s.names = {"first", "second", "rounding"};
  const mlce::EachChannelResult r = mlce::estimate_each_channel(s, {});
  ASSERT_EQ(r.estimated, 3u);
  ASSERT_TRUE(r.channels[2].result);
  EXPECT_FALSE(r.channels[2].result->unreliable.empty()) << r.channels[2].result->lambda;
  EXPECT_EQ(r.compared, 2u);
  for (std::size_t c = 0; c < 2; ++c) EXPECT_NEAR(r.channels[c].result->lambda, -zeta * omega, 0.03 * zeta * omega);
  EXPECT_TRUE(r.verdict.agree) << r.verdict.gap << " " << r.verdict.tolerance_floor;
  EXPECT_NEAR(r.verdict.median_lambda, -zeta * omega, 0.03 * zeta * omega);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("rounding is left out of the comparison"), std::string::npos) << r.warnings[0];
  // Judged over all three, the noise's interval would stand apart.
  EXPECT_FALSE(mlce::judge_agreement({&*r.channels[0].result, &*r.channels[1].result, &*r.channels[2].result}).agree);
  // Noise beside noise: estimated, nothing compared, no verdict.
  mlce::Series both = mlce::make_series_with_step({noise, std::vector<double>(noise.rbegin(), noise.rend())}, dt);
  const mlce::EachChannelResult none = mlce::estimate_each_channel(both, {});
  EXPECT_EQ(none.estimated, 2u);
  EXPECT_EQ(none.compared, 0u);
  EXPECT_FALSE(none.verdict.agree);
  EXPECT_TRUE(std::isnan(none.verdict.gap) && std::isnan(none.verdict.median_lambda));
  ASSERT_EQ(none.warnings.size(), 3u);
  EXPECT_NE(none.warnings[2].find("0 of the 2 estimated channels measure a divergence"), std::string::npos) << none.warnings[2];
}

TEST(EachChannel, AChannelThatCannotBeEstimatedIsRecordedAndTheOthersGoOn) {
  const double dt = 0.01;
  const std::size_t n = 2000;
  const auto x = mlce::reference::damped_oscillator(n, dt, 0.05, kTwoPi);
  const std::vector<double> constant(n, 3.0);
  const mlce::EachChannelResult r = mlce::estimate_each_channel(two_channels(x, constant, dt), {});
  EXPECT_EQ(r.estimated, 1u);
  ASSERT_TRUE(r.channels[0].result);
  EXPECT_FALSE(r.channels[1].result);
  EXPECT_NE(r.channels[1].error.find("constant"), std::string::npos) << r.channels[1].error;
  EXPECT_FALSE(r.verdict.agree);  // nothing to compare with
  EXPECT_TRUE(std::isnan(r.verdict.gap) && std::isnan(r.verdict.common_low) && std::isnan(r.verdict.common_high));
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_NE(r.warnings[0].find("second could not be estimated"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[1].find("only one channel"), std::string::npos) << r.warnings[1];
  // No channel at all: the first one's error, as an input error.
  try {
    mlce::estimate_each_channel(two_channels(constant, constant, dt), {});
    ADD_FAILURE() << "expected an InputError";
  } catch (const mlce::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no channel could be estimated; first: "), std::string::npos) << e.what();
  }
  // One channel is not a comparison; bad tolerances are option errors.
  EXPECT_THROW(mlce::estimate_each_channel(mlce::make_series_with_step({x}, dt), {}), mlce::OptionError);
  mlce::EachChannelOptions bad;
  bad.relative_tolerance = -1.0;
  EXPECT_THROW(mlce::estimate_each_channel(two_channels(x, x, dt), bad), mlce::OptionError);
}

TEST(EachChannel, ProgressRunsOverAllChannelsAndNamesThem) {
  const double dt = 0.01;
  const auto x = mlce::reference::damped_oscillator(2000, dt, 0.05, kTwoPi);
  mlce::EachChannelOptions o;
  std::vector<std::pair<std::string, double>> seen;
  o.estimate.progress = [&](std::string_view stage, double fraction) { seen.emplace_back(std::string(stage), fraction); };
  mlce::estimate_each_channel(two_channels(x, damped_velocity(2000, dt, 0.05, kTwoPi), dt), o);
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.back().first, "done");
  EXPECT_EQ(seen.back().second, 1.0);
  bool first = false, second = false;
  for (std::size_t k = 0; k < seen.size(); ++k) {
    first = first || seen[k].first.rfind("first (1 of 2): ", 0) == 0;
    second = second || seen[k].first.rfind("second (2 of 2): ", 0) == 0;
    EXPECT_GE(seen[k].second, 0.0);
    EXPECT_LE(seen[k].second, 1.0);
    if (k > 0) {
      EXPECT_GE(seen[k].second, seen[k - 1].second) << seen[k].first;
    }
  }
  EXPECT_TRUE(first && second);
}

TEST(EachChannel, AgreementIsJudgedAtTheEstimatesResolution) {
  // Intervals built by hand, the verdict worked out by hand.
  auto estimate = [](double lambda, double half_width, double mean_frequency) {
    mlce::MlceResult r;
    r.lambda = lambda, r.ci95_low = lambda - half_width, r.ci95_high = lambda + half_width;
    r.mean_period.mean_frequency = mean_frequency;
    return r;
  };
  // A limit cycle read through two channels: 0 resolved to 1 % of the mean frequency (1 Hz: 0.01
  // 1/s), so narrow intervals 5e-5 apart are one exponent even though they do not overlap.
  const auto a = estimate(-2e-5, 1e-6, 1.0), b = estimate(3e-5, 1e-6, 1.0);
  mlce::Agreement v = mlce::judge_agreement({&a, &b});
  EXPECT_NEAR(v.gap, 5e-5 - 2e-6, 1e-12);
  EXPECT_DOUBLE_EQ(v.tolerance_floor, 0.01);
  EXPECT_TRUE(v.agree);
  EXPECT_TRUE(std::isnan(v.common_low));
  EXPECT_EQ(v.highest_low, 1u);
  EXPECT_EQ(v.lowest_high, 0u);
  // 0.31 +- 0.01 against 0.35 +- 0.01, no frequency term: 0.02 apart, beyond 5 % of the median 0.33.
  const auto c = estimate(0.31, 0.01, 0.0), d = estimate(0.35, 0.01, 0.0);
  v = mlce::judge_agreement({&c, &d});
  EXPECT_NEAR(v.gap, 0.02, 1e-12);
  EXPECT_NEAR(v.tolerance_floor, 0.05 * 0.33, 1e-12);
  EXPECT_FALSE(v.agree);
  // Three that overlap: the common part is [max low, min high], the median the middle one.
  const auto e = estimate(0.30, 0.05, 0.0), f = estimate(0.33, 0.05, 0.0), g = estimate(0.32, 0.04, 0.0);
  v = mlce::judge_agreement({&e, &f, &g});
  EXPECT_TRUE(v.agree);
  EXPECT_NEAR(v.common_low, 0.28, 1e-12);
  EXPECT_NEAR(v.common_high, 0.35, 1e-12);
  EXPECT_DOUBLE_EQ(v.median_lambda, 0.32);
  // One estimate is no comparison.
  v = mlce::judge_agreement({&e});
  EXPECT_FALSE(v.agree);
  EXPECT_TRUE(std::isnan(v.gap));
}
