// How often `mlce convergence` calls a stationary chaotic run unsettled: the 64 Lorenz x (dt 0.01) and
// 64 Roessler x (dt 0.1) series of `build/finite_time_spread starts`' first two seeds (mt19937 seeds 1
// and 2, 32 starts each, N = 10^4), each split into 8 parts, every parameter automatic. Per flow: how
// many verdicts say "not converged", by which clause (a part beyond the intervals and the tolerance
// floor, or the one-way drift from half the run on: ConvergenceOptions::relative_tolerance), and how
// many read a reading that changes with the run length. The series are stationary: each unsettled
// verdict is what N = 10^4 leaves unresolved, not a drift of the motion.
//   build/convergence_verdicts        (about 1 min)
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mlce/convergence.hpp"
#include "reference_systems.hpp"

namespace {

std::vector<std::vector<double>> flow_series(std::array<double, 3> (*flow)(const std::array<double, 3>&), double dt,
                                             double h, double transient) {
  std::vector<std::vector<double>> out;
  for (const auto& x0 : mlce::reference::random_starts(1, 2))
    out.push_back(mlce::reference::sample_flow<3>(flow, x0, dt, 10000, transient, static_cast<std::size_t>(std::lround(dt / h))));
  return out;
}

void study(const char* name, double dt, const std::vector<std::vector<double>>& series) {
  std::size_t unsettled = 0, by_drift = 0, reading_moves = 0;
  for (const auto& x : series) {
    const mlce::ConvergenceResult r = mlce::estimate_convergence(mlce::make_series_with_step({x}, dt), {});
    if (!r.converged) {
      ++unsettled;
      for (const auto& w : r.warnings) by_drift += w.find("each longer part") != std::string::npos;
    }
    reading_moves += !r.reading_settled;
  }
  std::printf("%s: %zu series, not converged %zu (%zu beyond the intervals, %zu by the one-way drift), reading changes %zu\n",
              name, series.size(), unsettled, unsettled - by_drift, by_drift, reading_moves);
}

}  // namespace

int main() {
  study("Lorenz x", 0.01, flow_series(mlce::reference::lorenz_rhs, 0.01, 0.001, 50.0));
  study("Roessler x", 0.1, flow_series(mlce::reference::roessler_rhs, 0.1, 0.01, 500.0));
}
