// Where the slope of Rosenstein's curve on a flow goes wrong: the flow's neutral direction, and
// the pairs' finite size. For Lorenz (dt = 0.01) and Roessler (dt = 0.1), N = 10^4, 12 series each
// from the random starts of finite_time_spread's section 2 (mt19937 seed 1), in the true state
// space (x, y, z: no embedding, so no choice of delay or dimension is involved), nearest neighbours
// by the library's kd-tree with the Theiler window the estimator picks for x (Lorenz 171, Roessler
// 61 samples), each curve's least-squares slope over fixed steps (Lorenz 50..300, Roessler
// 25..250) / lambda_1:
//   plain      <ln |x_nb(i) - x_ref(i)|>, Rosenstein's curve;
//   projected  the same separations with their component along the flow at the reference removed;
//   linear     each pair's initial separation carried by the tangent map along the reference
//              trajectory (RK4, as the series), then projected: the pairs as linear theory sees them;
//   own        the finite-time exponent of the trajectory the series samples.
// In linear theory a separation is c1 E1(t) e1 + c2 f + (decaying parts), with c2 along the flow
// f (exponent 0): removing it leaves c1 E1(t) |P e1|, whose mean log grows at the reference
// window's own exponent from the start. The plain curve keeps c2, which holds its slope below
// lambda_1 until c1 E1 dominates; the estimator's phase alignment removes c2 at step 0 only
// (orthogonally, c2 = -c1 cos(e1, f)), which makes the early slope too steep instead.
//   build/neutral_direction
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <span>
#include <vector>

#include "mlce/embedding.hpp"
#include "mlce/neighbours.hpp"
#include "mlce/numerics.hpp"
#include "reference_systems.hpp"

namespace {

using State = std::array<double, 3>;
using Augmented = std::array<double, 6>;  // state and separation together

using mlce::reference::lorenz_rhs, mlce::reference::lorenz_tangent_rhs;
using mlce::reference::roessler_rhs, mlce::reference::roessler_tangent_rhs;

struct Flow {
  const char* name;
  double lambda, dt, h, transient;
  std::size_t theiler, first, last;
  State (*f)(const State&);
  Augmented (*with_tangent)(const Augmented&);
};

/// ln of |d| and of |d| with its component along v removed.
double log_norm(const State& d) { return 0.5 * std::log(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]); }
double log_norm_across(const State& d, const State& v) {
  const double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], dv = d[0] * v[0] + d[1] * v[1] + d[2] * v[2],
               vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  return 0.5 * std::log(std::max(dd - dv * dv / vv, 1e-300 * dd));
}

void study(const Flow& flow) {
  using mlce::reference::rk4_step;
  constexpr std::size_t n = 10000;
  const auto substeps = static_cast<std::size_t>(std::lround(flow.dt / flow.h));
  const std::size_t horizon = flow.last + 1;
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::printf("%s (dt = %g, N = %zu, state space, Theiler window %zu), slope over steps %zu..%zu / %.4f:\n", flow.name,
              flow.dt, n, flow.theiler, flow.first, flow.last, flow.lambda);
  std::printf("  series | plain | projected | linear | own\n");
  double sum[4] = {}, sum2[4] = {};
  constexpr int kSeries = 12;
  for (int k = 0; k < kSeries; ++k) {
    const State x0{u(gen), u(gen), std::abs(u(gen)) / 3};
    std::array<std::vector<double>, 3> xyz;
    for (std::size_t c = 0; c < 3; ++c)
      xyz[c] = mlce::reference::sample_flow<3>(flow.f, x0, flow.dt, n, flow.transient, substeps, c);
    auto state = [&](std::size_t i) { return State{xyz[0][i], xyz[1][i], xyz[2][i]}; };
    const std::size_t points = n - horizon - 1;
    const mlce::DelayEmbedding embedding({std::span<const double>(xyz[0]), std::span<const double>(xyz[1]),
                                          std::span<const double>(xyz[2])},
                                         1, 1, points);
    std::vector<std::uint32_t> queries(points);
    for (std::size_t i = 0; i < points; ++i) queries[i] = static_cast<std::uint32_t>(i);
    mlce::NeighbourOptions no;
    no.theiler = flow.theiler;
    const auto nearest = mlce::find_nearest_neighbours(embedding, queries, no);
    std::vector<double> plain(horizon + 1), across(horizon + 1), linear(horizon + 1);
    std::size_t pairs = 0;
    for (std::size_t j = 0; j < points; ++j) {
      const std::uint32_t nb = nearest.neighbour[j];
      if (nb == mlce::NeighbourResult::none) continue;
      ++pairs;
      const State r0 = state(j), b0 = state(nb);
      Augmented s{r0[0], r0[1], r0[2], b0[0] - r0[0], b0[1] - r0[1], b0[2] - r0[2]};
      for (std::size_t i = 0; i <= horizon; ++i) {
        const State r = state(j + i), b = state(nb + i), v = flow.f(r);
        const State d{b[0] - r[0], b[1] - r[1], b[2] - r[2]};
        plain[i] += log_norm(d);
        across[i] += log_norm_across(d, v);
        linear[i] += log_norm_across({s[3], s[4], s[5]}, flow.f({s[0], s[1], s[2]}));
        for (std::size_t q = 0; q < substeps; ++q) s = rk4_step<6>(flow.with_tangent, s, flow.h);
      }
    }
    const double own =
        mlce::reference::own_exponent(flow.f, flow.with_tangent, x0, flow.transient, flow.dt, flow.h, n) / flow.lambda;
    double q[4];
    const std::vector<double>* curves[3] = {&plain, &across, &linear};
    for (int c = 0; c < 3; ++c) {
      std::vector<double> mean(horizon + 1);
      for (std::size_t i = 0; i <= horizon; ++i) mean[i] = (*curves[c])[i] / static_cast<double>(pairs);
      q[c] = mlce::fit_line(mean.data(), flow.first, flow.last).slope / flow.dt / flow.lambda;
    }
    q[3] = own;
    for (int c = 0; c < 4; ++c) sum[c] += q[c], sum2[c] += q[c] * q[c];
    std::printf("  %6d | %.3f | %.3f | %.3f | %.3f\n", k + 1, q[0], q[1], q[2], q[3]);
  }
  const char* names[4] = {"plain", "projected", "linear", "own"};
  for (int c = 0; c < 4; ++c) {
    const double mean = sum[c] / kSeries, sd = std::sqrt(std::max(0.0, (sum2[c] - kSeries * mean * mean) / (kSeries - 1)));
    std::printf("  %-9s mean %.3f, standard deviation %.3f\n", names[c], mean, sd);
  }
}

}  // namespace

int main() {
  study({"Lorenz", 0.9056, 0.01, 0.001, 50.0, 171, 50, 300, lorenz_rhs, lorenz_tangent_rhs});
  study({"Roessler", 0.0714, 0.1, 0.01, 500.0, 61, 25, 250, roessler_rhs, roessler_tangent_rhs});
  return 0;
}
