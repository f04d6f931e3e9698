// End-to-end: every parameter automatic, against the known exponents of reference systems.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include "mlce/estimate.hpp"
#include "mlce/reading.hpp"
#include "mlce/recurrence.hpp"
#include "mlce/transient.hpp"
#include "mlce/reader/channel_spec.hpp"
#include "mlce/reader/mbdyn_text.hpp"
#include "reference_systems.hpp"
#include "result_checks.hpp"

using namespace mlce;

namespace {
MlceResult run(const std::vector<double>& x, double dt) { return estimate_mlce(make_series_with_step({x}, dt), {}); }

/// Population standard deviation (the truth a noise level is measured against).
double standard_deviation(const std::vector<double>& v) {
  double m = 0, s = 0;
  for (double a : v) m += a / static_cast<double>(v.size());
  for (double a : v) s += (a - m) * (a - m);
  return std::sqrt(s / static_cast<double>(v.size()));
}

/// `clean` plus white Gaussian noise of `level` x its standard deviation (mt19937_64 seeded with
/// `seed`), and that noise's standard deviation over the noisy series' own: the truth a noise
/// estimate is held to.
struct Noisy {
  std::vector<double> x;
  double share = 0.0;
};
Noisy with_noise(const std::vector<double>& clean, double level, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> g(0.0, level * standard_deviation(clean));
  std::vector<double> noise(clean.size()), x(clean.size());
  for (std::size_t i = 0; i < x.size(); ++i) noise[i] = g(gen), x[i] = clean[i] + noise[i];
  return {x, standard_deviation(noise) / standard_deviation(x)};
}

using mlce::testing::has_warning;

/// A deterministic series on its attractor: its curve is neither flagged as noise-dominated nor
/// as unresolved, and its start recurs.
void expect_clean(const MlceResult& r) {
  EXPECT_EQ(r.skipped_start, 0u);
  EXPECT_TRUE(std::isnan(r.noise_level)) << r.noise_level;
  EXPECT_FALSE(has_warning(r, "measurement noise")) << r.fit.rule;
  EXPECT_FALSE(has_warning(r, "divergence not resolved")) << r.fit.rule;
  EXPECT_FALSE(has_warning(r, "drifts"));
  EXPECT_FALSE(has_warning(r, "the embedding window")) << r.dim << " x " << r.delay;
}
}  // namespace

/// lambda / known on `count` series of one system from pseudo-random initial states (seed fixed,
/// independent of the seeds bench/finite_time_spread studies).
template <class Make>
std::vector<double> ratios_over_initial_states(Make make, double dt, double known, int count) {
  std::mt19937 gen(20261121);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<double> out;
  for (int k = 0; k < count; ++k) {
    const std::array<double, 3> x0{u(gen), u(gen), std::abs(u(gen))};
    const auto r = run(make(x0), dt);
    out.push_back(r.lambda / known);
  }
  return out;
}

int count_within(const std::vector<double>& ratios, double tolerance) {
  return static_cast<int>(std::count_if(ratios.begin(), ratios.end(), [&](double q) { return std::abs(q - 1) <= tolerance; }));
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return 0.5 * (v[(v.size() - 1) / 2] + v[v.size() / 2]);
}

std::string listed(const std::vector<double>& v) {
  std::string s;
  for (double q : v) s += std::to_string(q).substr(0, 5) + " ";
  return s;
}

// Issue 2 asks Lorenz x (N = 1e4, dt = 0.01) within 5 %. One series is one draw: the slope of
// Rosenstein's curve scatters by several per cent from series to series even in the true state
// space (bench/finite_time_spread), so the check is on 16 series from random initial states.
TEST(EstimateSystems, LorenzWithinFivePercentOnMostSeries) {
  const auto q = ratios_over_initial_states(
      [](std::array<double, 3> x0) { x0[2] += 20.0; return reference::lorenz_x(10000, 0.01, x0); }, 0.01, 0.9056, 16);
  std::printf("Lorenz lambda / 0.9056 on 16 series: %s\n", listed(q).c_str());
  EXPECT_GE(count_within(q, 0.05), 12) << listed(q);
  EXPECT_GE(count_within(q, 0.10), 15) << listed(q);
  EXPECT_NEAR(median(q), 1.0, 0.03) << listed(q);
}

TEST(EstimateSystems, LorenzCanonicalSeries) {
  const auto r = run(reference::lorenz_x(10000, 0.01), 0.01);
  EXPECT_NEAR(r.lambda, 0.9056, 0.06 * 0.9056) << r.fit.rule;
  EXPECT_EQ(r.dim, 3u);
  EXPECT_GT(r.r2, 0.98);
  expect_clean(r);
}

TEST(EstimateSystems, EmbeddingWindowOfSeveralMeanPeriodsIsFlagged) {
  // The automatic embedding of Lorenz x spans (3 - 1) x 18 = 36 samples of its 171-sample mean
  // period (expect_clean above). A given m = 30 spans 29 x 18 = 522 samples, about 3 mean periods:
  // flagged; m = 10 (162 samples, under two periods) is not.
  const Series s = make_series_with_step({reference::lorenz_x(10000, 0.01)}, 0.01);
  MlceOptions o;
  o.dim = 30;
  const auto wide = estimate_mlce(s, o);
  ASSERT_TRUE(has_warning(wide, "the embedding window (m-1)*delay = 522 samples spans 3.")) << wide.warnings.size();
  o.dim = 10;
  EXPECT_FALSE(has_warning(estimate_mlce(s, o), "the embedding window"));
}

TEST(EstimateSystems, LorenzYWhoseStartUpOutlastsTheNextPieceIsNotFitted) {
  // Lorenz y (another observable of the same attractor) from this start: the curve's start-up
  // (0..68 steps, 2.7 lambda_1) is longer than the next piece, and the pieces after it were not all
  // merged, so the start-up was fitted and read 2.74 lambda_1
  // (mechanism: Fit.PiecesMergedIntoANeighbourWithinToleranceAreComparedWithTheOneBeforeToo).
  const auto r = run(reference::lorenz(10000, 0.01, {2.6510216876562538, -0.72118025867994362, 0.52584013447027067}, 50.0, 1), 0.01);
  EXPECT_NEAR(r.lambda, 0.9056, 0.10 * 0.9056) << r.fit.rule;
  EXPECT_GT(r.fit.first, 60u) << r.fit.rule;
}

// The whole state of a run (several channels, embedded jointly): Lorenz (x, y, z) from five starts
// of bench/finite_time_spread "channels" (mt19937(1): the 4th, 9th, 15th, 18th and 28th). Their
// curves start up over ~50 steps at ~3 lambda_1, shorter than the mean period (z's, ~75 samples),
// then bend within ~40 steps into a straight stretch; the bend was taken for the one into the
// plateau, and the start-up was fitted: 3.03, 2.84, 2.93, 3.01 and 2.45 lambda_1.
TEST(EstimateSystems, LorenzStateEmbeddedJointlyIsNotReadFromItsStartUp) {
  const std::array<std::array<double, 3>, 5> starts{{{2.077865510069044, -1.1203589214675205, 0.049096325731472788},
                                                      {2.190121473106168, 1.9748814653995534, 0.6592067294218783},
                                                      {-0.32319299558115588, -1.6672527085208158, 0.85327165149933382},
                                                      {2.5011680070480828, 2.4626902791833896, 0.40213977812531104},
                                                      {0.88649637572048956, -0.87636544823049212, 0.5264661146089894}}};
  for (const auto& x0 : starts) {
    std::vector<std::vector<double>> state;
    for (std::size_t c = 0; c < 3; ++c) state.push_back(reference::lorenz(10000, 0.01, x0, 50.0, c));
    const auto r = estimate_mlce(make_series_with_step(std::move(state), 0.01), {});
    EXPECT_NEAR(r.lambda, 0.9056, 0.25 * 0.9056) << r.fit.rule;
    EXPECT_GT(r.fit.first, r.mean_period.mean_period / 2) << r.fit.rule;  // past the start-up
  }
}

// The state (x, y, z) of Lorenz embedded jointly, from 8 random starts: the fit rule's period is the
// median channel's (y's), not eq. 19's fastest (z's, at twice x's frequency by the attractor's
// symmetry), whose short region kept to the curve's steep start (bench/finite_time_spread channels:
// 12 / 19 of 32 within 5 / 10 %, mean 1.087; now 25 / 31, mean 1.014). The Theiler window stays z's.
TEST(EstimateSystems, LorenzStateEmbeddedJointlyIsFittedOverItsTypicalChannelsPeriod) {
  std::mt19937 gen(20261128);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<double> q, q_fastest;
  for (int k = 0; k < 8; ++k) {
    const std::array<double, 3> x0{u(gen), u(gen), 20.0 + u(gen)};
    std::vector<std::vector<double>> state;
    for (std::size_t c = 0; c < 3; ++c) state.push_back(reference::lorenz(10000, 0.01, x0, 50.0, c));
    const Series s = make_series_with_step(std::move(state), 0.01);
    const auto r = estimate_mlce(s, {});
    q.push_back(r.lambda / 0.9056);
    MlceOptions fastest;  // the rule before: eq. 19's period for the fit too
    fastest.fit.period = r.mean_period.mean_period;
    q_fastest.push_back(estimate_mlce(s, fastest).lambda / 0.9056);
    std::vector<double> periods;
    for (double f : r.mean_period.channel_frequency) periods.push_back(1.0 / (f * 0.01));
    std::sort(periods.begin(), periods.end());
    EXPECT_EQ(r.theiler, r.mean_period.mean_period);
    EXPECT_LE(static_cast<double>(r.theiler), periods.front() + 1.0);  // eq. 19: the fastest channel
    EXPECT_GT(periods[1], 1.5 * periods.front());                      // z's period is the short one
  }
  double mean = 0.0, mean_fastest = 0.0;
  for (std::size_t k = 0; k < q.size(); ++k)
    mean += q[k] / static_cast<double>(q.size()), mean_fastest += q_fastest[k] / static_cast<double>(q.size());
  std::printf("Lorenz (x, y, z) jointly, lambda / 0.9056 on 8 series: %s(mean %.3f); with eq. 19's period for the fit: "
              "%s(mean %.3f, %d within 10 %%)\n",
              listed(q).c_str(), mean, listed(q_fastest).c_str(), mean_fastest, count_within(q_fastest, 0.10));
  EXPECT_GE(count_within(q, 0.10), 7) << listed(q);
  EXPECT_NEAR(mean, 1.0, 0.05) << listed(q);
  EXPECT_LT(std::abs(mean - 1.0), std::abs(mean_fastest - 1.0));
}

// Two Lorenz x series whose linear region was fitted over less than one and a half mean periods
// (bench/finite_time_spread "starts": mt19937(3), 23rd start, and (1), 30th): 88..216 and 90..258,
// 0.76 and 0.97 periods, read 1.235 and 1.138 lambda_1 (own exponents 0.945 and 0.986). The
// oscillation the curve carries at the mean period takes over so short a slope; over 1.5 periods
// (FitOptions::min_periods) they are within 5 %. Since the extension stops before it bends the
// region (FitOptions::extension_straightness: 5 of 6 Chua series closer to their own exponents, and
// 109 instead of 107 of the 128 Lorenz x series of "starts" within 5 %), the first stops at step 242
// and reads 1.18 lambda_1 again: its flattening after 0.76 periods (0.0112 then 0.0064 per step)
// looks like Chua's bend (0.0238 then 0.0121..0.0157). The 1.5 periods are checked with the whole
// extension; the default rule on the second.
TEST(EstimateSystems, LorenzWhoseLinearRegionIsShortIsFittedOverOneAndAHalfPeriods) {
  const std::array<double, 3> starts[] = {{-1.1864183185693871, 1.8421360499821722, 0.36100992934238035},
                                          {-2.9299848326973059, -0.011345582553034639, 0.8524159776877166}};
  MlceOptions whole;
  whole.fit.extension_straightness = 0.0;
  for (const auto& x0 : starts) {
    const auto r = estimate_mlce(make_series_with_step({reference::lorenz_x(10000, 0.01, x0)}, 0.01), whole);
    EXPECT_NEAR(r.lambda, 0.9056, 0.05 * 0.9056) << r.fit.rule;
    EXPECT_GE(2 * (r.fit.last - r.fit.first), 3 * r.theiler) << r.fit.rule;  // theiler = the mean period here
  }
  const auto r = run(reference::lorenz_x(10000, 0.01, starts[1]), 0.01);
  EXPECT_NEAR(r.lambda, 0.9056, 0.05 * 0.9056) << r.fit.rule;
  EXPECT_GE(2 * (r.fit.last - r.fit.first), 3 * r.theiler) << r.fit.rule;
}

// Two Lorenz x series whose curves flatten from the start-up to the plateau with no straight
// stretch (bench/finite_time_spread "starts": the starts drawn by mt19937(2), 7th, and (4), 11th).
// The piece of largest change was the flattest before the bend and read 0.800 and 0.715 lambda_1;
// fitted from the start-up's end they read 0.939 and 0.934.
TEST(EstimateSystems, LorenzWhoseCurveHasNoStraightStretchIsFittedOverItsWholeGrowth) {
  for (const std::array<double, 3> x0 : {std::array<double, 3>{-1.9380922561792264, 2.817794446013373, 0.40596328000293758},
                                         std::array<double, 3>{2.2218388526624659, 2.0115402456432179, 0.47805584197784956}}) {
    const auto r = run(reference::lorenz_x(10000, 0.01, x0), 0.01);
    EXPECT_NEAR(r.lambda, 0.9056, 0.10 * 0.9056) << r.fit.rule;
    EXPECT_LT(r.fit.first, 100u) << r.fit.rule;
  }
}

TEST(EstimateSystems, HenonWithinTwoPercent) {
  const auto r = run(reference::henon_x(10000), 1.0);
  EXPECT_NEAR(r.lambda, 0.41922, 0.02 * 0.41922) << r.fit.rule;
  EXPECT_EQ(r.delay, 1u);
  EXPECT_EQ(r.dim, 2u);
  expect_clean(r);  // its first step rises at 0.7 x the slope: a map's jump is its exponent
}

TEST(EstimateSystems, HenonWithinTwoPercentOnMostSeries) {
  // 16 series from random initial states (seed independent of bench/finite_time_spread's).
  std::mt19937 gen(20261121);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  std::vector<double> q;
  for (int k = 0; k < 16; ++k) {
    const double x0 = u(gen), y0 = 0.3 * u(gen);
    q.push_back(run(reference::henon_x(10000, x0, y0), 1.0).lambda / 0.41922);
  }
  std::printf("Henon lambda / 0.41922 on 16 series: %s\n", listed(q).c_str());
  EXPECT_GE(count_within(q, 0.02), 15) << listed(q);
  EXPECT_NEAR(median(q), 1.0, 0.01) << listed(q);
}

// The trajectory's own finite-time exponent (tangent map along the very iterations a series
// samples) scatters by ~0.9 % at 10^4 iterations, and on some orbits by more than 2 %
// (bench/finite_time_spread maps: 250 of 256 within 2 %). The estimator must follow it: each of
// the 16 series within 1.5 % of lambda_1 from its own exponent (256 series: -1.08 .. +0.47 %).
TEST(EstimateSystems, HenonFollowsTheExponentOfTheTrajectoryItSamples) {
  std::mt19937 gen(20261121);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  for (int k = 0; k < 16; ++k) {
    const double x0 = u(gen), y0 = 0.3 * u(gen);
    const double own = reference::henon_own_exponent(10000, x0, y0);
    EXPECT_NEAR(run(reference::henon_x(10000, x0, y0), 1.0).lambda, own, 0.015 * 0.41922)
        << "series " << k + 1 << " from (" << x0 << ", " << y0 << ")";
  }
}

TEST(EstimateSystems, LogisticWithinTwoPercentOfLn2) {
  const auto r = run(reference::logistic(10000), 1.0);
  EXPECT_NEAR(r.lambda, std::log(2.0), 0.02 * std::log(2.0)) << r.fit.rule;
  expect_clean(r);
}

// Banded chaotic maps (the orbit visits 2 or 4 bands in a fixed cycle): their AMI levels off above
// its floor, and the shoulder rule took a "minimum" 14-38 lags on (m = 5-7 then, 0.77-1.30 of the
// orbits' own exponents); within the bands the pairs saturate short of the whole attractor's scale,
// which the bounded rule took for a limit cycle (Henon a = 1.06: 0.18). `build/map_bands` scans
// r = 3.57..4 and a = 1.00..1.40. The truth: the orbit's own exponent, the mean of ln |f'| (logistic)
// or the tangent map (Henon) along the very iterations sampled.
TEST(EstimateSystems, BandedChaoticMapsWithinTwoPercentOfTheirOrbitsExponents) {
  for (const double r : {3.58, 3.6, 3.65}) {
    const auto x = reference::logistic(10000, 0.1234567, r);
    const double own = reference::logistic_own_exponent(x, r);
    const auto e = run(x, 1.0);
    EXPECT_NEAR(e.lambda, own, 0.02 * own) << "r = " << r << ": " << e.fit.rule;
    EXPECT_EQ(e.delay, 1u) << "r = " << r;
    EXPECT_TRUE(e.unreliable.empty()) << "r = " << r << ": " << e.unreliable;
  }
  for (const double a : {1.06, 1.12}) {
    const auto x = reference::henon_x(10000, 0.1, 0.1, a);
    const double own = reference::henon_own_exponent(10000, 0.1, 0.1, a);
    const auto e = run(x, 1.0);
    EXPECT_NEAR(e.lambda, own, 0.02 * own) << "a = " << a << ": " << e.fit.rule;
    EXPECT_NE(e.fit.end, CurveEnd::bounded) << "a = " << a;
  }
}

// Maps whose orbit stays on one lobe for many iterations before it switches: the switching puts
// most of the power at low frequencies, so the mean period (eq. 19) reads 8-27 samples as a
// sampled flow's would, but 6.6-16 % of the power lies at periods below 4 samples, where a sampled
// flow has almost none (MeanPeriodResult::map). Read as flows they took delays of 2-171 and m = 6-9
// (the AMI keeps the lobe's memory), then phase alignment between iterations: -0.07..0.29 of their
// exponents, every one flagged undetermined (`build/map_bands switching`). As maps: delay 1, and each
// orbit's own exponent.
TEST(EstimateSystems, MapsThatSwitchSlowlyBetweenLobesReadTheirOrbitsExponents) {
  struct Case {
    const char* name;
    reference::MapSample sample;
    double tolerance;
  };
  const std::vector<Case> cases{{"Duffing map a = 2.75, b = 0.2", reference::duffing_map_x(10000), 0.05},
                                {"Duffing map a = 2.7, b = 0.1", reference::duffing_map_x(10000, 2.7, 0.1), 0.02},
                                {"cubic map a = 2.64", reference::cubic_map(10000, 2.64), 0.02},
                                {"cubic map a = 2.72", reference::cubic_map(10000, 2.72), 0.02}};
  for (const auto& c : cases) {
    const auto e = run(c.sample.x, 1.0);
    EXPECT_TRUE(e.mean_period.map) << c.name << ": fast share " << e.mean_period.fast_share;
    EXPECT_GE(e.mean_period.mean_period, kMinFlowPeriod) << c.name << " (a map by its spectrum, not its period)";
    EXPECT_EQ(e.delay, 1u) << c.name;
    EXPECT_NEAR(e.lambda, c.sample.own_exponent, c.tolerance * c.sample.own_exponent) << c.name << ": " << e.fit.rule;
    EXPECT_TRUE(e.unreliable.empty()) << c.name << ": " << e.unreliable;
    std::printf("%-30s own %.4f  estimate %.4f (%.3f)  mean period %zu, fast share %.3f, m %zu\n", c.name,
                c.sample.own_exponent, e.lambda, e.lambda / c.sample.own_exponent, e.mean_period.mean_period,
                e.mean_period.fast_share, e.dim);
  }
}

// In floating point this logistic orbit lands on 1/2, then 1, and stays at the fixed point 0 from
// sample 6037 on (bench/finite_time_spread, default maps section, series 4): 3963 samples of 0. The
// estimator analyses the chaotic part up to the floor, says so, and still reads ln 2.
TEST(EstimateSystems, LogisticOrbitStuckAtZeroIsAnalysedUpToThatFloor) {
  const auto x = reference::logistic(10000, 0.45785506968646067);
  ASSERT_EQ(std::find(x.begin(), x.end(), 0.0) - x.begin(), 6037);
  ASSERT_EQ(x.back(), 0.0);
  const auto r = run(x, 1.0);
  EXPECT_NEAR(r.lambda, std::log(2.0), 0.02 * std::log(2.0)) << r.fit.rule;
  EXPECT_TRUE(has_warning(r, "floor from sample"));
  EXPECT_LE(r.n_points, 6200u);
}

TEST(EstimateSystems, DampedOscillatorWithinThreePercent) {
  const double zeta = 0.05, w = 2 * M_PI;
  const auto r = run(reference::damped_oscillator(2000, 0.01, zeta, w), 0.01);
  EXPECT_NEAR(r.lambda, -zeta * w, 0.03 * zeta * w) << r.fit.rule;
  EXPECT_LT(r.ci95_low, r.ci95_high);
  expect_clean(r);
}

// A lightly damped mode over a few periods, as a rotor's lag mode in a short record: the AMI's
// histogram ripples every ~T / (pi B) lags (ami.hpp, AmiOptions::smoothing), and with a 3-lag average
// its first ripple was taken for the delay (14 samples for a quarter period of 157), the embedding
// was a thin ellipse whose neighbours lay on the other side of the motion, and the decay read
// lambda = +0.070, +0.168 and -0.111 for -0.005, -0.010 and -0.005 (commit 9adc53d's library).
// Truth: -zeta omega.
TEST(EstimateSystems, LightlyDampedModeOverAFewPeriodsReadsItsDecay) {
  struct Case {
    std::size_t n;
    double zeta, omega;
  };
  for (const Case c : {Case{2000, 0.005, 1.0}, Case{2000, 0.005, 2.0}, Case{3000, 0.005, 1.0}}) {
    const auto r = run(reference::damped_oscillator(c.n, 0.01, c.zeta, c.omega), 0.01);
    const double quarter = 2 * M_PI / c.omega / 0.01 / 4;
    std::printf("zeta %.3f omega %.1f N %zu: delay %zu (quarter period %.0f), lambda %.5f (truth %.5f)\n", c.zeta,
                c.omega, c.n, r.delay, quarter, r.lambda, -c.zeta * c.omega);
    EXPECT_GT(static_cast<double>(r.delay), quarter / 2) << c.n << " " << c.omega;
    EXPECT_NEAR(r.lambda, -c.zeta * c.omega, 0.03 * c.zeta * c.omega) << r.fit.rule;
  }
}

TEST(EstimateSystems, SeveralDecayingModesReadTheLeastDampedOne) {
  // The free response of a linear system of two modes: its exponent is the larger rate, the least
  // damped mode, which the divergence curve follows only once the faster mode has died out (at close
  // frequencies the two beat first). The growth rule's region read these 1.69, 1.18, 1.48 and 1.16
  // times the exponent (build/decay_modes prints both).
  using reference::DecayingMode;
  struct Case {
    std::size_t n;
    std::vector<DecayingMode> modes;
    double lambda1;
  };
  const std::vector<Case> cases{
      {4000, {{-0.3, 1.0, 1.0}, {-0.5, 1.37, 1.0, 0.7}}, -0.3},
      {4000, {{-0.3, 1.0, 0.2}, {-1.0, 3.3, 1.0, 0.7}}, -0.3},
      {2000, {{-0.3, 1.0, 0.2}, {-1.0, 1.37, 1.0, 0.7}}, -0.3},
      {3000, {{-2.0, 2.0, 1.0}, {-0.2, 1.0, 0.01, 0.7}}, -0.2},
  };
  for (const auto& c : cases) {
    const auto r = run(reference::decaying_modes(c.n, 0.01, c.modes), 0.01);
    EXPECT_NEAR(r.lambda, c.lambda1, 0.05 * std::abs(c.lambda1)) << c.n << ": " << r.fit.rule;
    EXPECT_EQ(read_stability(r).stability, Stability::stable) << r.fit.rule;
  }
  // A weak slow mode under a strong fast one: the curve's fall slows, and the warning says why.
  const auto r = run(reference::decaying_modes(3000, 0.01, cases.back().modes), 0.01);
  EXPECT_TRUE(has_warning(r, "the decay slows along the divergence curve")) << r.fit.rule;
}

TEST(EstimateSystems, NoisyDecayOfTwoModesWhoseCurveShowsNoFloorIsFittedLate) {
  // e^{-0.3 t} cos 2 pi t + e^{-t} cos(2 pi 1.37 t + 0.7) plus white noise of 0.1 % of the start: the
  // estimator cuts the floor the decay sinks into off the series (its last part white), and what is
  // left shows no floor on the curve, only the fast mode dying out. The signal's floor then explains
  // nothing, and the late region reads the least damped mode; step 3 read the fast modes' part.
  using reference::DecayingMode;
  auto x = reference::decaying_modes(4000, 0.01, {{-0.3, 1.0, 1.0}, {-1.0, 1.37, 1.0, 0.7}});
  std::mt19937_64 gen(1);
  std::normal_distribution<double> white(0.0, 2e-3);
  for (double& v : x) v += white(gen);
  const auto series = make_series_with_step({x}, 0.01);
  const auto r = estimate_mlce(series, {});
  EXPECT_TRUE(has_warning(r, "decays into white measurement noise")) << r.fit.rule;
  EXPECT_EQ(r.fit.end, CurveEnd::none) << r.fit.rule;
  EXPECT_NEAR(r.lambda, -0.3, 0.05 * 0.3) << r.fit.rule;
  mlce::MlceOptions step3;
  step3.fit.late_decay_share = 0.0;
  EXPECT_LT(estimate_mlce(series, step3).lambda, -1.2 * 0.3);
}

// A noisy decay of two modes, e^{-0.1257 t} cos 2 pi t (zeta 0.02, the least damped: lambda_1) at 5x a
// mode of -1 1/s at 1.37 Hz, plus white noise of 1 % of the slow mode's amplitude: the plain curve is
// held up by the noise, the compensated one still carries the fast mode's fall at its start, and
// is fitted late (stage 2b'), where the fast mode has died out. 4 noise seeds: each within 10 % of
// lambda_1, and its 95 % interval holds lambda_1 on at least 3. The growth rule's region, the rule
// before, took the fast mode's fall (seeds 21 and 22: 1.39 and 1.77 lambda_1 in
// `build/noisy_decays modes` built against commit d0a870f's library).
TEST(EstimateSystems, NoisyDecayOfTwoModesIsFittedLateOnItsCompensatedCurve) {
  const double slow = -0.02 * 2 * M_PI;
  const auto clean = reference::decaying_modes(4774, 0.01, {{slow, 1.0, 5.0}, {-1.0, 1.37, 1.0, 0.7}});
  int covered = 0;
  for (std::uint64_t seed = 21; seed <= 24; ++seed) {
    const auto r = run(reference::with_white_noise(clean, 0.01 * 5.0, seed), 0.01);
    EXPECT_TRUE(r.noise_compensated) << seed;
    EXPECT_NEAR(r.lambda / slow, 1.0, 0.10) << seed << ": " << r.fit.rule;
    EXPECT_NE(r.fit.rule.find("a noise-compensated fall"), std::string::npos) << r.fit.rule;
    covered += r.ci95_low <= slow && slow <= r.ci95_high;
    std::printf("seed %llu: lambda / lambda_1 %.3f, plain curve %.3f, fit %zu..%zu\n",
                static_cast<unsigned long long>(seed), r.lambda / slow, r.uncompensated_lambda / slow, r.fit.first,
                r.fit.last);
  }
  EXPECT_GE(covered, 3);
}

TEST(EstimateSystems, SeveralGrowingModesReadTheFastestOne) {
  // The response of a linear system with a growing mode: its exponent is the largest rate, which the
  // divergence curve follows only once that mode dominates (at close frequencies the modes beat
  // first, and a beat's flat part looked like a saturation plateau). The growth rule's region read
  // these 1.25, 3.10, 1.12 and 1.87 times the exponent (build/decay_modes, growths section).
  using reference::DecayingMode;
  const std::vector<std::vector<DecayingMode>> cases{
      {{0.3, 1.0, 0.01}, {-0.5, 1.37, 1.0, 0.7}},
      {{0.3, 1.0, 0.01}, {0.1, 1.37, 1.0, 0.7}},
      {{0.3, 1.0, 0.1}, {-0.5, 1.37, 1.0, 0.7}},
      {{0.3, 1.0, 0.1}, {0.1, 1.37, 1.0, 0.7}},
  };
  for (const auto& modes : cases) {
    const auto r = run(reference::decaying_modes(3000, 0.01, modes), 0.01);
    // 0.3 at 1 % beside a +0.1 mode dominates only over the last 7 of 30 s: within 11 %, the others 5 %.
    const double tolerance = modes[0].amplitude < 0.05 && modes[1].rate > 0.0 ? 0.11 : 0.05;
    EXPECT_NEAR(r.lambda, 0.3, tolerance * 0.3) << modes[0].amplitude << " " << modes[1].rate << ": " << r.fit.rule;
    EXPECT_EQ(read_stability(r).stability, Stability::unstable) << r.fit.rule;
  }
  // The signal's end rate, which decides, is its amplitude's growth over its second half: e^{0.3 t}.
  const auto one = run(reference::decaying_modes(3000, 0.01, {{0.3, 1.0, 1.0}}), 0.01);
  EXPECT_NEAR(one.end_envelope_rate / 0.01, 0.3, 0.01 * 0.3);
}

TEST(EstimateSystems, VanDerPolLimitCycleIsZero) {
  for (double dt : {0.01, 0.05}) {
    const auto r = run(reference::van_der_pol_x(10000, dt), dt);
    EXPECT_LT(std::abs(r.lambda), 0.01) << "dt " << dt << ": " << r.fit.rule;
    expect_clean(r);
  }
}

TEST(EstimateSystems, SineWrittenToFullPrecisionIsNeutralNotItsRounding) {
  // sin(2 pi i / 100), 5000 samples: lambda = 0. Its points repeat every period only to the
  // rounding of sin's argument (~1e-13): those repeats are passed over (RosensteinOptions::
  // repeat_resolution), the neighbours lie a sample of phase away and the curve is flat. Taken as
  // neighbours, the repeats followed the rounding's drift from ln d ~ -31 (lambda x period = +0.047,
  // beyond the neutral band) and FNN chose m = 4. Not a quantised series: no resolution warning.
  std::vector<double> x(5000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(2 * M_PI * static_cast<double>(i) / 100.0);
  const auto r = estimate_mlce(make_series_with_step({x}, 1.0), {});
  EXPECT_EQ(r.dim, 2u);
  EXPECT_LT(std::abs(r.lambda * 100.0), 1e-3) << r.lambda;
  EXPECT_GT(r.curve.mean_log_distance.front(), -5.0);  // a sample of phase: ln 0.06
  bool near_repeats_said = false;
  for (const auto& w : r.warnings) {
    EXPECT_EQ(w.find("lambda is unreliable"), std::string::npos) << w;
    near_repeats_said |= w.find("repeats to the rounding") != std::string::npos;
  }
  EXPECT_TRUE(near_repeats_said);
  RosensteinOptions o;
  o.dim = 2, o.delay = 19, o.theiler = 100, o.horizon = 200, o.repeat_resolution = 0.0;  // the mechanism
  EXPECT_LT(divergence_curve(make_series_with_step({x}, 1.0), o).mean_log_distance.front(), -25.0);
  o.repeat_resolution = -1.0;
  EXPECT_THROW(o.validate(), OptionError);
}

TEST(EstimateSystems, PeriodicSeriesWrittenWithFewDigitsRepeatsStretchesNotAQuantum) {
  // The same sine written with 6 significant digits (MBDyn's default precision): its points repeat
  // exactly every period, as many times per reference as a quantised series' do, but whole
  // stretches repeat with them. lambda = 0, and the warning says periodic, not "unreliable". Lorenz x
  // rounded to integers repeats single points only: there the resolution warning stands.
  std::vector<double> x(5000);
  for (std::size_t i = 0; i < x.size(); ++i) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", std::sin(2 * M_PI * static_cast<double>(i) / 100.0));
    x[i] = std::strtod(text, nullptr);
  }
  const auto periodic = estimate_mlce(make_series_with_step({x}, 1.0), {});
  EXPECT_LT(std::abs(periodic.lambda * 100.0), 1e-3) << periodic.lambda;
  auto said = [](const MlceResult& r, const char* what) {
    return std::any_of(r.warnings.begin(), r.warnings.end(),
                       [&](const std::string& w) { return w.find(what) != std::string::npos; });
  };
  EXPECT_TRUE(said(periodic, "repeats whole stretches (100 %")) << periodic.warnings.size();
  EXPECT_FALSE(said(periodic, "lambda is unreliable"));
  auto coarse = reference::lorenz_x(10000, 0.01);
  for (double& v : coarse) v = std::round(v);
  const auto quantised = estimate_mlce(make_series_with_step({coarse}, 0.01), {});
  EXPECT_TRUE(said(quantised, "lambda is unreliable"));
  EXPECT_FALSE(said(quantised, "repeats whole stretches"));
  EXPECT_FALSE(quantised.unreliable.empty()) << "its reading is undetermined";
  // The logistic map's stable period-3 orbit (r = 3.84, own exponent -0.044 per iteration) repeats to
  // the rounding (near repeats, 1e-10 of a point's size), and the orbit stretches such a repeat ~10x
  // within each period before contracting it: whole stretches still, not a quantum (they were read
  // as one, "lambda is unreliable", before kStretchSpread).
  const auto orbit = reference::logistic(10000, 0.1234567, 3.84);
  const double own = reference::logistic_own_exponent(orbit, 3.84);  // the tangent map along it
  const auto cycle = estimate_mlce(make_series_with_step({orbit}, 1.0), {});
  EXPECT_TRUE(said(cycle, "repeats whole stretches")) << cycle.warnings.size();
  EXPECT_FALSE(said(cycle, "lambda is unreliable"));
  EXPECT_TRUE(cycle.unreliable.empty()) << cycle.unreliable;
  EXPECT_NEAR(cycle.lambda, own, 0.1 * std::abs(own)) << own;
}

TEST(EstimateSystems, LimitCycleRunOfLessThanTwoCyclesIsRefused) {
  // van der Pol at dt = 0.001 over 10 time units: 1.5 of its 6.66-s cycles. No point has a
  // neighbour on another pass of the cycle; with the Theiler window cut to N/4 the estimate read
  // +0.43 1/s on a limit cycle (lambda = 0). Refused, naming the cycles counted with the spectrum's
  // own mean period (not the clamped one, which would say 4).
  try {
    run(reference::van_der_pol_x(10000, 0.001), 0.001);
    FAIL() << "a limit cycle over 1.5 cycles was estimated";
  } catch (const InputError& e) {
    const std::string m = e.what();
    ASSERT_NE(m.find("span only "), std::string::npos) << m;
    const double spanned = std::stod(m.substr(m.find("span only ") + 10));
    EXPECT_GT(spanned, 1.0) << m;
    EXPECT_LT(spanned, 2.0) << m;
    EXPECT_NE(m.find("another pass"), std::string::npos) << m;
  }
  // An explicit window is the user's decision: estimated, with the warning.
  MlceOptions o;
  o.theiler = 1000;
  const auto r = estimate_mlce(make_series_with_step({reference::van_der_pol_x(10000, 0.001)}, 0.001), o);
  EXPECT_TRUE(has_warning(r, "spans only"));
}

TEST(EstimateSystems, LimitCycleRunOfTwoAndAHalfCyclesIsZeroAndFlaggedWithItsTrueLength) {
  // dt = 0.0017: 2.6 cycles. The mean period is clamped to N/4 for the Theiler window; the warning
  // counts the cycles with the spectrum's own mean period (it said "4 mean periods" from the clamped one).
  const auto r = run(reference::van_der_pol_x(10000, 0.0017), 0.0017);
  EXPECT_TRUE(r.mean_period.clamped);
  const auto w = std::find_if(r.warnings.begin(), r.warnings.end(),
                              [](const std::string& s) { return s.find("spans only") != std::string::npos; });
  ASSERT_NE(w, r.warnings.end());
  const double spanned = std::stod(w->substr(w->find("spans only") + 11));
  EXPECT_GT(spanned, 2.0) << *w;
  EXPECT_LT(spanned, 3.0) << *w;
  // Truth 0. Over 2.6 cycles the curve is flat within the fit's own 95 % interval (half-width ~0.06
  // 1/s): any delay from 105 to 950 samples reads -0.007 .. -0.013 (`--delay`), the automatic one
  // -0.012: the interval must hold 0, and |lambda| stay within a third of its half-width.
  EXPECT_LT(r.ci95_low, 0.0);
  EXPECT_GT(r.ci95_high, 0.0);
  EXPECT_LT(std::abs(r.lambda), 0.02) << r.fit.rule;
}

TEST(EstimateSystems, RoesslerWithinTenPercent) {
  const auto r = run(reference::roessler_x(10000, 0.1), 0.1);
  EXPECT_NEAR(r.lambda, 0.0714, 0.1 * 0.0714) << r.fit.rule;
  EXPECT_TRUE(r.curve.phase_aligned);
  expect_clean(r);
}

// White noise has no divergence to resolve: delay vectors (m - 1) x delay + 1 samples after the
// match share no sample with the matched ones, and the curve is at its plateau from there.
TEST(EstimateSystems, WhiteNoiseIsFlaggedAsUnresolved) {
  std::mt19937_64 gen(11);
  std::normal_distribution<double> g;
  std::vector<double> x(10000);
  for (double& v : x) v = g(gen);
  const auto r = run(x, 1.0);
  std::printf("white noise: \"lambda\" %.3f per sample, m %zu, plateau from step %zu\n", r.lambda, r.dim, r.fit.end_index);
  EXPECT_TRUE(has_warning(r, "divergence not resolved")) << r.fit.rule;
  EXPECT_EQ(r.delay, 1u);
  EXPECT_LE(r.fit.end_index, r.dim + 2) << r.fit.rule;  // the plateau piece starts right after the window
}

// Stochastic series have no deterministic exponent, and FNN never unfolds them: its fraction stays
// at kStochasticFnnShare or more at every m up to 10 (white noise, AR(1) processes, random walks),
// while a deterministic signal it does not quite unfold stays lower (Roessler z). A random walk's
// curve rises and levels off as chaos does, and read "chaotic" before the rule.
TEST(EstimateSystems, AStochasticSeriesThatNeverUnfoldsIsNotRead) {
  std::mt19937_64 gen(2026);
  std::normal_distribution<double> g;
  const auto lowest = [](const MlceResult& r) {
    return r.fnn ? *std::min_element(r.fnn->fraction.begin(), r.fnn->fraction.end()) : 0.0;
  };
  const auto series = [&](double coefficient) {  // x_k = coefficient x_{k-1} + e_k; 1: a random walk
    std::vector<double> x(10000);
    double v = 0.0;
    for (double& s : x) s = v = coefficient * v + g(gen);
    return x;
  };
  for (const double coefficient : {0.0, 0.9, 0.99, 1.0, 1.0, 1.0}) {
    const auto r = run(series(coefficient), 1.0);
    const Reading reading = read_stability(r);
    std::printf("x_k = %.2f x_(k-1) + e_k: FNN lowest %.3f, lambda %.4f per sample, reading %s (%s)\n", coefficient,
                lowest(r), r.lambda, reading.motion.c_str(), r.unreliable.c_str());
    EXPECT_EQ(reading.stability, Stability::undetermined) << coefficient;
    // The FNN rule holds on every one, walks included (a walk is also said to be one:
    // ARandomWalkIsSaidAndNotRead).
    EXPECT_GE(lowest(r), kStochasticFnnShare) << coefficient;
    EXPECT_TRUE(has_warning(r, "false nearest neighbours stay at")) << coefficient;
  }
  const auto z = run(reference::roessler(10000, 0.1, {1.0, 1.0, 0.0}, 2), 0.1);
  std::printf("Roessler z: FNN lowest %.3f\n", lowest(z));
  EXPECT_LT(lowest(z), kStochasticFnnShare);
  EXPECT_FALSE(has_warning(z, "false nearest neighbours stay at"));
}

// Measurement noise added to Lorenz x: the curve's first step jumps by the noise's share, which
// gives its level. Truth: the sample standard deviation of the noise added, over the noisy
// series' own (the estimator standardises what it is given). The estimate is an upper one (the
// deterministic separation is in it too): within [0.95, 1.6] x the truth. A quick start-up (Lorenz
// at dt = 0.05: the first step rises at ~6 x the slope) is not noise.
TEST(EstimateSystems, MeasurementNoiseIsFlaggedWithItsLevel) {
  const auto clean = reference::lorenz_x(10000, 0.01);
  for (double level : {0.01, 0.1, 0.3}) {
    const auto [x, truth] = with_noise(clean, level, 3);
    const auto r = run(x, 0.01);
    std::printf("Lorenz x + noise %.3f of its standard deviation: lambda %.3f, noise_level %.4f\n", truth, r.lambda,
                r.noise_level);
    ASSERT_TRUE(std::isfinite(r.noise_level)) << "noise " << level << ": " << r.fit.rule;
    EXPECT_GE(r.noise_level, 0.95 * truth) << "noise " << level;
    EXPECT_LE(r.noise_level, 1.6 * truth) << "noise " << level;
    EXPECT_TRUE(has_warning(r, "measurement noise")) << "noise " << level;
  }
  // Clean curves: the first step against the fitted slope per step (README quotes these).
  for (const auto& [name, clean_run] :
       {std::pair<const char*, MlceResult>{"Lorenz x, dt = 0.01", run(clean, 0.01)},
        {"Lorenz x, dt = 0.05", run(reference::lorenz_x(10000, 0.05), 0.05)},
        {"Henon x", run(reference::henon_x(10000), 1.0)}}) {
    const auto& y = clean_run.curve.mean_log_distance;
    std::printf("%s, no noise: first step %.3f, fitted slope %.4f per step (%.1f x)\n", name, y[1] - y[0],
                clean_run.fit.slope, (y[1] - y[0]) / clean_run.fit.slope);
    expect_clean(clean_run);
  }
}

// Noise on a map: a map's curve rises by about its slope per step from the first step on, so the
// first-step jump that flags noise on a flow never shows (logistic + 1 % read 0.89 of ln 2 unflagged).
// The closest pairs' one-step stretch does: the map stretches them like the others, noise sets
// their distance one step on (kMapNoiseStretchSlope). Truth: the noise added, measured on its own
// samples; and maps without noise (a tent map of slope 1.99, whose stretch is ln 1.99 exactly,
// logistic r = 4, Henon) are not flagged.
TEST(EstimateSystems, NoiseOnAMapIsFlaggedByItsClosestPairsStretch) {
  std::vector<double> tent(10000);
  double t = 0.2345;
  for (double& v : tent) v = t = t < 0.5 ? 1.99 * t : 1.99 * (1 - t);
  for (const auto& [name, clean] : {std::pair<const char*, std::vector<double>>{"logistic r = 4", reference::logistic(10000)},
                                    {"Henon x", reference::henon_x(10000)},
                                    {"tent 1.99", tent}}) {
    const auto plain = run(clean, 1.0);
    expect_clean(plain);
    for (const double level : {0.003, 0.01}) {
      const auto [x, truth] = with_noise(clean, level, 5);
      const auto r = run(x, 1.0);
      std::printf("%s + noise %.4f of its standard deviation: lambda %.4f (clean %.4f), noise_level %.4f\n", name, truth,
                  r.lambda, plain.lambda, r.noise_level);
      ASSERT_TRUE(std::isfinite(r.noise_level)) << name << ", noise " << level << ": " << r.fit.rule;
      EXPECT_GE(r.noise_level, 0.5 * truth) << name << ", noise " << level;  // "within a factor 2"
      EXPECT_LE(r.noise_level, 2.0 * truth) << name << ", noise " << level;
      EXPECT_TRUE(has_warning(r, "closest neighbour pairs stretch")) << name;
      EXPECT_LT(r.lambda, plain.lambda) << name << ": the warning calls the estimate a lower bound";
      EXPECT_NE(read_stability(r).summary.find("measurement noise"), std::string::npos) << read_stability(r).summary;
    }
  }
}

// A decay into measurement noise (paper 001 Fig. 6 with a white floor): lambda = -zeta w = -0.3142
// 1/s exactly. The floor is found by its whiteness (transient.hpp, detect_floor: of the last
// quarter's samples, or of their increments when the noise holds only its end, 0.3 % over 2000
// samples) and the series analysed up to where the signal is still 5x the noise. Uncut, noise of
// 0.1 % read +2.55 1/s (undetermined) on 8000 samples; 1 % read -0.185 on 2000 (41 % off, no
// warning); 0.3 % on 2000, before the increments rule, 0.737 lambda.
TEST(EstimateSystems, DecayIntoMeasurementNoiseIsAnalysedUpToItsWhiteFloor) {
  const double zeta = 0.05, w = 2 * M_PI, lambda = -zeta * w;
  for (const auto& [n, noise, tolerance] : {std::tuple{8000, 1e-3, 0.03}, std::tuple{2000, 3e-3, 0.05},
                                           std::tuple{2000, 1e-2, 0.10}, std::tuple{8000, 1e-2, 0.10}}) {
    const auto x = reference::noisy_decay(n, 0.01, zeta, w, noise);
    const auto r = run(x, 0.01);
    const auto reading = mlce::read_stability(r);
    // What the floor rule prevents: the same series analysed whole (floor_ratio 0).
    MlceOptions uncut;
    uncut.floor_ratio = 0.0;
    const auto whole = estimate_mlce(make_series_with_step({x}, 0.01), uncut);
    std::printf("e^{-0.314 t} cos 2 pi t + noise %.0e, %d samples: lambda %.4f (truth %.4f), %zu analysed; %s; "
                "analysed whole: %.4f, %s\n",
                noise, n, r.lambda, lambda, r.n_points, reading.summary.c_str(), whole.lambda,
                mlce::to_string(mlce::read_stability(whole).stability));
    EXPECT_NEAR(r.lambda / lambda, 1.0, tolerance) << n << " " << noise << ": " << r.fit.rule;
    EXPECT_TRUE(has_warning(r, "decays into white measurement noise")) << n << " " << noise;
    // The cut leaves the part where the amplitude is above 5x the noise: e^{-0.314 t} / sqrt 2 > 5 noise.
    const double t_cut = std::log(1.0 / (std::sqrt(2.0) * 5.0 * noise)) / (zeta * w);
    EXPECT_NEAR(0.01 * static_cast<double>(r.n_points), t_cut, 0.25 * t_cut) << n << " " << noise;
    EXPECT_EQ(reading.stability, mlce::Stability::stable);
  }
}

// A slow decay whose neighbour distances the noise dominates over much of what is left before its
// floor: zeta 0.01 with 1 % noise over 80 s (the signal at most 70x the noise; the cut at 5x leaves
// a decay by e^{-2.7}). Eq. 23's curve is held up by the noise and reads 0.44-0.49 of the rate on
// 8 noise seeds; the noise-compensated curve (NoiseCompensation) reads the rate itself: at least 6
// of 8 within 10 %, the median within 5 %. With 3 % noise (the cut at 25 s: a decay by e^{-1.6},
// the noise ~0.7 of the pairs' mean square at the curve's end) the noise is measured over the whole
// record, the floor left out included: over the analysed part's last quarter (640 samples) its
// estimate erred by up to 10 %, and 4 of 8 read within 10 % (0.76-1.48). Fitted late (stage 2b'),
// 5 of these 8 read within 10 %, all within 20 %, the median within 5 % (the growth rule's region
// read 6 of 8 within 10 % here, but over 40 other seeds 19 of 40 with an rms error of 0.30, against
// 20 and 0.14: `build/noisy_decays seeds`). The measured level is the noise's within 3 % (the
// analysed part's deviation converts it). Printed for README.
TEST(EstimateSystems, NoisyDecayAboveItsFloorReadsItsRateOnTheCompensatedCurve) {
  const double zeta = 0.01, w = 2 * M_PI, lambda = -zeta * w;
  const auto clean = reference::damped_oscillator(8000, 0.01, zeta, w);
  for (const double noise : {0.01, 0.03}) {
    std::vector<double> compensated, plain;
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
      const std::vector<double> x = reference::with_white_noise(clean, noise, seed);
      const auto r = run(x, 0.01);
      MlceOptions off;
      off.noise_compensation = NoiseCompensation::off;
      const auto p = estimate_mlce(make_series_with_step({x}, 0.01), off);
      compensated.push_back(r.lambda / lambda);
      plain.push_back(p.lambda / lambda);
      EXPECT_TRUE(r.noise_compensated) << seed;
      EXPECT_TRUE(has_warning(r, "noise-compensated curve")) << seed;
      EXPECT_TRUE(has_warning(r, "the whole record's third differences")) << seed;
      EXPECT_NEAR(r.uncompensated_lambda, p.lambda, 1e-12) << seed;
      EXPECT_EQ(r.plain_curve, p.curve.mean_log_distance) << seed;
      EXPECT_FALSE(p.noise_compensated);
      EXPECT_TRUE(std::isnan(p.uncompensated_lambda));
      EXPECT_LT(p.lambda / lambda, 0.6) << seed;
      EXPECT_EQ(mlce::read_stability(r).stability, mlce::Stability::stable) << seed;
      const std::vector<double> analysed(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(r.n_points));
      EXPECT_NEAR(r.noise_level * standard_deviation(analysed) / noise, 1.0, 0.03) << seed;
    }
    std::printf("zeta 0.01 + %g %% noise over 8000 samples, 8 seeds, lambda / (-zeta w): compensated %s; plain %s\n",
                100 * noise, listed(compensated).c_str(), listed(plain).c_str());
    EXPECT_GE(count_within(compensated, 0.10), noise < 0.02 ? 6 : 5) << noise << ": " << listed(compensated);
    EXPECT_EQ(count_within(compensated, 0.20), 8) << noise << ": " << listed(compensated);
    EXPECT_NEAR(median(compensated), 1.0, 0.05) << noise << ": " << listed(compensated);
  }
}

// Coarsely sampled (20 samples per period, omega dt = 0.31), a slow decay's motion leaks into the
// third differences as (omega dt)^3 x its amplitude: in the record's first eighth it raises their
// mean square by ~50 % over 0.5 % noise, a whole-record estimate of the noise by ~2 %, and the
// compensated curve, whose noise share nears 1 at its end, by ~15 % of the rate (1.15 on both of two
// noise draws, a working tree). The noise is measured from where it is steady: the measured level is
// the noise's within 3 %, and the rate within 10 %. 4 noise seeds.
TEST(EstimateSystems, CoarselySampledDecaysNoiseIsMeasuredWhereItsMotionDoesNotLeak) {
  const double zeta = 0.005, w = 2 * M_PI, lambda = -zeta * w, dt = 0.05, noise = 0.005;
  const auto clean = reference::damped_oscillator(3819, dt, zeta, w);
  std::vector<double> ratios, whole_noise;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const std::vector<double> x = reference::with_white_noise(clean, noise, seed);
    const auto r = run(x, dt);
    ASSERT_TRUE(r.noise_compensated) << seed << ": " << r.fit.rule;
    EXPECT_TRUE(has_warning(r, "the record's third differences where they are steady")) << seed;
    const std::vector<double> analysed(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(r.n_points));
    EXPECT_NEAR(r.noise_level * standard_deviation(analysed) / noise, 1.0, 0.03) << seed;
    ratios.push_back(r.lambda / lambda);
    // What the steady stretch leaves out: the whole record's estimate, which the leak raises.
    const auto series = make_series_with_step({x}, dt);
    const auto whole = mlce::white_increment_noise(series, 0, x.size(), mlce::WhitenessTest::third_differences);
    ASSERT_TRUE(whole.has_value()) << seed;
    whole_noise.push_back(whole->deviation[0] / noise);
    EXPECT_GT(mlce::steady_noise_start(series), 0u) << seed;
  }
  std::printf("zeta 0.005 + 0.5 %% noise, dt = 0.05, 4 seeds: lambda / (-zeta w) %s; the whole record's noise / "
              "truth %s\n", listed(ratios).c_str(), listed(whole_noise).c_str());
  EXPECT_EQ(count_within(ratios, 0.10), 4) << listed(ratios);
}

// The noise-compensated curve needs noise that is white: the increments of a decay with no noise
// are not, and its curve stays eq. 23's (also when the sampling is so fine that its last digits
// are all it has left: e^{-0.314 t} cos 2 pi t over 20 s, read exactly).
TEST(EstimateSystems, CleanDecayIsNotCompensated) {
  const auto r = run(reference::damped_oscillator(2000, 0.01, 0.05, 2 * M_PI), 0.01);
  EXPECT_FALSE(r.noise_compensated);
  EXPECT_TRUE(std::isnan(r.uncompensated_lambda));
  EXPECT_TRUE(r.plain_curve.empty());
  EXPECT_NEAR(r.lambda / (-0.05 * 2 * M_PI), 1.0, 0.03);
}

// Two channels of one decay, each with noise of its own size (1 % and 3 % of the start, the second
// in another unit): the noise is measured per channel and each channel's share taken out. 4 noise
// seeds: each compensated estimate within 20 % of the rate (0.986, 0.822, 1.036, 1.028; the growth
// rule's region, before compensated decays were fitted late: 1.032, 0.822, 1.098, 1.026) and closer
// to it than eq. 23's curve (~0.3 of it); the 3 % channel's noise leaves little signal in the pairs'
// distances. Seed 2 read 0.761 while the noise's steady stretch was judged window by window against
// those after it: its last window was low by chance, and the 3 % channel's noise read 12 % low.
TEST(EstimateSystems, NoiseOfEachChannelIsCompensated) {
  const double zeta = 0.01, w = 2 * M_PI, lambda = -zeta * w;
  const std::size_t n = 8000;
  const double wd = w * std::sqrt(1.0 - zeta * zeta);
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    std::vector<double> x(n), v(n);
    std::mt19937_64 gen(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    for (std::size_t i = 0; i < n; ++i) {
      const double t = 0.01 * static_cast<double>(i), e = std::exp(-zeta * w * t);
      x[i] = e * std::cos(wd * t) + 0.01 * g(gen);
      v[i] = 1e3 * (e * std::sin(wd * t) + 0.03 * g(gen));
    }
    const auto r = estimate_mlce(make_series_with_step({x, v}, 0.01), {});
    MlceOptions off;
    off.noise_compensation = NoiseCompensation::off;
    const auto p = estimate_mlce(make_series_with_step({x, v}, 0.01), off);
    std::printf("two channels, 1 %% and 3 %% noise, seed %d: lambda / (-zeta w) compensated %.3f, plain %.3f\n",
                static_cast<int>(seed), r.lambda / lambda, p.lambda / lambda);
    EXPECT_TRUE(r.noise_compensated) << seed;
    EXPECT_NEAR(r.lambda / lambda, 1.0, 0.2) << seed;
    EXPECT_LT(std::abs(r.lambda / lambda - 1.0), std::abs(p.lambda / lambda - 1.0)) << seed;
  }
}

// Noise on a limit cycle also holds its curve level (it jumps in its first step, then nothing
// moves: the noise is fresh at every step), but so does motion the embedding does not resolve on a
// coarsely sampled noise-free one (Hammond at 290 rpm every 0.02 s): the shape is flagged only on a
// decaying signal, where it hides the decay. Van der Pol (mu = 1, largest exponent 0) plus white
// noise of 0.3 %, 1 %, 3 % of its standard deviation reads |lambda| < 0.01 and neutral (limit
// cycle); at 10 % the noise keeps FNN's neighbours false up to m = 9, and the embedding window of
// 2.1 mean periods voids the reading (undetermined, with that reason).
TEST(EstimateSystems, NoiseOnALimitCycleLeavesALimitCycle) {
  const auto clean = reference::van_der_pol_x(10000, 0.01);
  for (double level : {0.003, 0.01, 0.03, 0.1}) {
    std::mt19937_64 gen(3);
    std::normal_distribution<double> g(0.0, level * standard_deviation(clean));
    std::vector<double> x = clean;
    for (double& v : x) v += g(gen);
    const auto r = run(x, 0.01);
    const auto reading = mlce::read_stability(r);
    std::printf("van der Pol + noise %.3f: lambda %.5f, %s\n", level, r.lambda, reading.summary.c_str());
    EXPECT_LT(std::abs(r.lambda), 0.01) << level;
    if (level > 0.05) {
      EXPECT_TRUE(reading.stability == mlce::Stability::neutral || !r.unreliable.empty()) << reading.summary;
      continue;
    }
    EXPECT_EQ(reading.stability, mlce::Stability::neutral) << level;
    EXPECT_EQ(reading.motion, "limit cycle") << level;
  }
}

// A lightly damped oscillation whose change per cycle is below the noise: zeta = 0.004 (lambda =
// -0.02513 1/s, lambda T = -0.0251 per period, beyond the neutral band of 0.01) plus 1 % noise
// over 160 s (the amplitude falls to 1.8 % of its start; the white floor is cut at 5x the noise).
// Nearest neighbours one cycle apart differ by 2.5 % of the amplitude, less than the noise: eq. 23's
// curve is level after its first step and reads ~-0.003. The noise is flagged; white (its
// third differences), it is measured and taken out of the curve, which reads the rate within 5 %, and
// the measured level is the noise's over the analysed part's deviation within 5 %. With the
// compensation off, the flag stands, and the reading takes the signal's own decay: stable, its
// envelope rate the decay's (within 10 %).
TEST(EstimateSystems, NoiseThatHoldsALightDecayLevelIsMeasuredAndTakenOut) {
  const double zeta = 0.004, w = 2 * M_PI, lambda = -zeta * w;
  const auto x = reference::noisy_decay(16000, 0.01, zeta, w, 0.01);
  const auto r = run(x, 0.01);
  const auto reading = mlce::read_stability(r);
  const std::vector<double> analysed(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(r.n_points));
  const double truth = 0.01 / standard_deviation(analysed);
  std::printf("zeta 0.004 + 1 %% noise: lambda %.5f (truth %.5f; plain curve %.5f), envelope %.5f, noise_level %.4f "
              "(truth %.4f); %s\n",
              r.lambda, lambda, r.uncompensated_lambda, r.envelope_rate / r.dt, r.noise_level, truth, reading.summary.c_str());
  ASSERT_TRUE(r.noise_compensated) << r.fit.rule;
  EXPECT_NEAR(r.lambda / lambda, 1.0, 0.05);
  EXPECT_NEAR(r.noise_level / truth, 1.0, 0.05);
  EXPECT_GT(r.uncompensated_lambda / lambda, 0.0);
  EXPECT_LT(r.uncompensated_lambda / lambda, 0.3);
  EXPECT_TRUE(has_warning(r, "holds the curve level"));  // said of the plain curve
  EXPECT_EQ(reading.stability, mlce::Stability::stable) << reading.summary;
  EXPECT_NE(reading.summary.find("noise-compensated"), std::string::npos) << reading.summary;

  MlceOptions off;
  off.noise_compensation = NoiseCompensation::off;
  const auto p = estimate_mlce(make_series_with_step({x}, 0.01), off);
  const auto plain_reading = mlce::read_stability(p);
  const double whole_truth = 0.01 / standard_deviation(x);  // the flag's upper estimate, against the whole series
  ASSERT_TRUE(std::isfinite(p.noise_level)) << p.fit.rule;
  EXPECT_GE(p.noise_level, 0.95 * whole_truth);
  EXPECT_LE(p.noise_level, 1.6 * whole_truth);
  EXPECT_TRUE(has_warning(p, "holds the curve level"));
  EXPECT_EQ(plain_reading.stability, mlce::Stability::stable) << plain_reading.summary;
  EXPECT_EQ(plain_reading.motion, "decays to rest");
  EXPECT_NEAR(p.envelope_rate / p.dt / lambda, 1.0, 0.10);
  // Without the noise the same decay reads its exact rate, unflagged.
  const auto clean = run(reference::damped_oscillator(16000, 0.01, zeta, w), 0.01);
  EXPECT_NEAR(clean.lambda / lambda, 1.0, 0.01) << clean.fit.rule;
  EXPECT_TRUE(std::isnan(clean.noise_level));
  EXPECT_FALSE(clean.noise_compensated);
}

TEST(EstimateSystems, RoesslerWithinTenPercentOnMostSeries) {
  const auto q = ratios_over_initial_states(
      [](std::array<double, 3> x0) { x0[2] /= 3.0; return reference::roessler_x(10000, 0.1, x0); }, 0.1, 0.0714, 16);
  std::printf("Roessler lambda / 0.0714 on 16 series: %s\n", listed(q).c_str());
  EXPECT_GE(count_within(q, 0.10), 10) << listed(q);
  EXPECT_NEAR(median(q), 1.0, 0.05) << listed(q);
}

TEST(EstimateSystems, RoesslerZIsStillChaoticAndFlagged) {
  // z is a poor observable of Roessler's attractor (near 0 most of the loop, one spike per loop):
  // FNN does not converge and the magnitude is unreliable, but the sign must not flip, and the
  // result says it is unreliable.
  const auto r = run(reference::roessler(10000, 0.1, {1.0, 1.0, 0.0}, 2), 0.1);
  EXPECT_GT(r.lambda, 0.0) << r.fit.rule;
  EXPECT_LT(r.delay, 20u);
  EXPECT_FALSE(r.warnings.empty());
}

TEST(EstimateSystems, DriftingSeriesIsFlaggedAndItsRefusalSaysWhy) {
  // A quantity that keeps growing never comes back near its past states: an oscillation on a ramp
  // is estimated with a warning; a rotor azimuth (ramp of 10 000 samples, the spectrum's "mean
  // period" is the ramp's) is refused, and the refusal names the drift.
  std::vector<double> ramp_sine(10000), azimuth(10000);
  for (std::size_t i = 0; i < ramp_sine.size(); ++i) {
    const double t = 0.01 * static_cast<double>(i);
    ramp_sine[i] = 0.3 * t + std::sin(2 * std::numbers::pi * t);
    azimuth[i] = 25.4 * t + 0.05 * std::sin(25.4 * t);
  }
  const auto r = estimate_mlce(make_series_with_step({ramp_sine}, 0.01), {});
  EXPECT_TRUE(has_warning(r, "the series drifts: a straight line through time explains 9"));
  try {
    estimate_mlce(make_series_with_step({azimuth}, 0.01), {});
    ADD_FAILURE() << "a rotor azimuth was estimated";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("but the series drifts"), std::string::npos) << e.what();
  }
  // A chaotic signal wanders but comes back: the largest share a line explains of Lorenz x from 32
  // random starts, over 100 and over 20 time units (one lobe can hold the shorter run for long).
  std::mt19937 gen(20261122);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (std::size_t n : {10000u, 2000u}) {
    double largest = 0.0;
    for (int k = 0; k < 32; ++k) {
      const auto x = reference::lorenz_x(n, 0.01, {u(gen), u(gen), std::abs(u(gen))}, 50.0);
      largest = std::max(largest, linear_drift(make_series_with_step({x}, 0.01)).share);
    }
    std::printf("Lorenz x over %g time units: a straight line explains at most %.3f of the variance\n", 0.01 * n, largest);
    EXPECT_LT(largest, kDriftShare) << n;
  }
  // Lorenz x from (1, 1, 1) with nothing discarded (its spiral start is left out) does not drift.
  const auto l = estimate_mlce(make_series_with_step({reference::lorenz_x(10000, 0.01, {1, 1, 1}, 0.0)}, 0.01), {});
  EXPECT_GT(l.skipped_start, 0u);
  EXPECT_FALSE(has_warning(l, "drifts"));
}

TEST(EstimateSystems, ARandomWalkIsSaidAndNotRead) {
  // A Gaussian random walk (x += N(0, 1) per sample: a random walk by construction) has no attractor
  // and its deterministic part x[t+1] = x[t] has exponent 0; 2 of 30 seeds read "unstable, diverging"
  // before. Its steps are white, and Ljung-Box's Q over 20 lags is then chi-square with 20 degrees of
  // freedom: mean 20, standard deviation sqrt 40 (the truth the statistic is checked against).
  constexpr int walks = 200;
  double q_sum = 0.0;  // 200 terms of ~20: no compensation needed
  int found = 0;
  for (int k = 0; k < walks; ++k) {
    const WhiteSteps w = white_steps(make_series_with_step({reference::random_walk(2000, 7000 + k)}, 0.01));
    found += w.found ? 1 : 0;
    ASSERT_EQ(w.lags, kWhiteStepLags);
    q_sum += w.statistic;
  }
  const double mean_q = q_sum / walks;
  std::printf("random walks, N = 2000: %d of %d found, mean Q %.2f (chi-square 20: 20 +- %.2f)\n", found, walks, mean_q,
              std::sqrt(40.0 / walks) * 3.0);
  EXPECT_GE(found, walks - 2);  // a white sequence exceeds the 99.9 % point once in 1000
  EXPECT_NEAR(mean_q, 20.0, 3.0 * std::sqrt(40.0 / walks));
  // The estimate says so, and reads no stability; the scale does not matter (1e-200, 1e200).
  for (const std::size_t n : {10000u, 1000u})
    for (std::uint64_t seed : {1u, 7u, 12u}) {
      const auto x = reference::random_walk(n, seed);
      const MlceResult r = run(x, 0.01);
      const Reading reading = read_stability(r);
      std::printf("random walk N = %zu seed %llu: lambda %+.4f, %s\n", n, static_cast<unsigned long long>(seed), r.lambda,
                  reading.summary.substr(0, 70).c_str());
      EXPECT_EQ(r.unreliable, "a random walk (its steps are white noise)") << n << " " << seed;
      EXPECT_EQ(reading.stability, Stability::undetermined) << n << " " << seed;
      EXPECT_TRUE(has_warning(r, "is a random walk: its steps are white noise")) << n << " " << seed;
      for (const double scale : {1e-200, 1e200}) {
        std::vector<double> scaled = x;
        for (double& v : scaled) v *= scale;
        const WhiteSteps w = white_steps(make_series_with_step({scaled}, 0.01));
        EXPECT_TRUE(w.found) << scale;
        EXPECT_NEAR(w.statistic, white_steps(make_series_with_step({x}, 0.01)).statistic, 1e-6) << scale;
      }
    }
  // No sampled motion's steps are white: flows (smooth steps), maps (steps tied by the map), linear
  // noise that returns (an AR(2) resonance, a noise-driven mode's q and v), white noise itself, a
  // ramp printed with 4 decimals (a drift with rounding) and a wrapping azimuth.
  std::vector<std::pair<std::string, std::vector<double>>> motions = {
      {"Lorenz x", reference::lorenz_x(10000, 0.01)},
      {"Roessler x", reference::roessler_x(10000, 0.1)},
      {"van der Pol x", reference::van_der_pol_x(10000, 0.01)},
      {"damped oscillator", reference::damped_oscillator(2000, 0.01, 0.05, 2.0 * std::numbers::pi)},
      {"Henon x", reference::henon_x(10000)},
      {"logistic", reference::logistic(10000)},
      {"AR(2) resonance", reference::ar2_resonance(10000, 0.99, 0.2, 3)},
      {"noise-driven mode q", reference::noise_driven_oscillator(10000, 0.01, 0.05, 2.0 * std::numbers::pi, 3).q},
      {"noise-driven mode v", reference::noise_driven_oscillator(10000, 0.01, 0.05, 2.0 * std::numbers::pi, 3).v}};
  std::mt19937_64 gen(11);
  std::normal_distribution<double> e(0.0, 1.0);
  std::vector<double> white(10000), ramp(10000), azimuth(10000);
  for (std::size_t i = 0; i < white.size(); ++i) {
    white[i] = e(gen);
    ramp[i] = std::round(1e4 * 0.37 * 0.01 * static_cast<double>(i)) / 1e4;
    azimuth[i] = std::remainder(25.4 * 0.01 * static_cast<double>(i), 2.0 * std::numbers::pi);
  }
  motions.emplace_back("white noise", white);
  motions.emplace_back("ramp, 4 decimals", ramp);
  motions.emplace_back("wrapping azimuth", azimuth);
  for (const auto& [name, x] : motions) {
    const WhiteSteps w = white_steps(make_series_with_step({x}, 0.01));
    if (w.tested)
      std::printf("%-20s random walk: %s (Q %.3g over %zu lags, point %.3g; variance ratio %.3g)\n", name.c_str(),
                  w.found ? "yes" : "no", w.statistic, w.lags, w.critical, w.variance_ratio);
    else
      std::printf("%-20s random walk: no (variance below %g x its steps', or steps of one sign)\n", name.c_str(),
                  kWalkVarianceRatio);
    EXPECT_FALSE(w.found) << name;
  }
  // A slowly wrapping azimuth (0.5 rad/s, a turn every 1257 samples) has steps of one value but for
  // rare whole turns, which the portmanteau test cannot tell from white: the wrap is the finding.
  std::vector<double> slow_azimuth(10000);
  for (std::size_t i = 0; i < slow_azimuth.size(); ++i)
    slow_azimuth[i] = std::remainder(0.5 * 0.01 * static_cast<double>(i), 2.0 * std::numbers::pi);
  EXPECT_TRUE(white_steps(make_series_with_step({slow_azimuth}, 0.01)).found);
  for (const auto& angle : {azimuth, slow_azimuth}) {
    try {
      const MlceResult a = estimate_mlce(make_series_with_step({angle}, 0.01), {});
      EXPECT_EQ(a.unreliable, "an angle that wraps by whole turns");
      EXPECT_FALSE(has_warning(a, "random walk"));
    } catch (const InputError& refused) {  // too few mean periods: refused, and not for a walk
      EXPECT_EQ(std::string(refused.what()).find("random walk"), std::string::npos) << refused.what();
    }
  }
  const MlceResult w = run(reference::random_walk(10000, 1), 0.01);
  for (const auto& text : w.warnings)
    if (text.find("random walk") != std::string::npos) std::printf("warning: %s\n", text.c_str());
}

TEST(EstimateSystems, NoChannelOfTheBundledMbdynRunsIsARandomWalk) {
  // Real solver output (data/mbdyn: limit cycle, growth, decays): every node column (position,
  // orientation, velocities), every joint and inertia column and the blades' lags. A multibody
  // integrator's steps follow each other smoothly; none is white.
  std::size_t channels = 0, tested = 0;
  double lowest = std::numeric_limits<double>::infinity();
  std::string lowest_name;
  for (const char* run : {"c3zero_242rpm_cyhalf_lco/c3zero_242rpm_cyhalf", "c3zero_242rpm_cyhalf_10s/c3zero_242rpm_cyhalf",
                          "iso_200rpm_5s/iso_200rpm", "iso_200rpm_1s/iso_200rpm"}) {
    const std::string prefix = std::string(MLCE_DATA_DIR) + "/mbdyn/" + run;
    const reader::Inventory inventory = reader::describe_mbdyn_text(prefix);
    std::vector<reader::ChannelSpec> specs;
    for (const auto& node : inventory.nodes)
      for (const char* field : {"x", "y", "z", "r1", "r2", "r3", "vx", "vy", "vz", "wx", "wy", "wz"})
        specs.push_back(reader::parse_channel_spec(fmt::format("node:{}:{}", node.label, field)));
    for (const auto& entity : inventory.entities)
      for (std::size_t k = 2; k <= entity.columns; ++k)
        specs.push_back(reader::parse_channel_spec(fmt::format("{}:{}:{}", entity.file, entity.label, k)));
    for (const int blade : {11, 12, 13, 14}) specs.push_back(reader::parse_channel_spec(fmt::format("rel:{}:4:z", blade)));
    const reader::ChannelSet set = reader::read_mbdyn_text(prefix, specs);
    for (std::size_t c = 0; c < set.values.size(); ++c) {
      const WhiteSteps w = white_steps(make_series_with_step({set.values[c]}, 0.01));
      EXPECT_FALSE(w.found) << run << " " << set.names[c] << ": Q " << w.statistic;
      ++channels;
      if (w.tested && w.statistic / w.critical < lowest)
        lowest = w.statistic / w.critical, lowest_name = std::string(run) + " " + set.names[c];
      tested += w.tested ? 1 : 0;
    }
  }
  std::printf("%zu channels of the bundled MBDyn runs, none a random walk; %zu wander 10 x their steps' variance, "
              "their Q at least %.3g x the 99.9 %% point (%s)\n", channels, tested, lowest, lowest_name.c_str());
  EXPECT_GT(channels, 300u);
}

TEST(EstimateSystems, ALevelCreepingBeneathTheNeighboursIsSaid) {
  // Roessler x plus 0.0005 t (0.5 over the run, ~10 % of x's deviation; a line explains under 1 %
  // of the variance, far below kDriftShare) and Lorenz x plus 0.01 t: the neighbours' separations
  // carry the level's change over their time apart, the curve is held up and lambda reads low. The
  // pairs see the creep, with its sign, and at most at its true rate (the search prefers pairs whose
  // own separation offsets it). The same series without the creep are not warned, nor are 8 more
  // Lorenz x and Roessler x from other starts (bench/level_drift: 240 stationary flow series, share
  // at most 0.010), nor a limit cycle on a creep, whose curve stays level either way.
  struct Case {
    std::vector<double> x;
    double dt, creep;
  };
  const std::vector<Case> cases = {{reference::roessler_x(10000, 0.1, {1.3, -2.1, 0.0}), 0.1, 5e-4},
                                   {reference::lorenz_x(10000, 0.01, {2.0, -1.0, 25.0}), 0.01, 1e-2}};
  for (const auto& c : cases) {
    std::vector<double> creeping = c.x;
    for (std::size_t i = 0; i < creeping.size(); ++i) creeping[i] += c.creep * c.dt * static_cast<double>(i);
    const MlceResult plain = run(c.x, c.dt), crept = run(creeping, c.dt);
    std::printf("creep %g per time unit: share %.4f (without: %.4f), seen %.3g, lambda %.4f (without: %.4f)\n", c.creep,
                crept.neighbour_drift.share, plain.neighbour_drift.share, crept.neighbour_drift.rate_per_sample / c.dt,
                crept.lambda, plain.lambda);
    EXPECT_TRUE(has_warning(crept, "creeps beneath the neighbour pairs")) << c.creep;
    EXPECT_GT(crept.neighbour_drift.share, kNeighbourDriftShare);
    EXPECT_GT(crept.neighbour_drift.rate_per_sample, 0.0);
    EXPECT_LE(crept.neighbour_drift.rate_per_sample / c.dt, c.creep);
    EXPECT_LT(crept.lambda, plain.lambda);
    EXPECT_LT(linear_drift(make_series_with_step({creeping}, c.dt)).share, kDriftShare);
    EXPECT_FALSE(has_warning(plain, "creeps beneath")) << plain.neighbour_drift.share;
  }
  std::mt19937 gen(20261127);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  double largest = 0.0;
  for (int k = 0; k < 8; ++k) {
    const MlceResult l = run(reference::lorenz_x(10000, 0.01, {u(gen), u(gen), 20.0 + u(gen)}, 50.0), 0.01);
    const MlceResult r = run(reference::roessler_x(10000, 0.1, {u(gen), u(gen), 0.0}), 0.1);
    largest = std::max({largest, l.neighbour_drift.share, r.neighbour_drift.share});
    EXPECT_FALSE(has_warning(l, "creeps beneath")) << k;
    EXPECT_FALSE(has_warning(r, "creeps beneath")) << k;
  }
  std::printf("stationary Lorenz x and Roessler x, 8 each: largest share %.4f\n", largest);
  EXPECT_LT(largest, kNeighbourDriftShare);
  // A limit cycle's curve stays level with the offset or without it: van der Pol x plus 0.01 t shows
  // a large share, reads neutral all the same, and is not warned.
  std::vector<double> cycle = reference::van_der_pol_x(10000, 0.01);
  for (std::size_t i = 0; i < cycle.size(); ++i) cycle[i] += 0.01 * 0.01 * static_cast<double>(i);
  const MlceResult v = run(cycle, 0.01);
  std::printf("van der Pol x + 0.01 t: share %.3f, lambda %.2g\n", v.neighbour_drift.share, v.lambda);
  EXPECT_GT(v.neighbour_drift.share, kNeighbourDriftShare);
  EXPECT_LT(std::abs(v.lambda), 0.01);
  EXPECT_FALSE(has_warning(v, "creeps beneath"));
}

TEST(EstimateSystems, NeighboursConvergingFasterThanTheSignalDecaysAreSaid) {
  // Two modes of like damping, e^{-0.2 t}(cos 2 pi t + cos 2.2 pi t) over 30 s (lambda_1 = -0.2
  // exactly): three beats of 10 s, and the curve's horizon holds one. Its falling half reads about
  // twice the rate, while the signal's own envelope falls at ~-0.2 over its second half; the
  // estimate says so. Where the least damped mode leads (two modes of rates -0.3 and -1.0) it
  // sets both, and nothing is said.
  const auto beat = reference::decaying_modes(3000, 0.01, {{-0.2, 1.0, 1.0}, {-0.2, 1.1, 1.0}});
  const auto r = estimate_mlce(make_series_with_step({beat}, 0.01), {});
  EXPECT_LT(r.lambda, -0.3) << r.fit.rule;
  EXPECT_TRUE(has_warning(r, "the neighbours converge")) << r.lambda;
  const auto led = reference::decaying_modes(2000, 0.01, {{-0.3, 1.0, 1.0}, {-1.0, 1.37, 1.0}});
  const auto l = estimate_mlce(make_series_with_step({led}, 0.01), {});
  EXPECT_NEAR(l.lambda, -0.3, 0.05 * 0.3) << l.fit.rule;
  EXPECT_FALSE(has_warning(l, "the neighbours converge")) << l.lambda;
  const auto single = estimate_mlce(make_series_with_step({reference::damped_oscillator(2000, 0.01, 0.05, 2 * std::numbers::pi)}, 0.01), {});
  EXPECT_FALSE(has_warning(single, "the neighbours converge")) << single.lambda;
}

TEST(EstimateSystems, NeighboursSeparatingFasterThanTheSignalGrowsAreSaid) {
  // The same beat growing, e^{0.1 t}(cos 2 pi t + cos 2.2 pi t) over 60 s (lambda_1 = 0.1 exactly):
  // the curve's horizon holds less than a beat, its rise reads ~7 x the signal's own growth, and
  // the estimate says so. A mode of 0.3 under a stronger one of 0.1 (the envelope lags the fastest
  // mode until it leads: ~0.17) is read within 15 % and nothing is said (twice the envelope's rate
  // is the bound for growths).
  const auto beat = reference::decaying_modes(6000, 0.01, {{0.1, 1.0, 1.0}, {0.1, 1.1, 1.0}});
  const auto r = estimate_mlce(make_series_with_step({beat}, 0.01), {});
  EXPECT_GT(r.lambda, 0.3) << r.fit.rule;
  EXPECT_TRUE(has_warning(r, "the neighbours separate")) << r.lambda;
  const auto led = reference::decaying_modes(3000, 0.01, {{0.3, 1.0, 0.01}, {0.1, 1.37, 1.0, 0.7}});
  const auto l = estimate_mlce(make_series_with_step({led}, 0.01), {});
  EXPECT_NEAR(l.lambda, 0.3, 0.15 * 0.3) << l.fit.rule;
  EXPECT_FALSE(has_warning(l, "the neighbours separate")) << l.lambda;
}

TEST(EstimateSystems, ADecayWhoseFalseNeighboursSeparateIsReconstructedInMoreDimensions) {
  // The same two modes of like damping over 120 s (the floor rule keeps the first 93.6 s, 12 beats):
  // FNN leaves 3.3 % false at m = 3, yet there points of the same amplitude and another beat phase
  // are matched and separate to their common scale: lambda = +0.68 1/s while the signal decays,
  // read "undetermined". A decay to rest has no neighbours that separate; m = 4 reads lambda_1 = -0.2.
  const auto beat = reference::decaying_modes(12000, 0.01, {{-0.2, 1.0, 1.0}, {-0.2, 1.1, 1.0}});
  const auto r = estimate_mlce(make_series_with_step({beat}, 0.01), {});
  EXPECT_NEAR(r.lambda, -0.2, 0.05 * 0.2) << r.fit.rule;
  ASSERT_TRUE(r.dim_widened_from.has_value());
  EXPECT_EQ(*r.dim_widened_from, 3u);
  EXPECT_EQ(r.dim_widened_because, DimensionWidening::growth_in_a_decay);
  EXPECT_EQ(r.dim, 4u);
  EXPECT_TRUE(has_warning(r, "m = 3 (false nearest neighbours) read lambda = +0.0068")) << r.warnings.front();
  EXPECT_EQ(read_stability(r).stability, Stability::stable);
  // A dimension given by hand stands: m = 3 keeps its contradiction, which the curve alone cannot
  // resolve (undetermined); the record's modes, identified for it, read the decay at -0.2 (truth).
  MlceOptions given;
  given.dim = 3;
  const auto three = estimate_mlce(make_series_with_step({beat}, 0.01), given);
  EXPECT_GT(three.lambda, 0.0);
  EXPECT_FALSE(three.dim_widened_from.has_value());
  ASSERT_TRUE(three.record_modes.has_value());
  EXPECT_NEAR(three.record_modes->lambda, -0.2, 0.01 * 0.2);
  EXPECT_EQ(read_stability(three).stability, Stability::stable) << read_stability(three).summary;
  auto curve_alone = three;
  curve_alone.record_modes.reset();
  EXPECT_EQ(read_stability(curve_alone).stability, Stability::undetermined);
}

TEST(EstimateSystems, AFlowThatDivergesIsNeverReconstructedInFewerThanThreeCoordinates) {
  // Roessler (x, y) embedded jointly: FNN leaves 4.9 % false at m = 1 (below its 5 % threshold), a
  // state of 2 coordinates, whose neighbours separate up to the attractor's scale. A flow in a plane
  // settles on fixed points and limit cycles only (Poincare-Bendixson): the estimate is redone at m = 2.
  const std::array<double, 3> x0{1.8165450207445701, -2.4431951381544246, 0.03630509678848215};
  auto flow = [](const std::array<double, 3>& s) { return reference::roessler_rhs(s); };
  auto tangent = [](const std::array<double, 6>& s) { return reference::roessler_tangent_rhs(s); };
  const double dt = 0.1;
  const double own = reference::own_exponent(flow, tangent, x0, 500.0, dt, 0.01, 10000);
  const Series xy = make_series_with_step({reference::sample_flow<3>(flow, x0, dt, 10000, 500.0, 10, 0),
                                           reference::sample_flow<3>(flow, x0, dt, 10000, 500.0, 10, 1)},
                                          dt);
  const auto r = estimate_mlce(xy, {});
  ASSERT_TRUE(r.dim_widened_from.has_value());
  EXPECT_EQ(*r.dim_widened_from, 1u);
  ASSERT_TRUE(r.fnn.has_value());
  std::printf("Roessler (x, y): %.2f %% false at m = 1, lambda %.4f at m = 2 (own %.4f)\n", 100.0 * r.fnn->fraction[0],
              r.lambda, own);
  EXPECT_EQ(r.dim_widened_because, DimensionWidening::flow_in_a_plane);
  EXPECT_EQ(r.dim, 2u);
  EXPECT_TRUE(has_warning(r, "a flow of fewer than 3 dimensions settles on fixed points and limit cycles only")) << r.warnings.front();
  EXPECT_NEAR(r.lambda / own, 1.0, 0.05) << own;
  // m = 1 given by hand stands, and reads farther from the trajectory's own exponent.
  MlceOptions plane;
  plane.dim = 1;
  const auto p = estimate_mlce(xy, plane);
  EXPECT_FALSE(p.dim_widened_from.has_value());
  EXPECT_GT(std::abs(p.lambda / own - 1.0), std::abs(r.lambda / own - 1.0) + 0.05) << p.lambda / own;
  // Nor is it widened beyond the largest m FNN is asked to test.
  MlceOptions capped;
  capped.fnn.max_dim = 1;
  const auto c1 = estimate_mlce(xy, capped);
  EXPECT_EQ(c1.dim, 1u);
  EXPECT_FALSE(c1.dim_widened_from.has_value());

  // A map is chaotic in a plane: Henon's own state (x_n, y_n = 0.3 x_{n-1}) is not widened and reads
  // its exponent; nor is a limit cycle's (x, dx/dt), whose neighbours do not separate.
  const auto hx = reference::henon_x(10001);
  std::vector<double> hy(hx.begin(), hx.end() - 1), hxx(hx.begin() + 1, hx.end());
  for (double& v : hy) v *= 0.3;
  const auto h = estimate_mlce(make_series_with_step({hxx, hy}, 1.0), {});
  EXPECT_EQ(h.dim, 1u);
  EXPECT_FALSE(h.dim_widened_from.has_value());
  EXPECT_NEAR(h.lambda, 0.4192, 0.02 * 0.4192);
  const auto vx = reference::van_der_pol_x(10001);
  std::vector<double> v(vx.begin(), vx.end() - 1), dv(vx.size() - 1);
  for (std::size_t i = 0; i + 1 < vx.size(); ++i) dv[i] = (vx[i + 1] - vx[i]) / 0.01;
  const auto c = estimate_mlce(make_series_with_step({v, dv}, 0.01), {});
  EXPECT_FALSE(c.dim_widened_from.has_value()) << c.dim;
  EXPECT_LT(std::abs(c.lambda), 0.01);
}

TEST(EstimateSystems, ADecayThatSettlesIsNoDrift) {
  // A slow overdamped mode under a faster oscillating one, e^{-0.1 t} + 0.3 e^{-0.3 t} sin 2 pi t over
  // 40 s (lambda_1 = -0.1 exactly): a line explains 78 % of it, and it was called a drift ("a quantity
  // that keeps growing") in its refusal and in the reading. Its trend settles: the second half's
  // slope is e^{-2} of the first's. The spectrum's mean period is the slow mode's (~1.1 of them in
  // the run), so the automatic window is refused; a window given by hand reads lambda_1, but the
  // reading is not given (it read a neutral limit cycle, the RMS about the run's mean steady).
  std::vector<double> x(4000);
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double t = 0.01 * static_cast<double>(i);
    x[i] = std::exp(-0.1 * t) + 0.3 * std::exp(-0.3 * t) * std::sin(2 * std::numbers::pi * t);
  }
  const Series s = make_series_with_step({x}, 0.01);
  const Drift d = linear_drift(s);
  EXPECT_LT(d.share, kDriftShare);
  EXPECT_GT(d.settling_share, 0.75);
  try {
    estimate_mlce(s, {});
    ADD_FAILURE() << "1.1 mean periods estimated with the automatic window";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find("drifts"), std::string::npos) << e.what();
  }
  MlceOptions o;
  o.theiler = 100;
  const auto r = estimate_mlce(s, o);
  EXPECT_NEAR(r.lambda, -0.1, 0.05 * 0.1) << r.fit.rule;
  EXPECT_FALSE(has_warning(r, "drifts"));
  EXPECT_EQ(r.unreliable, "fewer than two mean periods of a motion that persists");
  EXPECT_EQ(read_stability(r).stability, Stability::undetermined);
}

TEST(EstimateSystems, CurveOfFewPairsIsFlagged) {
  // Henon x: the curve averages one pair per reference point (max_references strides them).
  MlceOptions few;
  few.max_references = 40;
  const auto strided = estimate_mlce(make_series_with_step({reference::henon_x(10000)}, 1.0), few);
  EXPECT_EQ(strided.curve.pairs, 40u);
  EXPECT_TRUE(has_warning(strided, "only 40 neighbour pair(s)"));
  EXPECT_TRUE(has_warning(strided, "more reference points"));
  // 150 iterations: about 117 admissible points, whatever the reference count.
  const auto short_run = run(reference::henon_x(150), 1.0);
  EXPECT_LT(short_run.curve.pairs, kFewPairs);
  EXPECT_TRUE(has_warning(short_run, "analyse a longer series"));
  EXPECT_FALSE(has_warning(run(reference::henon_x(10000), 1.0), "neighbour pair(s)"));
}

TEST(EstimateSystems, ScaleInvariantTo1e200) {
  const auto x = reference::lorenz_x(5000, 0.01);
  const auto ref = run(x, 0.01);
  for (double scale : {1e-200, 1e200}) {
    auto y = x;
    for (double& v : y) v *= scale;
    const auto r = run(y, 0.01);
    EXPECT_NEAR(r.lambda, ref.lambda, 1e-9 * std::abs(ref.lambda)) << scale;
    EXPECT_EQ(r.delay, ref.delay);
    EXPECT_EQ(r.dim, ref.dim);
  }
}

TEST(EstimateSystems, ResultDoesNotDependOnTheThreadCount) {
  const auto x = reference::henon_x(5000);
  omp_set_num_threads(1);
  const auto one = run(x, 1.0);
  omp_set_num_threads(2);
  const auto two = run(x, 1.0);
  EXPECT_EQ(one.lambda, two.lambda);
}

TEST(EstimateSystems, TooShortSeriesIsAClearError) {
  try {
    run(reference::lorenz_x(30, 0.01), 0.01);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("too short"), std::string::npos) << e.what();
  }
}
