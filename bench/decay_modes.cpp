// Decays of several modes: the free response of a linear system, e^{-0.3 t} cos 2 pi t (the least
// damped mode: lambda_1 = -0.3 1/s exactly) plus one faster-decaying mode (rate -0.5, -1 or -3 1/s, at
// 0.45, 1.37 or 3.3 Hz, the slow mode's amplitude 0.2, 1 or 5 times the fast one's), dt = 0.01 s,
// 2000 and 4000 samples, without and with 0.1 % white noise; then two three-mode decays, a weak slow mode under a strong fast one, and
// growths of several modes: e^{0.3 t} cos 2 pi t beside a decaying or a slower growing mode.
// Every parameter automatic; each series is estimated with the fit rule's late region (decays:
// FitOptions::late_decay_share, growths: late_growth_share, 0.75 by default) and with it off (0: the
// growth rule's region, the rule before), and the warning that the decay slows along the curve is
// counted. The growths also print how much the signal grows over the curve's horizon (its second half's envelope rate x
// horizon, the fit's test for a signal that grows on its own: at least 0.5).
//   build/decay_modes        (about 10 s)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "mlce/estimate.hpp"
#include "ratio_tally.hpp"
#include "reference_systems.hpp"

namespace {

using mlce::bench::Tally;
using mlce::reference::DecayingMode;

bool warns(const mlce::MlceResult& r, const char* what) {
  for (const auto& w : r.warnings)
    if (w.find(what) != std::string::npos) return true;
  return false;
}

struct Row {
  double late, before;
  bool slowing;
  /// Each estimate warned that its neighbours converge faster than the signal decays.
  bool faster_late, faster_before;
  double signal_growth;  ///< end envelope rate x horizon of the default estimate (the fit's test)
};

Row estimate_both(const std::vector<double>& x, double dt) {
  const auto series = mlce::make_series_with_step({x}, dt);
  mlce::MlceOptions late, before;
  before.fit.late_decay_share = 0.0;
  before.fit.late_growth_share = 0.0;
  const auto a = mlce::estimate_mlce(series, late);
  const auto b = mlce::estimate_mlce(series, before);
  // The rate beyond the signal's own envelope (estimate.cpp): "converge" in a decay, "separate" in a growth.
  auto faster = [](const mlce::MlceResult& r) {
    return warns(r, "the neighbours converge") || warns(r, "the neighbours separate");
  };
  return {a.lambda, b.lambda, warns(a, "the decay slows"), faster(a), faster(b),
          a.end_envelope_rate * static_cast<double>(a.horizon)};
}

}  // namespace

int main() {
  const double dt = 0.01, truth = -0.3;
  Tally late, before;
  int slowing = 0, faster_late = 0, faster_before = 0;
  double flagged_lo = INFINITY, flagged_hi = 0.0;  // before / lambda_1 of the estimates that warn
  std::printf("%5s %6s %5s %4s %10s %10s %9s   (* the estimate warns that its neighbours converge faster than the "
              "signal decays)\n", "N", "rate2", "f2", "a1", "late", "before", "warning");
  for (std::size_t n : {2000u, 4000u})
    for (double rate : {-0.5, -1.0, -3.0})
      for (double f : {0.45, 1.37, 3.3})
        for (double a1 : {0.2, 1.0, 5.0}) {
          const auto x = mlce::reference::decaying_modes(n, dt, {DecayingMode{truth, 1.0, a1, 0.0}, DecayingMode{rate, f, 1.0, 0.7}});
          const Row r = estimate_both(x, dt);
          late.add(r.late / truth);
          before.add(r.before / truth);
          slowing += r.slowing, faster_late += r.faster_late, faster_before += r.faster_before;
          if (r.faster_before) flagged_lo = std::min(flagged_lo, r.before / truth), flagged_hi = std::max(flagged_hi, r.before / truth);
          std::printf("%5zu %6.2f %5.2f %4.1f %10.4f%s %9.4f%s %9s\n", n, rate, f, a1, r.late, r.faster_late ? "*" : " ",
                      r.before, r.faster_before ? "*" : " ", r.slowing ? "slows" : "");
        }
  std::printf("two modes, lambda_1 = -0.3 1/s, estimate / lambda_1 (%d of %zu warn that the decay slows):\n", slowing,
              late.values.size());
  std::printf("  warn that the neighbours converge faster than the signal decays: late region %d, the rule before %d of "
              "%zu (those read %.2f..%.2f lambda_1)\n",
              faster_late, faster_before, late.values.size(), flagged_lo, flagged_hi);
  late.print("late region (default)");
  before.print("growth rule's region (before)");

  // The same decays with white measurement noise of 0.1 % of the first sample's amplitude: the
  // estimator cuts the floor they decay into off the series (FitOptions::signal_floor).
  Tally late_noisy, before_noisy;
  std::mt19937_64 gen(1);
  std::normal_distribution<double> white(0.0, 1e-3);
  for (std::size_t n : {2000u, 4000u})
    for (double rate : {-0.5, -1.0, -3.0})
      for (double f : {0.45, 1.37, 3.3})
        for (double a1 : {0.2, 1.0, 5.0}) {
          auto x = mlce::reference::decaying_modes(n, dt, {DecayingMode{truth, 1.0, a1, 0.0}, DecayingMode{rate, f, 1.0, 0.7}});
          const double scale = std::abs(x[0]);
          for (double& v : x) v += scale * white(gen);
          const Row r = estimate_both(x, dt);
          late_noisy.add(r.late / truth);
          std::printf("%5zu %6.2f %5.2f %4.1f %10.4f %10.4f  (0.1 %% noise)\n", n, rate, f, a1, r.late, r.before);
          before_noisy.add(r.before / truth);
        }
  std::printf("the same with 0.1 %% white noise, estimate / lambda_1:\n");
  late_noisy.print("late region (default)");
  before_noisy.print("growth rule's region (before)");

  struct Case {
    const char* name;
    std::size_t n;
    std::vector<DecayingMode> modes;
  };
  const std::vector<Case> others{
      {"-0.3@1 Hz x0.5, -0.4@1.2 x1, -1.5@3 x1", 3000, {{-0.3, 1.0, 0.5}, {-0.4, 1.2, 1.0, 0.7}, {-1.5, 3.0, 1.0, 1.4}}},
      {"-0.3@1 Hz x1, -0.35@0.8 x1, -2@2.5 x2", 3000, {{-0.3, 1.0, 1.0}, {-0.35, 0.8, 1.0, 0.7}, {-2.0, 2.5, 2.0, 1.4}}},
      {"-2@2 Hz x1, -0.2@1 x0.01", 3000, {{-2.0, 2.0, 1.0}, {-0.2, 1.0, 0.01, 0.7}}},
      {"-3@1 Hz x1, -0.4@1.37 x0.05", 3000, {{-3.0, 1.0, 1.0}, {-0.4, 1.37, 0.05, 0.7}}},
  };
  std::printf("other decays (lambda_1 = the largest rate):\n");
  for (const auto& c : others) {
    double lambda1 = -INFINITY;
    for (const auto& m : c.modes) lambda1 = std::max(lambda1, m.rate);
    const Row r = estimate_both(mlce::reference::decaying_modes(c.n, dt, c.modes), dt);
    std::printf("  %-42s N %zu: lambda_1 %.3f, late %.4f (%.3f), before %.4f (%.3f)%s\n", c.name, c.n, lambda1, r.late,
                r.late / lambda1, r.before, r.before / lambda1, r.slowing ? ", warns that the decay slows" : "");
  }
  // Growths of several modes: e^{0.3 t} cos 2 pi t at amplitude 0.01, 0.1 and 1 beside a decaying or
  // a second, slower growing mode; lambda_1 = 0.3.
  std::printf("growths (lambda_1 = 0.3 1/s, N 3000): late / before, (signal's growth over the horizon)\n");
  Tally late_growth, before_growth;
  int growth_faster_late = 0, growth_faster_before = 0;
  for (double a1 : {0.01, 0.1, 1.0})
    for (const DecayingMode& other : {DecayingMode{-0.5, 1.37, 1.0, 0.7}, DecayingMode{-1.0, 3.3, 1.0, 0.7},
                                      DecayingMode{-0.5, 0.45, 1.0, 0.7}, DecayingMode{0.1, 1.37, 1.0, 0.7}}) {
      const Row r = estimate_both(mlce::reference::decaying_modes(3000, dt, {DecayingMode{0.3, 1.0, a1, 0.0}, other}), dt);
      late_growth.add(r.late / 0.3);
      before_growth.add(r.before / 0.3);
      growth_faster_late += r.faster_late, growth_faster_before += r.faster_before;
      std::printf("  0.3@1 Hz x%-4g beside %+.1f@%.2f Hz x1: %.4f%s (%.3f) / %.4f%s (%.3f)  (%.2f)\n", a1, other.rate,
                  other.frequency, r.late, r.faster_late ? "*" : "", r.late / 0.3, r.before, r.faster_before ? "*" : "",
                  r.before / 0.3, r.signal_growth);
    }
  std::printf("growths, estimate / lambda_1 (* and warned that the neighbours separate faster than the signal grows: "
              "late region %d, the rule before %d of %zu):\n",
              growth_faster_late, growth_faster_before, late_growth.values.size());
  late_growth.print("late region (default)");
  before_growth.print("growth rule's region (before)");
  return 0;
}
