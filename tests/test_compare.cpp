// Two time histories side by side (mlce compare): differences against values known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "mlce/compare.hpp"

namespace {

struct History {
  std::vector<double> t, v;
};

/// f at t = t0 + k dt, the times accumulated by repeated addition as a solver does (so they drift
/// off the decimal grid by rounding: 1199 x 0.005 ends at 5.995000000000...).
template <class F>
History sampled(F f, double dt, std::size_t n) {
  History h;
  double t = 0.0;
  for (std::size_t k = 0; k < n; ++k, t += dt) h.t.push_back(t), h.v.push_back(f(t));
  return h;
}

}  // namespace

TEST(CompareHistories, ConstantOffsetIsTheDifferenceEverywhere) {
  const auto a = sampled([](double t) { return std::sin(t); }, 0.01, 1001);
  const auto b = sampled([](double t) { return std::sin(t) + 0.1; }, 0.01, 1001);
  const auto r = mlce::compare_histories(a.t, a.v, b.t, b.v, {});
  EXPECT_EQ(r.points, 1001u);
  EXPECT_NEAR(r.max_abs_difference, 0.1, 1e-12);
  EXPECT_NEAR(r.rms_difference, 0.1, 1e-12);
  EXPECT_NEAR(r.range_relative_difference, 0.0, 1e-12);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(CompareHistories, CoarserSecondHistoryDiffersByItsLinearInterpolationErrorOnly) {
  // At the midpoint m of two nodes h apart, sin(m) - its linear interpolant = sin(m) (1 - cos(h/2))
  // (~ h^2/8 sin m); A's odd samples are B's midpoints, the largest at m = 1.57 (sin m = 0.9999997).
  const auto a = sampled([](double t) { return std::sin(t); }, 0.01, 1001);
  const auto b = sampled([](double t) { return std::sin(t); }, 0.02, 501);
  const auto r = mlce::compare_histories(a.t, a.v, b.t, b.v, {});
  EXPECT_NEAR(r.max_abs_difference, std::sin(1.57) * (1 - std::cos(0.01)), 1e-12);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("sampled more coarsely"), std::string::npos);
}

TEST(CompareHistories, WindowEndsMatchAccumulatedTimesWithinRounding) {
  // A user's --from 1 --to 5.995 holds samples 200..1199 even though the accumulated times are a
  // rounding off 1 and 5.995.
  const auto a = sampled([](double t) { return std::cos(3 * t); }, 0.005, 2001);
  ASSERT_NE(a.t[1199], 5.995);
  mlce::HistoryComparisonOptions o;
  o.from = 1.0, o.to = 5.995;
  const auto r = mlce::compare_histories(a.t, a.v, a.t, a.v, o);
  EXPECT_EQ(r.points, 1000u);
  EXPECT_EQ(r.t_first, a.t[200]);
  EXPECT_EQ(r.t_last, a.t[1199]);
  EXPECT_EQ(r.max_abs_difference, 0.0);
}

TEST(CompareHistories, BadHistoriesAreRefusedNamingTheSample) {
  auto a = sampled([](double t) { return t; }, 0.1, 10);
  auto b = a;
  b.v[4] = std::nan("");
  try {
    mlce::compare_histories(a.t, a.v, b.t, b.v, {});
    ADD_FAILURE() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "second history: non-finite value at sample 4");
  }
  b = a;
  b.t[6] = b.t[5];
  EXPECT_THROW(mlce::compare_histories(a.t, a.v, b.t, b.v, {}), std::invalid_argument);
  mlce::HistoryComparisonOptions o;
  o.from = 20.0, o.to = 30.0;  // outside both runs: the message gives both spans and the window
  try {
    mlce::compare_histories(a.t, a.v, a.t, a.v, o);
    ADD_FAILURE() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "the two histories share fewer than 2 samples in the window: A spans t = 0..0.9, B 0..0.9, "
                           "the window is [20, 30]");
  }
  o.from = 0.0, o.to = std::nan("");  // would otherwise compare every sample
  EXPECT_THROW(mlce::compare_histories(a.t, a.v, a.t, a.v, o), std::invalid_argument);
}
