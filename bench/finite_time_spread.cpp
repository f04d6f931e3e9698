// How precisely can one series of N = 10^4 samples give lambda_1? For Roessler x (dt = 0.1, 1000
// time units, lambda_1 = 0.0714) and Lorenz x (dt = 0.01, 100 time units, lambda_1 = 0.9056), two
// independent numbers, no fit rule involved in the first:
//  1. the finite-time exponent of the trajectory itself: the tangent vector integrated along 20
//     consecutive segments as long as one series (RK4, renormalised every sample), each
//     segment's exponent / lambda_1 -- the scatter any estimator from such a series inherits;
//  2. on 32 series from pseudo-random initial states (after a transient): `estimate_mlce` with every
//     parameter automatic, the same with phase alignment off (Rosenstein's plain curve), the slope
//     of the plain curve computed in the true state space (x, y, z) over fixed steps (Roessler
//     0..100, Lorenz 80..300: no embedding, no fit rule), and the finite-time exponent of the very
//     trajectory each series samples, each / lambda_1;
//  3. Henon x and the logistic map on 32 series from random initial states, each beside the
//     finite-time exponent of the very trajectory it samples.
//   build/finite_time_spread
// and, for the length a series needs:
//  4. Lorenz x and Roessler x at N = 5e3 ... 1e5: the automatic estimate and the own exponent of 32
//     random series at each length.
//   build/finite_time_spread lengths
// and, on more series (the automatic estimate and the own exponent):
//  5. Lorenz x and Roessler x at N = 10^4 on 128 series: the starts drawn by mt19937 seeds 1..4,
//     32 each, (x, y) uniform in [-3, 3], z in [0, 1], no offset; how often the estimate's 95 %
//     interval holds lambda_1 (and the own exponent); the series outside 10 % listed
//     with their own exponents, and the series whose fit the concave-growth rule started at the
//     start-up's end; the range of the spectrum's taper_mean_share (mean_period.hpp) over them.
//   build/finite_time_spread starts
// and, for other observables of the same flows (Lorenz y and z, Roessler y; 32 series each, the
// starts of seed 1 above, with own exponents and the intervals' coverage):
//   build/finite_time_spread observables
// and section 3 on 256 series (seed 7), with the intervals' coverage, the Henon series outside 2 %
// listed with their own exponents:
//   build/finite_time_spread maps
// and the verdict of `mlce estimate --each` on channels of one trajectory (Lorenz x, y, z; Roessler
// x, y; 32 series each, the starts of the observables), with the median over the channels, and the
// same channels embedded jointly as one state (several --channel without --each):
//   build/finite_time_spread channels
// and 100 consecutive stretches of 10^4 samples of one Lorenz x run, with the fit rule's 1.5-period
// minimum, without it, and at 1.2 and 1.6 periods:
//   build/finite_time_spread segments
// and 32 Lorenz x series with 0, 1 and 3 % measurement noise, the minimum on and off:
//   build/finite_time_spread noise
// and, on the 128 series of `starts`, the embedding and the Theiler window set otherwise than the
// automatic rules set them (m = 4 or 5 with the automatic delay, or with the delay shortened so
// that the window (m - 1) J stays the automatic one; the Theiler window 0.5, 2 and 4 mean periods;
// the delay one sample shorter or longer), and the mean of five of those embeddings' estimates:
// does any fixed alternative, or their average, read closer to lambda_1? (4 minutes)
//   build/finite_time_spread embedding
// and the sampling step (each row also with the aligned neighbours read on cubics,
// MlceOptions::phase_interpolation): the same 32 Lorenz x trajectories (the starts of `starts`, seed 1) over 100
// and 500 time units sampled at dt = 0.01, 0.02, 0.05, 0.1, and Roessler x over 1000 time units at
// dt = 0.05 ... 0.3, with the delays and dimensions the rules chose (does the estimate depend on
// how finely the solver wrote its output?):
//   build/finite_time_spread sampling
// and one Lorenz x series (N = 10^4, dt = 0.01; the series `build/make_series lorenz 10000 0.01 T X Y Z`
// writes): the automatic estimate, the plain curve's and the own exponent of that trajectory:
//   build/finite_time_spread lorenz X Y Z T
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "mlce/each_channel.hpp"
#include "mlce/estimate.hpp"
#include "mlce/numerics.hpp"
#include "ratio_tally.hpp"
#include "reference_systems.hpp"

namespace {

using State = std::array<double, 3>;
using Tangent = std::array<double, 6>;  // state and tangent vector together

struct System {
  const char* name;
  double lambda, dt, h, transient;   // known exponent, sampling step, RK4 step, discarded time
  std::size_t fit_first, fit_last;   // fixed comparison region of the curve, steps
  State (*flow)(const State&);
  Tangent (*with_tangent)(const Tangent&);
  State start_offset;                // added to the random initial state
  State canonical_start;             // the start of tests/support/reference_systems.hpp's series
};

using mlce::reference::lorenz_rhs, mlce::reference::lorenz_tangent_rhs;
using mlce::reference::roessler_rhs, mlce::reference::roessler_tangent_rhs;

/// The finite-time exponent of the very trajectory a series samples (reference_systems.hpp).
double own_exponent(const System& sys, const State& x0, std::size_t n, int /*substeps: from dt / h*/) {
  return mlce::reference::own_exponent(sys.flow, sys.with_tangent, x0, sys.transient, sys.dt, sys.h, n);
}

using mlce::bench::Tally;

void study(const System& sys) {
  using mlce::reference::rk4_step;
  constexpr std::size_t n = 10000;
  const int substeps = static_cast<int>(std::lround(sys.dt / sys.h));
  Tangent s{1, 1, 1 + sys.start_offset[2], 1, 0, 0};
  // NOLINTNEXTLINE(clang-analyzer-security.FloatLoopCounter): warm-up timed as in reference_systems.hpp
  for (double t = 0; t < 100.0; t += sys.h) s = rk4_step<6>(sys.with_tangent, s, sys.h);
  const double aligned = std::sqrt(s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
  for (int c = 3; c < 6; ++c) s[c] /= aligned;  // the warm-up's growth is not part of segment 1
  std::printf("%s: finite-time exponent of 20 consecutive %g-time-unit segments / %.4f:\n", sys.name, n * sys.dt,
              sys.lambda);
  double sum = 0, sum2 = 0;
  for (int seg = 0; seg < 20; ++seg) {
    long double acc = 0;
    for (std::size_t k = 0; k < n; ++k) {
      for (int j = 0; j < substeps; ++j) s = rk4_step<6>(sys.with_tangent, s, sys.h);
      const double norm = std::sqrt(s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
      acc += std::log(norm);
      for (int c = 3; c < 6; ++c) s[c] /= norm;
    }
    const double ratio = static_cast<double>(acc) / (n * sys.dt) / sys.lambda;
    sum += ratio, sum2 += ratio * ratio;
    std::printf(" %.3f", ratio);
  }
  const double mean = sum / 20, sd = std::sqrt((sum2 - 20 * mean * mean) / 19);
  std::printf("\n  mean %.3f, standard deviation %.3f\n", mean, sd);

  constexpr int kSeries = 32;
  std::printf("%s: %d series from random initial states (N = 10^4, dt = %g), each / %.4f:\n"
              "  automatic (phase alignment auto) | alignment off | plain curve in (x, y, z), steps %zu..%zu | own exponent\n",
              sys.name, kSeries, sys.dt, sys.lambda, sys.fit_first, sys.fit_last);
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  Tally automatic, off, state, own;
  for (int k = 0; k < kSeries; ++k) {
    State x0{u(gen), u(gen), std::abs(u(gen)) / 3};
    for (int c = 0; c < 3; ++c) x0[c] += sys.start_offset[c];
    const auto x = mlce::reference::sample_flow<3>(sys.flow, x0, sys.dt, n, sys.transient, substeps);
    const auto series = mlce::make_series_with_step({x}, sys.dt);
    const auto r = mlce::estimate_mlce(series, {});
    mlce::MlceOptions plain;
    plain.phase_alignment = mlce::PhaseAlignment::off;
    const auto p = mlce::estimate_mlce(series, plain);
    const double o = own_exponent(sys, x0, n, substeps) / sys.lambda;
    // Rosenstein's plain curve in the true state space (x, y, z; no embedding), same Theiler window.
    std::vector<std::vector<double>> xyz{x};
    for (std::size_t c = 1; c < 3; ++c)
      xyz.push_back(mlce::reference::sample_flow<3>(sys.flow, x0, sys.dt, n, sys.transient, substeps, c));
    mlce::MlceOptions so = plain;
    so.dim = 1, so.delay = 1, so.theiler = r.theiler, so.horizon = sys.fit_last + 1;
    const auto ss = mlce::estimate_mlce(mlce::make_series_with_step(xyz, sys.dt), so);
    const double st =
        mlce::fit_line(ss.curve.mean_log_distance.data(), sys.fit_first, sys.fit_last).slope / sys.dt / sys.lambda;
    automatic.add(r.lambda / sys.lambda, o), off.add(p.lambda / sys.lambda, o), state.add(st, o), own.add(o, o);
    automatic.check_flags(r);
    std::printf("  series %2d: %.3f | %.3f | %.3f | %.3f\n", k + 1, r.lambda / sys.lambda, p.lambda / sys.lambda, st, o);
  }
  automatic.print("automatic");
  off.print("alignment off");
  state.print("plain (x, y, z), fixed steps");
  own.print("own exponent");
  // The tests' and data/'s series (reference::lorenz_x / roessler_x: from the canonical start).
  const auto xc = mlce::reference::sample_flow<3>(sys.flow, sys.canonical_start, sys.dt, n, sys.transient, substeps);
  std::printf("  canonical series (start %g, %g, %g): automatic %.3f, own exponent %.3f\n", sys.canonical_start[0],
              sys.canonical_start[1], sys.canonical_start[2],
              mlce::estimate_mlce(mlce::make_series_with_step({xc}, sys.dt), {}).lambda / sys.lambda,
              own_exponent(sys, sys.canonical_start, n, substeps) / sys.lambda);
}

/// How long must a series be? The automatic estimate on 32 random series at each length N (same
/// sampling step, same discarded transient), beside the finite-time exponent of the very trajectory
/// each series samples (its rms is the floor any estimator inherits at that length).
void length_study(const System& sys, const std::vector<std::size_t>& lengths) {
  using mlce::reference::rk4_step;
  constexpr int kSeries = 32;
  const int substeps = static_cast<int>(std::lround(sys.dt / sys.h));
  std::printf("%s: automatic estimate and own exponent against series length (32 random series each, dt = %g):\n",
              sys.name, sys.dt);
  for (const std::size_t n : lengths) {
    std::mt19937 gen(1);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    Tally automatic, own;
    for (int k = 0; k < kSeries; ++k) {
      State x0{u(gen), u(gen), std::abs(u(gen)) / 3};
      for (int c = 0; c < 3; ++c) x0[c] += sys.start_offset[c];
      const auto x = mlce::reference::sample_flow<3>(sys.flow, x0, sys.dt, n, sys.transient, substeps);
      const double o = own_exponent(sys, x0, n, substeps) / sys.lambda;
      const auto r = mlce::estimate_mlce(mlce::make_series_with_step({x}, sys.dt), {});
      automatic.add(r.lambda / sys.lambda, o);
      automatic.check_flags(r);
      own.add(o, o);
    }
    char label[64];
    std::snprintf(label, sizeof label, "N = %zu, automatic", n);
    automatic.print(label);
    std::snprintf(label, sizeof label, "N = %zu, own exponent", n);
    own.print(label);
  }
}

/// More series than the other studies, from other starts: 4 seeds x 32 (section 5 of the header).
void starts_study(const System& sys) {
  constexpr std::size_t n = 10000;
  const int substeps = static_cast<int>(std::lround(sys.dt / sys.h));
  Tally automatic;
  std::string outside, joined, skipped;
  double least_taper_share = 1.0, most_taper_share = 0.0;  // MeanPeriodResult::taper_mean_share over the series
  for (unsigned seed = 1; seed <= 4; ++seed) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (int k = 0; k < 32; ++k) {
      const State x0{u(gen), u(gen), std::abs(u(gen)) / 3};
      const auto x = mlce::reference::sample_flow<3>(sys.flow, x0, sys.dt, n, sys.transient, substeps);
      const auto r = mlce::estimate_mlce(mlce::make_series_with_step({x}, sys.dt), {});
      const double q = r.lambda / sys.lambda, o = own_exponent(sys, x0, n, substeps) / sys.lambda;
      automatic.add(q, o, r.ci95_low / sys.lambda, r.ci95_high / sys.lambda);
      automatic.check_flags(r);
      least_taper_share = std::min(least_taper_share, r.mean_period.taper_mean_share);
      most_taper_share = std::max(most_taper_share, r.mean_period.taper_mean_share);
      if (r.fit.rule.find("concave growth") != std::string::npos) {
        char item[128];
        std::snprintf(item, sizeof item, " seed %u #%d: %.3f (fit %zu..%zu);", seed, k + 1, q, r.fit.first, r.fit.last);
        joined += item;
      }
      if (r.skipped_start > 0) {  // on the attractor (the transient is discarded): should not happen
        mlce::MlceOptions keep;
        keep.skip_nonrecurrent_start = false;
        const double kept = mlce::estimate_mlce(mlce::make_series_with_step({x}, sys.dt), keep).lambda / sys.lambda;
        char item[160];
        std::snprintf(item, sizeof item, " seed %u #%d: first %zu samples (windows score %.2f", seed, k + 1, r.skipped_start,
                      r.recurrence.ratio.front());
        skipped += item;
        if (r.recurrence.by_distance) {  // recurrence.hpp's distance test decided
          skipped += "; left out by distance, ratios";
          for (double ratio : r.recurrence.distance_ratio) std::snprintf(item, sizeof item, " %.2f", ratio), skipped += item;
        }
        std::snprintf(item, sizeof item, "), %.3f (kept: %.3f);", q, kept);
        skipped += item;
      }
      if (std::abs(q - 1) > 0.10) {
        char item[128];
        std::snprintf(item, sizeof item, " seed %u #%d: %.3f, own %.3f (fit %zu..%zu);", seed, k + 1, q, o, r.fit.first,
                      r.fit.last);
        outside += item;
      }
    }
  }
  std::printf("%s: 128 series (N = 10^4, dt = %g, seeds 1..4 x 32 starts), automatic / %.4f:\n", sys.name, sys.dt,
              sys.lambda);
  automatic.print("automatic");
  std::printf("  outside 10 %%:%s\n", outside.empty() ? " none" : outside.c_str());
  std::printf("  start left out as not recurring:%s\n", skipped.empty() ? " none" : skipped.c_str());
  std::printf("  fitted from the start-up's end (concave growth):%s\n", joined.empty() ? " none" : joined.c_str());
  std::printf("  the plain mean beneath the spectrum's taper holds %.2g .. %.2g of its energy (taper-weighted above %g)\n",
              least_taper_share, most_taper_share, mlce::kTaperMeanShare);
}

/// The 128 series of starts_study with the embedding or the Theiler window set by hand, each variant
/// derived from the automatic choice of the same series (its delay J, dimension m0, mean period).
void embedding_study(const System& sys) {
  constexpr std::size_t n = 10000;
  const int substeps = static_cast<int>(std::lround(sys.dt / sys.h));
  struct Variant {
    const char* label;
    std::size_t dim;        // 0 = automatic
    double window_kept;     // > 0: delay = round(automatic (m0 - 1) J / (dim - 1)), the window kept
    double theiler_factor;  // 0 = automatic
    int delay_shift = 0;    // != 0: delay = automatic J + shift, automatic m
  };
  const std::vector<Variant> variants{{"automatic", 0, 0, 0},
                                      {"m = 4, automatic delay", 4, 0, 0},
                                      {"m = 5, automatic delay", 5, 0, 0},
                                      {"m = 4, window (m - 1) J kept", 4, 1, 0},
                                      {"m = 5, window (m - 1) J kept", 5, 1, 0},
                                      {"Theiler 0.5 mean periods", 0, 0, 0.5},
                                      {"Theiler 2 mean periods", 0, 0, 2},
                                      {"Theiler 4 mean periods", 0, 0, 4},
                                      {"delay J - 1", 0, 0, 0, -1},
                                      {"delay J + 1", 0, 0, 0, +1}};
  // An ensemble of embeddings: would averaging the estimates of neighbouring (m, J) cancel part of
  // the scatter? Only if their errors were independent: they come from pairs of the same series.
  const std::vector<std::size_t> ensemble{0, 3, 4, 8, 9};
  Tally ensemble_mean;
  std::vector<Tally> tallies(variants.size());
  for (unsigned seed = 1; seed <= 4; ++seed) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (int k = 0; k < 32; ++k) {
      const State x0{u(gen), u(gen), std::abs(u(gen)) / 3};
      const auto series = mlce::make_series_with_step({mlce::reference::sample_flow<3>(sys.flow, x0, sys.dt, n, sys.transient, substeps)}, sys.dt);
      const auto automatic = mlce::estimate_mlce(series, {});
      std::vector<double> ratios(variants.size());
      for (std::size_t v = 0; v < variants.size(); ++v) {
        const Variant& var = variants[v];
        mlce::MlceOptions o;
        if (var.dim > 0) o.dim = var.dim;
        if (var.window_kept > 0)
          o.delay = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(
                                                 static_cast<double>((automatic.dim - 1) * automatic.delay) / static_cast<double>(var.dim - 1))));
        if (var.theiler_factor > 0)
          o.theiler = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(var.theiler_factor * static_cast<double>(automatic.theiler))));
        if (var.delay_shift != 0)
          o.delay = static_cast<std::size_t>(std::max<long>(1, static_cast<long>(automatic.delay) + var.delay_shift));
        const auto r = v == 0 ? automatic : mlce::estimate_mlce(series, o);
        ratios[v] = r.lambda / sys.lambda;
        tallies[v].add(ratios[v]);
      }
      double sum = 0;
      for (const std::size_t v : ensemble) sum += ratios[v];
      ensemble_mean.add(sum / static_cast<double>(ensemble.size()));
    }
    std::fprintf(stderr, "%s: seed %u of 4 done\n", sys.name, seed);
  }
  std::printf("%s: 128 series (N = 10^4, dt = %g, the starts of `starts`), / %.4f:\n", sys.name, sys.dt, sys.lambda);
  for (std::size_t v = 0; v < variants.size(); ++v) tallies[v].print(variants[v].label);
  ensemble_mean.print("mean of the automatic, m = 4 and 5 (window kept), J - 1, J + 1");
}

/// Other observables of the same flows (an MBDyn analyst does not choose which channel is
/// chaotic): 32 series each (seed 1, the starts of starts_study) of component `component`, with
/// the own exponents of the same trajectories and the intervals' coverage.
void observable_study(const System& sys, std::size_t component, const char* label) {
  constexpr std::size_t n = 10000;
  const int substeps = static_cast<int>(std::lround(sys.dt / sys.h));
  Tally automatic;
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int k = 0; k < 32; ++k) {
    const State x0{u(gen), u(gen), std::abs(u(gen)) / 3};
    const auto x = mlce::reference::sample_flow<3>(sys.flow, x0, sys.dt, n, sys.transient, substeps, component);
    const auto r = mlce::estimate_mlce(mlce::make_series_with_step({x}, sys.dt), {});
    automatic.add(r.lambda / sys.lambda, own_exponent(sys, x0, n, substeps) / sys.lambda, r.ci95_low / sys.lambda,
                  r.ci95_high / sys.lambda);
    automatic.check_flags(r);
  }
  std::printf("%s: 32 series (N = 10^4, dt = %g), automatic / %.4f:\n", label, sys.dt, sys.lambda);
  automatic.print("automatic");
}

std::string fmt_series(int k) { return " #" + std::to_string(k) + ":"; }

/// Several observables of one trajectory share lambda_1: how often does the verdict of
/// `mlce estimate --each` (estimate_each_channel) say they disagree, on 32 series (seed 1, the
/// starts of observable_study) whose channels are components of the same run? Each disagreement is
/// listed with its channels' estimates. Also the median over the channels as an estimate of lambda_1.
void channels_study(const System& sys, const std::vector<std::size_t>& components, const char* label) {
  constexpr std::size_t n = 10000;
  const int substeps = static_cast<int>(std::lround(sys.dt / sys.h));
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  Tally median, first, joint, joint_curve_first_region, first_curve_joint_region;
  std::vector<Tally> other_curve_first_region(components.size());  // channel c's curve over the first's region
  int agree = 0, not_judged = 0, widened_count = 0;
  std::string disagreements, widened;  // joint states FNN left with fewer than 3 coordinates (estimate_mlce widens them)
  for (int k = 0; k < 32; ++k) {
    const State x0{u(gen), u(gen), std::abs(u(gen)) / 3};
    std::vector<std::vector<double>> channels;
    for (const std::size_t c : components)
      channels.push_back(mlce::reference::sample_flow<3>(sys.flow, x0, sys.dt, n, sys.transient, substeps, c));
    mlce::Series series = mlce::make_series_with_step(std::move(channels), sys.dt);
    for (const std::size_t c : components) series.names.push_back(std::string(1, "xyz"[c]));
    const double own = own_exponent(sys, x0, n, substeps) / sys.lambda;
    // The channels as one state (several --channel without --each): embedded jointly.
    const auto together = mlce::estimate_mlce(series, {});
    joint.add(together.lambda / sys.lambda, own, together.ci95_low / sys.lambda, together.ci95_high / sys.lambda);
    if (together.dim_widened_because == mlce::DimensionWidening::flow_in_a_plane) {
      char item[64];
      std::snprintf(item, sizeof item, " #%d (%.1f %% false)", k + 1, 100.0 * together.fnn->fraction[*together.dim_widened_from - 1]);
      widened += item;
      ++widened_count;
    }
    const auto r = mlce::estimate_each_channel(series, {});
    if (r.estimated < 2) {
      ++not_judged;
      continue;
    }
    median.add(r.verdict.median_lambda / sys.lambda, own);
    if (const auto& alone = r.channels[0].result) {
      first.add(alone->lambda / sys.lambda, own);
      // Where does the joint state's difference come from: its curve (fitted over the first channel's
      // region) or its region (the first channel's curve fitted over it)? Both curves phase-aligned.
      const auto slope_over = [&](const mlce::MlceResult& curve_of, const mlce::FitResult& region) {
        const auto& y = curve_of.curve.mean_log_distance;
        const std::size_t last = std::min(region.last, y.size() - 1);
        return mlce::fit_line(y.data(), region.first, last).slope / sys.dt / sys.lambda;
      };
      joint_curve_first_region.add(slope_over(together, alone->fit), own);
      first_curve_joint_region.add(slope_over(*alone, together.fit), own);
      for (std::size_t c = 1; c < components.size(); ++c)
        if (const auto& other = r.channels[c].result) other_curve_first_region[c].add(slope_over(*other, alone->fit), own);
    }
    if (r.verdict.agree) {
      ++agree;
      continue;
    }
    disagreements += fmt_series(k + 1);
    for (const auto& c : r.channels)
      if (c.result) {
        char item[96];
        std::snprintf(item, sizeof item, " %s %.3f [%.3f, %.3f]", c.name.c_str(), c.result->lambda / sys.lambda,
                      c.result->ci95_low / sys.lambda, c.result->ci95_high / sys.lambda);
        disagreements += item;
      }
    disagreements += ";";
  }
  std::printf("%s: 32 series (N = 10^4, dt = %g), every channel on its own (estimate --each):\n", label, sys.dt);
  std::printf("  the verdict says they agree on %d of 32 (not judged: %d)\n", agree, not_judged);
  std::printf("  disagreements (lambda / %.4f, 95 %% interval):%s\n", sys.lambda,
              disagreements.empty() ? " none" : disagreements.c_str());
  median.print("median of the channels");
  first.print((std::string(1, "xyz"[components[0]]) + " alone").c_str());
  joint.print("embedded jointly");
  std::printf("                                 widened to 3 coordinates (a flow in a plane) on %d of 32:%s\n", widened_count,
              widened.empty() ? " none" : widened.c_str());
  joint_curve_first_region.print((std::string("joint curve, ") + "xyz"[components[0]] + "'s region").c_str());
  first_curve_joint_region.print((std::string(1, "xyz"[components[0]]) + "'s curve, the joint region").c_str());
  for (std::size_t c = 1; c < components.size(); ++c)
    other_curve_first_region[c].print(
        (std::string(1, "xyz"[components[c]]) + "'s curve alone, " + "xyz"[components[0]] + "'s region").c_str());
}

/// Consecutive stretches of one long run: Lorenz x from (1, 1, 1) after 50
/// time units, 10^6 samples cut into 100 series of 10^4, each estimated on its own; the fit rule's
/// 1.5-period minimum (FitOptions::min_periods) on and off.
void segments_study() {
  constexpr std::size_t n = 10000, count = 100;
  const auto all = mlce::reference::lorenz_x(n * count, 0.01);
  for (const double min_periods : {1.5, 0.0, 1.2, 1.6}) {
    mlce::MlceOptions options;
    options.fit.min_periods = min_periods;
    Tally automatic;
    for (std::size_t k = 0; k < count; ++k) {
      const std::vector<double> x(all.begin() + static_cast<std::ptrdiff_t>(k * n), all.begin() + static_cast<std::ptrdiff_t>((k + 1) * n));
      automatic.add(mlce::estimate_mlce(mlce::make_series_with_step({x}, 0.01), options).lambda / 0.9056);
    }
    char label[64];
    std::snprintf(label, sizeof label, min_periods == 1.5 ? "automatic" : min_periods == 0 ? "min_periods 0 (before)" : "min_periods %.1f", min_periods);
    automatic.print(label);
  }
}

/// Measurement noise and the 1.5-period minimum: 32 Lorenz x series (mt19937 seed 1, (x, y) in
/// [-3, 3], z in [0, 1], after 50 time units) plus white Gaussian noise of 1 % and 3 % of the clean
/// series' standard deviation (mt19937_64 seed 3 + series number), automatic with min_periods 1.5
/// and 0. A noisy curve's first step jumps, and the minimum then stands aside (fit.hpp): the two
/// rows agree on noisy series and differ on clean ones.
void noise_study() {
  for (const double level : {0.0, 0.01, 0.03}) {
    for (const double min_periods : {1.5, 0.0}) {
      mlce::MlceOptions options;
      options.fit.min_periods = min_periods;
      std::mt19937 gen(1);
      std::uniform_real_distribution<double> u(-3.0, 3.0);
      Tally automatic;
      for (int k = 0; k < 32; ++k) {
        const State x0{u(gen), u(gen), std::abs(u(gen)) / 3};
        auto x = mlce::reference::lorenz_x(10000, 0.01, x0);
        double mean = 0, var = 0;
        for (const double v : x) mean += v / static_cast<double>(x.size());
        for (const double v : x) var += (v - mean) * (v - mean) / static_cast<double>(x.size());
        std::mt19937_64 noise_gen(static_cast<std::uint64_t>(k) + 3);
        std::normal_distribution<double> noise(0.0, level * std::sqrt(var) + 1e-300);
        if (level > 0)
          for (double& v : x) v += noise(noise_gen);
        automatic.add(mlce::estimate_mlce(mlce::make_series_with_step({x}, 0.01), options).lambda / 0.9056);
      }
      char label[64];
      std::snprintf(label, sizeof label, "noise %.0f %%, min_periods %.1f", 100 * level, min_periods);
      automatic.print(label);
    }
  }
}

/// Maps (issue 2: Henon x and logistic r = 4 within 2 % at N = 10^4): series from random
/// initial states after 1000 (Henon) or 100 (logistic) iterations, every parameter automatic,
/// beside the finite-time exponent of the very trajectory each samples (reference::
/// henon_own_exponent, logistic_own_exponent).
void map_study(int series, unsigned seed) {
  constexpr std::size_t n = 10000;
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  Tally henon, logistic, henon_own, logistic_own;
  for (Tally* t : {&henon, &logistic, &henon_own, &logistic_own}) t->tight = 0.02, t->loose = 0.05, t->digits = 4;
  constexpr double kHenon = 0.41922;
  const double kLogistic = std::log(2.0);
  std::string outside;
  for (int k = 0; k < series; ++k) {
    const double x = u(gen) - 0.5, y = 0.3 * (u(gen) - 0.5), z = u(gen);
    const auto h = mlce::reference::henon_x(n, x, y), l = mlce::reference::logistic(n, z);
    const auto rh = mlce::estimate_mlce(mlce::make_series_with_step({h}, 1.0), {});
    const auto rl = mlce::estimate_mlce(mlce::make_series_with_step({l}, 1.0), {});
    const double qh = rh.lambda / kHenon;
    const double oh = mlce::reference::henon_own_exponent(n, x, y) / kHenon;
    const double ol = mlce::reference::logistic_own_exponent(l) / kLogistic;
    henon.add(qh, oh, rh.ci95_low / kHenon, rh.ci95_high / kHenon), henon_own.add(oh, oh);
    logistic.add(rl.lambda / kLogistic, ol, rl.ci95_low / kLogistic, rl.ci95_high / kLogistic);
    logistic_own.add(ol, ol);
    henon.check_flags(rh), logistic.check_flags(rl);
    if (std::abs(qh - 1) > 0.02) {
      char item[64];
      std::snprintf(item, sizeof item, " #%d: %.4f, own %.4f;", k + 1, qh, oh);
      outside += item;
    }
  }
  std::printf("Maps: %d series from random initial states (N = 10^4), each / known exponent:\n", series);
  henon.print("Henon x (0.41922)");
  henon_own.print("Henon x, own exponent");
  std::printf("  Henon x outside 2 %%:%s\n", outside.empty() ? " none" : outside.c_str());
  logistic.print("logistic r = 4 (ln 2)");
  logistic_own.print("logistic, own exponent");
}

/// One system over `duration` time units at each sampling step (section "sampling" of the header):
/// the same 32 trajectories (seed 1, the starts of starts_study) at every step.
void sampling_study(const System& sys, double duration, const std::vector<double>& steps, double tight) {
  std::printf("%s over %g time units, 32 series (seed 1), automatic / %.4f:\n", sys.name, duration, sys.lambda);
  for (double dt : steps) {
    const std::size_t n = static_cast<std::size_t>(std::lround(duration / dt));
    const auto substeps = static_cast<std::size_t>(std::max<long>(1, std::lround(dt / sys.h)));
    Tally automatic, cubic;
    automatic.tight = tight, automatic.loose = 2 * tight;
    cubic.tight = tight, cubic.loose = 2 * tight;
    mlce::MlceOptions on_cubics;
    on_cubics.phase_interpolation = mlce::RosensteinOptions::Interpolation::cubic;
    std::vector<int> delays(64, 0), dims(16, 0);
    std::mt19937 gen(1);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (int k = 0; k < 32; ++k) {
      const State x0{u(gen), u(gen), std::abs(u(gen)) / 3};
      const auto x = mlce::reference::sample_flow<3>(sys.flow, x0, dt, n, sys.transient, substeps);
      const auto r = mlce::estimate_mlce(mlce::make_series_with_step({x}, dt), {});
      automatic.add(r.lambda / sys.lambda);
      ++delays[std::min<std::size_t>(r.delay, 63)], ++dims[std::min<std::size_t>(r.dim, 15)];
      cubic.add(mlce::estimate_mlce(mlce::make_series_with_step({x}, dt), on_cubics).lambda / sys.lambda);
    }
    char label[64];
    std::snprintf(label, sizeof label, "dt = %g (N = %zu)", dt, n);
    automatic.print(label);
    std::printf("  %-30s delays", "");
    for (std::size_t d = 0; d < delays.size(); ++d)
      if (delays[d]) std::printf(" %zu x%d", d, delays[d]);
    std::printf(", dimensions");
    for (std::size_t d = 0; d < dims.size(); ++d)
      if (dims[d]) std::printf(" %zu x%d", d, dims[d]);
    std::printf("\n");
    std::snprintf(label, sizeof label, "  --phase-interpolation cubic");
    cubic.print(label);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const System roessler_x{"Roessler x", 0.0714, 0.1, 0.01, 500.0, 0, 100, roessler_rhs, roessler_tangent_rhs, {0, 0, 0}, {1, 1, 0}};
  const System lorenz_x{"Lorenz x", 0.9056, 0.01, 0.001, 50.0, 80, 300, lorenz_rhs, lorenz_tangent_rhs, {0, 0, 20}, {1, 1, 1}};
  System lorenz_plain = lorenz_x;  // the starts of `starts` and `embedding`: z near 0, not shifted by 20
  lorenz_plain.start_offset = {0, 0, 0};
  if (argc > 1 && std::string(argv[1]) == "lengths") {
    length_study(lorenz_x, {5000, 10000, 20000, 50000, 100000});
    length_study(roessler_x, {5000, 10000, 20000, 50000, 100000});
    return 0;
  }
  if (argc > 1 && std::string(argv[1]) == "starts") {
    starts_study(lorenz_plain);
    starts_study(roessler_x);
    return 0;
  }
  if (argc > 1 && std::string(argv[1]) == "embedding") {
    embedding_study(lorenz_plain);
    embedding_study(roessler_x);
    return 0;
  }
  if (argc > 1 && std::string(argv[1]) == "observables") {
    observable_study(lorenz_x, 1, "Lorenz y");
    observable_study(lorenz_x, 2, "Lorenz z");
    observable_study(roessler_x, 1, "Roessler y");
    return 0;
  }
  if (argc == 6 && std::string(argv[1]) == "lorenz") {
    const State x0{std::strtod(argv[2], nullptr), std::strtod(argv[3], nullptr), std::strtod(argv[4], nullptr)};
    System sys = lorenz_x;
    sys.transient = std::strtod(argv[5], nullptr);
    const std::size_t n = 10000;
    const auto x = mlce::reference::lorenz_x(n, sys.dt, x0, sys.transient);  // = make_series lorenz n dt T X Y Z
    const auto r = mlce::estimate_mlce(mlce::make_series_with_step({x}, sys.dt), {});
    std::printf("Lorenz x from (%g, %g, %g) after %g time units, N = %zu: automatic %.4f (%.3f x lambda_1, fit %zu..%zu, "
                "plain curve %.3f x), own exponent %.3f x lambda_1\n",
                x0[0], x0[1], x0[2], sys.transient, n, r.lambda, r.lambda / sys.lambda, r.fit.first, r.fit.last,
                r.unaligned_lambda / sys.lambda, own_exponent(sys, x0, n, 10) / sys.lambda);
    return 0;
  }
  if (argc > 1 && std::string(argv[1]) == "channels") {
    channels_study(lorenz_x, {0, 1, 2}, "Lorenz x, y, z");
    channels_study(roessler_x, {0, 1}, "Roessler x, y");
    return 0;
  }
  if (argc > 1 && std::string(argv[1]) == "segments") {
    std::printf("Lorenz x: 100 consecutive series of 10^4 samples from one run (dt = 0.01), automatic / 0.9056:\n");
    segments_study();
    return 0;
  }
  if (argc > 1 && std::string(argv[1]) == "noise") {
    std::printf("Lorenz x, 32 series (N = 10^4, dt = 0.01) with measurement noise, automatic / 0.9056:\n");
    noise_study();
    return 0;
  }
  if (argc > 1 && std::string(argv[1]) == "sampling") {
    sampling_study(lorenz_plain, 100.0, {0.01, 0.02, 0.05, 0.1}, 0.05);
    sampling_study(lorenz_plain, 500.0, {0.01, 0.02, 0.05, 0.1}, 0.05);
    sampling_study(roessler_x, 1000.0, {0.05, 0.1, 0.2, 0.3}, 0.10);
    return 0;
  }
  if (argc > 1 && std::string(argv[1]) == "maps") {
    map_study(256, 7);
    return 0;
  }
  study(roessler_x);
  study(lorenz_x);
  map_study(32, 3);
}
