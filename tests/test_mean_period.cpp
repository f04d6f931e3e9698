#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "mlce/mean_period.hpp"
#include "reference_systems.hpp"

using namespace mlce;

namespace {
// Two sinusoids on Fourier bins: the power-weighted mean frequency is exactly
// (a1^2 f1 + a2^2 f2) / (a1^2 + a2^2) for a rectangular window, and also for Hann, whose leakage
// of an on-bin line into its two neighbours is symmetric.
Series two_tones(std::size_t n, double dt, double f1, double a1, double f2, double a2) {
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = dt * static_cast<double>(i);
    x[i] = 5.0 + a1 * std::sin(2 * std::numbers::pi * f1 * t) + a2 * std::cos(2 * std::numbers::pi * f2 * t + 0.3);
  }
  return make_series_with_step({x}, dt);
}
}  // namespace

TEST(MeanPeriod, PowerWeightedMeanFrequencyMatchesAnalyticSpectrum) {
  const std::size_t n = 4096;
  const double dt = 0.01;
  const double df = 1.0 / (n * dt);
  const double f1 = 40 * df, f2 = 250 * df;
  const double expected = (4.0 * f1 + 1.0 * f2) / 5.0;
  for (auto w : {SpectralWindow::rectangular, SpectralWindow::hann}) {
    MeanPeriodOptions o;
    o.window = w;
    const auto r = estimate_mean_period(two_tones(n, dt, f1, 2.0, f2, 1.0), o);
    EXPECT_NEAR(r.mean_frequency, expected, 1e-9 * expected);
    EXPECT_EQ(r.mean_period, static_cast<std::size_t>(std::ceil(1.0 / (expected * dt) - 1e-9)));  // eq. 19
    EXPECT_FALSE(r.clamped);
  }
}

TEST(MeanPeriod, FastShareIsThePowerAboveAQuarterOfTheSamplingRate) {
  // Two on-bin tones, one at a period of 20 samples and one of 3: the share of the power above
  // fs/4 is a2^2 / (a1^2 + a2^2) exactly (Hann's leakage stays within a bin of each line).
  const std::size_t n = 4200;  // a multiple of 20 and 3
  for (const double a2 : {0.1, 0.3, 1.0}) {
    const auto r = estimate_mean_period(two_tones(n, 1.0, 1.0 / 20, 1.0, 1.0 / 3, a2), {});
    EXPECT_NEAR(r.fast_share, a2 * a2 / (1.0 + a2 * a2), 1e-9);
    // A map whatever its mean period once 5 % or more of the power is that fast (MeanPeriodResult::map).
    EXPECT_EQ(r.map, a2 * a2 / (1.0 + a2 * a2) >= 0.05) << a2;
    EXPECT_EQ(r.mean_period, static_cast<std::size_t>(std::ceil((1.0 + a2 * a2) / (1.0 / 20 + a2 * a2 / 3) - 1e-9)));
    // A map with a flow's mean period (its slow part's) is given a white spectrum's period of 4 samples
    // for the estimator's rules; a period below kMinFlowPeriod is kept (a2 = 1: 6 samples).
    EXPECT_EQ(r.rule_period(), r.map && r.mean_period >= kMinFlowPeriod ? 4u : r.mean_period) << a2;
  }
  // A mean period below kMinFlowPeriod is a map with no fast power at all: its own period stays.
  const auto slow_map = estimate_mean_period(two_tones(n, 1.0, 1.0 / 5, 1.0, 1.0 / 6, 1.0), {});
  EXPECT_LT(slow_map.fast_share, 1e-9);
  EXPECT_TRUE(slow_map.map);
  EXPECT_EQ(slow_map.rule_period(), slow_map.mean_period);
  EXPECT_LT(slow_map.mean_period, kMinFlowPeriod);
  // The option is validated.
  MeanPeriodOptions bad;
  bad.map_fast_share = 0.0;
  EXPECT_THROW(estimate_mean_period(two_tones(n, 1.0, 1.0 / 20, 1.0, 1.0 / 3, 0.1), bad), OptionError);
}

TEST(MeanPeriod, MultichannelTakesTheHighestMeanFrequency) {
  const std::size_t n = 2048;
  Series s = two_tones(n, 1.0, 10.0 / n, 1.0, 20.0 / n, 0.0);
  s.channels.push_back(two_tones(n, 1.0, 100.0 / n, 1.0, 20.0 / n, 0.0).channels[0]);
  const auto r = estimate_mean_period(s, {});
  EXPECT_NEAR(r.mean_frequency_per_sample, 100.0 / n, 1e-9);
  EXPECT_EQ(r.mean_period, static_cast<std::size_t>(std::ceil(n / 100.0)));
}

TEST(MeanPeriod, ClampsAndReportsVeryLongPeriods) {
  const std::size_t n = 1000;
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = std::sin(2 * std::numbers::pi * i / 1800.0);  // under one cycle
  const auto r = estimate_mean_period(make_series_with_step({x}, 1.0), {});
  EXPECT_TRUE(r.clamped);
  EXPECT_EQ(r.mean_period, 250u);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("clamped to 250 (0.25 of the series)"), std::string::npos) << r.warnings[0];
  // A fraction smaller than std::to_string's six decimals is still named (it printed 0.000000).
  MeanPeriodOptions tiny;
  tiny.max_fraction = 2e-3;
  const auto t = estimate_mean_period(make_series_with_step({x}, 1.0), tiny);
  EXPECT_EQ(t.mean_period, 2u);
  ASSERT_FALSE(t.warnings.empty());
  EXPECT_NE(t.warnings[0].find("(0.002 of the series)"), std::string::npos) << t.warnings[0];
  tiny.max_fraction = 1e-7;
  try {
    tiny.validate();
  } catch (const std::exception&) {
    ADD_FAILURE() << "1e-7 is a valid fraction";
  }
  tiny.max_fraction = -1e-7;
  try {
    tiny.validate();
    ADD_FAILURE() << "no error";
  } catch (const std::exception& e) {
    EXPECT_EQ(std::string(e.what()), "mean_period.max_fraction = -1e-07: expected 0 < value <= 1");
  }
}

TEST(MeanPeriod, StrongDecaysAndGrowthsReadTheirOscillationsPeriod) {
  // A motion the Hann taper sees only where it is small: the plain mean left beneath the taper was a
  // bump whose power sat in the lowest bins (zeta = 0.5 at 50 Hz: 2612 samples, clamped to 1000; zeta = 0.2
  // over 20 periods: 121 samples). The taper-weighted mean is removed instead, and the mean period is the
  // damped period 2 pi / (omega sqrt(1 - zeta^2)) to its eq.-19 ceiling. A growth is the same record
  // reversed in time; a decay over 137 decades (zeta = 0.05 over 1000 periods) too.
  struct Case {
    std::size_t n;
    double dt, zeta, omega;
  };
  for (const Case& c : {Case{4000, 1e-4, 0.5, 100 * std::numbers::pi}, Case{2000, 0.01, 0.2, 2 * std::numbers::pi},
                        Case{2000, 0.01, -0.2, 2 * std::numbers::pi}, Case{100000, 0.01, 0.05, 2 * std::numbers::pi}}) {
    const auto r = estimate_mean_period(make_series_with_step({reference::damped_oscillator(c.n, c.dt, c.zeta, c.omega)}, c.dt), {});
    const double period = 2 * std::numbers::pi / (c.omega * std::sqrt(1 - c.zeta * c.zeta)) / c.dt;  // samples
    EXPECT_FALSE(r.clamped) << c.zeta;
    EXPECT_TRUE(r.taper_weighted_mean) << c.zeta << ": " << r.taper_mean_share;
    EXPECT_GT(r.taper_mean_share, kTaperMeanShare) << c.zeta;
    EXPECT_GE(static_cast<double>(r.mean_period), period) << c.zeta;
    EXPECT_LE(static_cast<double>(r.mean_period), 1.02 * period + 1) << c.zeta;
  }
  // A stationary motion keeps its plain mean: two tones on a level of 5 read as before (exact on their bins).
  const auto tones = estimate_mean_period(two_tones(2048, 1.0, 10.0 / 2048, 1.0, 40.0 / 2048, 1.0), {});
  EXPECT_NEAR(tones.mean_frequency_per_sample, 25.0 / 2048, 1e-9);
  EXPECT_FALSE(tones.taper_weighted_mean);
  EXPECT_LT(tones.taper_mean_share, 1e-6);
  // The rectangular window has no taper to hide a bump beneath.
  MeanPeriodOptions rectangular;
  rectangular.window = SpectralWindow::rectangular;
  const auto plain = estimate_mean_period(make_series_with_step({reference::damped_oscillator(4000, 1e-4, 0.5, 100 * std::numbers::pi)}, 1e-4), rectangular);
  EXPECT_FALSE(plain.taper_weighted_mean);
  EXPECT_EQ(plain.taper_mean_share, 0.0);
}

TEST(MeanPeriod, ScaleInvariantAtExtremeAmplitudes) {
  const Series s = two_tones(1024, 0.1, 0.3, 1.0, 1.7, 0.5);
  const auto ref = estimate_mean_period(s, {});
  for (double scale : {1e-300, 1e300}) {
    Series t = s;
    for (double& v : t.channels[0]) v *= scale;
    EXPECT_NEAR(estimate_mean_period(t, {}).mean_frequency, ref.mean_frequency, 1e-12 * ref.mean_frequency);
  }
}

TEST(MeanPeriod, EndRepeatIsTheRmsDifferenceOnePeriodOnOverTheDeviation) {
  // A periodic signal of 37.3 samples (a fundamental and its second harmonic, between two samples):
  // the period to a few hundredths of a sample (the parabola through D's least value), and a
  // difference set by the residual of that parabola only, far below any motion's.
  constexpr double period = 37.3, two_pi = 2.0 * std::numbers::pi;
  std::vector<double> cycle(6000), noisy(6000), white(6000);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  for (std::size_t i = 0; i < cycle.size(); ++i) {
    const double phase = two_pi * static_cast<double>(i) / period;
    cycle[i] = 3.0 + std::sin(phase) + 0.4 * std::cos(2.0 * phase + 0.5);
    noisy[i] = cycle[i] + 0.05 * g(rng);
    white[i] = g(rng);
  }
  const EndRepeat exact = end_repeat(make_series_with_step({cycle}, 0.01));
  EXPECT_NEAR(exact.period, period, 0.05);
  EXPECT_LT(exact.difference, 0.01);
  // White noise e of deviation s on a cycle of variance v: D = 2 s^2 / (v + s^2) at the period
  // (v = (1 + 0.4^2) / 2 = 0.58), difference = sqrt(D) = 0.0925 for s = 0.05, within its scatter
  // over the 2000-sample third.
  const EndRepeat with_noise = end_repeat(make_series_with_step({noisy}, 0.01));
  EXPECT_NEAR(with_noise.period, period, 0.5);
  EXPECT_NEAR(with_noise.difference, std::sqrt(2.0 * 0.0025 / (0.58 + 0.0025)), 0.01);
  // White noise alone never repeats: D ~ 2 at every lag, difference ~ sqrt 2 (the least of 666 lags
  // a little below it).
  const EndRepeat noise = end_repeat(make_series_with_step({white}, 1.0));
  EXPECT_GT(noise.difference, 1.2);
  EXPECT_LT(noise.difference, 1.5);
  // Chaos never repeats: Lorenz x (N = 10^4, dt = 0.01) and Roessler x (dt = 0.1) stay far from 0.
  EXPECT_GT(end_repeat(make_series_with_step({reference::lorenz_x(10000, 0.01)}, 0.01)).difference, 0.5);
  EXPECT_GT(end_repeat(make_series_with_step({reference::roessler_x(10000, 0.1)}, 0.1)).difference, 0.1);
  // Channels average their D: the cycle beside white noise, D = (D_cycle + ~2) / 2.
  const EndRepeat both = end_repeat(make_series_with_step({cycle, white}, 0.01));
  EXPECT_GT(both.difference, 0.9);
  // Scale-free: the cycle times 1e-200 and 1e200 reads the same (each channel over its peak first).
  for (const double scale : {1e-200, 1e200}) {
    std::vector<double> scaled = cycle;
    for (double& v : scaled) v *= scale;
    const EndRepeat e = end_repeat(make_series_with_step({scaled}, 0.01));
    EXPECT_NEAR(e.period, exact.period, 1e-9 * period) << scale;
    EXPECT_NEAR(e.difference, exact.difference, 1e-6) << scale;
  }
  // Nothing to tell: a constant, a third shorter than 16 samples, a period beyond a third of the third.
  EXPECT_TRUE(std::isnan(end_repeat(make_series_with_step({std::vector<double>(300, 2.0)}, 1.0)).difference));
  EXPECT_TRUE(std::isnan(end_repeat(make_series_with_step({std::vector<double>(cycle.begin(), cycle.begin() + 40)}, 1.0)).difference));
  std::vector<double> slow(600);
  for (std::size_t i = 0; i < slow.size(); ++i) slow[i] = std::sin(two_pi * static_cast<double>(i) / 500.0);
  EXPECT_TRUE(std::isnan(end_repeat(make_series_with_step({slow}, 1.0)).period));
}
