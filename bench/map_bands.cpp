// Maps beyond the two parameters, every parameter automatic, each series beside the
// exponent of the very orbit it samples (the mean of ln |f'| along it; for Henon the tangent map):
//  - the logistic map x -> r x (1 - x), r = 3.57 ... 4.00 in steps of 0.01, N = 10^4 from
//    x0 = 0.1234567 after 100 iterations: below r ~ 3.68 its attractor is banded (2, 4, ... bands
//    visited in a fixed cycle);
//  - the Henon map x -> 1 - a x^2 + y, y -> 0.3 x, a = 1.00 ... 1.40 in steps of 0.02, N = 10^4
//    from (0.1, 0.1) after 1000 iterations (the tangent map along the same iterations).
// Per parameter: own exponent, the estimate and its ratio to own, delay, dimension, the reading,
// and the estimate under the rules before commit "a map's AMI minimum beyond its mean period":
// the AMI's first minimum (or shoulder) taken at any lag (AmiOptions::mean_period set to a flow's,
// kMinFlowPeriod) and a curve held bounded however far it rose (FitOptions::bounded_max_rise
// infinite). Orbits whose own exponent is below 0.01 (periodic windows) are listed apart with
// what the estimator reads of them. The counts within 2 % of own close each map.
//   build/map_bands        (about 16 s)
// and the same maps' usual parameters (logistic r = 4, Henon a = 1.4) with white measurement noise
// of 0.1, 0.3, 1 and 3 % of the series' standard deviation, three orbits each: the estimate over the
// clean orbit's own exponent, m, the curve's first step over its fitted slope per step, and whether
// the estimator flagged the noise (noise_level):
//   build/map_bands noise  (about 1 s)
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "mlce/estimate.hpp"
#include "mlce/reading.hpp"
#include "reference_systems.hpp"

namespace {

struct Orbit {
  std::vector<double> x;
  double own = 0.0;  // per iteration
};

/// One map's scan; returns nothing, prints a row per parameter and the counts.
template <class MakeOrbit>
void scan(const char* name, const char* parameter, double from, double to, double step, MakeOrbit make) {
  constexpr std::size_t n = 10000;
  int chaotic = 0, within = 0, within_before = 0;
  std::string periodic;
  std::printf("%s, N = %zu: %s | own | estimate (/ own) | delay, m | reading || before: estimate (/ own), delay, m\n",
              name, n, parameter);
  for (int k = 0; from + k * step <= to + 1e-9; ++k) {
    const double p = from + k * step;
    const Orbit o = make(p, n);
    const auto series = mlce::make_series_with_step({o.x}, 1.0);
    const auto r = mlce::estimate_mlce(series, {});
    const auto reading = mlce::read_stability(r);
    if (o.own < 0.01) {
      char item[160];
      std::snprintf(item, sizeof item, " %s %.2f: own %.3f, estimate %.4f (%s);", parameter, p, o.own, r.lambda,
                    reading.motion.c_str());
      periodic += item;
      continue;
    }
    mlce::MlceOptions before;
    before.ami.mean_period = mlce::kMinFlowPeriod;
    before.fit.bounded_max_rise = std::numeric_limits<double>::infinity();
    const auto b = mlce::estimate_mlce(series, before);
    ++chaotic;
    within += std::abs(r.lambda / o.own - 1) <= 0.02;
    within_before += std::abs(b.lambda / o.own - 1) <= 0.02;
    std::printf("  %s %.2f | %.4f | %.4f (%.3f) | %zu, %zu | %s || %.4f (%.3f), %zu, %zu\n", parameter, p, o.own,
                r.lambda, r.lambda / o.own, r.delay, r.dim, reading.motion.c_str(), b.lambda, b.lambda / o.own, b.delay,
                b.dim);
  }
  std::printf("  within 2 %% of own: %d of %d chaotic orbits (before: %d)\n", within, chaotic, within_before);
  std::printf("  periodic windows (own < 0.01):%s\n", periodic.empty() ? " none" : periodic.c_str());
}

/// Measurement noise on a map (the mode `noise`): the estimate of each noisy orbit over the clean
/// orbit's own exponent.
void noise_study() {
  constexpr std::size_t n = 10000;
  std::printf("maps with white measurement noise (N = %zu; noise in %% of the series' standard deviation), estimate / "
              "the clean orbit's own exponent (m, the curve's first step / its fitted slope, noise flagged):\n",
              n);
  for (int map = 0; map < 2; ++map)
    for (const double noise : {0.0, 0.001, 0.003, 0.01, 0.03}) {
      std::printf("  %-8s %4.1f %%:", map == 0 ? "logistic" : "Henon", 100 * noise);
      for (int k = 1; k <= 3; ++k) {
        const auto x = map == 0 ? mlce::reference::logistic(n, 0.1 * k + 0.0234567)
                                : mlce::reference::henon_x(n, 0.1 * k, 0.1);
        const double own = map == 0 ? mlce::reference::logistic_own_exponent(x)
                                    : mlce::reference::henon_own_exponent(n, 0.1 * k, 0.1);
        double mean = 0, square = 0;
        for (const double v : x) mean += v;
        mean /= static_cast<double>(n);
        for (const double v : x) square += (v - mean) * (v - mean);
        const double deviation = std::sqrt(square / static_cast<double>(n));
        const auto noisy = noise > 0 ? mlce::reference::with_white_noise(x, noise * deviation, static_cast<std::uint64_t>(k)) : x;
        const auto r = mlce::estimate_mlce(mlce::make_series_with_step({noisy}, 1.0), {});
        const auto& y = r.curve.mean_log_distance;
        std::printf("  %.3f (m %zu, first step %.2f x%s)", r.lambda / own, r.dim, (y[1] - y[0]) / r.lambda_per_sample,
                    std::isnan(r.noise_level) ? "" : ", flagged");
      }
      std::printf("\n");
    }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "noise") {
    noise_study();
    return 0;
  }
  scan("logistic map", "r", 3.57, 4.0, 0.01, [](double r, std::size_t n) {
    Orbit o;
    o.x = mlce::reference::logistic(n, 0.1234567, r);
    o.own = mlce::reference::logistic_own_exponent(o.x, r);
    return o;
  });
  scan("Henon map (b = 0.3), x", "a", 1.0, 1.4, 0.02, [](double a, std::size_t n) {
    Orbit o;
    o.x = mlce::reference::henon_x(n, 0.1, 0.1, a);
    o.own = mlce::reference::henon_own_exponent(n, 0.1, 0.1, a);
    return o;
  });
}
