// Why does the phase-aligned curve start steeper than lambda_1 (Lorenz's start-up, Roessler's
// concave curve), and what would make it straight? A diagnostic with the known equations, in the
// true state space: nearest neighbours by the exact kd-tree search (Euclidean, raw coordinates, Theiler window
// T), each pair followed with the neighbour moved along its own trajectory by a shift s (cubic
// interpolation between samples), for three choices of s:
//   none        s = 0 (the plain curve);
//   orthogonal  s removes the separation's component along the flow f by orthogonal projection
//               (what RosensteinOptions::align_phase does from data: the closest phase);
//   oblique     s removes only the flow's share of the separation decomposed along (u, f, u x f),
//               u the unstable direction at the neighbour (the tangent vector carried along the
//               trajectory from 500 time units before: the backward Lyapunov vector);
//   data        the same with u estimated from the data alone (see run()): a first try at the open
//               step below.
// The orthogonal projection also removes the part of u's component that lies along f, which the
// curve then regains at the rate lambda_1: |v(t)|^2 ~ e^{2 lt} - 2 k e^{lt} + k, k = cos^2(u, f),
// whose slope is above lambda_1 for a few 1 / lambda_1 (Roessler: 140 samples, its whole fit region).
// Prints the local slope of each curve per sixteenth of the horizon, / lambda_1; then the same
// shifts in the delay embedding of Lorenz x (embedded_lorenz), there with u and the flow also
// estimated from the embedded series alone ("data").
//   build/oblique_alignment      (3 s)
// Not an estimator: u comes from the Jacobian, or (data) from the nearest neighbours of every point
// found by the exact search. In the embedding the data's shift reads no closer to the own exponent than
// the orthogonal one over the region the automatic fit uses (README), so the estimator keeps the
// closest phase.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <span>
#include <type_traits>
#include <vector>

#include "mlce/embedding.hpp"
#include "mlce/neighbours.hpp"
#include "mlce/numerics.hpp"
#include "reference_systems.hpp"

namespace {

using V = std::array<double, 3>;
using mlce::reference::rk4_step;

double dot(const V& a, const V& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V cross(const V& a, const V& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double det3(const V& c0, const V& c1, const V& c2) { return dot(c0, cross(c1, c2)); }
V minus(const V& a, const V& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

/// Samples[t] at a continuous index t: the cubic through the samples floor(t) - 1 .. floor(t) + 2.
template <class T>
T cubic_at(const std::vector<T>& samples, double t) {
  const auto a = static_cast<std::size_t>(std::floor(t));
  const auto w = mlce::lagrange_cubic_weights(t - static_cast<double>(a));
  T r{};
  for (std::size_t k = 0; k < 4; ++k) {
    if constexpr (std::is_same_v<T, V>) {
      for (std::size_t d = 0; d < 3; ++d) r[d] += w[k] * samples[a - 1 + k][d];
    } else {
      r += w[k] * samples[a - 1 + k];
    }
  }
  return r;
}

/// Nearest neighbour (Euclidean, raw coordinates, more than `theiler` samples apart) of every point
/// 2 .. last - 1 of the delay embedding (dim, delay) of `channels` among the same points, by the
/// library's exact kd-tree search (mlce::find_nearest_neighbours, the one the estimator uses; ties
/// go to the earlier point); `none` where there is none. The view starts at sample 2 so that every
/// neighbour can be interpolated on the cubic through its samples k - 1 .. k + 2.
std::vector<std::size_t> nearest_neighbours(const std::vector<const std::vector<double>*>& channels, std::size_t dim,
                                            std::size_t delay, std::size_t last, std::size_t theiler, std::size_t none) {
  std::vector<std::span<const double>> from_two;
  for (const auto* c : channels) from_two.emplace_back(std::span<const double>(*c).subspan(2));
  const mlce::DelayEmbedding view(from_two, dim, delay, last - 2);
  mlce::NeighbourOptions options;
  options.theiler = theiler;
  const auto found = mlce::find_nearest_neighbours(view, mlce::strided_indices(last - 2, 0), options);
  std::vector<std::size_t> nearest(none, none);
  for (std::size_t q = 0; q < found.neighbour.size(); ++q)
    if (found.neighbour[q] != mlce::NeighbourResult::none) nearest[q + 2] = found.neighbour[q] + 2;
  return nearest;
}

/// u from the data alone: at point k, the dominant direction (power iteration on the sum of
/// w w^T / |w|^2) of the separations w of the pairs of points k - tau, tau = 100, 105 .. 300,
/// each shifted to its closest phase at its start and followed tau steps into k. Their flow
/// offsets stay while their unstable parts grow by ~e^{lambda tau}. at(t): the point at the
/// continuous index t; flow(i): the flow at point i (per unit time). Zero where not estimated.
template <class At, class Flow>
std::vector<V> unstable_from_data(std::size_t n, std::size_t last, const std::vector<std::size_t>& nearest, double dt,
                                  const At& at, const Flow& flow) {
  std::vector<V> u_data(n, V{0, 0, 0});
  for (std::size_t k = 302; k < last; ++k) {
    double C[3][3] = {};
    for (std::size_t tau = 100; tau <= 300; tau += 5) {
      const std::size_t r = k - tau, q = nearest[r];
      if (q == n || q + tau + 3 >= n) continue;
      const V v0 = minus(at(static_cast<double>(q)), at(static_cast<double>(r))), fq = flow(q);
      const double shift = std::clamp(-dot(v0, fq) / dot(fq, fq) / dt, -1.5, 1.5);
      const V w = minus(at(static_cast<double>(q + tau) + shift), at(static_cast<double>(k)));
      if (!(dot(w, w) > 0)) continue;
      for (std::size_t a = 0; a < 3; ++a)
        for (std::size_t b = 0; b < 3; ++b) C[a][b] += w[a] * w[b] / dot(w, w);
    }
    V v{1, 1, 1};
    for (int it = 0; it < 50; ++it) {
      V y{0, 0, 0};
      for (std::size_t a = 0; a < 3; ++a)
        for (std::size_t b = 0; b < 3; ++b) y[a] += C[a][b] * v[b];
      const double norm = std::sqrt(dot(y, y));
      if (!(norm > 0)) break;
      for (std::size_t a = 0; a < 3; ++a) v[a] = y[a] / norm;
    }
    u_data[k] = v;
  }
  return u_data;
}

struct Case {
  const char* name;
  std::size_t n, horizon, theiler, substeps;
  double dt, lambda;
  std::array<double, 6> start;  // state and tangent
};

template <class Flow, class WithTangent>
void run(const Case& c, const Flow& flow, const WithTangent& with_tangent) {
  const double h = c.dt / static_cast<double>(c.substeps);
  auto s = c.start;
  auto normalise = [&s] {
    const double norm = std::sqrt(s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
    for (int k = 3; k < 6; ++k) s[k] /= norm;
  };
  // NOLINTNEXTLINE(clang-analyzer-security.FloatLoopCounter): warm-up timed as in reference_systems.hpp
  for (double t = 0; t < 500; t += h) s = rk4_step<6>(with_tangent, s, h), normalise();
  std::vector<V> p(c.n), u(c.n), f(c.n);
  for (std::size_t i = 0; i < c.n; ++i) {
    normalise();
    p[i] = {s[0], s[1], s[2]}, u[i] = {s[3], s[4], s[5]}, f[i] = flow(p[i]);
    for (std::size_t k = 0; k < c.substeps; ++k) s = rk4_step<6>(with_tangent, s, h);
  }
  auto at = [&p](double x) { return cubic_at(p, x); };
  const std::size_t H = c.horizon, last = c.n - H - 4;  // points followed for H steps, shifts up to 1.5
  std::array<std::vector<double>, 3> xyz;
  for (std::size_t d = 0; d < 3; ++d)
    for (const V& q : p) xyz[d].push_back(q[d]);
  const auto nearest = nearest_neighbours({&xyz[0], &xyz[1], &xyz[2]}, 1, 1, last, c.theiler, c.n);
  const auto u_data = unstable_from_data(c.n, last, nearest, c.dt, at, [&f](std::size_t i) { return f[i]; });
  double agreement = 0;
  std::size_t estimated = 0;
  for (std::size_t k = 0; k < c.n; ++k)
    if (dot(u_data[k], u_data[k]) > 0) agreement += std::abs(dot(u_data[k], u[k])), ++estimated;
  std::printf("%s, N = %zu, dt = %g, Theiler window %zu: local slope / lambda_1 per %zu steps\n", c.name, c.n, c.dt,
              c.theiler, H / 16);
  std::printf("  (u from the data: |cos| to the tangent's u %.3f on average)\n",
              agreement / static_cast<double>(std::max<std::size_t>(estimated, 1)));
  for (const char* rule : {"none", "orthogonal", "oblique", "data"}) {
    std::vector<double> sum(H + 1, 0.0);
    std::size_t pairs = 0;
    double moved = 0;
    for (std::size_t j = 2; j < last; ++j) {
      const std::size_t k = nearest[j];
      if (k == c.n) continue;
      const V v0 = minus(p[k], p[j]);
      double shift = 0;  // samples: p(k + shift) ~ p(k) + shift dt f(k)
      if (rule[1] == 'r') shift = -dot(v0, f[k]) / dot(f[k], f[k]) / c.dt;
      if (rule[1] == 'b' || rule[0] == 'd') {  // v0 = a u + b f + c (u x f): Cramer's rule for b
        const V& uk = rule[0] == 'd' ? u_data[k] : u[k];
        if (dot(uk, uk) == 0) continue;  // data: no estimate of u here (the first 300 points)
        const V w = cross(uk, f[k]);
        shift = -det3(uk, v0, w) / det3(uk, f[k], w) / c.dt;
      }
      shift = std::clamp(shift, -1.5, 1.5);
      moved += std::abs(shift), ++pairs;
      for (std::size_t i = 0; i <= H; ++i) {
        const V d = minus(at(static_cast<double>(k + i) + shift), p[j + i]);
        sum[i] += 0.5 * std::log(dot(d, d));
      }
    }
    std::printf("  %-10s (mean |shift| %.3f samples):", rule, moved / static_cast<double>(pairs));
    const std::size_t q = H / 16;
    for (std::size_t a = 0; a + q <= H; a += q)
      std::printf(" %.2f", (sum[a + q] - sum[a]) / static_cast<double>(pairs) / static_cast<double>(q) / (c.lambda * c.dt));
    std::printf("\n");
  }
}

/// The same in the delay embedding of Lorenz x (m = 3, delay J = 17, as the estimator picks for
/// dt = 0.01; Theiler window 150), from (x0, 1, 1) after 100 time units: the unstable direction of
/// an embedded point i is (u_x(i), g(i, i + J) u_x(i + J), g(i, i + 2J) u_x(i + 2J)), the tangent
/// vector carried along (g: its growth), the flow's is (f_x(i), f_x(i + J), f_x(i + 2J)). Prints
/// the slope of the chord over steps 25..225 and 50..250 / lambda_1, and the trajectory's own
/// exponent over the series.
void embedded_lorenz(double x0) {
  const std::size_t n = 10000, H = 400, T = 150, J = 17, substeps = 10;
  const double dt = 0.01, h = dt / substeps, lambda = 0.9056;
  auto flow = [](const V& x) { return V{10.0 * (x[1] - x[0]), x[0] * (28.0 - x[2]) - x[1], x[0] * x[1] - 8.0 / 3.0 * x[2]}; };
  std::array<double, 6> s{x0, 1, 1, 1, 0, 0};
  auto normalise = [&s] {
    const double norm = std::sqrt(s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
    for (int k = 3; k < 6; ++k) s[k] /= norm;
    return norm;
  };
  // NOLINTNEXTLINE(clang-analyzer-security.FloatLoopCounter): warm-up timed as in reference_systems.hpp
  for (double t = 0; t < 100; t += h) s = rk4_step<6>(mlce::reference::lorenz_tangent_rhs, s, h), normalise();
  std::vector<double> x(n), ux(n), fx(n), growth(n, 0.0);  // growth: ln of the tangent's growth since sample 0
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) growth[i] = growth[i - 1] + std::log(normalise());
    x[i] = s[0], ux[i] = s[3], fx[i] = flow({s[0], s[1], s[2]})[0];
    for (std::size_t k = 0; k < substeps; ++k) s = rk4_step<6>(mlce::reference::lorenz_tangent_rhs, s, h);
  }
  const std::size_t M = n - 2 * J, last = M - H - 4;
  auto point = [&](std::size_t i) { return V{x[i], x[i + J], x[i + 2 * J]}; };
  auto unstable = [&](std::size_t i) {
    return V{ux[i], std::exp(growth[i + J] - growth[i]) * ux[i + J], std::exp(growth[i + 2 * J] - growth[i]) * ux[i + 2 * J]};
  };
  auto along = [&](std::size_t i) { return V{fx[i], fx[i + J], fx[i + 2 * J]}; };
  auto at = [&x](double t) { return cubic_at(x, t); };
  const auto nearest = nearest_neighbours({&x}, 3, J, last, T, M);
  // From the data alone: the flow by central differences, u as in run() (|cos| to the tangent's).
  auto embedded_at = [&x](double t) { return V{cubic_at(x, t), cubic_at(x, t + J), cubic_at(x, t + 2 * J)}; };
  auto flow_from_data = [&](std::size_t i) {
    const V d = minus(point(i + 1), point(i - 1));
    return V{d[0] / (2 * dt), d[1] / (2 * dt), d[2] / (2 * dt)};
  };
  const auto u_data = unstable_from_data(M, last, nearest, dt, embedded_at, flow_from_data);
  double agreement = 0;
  std::size_t estimated = 0;
  for (std::size_t k = 0; k < M; ++k)
    if (dot(u_data[k], u_data[k]) > 0) {
      const V t = unstable(k);
      agreement += std::abs(dot(u_data[k], t)) / std::sqrt(dot(t, t)), ++estimated;
    }
  std::printf("  x0 = %g, own exponent %.3f, |cos| %.3f:", x0, growth[n - 1] / (static_cast<double>(n - 1) * dt) / lambda,
              agreement / static_cast<double>(std::max<std::size_t>(estimated, 1)));
  for (const char* rule : {"orthogonal", "oblique", "data"}) {
    std::vector<double> sum(H + 1, 0.0);
    std::size_t pairs = 0;
    for (std::size_t j = 2; j < last; ++j) {
      const std::size_t k = nearest[j];
      if (k == M) continue;
      const bool data = rule[0] == 'd';
      if (data && !(dot(u_data[k], u_data[k]) > 0)) continue;  // no estimate of u here (the first 302 points)
      const V v0 = minus(point(k), point(j)), f = data ? flow_from_data(k) : along(k), u = data ? u_data[k] : unstable(k);
      double shift = rule[1] == 'r' ? -dot(v0, f) / dot(f, f) / dt : -det3(u, v0, cross(u, f)) / det3(u, f, cross(u, f)) / dt;
      shift = std::clamp(shift, -1.5, 1.5);
      ++pairs;
      for (std::size_t i = 0; i <= H; ++i) {
        double d2 = 0;
        for (std::size_t l = 0; l < 3; ++l) {
          const double e = at(static_cast<double>(k + i + l * J) + shift) - x[j + i + l * J];
          d2 += e * e;
        }
        sum[i] += 0.5 * std::log(d2);
      }
    }
    auto chord = [&](std::size_t a, std::size_t b) {
      return (sum[b] - sum[a]) / static_cast<double>(pairs) / static_cast<double>(b - a) / (lambda * dt);
    };
    std::printf("  %s %.3f (25..225), %.3f (50..250), %.3f (85..340);", rule, chord(25, 225), chord(50, 250),
                chord(85, 340));
  }
  std::printf("\n");
}

}  // namespace

int main() {
  using namespace mlce::reference;
  run({"Roessler a = b = 0.2, c = 5.7", 10000, 400, 57, 10, 0.1, 0.0714, {1, 1, 0, 1, 0, 0}}, roessler_rhs,
      roessler_tangent_rhs);
  run({"Lorenz sigma = 10, rho = 28, beta = 8/3", 10000, 400, 150, 10, 0.01, 0.9056, {1, 1, 1, 1, 0, 0}},
      [](const V& x) { return V{10.0 * (x[1] - x[0]), x[0] * (28.0 - x[2]) - x[1], x[0] * x[1] - 8.0 / 3.0 * x[2]}; },
      lorenz_tangent_rhs);
  std::printf("Lorenz x, delay embedding m = 3, J = 17, Theiler window 150: chord slope / lambda_1\n");
  for (const double x0 : {1.0, 2.0, 3.0, 4.0, 5.0, 6.0}) embedded_lorenz(x0);
}
