// Cost of one 60-s Hammond run (blade 3 damper inoperative, 242.4 rpm, output every 5 ms) per
// integrator and tolerance, with the accuracy bought: the largest deviation of blade 3's lag from
// a reference run (rk45, rtol 1e-12) over the run, as the counter `max_err_rad`.
//   build/bench_models [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>

#include "mlce/models/scene.hpp"
#include "mlce/models/simulate.hpp"

namespace {

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

mlce::models::Scene scene(const char* integrator, double rtol, double h = 0) {
  std::vector<std::string> o = {"--rpm", "242.4", "--c", "4067.5,4067.5,0,4067.5", "--t_end", "60", "--integrator",
                                integrator, "--rtol", num(rtol), "--atol", num(rtol * 1e-2)};
  if (h > 0) o.insert(o.end(), {"--h", num(h)});
  return mlce::models::load_scene("", o);
}

const mlce::models::Trajectory& reference() {
  static const auto r = mlce::models::simulate(scene("rk45", 1e-12));
  return r;
}

void run(benchmark::State& state, const char* integrator, double rtol, double h) {
  const auto s = scene(integrator, rtol, h);
  mlce::models::Trajectory tr;
  for (auto _ : state) {
    tr = mlce::models::simulate(s);
    benchmark::DoNotOptimize(tr.states.back().data());
  }
  double err = 0;
  for (std::size_t k = 0; k < tr.states.size(); ++k) err = std::max(err, std::abs(tr.states[k](2) - reference().states[k](2)));
  state.counters["max_err_rad"] = err;
  state.counters["steps"] = static_cast<double>(tr.stats.steps);
  state.counters["f_evals"] = static_cast<double>(tr.stats.evaluations);
}

}  // namespace

BENCHMARK_CAPTURE(run, rk45_rtol1e-6, "rk45", 1e-6, 0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(run, rk45_rtol1e-8, "rk45", 1e-8, 0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(run, rk45_rtol1e-10, "rk45", 1e-10, 0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(run, rk23_rtol1e-6, "rk23", 1e-6, 0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(run, rk23_rtol1e-8, "rk23", 1e-8, 0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(run, rk4_h1ms, "rk4", 1e-8, 1e-3)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(run, rk4_h5ms, "rk4", 1e-8, 5e-3)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
