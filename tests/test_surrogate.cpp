// The surrogate test of the divergence against linear noise (surrogate.hpp): IAAFT surrogates keep
// the series' values exactly and its power spectrum closely (checked against the series' own
// periodogram, their definition); chaotic series (Lorenz x, Henon x) are told from their
// surrogates, linear stochastic ones (an AR(2) resonance, which reads "chaotic" without the test)
// are not.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
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
  // Two channels embedded jointly: not run, and said so.
  const MlceResult two =
      estimate_mlce(make_series_with_step({reference::lorenz_x(4000), reference::lorenz(4000, 0.01, {1, 1, 1}, 50.0, 1)}, 0.01),
                    with_surrogates());
  EXPECT_FALSE(two.surrogates.has_value());
  EXPECT_TRUE(std::any_of(two.warnings.begin(), two.warnings.end(),
                          [](const std::string& w) { return w.find("surrogate test takes one channel") != std::string::npos; }));
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
