// The surrogate test of the divergence against linear noise (surrogate.hpp): IAAFT surrogates keep
// the series' values exactly and its power spectrum closely (checked against the series' own
// periodogram, their definition), and the multivariate ones the channels' cross-correlation too;
// chaotic series (Lorenz x, Henon x; Lorenz (x, z) embedded jointly) are told from their
// surrogates, linear stochastic ones (an AR(2) resonance, a noise-driven mode's displacement and
// velocity, which read "chaotic" without the test) are not.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <numbers>
#include <cstdio>
#include <random>
#include <vector>

#include "mlce/estimate.hpp"
#include "mlce/reading.hpp"
#include "mlce/surrogate.hpp"
#include "reference_systems.hpp"

namespace {

using namespace mlce;

/// |DFT|^2 at k = 1 .. n/2 by direct summation (an independent check of FFTW's use).
std::vector<double> periodogram(const std::vector<double>& x) {
  const std::size_t n = x.size();
  std::vector<double> p(n / 2);
  for (std::size_t k = 1; k <= n / 2; ++k) {
    std::complex<double> s = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      s += x[i] * std::polar(1.0, -2.0 * M_PI * static_cast<double>(k * i % n) / static_cast<double>(n));
    p[k - 1] = std::norm(s);
  }
  return p;
}

/// `mlce estimate --surrogates 19`: on every estimate, 19 surrogates of the whole series, 200 passes.
MlceOptions with_surrogates() {
  MlceOptions o;
  o.surrogates_when = SurrogateWhen::always;
  o.surrogates = SurrogateOptions{};
  return o;
}

MlceOptions without_surrogates() {
  MlceOptions o;
  o.surrogates_when = SurrogateWhen::never;
  return o;
}

}  // namespace

TEST(Surrogate, IaaftKeepsTheValuesAndNearlyTheSpectrum) {
  const std::vector<double> x = reference::lorenz_x(1024);
  const std::vector<double> s = iaaft_surrogate(x, 7, 200);
  std::vector<double> a(x), b(s);
  std::sort(a.begin(), a.end()), std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);  // the very values
  EXPECT_NE(x, s);  // in another order
  const std::vector<double> px = periodogram(x), ps = periodogram(s);
  double total = 0.0, difference = 0.0;
  for (std::size_t k = 0; k < px.size(); ++k) total += px[k], difference += std::abs(px[k] - ps[k]);
  std::printf("IAAFT of 1024 Lorenz x samples: periodogram differs by %.3g %% of its power\n", 100.0 * difference / total);
  EXPECT_LT(difference / total, 0.05);
  // Another seed, another surrogate; the same seed, the same one.
  EXPECT_NE(iaaft_surrogate(x, 8, 200), s);
  EXPECT_EQ(iaaft_surrogate(x, 7, 200), s);
  // Scale-free: the surrogate of 1e200 x is 1e200 times the surrogate of x.
  std::vector<double> big(x);
  for (double& v : big) v *= 1e200;
  const std::vector<double> sb = iaaft_surrogate(big, 7, 200);
  for (std::size_t i = 0; i < s.size(); ++i) ASSERT_EQ(sb[i], s[i] * 1e200) << i;
}

TEST(Surrogate, ChaosIsToldFromItsSurrogates) {
  for (const auto& [name, x, dt] : {std::tuple{"Lorenz x", reference::lorenz_x(10000), 0.01},
                                    std::tuple{"Henon x", reference::henon_x(10000), 1.0}}) {
    const MlceResult r = estimate_mlce(make_series_with_step({x}, dt), with_surrogates());
    ASSERT_TRUE(r.surrogates.has_value()) << name;
    const SurrogateTest& t = *r.surrogates;
    std::printf("%s: slope %.5f per step, surrogates up to %.5f, p = %.2f, %.1f sigmas\n", name, t.series_slope,
                *std::max_element(t.surrogate_slopes.begin(), t.surrogate_slopes.end()), t.p_value, t.sigmas);
    EXPECT_TRUE(t.distinguished) << name;
    EXPECT_DOUBLE_EQ(t.p_value, 0.05) << name;
    EXPECT_EQ(read_stability(r).motion, "chaotic") << name;
  }
}

TEST(Surrogate, ALinearResonanceDrivenByNoiseIsNotChaos) {
  // Without the test the first reads "unstable, chaotic" (lambda = +0.028 per sample, m = 5).
  const Series first = make_series_with_step({reference::ar2_resonance(10000, 0.99, 0.2, 1)}, 1.0);
  EXPECT_EQ(read_stability(estimate_mlce(first, without_surrogates())).motion, "chaotic");
  for (const std::uint64_t seed : {1, 2, 3}) {
    const MlceResult r = estimate_mlce(make_series_with_step({reference::ar2_resonance(10000, 0.99, 0.2, seed)}, 1.0), with_surrogates());
    ASSERT_TRUE(r.surrogates.has_value());
    const Reading reading = read_stability(r);
    std::printf("AR(2) seed %d: lambda %+.4f, p = %.2f, %.2f sigmas: %s\n", static_cast<int>(seed), r.lambda,
                r.surrogates->p_value, r.surrogates->sigmas, reading.motion.c_str());
    EXPECT_FALSE(r.surrogates->distinguished) << seed;
    EXPECT_NE(reading.motion, "chaotic") << seed;
    EXPECT_LT(std::abs(r.surrogates->sigmas), 3.0) << seed;
  }
}

TEST(Surrogate, OptionsAndWhereItIsNotRun) {
  SurrogateOptions o;
  o.count = 0;
  EXPECT_THROW(o.validate(), OptionError);
  o = {};
  o.significance = 1.0;
  EXPECT_THROW(o.validate(), OptionError);
  EXPECT_THROW(iaaft_surrogate({1.0, 1.0, 1.0, 1.0}, 1, 10), InputError);
  EXPECT_THROW(iaaft_surrogate({1.0, 2.0}, 1, 10), InputError);
  EXPECT_THROW(iaaft_surrogates({}, 1, 10), InputError);
  EXPECT_THROW(iaaft_surrogates({{1.0, 2.0, 3.0, 4.0}, {1.0, 2.0, 3.0}}, 1, 10), InputError);  // unequal lengths
  EXPECT_THROW(iaaft_surrogates({{1.0, 2.0, 3.0, 4.0}, {5.0, 5.0, 5.0, 5.0}}, 1, 10), InputError);  // a constant channel
  // By default only where the curve alone reads chaos: not on a decay, nor when turned off.
  EXPECT_FALSE(estimate_mlce(make_series_with_step({reference::damped_oscillator(2000, 0.01, 0.05, 2.0 * std::numbers::pi)}, 0.01), {})
                   .surrogates.has_value());
  EXPECT_FALSE(estimate_mlce(make_series_with_step({reference::henon_x(3000)}, 1.0), without_surrogates()).surrogates.has_value());
  const MlceResult henon = estimate_mlce(make_series_with_step({reference::henon_x(3000)}, 1.0), {});
  ASSERT_TRUE(henon.surrogates.has_value());
  EXPECT_EQ(henon.surrogates->samples, 3000u);  // shorter than the default's 4096: the whole series
  EXPECT_TRUE(henon.surrogates->distinguished);
}

// The default test, where the curve alone reads chaos, on the series' first 4096 samples: an AR(2)
// resonance (a stable linear filter driven by noise) no longer reads chaotic, and Lorenz x and the
// logistic map still do, far above their surrogates.
TEST(Surrogate, ByDefaultAChaoticReadingIsTestedOnTheFirstSamples) {
  for (const std::uint64_t seed : {1, 2, 3, 4}) {
    const Series ar2 = make_series_with_step({reference::ar2_resonance(10000, 0.99, 0.2, seed)}, 1.0);
    const MlceResult untested = estimate_mlce(ar2, without_surrogates());
    const MlceResult r = estimate_mlce(ar2, {});
    std::printf("AR(2) seed %d: without the test %s; by default %s (%s)\n", static_cast<int>(seed),
                read_stability(untested).motion.c_str(), read_stability(r).motion.c_str(),
                r.surrogates ? fmt::format("p = {:.2f}, {:.2f} sigmas on {} samples", r.surrogates->p_value,
                                           r.surrogates->sigmas, r.surrogates->samples).c_str()
                             : "not tested");
    EXPECT_NE(read_stability(r).motion, "chaotic") << seed;
    EXPECT_EQ(r.surrogates.has_value(), read_stability(untested).motion == "chaotic") << seed;
    if (r.surrogates) {
      EXPECT_EQ(r.surrogates->samples, 4096u);
    }
  }
  for (const auto& [name, x, dt] : {std::tuple{"Lorenz x", reference::lorenz_x(10000), 0.01},
                                    std::tuple{"logistic", reference::logistic(10000), 1.0}}) {
    const MlceResult r = estimate_mlce(make_series_with_step({x}, dt), {});
    ASSERT_TRUE(r.surrogates.has_value()) << name;
    std::printf("%s: %.1f sigmas above its surrogates on %zu of %zu samples, %.1f IAAFT passes\n", name,
                r.surrogates->sigmas, r.surrogates->samples, r.surrogates->of_samples, r.surrogates->mean_passes);
    EXPECT_EQ(r.surrogates->samples, 4096u) << name;
    EXPECT_EQ(r.surrogates->of_samples, r.n_points) << name;
    EXPECT_TRUE(r.surrogates->distinguished) << name;
    EXPECT_GT(r.surrogates->sigmas, 10.0) << name;
    EXPECT_EQ(read_stability(r).motion, "chaotic") << name;
  }
}

// The test on the first max_samples is the test of those samples: the same slopes, bit for bit, as
// on the series cut there by hand; and it keeps at least 8 x the fit region's embedded span.
TEST(Surrogate, ALeadingSegmentIsTheTestOfThatSegment) {
  const Series lorenz = make_series_with_step({reference::lorenz_x(10000)}, 0.01);
  SurrogateSetup setup;
  setup.dim = 3, setup.delay = 17, setup.theiler = 160, setup.first = 80, setup.last = 300;
  SurrogateOptions head;
  head.count = 5, head.iterations = 30, head.max_samples = 4096;
  const SurrogateTest on_head = surrogate_test(lorenz, setup, head);
  Series cut = lorenz;
  cut.channels[0].resize(4096);
  SurrogateOptions whole = head;
  whole.max_samples = 0;
  const SurrogateTest on_cut = surrogate_test(cut, setup, whole);
  EXPECT_EQ(on_head.samples, 4096u);
  EXPECT_EQ(on_head.of_samples, 10000u);
  EXPECT_EQ(on_cut.samples, 4096u);
  EXPECT_EQ(on_head.series_slope, on_cut.series_slope);
  EXPECT_EQ(on_head.surrogate_slopes, on_cut.surrogate_slopes);
  EXPECT_LE(on_head.mean_passes, 30.0);
  head.max_samples = 16;  // below 8 x ((m - 1) delay + last + 1) = 8 x 335
  EXPECT_EQ(surrogate_test(lorenz, setup, head).samples, 8u * (2 * 17 + 300 + 1));
  // Made one at a time (one thread), the surrogates and their slopes are those made side by side.
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const SurrogateTest serial = surrogate_test(lorenz, setup, SurrogateOptions{.count = 5, .iterations = 30, .max_samples = 4096});
  omp_set_num_threads(threads);
  EXPECT_EQ(serial.surrogate_slopes, on_head.surrogate_slopes);
  // A leading segment that holds still has no surrogates of its own: the test takes the whole series.
  Series still_start = lorenz;
  std::fill_n(still_start.channels[0].begin(), 5000, still_start.channels[0][5000]);
  EXPECT_EQ(surrogate_test(still_start, setup, head).samples, 10000u);
  Series constant = lorenz;
  std::fill(constant.channels[0].begin(), constant.channels[0].end(), 1.0);
  EXPECT_THROW(surrogate_test(constant, setup, head), InputError);
}

namespace {
/// Pearson's correlation of x(t) and y(t + lag) over the samples both cover (direct sums).
double lagged_correlation(const std::vector<double>& x, const std::vector<double>& y, int lag) {
  const std::size_t n = x.size(), shift = static_cast<std::size_t>(std::abs(lag));
  double mx = 0.0, my = 0.0;
  for (double v : x) mx += v;
  for (double v : y) my += v;
  mx /= static_cast<double>(n), my /= static_cast<double>(n);
  double sxy = 0.0, sxx = 0.0, syy = 0.0;
  for (std::size_t i = 0; i + shift < n; ++i) {
    const double a = x[lag >= 0 ? i : i + shift] - mx, b = y[lag >= 0 ? i + shift : i] - my;
    sxy += a * b, sxx += a * a, syy += b * b;
  }
  return sxy / std::sqrt(sxx * syy);
}
}  // namespace

// Multivariate IAAFT (Schreiber and Schmitz 2000): each channel keeps its values and spectrum, the
// channels keep how they move together -- their correlation at every lag, which the univariate
// surrogates of each channel on its own lose -- and one channel is the univariate surrogate.
TEST(Surrogate, MultivariateSurrogatesKeepHowTheChannelsMoveTogether) {
  const std::array<double, 3> start = {1.0, 1.0, 1.0};
  const std::vector<double> x = reference::lorenz(2048, 0.01, start, 50.0, 0), y = reference::lorenz(2048, 0.01, start, 50.0, 1);
  // One channel: the univariate surrogate, bit for bit (the same shuffle, the same passes).
  std::size_t one_passes = 0, single_passes = 0;
  EXPECT_EQ(iaaft_surrogates({x}, 7, 200, &one_passes).front(), iaaft_surrogate(x, 7, 200, &single_passes));
  EXPECT_EQ(one_passes, single_passes);
  // A channel twice: after the first pass both channels are turned alike, so they end equal.
  const std::vector<std::vector<double>> twice = iaaft_surrogates({x, x}, 7, 200);
  EXPECT_EQ(twice[0], twice[1]);
  EXPECT_NE(twice[0], x);

  std::size_t passes = 0;
  const std::vector<std::vector<double>> s = iaaft_surrogates({x, y}, 7, 200, &passes);
  ASSERT_EQ(s.size(), 2u);
  for (std::size_t c = 0; c < 2; ++c) {
    std::vector<double> a(c == 0 ? x : y), b(s[c]);
    std::sort(a.begin(), a.end()), std::sort(b.begin(), b.end());
    EXPECT_EQ(a, b) << c;  // the very values
    const std::vector<double> pa = periodogram(c == 0 ? x : y), pb = periodogram(s[c]);
    double total = 0.0, difference = 0.0;
    for (std::size_t k = 0; k < pa.size(); ++k) total += pa[k], difference += std::abs(pa[k] - pb[k]);
    EXPECT_LT(difference / total, 0.05) << c;
  }
  EXPECT_NE(s[0], x);
  // The cross-correlation at lags -50..50 samples (Lorenz x and y: +0.88 at lag 0), against the
  // univariate surrogates of each channel made on its own, which keep each spectrum only.
  const std::vector<double> ux = iaaft_surrogate(x, 7, 200), uy = iaaft_surrogate(y, 8, 200);
  double worst = 0.0, univariate_at_0 = 0.0;
  for (int lag = -50; lag <= 50; lag += 5) {
    const double truth = lagged_correlation(x, y, lag);
    worst = std::max(worst, std::abs(lagged_correlation(s[0], s[1], lag) - truth));
    if (lag == 0) univariate_at_0 = lagged_correlation(ux, uy, 0);
  }
  std::printf("Lorenz (x, y), 2048 samples, %zu passes: cross-correlation at lags -50..50 within %.3f of the series'; "
              "univariate surrogates: %.3f at lag 0 against the series' %.3f\n",
              passes, worst, univariate_at_0, lagged_correlation(x, y, 0));
  EXPECT_LT(worst, 0.05);
  EXPECT_GT(std::abs(univariate_at_0 - lagged_correlation(x, y, 0)), 0.3);
}

// A joint embedding of one stable linear mode driven by noise (displacement and velocity, exponent
// -zeta omega = -0.314 1/s) reads "unstable, chaotic" from its curve alone; by default its
// multivariate surrogates now test it, and it is not read chaotic. Lorenz (x, z) embedded jointly
// still is, far above its surrogates.
TEST(Surrogate, AJointEmbeddingIsTestedWithMultivariateSurrogates) {
  std::size_t untested_chaotic = 0;
  for (const std::uint64_t seed : {1001, 1002, 1003}) {
    reference::NoiseDrivenMode mode = reference::noise_driven_oscillator(10000, 0.01, 0.05, 2.0 * std::numbers::pi, seed);
    const Series joint = make_series_with_step({std::move(mode.q), std::move(mode.v)}, 0.01);
    const MlceResult untested = estimate_mlce(joint, without_surrogates());
    const MlceResult r = estimate_mlce(joint, {});
    if (read_stability(untested).motion == "chaotic") ++untested_chaotic;
    std::printf("mode (q, v) seed %d: lambda %+.3f 1/s; without the test %s; by default %s (%s)\n", static_cast<int>(seed),
                r.lambda, read_stability(untested).motion.c_str(), read_stability(r).motion.c_str(),
                r.surrogates ? fmt::format("p = {:.2f}, {:.2f} sigmas", r.surrogates->p_value, r.surrogates->sigmas).c_str()
                             : "not tested");
    EXPECT_NE(read_stability(r).motion, "chaotic") << seed;
    EXPECT_EQ(r.surrogates.has_value(), read_stability(untested).motion == "chaotic") << seed;
    if (r.surrogates) {
      EXPECT_FALSE(r.surrogates->distinguished) << seed;
      EXPECT_EQ(r.surrogates->channels, 2u);
      const std::string summary = read_stability(r).summary;  // says which surrogates it was not told from
      EXPECT_NE(summary.find("cross-spectra (multivariate IAAFT)"), std::string::npos) << summary;
    }
  }
  EXPECT_GE(untested_chaotic, 2u);  // what the test is for: the curve alone reads chaos here
  const std::array<double, 3> start = {1.0, 1.0, 1.0};
  const Series lorenz = make_series_with_step(
      {reference::lorenz(10000, 0.01, start, 50.0, 0), reference::lorenz(10000, 0.01, start, 50.0, 2)}, 0.01);
  const MlceResult r = estimate_mlce(lorenz, {});
  ASSERT_TRUE(r.surrogates.has_value());
  std::printf("Lorenz (x, z): lambda %.3f 1/s, %.1f sigmas above its surrogates\n", r.lambda, r.surrogates->sigmas);
  EXPECT_TRUE(r.surrogates->distinguished);
  EXPECT_GT(r.surrogates->sigmas, 10.0);
  EXPECT_EQ(read_stability(r).motion, "chaotic");
}

// End matching (several channels): the segment chosen is, by brute force over the same candidates,
// the one whose wrap steps least in each channel's own step size; on a motion of exact period 100
// samples the ends meet at a whole number of periods; and the test on that segment is, bit for bit,
// the test of the segment cut by hand (with end matching off).
TEST(Surrogate, SeveralChannelsAreTestedOnTheSegmentWhoseEndsMeet) {
  const std::array<double, 3> start = {1.0, 1.0, 1.0};
  const std::vector<std::vector<double>> xz = {reference::lorenz(6000, 0.01, start, 50.0, 0),
                                               reference::lorenz(6000, 0.01, start, 50.0, 2)};
  const std::size_t length = 4096, min_length = 3000;
  const EndMatch m = match_ends(xz, length, min_length);
  // Brute force: every start in the first tenth, every length down to a fifth shorter (not below min_length).
  std::vector<double> step(2, 0.0);
  for (std::size_t c = 0; c < 2; ++c) {
    for (std::size_t i = 1; i < length; ++i) step[c] += (xz[c][i] - xz[c][i - 1]) * (xz[c][i] - xz[c][i - 1]);
    step[c] /= static_cast<double>(length - 1);
  }
  double best = 1e300;
  std::size_t best_first = 0, best_samples = 0;
  for (std::size_t s = 0; s < length / 10; ++s)
    for (std::size_t l = std::max(min_length, length - length / 5); l <= length; ++l) {
      double j = 0.0;
      for (std::size_t c = 0; c < 2; ++c) j += std::pow(xz[c][s + l] - xz[c][s], 2) / step[c];
      if (j < best) best = j, best_first = s, best_samples = l;
    }
  std::printf("Lorenz (x, z): ends meet on samples %zu..%zu, jump %.3g steps^2 (the leading 4096: %.3g)\n", m.first,
              m.first + m.samples - 1, m.jump,
              std::pow(xz[0][length] - xz[0][0], 2) / step[0] + std::pow(xz[1][length] - xz[1][0], 2) / step[1]);
  EXPECT_EQ(m.first, best_first);
  EXPECT_EQ(m.samples, best_samples);
  EXPECT_NEAR(m.jump, best, 1e-9 * best);
  EXPECT_LT(m.jump, 0.01);
  // A motion of period 100 samples: its ends meet after whole periods.
  std::vector<std::vector<double>> circle(2, std::vector<double>(5000));
  for (std::size_t i = 0; i < 5000; ++i)
    circle[0][i] = std::sin(2.0 * std::numbers::pi * static_cast<double>(i % 100) / 100.0),
    circle[1][i] = std::cos(2.0 * std::numbers::pi * static_cast<double>(i % 100) / 100.0);
  const EndMatch periodic = match_ends(circle, 4096, 100);
  EXPECT_EQ(periodic.samples % 100, 0u);
  EXPECT_EQ(periodic.jump, 0.0);
  // The whole series: a segment that ends before its last sample. No room above min_length: no choice.
  const EndMatch whole = match_ends(xz, 6000, 100);
  EXPECT_LT(whole.first + whole.samples, 6000u);
  EXPECT_GE(whole.samples, 6000u - 6000u / 5 - whole.first);
  EXPECT_EQ(match_ends(xz, 4096, 4096).samples, 4096u);
  EXPECT_EQ(match_ends(xz, 4096, 4096).first, 0u);
  EXPECT_THROW(match_ends(xz, 6001, 100), InputError);

  // The test on the matched segment is the test of that segment cut by hand.
  const Series series = make_series_with_step(xz, 0.01);
  SurrogateSetup setup;
  setup.dim = 2, setup.delay = 17, setup.theiler = 160, setup.first = 60, setup.last = 250;
  const SurrogateOptions o{.count = 5, .iterations = 30, .max_samples = 4096};
  const SurrogateTest matched = surrogate_test(series, setup, o);
  EXPECT_EQ(matched.first_sample, m.first);
  EXPECT_EQ(matched.samples, m.samples);
  EXPECT_DOUBLE_EQ(matched.end_jump, m.jump);
  Series cut = series;
  for (auto& c : cut.channels)
    c = std::vector<double>(c.begin() + static_cast<std::ptrdiff_t>(m.first), c.begin() + static_cast<std::ptrdiff_t>(m.first + m.samples));
  SurrogateOptions by_hand = o;
  by_hand.max_samples = 0, by_hand.match_ends = false;
  const SurrogateTest on_cut = surrogate_test(cut, setup, by_hand);
  EXPECT_EQ(on_cut.first_sample, 0u);
  EXPECT_TRUE(std::isnan(on_cut.end_jump));
  EXPECT_EQ(matched.series_slope, on_cut.series_slope);
  EXPECT_EQ(matched.surrogate_slopes, on_cut.surrogate_slopes);
  EXPECT_EQ(segment_words(matched), fmt::format("samples {}..{} of 6000", m.first, m.first + m.samples - 1));
  // One channel: the leading segment, end matching or not.
  const SurrogateTest one = surrogate_test(make_series_with_step({xz[0]}, 0.01), setup, o);
  EXPECT_EQ(one.first_sample, 0u);
  EXPECT_EQ(one.samples, 4096u);
}
