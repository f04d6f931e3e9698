// Does the surrogate test (surrogate.hpp) tell chaos from linear noise? On series whose nature is
// known, every parameter automatic, then surrogate_test with K = 19 IAAFT surrogates (p = 0.05 when
// the series' divergence exceeds every surrogate's):
//  - chaotic: Lorenz x (dt 0.01), Roessler x (dt 0.1), Henon x, the logistic map at r = 4, N = 10^4,
//    `starts` series each from pseudo-random initial states: the test should distinguish them
//    (its power: how often it does);
//  - linear stochastic: AR(2) resonances x_t = 2 r cos(w) x_{t-1} - r^2 x_{t-2} + e_t (r = 0.95,
//    0.99, 0.995; w = 0.2), AR(1) (phi = 0.9), a sine plus white noise (10 % of its amplitude),
//    N = 10^4, Gaussian e_t from mt19937_64, and a damped oscillator (zeta 0.05, omega 2 pi, dt 0.01)
//    driven by white noise: the null holds, and the test should distinguish them on about 5 % of
//    series (its size);
//  - two channels embedded jointly (multivariate surrogates): Lorenz (x, z) and Roessler (x, y),
//    chaotic; a noise-driven mode's displacement and velocity, and two noise-driven modes (1 and
//    1.2 Hz) seen as their sum and difference, linear; and the mode's (q, v) as a periodic record
//    (periodic_mode), whose ends meet as a surrogate's do;
// per series: lambda, the reading's motion, the series' slope over the fit region, the surrogates'
// largest, p, S (sigmas) and the reading with the test; then per kind how often the test
// distinguished the series and how often the reading said "chaotic" without it, with it on the whole
// series (--surrogates 19) and by default (the test on the first 4096 samples where the curve reads chaos).
// Several channels: the default's reading also with the test on the leading segment
// (SurrogateOptions::match_ends off), as before end matching.
//   build/surrogate_power [STARTS] [KIND]   (STARTS series per kind, default 8; about 5 min at 8;
//                                            only the kinds whose name holds KIND, e.g. "(q, v)")
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "mlce/estimate.hpp"
#include "mlce/reading.hpp"
#include "mlce/surrogate.hpp"
#include "reference_systems.hpp"

namespace {

using namespace mlce;

std::vector<double> ar1(std::size_t n, double phi, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> e(0.0, 1.0);
  std::vector<double> x(n);
  double v = 0.0;
  for (std::size_t i = 0; i < n + 1000; ++i) {
    v = phi * v + e(gen);
    if (i >= 1000) x[i - 1000] = v;
  }
  return x;
}

std::vector<double> noisy_sine(std::size_t n, double noise, std::uint64_t seed) {
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = std::sin(0.05 * static_cast<double>(i));
  return reference::with_white_noise(x, noise, seed);
}

struct Kind {
  std::string name;
  double dt;
  std::function<std::vector<double>(std::uint64_t)> make;
  /// Several channels embedded jointly (the multivariate surrogates); `make` is then unused.
  std::function<std::vector<std::vector<double>>(std::uint64_t)> make_channels = {};
};

/// Two lightly damped modes (zeta 0.05 at 1 and 1.2 Hz) each driven by its own white noise, observed
/// as their sum and their difference: two channels of one stable linear motion (an airframe's x and
/// y, each seeing both modes), exponent -0.05 x 2 pi = -0.314 1/s.
std::vector<std::vector<double>> two_modes(std::size_t n, double dt, std::uint64_t seed) {
  const std::vector<double> a = reference::noise_driven_oscillator(n, dt, 0.05, 2.0 * std::numbers::pi, seed).q;
  const std::vector<double> b = reference::noise_driven_oscillator(n, dt, 0.05, 2.4 * std::numbers::pi, seed + 7919).q;
  std::vector<std::vector<double>> out(2, std::vector<double>(n));
  for (std::size_t i = 0; i < n; ++i) out[0][i] = a[i] + b[i], out[1][i] = a[i] - b[i];
  return out;
}

/// The same stable mode as a periodic record: q the sum of the mode's response at every Fourier
/// frequency k / (n dt) (transfer function 1 / (omega0^2 - w^2 + 2 i zeta omega0 w) times a complex
/// Gaussian, mt19937_64 `seed`), so that the record wraps around seamlessly, and v its circular
/// difference quotient, (q_i - q_{i-1 mod n}) / dt: the relation between the channels holds across
/// the wrap as everywhere else, as it does in a surrogate. Tells whether what sets (q, v) apart from
/// its surrogates is the record's ends.
std::vector<std::vector<double>> periodic_mode(std::size_t n, double dt, std::uint64_t seed) {
  const double zeta = 0.05, omega0 = 2.0 * std::numbers::pi;
  std::mt19937_64 g(seed);
  std::normal_distribution<double> e(0.0, 1.0);
  std::vector<double> q(n, 0.0), v(n);
  for (std::size_t k = 1; k < n / 2; ++k) {
    const double w = 2.0 * std::numbers::pi * static_cast<double>(k) / (static_cast<double>(n) * dt);
    const std::complex<double> h = 1.0 / std::complex<double>(omega0 * omega0 - w * w, 2.0 * zeta * omega0 * w);
    const std::complex<double> c = h * std::complex<double>(e(g), e(g));
    for (std::size_t i = 0; i < n; ++i) {  // the angle from (k i) mod n: exact periodicity
      const double angle = 2.0 * std::numbers::pi * static_cast<double>(k * i % n) / static_cast<double>(n);
      q[i] += c.real() * std::cos(angle) - c.imag() * std::sin(angle);
    }
  }
  for (std::size_t i = 0; i < n; ++i) v[i] = (q[i] - q[(i + n - 1) % n]) / dt;
  return {std::move(q), std::move(v)};
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t starts = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 8;
  const std::string only = argc > 2 ? argv[2] : "";  // the kinds whose name holds it (all when empty)
  const std::size_t n = 10000;
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  const std::vector<Kind> kinds = {
      {"Lorenz x", 0.01,
       [&](std::uint64_t s) {
         std::mt19937_64 g(s);
         return reference::lorenz_x(n, 0.01, {u(g), u(g), 20.0 + u(g)});
       }},
      {"Roessler x", 0.1,
       [&](std::uint64_t s) {
         std::mt19937_64 g(s);
         return reference::roessler_x(n, 0.1, {u(g), u(g), 0.0});
       }},
      {"Henon x", 1.0,
       [&](std::uint64_t s) {
         std::mt19937_64 g(s);
         return reference::henon_x(n, 0.1 * u(g), 0.03 * u(g));
       }},
      {"logistic r = 4", 1.0,
       [&](std::uint64_t s) {
         std::mt19937_64 g(s);
         return reference::logistic(n, 0.5 + 0.1 * u(g));
       }},
      {"AR(2) r = 0.95", 1.0, [&](std::uint64_t s) { return reference::ar2_resonance(n, 0.95, 0.2, s); }},
      {"AR(2) r = 0.99", 1.0, [&](std::uint64_t s) { return reference::ar2_resonance(n, 0.99, 0.2, s); }},
      {"AR(2) r = 0.995", 1.0, [&](std::uint64_t s) { return reference::ar2_resonance(n, 0.995, 0.2, s); }},
      {"AR(1) phi = 0.9", 1.0, [&](std::uint64_t s) { return ar1(n, 0.9, s); }},
      {"sine + 10 % noise", 1.0, [&](std::uint64_t s) { return noisy_sine(n, 0.1, s); }},
      {"mode + noise", 0.01, [&](std::uint64_t s) { return reference::noise_driven_oscillator(n, 0.01, 0.05, 2.0 * std::numbers::pi, s).q; }},
      // Channels embedded jointly: chaotic flows' two coordinates, and stable modes driven by noise.
      {"Lorenz (x, z)", 0.01, {},
       [&](std::uint64_t s) {
         std::mt19937_64 g(s);
         const std::array<double, 3> x0 = {u(g), u(g), 20.0 + u(g)};
         return std::vector<std::vector<double>>{reference::lorenz(n, 0.01, x0, 50.0, 0), reference::lorenz(n, 0.01, x0, 50.0, 2)};
       }},
      {"Roessler (x, y)", 0.1, {},
       [&](std::uint64_t s) {
         std::mt19937_64 g(s);
         const std::array<double, 3> x0 = {u(g), u(g), 0.0};
         return std::vector<std::vector<double>>{reference::roessler(n, 0.1, x0, 0), reference::roessler(n, 0.1, x0, 1)};
       }},
      {"mode (q, v)", 0.01, {},
       [&](std::uint64_t s) {
         reference::NoiseDrivenMode m = reference::noise_driven_oscillator(n, 0.01, 0.05, 2.0 * std::numbers::pi, s);
         return std::vector<std::vector<double>>{std::move(m.q), std::move(m.v)};
       }},
      {"two modes (sum, diff)", 0.01, {}, [&](std::uint64_t s) { return two_modes(n, 0.01, s); }},
      {"periodic mode (q, v)", 0.01, {}, [&](std::uint64_t s) { return periodic_mode(n, 0.01, s); }},
  };
  std::vector<std::string> summary;
  for (const Kind& kind : kinds) {
    if (kind.name.find(only) == std::string::npos) continue;
    std::size_t distinguished = 0, chaotic = 0, tested = 0, chaotic_tested = 0, chaotic_screened = 0;
    std::size_t leading_chaotic = 0;  // several channels: the default on the leading segment (match_ends off)
    for (std::size_t k = 0; k < starts; ++k) {
      const Series series = kind.make_channels ? make_series_with_step(kind.make_channels(1000 + k), kind.dt)
                                               : make_series_with_step({kind.make(1000 + k)}, kind.dt);
      MlceResult r;
      try {
        MlceOptions untested;
        untested.surrogates_when = SurrogateWhen::never;
        r = estimate_mlce(series, untested);
      } catch (const std::exception& e) {
        std::printf("%-18s #%zu  refused: %s\n", kind.name.c_str(), k + 1, e.what());
        continue;
      }
      const Reading reading = read_stability(r);
      if (reading.motion == "chaotic") ++chaotic;
      if (r.fit.last <= r.fit.first || r.map_cycle.approach_measured()) {
        std::printf("%-18s #%zu  lambda %+.4f  %-14s  (no fit region: not tested)\n", kind.name.c_str(), k + 1,
                    r.lambda, reading.motion.c_str());
        continue;
      }
      MlceOptions with = {};  // K = 19 on the whole series, whatever the curve reads (--surrogates 19)
      with.surrogates_when = SurrogateWhen::always;
      with.surrogates = SurrogateOptions{};
      const MlceResult tested_r = estimate_mlce(series, with);
      // The default: the test on the first 4096 samples where the curve alone reads chaos.
      const MlceResult screened = estimate_mlce(series, {});
      if (read_stability(screened).motion == "chaotic") ++chaotic_screened;
      std::string leading;  // several channels: the default's test on the leading segment, as before end matching
      if (series.channels.size() > 1) {
        MlceOptions unmatched;
        unmatched.surrogates.match_ends = false;
        const MlceResult l = estimate_mlce(series, unmatched);
        if (read_stability(l).motion == "chaotic") ++leading_chaotic;
        leading = l.surrogates ? fmt::format(";  leading segment: S {:.2f} -> {}", l.surrogates->sigmas, read_stability(l).motion)
                               : std::string(";  leading segment: not tested");
      }
      const SurrogateTest& t = *tested_r.surrogates;
      ++tested;
      double largest = -1e300;
      for (const double s : t.surrogate_slopes) largest = std::max(largest, s);
      if (t.distinguished) ++distinguished;
      if (read_stability(tested_r).motion == "chaotic") ++chaotic_tested;
      std::printf("%-18s #%zu  lambda %+.4f  %-14s  m %zu  fit %zu..%zu  slope %.5f  surrogates' largest %.5f  p %.2f  "
                  "S %.1f  -> %s;  default: %s -> %s%s\n",
                  kind.name.c_str(), k + 1, r.lambda, reading.motion.c_str(), r.dim, t.first, t.last, t.series_slope,
                  largest, t.p_value, t.sigmas, read_stability(tested_r).motion.c_str(),
                  screened.surrogates ? (std::to_string(screened.surrogates->samples) + " samples, S " +
                                         std::to_string(screened.surrogates->sigmas).substr(0, 6))
                                            .c_str()
                                      : "not tested",
                  read_stability(screened).motion.c_str(), leading.c_str());
      std::fflush(stdout);
    }
    char line[240];
    std::snprintf(line, sizeof line,
                  "%-18s distinguished %zu of %zu tested; read chaotic %zu of %zu, with the test %zu, by default %zu",
                  kind.name.c_str(), distinguished, tested, chaotic, starts, chaotic_tested, chaotic_screened);
    summary.emplace_back(line);
    if (kind.make_channels) summary.back() += fmt::format(" (on the leading segment {})", leading_chaotic);
  }
  std::printf("\n");
  for (const auto& s : summary) std::printf("%s\n", s.c_str());
}
