// A map settled on a periodic cycle (map_cycle.hpp): the cycle found in the samples, and its
// exponent read from the approach, against the exponent of the cycle itself, (1/p) ln |mu| of its
// multiplier mu = prod f'(x_i) over its points, computed from the map's derivative on the settled
// cycle (an independent truth: no series, no fit), and for the logistic 2-cycle analytically
// (mu = 4 + 2 r - r^2).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mlce/estimate.hpp"
#include "mlce/map_cycle.hpp"
#include "mlce/reading.hpp"
#include "reference_systems.hpp"

namespace {

using namespace mlce;

/// The logistic map's orbit from x0, with no iteration discarded: the approach to its attractor included.
std::vector<double> logistic_from(double x0, double r, std::size_t n) {
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i, x0 = r * x0 * (1.0 - x0)) x[i] = x0;
  return x;
}

/// The exponent of the logistic map's attracting p-cycle: the mean of ln |f'(x)| = ln |r (1 - 2 x)| over
/// its p points, found by iterating 10^5 times from 0.1 (an attracting cycle: the orbit is on it by then).
double logistic_cycle_exponent(double r, std::size_t p) {
  double x = 0.1;
  for (int i = 0; i < 100000; ++i) x = r * x * (1.0 - x);
  double sum = 0.0;
  for (std::size_t i = 0; i < p; ++i, x = r * x * (1.0 - x)) sum += std::log(std::abs(r * (1.0 - 2.0 * x)));
  return sum / static_cast<double>(p);
}

/// Henon x -> 1 - a x^2 + y, y -> 0.3 x from (0.1, 0.1), no iteration discarded.
std::vector<double> henon_from(double a, std::size_t n) {
  std::vector<double> out(n);
  double x = 0.1, y = 0.1;
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = x;
    const double xn = 1.0 - a * x * x + y;
    y = 0.3 * x, x = xn;
  }
  return out;
}

/// The largest exponent of Henon's attracting p-cycle: the larger |eigenvalue| of the product of the
/// Jacobians [[-2 a x, 1], [0.3, 0]] over its p points (after 10^5 iterations), (1/p) ln of it.
double henon_cycle_exponent(double a, std::size_t p) {
  double x = 0.1, y = 0.1;
  for (int i = 0; i < 100000; ++i) {
    const double xn = 1.0 - a * x * x + y;
    y = 0.3 * x, x = xn;
  }
  std::array<double, 4> m{1, 0, 0, 1};  // row-major
  for (std::size_t i = 0; i < p; ++i) {
    const std::array<double, 4> j{-2.0 * a * x, 1.0, 0.3, 0.0};
    m = {j[0] * m[0] + j[1] * m[2], j[0] * m[1] + j[1] * m[3], j[2] * m[0] + j[3] * m[2], j[2] * m[1] + j[3] * m[3]};
    const double xn = 1.0 - a * x * x + y;
    y = 0.3 * x, x = xn;
  }
  const double tr = m[0] + m[3], det = m[0] * m[3] - m[1] * m[2];
  const double disc = tr * tr / 4.0 - det;  // real eigenvalues for the cycles tested (asserted by the caller)
  return std::log(std::abs(tr / 2.0) + std::sqrt(std::max(disc, 0.0))) / static_cast<double>(p);
}

Series of(const std::vector<double>& x, double scale = 1.0) {
  std::vector<double> y(x);
  for (double& v : y) v *= scale;
  return make_series_with_step({y}, 1.0, "");
}

}  // namespace

TEST(MapCycle, TheLogisticMapsCyclesAndTheirExponentsFromTheApproach) {
  // r = 3.2: mu = 4 + 2r - r^2 = 0.16 (analytic); the others from the map's derivative on the cycle.
  EXPECT_NEAR(logistic_cycle_exponent(3.2, 2), std::log(0.16) / 2.0, 1e-12);
  struct Case { double r; std::size_t p; };
  for (const Case c : {Case{3.2, 2}, Case{3.5, 4}, Case{3.74, 5}, Case{3.83, 3}}) {
    const MapCycle cycle = map_cycle(of(logistic_from(0.1, c.r, 2000)));
    const double truth = logistic_cycle_exponent(c.r, c.p);
    std::printf("r = %.2f: period %zu from sample %zu, approach %.6f per sample (95 %% %.6f .. %.6f) over %zu..%zu, "
                "%zu cycles; the cycle's exponent %.6f\n",
                c.r, cycle.period, cycle.from, cycle.approach_rate, cycle.approach_ci_low, cycle.approach_ci_high,
                cycle.approach_first, cycle.approach_last, cycle.approach_cycles, truth);
    EXPECT_EQ(cycle.period, c.p) << "r = " << c.r;
    ASSERT_TRUE(cycle.approach_measured()) << "r = " << c.r;
    EXPECT_NEAR(cycle.approach_rate, truth, 0.002 * std::abs(truth)) << "r = " << c.r;
    EXPECT_LE(cycle.approach_ci_low, truth) << "r = " << c.r;
    EXPECT_GE(cycle.approach_ci_high, truth) << "r = " << c.r;
  }
}

TEST(MapCycle, HenonsSevenCycleAndItsLargestExponent) {
  const MapCycle cycle = map_cycle(of(henon_from(1.3, 3000)));
  const double truth = henon_cycle_exponent(1.3, 7);
  std::printf("Henon a = 1.3: period %zu from %zu, approach %.6f (%.6f .. %.6f), %zu cycles; the cycle's %.6f\n",
              cycle.period, cycle.from, cycle.approach_rate, cycle.approach_ci_low, cycle.approach_ci_high,
              cycle.approach_cycles, truth);
  EXPECT_EQ(cycle.period, 7u);
  ASSERT_TRUE(cycle.approach_measured());
  // Two multipliers: the second one's share of the deviation (its exponent -0.967, the pair summing
  // to ln 0.3) fades only at -0.73 per sample relative to the first's, and leaves the fit 1.3 % off.
  EXPECT_NEAR(cycle.approach_rate, truth, 0.02 * std::abs(truth));
  EXPECT_LE(cycle.approach_ci_low, truth);
  EXPECT_GE(cycle.approach_ci_high, truth);
}

TEST(MapCycle, ChaoticMapsAndAFlowHaveNone) {
  EXPECT_FALSE(map_cycle(of(reference::logistic(10000))).found());
  EXPECT_FALSE(map_cycle(of(reference::henon_x(10000))).found());
  for (const double r : {3.58, 3.6, 3.65})  // banded: their bands repeat, their points do not
    EXPECT_FALSE(map_cycle(of(reference::logistic(10000, 0.1234567, r))).found()) << "r = " << r;
  // A map that settles on a cycle at 1e-6 of its range and then keeps moving does not repeat to 1e-9.
  std::vector<double> x = logistic_from(0.1, 3.2, 2000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] += 1e-6 * std::sin(0.1 * static_cast<double>(i));
  EXPECT_FALSE(map_cycle(of(x)).found());
}

TEST(MapCycle, ScaleFreeAndAtTheWrittenResolution) {
  const std::vector<double> x = logistic_from(0.1, 3.83, 2000);
  const MapCycle plain = map_cycle(of(x));
  for (const double scale : {1e-200, 1e200}) {
    const MapCycle scaled = map_cycle(of(x, scale));
    EXPECT_EQ(scaled.period, plain.period);
    EXPECT_NEAR(scaled.approach_rate, plain.approach_rate, 1e-9 * std::abs(plain.approach_rate)) << scale;
  }
  // Written with 6 digits: the cycle repeats exactly, its approach lies within 100 quanta of the
  // ceiling: no rate, and no rate taken from the quanta's steps.
  std::vector<double> written(x);
  for (double& v : written) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v);
    v = std::stod(text);
  }
  const MapCycle coarse = map_cycle(of(written));
  EXPECT_EQ(coarse.period, 3u);
  EXPECT_FALSE(coarse.approach_measured()) << coarse.approach_rate;
}

TEST(MapCycle, TheEstimateAndItsReading) {
  // With the approach: lambda is the cycle's exponent; the curve's neighbours are the cycle's points.
  const MlceResult approach = estimate_mlce(of(logistic_from(0.1, 3.83, 2000)), {});
  const double truth = logistic_cycle_exponent(3.83, 3);
  EXPECT_NEAR(approach.lambda, truth, 0.002 * std::abs(truth));
  EXPECT_TRUE(std::isfinite(approach.curve_lambda));
  const Reading with = read_stability(approach);
  std::printf("with the approach: lambda %.6f (curve %.6f): %s\n", approach.lambda, approach.curve_lambda,
              with.summary.c_str());
  EXPECT_EQ(with.stability, Stability::stable);
  EXPECT_EQ(with.motion, "periodic orbit");
  // Settled from the start (the reference series discard 100 iterations): no rate, stable.
  const MlceResult settled = estimate_mlce(of(reference::logistic(10000, 0.1234567, 3.5)), {});
  EXPECT_EQ(settled.map_cycle.period, 4u);
  EXPECT_FALSE(settled.map_cycle.approach_measured());
  EXPECT_FALSE(settled.unreliable.empty());
  const Reading without = read_stability(settled);
  std::printf("settled: lambda %.6f: %s\n", settled.lambda, without.summary.c_str());
  EXPECT_EQ(without.stability, Stability::stable);
  EXPECT_EQ(without.motion, "periodic orbit");
  EXPECT_LT(settled.map_cycle.rate_bound, 0.01);
  // A chaotic map keeps its reading and has no cycle.
  const MlceResult chaotic = estimate_mlce(of(reference::logistic(10000)), {});
  EXPECT_FALSE(chaotic.map_cycle.found());
  EXPECT_TRUE(std::isnan(chaotic.curve_lambda));
}
