// A level that creeps beneath the neighbour pairs (neighbour_drift, recurrence.hpp): how large its
// share of the pairs' squared initial distance is on stationary series (the warning must stay quiet
// there), and how far a small linear trend a t moves the estimate and the share. Every parameter
// automatic; the known exponents are Lorenz 0.9056, Roessler 0.0714 (1/time unit).
//   stationary: 48 Lorenz x, y, z (N = 10^4, dt = 0.01, random starts after 50 time units), 48
//               Roessler x and z (dt = 0.1, after 500), 16 Henon x and logistic from other starts,
//               van der Pol (mu 0.5, 1, 2), a quasi-periodic two-tone, white noise, van der Pol
//               with 2 % noise, and 16 Lorenz (x, y, z) and Roessler (x, y) embedded jointly: the
//               share's smallest, median and largest value, and how many are warned (share above
//               kNeighbourDriftShare, motion persisting)
//   trends:     the first 16 Lorenz x and Roessler x plus a t: per a, the estimates / lambda_1 and the
//               shares (range), and how many are warned; van der Pol x plus a t (a limit cycle, not
//               warned: its curve stays level)
//   detrended:  the same stationary Lorenz x with their least-squares line removed: what removing a
//               trend that is not there does (the reason the warning advises no detrending)
//   passes:     the first 4 Lorenz x + 0.01 t and Roessler x + 0.002 t, the creep the pairs see removed
//               and the search made again, 12 times: the estimate / lambda_1, the share and the creep
//               removed so far after each pass (a correction that was not built: each pass sees only
//               part of what is left)
//   build/level_drift        (about 70 s)
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "mlce/estimate.hpp"
#include "mlce/numerics.hpp"
#include "reference_systems.hpp"

namespace {

using namespace mlce::reference;

struct Reading {
  double lambda = NAN, share = NAN;
  bool warned = false;
};

Reading estimate(std::vector<std::vector<double>> channels, double dt) {
  try {
    const auto r = mlce::estimate_mlce(mlce::make_series_with_step(std::move(channels), dt), mlce::MlceOptions{});
    Reading out{r.lambda, r.neighbour_drift.share, false};
    for (const auto& w : r.warnings) out.warned = out.warned || w.find("creeps beneath the neighbour pairs") != std::string::npos;
    return out;
  } catch (const std::exception& e) {
    std::printf("  (refused: %s)\n", e.what());
    return {};
  }
}

Reading estimate(const std::vector<double>& x, double dt) { return estimate(std::vector<std::vector<double>>{x}, dt); }

struct Column {
  std::vector<double> values;
  int warned = 0;
  void add(const Reading& r) {
    if (std::isnan(r.share)) return;  // refused (said above)
    values.push_back(r.share);
    warned += r.warned;
  }
  void print(const char* name) const {
    std::vector<double> v = values;
    std::sort(v.begin(), v.end());
    std::printf("  %-24s %3zu series  share min %.4f  median %.4f  max %.4f  warned %d\n", name, v.size(), v.front(),
                v[v.size() / 2], v.back(), warned);
  }
};

std::vector<double> with_trend(std::vector<double> x, double a, double dt) {
  for (std::size_t i = 0; i < x.size(); ++i) x[i] += a * dt * static_cast<double>(i);
  return x;
}

std::vector<double> without_line(std::vector<double> x) {
  const mlce::LineFit line = mlce::fit_line(x.data(), std::size_t{0}, x.size() - 1);  // least squares over the sample index
  for (std::size_t i = 0; i < x.size(); ++i) x[i] -= line.intercept + line.slope * static_cast<double>(i);
  return x;
}

}  // namespace

int main() {
  constexpr int kFlows = 48, kTrended = 16;
  constexpr double kLorenz = 0.9056, kRoessler = 0.0714;
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> u(-10, 10);
  std::vector<std::vector<double>> lorenz_x, roessler_x;
  Column lx, ly, lz, rx, rz, maps, others, joint;
  std::printf("stationary series (share of the pairs' squared initial distance that a drifting level makes):\n");
  for (int i = 0; i < kFlows; ++i) {
    const std::array<double, 3> x0 = {u(g), u(g), 20 + u(g)};
    lorenz_x.push_back(lorenz(10000, 0.01, x0, 50.0, 0));
    lx.add(estimate(lorenz_x.back(), 0.01));
    ly.add(estimate(lorenz(10000, 0.01, x0, 50.0, 1), 0.01));
    lz.add(estimate(lorenz(10000, 0.01, x0, 50.0, 2), 0.01));
    if (i < 16)
      joint.add(estimate(std::vector<std::vector<double>>{lorenz_x.back(), lorenz(10000, 0.01, x0, 50.0, 1), lorenz(10000, 0.01, x0, 50.0, 2)}, 0.01));
    const std::array<double, 3> r0 = {u(g) / 2, u(g) / 2, 0.0};
    roessler_x.push_back(roessler(10000, 0.1, r0, 0));
    rx.add(estimate(roessler_x.back(), 0.1));
    rz.add(estimate(roessler(10000, 0.1, r0, 2), 0.1));
    if (i < 16) joint.add(estimate(std::vector<std::vector<double>>{roessler_x.back(), roessler(10000, 0.1, r0, 1)}, 0.1));
  }
  for (int i = 0; i < 16; ++i) {
    maps.add(estimate(henon_x(10000, 0.1 + 0.01 * i, 0.1), 1.0));
    maps.add(estimate(logistic(10000, 0.1013 + 0.03 * i), 1.0));  // 0.25 would land on the fixed point 0.75
  }
  for (double mu : {0.5, 1.0, 2.0}) others.add(estimate(van_der_pol_x(10000, 0.01, mu), 0.01));
  std::vector<double> tones(10000);
  for (std::size_t i = 0; i < tones.size(); ++i)
    tones[i] = std::sin(0.0731 * static_cast<double>(i)) + 0.7 * std::sin(0.0731 * std::sqrt(2.0) * static_cast<double>(i));
  others.add(estimate(tones, 0.01));
  std::vector<double> noise(10000);
  std::normal_distribution<double> gauss;
  for (double& v : noise) v = gauss(g);
  others.add(estimate(noise, 0.01));
  others.add(estimate(with_white_noise(van_der_pol_x(10000, 0.01, 1.0), 0.02, 5), 0.01));
  lx.print("Lorenz x");
  ly.print("Lorenz y");
  lz.print("Lorenz z");
  rx.print("Roessler x");
  rz.print("Roessler z");
  maps.print("Henon x, logistic");
  others.print("limit cycles, tones, noise");
  joint.print("Lorenz xyz, Roessler xy");

  std::printf("\ntrends: the series plus a t (estimate / lambda_1 range; share range; warned of %d)\n", kTrended);
  auto trend_rows = [&](const char* name, const std::vector<std::vector<double>>& set, double dt, double truth,
                        std::initializer_list<double> rates) {
    for (double a : rates) {
      double qlo = 1e300, qhi = -1e300, slo = 1e300, shi = -1e300, qsum = 0;
      int warned = 0;
      for (int i = 0; i < kTrended; ++i) {
        const Reading r = estimate(with_trend(set[i], a, dt), dt);
        const double q = r.lambda / truth;
        qlo = std::min(qlo, q), qhi = std::max(qhi, q), qsum += q;
        slo = std::min(slo, r.share), shi = std::max(shi, r.share);
        warned += r.warned;
      }
      std::printf("  %-10s a = %-7g lambda / lambda_1 %.3f..%.3f (mean %.3f)  share %.4f..%.4f  warned %2d\n", name, a,
                  qlo, qhi, qsum / kTrended, slo, shi, warned);
    }
  };
  trend_rows("Lorenz x", lorenz_x, 0.01, kLorenz, {0.0, 0.001, 0.002, 0.005, 0.01, 0.02});
  trend_rows("Roessler x", roessler_x, 0.1, kRoessler, {0.0, 0.0002, 0.0005, 0.001, 0.002});
  // A limit cycle: its curve stays level with the offset or without it, and is not warned.
  for (double a : {0.0, 0.001, 0.01, 0.05}) {
    const Reading r = estimate(with_trend(van_der_pol_x(10000, 0.01, 1.0), a, 0.01), 0.01);
    std::printf("  van der Pol x (mu = 1) a = %-5g lambda %+.2g  share %.4f  warned %d\n", a, r.lambda, r.share, r.warned);
  }

  std::printf("\ndetrended (least-squares line removed from the stationary series):\n");
  double qlo = 1e300, qhi = -1e300, qsum = 0;
  int warned = 0;
  for (int i = 0; i < kTrended; ++i) {
    const Reading r = estimate(without_line(lorenz_x[i]), 0.01);
    const double q = r.lambda / kLorenz;
    qlo = std::min(qlo, q), qhi = std::max(qhi, q), qsum += q;
    warned += r.warned;
  }
  std::printf("  Lorenz x   lambda / lambda_1 %.3f..%.3f (mean %.3f)  warned %d of %d\n", qlo, qhi, qsum / kTrended,
              warned, kTrended);

  std::printf("\npasses (estimate / lambda_1, share, creep removed so far per time unit):\n");
  auto passes = [](const char* name, std::vector<double> x, double dt, double truth) {
    std::printf("  %s:", name);
    double removed = 0.0;
    for (int pass = 0; pass < 12; ++pass) {
      const auto r = mlce::estimate_mlce(mlce::make_series_with_step({x}, dt), mlce::MlceOptions{});
      std::printf(" [%.3f %.4f %.4g]", r.lambda / truth, r.neighbour_drift.share, removed / dt);
      const double seen = r.neighbour_drift.rate_per_sample;
      for (std::size_t i = 0; i < x.size(); ++i) x[i] -= seen * static_cast<double>(i);
      removed += seen;
    }
    std::printf("\n");
  };
  for (int i = 0; i < 4; ++i) {
    passes(("Lorenz x " + std::to_string(i) + " + 0.01 t").c_str(), with_trend(lorenz_x[i], 0.01, 0.01), 0.01, kLorenz);
    passes(("Roessler x " + std::to_string(i) + " + 0.002 t").c_str(), with_trend(roessler_x[i], 0.002, 0.1), 0.1, kRoessler);
  }
}
