// Slow decays under white measurement noise, with and without the noise-compensated curve
// (MlceOptions::noise_compensation): e^{-zeta w t} cos(w_d t), w = 2 pi, dt = 0.01 s, plus Gaussian
// white noise of a share of the start's amplitude, 8 noise seeds (mt19937_64 1..8) per case; every
// parameter automatic. Prints lambda / (-zeta w) per seed, then per case and over all: how many of
// the series within 5 % / 10 %, the range, mean and rms error; and how many were compensated (the
// estimator compensates only where eq. 23's curve is flagged as held up by noise and the third
// differences are white: over the whole record, where it measures the noise, or else over the
// analysed part's last quarter); then how many intervals (ci95) hold -zeta w, over all series and over
// the compensated ones, these with and without the measured noise level's part
// (MlceResult::noise_lambda_stderr).
//   build/noisy_decays        (about 6 s)
// and, on other decays (the same form; zeta 0.005 ... 0.03, noise 0.5 % and 2 %, sampled at dt = 0.01
// ... 0.05 s, i.e. 100 ... 20 samples per period, each over 6 / (zeta w) s = e^{-6} of its start, 3 noise
// seeds 11..13): per dt and over all, the same counts, compensated and plain, the intervals, and every
// series outside 20 % with the noise's share of the pairs' mean square over its fit, the fit's steps,
// and lambda / (-zeta w) from a line through the curve from the fit's first step to its end:
//   build/noisy_decays grid   (about 3 s)
// and on two-mode decays, the free response of a linear system whose least damped mode sets lambda_1:
// e^{r t} cos 2 pi t at r = -0.0628, -0.126 and -0.3 1/s (zeta 0.01, 0.02, 0.048) and amplitude 0.2, 1
// or 5, plus a faster mode of amplitude 1 (-0.5 1/s at 0.45 Hz, -1 at 1.37 or -3 at 3.3, phase 0.7),
// dt = 0.01 s, each over 6 / |r| s (e^{-6} of the slow mode's start), with white noise of 1 % and 3 %
// of the slow mode's amplitude, noise seeds 21, 22; the same counts and the series outside 20 %:
//   build/noisy_decays modes  (about 2 s)
// and, over 40 noise seeds (101..140) of three of the first study's cases, the compensated series'
// lambda / (-zeta w) by the default rule and by the rule before stage 2b' (FitOptions::late_decay_share
// 0: the growth rule's region), with how many intervals hold -zeta w:
//   build/noisy_decays seeds  (about 15 s)
// and, on the modes study's -0.3 1/s decays (the floor cut leaves 560 ... 1100 of their 2000 samples),
// the default estimate with its interval (and the slope of its fit region's second half over its first's)
// beside two alternatives tried and not kept: the whole record
// analysed, uncut (MlceOptions::floor_ratio 0; the noise compensated where the curve is flagged), and
// the default's curve from the later half of its references only (where the slow mode dominates):
//   build/noisy_decays short  (about 1 s)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "mlce/estimate.hpp"
#include "mlce/numerics.hpp"
#include "mlce/reading.hpp"
#include "mlce/rosenstein.hpp"
#include "mlce/fit.hpp"
#include "ratio_tally.hpp"
#include "reference_systems.hpp"

namespace {

/// A clean decay plus Gaussian white noise of standard deviation `noise` (mt19937_64 `seed`),
/// estimated with every parameter automatic and with the compensation off: lambda / (-zeta w) each.
struct NoisyRun {
  double compensated, plain;
  bool was_compensated;
  /// The default estimate's reading: stable is right, undetermined says it cannot tell, neutral or
  /// unstable misleads.
  mlce::Stability reading = mlce::Stability::undetermined;
  /// Does the default estimate's 95 % interval hold -zeta w; compensated: would the batches' part alone?
  bool covered = false, covered_by_batches = false;
  /// Compensated: the noise's share of the pairs' mean square at the fit's first and last step, and
  /// the noise level's part of the interval, 1.96 noise_lambda_stderr over its half-width.
  double share_first = 0.0, share_last = 0.0, noise_part = 0.0;
  /// Compensated: the fit region, the curve's last step, the mean period (samples), and the slope of
  /// the line through the curve from the region's first step to its end, over -zeta w dt.
  std::size_t first = 0, last = 0, end = 0, period = 0;
  double rest_slope = 0.0;
};
/// `lambda` is the clean signal's exponent (-zeta w for one mode; the least damped mode's rate).
NoisyRun run_noisy(const std::vector<double>& clean, double dt, double lambda, double noise, std::uint64_t seed) {
  const auto series = mlce::make_series_with_step({mlce::reference::with_white_noise(clean, noise, seed)}, dt);
  mlce::MlceOptions plain;
  plain.noise_compensation = mlce::NoiseCompensation::off;
  const auto r = mlce::estimate_mlce(series, {});
  const auto p = mlce::estimate_mlce(series, plain);
  NoisyRun q{r.lambda / lambda, p.lambda / lambda, r.noise_compensated, mlce::read_stability(r).stability};
  const double half = 0.5 * (r.ci95_high - r.ci95_low);
  q.covered = std::abs(r.lambda - lambda) <= half;
  if (r.noise_compensated) {
    const double noise_part = 1.96 * r.noise_lambda_stderr;
    const double batches = std::sqrt(std::max(0.0, half * half - noise_part * noise_part));
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

/// Over all runs: the readings, and how many intervals hold the exponent; over the compensated runs:
/// how many hold it, with and without the noise level's part, and that part's share of the
/// half-width (median, largest).
struct Coverage {
  int runs = 0, covered_all = 0, compensated = 0, covered = 0, covered_by_batches = 0;
  int readings[4] = {};  // indexed by mlce::Stability
  std::vector<double> noise_parts;
  void add(const NoisyRun& q) {
    ++readings[static_cast<int>(q.reading)];
    ++runs, covered_all += q.covered;
    if (!q.was_compensated) return;
    ++compensated, covered += q.covered, covered_by_batches += q.covered_by_batches;
    noise_parts.push_back(q.noise_part);
  }
  void print() {
    std::printf("readings (default): stable %d, neutral %d, unstable %d, undetermined %d; the 95 %% interval holds the "
                "exponent on %d of %d\n",
                readings[0], readings[1], readings[2], readings[3], covered_all, runs);
    if (noise_parts.empty()) return;
    std::sort(noise_parts.begin(), noise_parts.end());
    std::printf("95 %% interval holds the exponent: %d of %d compensated (the batch means' part alone: %d); the noise "
                "level's part, 1.96 noise_lambda_stderr, is %.2f of its half-width (median; largest %.2f)\n",
                covered, compensated, covered_by_batches, noise_parts[noise_parts.size() / 2], noise_parts.back());
  }
};

/// A series outside 20 %, for the studies' last line: `what` names the case; if compensated, the
/// noise's share over its fit, the fit's steps, the curve's end, the mean period and the slope from
/// the fit's first step to the curve's end; its reading unless stable.
std::string describe_outlier(const std::string& what, const NoisyRun& q) {
  char item[400], share[200] = " not compensated";
  if (q.was_compensated)
    std::snprintf(share, sizeof share,
                  " noise share %.2f..%.2f over the fit, steps %zu..%zu of 0..%zu (period %zu), from %zu to the end %.3f",
                  q.share_first, q.share_last, q.first, q.last, q.end, q.period, q.first, q.rest_slope);
  std::snprintf(item, sizeof item, " %s: %.3f%s (plain %.3f)%s%s;", what.c_str(), q.compensated, share, q.plain,
                q.reading == mlce::Stability::stable ? "" : ", read ", q.reading == mlce::Stability::stable ? "" : mlce::to_string(q.reading));
  return item;
}

/// A group of runs (one case, or a whole study): compensated and plain tallies, how many were
/// compensated, the intervals and readings, and the series outside 20 %.
struct Group {
  mlce::bench::Tally on, off, compensated_on, compensated_off;  // all; the compensated series alone
  int total = 0, compensated = 0;
  Coverage coverage;
  std::string outside;
  void add(const NoisyRun& q, const char* what) {
    on.add(q.compensated), off.add(q.plain);
    if (q.was_compensated) compensated_on.add(q.compensated), compensated_off.add(q.plain);
    ++total, compensated += q.was_compensated;
    coverage.add(q);
    if (std::abs(q.compensated - 1.0) > 0.2) outside += describe_outlier(what, q);
  }
  void print_case() const {
    on.print("  compensated (default)");
    off.print("  plain (--noise-compensation off)");
  }
  void print_all() {
    std::printf("all %d series (%d compensated):\n", total, compensated);
    on.print("compensated (default)");
    off.print("plain (--noise-compensation off)");
    if (compensated > 0 && compensated < total) {
      std::printf("the %d compensated series alone:\n", compensated);
      compensated_on.print("compensated (default)");
      compensated_off.print("plain (--noise-compensation off)");
    }
    coverage.print();
    std::printf("outside 20 %%:%s\n", outside.empty() ? " none" : outside.c_str());
  }
};

/// The second study of the header: decays of other rates, noise and sampling.
void grid() {
  const double w = 2 * std::numbers::pi;
  Group all;
  std::printf("dt      lambda / (-zeta w) over zeta 0.005 0.01 0.02 0.03 x noise 0.5 %% 2 %% x seeds 11..13\n");
  for (const double dt : {0.01, 0.02, 0.03, 0.05}) {
    Group at_dt;
    for (const double zeta : {0.005, 0.01, 0.02, 0.03}) {
      const auto n = static_cast<std::size_t>(std::min(40000.0, 6.0 / (zeta * w) / dt));
      const auto clean = mlce::reference::damped_oscillator(n, dt, zeta, w);
      for (const double noise : {0.005, 0.02})
        for (std::uint64_t seed = 11; seed <= 13; ++seed) {
          const NoisyRun q = run_noisy(clean, dt, -zeta * w, noise, seed);
          char what[96];
          std::snprintf(what, sizeof what, "zeta %g noise %g %% dt %g seed %llu", zeta, 100 * noise, dt,
                        static_cast<unsigned long long>(seed));
          at_dt.add(q, what), all.add(q, what);
        }
    }
    std::printf("%4.2f s (%d compensated of 24):\n", dt, at_dt.compensated);
    at_dt.print_case();
  }
  all.print_all();
}

/// The two-mode decays of the modes and short studies: e^{r t} cos 2 pi t at amplitude a1 (the slow
/// mode, lambda_1 = r) beside a faster mode of amplitude 1 and phase 0.7, n samples at dt.
struct FastMode {
  double rate, frequency;
};
constexpr FastMode kFastModes[] = {{-0.5, 0.45}, {-1.0, 1.37}, {-3.0, 3.3}};
std::vector<double> two_mode_decay(std::size_t n, double dt, double slow_rate, double a1, const FastMode& fast) {
  using mlce::reference::DecayingMode;
  return mlce::reference::decaying_modes(
      n, dt, {DecayingMode{slow_rate, 1.0, a1, 0.0}, DecayingMode{fast.rate, fast.frequency, 1.0, 0.7}});
}

/// The third study of the header: two-mode decays under noise.
void modes() {
  const double dt = 0.01;
  Group all;
  std::printf("slow mode   noise  lambda / lambda_1 over the fast mode (-0.5 @ 0.45, -1 @ 1.37, -3 @ 3.3 Hz) x the slow "
              "mode's amplitude 0.2, 1, 5 x seeds 21, 22\n");
  for (const double slow_rate : {-0.01 * 2 * std::numbers::pi, -0.02 * 2 * std::numbers::pi, -0.3})
    for (const double noise : {0.01, 0.03}) {
      Group one;
      const auto n = static_cast<std::size_t>(6.0 / -slow_rate / dt);
      for (const auto& fast : kFastModes)
        for (const double a1 : {0.2, 1.0, 5.0}) {
          const auto clean = two_mode_decay(n, dt, slow_rate, a1, fast);
          for (std::uint64_t seed = 21; seed <= 22; ++seed) {
            const NoisyRun q = run_noisy(clean, dt, slow_rate, noise * a1, seed);
            char what[120];
            std::snprintf(what, sizeof what, "slow %.3f x%g, fast %g @ %g Hz, noise %g %% seed %llu", slow_rate, a1,
                          fast.rate, fast.frequency, 100 * noise, static_cast<unsigned long long>(seed));
            one.add(q, what), all.add(q, what);
          }
        }
      std::printf("%6.3f 1/s %4.0f %%, N %zu (%d compensated of 18):\n", slow_rate, 100 * noise, n, one.compensated);
      one.print_case();
    }
  all.print_all();
}

/// The fifth study of the header: the modes study's -0.3 1/s decays, whose records the floor cut
/// leaves short, against two alternatives that were tried and not kept.
void short_records() {
  const double dt = 0.01, slow_rate = -0.3;
  mlce::MlceOptions uncut;
  uncut.floor_ratio = 0.0;
  const auto n = static_cast<std::size_t>(6.0 / -slow_rate / dt);
  std::printf("slow mode -0.3 1/s beside a faster one, amplitude 0.2, 1, 5, seeds 21, 22; lambda / lambda_1: default "
              "[95 %% interval, * = does not hold lambda_1] (analysed samples of %zu, the fit region's second half's slope over "
              "its first's) | uncut | later references\n", n);
  for (const double noise : {0.01, 0.03}) {
    mlce::bench::Tally by_default, by_uncut, by_later;
    int held = 0, runs = 0, stable = 0;
    for (const auto& fast : kFastModes) {
      std::printf("%2.0f %% noise, fast %4g @ %4g Hz:", 100 * noise, fast.rate, fast.frequency);
      for (const double a1 : {0.2, 1.0, 5.0}) {
        const auto clean = two_mode_decay(n, dt, slow_rate, a1, fast);
        for (std::uint64_t seed = 21; seed <= 22; ++seed) {
          const auto series = mlce::make_series_with_step({mlce::reference::with_white_noise(clean, noise * a1, seed)}, dt);
          const auto r = mlce::estimate_mlce(series, {});
          const auto u = mlce::estimate_mlce(series, uncut);
          // The default's pairs from the later half of its references only, where the slow mode
          // dominates more, fitted by the rule with the default's period and the signal's floor.
          mlce::Series analysed = series;
          analysed.channels[0].resize(r.n_points);
          mlce::RosensteinOptions ro;
          ro.dim = r.dim, ro.delay = r.delay, ro.theiler = r.theiler, ro.horizon = r.horizon;
          mlce::NeighbourPairs pairs = mlce::find_pairs(analysed, ro), later = pairs;
          const std::size_t half = pairs.references.size() / 2;
          later.references.assign(pairs.references.begin() + static_cast<std::ptrdiff_t>(half), pairs.references.end());
          later.nearest.neighbour.assign(pairs.nearest.neighbour.begin() + static_cast<std::ptrdiff_t>(half),
                                         pairs.nearest.neighbour.end());
          later.nearest.distance.assign(pairs.nearest.distance.begin() + static_cast<std::ptrdiff_t>(half),
                                        pairs.nearest.distance.end());
          mlce::FitOptions fo;
          fo.period = r.mean_period.mean_period, fo.signal_floor = r.n_points < series.size();
          const double later_lambda = mlce::fit_divergence(mlce::follow_pairs(analysed, ro, later), fo).slope / dt;
          const bool holds = r.ci95_low <= slow_rate && slow_rate <= r.ci95_high;
          ++runs, held += holds, stable += mlce::read_stability(r).stability == mlce::Stability::stable;
          by_default.add(r.lambda / slow_rate), by_uncut.add(u.lambda / slow_rate), by_later.add(later_lambda / slow_rate);
          // Does the region show its bias? The slope of its second half over its first's.
          const std::size_t mid = (r.fit.first + r.fit.last) / 2;
          const auto& y = r.curve.mean_log_distance;
          const double halves = mlce::fit_line(y.data(), mid, r.fit.last).slope / mlce::fit_line(y.data(), r.fit.first, mid).slope;
          std::printf(" %.3f [%.2f..%.2f]%s (%zu, halves %.2f) | %.3f | %.3f;", r.lambda / slow_rate, r.ci95_high / slow_rate,
                      r.ci95_low / slow_rate, holds ? "" : "*", r.n_points, halves, u.lambda / slow_rate,
                      later_lambda / slow_rate);
        }
      }
      std::printf("\n");
    }
    std::printf("%2.0f %% noise, the 95 %% interval holds lambda_1 on %d of %d; read stable: %d\n", 100 * noise, held, runs,
                stable);
    by_default.print("  default");
    by_uncut.print("  uncut (floor_ratio 0)");
    by_later.print("  later half of the references");
  }
}

/// The fourth study of the header: the rule for compensated curves against the one before, over many
/// noise draws.
void seeds() {
  struct Case {
    double zeta, noise;
    std::size_t n;
  };
  const Case cases[] = {{0.01, 0.01, 8000}, {0.01, 0.03, 8000}, {0.004, 0.03, 16000}};
  const double w = 2 * std::numbers::pi, dt = 0.01;
  mlce::MlceOptions before;
  before.fit.late_decay_share = 0.0;
  std::printf("compensated series of 40 noise seeds (101..140), lambda / (-zeta w): the default rule (a compensated "
              "decay fitted late, to where the noise level's error moves the slope by at most 5 %%) and the rule "
              "before (late_decay_share 0: the growth rule's region)\n");
  for (const auto& c : cases) {
    mlce::bench::Tally now, then;
    int covered_now = 0, covered_then = 0;
    const double lambda = -c.zeta * w;
    const auto clean = mlce::reference::damped_oscillator(c.n, dt, c.zeta, w);
    for (std::uint64_t seed = 101; seed <= 140; ++seed) {
      const auto series = mlce::make_series_with_step({mlce::reference::with_white_noise(clean, c.noise, seed)}, dt);
      const auto a = mlce::estimate_mlce(series, {});
      if (!a.noise_compensated) continue;
      const auto b = mlce::estimate_mlce(series, before);
      now.add(a.lambda / lambda), then.add(b.lambda / lambda);
      covered_now += a.ci95_low <= lambda && lambda <= a.ci95_high;
      covered_then += b.ci95_low <= lambda && lambda <= b.ci95_high;
    }
    std::printf("zeta %g, %g %% noise, N %zu (%zu compensated):\n", c.zeta, 100 * c.noise, c.n, now.values.size());
    now.print("  default");
    then.print("  the rule before");
    std::printf("    95 %% interval holds -zeta w: default %d, the rule before %d\n", covered_now, covered_then);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const struct {
    const char* name;
    void (*run)();
  } studies[] = {{"grid", grid}, {"modes", modes}, {"short", short_records}, {"seeds", seeds}};
  for (const auto& study : studies)
    if (argc > 1 && std::string(argv[1]) == study.name) {
      study.run();
      return 0;
    }
  struct Case {
    double zeta, noise;
    std::size_t n;
  };
  const Case cases[] = {{0.01, 0.003, 8000}, {0.01, 0.01, 8000}, {0.01, 0.03, 8000}, {0.004, 0.01, 16000},
                        {0.004, 0.03, 16000}, {0.02, 0.01, 4000}, {0.05, 0.01, 2000}, {0.05, 0.03, 2000}};
  const double w = 2 * std::numbers::pi, dt = 0.01;
  Group all;
  std::printf("zeta   noise      N   lambda / (-zeta w) for seeds 1..8: compensated (* = not compensated) | plain\n");
  for (const auto& c : cases) {
    Group one;
    std::vector<NoisyRun> runs;
    const auto clean = mlce::reference::damped_oscillator(c.n, dt, c.zeta, w);
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
      runs.push_back(run_noisy(clean, dt, -c.zeta * w, c.noise, seed));
      char what[96];
      std::snprintf(what, sizeof what, "zeta %g noise %g %% seed %llu", c.zeta, 100 * c.noise,
                    static_cast<unsigned long long>(seed));
      one.add(runs.back(), what), all.add(runs.back(), what);
    }
    std::printf("%5.3f %5.1f %% %6zu  ", c.zeta, 100 * c.noise, c.n);
    for (const auto& q : runs) std::printf(" %6.3f%s", q.compensated, q.was_compensated ? " " : "*");
    std::printf(" |");
    for (const auto& q : runs) std::printf(" %6.3f", q.plain);
    std::printf("\n");
    one.print_case();
  }
  all.print_all();
}
