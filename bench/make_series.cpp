// Writes a reference series as a two-column file "time value" (the bundled demo data and the
// benchmark inputs are made by this program, not by hand).
//   make_series lorenz|roessler|roessler_z|vanderpol|henon|logistic|oscillator N [dt] > file
//   make_series lorenz N dt TRANSIENT > file   (Lorenz from (1, 1, 1) after TRANSIENT time units; default 50)
//   make_series lorenz N dt TRANSIENT X Y Z    (from (X, Y, Z) instead)
//   make_series roessler N dt TRANSIENT X Y Z  (Roessler from (X, Y, Z) after TRANSIENT time units)
//   make_series lorenz_xyz N [dt] > file        (columns t x y z of that trajectory: mlce estimate --each)
//   make_series logistic N R > file             (the logistic map at r = R instead of 4)
//   make_series oscillator N dt ZETA OMEGA      (x = e^{-zeta omega t} cos(omega_d t); default 0.05, 2 pi)
//   make_series random_walk N dt SEED           (a Gaussian random walk, x += N(0, 1) per sample)
#include <cstdio>
#include <cstdlib>
#include <string>

#include "reference_systems.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: make_series lorenz|roessler|roessler_z|vanderpol|henon|logistic|oscillator N [dt]\n"
                         "       make_series lorenz N dt TRANSIENT   (from (1, 1, 1) after TRANSIENT time units; default 50)\n"
                         "       make_series lorenz N dt TRANSIENT X Y Z   (from (X, Y, Z))\n"
                         "       make_series lorenz_xyz N [dt]       (columns t x y z of that trajectory)\n"
                         "       make_series logistic N R            (the logistic map at r = R)\n"
                         "       make_series oscillator N dt ZETA OMEGA   (damping ratio and natural frequency; default 0.05, 2 pi)\n"
                         "       make_series random_walk N dt SEED   (a Gaussian random walk, x += N(0, 1) per sample)\n");
    return 2;
  }
  const std::string name = argv[1];
  const auto n = static_cast<std::size_t>(std::strtoull(argv[2], nullptr, 10));
  double dt = argc > 3 ? std::strtod(argv[3], nullptr) : 0.0;
  std::vector<double> x;
  using namespace mlce::reference;
  if (name == "lorenz_xyz") {  // the three observables of one trajectory, one column each
    dt = dt > 0 ? dt : 0.01;
    std::vector<std::vector<double>> c;
    for (std::size_t k = 0; k < 3; ++k) c.push_back(lorenz(n, dt, {1.0, 1.0, 1.0}, 50.0, k));
    std::printf("# lorenz x, y, z from (1, 1, 1) after 50 time units, dt = %.17g, N = %zu\nt x y z\n", dt, n);
    for (std::size_t i = 0; i < n; ++i)
      std::printf("%.10g %.17g %.17g %.17g\n", dt * static_cast<double>(i), c[0][i], c[1][i], c[2][i]);
    return 0;
  }
  if (name == "lorenz") {
    const std::array<double, 3> start = argc > 7 ? std::array<double, 3>{std::strtod(argv[5], nullptr), std::strtod(argv[6], nullptr),
                                                                         std::strtod(argv[7], nullptr)}
                                                 : std::array<double, 3>{1.0, 1.0, 1.0};
    x = lorenz_x(n, dt = dt > 0 ? dt : 0.01, start, argc > 4 ? std::strtod(argv[4], nullptr) : 50.0);
  } else if (name == "roessler" && argc > 7) {  // from (X, Y, Z) after TRANSIENT time units (RK4, 10 steps per sample)
    const std::array<double, 3> start{std::strtod(argv[5], nullptr), std::strtod(argv[6], nullptr), std::strtod(argv[7], nullptr)};
    x = sample_flow<3>(roessler_rhs, start, dt = dt > 0 ? dt : 0.1, n, std::strtod(argv[4], nullptr), 10);
  } else if (name == "roessler") x = roessler_x(n, dt = dt > 0 ? dt : 0.1);
  else if (name == "roessler_z") x = roessler(n, dt = dt > 0 ? dt : 0.1, {1.0, 1.0, 0.0}, 2);
  else if (name == "vanderpol") x = van_der_pol_x(n, dt = dt > 0 ? dt : 0.01);
  else if (name == "oscillator")
    x = damped_oscillator(n, dt = dt > 0 ? dt : 0.01, argc > 5 ? std::strtod(argv[4], nullptr) : 0.05,
                          argc > 5 ? std::strtod(argv[5], nullptr) : 2.0 * M_PI);
  else if (name == "henon") x = henon_x(n), dt = 1.0;
  else if (name == "random_walk")
    x = random_walk(n, argc > 4 ? std::strtoull(argv[4], nullptr, 10) : 1), dt = dt > 0 ? dt : 1.0;
  else if (name == "logistic") x = logistic(n, 0.1234567, argc > 3 ? std::strtod(argv[3], nullptr) : 4.0), dt = 1.0;
  else {
    std::fprintf(stderr, "make_series: unknown system '%s'\n", name.c_str());
    return 2;
  }
  std::printf("# %s, dt = %.17g, N = %zu\n# time value\n", name.c_str(), dt, n);
  for (std::size_t i = 0; i < x.size(); ++i) std::printf("%.10g %.17g\n", dt * static_cast<double>(i), x[i]);
  return 0;
}
