// Slow decays under white measurement noise, with and without the noise-compensated curve
// (MlceOptions::noise_compensation): e^{-zeta w t} cos(w_d t), w = 2 pi, dt = 0.01 s, plus Gaussian
// white noise of a share of the start's amplitude, 8 noise seeds (mt19937_64 1..8) per case; every
// parameter automatic. Prints lambda / (-zeta w) per seed, then per case and over all: how many of
// the series within 5 % / 10 %, the range, mean and rms error; and how many were compensated (the
// estimator compensates only where eq. 23's curve is flagged as held up by noise and the third
// differences are white: over the whole record, where it measures the noise, or else over the
// analysed part's last quarter); then how many compensated intervals (ci95) hold -zeta w, with and
// without the measured noise level's part (MlceResult::noise_lambda_stderr).
//   build/noisy_decays        (about 6 s)
// and, on other decays (the same form; zeta 0.005 ... 0.03, noise 0.5 % and 2 %, sampled at dt = 0.01
// ... 0.05 s, i.e. 100 ... 20 samples per period, each over 6 / (zeta w) s = e^{-6} of its start, 3 noise
// seeds 11..13): per dt and over all, the same counts, compensated and plain, the intervals, and every
// series outside 20 % with the noise's share of the pairs' mean square over its fit, the fit's steps,
// and lambda / (-zeta w) from a line through the curve from the fit's first step to its end:
//   build/noisy_decays grid   (about 3 s)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "mlce/estimate.hpp"
#include "mlce/numerics.hpp"
#include "ratio_tally.hpp"
#include "reference_systems.hpp"

namespace {

/// A clean decay plus Gaussian white noise of standard deviation `noise` (mt19937_64 `seed`),
/// estimated with every parameter automatic and with the compensation off: lambda / (-zeta w) each.
struct NoisyRun {
  double compensated, plain;
  bool was_compensated;
  /// Compensated: does the 95 % interval hold -zeta w, and would the batches' part alone?
  bool covered = false, covered_by_batches = false;
  /// Compensated: the noise's share of the pairs' mean square at the fit's first and last step, and
  /// the noise level's part of the interval, 1.96 noise_lambda_stderr over its half-width.
  double share_first = 0.0, share_last = 0.0, noise_part = 0.0;
  /// Compensated: the fit region, the curve's last step, the mean period (samples), and the slope of
  /// the line through the curve from the region's first step to its end, over -zeta w dt.
  std::size_t first = 0, last = 0, end = 0, period = 0;
  double rest_slope = 0.0;
};
NoisyRun run_noisy(const std::vector<double>& clean, double dt, double zeta, double noise, std::uint64_t seed) {
  const auto series = mlce::make_series_with_step({mlce::reference::with_white_noise(clean, noise, seed)}, dt);
  mlce::MlceOptions plain;
  plain.noise_compensation = mlce::NoiseCompensation::off;
  const auto r = mlce::estimate_mlce(series, {});
  const auto p = mlce::estimate_mlce(series, plain);
  const double lambda = -zeta * 2 * std::numbers::pi;
  NoisyRun q{r.lambda / lambda, p.lambda / lambda, r.noise_compensated};
  if (r.noise_compensated) {
    const double half = 0.5 * (r.ci95_high - r.ci95_low), noise_part = 1.96 * r.noise_lambda_stderr;
    const double batches = std::sqrt(std::max(0.0, half * half - noise_part * noise_part));
    q.covered = std::abs(r.lambda - lambda) <= half;
    q.noise_part = noise_part / half;
    q.covered_by_batches = std::abs(r.lambda - lambda) <= batches;
    q.share_first = r.curve.compensated_noise_share.at(r.fit.first);
    q.share_last = r.curve.compensated_noise_share.at(r.fit.last);
    const auto& y = r.curve.mean_log_distance;
    q.first = r.fit.first, q.last = r.fit.last, q.end = y.size() - 1, q.period = r.mean_period.mean_period;
    q.rest_slope = mlce::fit_line(y.data(), q.first, q.end).slope / (lambda * dt);
  }
  return q;
}

/// Over the compensated runs: how many intervals hold -zeta w, with and without the noise level's
/// part, and that part's share of the half-width (median, largest).
struct Coverage {
  int compensated = 0, covered = 0, covered_by_batches = 0;
  std::vector<double> noise_parts;
  void add(const NoisyRun& q) {
    if (!q.was_compensated) return;
    ++compensated, covered += q.covered, covered_by_batches += q.covered_by_batches;
    noise_parts.push_back(q.noise_part);
  }
  void print() {
    if (noise_parts.empty()) return;
    std::sort(noise_parts.begin(), noise_parts.end());
    std::printf("95 %% interval holds -zeta w: %d of %d compensated (the batch means' part alone: %d); the noise "
                "level's part, 1.96 noise_lambda_stderr, is %.2f of its half-width (median; largest %.2f)\n",
                covered, compensated, covered_by_batches, noise_parts[noise_parts.size() / 2], noise_parts.back());
  }
};

/// The second study of the header: decays of other rates, noise and sampling.
void grid() {
  const double w = 2 * std::numbers::pi;
  mlce::bench::Tally all_on, all_off;
  int compensated = 0, total = 0;
  Coverage coverage;
  std::string outside;
  std::printf("dt      lambda / (-zeta w) over zeta 0.005 0.01 0.02 0.03 x noise 0.5 %% 2 %% x seeds 11..13\n");
  for (const double dt : {0.01, 0.02, 0.03, 0.05}) {
    mlce::bench::Tally on, off;
    int compensated_dt = 0;
    for (const double zeta : {0.005, 0.01, 0.02, 0.03}) {
      const auto n = static_cast<std::size_t>(std::min(40000.0, 6.0 / (zeta * w) / dt));
      const auto clean = mlce::reference::damped_oscillator(n, dt, zeta, w);
      for (const double noise : {0.005, 0.02})
        for (std::uint64_t seed = 11; seed <= 13; ++seed) {
          const NoisyRun q = run_noisy(clean, dt, zeta, noise, seed);
          on.add(q.compensated), off.add(q.plain), all_on.add(q.compensated), all_off.add(q.plain);
          compensated_dt += q.was_compensated, ++total;
          coverage.add(q);
          if (std::abs(q.compensated - 1.0) > 0.2) {
            char item[320], share[200] = " not compensated";
            if (q.was_compensated)
              std::snprintf(share, sizeof share,
                            " noise share %.2f..%.2f over the fit, steps %zu..%zu of 0..%zu (period %zu), from %zu to "
                            "the end %.3f",
                            q.share_first, q.share_last, q.first, q.last, q.end, q.period, q.first, q.rest_slope);
            std::snprintf(item, sizeof item, " zeta %g noise %g %% dt %g seed %llu: %.3f%s (plain %.3f);", zeta,
                          100 * noise, dt, static_cast<unsigned long long>(seed), q.compensated, share, q.plain);
            outside += item;
          }
        }
    }
    compensated += compensated_dt;
    std::printf("%4.2f s (%d compensated of 24):\n", dt, compensated_dt);
    on.print("  compensated (default)");
    off.print("  plain (--noise-compensation off)");
  }
  std::printf("all %d series (%d compensated):\n", total, compensated);
  all_on.print("compensated (default)");
  all_off.print("plain (--noise-compensation off)");
  coverage.print();
  std::printf("outside 20 %%:%s\n", outside.empty() ? " none" : outside.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "grid") {
    grid();
    return 0;
  }
  struct Case {
    double zeta, noise;
    std::size_t n;
  };
  const Case cases[] = {{0.01, 0.003, 8000}, {0.01, 0.01, 8000}, {0.01, 0.03, 8000}, {0.004, 0.01, 16000},
                        {0.004, 0.03, 16000}, {0.02, 0.01, 4000}, {0.05, 0.01, 2000}, {0.05, 0.03, 2000}};
  const double w = 2 * std::numbers::pi, dt = 0.01;
  mlce::bench::Tally all_on, all_off;
  int compensated_total = 0, total = 0;
  Coverage coverage;
  std::printf("zeta   noise      N   lambda / (-zeta w) for seeds 1..8: compensated (* = not compensated) | plain\n");
  for (const auto& c : cases) {
    mlce::bench::Tally on, off;
    std::vector<double> a, b;
    std::vector<bool> compensated;
    const auto clean = mlce::reference::damped_oscillator(c.n, dt, c.zeta, w);
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
      const NoisyRun q = run_noisy(clean, dt, c.zeta, c.noise, seed);
      a.push_back(q.compensated), b.push_back(q.plain), compensated.push_back(q.was_compensated);
      on.add(a.back()), off.add(b.back()), all_on.add(a.back()), all_off.add(b.back());
      compensated_total += q.was_compensated, ++total;
      coverage.add(q);
    }
    std::printf("%5.3f %5.1f %% %6zu  ", c.zeta, 100 * c.noise, c.n);
    for (std::size_t k = 0; k < a.size(); ++k) std::printf(" %6.3f%s", a[k], compensated[k] ? " " : "*");
    std::printf(" |");
    for (const double v : b) std::printf(" %6.3f", v);
    std::printf("\n");
    on.print("  compensated (default)");
    off.print("  plain (--noise-compensation off)");
  }
  std::printf("all %d series (%d compensated), lambda / (-zeta w):\n", total, compensated_total);
  all_on.print("compensated (default)");
  all_off.print("plain (--noise-compensation off)");
  coverage.print();
}
