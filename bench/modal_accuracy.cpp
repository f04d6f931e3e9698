// How close and how fast is `mlce modes` (modes.hpp), against known rates, and where does it read what
// Rosenstein's curve cannot?
//   build/modal_accuracy [noise|short|coverage|speed]   (all four by default; about 2 min)
//  - noise: two decaying modes at close frequencies (e^{-0.02t} cos 2t + e^{-0.05t} cos 2.4t, 40 s at
//    dt = 0.01: the README's beating limitation) plus white noise of 0 .. 10 % of the first amplitude,
//    16 seeds each: the least damped rate's error (mean, rms, worst, relative to 0.02) and the time per
//    record, for the automatic options and for other pencil widths L (max_columns 40, 80, 320) and row
//    weightings (energy: the rows as recorded; amplitude: each row to unit norm); the trade between speed
//    and accuracy.
//  - short: the damped oscillator (zeta = 0.05, omega = 2 pi, dt = 0.01) and a growing one
//    (zeta = -0.05) over 0.75 .. 4 periods, and with 1 % noise: the modal rate and Rosenstein's lambda
//    with its reading, against -+zeta omega.
//  - coverage: how often lambda's 95 % interval (modes.hpp step 8) holds the true rate, over 40 seeds:
//    the beating decays with white noise of 1, 3 and 10 %, with red noise (AR(1), lag-one correlation 0.9)
//    of 3 %, and the damped oscillator over 3 periods with 1 % white noise; the replicates' mean spread
//    against the estimator's own scatter over the seeds, and the time per record with the interval and without it.
//  - speed: one damped mode with 1e-3 noise, N = 10^4 .. 10^6 samples (20 per period .. 2000 per
//    period): the time per record, without the interval and with it (100 replicates), and the rate's error.
// The noise section times the identification alone (ModalOptions::interval_replicates = 0).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "mlce/estimate.hpp"
#include "mlce/modes.hpp"
#include "mlce/reading.hpp"
#include "reference_systems.hpp"

namespace {

using namespace mlce;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

Series series_of(std::vector<double> x, double dt) {
  Series s;
  s.channels = {std::move(x)};
  s.dt = dt;
  s.time_unit = std::string("s");  // not = "s": gcc 12 warns a false -Wrestrict on assign(const char*) here
  return s;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string fmt_missing(int missing) { return "  (no lambda on " + std::to_string(missing) + ")"; }

void noise_section() {
  std::printf("== noise: e^{-0.02t} cos 2t + e^{-0.05t} cos 2.4t, 40 s at dt = 0.01, 16 seeds; error of the least damped "
              "rate relative to 0.02\n");
  std::printf("%-8s %-26s %8s %8s %8s %10s %6s\n", "noise", "options", "mean", "rms", "worst", "ms/record", "linear");
  // mean, rms, worst: over the records that give a lambda; linear: the records read as a sum of modes
  struct Variant {
    const char* name;
    ModalOptions options;
  };
  // The identification alone (no interval: the coverage section times it); every variant as automatic otherwise.
  ModalOptions automatic;
  automatic.interval_replicates = 0;
  std::vector<Variant> variants{{"automatic (L <= 160)", automatic}};
  for (const std::size_t l : {40, 80, 320}) {
    ModalOptions o = automatic;
    o.max_columns = l;
    o.max_rows = std::max<std::size_t>(o.max_rows, l);
    variants.push_back({l == 40 ? "L <= 40" : (l == 80 ? "L <= 80" : "L <= 320"), o});
  }
  ModalOptions energy = automatic, amplitude = automatic;
  energy.weighting = RowWeighting::energy;
  amplitude.weighting = RowWeighting::amplitude;
  variants.push_back({"energy weighting", energy});
  variants.push_back({"amplitude weighting", amplitude});
  const double truth = -0.02;
  for (const double noise : {0.0, 0.001, 0.01, 0.03, 0.1}) {
    for (const auto& v : variants) {
      double sum = 0.0, squares = 0.0, worst = 0.0, time = 0.0;
      int linear = 0, runs = 0, read = 0;
      for (std::uint64_t seed = 1; seed <= 16; ++seed) {
        auto x = reference::decaying_modes(4001, 0.01, {{-0.02, 2.0 / kTwoPi, 1.0}, {-0.05, 2.4 / kTwoPi, 1.0}});
        if (noise > 0.0) x = reference::with_white_noise(x, noise, seed);
        const auto start = std::chrono::steady_clock::now();
        const ModalResult r = identify_modes(series_of(x, 0.01), v.options);
        time += seconds_since(start);
        if (r.lambda) {  // no mode holding 5 % of a quarter: no lambda, counted apart
          const double e = *r.lambda / truth - 1.0;
          sum += e, squares += e * e, worst = std::max(worst, std::abs(e));
          ++read;
        }
        linear += r.linear, ++runs;
        if (noise == 0.0) break;  // one record without noise
      }
      if (read == 0) {
        std::printf("%-8g %-26s %8s %8s %8s %10.2f %3d/%d  (no lambda on any)\n", noise, v.name, "-", "-", "-",
                    1e3 * time / runs, linear, runs);
        continue;
      }
      std::printf("%-8g %-26s %+8.4f %8.4f %8.4f %10.2f %3d/%d%s\n", noise, v.name, sum / read, std::sqrt(squares / read), worst,
                  1e3 * time / runs, linear, runs, read < runs ? fmt_missing(runs - read).c_str() : "");
    }
  }
}

void short_section() {
  std::printf("\n== short: x'' + 2 zeta omega x' + omega^2 x = 0 (omega = 2 pi, dt = 0.01) over P periods; modal rate and "
              "Rosenstein's lambda against -zeta omega\n");
  std::printf("%6s %6s %6s %10s %10s  %-32s %10s  %s\n", "zeta", "P", "noise", "truth", "modes", "modal reading",
              "Rosenstein", "its reading");
  for (const double zeta : {0.05, -0.05})
    for (const double noise : {0.0, 0.01})
      for (const double periods : {0.75, 1.0, 1.5, 2.0, 3.0, 4.0}) {
        const auto n = static_cast<std::size_t>(periods * 100.0) + 1;
        auto x = reference::damped_oscillator(n, 0.01, zeta, kTwoPi);
        if (noise > 0.0) x = reference::with_white_noise(x, noise, 1);
        const Series s = series_of(x, 0.01);
        std::string modal = "-", reading = "error";
        try {
          const ModalResult r = identify_modes(s);
          modal = r.lambda ? std::to_string(*r.lambda) : "none";
          reading = r.reading.substr(0, 32);
        } catch (const std::exception& e) {
          reading = std::string(e.what()).substr(0, 32);
        }
        std::string rosenstein = "-", its = "error";
        try {
          const MlceResult e = estimate_mlce(s, {});
          rosenstein = std::to_string(e.lambda);
          const Reading rd = read_stability(e);
          its = std::string(to_string(rd.stability)) + ", " + rd.motion;
        } catch (const std::exception& e) {
          its = std::string(e.what()).substr(0, 60);
        }
        std::printf("%6.2f %6.2f %6.2f %10.5f %10s  %-32s %10s  %s\n", zeta, periods, noise, -zeta * kTwoPi, modal.c_str(),
                    reading.c_str(), rosenstein.c_str(), its.c_str());
      }
}

/// x plus red noise: AR(1) with lag-one correlation rho, standard deviation `noise` (mt19937_64 `seed`).
std::vector<double> with_red_noise(std::vector<double> x, double noise, double rho, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, noise * std::sqrt(1.0 - rho * rho));
  double e = std::normal_distribution<double>(0.0, noise)(rng);
  for (double& v : x) {
    v += e;
    e = rho * e + g(rng);
  }
  return x;
}

void coverage_section() {
  std::printf("\n== coverage: lambda's 95 %% interval (modes.hpp step 8, 100 replicates) against the true rate, 40 seeds\n");
  // covered: intervals holding the truth, of those given; spread: the replicates' mean standard deviation, which
  // the estimator's own scatter over the seeds (rms error, bias: relative to |truth|) should match.
  std::printf("%-48s %9s %6s %12s %12s %10s %9s %9s\n", "record", "covered", "no ci", "spread", "rms error", "bias",
              "ms (ci)", "ms (none)");
  struct Case {
    const char* name;
    double truth;
    std::function<std::vector<double>(std::uint64_t)> make;
    double dt;
  };
  const auto beating = [] {
    return reference::decaying_modes(4001, 0.01, {{-0.02, 2.0 / kTwoPi, 1.0}, {-0.05, 2.4 / kTwoPi, 1.0}});
  };
  const std::vector<Case> cases{
      {"beating decays, 1 % white noise", -0.02, [&](std::uint64_t k) { return reference::with_white_noise(beating(), 0.01, k); }, 0.01},
      {"beating decays, 3 % white noise", -0.02, [&](std::uint64_t k) { return reference::with_white_noise(beating(), 0.03, k); }, 0.01},
      {"beating decays, 10 % white noise", -0.02, [&](std::uint64_t k) { return reference::with_white_noise(beating(), 0.1, k); }, 0.01},
      {"beating decays, 3 % red noise (AR(1) 0.9)", -0.02, [&](std::uint64_t k) { return with_red_noise(beating(), 0.03, 0.9, k); }, 0.01},
      {"damped oscillator, 3 periods, 1 % white noise", -0.05 * kTwoPi,
       [](std::uint64_t k) { return reference::with_white_noise(reference::damped_oscillator(301, 0.01, 0.05, kTwoPi), 0.01, k); }, 0.01},
  };
  ModalOptions without;
  without.interval_replicates = 0;
  for (const Case& c : cases) {
    int covered = 0, no_interval = 0;
    double spread = 0.0, squares = 0.0, bias = 0.0, time_with = 0.0, time_without = 0.0;
    const int seeds = 40;
    for (int seed = 1; seed <= seeds; ++seed) {
      const Series s = series_of(c.make(static_cast<std::uint64_t>(seed)), c.dt);
      auto start = std::chrono::steady_clock::now();
      const ModalResult r = identify_modes(s);
      time_with += seconds_since(start);
      start = std::chrono::steady_clock::now();
      (void)identify_modes(s, without);
      time_without += seconds_since(start);
      if (r.lambda) {
        squares += (*r.lambda / c.truth - 1.0) * (*r.lambda / c.truth - 1.0);
        bias += (*r.lambda - c.truth) / std::abs(c.truth);
      }
      if (!r.lambda_low) {
        ++no_interval;
        continue;
      }
      covered += *r.lambda_low <= c.truth && c.truth <= *r.lambda_high;
      spread += r.lambda_spread / std::abs(c.truth);

    }
    const int with = seeds - no_interval;
    std::printf("%-48s %5d/%-3d %6d %11.3f%% %11.3f%% %+9.3f%% %9.1f %9.1f\n", c.name, covered, with, no_interval,
                with > 0 ? 100.0 * spread / with : NAN, 100.0 * std::sqrt(squares / seeds), 100.0 * bias / seeds,
                1e3 * time_with / seeds, 1e3 * time_without / seeds);
  }
}

void speed_section() {
  std::printf("\n== speed: e^{-0.005 t} sin(2 pi f t) + 1e-3 white noise, 100 s; N samples\n");
  std::printf("%9s %12s %8s %8s %10s %12s\n", "N", "per period", "stride", "L", "ms", "ms (ci, 100)");
  for (const std::size_t n : {10000, 100000, 1000000}) {
    const double dt = 100.0 / static_cast<double>(n);
    std::vector<double> x(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double t = dt * static_cast<double>(i);
      x[i] = std::exp(-0.005 * t) * std::sin(kTwoPi * 0.5 * t);
    }
    x = reference::with_white_noise(x, 1e-3, 3);
    ModalOptions plain;
    plain.interval_replicates = 0;
    auto start = std::chrono::steady_clock::now();
    const ModalResult r = identify_modes(series_of(x, dt), plain);
    const double ms = 1e3 * seconds_since(start);
    start = std::chrono::steady_clock::now();
    const ModalResult with = identify_modes(series_of(x, dt));
    const double ms_with = 1e3 * seconds_since(start);
    std::printf("%9zu %12.0f %8zu %8zu %10.1f %12.1f   lambda %.6f (truth -0.005), interval [%.6f, %.6f]\n", n, 2.0 / dt,
                r.stride, r.columns, ms, ms_with, r.lambda.value_or(NAN), with.lambda_low.value_or(NAN),
                with.lambda_high.value_or(NAN));
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string section = argc > 1 ? argv[1] : "all";
  if (section == "all" || section == "noise") noise_section();
  if (section == "all" || section == "short") short_section();
  if (section == "all" || section == "coverage") coverage_section();
  if (section == "all" || section == "speed") speed_section();
  return 0;
}
