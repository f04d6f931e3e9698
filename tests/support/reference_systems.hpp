#pragma once
// Reference dynamical systems with known Lyapunov exponents, generated in the tests themselves
// (never read from files): a fixed-step RK4 for flows, direct iteration for maps.
#include <array>
#include <cmath>
#include <numbers>
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

namespace mlce::reference {

template <std::size_t N, class F>
std::array<double, N> rk4_step(const F& f, const std::array<double, N>& x, double h) {
  auto axpy = [](const std::array<double, N>& a, double s, const std::array<double, N>& b) {
    std::array<double, N> r;
    for (std::size_t i = 0; i < N; ++i) r[i] = a[i] + s * b[i];
    return r;
  };
  const auto k1 = f(x);
  const auto k2 = f(axpy(x, h / 2, k1));
  const auto k3 = f(axpy(x, h / 2, k2));
  const auto k4 = f(axpy(x, h, k3));
  std::array<double, N> r;
  for (std::size_t i = 0; i < N; ++i) r[i] = x[i] + h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
  return r;
}

/// Lorenz (sigma = 10, rho = 28, beta = 8/3) and Roessler (a = b = 0.2, c = 5.7) right-hand sides,
/// and the same with a tangent vector carried along (state, then tangent: x' = f(x), v' = Df(x) v).
inline std::array<double, 3> lorenz_rhs(const std::array<double, 3>& s) {
  return {10.0 * (s[1] - s[0]), s[0] * (28.0 - s[2]) - s[1], s[0] * s[1] - 8.0 / 3.0 * s[2]};
}
inline std::array<double, 6> lorenz_tangent_rhs(const std::array<double, 6>& s) {
  const auto f = lorenz_rhs({s[0], s[1], s[2]});
  return {f[0], f[1], f[2], 10.0 * (s[4] - s[3]), (28.0 - s[2]) * s[3] - s[4] - s[0] * s[5],
          s[1] * s[3] + s[0] * s[4] - 8.0 / 3.0 * s[5]};
}
inline std::array<double, 3> roessler_rhs(const std::array<double, 3>& s) {
  return {-s[1] - s[2], s[0] + 0.2 * s[1], 0.2 + s[2] * (s[0] - 5.7)};
}
inline std::array<double, 6> roessler_tangent_rhs(const std::array<double, 6>& s) {
  const auto f = roessler_rhs({s[0], s[1], s[2]});
  return {f[0], f[1], f[2], -s[4] - s[5], s[3] + 0.2 * s[4], s[2] * s[3] + (s[0] - 5.7) * s[5]};
}

/// The finite-time exponent of the very trajectory a series of `n` samples (step dt, RK4 step h)
/// from x0 after `transient` time units samples: the tangent vector aligns during the transient's
/// last 50 time units, then its growth over the n - 1 sampled steps, per time unit.
template <class F, class FT>
double own_exponent(const F& flow, const FT& with_tangent, std::array<double, 3> x, double transient, double dt,
                    double h, std::size_t n) {
  const auto substeps = static_cast<std::size_t>(std::lround(dt / h));
  // Time is counted as sample_flow counts it, so that the tangent follows the very trajectory sampled.
  double t = 0;
  // NOLINTNEXTLINE(clang-analyzer-security.FloatLoopCounter)
  for (; t < transient - 50.0; t += h) x = rk4_step<3>(flow, x, h);
  std::array<double, 6> s{x[0], x[1], x[2], 1, 0, 0};
  // NOLINTNEXTLINE(clang-analyzer-security.FloatLoopCounter)
  for (; t < transient; t += h) s = rk4_step<6>(with_tangent, s, h);
  long double acc = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double norm = std::sqrt(s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
    if (k > 0) acc += std::log(norm);
    for (int c = 3; c < 6; ++c) s[c] /= norm;
    for (std::size_t j = 0; j < substeps; ++j) s = rk4_step<6>(with_tangent, s, h);
  }
  return static_cast<double>(acc) / (static_cast<double>(n - 1) * dt);
}

/// Samples component `component` of a flow every dt after discarding `transient` time units.
template <std::size_t N, class F>
std::vector<double> sample_flow(const F& f, std::array<double, N> x, double dt, std::size_t n, double transient,
                                std::size_t substeps, std::size_t component = 0) {
  const double h = dt / static_cast<double>(substeps);
  // The warm-up runs the transient within one step on every run alike; counting steps instead would
  // redraw every series the figures come from.
  // NOLINTNEXTLINE(clang-analyzer-security.FloatLoopCounter)
  for (double t = 0; t < transient; t += h) x = rk4_step(f, x, h);
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = x[component];
    for (std::size_t s = 0; s < substeps; ++s) x = rk4_step(f, x, h);
  }
  return out;
}

/// The initial states of `build/finite_time_spread starts` and the benchmarks that share its series:
/// 32 per mt19937 seed, seeds first_seed..last_seed, (x, y) uniform in [-3, 3] and z = |u| / 3 in [0, 1].
inline std::vector<std::array<double, 3>> random_starts(unsigned first_seed, unsigned last_seed) {
  std::vector<std::array<double, 3>> out;
  for (unsigned seed = first_seed; seed <= last_seed; ++seed) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (int k = 0; k < 32; ++k) {
      const double x = u(gen), y = u(gen);  // drawn in this order: x, y, then z
      out.push_back({x, y, std::abs(u(gen)) / 3});
    }
  }
  return out;
}

/// Lorenz sigma = 10, rho = 28, beta = 8/3; lambda_1 = 0.9056. From x0 after `transient` time units
/// (from (1, 1, 1) the trajectory spirals out of the fixed point C- for its first ~12-15).
/// Component `component` (0 = x, 1 = y, 2 = z) of that flow.
inline std::vector<double> lorenz(std::size_t n, double dt, std::array<double, 3> x0, double transient,
                                  std::size_t component) {
  auto f = [](const std::array<double, 3>& s) {
    return std::array<double, 3>{10.0 * (s[1] - s[0]), s[0] * (28.0 - s[2]) - s[1], s[0] * s[1] - 8.0 / 3.0 * s[2]};
  };
  return sample_flow<3>(f, x0, dt, n, transient, 10, component);
}
inline std::vector<double> lorenz_x(std::size_t n, double dt = 0.01, std::array<double, 3> x0 = {1.0, 1.0, 1.0},
                                    double transient = 50.0) {
  return lorenz(n, dt, x0, transient, 0);
}

/// Roessler a = b = 0.2, c = 5.7; lambda_1 = 0.0714. Component `component` (0 = x, 2 = z) from x0
/// after 500 time units.
inline std::vector<double> roessler(std::size_t n, double dt, std::array<double, 3> x0, std::size_t component) {
  auto f = [](const std::array<double, 3>& s) {
    return std::array<double, 3>{-s[1] - s[2], s[0] + 0.2 * s[1], 0.2 + s[2] * (s[0] - 5.7)};
  };
  return sample_flow<3>(f, x0, dt, n, 500.0, 10, component);
}
inline std::vector<double> roessler_x(std::size_t n, double dt = 0.1, std::array<double, 3> x0 = {1.0, 1.0, 0.0}) {
  return roessler(n, dt, x0, 0);
}

/// van der Pol mu = 1 on its limit cycle; lambda_1 = 0.
inline std::vector<double> van_der_pol_x(std::size_t n, double dt = 0.01, double mu = 1.0) {
  auto f = [mu](const std::array<double, 2>& s) {
    return std::array<double, 2>{s[1], mu * (1.0 - s[0] * s[0]) * s[1] - s[0]};
  };
  return sample_flow<2>(f, {2.0, 0.0}, dt, n, 200.0, 10);
}

/// x'' + 2 zeta omega x' + omega^2 x = 0 from x = 1, v = 0, exact solution; lambda = -zeta omega.
inline std::vector<double> damped_oscillator(std::size_t n, double dt, double zeta, double omega) {
  const double wd = omega * std::sqrt(1.0 - zeta * zeta);
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = dt * static_cast<double>(i);
    out[i] = std::exp(-zeta * omega * t) * (std::cos(wd * t) + zeta * omega / wd * std::sin(wd * t));
  }
  return out;
}

/// One mode of a linear system's free response: amplitude x e^{rate t} cos(2 pi frequency t + phase).
struct DecayingMode {
  double rate, frequency, amplitude, phase = 0.0;
};

/// The free response of a linear system with these modes, sampled n times every dt: the sum of the
/// modes. Its largest Lyapunov exponent is exactly the largest rate (the least damped mode), whatever
/// the amplitudes; the other modes die out faster and, at close frequencies, beat with it first.
inline std::vector<double> decaying_modes(std::size_t n, double dt, const std::vector<DecayingMode>& modes) {
  std::vector<double> out(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = dt * static_cast<double>(i);
    for (const auto& m : modes)
      out[i] += m.amplitude * std::exp(m.rate * t) * std::cos(2.0 * std::numbers::pi * m.frequency * t + m.phase);
  }
  return out;
}

/// x plus Gaussian white noise of standard deviation `noise`, drawn in order from mt19937_64 `seed`.
inline std::vector<double> with_white_noise(std::vector<double> x, double noise, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, noise);
  for (double& v : x) v += g(rng);
  return x;
}

/// The damped oscillator plus white noise of standard deviation `noise` (mt19937_64 seed 7): the
/// decay reaches the noise floor after ln(1/noise) / (zeta omega) time units (paper 001 Fig. 6).
inline std::vector<double> noisy_decay(std::size_t n, double dt, double zeta, double omega, double noise) {
  return with_white_noise(damped_oscillator(n, dt, zeta, omega), noise, 7);
}

/// A lightly damped mode driven by white noise, the AR(2) resonance x_t = 2 r cos(w) x_{t-1} -
/// r^2 x_{t-2} + e_t (e_t standard normal from mt19937_64 seeded `seed`), after 1000 samples of
/// start-up: a linear stochastic process, whose divergence curve rises and saturates as chaos's does.
inline std::vector<double> ar2_resonance(std::size_t n, double r, double w, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> e(0.0, 1.0);
  std::vector<double> x(n);
  double x1 = 0.0, x2 = 0.0;
  for (std::size_t i = 0; i < n + 1000; ++i) {
    const double v = 2.0 * r * std::cos(w) * x1 - r * r * x2 + e(gen);
    x2 = x1, x1 = v;
    if (i >= 1000) x[i - 1000] = v;
  }
  return x;
}

/// A Gaussian random walk x_t = x_{t-1} + e_t from x_0 = 0 (e_t standard normal from mt19937_64
/// seeded `seed`): not stationary (its variance grows as t), it never settles on an attractor, and no
/// exponent describes it -- a wandering coordinate, such as a free body's position under noise.
inline std::vector<double> random_walk(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> e(0.0, 1.0);
  std::vector<double> x(n);
  double s = 0.0;
  for (auto& v : x) v = (s += e(gen));
  return x;
}

/// A damped oscillator q'' + 2 zeta omega q' + omega^2 q = w(t), w white noise of unit intensity
/// (mt19937_64 seeded `seed`), by semi-implicit Euler at step dt after 20 / (zeta omega) time units of
/// start-up: its displacement q and velocity v, two channels of one stable linear mode (exponent
/// -zeta omega) that noise keeps moving -- a rotor mode in turbulence.
struct NoiseDrivenMode {
  std::vector<double> q, v;
};
inline NoiseDrivenMode noise_driven_oscillator(std::size_t n, double dt, double zeta, double omega, std::uint64_t seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> e(0.0, 1.0);
  const auto burn_in = static_cast<std::size_t>(20.0 / (zeta * omega) / dt);
  NoiseDrivenMode out{std::vector<double>(n), std::vector<double>(n)};
  double q = 0.0, v = 0.0;
  for (std::size_t i = 0; i < n + burn_in; ++i) {
    v += (-2.0 * zeta * omega * v - omega * omega * q) * dt + std::sqrt(dt) * e(gen);
    q += v * dt;
    if (i >= burn_in) out.q[i - burn_in] = q, out.v[i - burn_in] = v;
  }
  return out;
}

/// Henon x -> 1 - a x^2 + y, y -> 0.3 x, a = 1.4 unless given (lambda_1 = 0.41922 per iteration).
/// From (x0, y0) after 1000 iterations.
inline std::vector<double> henon_x(std::size_t n, double x0 = 0.1, double y0 = 0.1, double a = 1.4) {
  double x = x0, y = y0;
  for (int i = 0; i < 1000; ++i) {
    const double xn = 1.0 - a * x * x + y;
    y = 0.3 * x;
    x = xn;
  }
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = x;
    const double xn = 1.0 - a * x * x + y;
    y = 0.3 * x;
    x = xn;
  }
  return out;
}

/// Logistic map x -> r x (1 - x), r = 4 unless given (lambda = ln 2 per iteration), after 100 iterations.
inline std::vector<double> logistic(std::size_t n, double x0 = 0.1234567, double r = 4.0) {
  double x = x0;
  for (int i = 0; i < 100; ++i) x = r * x * (1.0 - x);
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = x;
    x = r * x * (1.0 - x);
  }
  return out;
}

/// The finite-time exponent of the very Henon trajectory henon_x(n, x0, y0, a) samples: the tangent
/// map along its n iterations, the tangent vector aligned during the last 50 of the 1000
/// discarded ones. Independent of any estimator: what one series of n iterations can carry.
inline double henon_own_exponent(std::size_t n, double x0 = 0.1, double y0 = 0.1, double a = 1.4) {
  double x = x0, y = y0, u = 1, v = 0;
  long double acc = 0;
  for (std::size_t i = 0; i < 1000 + n; ++i) {
    if (i >= 950) {
      const double un = -2.0 * a * x * u + v;  // Jacobian [[-2 a x, 1], [0.3, 0]]
      v = 0.3 * u, u = un;
      const double norm = std::hypot(u, v);
      if (i >= 1000) acc += std::log(norm);
      u /= norm, v /= norm;
    }
    const double xn = 1.0 - a * x * x + y;
    y = 0.3 * x, x = xn;
  }
  return static_cast<double>(acc / static_cast<long double>(n));
}

/// The same for a logistic series (r = 4 unless given): the mean of ln |f'(x)| = ln |r - 2 r x| over
/// its samples up to the first exact 0 (a floating-point orbit can land on 1/2, then 1, then the
/// repelling fixed point 0 and stay there). A sample exactly at 1/2 (f' = 0) is left out.
inline double logistic_own_exponent(const std::vector<double>& x, double r = 4.0) {
  long double acc = 0;
  std::size_t terms = 0;
  for (const double v : x) {
    if (v == 0.0) break;
    const double slope = std::abs(r - 2.0 * r * v);
    if (slope > 0) acc += std::log(slope), ++terms;
  }
  return terms > 0 ? static_cast<double>(acc / static_cast<long double>(terms)) : 0.0;
}

/// The Duffing (Holmes) map x -> y, y -> -b x + a y - y^3 (the textbook a = 2.75, b = 0.2), x
/// observed, from (0.1, 0.1) after 1000 iterations, and the finite-time exponent of that very
/// trajectory (its tangent map along the same n iterations, aligned during the last 50 discarded
/// ones). Its orbit stays on one lobe (x > 0 or x < 0) for dozens of iterations before it switches.
struct MapSample {
  std::vector<double> x;
  double own_exponent = 0.0;  ///< per iteration
};
inline MapSample duffing_map_x(std::size_t n, double a = 2.75, double b = 0.2) {
  double x = 0.1, y = 0.1, u = 1, v = 0;
  long double acc = 0;
  MapSample out;
  out.x.reserve(n);
  for (std::size_t i = 0; i < 1000 + n; ++i) {
    if (i >= 1000) out.x.push_back(x);
    if (i >= 950) {
      const double un = v, vn = -b * u + (a - 3.0 * y * y) * v;  // Jacobian [[0, 1], [-b, a - 3 y^2]]
      const double norm = std::hypot(un, vn);
      if (i >= 1000) acc += std::log(norm);
      u = un / norm, v = vn / norm;
    }
    const double xn = y, yn = -b * x + a * y - y * y * y;
    x = xn, y = yn;
  }
  out.own_exponent = static_cast<double>(acc / static_cast<long double>(n));
  return out;
}

/// The cubic map x -> a x - x^3 from x0 after 1000 iterations, and its orbit's own exponent, the
/// mean of ln |a - 3 x^2| over the samples. Beyond a ~ 2.6 the two symmetric attractors merge and
/// the orbit switches between x > 0 and x < 0 every few to dozens of iterations.
inline MapSample cubic_map(std::size_t n, double a, double x0 = 0.1) {
  double x = x0;
  for (int i = 0; i < 1000; ++i) x = a * x - x * x * x;
  MapSample out;
  out.x.reserve(n);
  long double acc = 0;
  for (std::size_t i = 0; i < n; ++i) {
    out.x.push_back(x);
    acc += std::log(std::abs(a - 3.0 * x * x));
    x = a * x - x * x * x;
  }
  out.own_exponent = static_cast<double>(acc / static_cast<long double>(n));
  return out;
}

}  // namespace mlce::reference
