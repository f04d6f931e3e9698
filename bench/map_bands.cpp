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
// the estimator flagged the noise (kMapNoiseStretchSlope on the closest pairs' stretch; the level it
// estimates); then other maps (tent, sine, logistic r = 3.9, Lozi, Ikeda) clean and with 0.1 and 1 %:
//   build/map_bands noise  (about 6 s)
// and maps whose orbit switches slowly between two lobes, with a flow's mean period but a share of
// their power at periods below 4 samples (MeanPeriodResult::map, MeanPeriodOptions::map_fast_share):
// the Duffing (Holmes) map x -> y, y -> -b x + a y - y^3 (b = 0.1: a = 2.62 ... 2.78; b = 0.2:
// a = 2.70 ... 2.76, and the textbook a = 2.75), the cubic map x -> a x - x^3 (a = 2.60 ... 2.80) and the Pomeau-Manneville map
// x -> x + x^z mod 1 (z = 1.5, 1.75), each beside its orbit's own exponent, automatic and treated as
// a map by its mean period alone (map_fast_share = 1, the rule before), and a map noise flag where
// one is raised (none: these orbits are clean); then the fast share of
// sampled flows (Lorenz x at dt = 0.01 ... 0.15, Roessler x at dt = 0.1 ... 0.8, Lorenz x with white
// noise of 10 ... 40 % of its standard deviation), for the threshold's margin:
//   build/map_bands switching  (about 12 s)
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "mlce/estimate.hpp"
#include "mlce/reading.hpp"
#include "mlce/rosenstein.hpp"
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
    before.ami.noise_rise = 0.0;  // nor the AMI minimum's rise above the curve's scatter (2026-12-05)
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

/// The stretch slope of the closest half of the estimate's neighbour pairs (stretch_by_distance; the
/// pairs found again with the estimate's m, delay, Theiler window and horizon), the statistic that
/// flags a map's measurement noise.
double closest_stretch_slope(const mlce::Series& series, const mlce::MlceResult& r) {
  mlce::RosensteinOptions ro;
  ro.dim = r.dim, ro.delay = r.delay, ro.theiler = r.theiler, ro.horizon = r.horizon;
  ro.max_references = mlce::MlceOptions{}.max_references;
  return mlce::stretch_by_distance(series, ro, mlce::find_pairs(series, ro)).closest_half_slope;
}

std::string flag(const mlce::MlceResult& r) {
  if (std::isnan(r.noise_level)) return "";
  char text[48];
  std::snprintf(text, sizeof text, ", flagged ~%.2g %%", 100 * r.noise_level);
  return text;
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
        const double deviation = mlce::rms_deviations(mlce::make_series_with_step({x}, 1.0)).front();
        const auto noisy = noise > 0 ? mlce::reference::with_white_noise(x, noise * deviation, static_cast<std::uint64_t>(k)) : x;
        const auto series = mlce::make_series_with_step({noisy}, 1.0);
        const auto r = mlce::estimate_mlce(series, {});
        const auto& y = r.curve.mean_log_distance;
        std::printf("  %.3f (m %zu, first step %.2f x, stretch %+.2f%s)", r.lambda / own, r.dim,
                    (y[1] - y[0]) / r.lambda_per_sample, closest_stretch_slope(series, r), flag(r).c_str());
      }
      std::printf("\n");
    }
  // Other maps, for the margin of kMapNoiseStretchSlope: clean, their stretch slope must stay above it.
  struct Map {
    const char* name;
    double (*step)(double& x, double& y);  // advances the state, returns the observed value
  };
  const Map others[] = {
      {"tent 1.99", [](double& x, double&) { return x = x < 0.5 ? 1.99 * x : 1.99 * (1 - x); }},
      {"sine", [](double& x, double&) { return x = std::sin(M_PI * x); }},
      {"logistic 3.9", [](double& x, double&) { return x = 3.9 * x * (1 - x); }},
      {"Lozi x", [](double& x, double& y) {
         const double next = 1 - 1.7 * std::abs(x) + y;
         y = 0.5 * x;
         return x = next;
       }},
      {"Ikeda x", [](double& x, double& y) {
         const double t = 0.4 - 6 / (1 + x * x + y * y), next = 1 + 0.9 * (x * std::cos(t) - y * std::sin(t));
         y = 0.9 * (x * std::sin(t) + y * std::cos(t));
         return x = next;
       }},
  };
  std::printf("other maps (N = %zu), lambda per iteration (m, stretch, noise flagged):\n", n);
  for (const Map& map : others)
    for (const double noise : {0.0, 0.001, 0.01}) {
      std::printf("  %-12s %4.1f %%:", map.name, 100 * noise);
      for (int k = 1; k <= 3; ++k) {
        double x = 0.1 * k + 0.0234567, y = 0.0;
        for (int i = 0; i < 1000; ++i) map.step(x, y);
        std::vector<double> v(n);
        for (double& value : v) value = map.step(x, y);
        const double deviation = mlce::rms_deviations(mlce::make_series_with_step({v}, 1.0)).front();
        if (noise > 0) v = mlce::reference::with_white_noise(v, noise * deviation, static_cast<std::uint64_t>(k));
        const auto series = mlce::make_series_with_step({v}, 1.0);
        const auto r = mlce::estimate_mlce(series, {});
        std::printf("  %.4f (m %zu, %+.2f%s)", r.lambda, r.dim, closest_stretch_slope(series, r), flag(r).c_str());
      }
      std::printf("\n");
    }
}

}  // namespace

/// One switching orbit: automatic, and treated as a map by its mean period alone.
void switching_row(const char* name, const mlce::reference::MapSample& o, int& rows, int& within, int& within_before) {
  const auto series = mlce::make_series_with_step({o.x}, 1.0);
  const auto r = mlce::estimate_mlce(series, {});
  mlce::MlceOptions by_period;
  by_period.mean_period.map_fast_share = 1.0;  // never reached but by a tone at the Nyquist frequency
  const auto b = mlce::estimate_mlce(series, by_period);
  const bool ok = std::abs(r.lambda / o.own_exponent - 1.0) <= 0.05, ok_before = std::abs(b.lambda / o.own_exponent - 1.0) <= 0.05;
  ++rows, within += ok, within_before += ok_before;
  std::printf("  %-32s own %.4f  T %2zu fast %.3f %s | %.4f (%.3f) J %zu m %zu%s%s || by period: %.4f (%.3f) J %zu m %zu%s\n", name,
              o.own_exponent, r.mean_period.mean_period, r.mean_period.fast_share, r.mean_period.map ? "map " : "flow",
              r.lambda, r.lambda / o.own_exponent, r.delay, r.dim, r.unreliable.empty() ? "" : " (undetermined)",
              flag(r).c_str(), b.lambda,
              b.lambda / o.own_exponent, b.delay, b.dim, b.unreliable.empty() ? "" : " (undetermined)");
}

mlce::reference::MapSample pomeau_manneville(std::size_t n, double z) {
  double x = 0.3;
  auto step = [z](double v) {
    const double next = v + std::pow(v, z);
    return next >= 1.0 ? next - 1.0 : next;
  };
  for (int i = 0; i < 1000; ++i) x = step(x);
  mlce::reference::MapSample o;
  long double acc = 0;
  for (std::size_t i = 0; i < n; ++i) {
    o.x.push_back(x);
    acc += std::log(1.0 + z * std::pow(x, z - 1.0));
    x = step(x);
  }
  o.own_exponent = static_cast<double>(acc / static_cast<long double>(n));
  return o;
}

void switching_study() {
  constexpr std::size_t n = 10000;
  int rows = 0, within = 0, within_before = 0;
  char name[64];
  std::printf("Maps that switch slowly between lobes, N = %zu: own | mean period T, fast share, map/flow | estimate (/ own), "
              "delay, m || treated as a map by T alone (map_fast_share = 1)\n", n);
  for (const auto& [b, from, steps] : {std::tuple{0.1, 2.62, 9}, std::tuple{0.2, 2.70, 4}})
    for (int k = 0; k < steps; ++k) {
      const double a = from + 0.02 * k;
      std::snprintf(name, sizeof name, "Duffing a %.2f b %.1f", a, b);
      switching_row(name, mlce::reference::duffing_map_x(n, a, b), rows, within, within_before);
    }
  switching_row("Duffing a 2.75 b 0.2 (textbook)", mlce::reference::duffing_map_x(n), rows, within, within_before);
  for (int k = 0; k <= 5; ++k) {
    const double a = 2.60 + 0.04 * k;
    std::snprintf(name, sizeof name, "cubic a %.2f", a);
    switching_row(name, mlce::reference::cubic_map(n, a), rows, within, within_before);
  }
  for (const double z : {1.5, 1.75}) {
    std::snprintf(name, sizeof name, "Pomeau-Manneville z %.2f", z);
    switching_row(name, pomeau_manneville(n, z), rows, within, within_before);
  }
  std::printf("within 5 %% of own: %d of %d automatic, %d by the mean period alone\n", within, rows, within_before);
  std::printf("Fast share of sampled flows (N = 10^4; MeanPeriodOptions::map_fast_share = %.2f):\n",
              mlce::MeanPeriodOptions{}.map_fast_share);
  // Each with its estimate over the known lambda_1, automatic and as a flow (map_fast_share = 1).
  auto flow = [](const char* label, const std::vector<double>& x, double dt, double lambda_1) {
    const auto series = mlce::make_series_with_step({x}, dt);
    const auto r = mlce::estimate_mlce(series, {});
    mlce::MlceOptions as_flow;
    as_flow.mean_period.map_fast_share = 1.0;
    const auto f = mlce::estimate_mlce(series, as_flow);
    auto verdict = [](const mlce::MlceResult& e) { return e.unreliable.empty() ? std::string() : " undetermined: " + e.unreliable; };
    std::printf("  %-30s T %3zu  fast share %.4f  %-4s | %.3f lambda_1%s || as a flow: %.3f%s\n", label, r.mean_period.mean_period,
                r.mean_period.fast_share, r.mean_period.map ? "map" : "flow", r.lambda / lambda_1, verdict(r).c_str(),
                f.lambda / lambda_1, verdict(f).c_str());
  };
  for (const double dt : {0.01, 0.05, 0.1, 0.15}) {
    std::snprintf(name, sizeof name, "Lorenz x, dt %.2f", dt);
    flow(name, mlce::reference::lorenz_x(n, dt), dt, 0.9056);
  }
  for (const double dt : {0.1, 0.3, 0.5, 0.8}) {
    std::snprintf(name, sizeof name, "Roessler x, dt %.1f", dt);
    flow(name, mlce::reference::roessler_x(n, dt), dt, 0.0714);
  }
  const auto lorenz = mlce::reference::lorenz_x(n);
  double mean = 0, sq = 0;
  for (const double v : lorenz) mean += v;
  mean /= static_cast<double>(n);
  for (const double v : lorenz) sq += (v - mean) * (v - mean);
  const double deviation = std::sqrt(sq / static_cast<double>(n));
  for (const double share : {0.1, 0.2, 0.3, 0.35, 0.4}) {
    std::snprintf(name, sizeof name, "Lorenz x + %.0f %% white noise", 100 * share);
    flow(name, mlce::reference::with_white_noise(lorenz, share * deviation, 7), 0.01, 0.9056);
  }
}

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "noise") {
    noise_study();
    return 0;
  }
  if (argc > 1 && std::string(argv[1]) == "switching") {
    switching_study();
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
