#include "mlce/convergence.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace mlce {

void ConvergenceOptions::validate() const {
  if (parts < 2) throw OptionError("convergence.parts = " + std::to_string(parts) + ": expected >= 2");
  if (!(relative_tolerance >= 0.0)) throw OptionError("convergence.relative_tolerance: expected >= 0");
  if (!(frequency_tolerance >= 0.0)) throw OptionError("convergence.frequency_tolerance: expected >= 0");
  reading.validate();
}

namespace {

ConvergencePoint point_of(const MlceResult& r, std::size_t samples, double t_end, const ReadingOptions& reading) {
  ConvergencePoint p;
  p.samples = samples, p.t_end = t_end, p.estimated = true;
  p.lambda = r.lambda, p.ci95_low = r.ci95_low, p.ci95_high = r.ci95_high;
  p.delay = r.delay, p.dim = r.dim, p.theiler = r.theiler;
  p.warnings = r.warnings.size();
  const Reading read = read_stability(r, reading);
  p.stability = read.stability, p.motion = read.motion;
  p.in_decay_floor = r.in_decay_floor;
  return p;
}

}  // namespace

double exponent_resolution(double lambda, double mean_frequency, double relative_tolerance, double frequency_tolerance) {
  return std::max(relative_tolerance * std::abs(lambda), frequency_tolerance * mean_frequency);
}

ConvergenceResult estimate_convergence(const Series& series, const ConvergenceOptions& options) {
  options.validate();
  const std::size_t n = series.size();
  ConvergenceResult result;
  MlceOptions quiet = options.estimate;
  quiet.progress = nullptr;  // one progress line per part, not per stage
  const auto report = [&](const std::string& stage, std::size_t done) {
    if (options.estimate.progress)
      options.estimate.progress(stage, static_cast<double>(done) / static_cast<double>(options.parts));
  };
  // The whole run first: its errors are the caller's, and it is the reference of the verdict.
  report("the whole run", 0);
  // After the whole run: a series too short to estimate is the data's error (mlce convergence on 3
  // samples said "convergence.parts = 8: more parts than the series has samples", a usage error).
  const MlceResult whole = estimate_mlce(series, quiet);
  if (options.parts > n)
    throw OptionError("convergence.parts = " + std::to_string(options.parts) + ": more parts than the series has samples (" +
                      std::to_string(n) + ")");
  result.warnings = whole.warnings;
  for (std::size_t k = 1; k < options.parts; ++k) {
    report("part " + std::to_string(k) + " of " + std::to_string(options.parts), k);
    const std::size_t samples = n * k / options.parts;
    const double t_end = series.time(samples > 0 ? samples - 1 : 0);
    try {
      result.points.push_back(point_of(estimate_mlce(leading_samples(series, samples), quiet), samples, t_end, options.reading));
    } catch (const InputError& e) {  // too short for the estimator: recorded, the longer parts go on
      ConvergencePoint p;
      p.samples = samples, p.t_end = t_end, p.error = e.what();
      result.points.push_back(p);
    }
  }
  result.points.push_back(point_of(whole, n, series.time(n - 1), options.reading));

  // Verdict over the parts k >= parts/2 (at least half the run, up to rounding).
  const double half_width = 0.5 * (whole.ci95_high - whole.ci95_low);
  result.tolerance_floor = exponent_resolution(whole.lambda, whole.mean_period.mean_frequency,
                                               options.relative_tolerance, options.frequency_tolerance);
  result.converged = true;
  for (std::size_t k = 1; k <= options.parts; ++k) {  // points[k - 1] is the first k/parts
    const auto& p = result.points[k - 1];
    if (2 * k < options.parts || !p.estimated) continue;
    const double tolerance = std::max({0.5 * (p.ci95_high - p.ci95_low), half_width, result.tolerance_floor});
    if (std::abs(p.lambda - whole.lambda) > tolerance) {
      result.converged = false;
      char text[512];
      std::snprintf(text, sizeof text,
                    "lambda still moves with the run length: %.6g over the first %zu samples (to t = %.6g) against %.6g "
                    "over all %zu, beyond the larger of their 95 %% half-widths and %.3g: the estimate still depends on how much of the "
                    "run is analysed (paper 001 Fig. 6). A motion still developing needs a longer run, a decay into a "
                    "noise floor the floor cut (the default); a limit cycle's 0 is resolved only to the spread of the parts",
                    p.lambda, p.samples, p.t_end, whole.lambda, n, result.tolerance_floor);
      result.warnings.push_back(text);
      break;
    }
  }
  // A drift the intervals hide: where the floor or a developing motion widens the batch-means intervals
  // (paper 001 Fig. 6 with the floor left in: -1.37 +- 0.81 over half the run, -0.61 +- 0.67 over all),
  // every part may lie within them of the whole run while each longer part moves the same way. Nested
  // parts share their samples, so a steady one-way move beyond the tolerance floor is the run length's,
  // not the curve's noise.
  if (result.converged) {
    const std::size_t first = (options.parts + 1) / 2;  // points[first - 1]: the first part of half the run or more
    int direction = 0;
    bool one_way = first < options.parts;
    for (std::size_t k = first; k < options.parts && one_way; ++k) {
      const auto& a = result.points[k - 1];
      const auto& b = result.points[k];
      if (!a.estimated || !b.estimated || b.lambda == a.lambda) one_way = false;
      const int d = b.lambda > a.lambda ? 1 : -1;
      if (direction != 0 && d != direction) one_way = false;
      direction = d;
    }
    const auto& from = result.points[first - 1];
    if (one_way && std::abs(from.lambda - whole.lambda) > result.tolerance_floor) {
      result.converged = false;
      char text[512];
      std::snprintf(text, sizeof text,
                    "lambda still moves with the run length: from %.6g over the first %zu samples (to t = %.6g) to %.6g over "
                    "all %zu, each longer part %s than the one before, by more than %.3g in all (within the parts' 95 %% "
                    "intervals, which the drift widens): the estimate still depends on how much of the run is analysed "
                    "(paper 001 Fig. 6). A motion still developing needs a longer run, a decay into a noise floor the "
                    "floor cut (the default)",
                    from.lambda, from.samples, from.t_end, whole.lambda, n, direction > 0 ? "higher" : "lower",
                    result.tolerance_floor);
      result.warnings.push_back(text);
    }
  }
  // Second verdict: does the reading (stable / neutral / unstable) hold from half the run on? A run
  // can be long enough to tell the sign while lambda still moves by more than its tolerance, and
  // the reverse on a rate near the neutral band's edge.
  const ConvergencePoint& last = result.points.back();
  result.reading_settled = true;
  for (std::size_t k = 1; k < options.parts; ++k) {
    const auto& p = result.points[k - 1];
    if (2 * k < options.parts || !p.estimated || p.stability == last.stability) continue;
    result.reading_settled = false;
    char text[512];
    std::snprintf(text, sizeof text,
                  "the reading changes with the run length: %s (%s) over the first %zu samples (to t = %.6g), %s (%s) over "
                  "all %zu: what the run says about the motion depends on how much of it is analysed (a run too short to "
                  "resolve the rate, a motion still developing, or a noise floor reached; the parts' intervals show which)",
                  to_string(p.stability), p.motion.c_str(), p.samples, p.t_end, to_string(last.stability),
                  last.motion.c_str(), n);
    result.warnings.push_back(text);
    break;
  }
  if (options.estimate.progress) options.estimate.progress("done", 1.0);
  return result;
}

}  // namespace mlce
