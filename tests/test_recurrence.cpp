// Does the start of a series recur? The window rule against neighbour indices built by hand, where
// the answer is known exactly, and the estimator on Lorenz's start-up spiral.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "mlce/estimate.hpp"
#include "mlce/recurrence.hpp"
#include "reference_systems.hpp"

using namespace mlce;

namespace {

/// Every admissible point a reference; points before `transient` have their neighbour among
/// themselves (100 samples on, cyclically within their block of 200), later points a uniformly random one outside the Theiler
/// window: on average a share (A - after) / A of them lies after any index `after`.
NeighbourPairs hand_made_pairs(std::size_t A, std::size_t theiler, std::size_t transient, std::uint64_t seed) {
  NeighbourPairs p;
  p.theiler = theiler, p.dim = 1, p.delay = 1, p.horizon = 1;
  std::mt19937_64 gen(seed);
  std::uniform_int_distribution<std::uint32_t> any(0, static_cast<std::uint32_t>(A - 1));
  for (std::uint32_t j = 0; j < A; ++j) {
    p.references.push_back(j);
    std::uint32_t n;
    if (j < transient) {
      const std::uint32_t block = j / 200 * 200;
      n = block + (j - block + 100) % 200;
    } else {
      do n = any(gen);
      while ((n > j ? n - j : j - n) <= theiler);
    }
    p.nearest.neighbour.push_back(n);
    p.nearest.distance.push_back(1.0);
  }
  return p;
}

}  // namespace

TEST(Recurrence, StartIsTheInitialRunOfWindowsWhoseNeighboursStayAmongThemselves) {
  RecurrenceOptions o;
  o.window = 200;
  const auto r = recurrent_start(hand_made_pairs(10000, 50, 600, 1), 10000, o);
  EXPECT_EQ(r.start, 600u);
  ASSERT_GE(r.ratio.size(), 20u);  // windows ending (with the Theiler window) in the first half: (5000 - 50) / 200
  EXPECT_EQ(r.ratio.size(), 24u);
  for (std::size_t w = 0; w < 3; ++w) EXPECT_EQ(r.ratio[w], 0.0) << w;
  // Later windows: 200 uniform neighbours each, the share after the window over its expectation.
  // Binomial: standard deviation sqrt((1 - p) / (200 p)) <= 0.07 for p >= 1/2; 5 of them allowed.
  for (std::size_t w = 3; w < r.ratio.size(); ++w) EXPECT_NEAR(r.ratio[w], 1.0, 0.35) << w;
}

TEST(Recurrence, ALaterWindowThatDoesNotRecurIsNotAStart) {
  // The same, but with the first windows recurrent and window 5 made of self-neighbours (an
  // excursion the series visits once): it is not a transient at the start, nothing is left out.
  auto p = hand_made_pairs(10000, 50, 0, 2);
  for (std::uint32_t j = 1000; j < 1200; ++j) p.nearest.neighbour[j] = 1000 + (j - 1000 + 100) % 200;
  RecurrenceOptions o;
  o.window = 200;
  const auto r = recurrent_start(p, 10000, o);
  EXPECT_EQ(r.start, 0u);
  EXPECT_EQ(r.ratio[5], 0.0);
}

TEST(Recurrence, WindowsWhereTheMotionJoinsTheAttractorAreKept) {
  // Windows 0..4 of 200 points score 0.1, 0.6, 0.2, 0.5, 0.9 by construction (that share of the
  // expected later neighbours sent to the series' end, the rest kept in the window), the rest
  // uniform. The start ends with window 2, the last below 0.3 before the first at 0.8 or more;
  // windows 1 and 3 are partial and do not decide. Starts that never score below 0.3 are no clear
  // transient, a first window at 0.5 or more is on the attractor, and a single window below 0.3 is
  // a dip: nothing is cut.
  const std::size_t A = 10000, theiler = 50, L = 200;
  auto scored = [&](std::vector<double> targets) {
    auto p = hand_made_pairs(A, theiler, L * targets.size(), 4);
    for (std::size_t w = 0; w < targets.size(); ++w) {
      const double expected = static_cast<double>(A - (w + 1) * L - theiler) / static_cast<double>(A);
      const auto later = static_cast<std::size_t>(std::lround(targets[w] * expected * L));
      for (std::size_t i = 0; i < later; ++i) p.nearest.neighbour[w * L + i] = static_cast<std::uint32_t>(A - 1 - i);
    }
    RecurrenceOptions o;
    o.window = L;
    return recurrent_start(p, A, o);
  };
  const auto joins = scored({0.1, 0.6, 0.2, 0.5, 0.9});
  for (std::size_t w = 0; w < 5; ++w) EXPECT_NEAR(joins.ratio[w], std::vector<double>({0.1, 0.6, 0.2, 0.5, 0.9})[w], 0.01) << w;
  EXPECT_EQ(joins.start, 3 * L);
  EXPECT_EQ(scored({0.45, 0.1, 0.2}).start, 3 * L);  // then uniform windows, scoring ~1
  EXPECT_EQ(scored({0.45, 0.6}).start, 0u);          // never clearly a transient
  EXPECT_EQ(scored({0.6, 0.1, 0.1}).start, 0u);      // starts on the attractor: an excursion follows
  EXPECT_EQ(scored({0.1, 0.9}).start, 0u);           // one low window: a dip, not told from a start-up
}

TEST(Recurrence, OneLowWindowFarFromTheRestIsAStartUpOneNearItADip) {
  // The pairs of hand_made_pairs with one self-neighbouring window (score 0, then ~1: the scores
  // alone keep it), and the series' values, embedded in one dimension, deciding by distance. The
  // second half is uniform in [0, 1); the first window lies at 100 (never visited again: ratio
  // ~10^6, left out), or in [0, 1) as everything else (a dip: ratio ~1, kept), or the whole first
  // half lies at 100 (a drift: the first half's typical distance to the second is as large, the
  // ratio ~1, kept). A first window that scores as recurring is not judged by distance at all.
  const std::size_t A = 5000, theiler = 50, L = 200;
  auto series = [&](std::size_t far_points) {
    std::mt19937_64 gen(9);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<double> x(A);
    for (std::size_t i = 0; i < A; ++i) x[i] = (i < far_points ? 100.0 : 0.0) + u(gen);
    return x;
  };
  RecurrenceOptions o;
  o.window = L;
  const auto pairs = hand_made_pairs(A, theiler, L, 5);
  const auto start_up = series(L), dip = series(0), drift = series(A / 2);
  const DelayEmbedding start_up_points({std::span<const double>(start_up)}, 1, 1, A), dip_points({std::span<const double>(dip)}, 1, 1, A),
      drift_points({std::span<const double>(drift)}, 1, 1, A);
  EXPECT_EQ(recurrent_start(pairs, A, o).start, 0u);  // the scores alone: one low window, kept

  const auto cut = recurrent_start(pairs, A, o, &start_up_points);
  EXPECT_EQ(cut.ratio.front(), 0.0);
  ASSERT_EQ(cut.distance_ratio.size(), 2u);  // the far window, then the first near one
  EXPECT_GT(cut.distance_ratio[0], 1e4);
  EXPECT_LT(cut.distance_ratio[1], 3.0);
  EXPECT_GT(cut.distance_ratio[1], 0.3);
  EXPECT_TRUE(cut.by_distance);
  EXPECT_EQ(cut.start, L);

  const auto kept = recurrent_start(pairs, A, o, &dip_points);
  ASSERT_EQ(kept.distance_ratio.size(), 1u);
  EXPECT_LT(kept.distance_ratio[0], 3.0);
  EXPECT_FALSE(kept.by_distance);
  EXPECT_EQ(kept.start, 0u);

  const auto drifting = recurrent_start(pairs, A, o, &drift_points);
  ASSERT_EQ(drifting.distance_ratio.size(), 1u);
  EXPECT_NEAR(drifting.distance_ratio[0], 1.0, 0.1);
  EXPECT_EQ(drifting.start, 0u);

  const auto on_attractor = recurrent_start(hand_made_pairs(A, theiler, 0, 5), A, o, &start_up_points);
  EXPECT_TRUE(on_attractor.distance_ratio.empty());
  EXPECT_EQ(on_attractor.start, 0u);

  o.far = 1.0;
  EXPECT_THROW(recurrent_start(pairs, A, o, &start_up_points), OptionError);
}

TEST(Recurrence, DefaultWindowAndTooFewReferences) {
  // Default window: max(2 x Theiler, A / 50). Strided references: 10 per window of 200 are too
  // few to judge, and nothing is judged or cut.
  const auto all = hand_made_pairs(10000, 150, 600, 3);
  EXPECT_EQ(recurrent_start(all, 10000, {}).window, 300u);
  NeighbourPairs sparse;
  sparse.theiler = 50;
  for (std::size_t k = 0; k < all.references.size(); k += 20)
    sparse.references.push_back(all.references[k]), sparse.nearest.neighbour.push_back(all.nearest.neighbour[k]),
        sparse.nearest.distance.push_back(all.nearest.distance[k]);
  RecurrenceOptions o;
  o.window = 200;
  const auto r = recurrent_start(sparse, 10000, o);
  EXPECT_TRUE(r.ratio.empty());
  EXPECT_EQ(r.start, 0u);
  o.min_references = 0;  // a window with no reference is still not judged (no 0/0)
  EXPECT_TRUE(recurrent_start(NeighbourPairs{}, 40, o).ratio.empty());
  o.window = 0;  // automatic: max(1, 2 x Theiler, A / 50), never 0
  EXPECT_EQ(recurrent_start(NeighbourPairs{}, 40, o).window, 1u);
  o.transient = 0.9;  // above `recurrent`
  EXPECT_THROW(recurrent_start(sparse, 10000, o), OptionError);
}

// A reference whose neighbour lies at the data's resolution recurs wherever that neighbour lies
// (RecurrenceOptions::repeat_distance): the same self-neighbours as the first test, at 1e-8 instead
// of 1, are a motion that repeats itself one block on, not a start-up.
TEST(Recurrence, NeighboursAtTheDataResolutionRecurWhereverTheyLie) {
  auto pairs = hand_made_pairs(10000, 50, 600, 1);
  for (std::size_t k = 0; k < 600; ++k) pairs.nearest.distance[k] = 1e-8;
  RecurrenceOptions o;
  o.window = 200;
  const auto r = recurrent_start(pairs, 10000, o);
  EXPECT_EQ(r.start, 0u);
  ASSERT_GE(r.ratio.size(), 3u);
  for (std::size_t w = 0; w < 3; ++w) EXPECT_GE(r.ratio[w], o.recurrent) << w;
  o.repeat_distance = 0.0;  // no repeat credited: the windows' own neighbours make them a start-up
  EXPECT_EQ(recurrent_start(pairs, 10000, o).start, 600u);
  // An exact repeat passed over (NeighbourResult::repeated) is a distance 0: credited at any
  // repeat_distance >= 0, not when it is off (negative).
  for (std::size_t k = 0; k < 600; ++k) pairs.nearest.distance[k] = 1.0;
  pairs.nearest.repeated.assign(pairs.references.size(), 0);
  for (std::size_t k = 0; k < 600; ++k) pairs.nearest.repeated[k] = 1;
  EXPECT_EQ(recurrent_start(pairs, 10000, o).start, 0u);
  o.repeat_distance = -1.0;
  EXPECT_EQ(recurrent_start(pairs, 10000, o).start, 600u);
  o.repeat_distance = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(recurrent_start(pairs, 10000, o), OptionError);
  pairs.nearest.repeated.pop_back();  // one flag short: refused
  EXPECT_THROW(recurrent_start(pairs, 10000, RecurrenceOptions{}), std::invalid_argument);
  pairs.nearest.repeated.clear();
  pairs.nearest.distance.pop_back();  // one distance short: refused, never read past the end
  EXPECT_THROW(recurrent_start(pairs, 10000, RecurrenceOptions{}), std::invalid_argument);
}

/// "lo .. hi" of the windows' scores of `rec`, over the windows that end by `until` (all when 0).
std::string score_range(const RecurrenceResult& rec, std::size_t until) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t w = 0; w < rec.ratio.size() && (until == 0 || (w + 1) * rec.window <= until); ++w)
    lo = std::min(lo, rec.ratio[w]), hi = std::max(hi, rec.ratio[w]);
  char text[64];
  std::snprintf(text, sizeof text, "%.2f .. %.2f", lo, hi);
  return text;
}

// An exactly periodic signal visits every point of its start again each period: nothing is left
// out. Its neighbours are the same phase one period (100 samples) on, inside the same window of the
// rule, at rounding distance (~1e-13); judged by index alone (repeat_distance off) its first windows
// scored low and 2618 samples were cut as a "start-up" (printed).
TEST(Recurrence, ExactlyPeriodicSignalKeepsItsStart) {
  std::vector<double> x(10000);
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double t = 0.01 * static_cast<double>(i);
    x[i] = std::sin(2.0 * std::numbers::pi * t) + 0.5 * std::sin(6.0 * std::numbers::pi * t);
  }
  const auto series = make_series_with_step({x}, 0.01);
  const MlceResult r = estimate_mlce(series, {});
  MlceOptions by_index;
  by_index.recurrence.repeat_distance = -1.0;
  const MlceResult old = estimate_mlce(series, by_index);
  std::printf("sin 2 pi t + 0.5 sin 6 pi t: %zu samples left out, lambda %.4f (neighbours judged by index alone: "
              "%zu left out, windows up to the cut score %s)\n",
              r.skipped_start, r.lambda, old.skipped_start, score_range(old.recurrence, old.skipped_start).c_str());
  EXPECT_EQ(r.skipped_start, 0u);
  EXPECT_EQ(r.n_points, x.size());
  ASSERT_FALSE(r.recurrence.ratio.empty());
  for (double ratio : r.recurrence.ratio) EXPECT_GE(ratio, RecurrenceOptions{}.recurrent);
  for (const auto& w : r.warnings) EXPECT_EQ(w.find("do not recur"), std::string::npos) << w;
}

double printed_with_six_digits(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return std::strtod(text, nullptr);
}

// The same motion printed with six significant digits (MBDyn's default), as a rotating node's
// coordinates would be: its points repeat exactly, the zero distances are passed over, and the
// neighbour at a positive distance is another phase, often in the same window. The exact repeat
// (NeighbourResult::repeated) says the point recurs: every window scores about 1.
TEST(Recurrence, PeriodicSignalPrintedWithSixDigitsRecurs) {
  for (const double period : {100.0, 80.0}) {  // samples
    std::vector<double> x(10000), y(10000);
    for (std::size_t i = 0; i < x.size(); ++i) {
      const double phase = 2.0 * std::numbers::pi * static_cast<double>(i % static_cast<std::size_t>(period)) / period;
      x[i] = printed_with_six_digits(2.5 * std::cos(phase));
      y[i] = printed_with_six_digits(2.5 * std::sin(phase));
    }
    for (const auto& channels : {std::vector<std::vector<double>>{x}, std::vector<std::vector<double>>{x, y}}) {
      const auto series = make_series_with_step(channels, 0.01);
      const MlceResult r = estimate_mlce(series, {});
      MlceOptions by_index;
      by_index.recurrence.repeat_distance = -1.0;
      const MlceResult old = estimate_mlce(series, by_index);
      ASSERT_FALSE(r.recurrence.ratio.empty());
      std::printf("period %g samples, %zu channel(s), six digits: %zu samples left out, windows score %s (by index "
                  "alone: %zu left out, windows score %s)\n",
                  period, channels.size(), r.skipped_start, score_range(r.recurrence, 0).c_str(), old.skipped_start,
                  score_range(old.recurrence, 0).c_str());
      EXPECT_EQ(r.skipped_start, 0u);
      for (double ratio : r.recurrence.ratio) EXPECT_GE(ratio, RecurrenceOptions{}.recurrent);
    }
  }
}

// Lorenz from (1, 1, 1) with nothing discarded spirals out of the fixed point C- first, and its
// neighbour pairs there separate slowly: the whole series reads low. The estimator leaves the
// spiral out and reads lambda_1 within 5 %; kept, the start pulls it down.
TEST(Recurrence, LorenzStartUpSpiralIsLeftOut) {
  const auto x = reference::lorenz_x(10000, 0.01, {1.0, 1.0, 1.0}, 0.0);
  const auto series = make_series_with_step({x}, 0.01);
  const MlceResult r = estimate_mlce(series, {});
  MlceOptions keep;
  keep.skip_nonrecurrent_start = false;
  const MlceResult kept = estimate_mlce(series, keep);
  std::printf("Lorenz x from (1, 1, 1), nothing discarded: %zu samples left out, lambda %.4f (kept: %.4f)\n",
              r.skipped_start, r.lambda, kept.lambda);
  EXPECT_GT(r.skipped_start, 0u);
  EXPECT_LE(r.skipped_start, 2000u);
  EXPECT_EQ(r.n_points, 10000u - r.skipped_start);
  EXPECT_NEAR(r.lambda, 0.9056, 0.05 * 0.9056) << r.fit.rule;
  EXPECT_LT(std::abs(r.lambda - 0.9056), std::abs(kept.lambda - 0.9056));
  EXPECT_EQ(kept.skipped_start, 0u);
  EXPECT_FALSE(r.recurrence.ratio.empty());
  EXPECT_LT(r.recurrence.ratio.front(), RecurrenceOptions{}.transient);
  EXPECT_NE(r.warnings.front().find("do not recur"), std::string::npos) << r.warnings.front();
}

// Lorenz from a random start near the origin (mt19937 seed 1's 29th start of `finite_time_spread
// starts`), nothing discarded: its first window scores 0.35 and the next 0.00, then it recurs, so
// the scores see one low window only and keep the start (as a dip would be kept). Its first four
// windows come no nearer to the second half than 5 typical distances, and are left out; the
// estimate is then within 5 % of lambda_1, nearer than with the start kept or than the scores alone.
TEST(Recurrence, LorenzStartUpOfOneLowWindowIsLeftOutByDistance) {
  const auto x = reference::lorenz_x(10000, 0.01, {-0.86080969832381982, 1.5167301025649813, 0.76268365812864669}, 0.0);
  const auto series = make_series_with_step({x}, 0.01);
  const MlceResult r = estimate_mlce(series, {});
  MlceOptions keep, scores_only;
  keep.skip_nonrecurrent_start = false;
  scores_only.recurrence.far = 1e12;  // no window is that far: the distance test cuts nothing
  const MlceResult kept = estimate_mlce(series, keep), by_scores = estimate_mlce(series, scores_only);
  std::printf("Lorenz x from a start near the origin: %zu samples left out (ratios", r.skipped_start);
  for (double ratio : r.recurrence.distance_ratio) std::printf(" %.2f", ratio);
  std::printf("), lambda %.4f (kept: %.4f, scores only: %.4f)\n", r.lambda, kept.lambda, by_scores.lambda);
  EXPECT_EQ(by_scores.skipped_start, 0u);
  ASSERT_GE(r.recurrence.ratio.size(), 2u);
  EXPECT_LT(r.recurrence.ratio[0], RecurrenceOptions{}.first_below);
  EXPECT_TRUE(r.recurrence.by_distance);
  EXPECT_GT(r.skipped_start, 0u);
  EXPECT_LE(r.skipped_start, 2000u);
  EXPECT_EQ(r.skipped_start % r.recurrence.window, 0u);
  const std::size_t far_windows = r.skipped_start / r.recurrence.window;
  ASSERT_EQ(r.recurrence.distance_ratio.size(), far_windows + 1);
  for (std::size_t w = 0; w < far_windows; ++w) EXPECT_GE(r.recurrence.distance_ratio[w], RecurrenceOptions{}.far);
  EXPECT_LT(r.recurrence.distance_ratio.back(), RecurrenceOptions{}.far);
  EXPECT_NEAR(r.lambda, 0.9056, 0.05 * 0.9056) << r.fit.rule;
  EXPECT_LT(std::abs(r.lambda - 0.9056), std::abs(kept.lambda - 0.9056));
  EXPECT_NE(r.warnings.front().find("typical distance"), std::string::npos) << r.warnings.front();
}

// neighbour_drift against pairs built by hand: channel 1 is a level a i plus an oscillation of
// period P samples, channel 2 the oscillation alone, and every neighbour lies a whole number of
// periods away (both ways), so that the neighbour's delay coordinates differ from the reference's by
// exactly a Delta in channel 1 and by nothing in channel 2. The regression then recovers a, and with
// distances set to twice the drift's part (sqrt(m) |a Delta| / sd of channel 1), the drift's share
// of the squared distances is exactly 1/4.
TEST(NeighbourDrift, ALevelLinearInTimeIsRecoveredFromPairsAWholeNumberOfPeriodsApart) {
  constexpr std::size_t n = 3000, P = 50, m = 3, J = 7;
  constexpr double a = 2.5e-3;
  std::vector<double> level(n), plain(n);
  for (std::size_t i = 0; i < n; ++i) {
    plain[i] = std::sin(2.0 * std::numbers::pi * static_cast<double>(i % P) / P);
    level[i] = a * static_cast<double>(i) + 0.8 * plain[i];
  }
  double mean = 0.0, var = 0.0;
  for (double v : level) mean += v / n;
  for (double v : level) var += (v - mean) * (v - mean) / n;
  const double sd = std::sqrt(var);
  NeighbourPairs p;
  p.dim = m, p.delay = J, p.theiler = P - 1, p.horizon = 1;
  for (std::uint32_t j = 0; j < 2000; j += 3) {
    const std::uint32_t periods = 1 + j % 9;
    const std::uint32_t k = j >= 1000 ? j - periods * P : j + periods * P;
    const double lag = static_cast<double>(k) - static_cast<double>(j);
    p.references.push_back(j);
    p.nearest.neighbour.push_back(k);
    p.nearest.distance.push_back(2.0 * std::sqrt(static_cast<double>(m)) * std::abs(a * lag) / sd);
  }
  p.references.push_back(2001);  // a reference without a neighbour is passed over
  p.nearest.neighbour.push_back(NeighbourResult::none);
  p.nearest.distance.push_back(std::numeric_limits<double>::infinity());
  const Series s = make_series_with_step({plain, level}, 0.01);
  const NeighbourDrift d = neighbour_drift(s, p);
  EXPECT_EQ(d.pairs, p.references.size() - 1);
  EXPECT_EQ(d.channel, 1u);
  EXPECT_NEAR(d.rate_per_sample, a, 1e-9 * a);
  EXPECT_NEAR(d.share, 0.25, 1e-9);
  EXPECT_NEAR(d.over_run_in_deviations, a * n / sd, 1e-9 * a * n / sd);
  // The same with the channels' roles swapped in the pairs' eyes: a level that falls.
  std::vector<double> falling = level;
  for (std::size_t i = 0; i < n; ++i) falling[i] = -level[i];
  const NeighbourDrift f = neighbour_drift(make_series_with_step({falling, plain}, 0.01), p);
  EXPECT_EQ(f.channel, 0u);
  EXPECT_NEAR(f.rate_per_sample, -a, 1e-9 * a);
  EXPECT_NEAR(f.share, 0.25, 1e-9);
  // No pairs: nothing measured, share 0; pairs of mismatched lengths are a logic error.
  NeighbourPairs none = p;
  none.references.clear(), none.nearest.neighbour.clear(), none.nearest.distance.clear();
  EXPECT_EQ(neighbour_drift(s, none).share, 0.0);
  none.references.push_back(0);
  EXPECT_THROW(neighbour_drift(s, none), std::invalid_argument);
}
