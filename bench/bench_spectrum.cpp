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

BENCHMARK_MAIN();
