// Overhead of the Jacobian-based references on the 12-state Hammond scene (blade 3 inoperative,
// 242.4 rpm, 60 s, rk45 rtol 1e-8, QR every 5 ms): a plain integration of the same scene, the
// discrete QR spectrum (state + 12x12 tangent), and QR with 1, 2 and 3 sensitivity parameters
// (each adds 12 + 144 states and two perturbed Jacobians per evaluation); the largest exponent
// alone (count 1: 2 tangent vectors instead of 12) by each Jacobian route and with one
// sensitivity; Floquet (one period) and multiblade eigen for scale.
//   build/bench_spectrum [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include "mlce/models/dynamics.hpp"
#include "mlce/models/scene.hpp"
#include "mlce/models/simulate.hpp"
#include "mlce/spectrum/floquet.hpp"
#include "mlce/spectrum/qr_spectrum.hpp"
#include "mlce/spectrum/solver_pencil.hpp"

namespace {

mlce::models::Scene scene() {
  return mlce::models::load_scene("", {"--rpm", "242.4", "--c", "4067.5,4067.5,0,4067.5", "--t_end", "60"});
}

void plain_integration(benchmark::State& state) {
  const auto s = scene();
  for (auto _ : state) benchmark::DoNotOptimize(mlce::models::simulate(s).states.back().data());
}

void qr(benchmark::State& state, const std::vector<std::string>& params, mlce::spectrum::JacobianMethod method,
        std::size_t count = 0) {
  const auto s = scene();
  const auto sys = mlce::models::dynamical_system(s);
  std::vector<mlce::ode::ParameterFamily> fam;
  for (const auto& p : params) fam.push_back(mlce::models::parameter_family(s, p));
  mlce::spectrum::QrOptions o;
  o.t_end = s.t_end;
  o.step = s.dt_out;
  o.transient = 6.0;
  o.jacobian = method;
  o.count = count;
  mlce::spectrum::QrResult r;
  for (auto _ : state) {
    r = mlce::spectrum::qr_spectrum(sys, s.x0, o, fam);
    benchmark::DoNotOptimize(r.exponents.data());
  }
  state.counters["lambda1"] = r.exponents(0);
  state.counters["steps"] = static_cast<double>(r.stats.steps);
}

void floquet(benchmark::State& state) {
  const auto sys = mlce::models::dynamical_system(scene());
  for (auto _ : state) benchmark::DoNotOptimize(mlce::spectrum::floquet(sys, {}).exponents.data());
}

void eigen_mbc(benchmark::State& state) {
  const auto s = mlce::models::load_scene("", {"--rpm", "242.4"});
  for (auto _ : state)
    benchmark::DoNotOptimize(mlce::spectrum::linear_eigen(mlce::models::time_invariant_form(s).A).exponents.data());
}

/// mlce eigenanalysis on MBDyn-sized pencils: n oscillator pairs in first-order residual form (Aplus
/// regular: LU + EigenSolver), and the same with Aplus made singular in one row (QZ). The cost of a
/// solver's eigenanalysis file, O(n^3).
void solver_pencil(benchmark::State& state, bool singular_aplus) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const double c = 5e-4;
  std::vector<double> plus(n * n, 0.0), minus(n * n, 0.0);
  for (std::size_t k = 0; k + 1 < n; k += 2) {  // x' = v, v' = -w^2 x - 2 zeta w v, w = 1 + k / 10, zeta = 0.02
    const double w = 1.0 + static_cast<double>(k) / 10.0, z = 0.02;
    const double e[2][2] = {{1, 0}, {0, 1}}, kk[2][2] = {{0, -1}, {w * w, 2 * z * w}};
    for (int r = 0; r < 2; ++r)
      for (int q = 0; q < 2; ++q) {
        plus[(k + r) * n + k + q] = e[r][q] + c * kk[r][q];
        minus[(k + r) * n + k + q] = e[r][q] - c * kk[r][q];
      }
  }
  for (std::size_t i = 0; i < n * n; i += 7) plus[i] += 1e-3, minus[i] += 1e-3;  // couple them
  if (singular_aplus)
    for (std::size_t q = 0; q < n; ++q) plus[(n - 1) * n + q] = 0.0;
  for (auto _ : state) benchmark::DoNotOptimize(mlce::spectrum::spectrum_from_pencil(n, plus, minus, c).eigenvalues.data());
}

using M = mlce::spectrum::JacobianMethod;

}  // namespace

BENCHMARK(plain_integration)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(qr, analytic_0_params, std::vector<std::string>{}, M::analytic)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(qr, complex_step_0_params, std::vector<std::string>{}, M::complex_step)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(qr, jacobian_free_0_params, std::vector<std::string>{}, M::jacobian_free)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(qr, analytic_1_param_c3, std::vector<std::string>{"c3"}, M::analytic)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(qr, analytic_2_params_c3_rpm, std::vector<std::string>{"c3", "rpm"}, M::analytic)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(qr, analytic_3_params_c3_rpm_cy, std::vector<std::string>{"c3", "rpm", "cy"}, M::analytic)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(qr, analytic_largest_only, std::vector<std::string>{}, M::analytic, 1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(qr, complex_step_largest_only, std::vector<std::string>{}, M::complex_step, 1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(qr, jacobian_free_largest_only, std::vector<std::string>{}, M::jacobian_free, 1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(qr, analytic_largest_only_1_param_c3, std::vector<std::string>{"c3"}, M::analytic, 1)->Unit(benchmark::kMillisecond);
BENCHMARK(floquet)->Unit(benchmark::kMillisecond);
BENCHMARK(eigen_mbc)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(solver_pencil, lu_eigensolver, false)->Arg(100)->Arg(250)->Arg(500)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(solver_pencil, qz, true)->Arg(100)->Arg(250)->Arg(500)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
