// Is the low Rosenstein slope on Roessler x a property of the method or of our embedding and
// search? This computes Rosenstein's curve by brute force (every pair, no kd-tree, no automatic
// parameter) in the true state space (x, y, z) and in the delay embedding of x (m = 3, delay 12),
// Theiler window 57 samples, and prints the local slope per 25 steps in 1/time-unit. Beside them,
// the estimator's phase-aligned curve in the true state space (divergence_curve on the channels
// x, y, z, each scaled to unit deviation, m = 1, the same Theiler window), with the neighbours read
// on the straight segment and on the cubic (RosensteinOptions::Interpolation): is the aligned
// curve's steep start (README, sampling) the delay embedding's, or the alignment's?
//   build/roessler_state_space [N=10000]
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

#include "mlce/rosenstein.hpp"
#include "mlce/series.hpp"
#include "reference_systems.hpp"

namespace {

using Point = std::array<double, 3>;

std::vector<double> curve(const std::vector<Point>& p, std::size_t horizon, std::size_t theiler) {
  const std::size_t n = p.size() - horizon;
  std::vector<double> sum(horizon + 1, 0.0);
  std::vector<std::size_t> count(horizon + 1, 0);
  auto d2 = [&](std::size_t a, std::size_t b) {
    double s = 0;
    for (int c = 0; c < 3; ++c) s += (p[a][c] - p[b][c]) * (p[a][c] - p[b][c]);
    return s;
  };
#pragma omp parallel for schedule(dynamic, 64)
  for (std::ptrdiff_t jj = 0; jj < static_cast<std::ptrdiff_t>(n); ++jj) {
    const auto j = static_cast<std::size_t>(jj);
    double best = std::numeric_limits<double>::infinity();
    std::size_t nn = j;
    for (std::size_t k = 0; k < n; ++k)
      if ((k > j ? k - j : j - k) > theiler && d2(j, k) > 0 && d2(j, k) < best) best = d2(j, k), nn = k;
    if (nn == j) continue;
    std::vector<double> local(horizon + 1);
    for (std::size_t i = 0; i <= horizon; ++i) local[i] = d2(j + i, nn + i);
#pragma omp critical
    for (std::size_t i = 0; i <= horizon; ++i)
      if (local[i] > 0) sum[i] += 0.5 * std::log(local[i]), ++count[i];
  }
  for (std::size_t i = 0; i <= horizon; ++i) sum[i] /= static_cast<double>(count[i]);
  return sum;
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t N = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 10000;
  const double dt = 0.1;
  const std::size_t delay = 12, horizon = 400, theiler = 57;
  auto f = [](const std::array<double, 3>& s) {
    return std::array<double, 3>{-s[1] - s[2], s[0] + 0.2 * s[1], 0.2 + s[2] * (s[0] - 5.7)};
  };
  std::vector<std::vector<double>> c(3);
  for (std::size_t k = 0; k < 3; ++k) c[k] = mlce::reference::sample_flow<3>(f, {1.0, 1.0, 0.0}, dt, N, 500.0, 10, k);
  std::vector<Point> state(N), embedded(N - 2 * delay);
  for (std::size_t i = 0; i < N; ++i) state[i] = {c[0][i], c[1][i], c[2][i]};
  for (std::size_t i = 0; i + 2 * delay < N; ++i) embedded[i] = {c[0][i], c[0][i + delay], c[0][i + 2 * delay]};
  const auto a = curve(state, horizon, theiler), b = curve(embedded, horizon, theiler);
  mlce::RosensteinOptions o;
  o.dim = 1, o.delay = 1, o.theiler = theiler, o.horizon = horizon, o.align_phase = true;
  const mlce::Series xyz = mlce::make_series_with_step(c, dt);
  const auto aligned = mlce::divergence_curve(xyz, o).mean_log_distance;
  o.interpolation = mlce::RosensteinOptions::Interpolation::cubic;
  const auto aligned_cubic = mlce::divergence_curve(xyz, o).mean_log_distance;
  std::printf("# Roessler a = b = 0.2, c = 5.7, dt = 0.1, N = %zu; lambda_1 = 0.0714\n", N);
  std::printf("# steps    slope (x,y,z)   slope (x embedded)   aligned (x,y,z): segment  cubic   [1/time unit, per 25 steps]\n");
  auto slope = [&](const std::vector<double>& y, std::size_t i) { return (y[i + 25] - y[i]) / (25 * dt); };
  for (std::size_t i = 0; i + 25 <= horizon; i += 25)
    std::printf("%3zu..%3zu   %8.4f        %8.4f             %8.4f %8.4f\n", i, i + 25, slope(a, i), slope(b, i),
                slope(aligned, i), slope(aligned_cubic, i));
}
