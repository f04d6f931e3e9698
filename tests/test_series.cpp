#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "mlce/series.hpp"
#include "reference_systems.hpp"

using namespace mlce;

TEST(Series, UniformTimeColumnGivesItsStep) {
  std::vector<double> t, x;
  for (int i = 0; i < 100; ++i) t.push_back(2.0 + 0.05 * i), x.push_back(std::sin(0.3 * i));
  const Series s = make_series_from_time(t, {x}, {});
  EXPECT_NEAR(s.dt, 0.05, 1e-15);
  EXPECT_DOUBLE_EQ(s.t0, 2.0);
  EXPECT_EQ(s.size(), 100u);
}

TEST(Series, NonUniformTimeIsAnErrorNamingTheSample) {
  std::vector<double> t, x;
  for (int i = 0; i < 100; ++i) t.push_back(0.1 * i + (i >= 40 ? 0.05 : 0.0)), x.push_back(std::sin(0.3 * i));
  try {
    make_series_from_time(t, {x}, {});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.index(), 40u);
    EXPECT_NE(std::string(e.what()).find("non-uniform"), std::string::npos);
  }
}

TEST(Series, ExplicitResamplingInterpolatesLinearly) {
  std::vector<double> t, x;
  for (int i = 0; i < 200; ++i) {
    const double ti = 0.1 * i + (i % 2 ? 0.03 : 0.0);  // jittered clock
    t.push_back(ti);
    x.push_back(3.0 * ti - 1.0);  // linear: interpolation is exact
  }
  SamplingOptions o;
  o.resample = true;
  std::vector<std::string> warnings;
  const Series s = make_series_from_time(t, {x}, o, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  for (std::size_t i = 0; i < s.size(); ++i) EXPECT_NEAR(s.channels[0][i], 3.0 * s.time(i) - 1.0, 1e-12);
}

TEST(Series, TimesPrintedWithTooFewDigitsForTheStepAreTakenAsTheirGrid) {
  // A %g export (6 significant digits) of t = 1000 + 0.005 k: 1000, 1000, 1000.01, 1000.01, ...
  // repeats times although the sampling is uniform; 100 + 0.0025 k prints steps of 0.002 and
  // 0.003 (20 % off). Both are their grid, said in a warning.
  for (const auto& [t0, step] : {std::pair{1000.0, 0.005}, std::pair{100.0, 0.0025}, std::pair{123456.0, 0.01}}) {
    std::vector<double> t, x;
    char text[32];
    for (int i = 0; i < 4000; ++i) {
      std::snprintf(text, sizeof text, "%g", t0 + step * i);
      t.push_back(std::stod(text)), x.push_back(std::sin(0.3 * i));
    }
    std::vector<std::string> warnings;
    const Series s = make_series_from_time(t, {x}, {}, &warnings);
    // The grid is known to about a printed unit over the span (123456 + 0.01 k: unit 1 over 40).
    const double unit = std::pow(10.0, std::floor(std::log10(t0)) - 5);
    EXPECT_NEAR(s.dt, step, std::max(1e-4, unit / (4000 * step)) * step) << t0;
    EXPECT_NEAR(s.t0, t0, unit) << t0;
    ASSERT_EQ(warnings.size(), 1u) << t0;
    EXPECT_NE(warnings[0].find("time printed with 6 significant digits"), std::string::npos) << warnings[0];
  }
  // Not rounding: a sample 3 printed units late (100.0125 printed as 100.015), a missing sample
  // among 6-digit times that resolve the step, and sample indices with a gap (too few digits to
  // tell a gap from rounding: never taken as a grid).
  auto printed = [](double t0, double step, int n, int skip, double late, int digits = 6) {
    std::vector<double> t;
    char text[32];
    for (int i = 0; i < n; ++i) {
      if (i == skip) continue;
      std::snprintf(text, sizeof text, "%.*g", digits, t0 + step * i + (i == 5 ? late : 0.0));
      t.push_back(std::stod(text));
    }
    return t;
  };
  // Nor a sample missing from 1000 + 0.001 k printed with 7 digits: the step is a whole printed
  // unit, every other time is exact, and the gap is the clock's.
  for (const auto& t : {printed(100.0, 0.0025, 400, -1, 0.003), printed(100.0, 0.005, 400, 200, 0.0),
                        printed(100.0, 1.0, 100, 50, 0.0), printed(1000.0, 0.001, 4000, 2000, 0.0, 7)}) {
    const std::vector<double> x(t.size(), 1.0);
    EXPECT_THROW(make_series_from_time(t, {x}, {}), InputError) << t[0] << " " << t[1];
  }
}

TEST(Series, DecreasingTimeIsAnError) {
  EXPECT_THROW(make_series_from_time({0.0, 1.0, 0.5}, {{1.0, 2.0, 3.0}}, {}), InputError);
}

TEST(Series, NonFiniteSampleIsAnErrorNamingTheIndex) {
  Series s = make_series_with_step({{1.0, 2.0, NAN, 4.0}}, 1.0);
  try {
    validate_series(s);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.index(), 2u);
  }
  s.channels[0][2] = INFINITY;
  EXPECT_THROW(validate_series(s), InputError);
}

TEST(Series, ConstantSeriesIsAnError) {
  const Series s = make_series_with_step({std::vector<double>(50, 3.25)}, 0.1);
  try {
    validate_series(s);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("constant"), std::string::npos);
  }
}

TEST(Series, StandardizationIsScaleFreeAtTheExtremes) {
  std::vector<double> x;
  for (int i = 0; i < 1000; ++i) x.push_back(std::sin(0.1 * i) + 0.3 * std::cos(0.37 * i) + 2.0);
  const Series ref = standardized(make_series_with_step({x}, 1.0));
  for (double scale : {1e-300, 1e-200, 1e200, 1e300}) {
    std::vector<double> y = x;
    for (double& v : y) v *= scale;
    const Series s = standardized(make_series_with_step({y}, 1.0));
    for (std::size_t i = 0; i < x.size(); ++i) ASSERT_NEAR(s.channels[0][i], ref.channels[0][i], 1e-12) << scale;
  }
}

// What scaled_to_unit_deviation divides by: the population standard deviation about the mean,
// here of a square wave of amplitude a about an offset (exactly a), at the ends of the double range
// too; a constant channel is divided by its magnitude, an all-zero one by 1. Dividing by it gives
// the scaled series.
TEST(Series, UnitDeviationDivisorIsTheChannelsStandardDeviation) {
  for (const double a : {1e-300, 1.0, 3.5, 1e300}) {
    std::vector<double> wave, constant(8, -2.0 * a), zero(8, 0.0);
    for (int i = 0; i < 8; ++i) wave.push_back((i % 2 ? 1.5 : -0.5) * a);  // offset a / 2, deviation a
    const Series s = make_series_with_step({wave, constant, zero}, 1.0);
    const auto divisors = unit_deviation_divisors(s);
    ASSERT_EQ(divisors.size(), 3u);
    EXPECT_NEAR(divisors[0] / a, 1.0, 1e-15) << a;
    EXPECT_NEAR(divisors[1] / a, 2.0, 1e-15) << a;
    EXPECT_EQ(divisors[2], 1.0);
    const Series unit = scaled_to_unit_deviation(s);
    for (std::size_t c = 0; c < 3; ++c)
      for (std::size_t i = 0; i < 8; ++i)
        EXPECT_NEAR(unit.channels[c][i], s.channels[c][i] / divisors[c], 1e-15) << a << " " << c << " " << i;
  }
}

TEST(Series, TimeWindowSelectsInclusiveRange) {
  std::vector<double> x(100);
  for (int i = 0; i < 100; ++i) x[i] = i;
  const Series s = make_series_with_step({x}, 0.5);
  const Series w = time_window(s, 10.0, 20.0);
  EXPECT_EQ(w.size(), 21u);
  EXPECT_DOUBLE_EQ(w.channels[0].front(), 20.0);
  EXPECT_DOUBLE_EQ(w.t0, 10.0);
  EXPECT_THROW(time_window(s, 100.0, 200.0), InputError);
}

#include "mlce/mean_period.hpp"
#include "mlce/transient.hpp"

namespace {
/// envelope(t) sin(2 pi t), t = 0, dt, ..., (n-1) dt: a unit-frequency oscillation whose
/// amplitude settles (or grows into saturation) as the envelope says.
template <class Envelope>
std::vector<double> enveloped_sine(int n, double dt, Envelope envelope) {
  std::vector<double> x;
  for (int i = 0; i < n; ++i) {
    const double t = dt * i;
    x.push_back(envelope(t) * std::sin(2 * M_PI * t));
  }
  return x;
}
}  // namespace

TEST(Transient, DecayOntoASteadyOscillationIsCutWhereItSettles) {
  // amplitude 1 + 4 e^{-t/5} sin(2 pi t). The settled sine's window RMS does not scatter, so the
  // automatic band is its floor, 2 %: settled after t = 5 ln(4 / 0.02) = 26.5. A given band of
  // 25 % settles after t = 5 ln 16 = 13.9.
  const auto x = enveloped_sine(40000, 0.01, [](double t) { return 1.0 + 4.0 * std::exp(-t / 5.0); });
  TransientOptions o;
  o.period = 100;
  const auto r = detect_transient(make_series_with_step({x}, 0.01), o);
  EXPECT_TRUE(r.settled);
  EXPECT_GT(r.end_time, 24.0) << r.rule;
  EXPECT_LT(r.end_time, 30.0) << r.rule;
  o.band = 0.25;
  const auto loose = detect_transient(make_series_with_step({x}, 0.01), o);
  EXPECT_GT(loose.end_time, 11.0) << loose.rule;
  EXPECT_LE(loose.end_time, 18.0) << loose.rule;  // windows of N/100 = 4 s
}

TEST(Transient, ShortRunOfALongPeriodOscillationIsStillCut) {
  // 30 periods of 200 samples (a 30 s MBDyn run of a 1 s limit cycle at 5 ms output): the
  // amplitude grows as e^{0.3 t} to saturate at 1 near t = 15 s. Windows of two periods give 15
  // windows; the old four-period windows gave 7 and nothing was cut.
  const auto x = enveloped_sine(6000, 0.005, [](double t) { return std::min(1.0, 0.011 * std::exp(0.3 * t)); });
  TransientOptions o;
  o.period = 200;
  const auto r = detect_transient(make_series_with_step({x}, 0.005), o);
  EXPECT_TRUE(r.settled);
  EXPECT_GT(r.end_time, 14.0) << r.rule;
  EXPECT_LT(r.end_time, 18.0) << r.rule;
}

TEST(Transient, ChaosIsNotCutShort) {
  // Stationary Lorenz x: window RMS scatters by ~10 %, the automatic band widens with it and
  // (almost) nothing is cut.
  const auto x = reference::lorenz_x(20000, 0.01);
  TransientOptions o;
  o.period = 171;
  const auto r = detect_transient(make_series_with_step({x}, 0.01), o);
  EXPECT_LT(r.end_time, 40.0) << r.rule;
  std::printf("Lorenz x, 200 s: %s\n", r.rule.c_str());
}

TEST(Transient, ChaosAlreadyOnItsAttractorIsNotCut) {
  // Series of 10^4 samples that start on the attractor have no transient. The last quarter's few
  // windows (7) may agree closely by chance, and with a band from their largest deviation alone an
  // excursion anywhere cut the series up to it: 17 of 32 Lorenz and 10 of 32 Roessler series lost
  // 10-75 % (until commit 27f33bd). With the band widened to 8 robust standard deviations of the
  // last quarter's window RMS (from second differences), few are cut by more than 10 %.
  std::mt19937 gen(12);
  std::uniform_real_distribution<double> u(-15.0, 15.0), uz(5.0, 40.0), ur(-5.0, 5.0);
  int lorenz_cut = 0, roessler_cut = 0;
  for (int k = 0; k < 16; ++k) {
    TransientResult r;
    skip_transient(make_series_with_step({reference::lorenz_x(10000, 0.01, {u(gen), u(gen), uz(gen)})}, 0.01), &r);
    lorenz_cut += r.end_index > 1000;
    skip_transient(make_series_with_step({reference::roessler(10000, 0.1, {ur(gen), ur(gen), 0.1}, 0)}, 0.1), &r);
    roessler_cut += r.end_index > 1000;
  }
  std::printf("cut by more than 10 %%: Lorenz %d of 16, Roessler %d of 16\n", lorenz_cut, roessler_cut);
  EXPECT_LE(lorenz_cut, 3);
  EXPECT_LE(roessler_cut, 1);
}

TEST(Transient, DecayIntoTheNoiseFloorEndsWhereTheFloorStarts) {
  // e^{-t} sin(2 pi t) reaches the 1e-12 noise of an integrator's absolute tolerance near
  // t = ln(1e12) = 27.6 (10x the floor at 25.3); the floor is not a settled motion to keep.
  std::vector<double> x;
  for (int i = 0; i < 20000; ++i) {
    const double t = 0.01 * i;
    x.push_back(std::exp(-t) * std::sin(2 * M_PI * t) + 1e-12 * std::sin(7.3 * i));
  }
  TransientOptions o;
  o.period = 100;
  const auto r = detect_transient(make_series_with_step({x}, 0.01), o);
  EXPECT_FALSE(r.settled);
  EXPECT_EQ(r.end_index, 0u);
  EXPECT_GT(r.floor_index * 0.01, 20.0);
  EXPECT_LT(r.floor_index * 0.01, 30.0);
  // The rule names the floor ratio as given (std::to_string printed 1e-9 as 0.000000).
  TransientOptions deep = o;
  deep.floor_ratio = 1e-9;
  const auto d = detect_transient(make_series_with_step({x}, 0.01), deep);
  EXPECT_GT(d.floor_index, 0u);
  EXPECT_NE(d.rule.find("(RMS below 1e-09 of its largest)"), std::string::npos) << d.rule;
  // A limit cycle, however small against its start-up, is not a floor.
  std::vector<double> lc;
  for (int i = 0; i < 20000; ++i) lc.push_back((1e-4 + std::exp(-0.01 * i)) * std::sin(2 * M_PI * 0.01 * i));
  EXPECT_EQ(detect_transient(make_series_with_step({lc}, 0.01), o).floor_index, 0u);
}

TEST(Transient, LastWindowAboveTheFloorLevelEndsNoFloor) {
  // The decay of the previous test, 20003 samples (100 windows of 200 and 3 over), with a late
  // kick in its last window: the last quarter's median is still far below the peak, but the series
  // does not end on a floor. The rule once reported a floor "from sample 20000" and cut the 3
  // samples past the windows (the iso_200rpm run's rel:11:4:z: 1 sample).
  std::vector<double> x;
  for (int i = 0; i < 20003; ++i) {
    const double t = 0.01 * i;
    x.push_back(std::exp(-t) * std::sin(2 * M_PI * t) + 1e-12 * std::sin(7.3 * i) + (i >= 19850 ? 1e-7 * std::sin(3.1 * i) : 0.0));
  }
  EXPECT_EQ(detect_floor(make_series_with_step({x}, 0.01), 1e-6).index, 0u);
  x.resize(19800);  // without the kick it ends on its floor, found as before
  EXPECT_GT(detect_floor(make_series_with_step({x}, 0.01), 1e-6).index, 0u);
}

TEST(Transient, DecayIntoWhiteMeasurementNoiseIsAFloorAtAnyLevel) {
  // e^{-t} sin 2 pi t plus white noise of 1e-3 (1.4e-3 of the largest window RMS: far above the
  // 1e-6 of the rounding floor): the last quarter is white and level, so it is a floor, cut where
  // the window RMS is still 5x the noise's (windows of 2 s; e^{-t}/sqrt 2 = 5e-3 at t = 4.95 s).
  std::mt19937_64 gen(5);
  std::normal_distribution<double> g(0.0, 1e-3);
  std::vector<double> x;
  for (int i = 0; i < 20000; ++i) x.push_back(std::exp(-0.01 * i) * std::sin(2 * M_PI * 0.01 * i) + g(gen));
  const Floor f = detect_floor(make_series_with_step({x}, 0.01), 1e-6);
  EXPECT_TRUE(f.white_noise);
  EXPECT_GE(f.index * 0.01, 4.0);
  EXPECT_LE(f.index * 0.01, 8.0);
  // The largest window RMS is the first's (0-2 s): sqrt(mean of e^{-2t} / 2) = sqrt((1 - e^{-4}) / 8).
  EXPECT_NEAR(f.level, 1e-3 / std::sqrt((1.0 - std::exp(-4.0)) / 8.0), 0.1 * 2.86e-3) << "the last quarter's RMS over the largest";
  EXPECT_NE(describe(f, 1e-6).find("white-noise floor"), std::string::npos);
  EXPECT_EQ(detect_floor(make_series_with_step({x}, 0.01), 0.0).index, 0u);  // 0: never a floor
  // detect_transient reports it and cuts nothing at the start.
  TransientOptions o;
  o.period = 100;
  const auto r = detect_transient(make_series_with_step({x}, 0.01), o);
  EXPECT_EQ(r.floor_index, f.index);
  EXPECT_EQ(r.end_index, 0u);
  EXPECT_NE(r.rule.find("white-noise floor"), std::string::npos) << r.rule;
}

TEST(Transient, NoiseThatHoldsOnlyTheEndOfADecayIsFoundByItsIncrements) {
  // e^{-0.3 t} cos 2 pi t plus white noise of 1e-5 over 40 s: the signal falls below the noise only
  // at t = 38 s, so the last quarter (30-40 s) is signal and noise mixed, its samples correlated at
  // lag 1 (the samples' whiteness rule finds no floor). Its increments are the noise's (the signal
  // moves by ~2 pi dt x 1e-4 per sample): they correlate -1/2, 0, 0 at lags 1-3, and the third
  // differences give the noise's RMS. The floor starts where the window RMS (0.4 s windows) stays
  // within 5x it: sqrt(S^2 + noise^2) = 5 noise at S = 0.707 e^{-0.3 t} = 4.9e-5, t = 31.9 s.
  const double w = 2 * M_PI, zeta = 0.3 / w;  // damped_oscillator: e^{-0.3 t} (cos + 0.05 sin) 2 pi t
  const auto x = mlce::reference::noisy_decay(4000, 0.01, zeta, w, 1e-5);
  const Floor f = detect_floor(make_series_with_step({x}, 0.01), 1e-6);
  EXPECT_TRUE(f.white_noise && f.from_increments);
  EXPECT_NEAR(f.index * 0.01, 31.9, 1.2);
  // The largest window RMS is the first's, 0.707 x sqrt((1 - e^{-0.24}) / 0.24) = 0.667.
  EXPECT_NEAR(f.level, 1e-5 / 0.667, 0.1 * 1.5e-5) << "the noise's RMS over the largest window's";
  EXPECT_NE(describe(f, 1e-6).find("increments white"), std::string::npos) << describe(f, 1e-6);
  // Two channels, cos and sin of the same decay, each with its own noise: every channel's increments
  // are white, and the floor is where the summed window RMS stays within 5x the summed noise's.
  std::mt19937_64 gen(11);
  std::normal_distribution<double> g(0.0, 1e-5);
  std::vector<double> sine;
  for (int i = 0; i < 4000; ++i) sine.push_back(std::exp(-0.003 * i) * std::sin(2 * M_PI * 0.01 * i) + g(gen));
  const Floor both = detect_floor(make_series_with_step({x, sine}, 0.01), 1e-6);
  EXPECT_TRUE(both.from_increments);
  EXPECT_NEAR(both.index * 0.01, f.index * 0.01, 1.2);
  // Without the noise the increments are the smooth signal's (lag-1 correlation ~1): no floor.
  EXPECT_EQ(detect_floor(make_series_with_step({mlce::reference::damped_oscillator(4000, 0.01, zeta, w)}, 0.01), 1e-6).index, 0u);
  // Series whose increments are white but which never decay into them are no floor: white noise
  // itself, and the logistic map (r = 4: uncorrelated samples), with and without noise of 1 %.
  std::vector<double> noise, logistic, noisy_logistic;
  double u = 0.3;
  for (int i = 0; i < 4000; ++i) {
    noise.push_back(g(gen));
    u = 4.0 * u * (1.0 - u);
    logistic.push_back(u);
    noisy_logistic.push_back(u + 1e3 * g(gen));
  }
  for (const auto* y : {&noise, &logistic, &noisy_logistic}) EXPECT_EQ(detect_floor(make_series_with_step({*y}, 1.0), 1e-6).index, 0u);
}

TEST(Transient, NoiseThroughoutIsNoFloorHoweverItsLevelVaries) {
  // White noise at 1 for 30 % of the record, 0.3 to half of it, then 0.03: the last quarter is white
  // and level at 0.03 of the largest RMS, as a decay's floor would be, but the samples kept before it
  // are white too (lag correlations ~1/sqrt(samples)): no motion decays there, so no floor, by either
  // white-noise rule (the samples' and the increments'). So with the noise's level changing smoothly
  // (a rounding noise that scales with the other states' motion), and with two such channels.
  std::mt19937_64 gen(5);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> steps, smooth, other;
  for (int i = 0; i < 4000; ++i) {
    steps.push_back((i < 1200 ? 1.0 : i < 2000 ? 0.3 : 0.03) * g(gen));
    smooth.push_back(std::exp(-0.0015 * std::min(i, 2400)) * g(gen));
    other.push_back(std::exp(-0.0015 * std::min(i, 2400)) * g(gen));
  }
  using Channels = std::vector<std::vector<double>>;
  for (const Channels& channels : {Channels{steps}, Channels{smooth}, Channels{smooth, other}})
    EXPECT_EQ(detect_floor(make_series_with_step(channels, 0.01), 1e-6).index, 0u) << channels.size() << " channel(s)";
  // The same levels carried by a motion (a sine of 25 samples per cycle, amplitude sqrt 2 x the
  // level) and noise of 0.03 from the start: a decay into a white floor, found at the last step.
  std::vector<double> decay;
  for (int i = 0; i < 4000; ++i)
    decay.push_back((i < 1200 ? 1.0 : i < 2000 ? 0.3 : 0.0) * std::sqrt(2.0) * std::sin(2 * M_PI * i / 25.0) + 0.03 * g(gen));
  const Floor f = detect_floor(make_series_with_step({decay}, 0.01), 1e-6);
  EXPECT_TRUE(f.white_noise);
  EXPECT_EQ(f.index, 2000u);
}

TEST(Transient, ThirdDifferenceNoiseEstimateScattersAsItsVarianceFactorSays) {
  // White Gaussian noise of deviation 0.3, k + 3 samples: the mean square white_increment_noise
  // reads from k third differences scatters around 0.09 with relative deviation
  // sqrt(kThirdDifferenceVarianceFactor / k) (their lag correlations -0.75, 0.3, -0.05; independent
  // squares would give sqrt(2 / k), 1.5 x less). 400 draws: the sample deviation is within 15 %.
  for (const std::size_t k : {500u, 4000u}) {
    std::mt19937_64 gen(11);
    std::normal_distribution<double> g(0.0, 0.3);
    double sum = 0.0, square = 0.0;
    int draws = 0;
    for (int draw = 0; draw < 400; ++draw) {
      std::vector<double> x(k + 3);
      for (double& v : x) v = g(gen);
      const auto noise = white_increment_noise(make_series_with_step({x}, 1.0), 0, x.size(), WhitenessTest::third_differences);
      if (!noise) continue;  // the whiteness test refuses a few draws by chance
      const double ratio = noise->deviation[0] * noise->deviation[0] / 0.09;
      sum += ratio, square += ratio * ratio, ++draws;
    }
    ASSERT_GT(draws, 380) << k;
    const double mean = sum / draws, sd = std::sqrt((square - draws * mean * mean) / (draws - 1));
    EXPECT_NEAR(mean, 1.0, 3.0 * std::sqrt(kThirdDifferenceVarianceFactor / static_cast<double>(k) / draws)) << k;
    EXPECT_NEAR(sd / std::sqrt(kThirdDifferenceVarianceFactor / static_cast<double>(k)), 1.0, 0.15) << k;
  }
}

TEST(Transient, SteadyNoiseStretchLeavesOutARaisedStartAndKeepsALowEnd) {
  // White noise of deviation 1 over 8000 samples (8 windows of 1000): all of it is steady. Its first
  // window at 1.25 (mean square 1.56x, as a coarsely sampled decay's leak raises it) is left out;
  // its last window at 0.8 (mean square 0.64x) is no reason to leave out the seven before it, which
  // the rule before this one (each window judged against the mean of those after it) did: the noise
  // was then read from the last 1000 samples alone. A last window low by chance (3.4 standard errors)
  // made it read a two-channel decay's noise 12 % low (EstimateSystems.NoiseOfEachChannelIsCompensated,
  // seed 2). Two channels: the raised window in either is left out.
  std::mt19937_64 gen(2);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> white(8000), raised(8000), low_end(8000);
  for (std::size_t i = 0; i < 8000; ++i) {
    white[i] = g(gen);
    raised[i] = (i < 1000 ? 1.25 : 1.0) * white[i];
    low_end[i] = (i >= 7000 ? 0.8 : 1.0) * white[i];
  }
  EXPECT_EQ(steady_noise_start(make_series_with_step({white}, 0.01)), 0u);
  EXPECT_EQ(steady_noise_start(make_series_with_step({raised}, 0.01)), 1000u);
  EXPECT_EQ(steady_noise_start(make_series_with_step({low_end}, 0.01)), 0u);
  EXPECT_EQ(steady_noise_start(make_series_with_step({low_end, raised}, 0.01)), 1000u);
}

TEST(Transient, SmallMotionsADecaySettlesOnAreNoWhiteFloor) {
  // Settled on a limit cycle of 1e-3 (smooth: lag-1 autocorrelation ~1), or on one sampled at 4 and
  // at 3 samples per cycle (lag 1 correlation 0 and -0.5, but lag 2 -1, lag 3 +1): motions, not noise.
  for (const double cycle : {100.0, 4.0, 3.0}) {
    std::vector<double> x;
    for (int i = 0; i < 20000; ++i)
      x.push_back((std::exp(-0.01 * i) + 1e-3) * std::sin(2 * M_PI * i / cycle + 0.3));
    EXPECT_EQ(detect_floor(make_series_with_step({x}, 0.01), 1e-6).index, 0u) << cycle << " samples per cycle";
  }
  // A decay still falling through its last quarter is no floor either, however white its samples
  // (2.1 samples per cycle, noise-free: its halves' RMS differ by e^{0.5 x 25} ~ 2.7e5).
  std::vector<double> y;
  for (int i = 0; i < 20000; ++i) y.push_back(std::exp(-0.002 * i) * std::sin(2 * M_PI * i / 2.1));
  const Floor f = detect_floor(make_series_with_step({y}, 0.01), 1e-6);
  EXPECT_FALSE(f.white_noise && f.index > 0) << f.index;
}

TEST(Transient, PureDecayIsNotCut) {
  std::vector<double> x;
  for (int i = 0; i < 20000; ++i) x.push_back(std::exp(-0.02 * i * 0.01) * std::sin(2 * M_PI * 0.01 * i));
  TransientOptions o;
  o.period = 100;
  const auto r = detect_transient(make_series_with_step({x}, 0.01), o);
  EXPECT_FALSE(r.settled);
  EXPECT_EQ(r.end_index, 0u);
}

TEST(Envelope, RateOfADecayingOscillationIsItsExponent) {
  // x = e^{-zeta omega t} cos(omega_d t): the envelope's rate is -zeta omega exactly, per sample -zeta omega dt.
  const double dt = 0.01, zeta = 0.05, omega = 2 * M_PI;
  const auto x = reference::damped_oscillator(4000, dt, zeta, omega);
  EXPECT_NEAR(envelope_rates(make_series_with_step({x}, dt), 100).whole, -zeta * omega * dt, 0.01 * zeta * omega * dt);
  // Its scale does not matter (no square of 1e200 overflows, none of 1e-200 underflows).
  for (double scale : {1e-200, 1e200}) {
    auto y = x;
    for (double& v : y) v *= scale;
    EXPECT_NEAR(envelope_rates(make_series_with_step({y}, dt), 100).whole, -zeta * omega * dt, 0.01 * zeta * omega * dt);
  }
}

TEST(Envelope, EndRateIsTheSecondHalfsRate) {
  // A growth that settles: amplitude e^{0.3 t} up to t = 10 s, then constant to t = 40 s (1 Hz, dt
  // 0.01). Over the second half the rate is 0 exactly; over the whole record it is the least-squares
  // slope of 0.3 min(t, 10) over the 40 one-second windows' centres, 0.0469 1/s. A free growth
  // e^{0.3 t}: 0.3 over both. Per sample: x dt.
  const double dt = 0.01;
  std::vector<double> settles(4000), grows(4000);
  for (std::size_t i = 0; i < settles.size(); ++i) {
    const double t = dt * static_cast<double>(i), phase = std::cos(2.0 * M_PI * t);
    settles[i] = std::exp(0.3 * std::min(t, 10.0)) * phase;
    grows[i] = std::exp(0.3 * t) * phase;
  }
  const EnvelopeRates s = envelope_rates(make_series_with_step({settles}, dt), 50);
  EXPECT_NEAR(s.whole / dt, 0.046857, 1e-3);  // the window RMS of a cosine under e^{0.3 t}: within 1e-3
  EXPECT_NEAR(s.end / dt, 0.0, 1e-9);
  const EnvelopeRates g = envelope_rates(make_series_with_step({grows}, dt), 50);
  EXPECT_NEAR(g.whole / dt, 0.3, 1e-3);
  EXPECT_NEAR(g.end / dt, 0.3, 1e-3);
  // Fewer than 4 windows in the second half: NaN there, the whole rate still known.
  const EnvelopeRates few = envelope_rates(make_series_with_step({grows}, dt), 350);  // 5 windows of 700
  EXPECT_TRUE(std::isfinite(few.whole));
  EXPECT_TRUE(std::isnan(few.end));
}

TEST(Envelope, StandardErrorOfTheRateIsTheTextbookOnesOverTheWindows) {
  // Brute force: the RMS of each window of 2 x period samples about its own mean, ln of it against the
  // window's centre, and the least-squares slope's standard error sqrt(SSR / (n - 2) / Sxx), in long
  // double. On white noise (a wander, no trend: |slope| within a few standard errors) and on a decay
  // (slope far beyond them).
  auto brute = [](const std::vector<double>& x, std::size_t period) {
    const std::size_t w = 2 * period, n = x.size() / w;
    std::vector<long double> c(n), y(n);
    for (std::size_t k = 0; k < n; ++k) {
      long double mean = 0, ss = 0;
      for (std::size_t i = k * w; i < (k + 1) * w; ++i) mean += x[i];
      mean /= w;
      for (std::size_t i = k * w; i < (k + 1) * w; ++i) ss += (x[i] - mean) * (x[i] - mean);
      c[k] = (k + 0.5L) * w, y[k] = 0.5L * std::log(ss / w);
    }
    long double mc = 0, my = 0, sxx = 0, sxy = 0, ssr = 0;
    for (std::size_t k = 0; k < n; ++k) mc += c[k] / n, my += y[k] / n;
    for (std::size_t k = 0; k < n; ++k) sxx += (c[k] - mc) * (c[k] - mc), sxy += (c[k] - mc) * (y[k] - my);
    const long double slope = sxy / sxx;
    for (std::size_t k = 0; k < n; ++k) ssr += (y[k] - my - slope * (c[k] - mc)) * (y[k] - my - slope * (c[k] - mc));
    return std::pair<double, double>{static_cast<double>(slope), static_cast<double>(std::sqrt(ssr / (n - 2) / sxx))};
  };
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> noise(6000);
  for (double& v : noise) v = g(rng);
  const auto decay = reference::damped_oscillator(6000, 0.01, 0.05, 2 * M_PI);
  const std::vector<double>& wandering = noise;
  for (const std::vector<double>* x : {&wandering, &decay}) {
    const auto [slope, stderr_] = brute(*x, 100);
    const EnvelopeRates r = envelope_rates(make_series_with_step({*x}, 0.01), 100);
    EXPECT_NEAR(r.whole, slope, 1e-9 * std::abs(slope) + 1e-15);
    EXPECT_NEAR(r.whole_stderr, stderr_, 1e-6 * stderr_ + 1e-15);
  }
  const EnvelopeRates wander = envelope_rates(make_series_with_step({noise}, 0.01), 100);
  EXPECT_LT(std::abs(wander.whole), 4.0 * wander.whole_stderr);
  const EnvelopeRates falls = envelope_rates(make_series_with_step({decay}, 0.01), 100);
  EXPECT_LT(falls.whole, -100.0 * falls.whole_stderr);
  EXPECT_TRUE(std::isnan(envelope_rates(make_series_with_step({noise}, 0.01), 1000).whole_stderr));  // 3 windows
}

TEST(Envelope, AmplitudeRatioOfTheLastThirdToTheFirst) {
  // Brute force: the RMS of the last third over that of the first, both about the whole series'
  // mean, summed directly in long double (the library scales by the peak and sums in windows).
  auto brute = [](const std::vector<double>& x) {
    const std::size_t w = x.size() / 3;
    long double mean = 0, first = 0, last = 0;
    for (std::size_t i = 0; i < 3 * w; ++i) mean += x[i];
    mean /= 3 * w;
    for (std::size_t i = 0; i < w; ++i) first += (x[i] - mean) * (x[i] - mean);
    for (std::size_t i = 2 * w; i < 3 * w; ++i) last += (x[i] - mean) * (x[i] - mean);
    return static_cast<double>(std::sqrt(last / first));
  };
  // A decay of e^{-zeta omega 20 s} ~ 1.9e-3 from the first third to the last; its mean (~1e-3 of
  // the start) weighs on the last third's tiny RMS.
  const double dt = 0.01, zeta = 0.05, omega = 2 * M_PI;
  const auto x = reference::damped_oscillator(3000, dt, zeta, omega);
  for (double scale : {1.0, 1e-200, 1e200}) {
    auto y = x;
    for (double& v : y) v *= scale;
    EXPECT_NEAR(amplitude_ratio(make_series_with_step({y}, dt)), brute(x), 1e-9 * brute(x)) << scale;
  }
  EXPECT_LT(amplitude_ratio(make_series_with_step({x}, dt)), 1.0 / kPersistentAmplitude);  // a decay, not refused
  // Growth: the same decay reversed in time.
  const std::vector<double> grow(x.rbegin(), x.rend());
  EXPECT_NEAR(amplitude_ratio(make_series_with_step({grow}, dt)), brute(grow), 1e-9 * brute(grow));
  EXPECT_GT(amplitude_ratio(make_series_with_step({grow}, dt)), kPersistentAmplitude);
  // A steady sine about an offset, whole cycles per third: exactly 1.
  std::vector<double> sine(3000);
  for (std::size_t i = 0; i < sine.size(); ++i) sine[i] = 2.0 + std::sin(omega * dt * static_cast<double>(i));
  EXPECT_NEAR(amplitude_ratio(make_series_with_step({sine}, dt)), 1.0, 1e-9);
  EXPECT_TRUE(std::isnan(amplitude_ratio(make_series_with_step({std::vector<double>(300, 3.0)}, dt))));
}

TEST(Envelope, SteadyMotionHasRateZeroAndTooShortOrConstantIsNaN) {
  const auto lc = reference::van_der_pol_x(20000, 0.01);  // limit cycle, period ~6.66 s = 666 samples
  EXPECT_NEAR(envelope_rates(make_series_with_step({lc}, 0.01), 666).whole, 0.0, 1e-6);
  const std::vector<double> flat(1000, 3.0);
  EXPECT_TRUE(std::isnan(envelope_rates(make_series_with_step({flat}, 0.01), 10).whole));  // no log 0
  EXPECT_TRUE(std::isnan(envelope_rates(make_series_with_step({lc}, 0.01), 3000).whole));   // 3 windows
}

TEST(Envelope, EndsRateIsTheChangeBetweenTheFirstAndLastWholePeriods) {
  // e^{0.005 t} sin t over 30 s (4.8 periods, dt = 0.01): the amplitude grows at 0.005 1/s exactly.
  // Between whole periods at the ends (one period each: a third holds 1.6) that is what the windows'
  // RMS say, to the O(sigma / omega) the growth within a window adds to its phase dependence. The
  // thirds cut their periods short and weigh the phases unevenly: their RMS ratio, 1.17, says
  // 0.0079 1/s over the 20 s between their centres.
  const double dt = 0.01, sigma = 0.005, two_pi = 2.0 * std::numbers::pi;
  std::vector<double> grows(3000), steady(3000);
  for (std::size_t i = 0; i < grows.size(); ++i) {
    const double t = dt * static_cast<double>(i);
    grows[i] = std::exp(sigma * t) * std::sin(t);
    steady[i] = 1.0 + std::sin(t);  // about an offset
  }
  const double period = two_pi / dt;  // 628.3 samples
  const Series g = make_series_with_step({grows}, dt);
  EXPECT_NEAR(ends_amplitude_rate(g, period) / dt, sigma, 0.02 * sigma);
  const double thirds_rate = std::log(amplitude_ratio(g)) / 20.0;  // the control
  std::printf("e^{0.005 t} sin t over 4.8 periods: whole periods %.5f 1/s, thirds %.5f 1/s (ratio %.3f)\n",
              ends_amplitude_rate(g, period) / dt, thirds_rate, amplitude_ratio(g));
  EXPECT_GT(std::abs(thirds_rate - sigma), 0.5 * sigma);
  // A steady sine about an offset: 0 (windows of 628.3 samples: the 629th weighted by 0.3).
  EXPECT_NEAR(ends_amplitude_rate(make_series_with_step({steady}, dt), period) * period, 0.0, 1e-5);
  // Scale-free (each channel over its peak first).
  for (const double scale : {1e-200, 1e200}) {
    std::vector<double> y = grows;
    for (double& v : y) v *= scale;
    EXPECT_NEAR(ends_amplitude_rate(make_series_with_step({y}, dt), period), ends_amplitude_rate(g, period), 1e-12);
  }
  // Nothing to tell: two windows do not fit (a period over half the run), no period, a constant.
  EXPECT_TRUE(std::isnan(ends_amplitude_rate(g, 1600.0)));
  EXPECT_TRUE(std::isnan(ends_amplitude_rate(g, 0.0)));
  EXPECT_TRUE(std::isnan(ends_amplitude_rate(g, std::numeric_limits<double>::infinity())));
  EXPECT_TRUE(std::isnan(ends_amplitude_rate(make_series_with_step({std::vector<double>(300, 3.0)}, dt), 50.0)));
}

TEST(Envelope, WholeRecordRepeatFindsTheFundamentalOfAShortLimitCycle) {
  // van der Pol (mu = 1) over 15 s, 2.25 periods of 6.6633 s (its published period): the record
  // repeats itself at the period, 666.3 samples, where the spectrum's mean period is 4 % shorter
  // (the cycle's harmonics raise its mean frequency). Whole periods of the repeat leave its
  // amplitude steady, rate below 1e-4 per period; windows of the mean period read 0.034 per period,
  // beyond the reading's neutral band (0.01).
  const double dt = 0.01;
  const Series lc = make_series_with_step({reference::van_der_pol_x(1500, dt)}, dt);
  const EndRepeat whole = whole_record_repeat(lc);
  EXPECT_NEAR(whole.period, 666.33, 1.0);
  EXPECT_LT(whole.difference, 0.01);
  EXPECT_LT(std::abs(ends_amplitude_rate(lc, whole.period) * whole.period), 1e-4);
  const double mean_period = 1.0 / estimate_mean_period(lc, {}).mean_frequency_per_sample;
  std::printf("van der Pol over 2.25 periods: repeats every %.2f samples, mean period %.2f (%.1f %% short); "
              "rate per period over whole repeats %.2g, over whole mean periods %.3f\n",
              whole.period, mean_period, 100.0 * (1.0 - mean_period / whole.period),
              ends_amplitude_rate(lc, whole.period) * whole.period, ends_amplitude_rate(lc, mean_period) * whole.period);
  EXPECT_LT(mean_period, 0.97 * whole.period);
  EXPECT_GT(std::abs(ends_amplitude_rate(lc, mean_period) * whole.period), 0.01);
  EXPECT_TRUE(std::isnan(whole_record_repeat(make_series_with_step({std::vector<double>(10, 1.0)}, dt)).period));
}

TEST(Envelope, ScaledRepeatTellsOneModeFromTwo) {
  // e^{sigma t} sin(omega t) one period P on is e^{sigma P} times itself: scale e^{sigma P} and no
  // rest but the linear interpolation's (P = 2 pi / 0.01 = 628.3 samples, between two samples).
  const double dt = 0.01, sigma = -0.02, two_pi = 2.0 * std::numbers::pi, period = two_pi / dt;
  std::vector<double> mode(2000), tones(2000);
  for (std::size_t i = 0; i < mode.size(); ++i) {
    const double t = dt * static_cast<double>(i);
    mode[i] = std::exp(sigma * t) * std::sin(t);
    tones[i] = std::sin(t) + 0.5 * std::sin(std::sqrt(2.0) * t + 0.3);  // a torus: two unrelated tones
  }
  const ScaledRepeat one = scaled_repeat(make_series_with_step({mode}, dt), period);
  EXPECT_NEAR(one.scale, std::exp(sigma * two_pi), 1e-4);
  EXPECT_LT(one.difference, 1e-3);
  // Two tones repeat at no lag: over the first tone's period a third of the signal or more is left,
  // and over the best of the lags 100 .. 1000 samples (in half samples) more than a tenth.
  const Series two = make_series_with_step({tones}, dt);
  EXPECT_GT(scaled_repeat(two, period).difference, 0.3);
  double best = 1.0;
  for (int half_samples = 200; half_samples <= 2000; ++half_samples)
    best = std::min(best, scaled_repeat(two, 0.5 * half_samples).difference);
  EXPECT_GT(best, 0.1);
  // A limit cycle: scale 1.
  const Series lc = make_series_with_step({reference::van_der_pol_x(1500, dt)}, dt);
  EXPECT_NEAR(scaled_repeat(lc, whole_record_repeat(lc).period).scale, 1.0, 1e-3);
  // Nothing to tell: a lag over half the record, no lag, a constant.
  EXPECT_TRUE(std::isnan(scaled_repeat(make_series_with_step({mode}, dt), 1001.0).difference));
  EXPECT_TRUE(std::isnan(scaled_repeat(make_series_with_step({mode}, dt), 0.0).difference));
  EXPECT_TRUE(std::isnan(scaled_repeat(make_series_with_step({std::vector<double>(300, 3.0)}, dt), 50.0).difference));
}

TEST(WrappedAngle, AzimuthPrintedModuloATurnIsFoundAndSmoothOrMapSignalsAreNot) {
  // A blade's azimuth at 4 rev/s with a lag wobble, sampled at 5 ms for 2 s, as MBDyn prints an
  // Euler angle (degrees in (-180, 180]) and as a rotation vector's angle (radians).
  std::vector<double> deg, rad, unwrapped;
  for (int i = 0; i < 400; ++i) {
    const double t = 0.005 * i, a = 360.0 * 4.0 * t + 5.0 * std::sin(2.0 * std::numbers::pi * 1.3 * t) + 30.0;
    unwrapped.push_back(a);
    deg.push_back(std::remainder(a, 360.0));
    rad.push_back(std::remainder(a * std::numbers::pi / 180.0, 2.0 * std::numbers::pi));
  }
  const auto d = wrapped_angle(make_series_with_step({deg}, 0.005));
  EXPECT_EQ(d.count, 8u);  // 30 + 2880 deg: passes +180 eight times
  EXPECT_TRUE(d.degrees);
  EXPECT_NEAR(d.jump, -360.0 + 7.2, 0.5);  // a turn back, less the 7.2 deg of one step
  EXPECT_NEAR(deg[d.sample - 1], 180.0, 10.0);
  const auto r = wrapped_angle(make_series_with_step({unwrapped, rad}, 0.005));
  EXPECT_EQ(r.count, 8u);
  EXPECT_EQ(r.channel, 1u);
  EXPECT_FALSE(r.degrees);
  // Never: the unwrapped azimuth, Lorenz x, Henon x (every step large), a sine of amplitude 180.
  std::vector<double> sine;
  for (int i = 0; i < 1000; ++i) sine.push_back(180.0 * std::sin(0.05 * i));
  for (const auto& x : {unwrapped, reference::lorenz_x(5000), reference::henon_x(5000), sine})
    EXPECT_EQ(wrapped_angle(make_series_with_step({x}, 0.01)).count, 0u);
}

// Isolated spikes (find_isolated_spikes): a glitch of one to three samples, told from motion by its
// two jumps standing alone. Truth: where the glitch was written, and brute-force jump ratios.
namespace {
using namespace mlce::reference;

Series one_channel(std::vector<double> x, double dt = 0.01) { return make_series_with_step({std::move(x)}, dt); }

/// The largest |x[i+1] - x[i]| over jumps that neither enter nor leave samples first..last.
double largest_other_jump(const std::vector<double>& x, std::size_t first, std::size_t last) {
  double largest = 0.0;
  for (std::size_t i = 0; i + 1 < x.size(); ++i)
    if (i + 1 < first || i > last) largest = std::max(largest, std::abs(x[i + 1] - x[i]));
  return largest;
}
}  // namespace

TEST(Spikes, AGlitchInsideAFlowsRangeIsFoundByItsJumps) {
  std::vector<double> x = lorenz_x(10000);
  x[5000] = 10.0;  // inside x's range (-18 .. 19): only its two jumps give it away
  const auto spikes = find_isolated_spikes(one_channel(x));
  ASSERT_EQ(spikes.size(), 1u);
  const IsolatedSpike& s = spikes.front();
  EXPECT_EQ(s.channel, 0u);
  EXPECT_EQ(s.first, 5000u);
  EXPECT_EQ(s.last, 5000u);
  EXPECT_EQ(s.peak, 10.0);
  EXPECT_EQ(s.before, x[4999]);
  EXPECT_EQ(s.after, x[5001]);
  const double ratio = std::min(std::abs(x[5000] - x[4999]), std::abs(x[5001] - x[5000])) / largest_other_jump(x, 5000, 5000);
  EXPECT_GT(ratio, SpikeOptions{}.jump_ratio);
  EXPECT_NEAR(s.jump_ratio, ratio, 1e-12 * ratio);
}

TEST(Spikes, SeveralSpikesOfUpToThreeSamplesInEveryChannel) {
  std::vector<double> x = lorenz_x(10000), y = lorenz_x(10000, 0.01, {2.0, -1.0, 20.0});
  x[3000] = 40.0, x[3001] = -30.0, x[3002] = 35.0;
  x[7000] = -60.0;
  y[100] = 1e6;
  const auto spikes = find_isolated_spikes(make_series_with_step({x, y}, 0.01));
  ASSERT_EQ(spikes.size(), 3u);
  EXPECT_EQ(spikes[0].first, 3000u);
  EXPECT_EQ(spikes[0].last, 3002u);
  double farthest = -1.0, peak = 0.0;  // the run's sample farthest from the line across it
  for (std::size_t i = 3000; i <= 3002; ++i) {
    const double off = std::abs(x[i] - (x[2999] + (x[3003] - x[2999]) * static_cast<double>(i - 2999) / 4.0));
    if (off > farthest) farthest = off, peak = x[i];
  }
  EXPECT_EQ(spikes[0].peak, peak);
  EXPECT_EQ(spikes[1].first, 7000u);
  EXPECT_EQ(spikes[1].last, 7000u);
  EXPECT_EQ(spikes[2].channel, 1u);
  EXPECT_EQ(spikes[2].first, 100u);
}

TEST(Spikes, MotionHasNone) {
  std::vector<std::pair<std::string, std::vector<double>>> motions = {
      {"Lorenz x", lorenz_x(10000)},
      {"Roessler x", roessler_x(10000)},
      {"Henon x", henon_x(10000)},
      {"logistic", logistic(10000)},
      {"van der Pol", van_der_pol_x(10000)},
      {"relaxation oscillation (van der Pol mu = 10, dt = 0.05)", van_der_pol_x(4000, 0.05, 10.0)},
      {"damped oscillator", damped_oscillator(2000, 0.01, 0.05, 2.0 * std::numbers::pi)},
      {"noisy decay", noisy_decay(2000, 0.01, 0.05, 2.0 * std::numbers::pi, 0.01)},
      {"logistic r = 2.8 approaching its fixed point", logistic(500, 0.01, 2.8)},
  };
  std::vector<double> quantised, step, start_up, impacts;
  for (int i = 0; i < 5000; ++i) {
    const double t = 0.01 * i;
    quantised.push_back(std::round(100.0 * std::sin(t)) / 100.0);  // a coarsely written sine: jumps of 0 or 0.01
    step.push_back(std::sin(t) + (i >= 2500 ? 50.0 : 0.0));          // one jump that does not come back
    start_up.push_back(35.0 * std::sin(t));
    impacts.push_back(std::sin(t) + (i % 1000 == 500 ? 10.0 : 0.0));  // five one-sample impacts: a feature
  }
  start_up[1] = -6036.0, start_up[2] = 1649.0, start_up[3] = -276.0;  // an MBDyn joint reaction's start-up
  motions.push_back({"quantised sine", quantised});
  motions.push_back({"step", step});
  motions.push_back({"solver start-up ringing", start_up});
  motions.push_back({"five impacts", impacts});
  for (const auto& [name, x] : motions) EXPECT_TRUE(find_isolated_spikes(one_channel(x)).empty()) << name;
}

TEST(Spikes, FoundAtTheEndsOfTheDoubleRange) {
  std::vector<double> x = lorenz_x(4000);
  x[2000] = 100.0;
  for (const double scale : {1e-300, 1e300}) {
    std::vector<double> y = x;
    for (double& v : y) v *= scale;
    const auto spikes = find_isolated_spikes(one_channel(y));
    ASSERT_EQ(spikes.size(), 1u) << scale;
    EXPECT_EQ(spikes.front().first, 2000u) << scale;
  }
  // A glitch at the largest double in a series of order 1: no jump overflows.
  std::vector<double> z = lorenz_x(4000);
  z[2000] = std::numeric_limits<double>::max();
  z[2500] = -std::numeric_limits<double>::max();
  Series s = one_channel(z);
  ASSERT_EQ(find_isolated_spikes(s).size(), 2u);
  replace_isolated_spikes(s);
  for (const double v : s.channels[0]) ASSERT_TRUE(std::isfinite(v));
  EXPECT_NEAR(s.channels[0][2000], 0.5 * (z[1999] + z[2001]), 1e-12);
}

TEST(Spikes, ReplacedByTheLineBetweenTheirNeighbours) {
  std::vector<double> x = lorenz_x(10000);
  const std::vector<double> clean = x;
  x[6000] = 70.0, x[6001] = 90.0;
  Series s = one_channel(x);
  const auto messages = replace_isolated_spikes(s);
  ASSERT_EQ(messages.size(), 1u);
  EXPECT_NE(messages.front().find("samples 6000..6001 (t = 60 .. 60.01 s) was an isolated spike (90 between"),
            std::string::npos) << messages.front();
  EXPECT_NEAR(s.channels[0][6000], x[5999] + (x[6002] - x[5999]) / 3.0, 1e-12);
  EXPECT_NEAR(s.channels[0][6001], x[5999] + 2.0 * (x[6002] - x[5999]) / 3.0, 1e-12);
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (i != 6000 && i != 6001) {
      ASSERT_EQ(s.channels[0][i], x[i]) << i;
    }
  }
  EXPECT_TRUE(find_isolated_spikes(s).empty());
  // Over 0.02 time units the line is the flow to within its curvature: 1e-2 of x's range.
  EXPECT_NEAR(s.channels[0][6000], clean[6000], 0.2);
}

TEST(Spikes, RefusalNamesTheSampleAndLeavesThoseBeforeTheWindow) {
  std::vector<double> x = lorenz_x(10000);
  x[5000] = 25.0;
  x[8000] = -50.0;
  const Series s = one_channel(x);
  try {
    refuse_isolated_spikes(s);
    FAIL();
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.index(), 5000u);
    EXPECT_NE(what.find("channel 1: sample 5000 (t = 50 s) is an isolated spike: 25 between"), std::string::npos) << what;
    EXPECT_NE(what.find("1 more: channel 1 sample 8000 (t = 80 s)"), std::string::npos) << what;
    EXPECT_NE(what.find("--despike"), std::string::npos) << what;
  }
  try {
    refuse_isolated_spikes(s, {}, 5001);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.index(), 8000u);
  }
  EXPECT_NO_THROW(refuse_isolated_spikes(s, {}, 8001));
}

TEST(Spikes, OptionsAndSamplesAreChecked) {
  std::vector<double> with_nan = lorenz_x(1000);
  with_nan[500] = std::numeric_limits<double>::quiet_NaN();  // the jumps' ranking would have no order
  EXPECT_THROW(find_isolated_spikes(one_channel(with_nan)), InputError);
  const Series s = one_channel(lorenz_x(1000));
  for (const double ratio : {1.0, 0.5, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    SpikeOptions o;
    o.jump_ratio = ratio;
    EXPECT_THROW(find_isolated_spikes(s, o), OptionError) << ratio;
  }
  SpikeOptions o;
  o.max_length = 0;
  EXPECT_THROW(find_isolated_spikes(s, o), OptionError);
  o = {};
  o.max_count = 0;
  EXPECT_THROW(find_isolated_spikes(s, o), OptionError);
}
