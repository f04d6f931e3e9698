// Kantz's curves (kantz.hpp) beside Rosenstein's estimate on the same series, every parameter
// automatic (the estimate's embedding, Theiler window, horizon and fit rule):
//  - Lorenz x (dt 0.01) and Roessler x (dt 0.1), N = 10^4: the 128 series of
//    `build/finite_time_spread starts` (mt19937 seeds 1..4, 32 starts each, (x, y) uniform in
//    [-3, 3], z in [0, 1]);
//  - Henon x and the logistic map at r = 4, N = 10^4: 64 series each from random initial states
//    (mt19937 seed 5).
// Per system, over its series and / the known exponent: within 5 % / 10 %, rms error and range of
// Rosenstein's reported estimate and of its plain curve (before phase alignment); of Kantz's median
// radius and of each radius (1st .. 4th, doubling from the median nearest-neighbour distance), with
// the neighbourhoods phase-aligned as the estimate's curve is (automatic) and, where that aligned
// them, not aligned; how often each agrees with Rosenstein's curve treated alike
// (KantzResult::agrees) and their correlation over the series; the mean of the two estimates (partly
// independent errors: would their average read closer?); the time of the estimate and of Kantz's
// automatic curves.
//   build/kantz_vs_rosenstein        (about 8 min)
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "mlce/estimate.hpp"
#include "mlce/kantz.hpp"
#include "ratio_tally.hpp"
#include "reference_systems.hpp"

namespace {

/// Kantz's estimates of the series, tallied / the known exponent: the median radius, each radius, how
/// often they agree with the Rosenstein curve treated alike, and their correlation with it.
struct KantzTally {
  mlce::bench::Tally median;
  std::array<mlce::bench::Tally, 4> radius;
  mlce::bench::Tally pairing;  // the median against Rosenstein's curve treated alike, for their correlation
  std::size_t agree = 0, runs = 0;
  void add(const mlce::KantzResult& r, double lambda) {
    median.add(r.lambda / lambda);
    pairing.add(r.lambda / lambda, r.rosenstein_lambda / lambda);
    for (std::size_t i = 0; i < r.radii.size() && i < radius.size(); ++i) radius[i].add(r.radii[i].lambda / lambda);
    agree += r.agrees, ++runs;
  }
  void print(const char* what) const {
    if (runs == 0) return;
    median.print((std::string("Kantz") + what + ", median radius").c_str());
    for (std::size_t i = 0; i < radius.size(); ++i)
      if (!radius[i].values.empty()) radius[i].print(("Kantz" + std::string(what) + ", radius " + std::to_string(i + 1)).c_str());
    std::printf("  Kantz%s: agrees with Rosenstein's curve treated alike on %zu of %zu; correlation with it %.2f\n", what,
                agree, runs, pairing.correlation_with_own());
  }
};

void study(const char* name, double lambda, double dt, const std::vector<std::vector<double>>& series) {
  mlce::bench::Tally reported, plain, mean_of_two;
  KantzTally automatic, unaligned;
  double t_estimate = 0, t_kantz = 0;
  for (std::size_t k = 0; k < series.size(); ++k) {
    const mlce::Series s = mlce::make_series_with_step({series[k]}, dt);
    const auto t0 = std::chrono::steady_clock::now();
    const mlce::MlceResult e = mlce::estimate_mlce(s, {});
    const auto t1 = std::chrono::steady_clock::now();
    const mlce::KantzResult r = mlce::estimate_kantz(s, e, {});
    const auto t2 = std::chrono::steady_clock::now();
    t_estimate += std::chrono::duration<double>(t1 - t0).count(), t_kantz += std::chrono::duration<double>(t2 - t1).count();
    reported.add(e.lambda / lambda);
    plain.add((e.curve.phase_aligned ? e.unaligned_lambda : e.lambda) / lambda);
    mean_of_two.add(0.5 * (e.lambda + r.lambda) / lambda);
    automatic.add(r, lambda);
    if (r.phase_aligned) {  // the same neighbourhoods not aligned, beside the estimate's plain curve
      mlce::KantzOptions off;
      off.phase_alignment = mlce::PhaseAlignment::off;
      unaligned.add(mlce::estimate_kantz(s, e, off), lambda);
    }
    if ((k + 1) % 32 == 0) std::fprintf(stderr, "%s: %zu of %zu series\n", name, k + 1, series.size());
  }
  std::printf("%s: %zu series (N = 10^4), / %.4f\n", name, series.size(), lambda);
  reported.print("Rosenstein, reported");
  plain.print("Rosenstein, plain curve");
  automatic.print("");
  unaligned.print(" (not aligned)");
  mean_of_two.print("mean of Rosenstein's estimate and Kantz's median radius");
  std::printf("  time per series %.2f s (estimate) + %.2f s (Kantz, automatic)\n",
              t_estimate / static_cast<double>(series.size()), t_kantz / static_cast<double>(series.size()));
}

/// The 128 starts of `build/finite_time_spread starts`.
std::vector<std::vector<double>> flow_series(std::array<double, 3> (*flow)(const std::array<double, 3>&), double dt,
                                             double h, double transient) {
  std::vector<std::vector<double>> out;
  for (const auto& x0 : mlce::reference::random_starts(1, 4))
    out.push_back(mlce::reference::sample_flow<3>(flow, x0, dt, 10000, transient, static_cast<std::size_t>(std::lround(dt / h))));
  return out;
}

}  // namespace

int main() {
  study("Lorenz x", 0.9056, 0.01, flow_series(mlce::reference::lorenz_rhs, 0.01, 0.001, 50.0));
  study("Roessler x", 0.0714, 0.1, flow_series(mlce::reference::roessler_rhs, 0.1, 0.01, 500.0));
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  std::vector<std::vector<double>> henon, logistic;
  for (int k = 0; k < 64; ++k) {
    henon.push_back(mlce::reference::henon_x(10000, 0.2 * u(gen), 0.2 * u(gen)));
    logistic.push_back(mlce::reference::logistic(10000, u(gen)));
  }
  study("Henon x", 0.4189, 1.0, henon);
  study("logistic", std::numbers::ln2, 1.0, logistic);
}
