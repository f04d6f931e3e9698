// Flows the issue does not name, every parameter automatic, each beside the exponent of the very
// trajectory it samples (the tangent vector integrated along it, RK4, renormalised every sample):
// does the method hold beyond Lorenz and Roessler, and does it say so when it does not?
//  - Lorenz at rho = 60 (more strongly chaotic), x, dt = 0.01, N = 10^4;
//  - Roessler at c = 14 (a = b = 0.1), x, dt = 0.1, N = 10^4;
//  - the forced Duffing oscillator x'' + 0.3 x' - x + x^3 = 0.5 cos(1.2 t), x at 50 samples per
//    forcing period, N = 2 x 10^4, 10^5 and 4 x 10^5 (how the estimate approaches its own exponent);
//  - Chua's circuit (alpha 15.6, beta 28, m0 -1.143, m1 -0.714), x, dt = 0.05, N = 10^4 and 4 x 10^4;
//  - Thomas' cyclically symmetric flow (b = 0.208186), x, dt = 0.1, N = 2 x 10^4 and 2 x 10^5, and the
//    mean log growth of random perturbations of 1e-8 over 40 time units (a weakly chaotic flow whose
//    perturbations grow far faster than lambda_1 over the time a curve can follow them);
//  - Lorenz x (rho = 28) and Roessler x (a = b = 0.2) at c = 4.6, 5.0 and 5.7, near the onset of chaos
//    and at the parameters: how closely each last third repeats one period on (EndRepeat).
// Three starts each; per series: own exponent, estimate (its ratio to own), 95 % interval, m, J,
// Theiler window, fit region, whether the curve bends within its fit region
// (FitOptions::bend_warning), the estimate without the region's 1.5-period minimum
// (FitOptions::min_periods = 0), the reading and how closely the last third repeats one period on
// (MlceResult::end_repeat: chaos never repeats itself).
//   build/other_flows        (about 30 s)
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "mlce/estimate.hpp"
#include "mlce/reading.hpp"

namespace {

using State = std::array<double, 6>;  // the state (3) and a tangent vector (3)
using Field = std::function<State(const State&)>;

State rk4(const Field& f, const State& x, double h) {
  auto add = [](const State& a, const State& b, double s) {
    State r;
    for (int i = 0; i < 6; ++i) r[i] = a[i] + s * b[i];
    return r;
  };
  const State k1 = f(x), k2 = f(add(x, k1, h / 2)), k3 = f(add(x, k2, h / 2)), k4 = f(add(x, k3, h));
  State r;
  for (int i = 0; i < 6; ++i) r[i] = x[i] + h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
  return r;
}

/// Samples component 0 of the flow every dt (substeps RK4 steps each) after `transient`, and the
/// exponent of that trajectory (tangent renormalised every sample; the sum of logs in long double).
void run(const char* name, const Field& f, State x, double dt, int substeps, std::size_t n, double transient) {
  const double h = dt / substeps;
  // NOLINTNEXTLINE(clang-analyzer-security.FloatLoopCounter): warm-up timed as in reference_systems.hpp
  for (double t = 0; t < transient; t += h) x = rk4(f, x, h);
  x[3] = 1, x[4] = 0, x[5] = 0;
  std::vector<double> s;
  s.reserve(n);
  long double log_sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    s.push_back(x[0]);
    for (int k = 0; k < substeps; ++k) x = rk4(f, x, h);
    const double norm = std::sqrt(x[3] * x[3] + x[4] * x[4] + x[5] * x[5]);
    log_sum += std::log(norm);
    x[3] /= norm, x[4] /= norm, x[5] /= norm;
  }
  const double own = static_cast<double>(log_sum) / (static_cast<double>(n) * dt);
  const auto series = mlce::make_series_with_step({s}, dt);
  const auto r = mlce::estimate_mlce(series, {});
  // The same without the fit region's minimum length (FitOptions::min_periods = 0): what the
  // 1.5 mean periods cost or buy on each flow.
  mlce::MlceOptions shortest;
  shortest.fit.min_periods = 0;
  const auto r0 = mlce::estimate_mlce(series, shortest);
  bool bends = false;
  for (const auto& w : r.warnings) bends |= w.find("bends within") != std::string::npos;
  std::printf("  %-30s N %6zu  own %.4f  estimate %.4f (%.3f)  95 %% [%.4f, %.4f]%s  m %zu J %zu T %zu fit %zu..%zu%s"
              "  [min_periods 0: %.3f, fit %zu..%zu]  reads: %s, repeats %.3f\n", name, n,
              own, r.lambda, r.lambda / own, r.ci95_low, r.ci95_high, r.ci95_low <= own && own <= r.ci95_high ? "" : " (own outside)",
              r.dim, r.delay, r.theiler, r.fit.first, r.fit.last, bends ? "  BENDS" : "", r0.lambda / own, r0.fit.first, r0.fit.last,
              mlce::read_stability(r).motion.c_str(), r.end_repeat.difference);
}

}  // namespace

int main() {
  std::printf("Other flows, x observed, all automatic; own = the sampled trajectory's exponent:\n");
  const Field lorenz60 = [](const State& s) {
    return State{10 * (s[1] - s[0]), s[0] * (60 - s[2]) - s[1], s[0] * s[1] - 8.0 / 3 * s[2],
                 10 * (s[4] - s[3]), (60 - s[2]) * s[3] - s[4] - s[0] * s[5], s[1] * s[3] + s[0] * s[4] - 8.0 / 3 * s[5]};
  };
  for (int k = 0; k < 3; ++k) run("Lorenz rho = 60, dt 0.01", lorenz60, State{1 + 0.1 * k, 1, 1}, 0.01, 10, 10000, 50);
  const Field roessler14 = [](const State& s) {
    return State{-s[1] - s[2], s[0] + 0.1 * s[1], 0.1 + s[2] * (s[0] - 14),
                 -s[4] - s[5], s[3] + 0.1 * s[4], s[2] * s[3] + (s[0] - 14) * s[5]};
  };
  for (int k = 0; k < 3; ++k) run("Roessler c = 14, dt 0.1", roessler14, State{1 + 0.1 * k, 1, 0}, 0.1, 10, 10000, 500);
  const Field duffing = [](const State& s) {  // the forcing phase as the third state
    const double x = s[0];
    return State{s[1], -0.3 * s[1] + x - x * x * x + 0.5 * std::cos(s[2]), 1.2,
                 s[4], (1 - 3 * x * x) * s[3] - 0.3 * s[4] - 0.5 * std::sin(s[2]) * s[5], 0};
  };
  const double forcing_step = 2 * M_PI / 1.2 / 50;
  for (std::size_t n : {20000u, 100000u, 400000u})
    for (int k = 0; k < 3; ++k) run("Duffing, 50 per forcing period", duffing, State{0.1 + 0.1 * k, 0, 0}, forcing_step, 5, n, 200);
  const Field chua = [](const State& s) {
    constexpr double alpha = 15.6, beta = 28, m0 = -1.143, m1 = -0.714;
    const double x = s[0], g = m1 * x + 0.5 * (m0 - m1) * (std::abs(x + 1) - std::abs(x - 1));
    const double slope = std::abs(x) < 1 ? m0 : m1;
    return State{alpha * (s[1] - x - g), x - s[1] + s[2], -beta * s[1],
                 alpha * (s[4] - s[3] - slope * s[3]), s[3] - s[4] + s[5], -beta * s[4]};
  };
  for (std::size_t n : {10000u, 40000u})
    for (int k = 0; k < 3; ++k) run("Chua, dt 0.05", chua, State{0.7 + 0.01 * k, 0, 0}, 0.05, 10, n, 100);
  constexpr double thomas_b = 0.208186;
  const Field thomas = [](const State& s) {
    return State{std::sin(s[1]) - thomas_b * s[0], std::sin(s[2]) - thomas_b * s[1], std::sin(s[0]) - thomas_b * s[2],
                 -thomas_b * s[3] + std::cos(s[1]) * s[4], -thomas_b * s[4] + std::cos(s[2]) * s[5],
                 std::cos(s[0]) * s[3] - thomas_b * s[5]};
  };
  for (std::size_t n : {20000u, 200000u}) run("Thomas b = 0.208186, dt 0.1", thomas, State{0.1, 0, 0}, 0.1, 10, n, 1000);
  // Why Thomas reads high: 400 random perturbations of 1e-8 (linear), each from its own point of the
  // attractor, followed for 40 time units by the flow itself; the mean of ln d and its slope.
  State x{0.1, 0, 0, 0, 0, 0};
  constexpr double h = 0.01;
  for (int i = 0; i < 100000; ++i) x = rk4(thomas, x, h);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> g;
  constexpr int starts = 400, steps = 4000;
  std::vector<double> mean_log(steps / 1000 + 1, 0.0);
  for (int p = 0; p < starts; ++p) {
    for (int i = 0; i < 3000; ++i) x = rk4(thomas, x, h);
    const double v0 = g(rng), v1 = g(rng), v2 = g(rng), norm = std::sqrt(v0 * v0 + v1 * v1 + v2 * v2);
    State a = x, b{x[0] + 1e-8 * v0 / norm, x[1] + 1e-8 * v1 / norm, x[2] + 1e-8 * v2 / norm, 0, 0, 0};
    for (int k = 0; k <= steps; ++k) {
      if (k % 1000 == 0)
        mean_log[k / 1000] += std::log(std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                                 (a[2] - b[2]) * (a[2] - b[2]))) / starts;
      a = rk4(thomas, a, h), b = rk4(thomas, b, h);
    }
  }
  std::printf("  Thomas: mean ln d of 400 perturbations of 1e-8 at t = 0, 10, 20, 30, 40:");
  for (const double m : mean_log) std::printf(" %.2f", m);
  std::printf("  (growth %.3f per time unit; the attractor's lambda_1 is the own exponent above)\n",
              (mean_log.back() - mean_log.front()) / 40.0);
  // Chaos never repeats itself (ReadingOptions::periodic_end): how closely the last third of the
  // issue's flows, and of Roessler's (a = b = 0.2) near the onset of chaos, repeats one period on.
  std::printf("The issue's flows and Roessler near the onset of chaos (a = b = 0.2), x: does the end repeat?\n");
  const Field lorenz = [](const State& s) {
    return State{10 * (s[1] - s[0]), s[0] * (28 - s[2]) - s[1], s[0] * s[1] - 8.0 / 3 * s[2],
                 10 * (s[4] - s[3]), (28 - s[2]) * s[3] - s[4] - s[0] * s[5], s[1] * s[3] + s[0] * s[4] - 8.0 / 3 * s[5]};
  };
  for (int k = 0; k < 3; ++k) run("Lorenz rho = 28, dt 0.01", lorenz, State{1 + 0.1 * k, 1, 1}, 0.01, 10, 10000, 50);
  for (const double c : {4.6, 5.0, 5.7}) {
    const Field roessler = [c](const State& s) {
      return State{-s[1] - s[2], s[0] + 0.2 * s[1], 0.2 + s[2] * (s[0] - c),
                   -s[4] - s[5], s[3] + 0.2 * s[4], s[2] * s[3] + (s[0] - c) * s[5]};
    };
    const std::string name = "Roessler c = " + std::to_string(c).substr(0, 3) + ", dt 0.1";
    for (int k = 0; k < 3; ++k) run(name.c_str(), roessler, State{1 + 0.1 * k, 1, 0}, 0.1, 10, 10000, 500);
  }
}
