// Google Benchmark: cost of each stage and of the whole automatic estimate on Lorenz x.
#include <benchmark/benchmark.h>

#include <map>

#include "mlce/estimate.hpp"
#include "reference_systems.hpp"

namespace {

const mlce::Series& lorenz(std::size_t n) {
  static std::map<std::size_t, mlce::Series> cache;
  auto it = cache.find(n);
  if (it == cache.end()) it = cache.emplace(n, mlce::make_series_with_step({mlce::reference::lorenz_x(n)}, 0.01)).first;
  return it->second;
}

void BM_EstimateAutomatic(benchmark::State& state) {
  const auto& s = lorenz(static_cast<std::size_t>(state.range(0)));
  double lambda = 0;
  for (auto _ : state) benchmark::DoNotOptimize(lambda = mlce::estimate_mlce(s, {}).lambda);
  state.counters["lambda"] = lambda;
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_EstimateAutomatic)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_MeanPeriod(benchmark::State& state) {
  const auto& s = lorenz(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(mlce::estimate_mean_period(s, {}));
}
BENCHMARK(BM_MeanPeriod)->Arg(100000)->Unit(benchmark::kMillisecond);

void BM_Ami(benchmark::State& state) {
  const auto& s = lorenz(static_cast<std::size_t>(state.range(0)));
  mlce::AmiOptions o;
  o.stop_at_minimum = true;
  for (auto _ : state) benchmark::DoNotOptimize(mlce::estimate_delay_ami(s, o));
}
BENCHMARK(BM_Ami)->Arg(100000)->Unit(benchmark::kMillisecond);

void BM_Fnn(benchmark::State& state) {
  const auto& s = lorenz(static_cast<std::size_t>(state.range(0)));
  mlce::FnnOptions o;
  o.theiler = 170;
  o.stop_at_choice = true;
  for (auto _ : state) benchmark::DoNotOptimize(mlce::estimate_dimension_fnn(s, 17, o));
}
BENCHMARK(BM_Fnn)->Arg(100000)->Unit(benchmark::kMillisecond);

// The reference-point count trades time for the statistical error of the curve.
void BM_CurveReferences(benchmark::State& state) {
  const auto& s = lorenz(100000);
  mlce::RosensteinOptions o;
  o.dim = 3;
  o.delay = 17;
  o.theiler = 170;
  o.horizon = 1300;
  o.max_references = static_cast<std::size_t>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(mlce::divergence_curve(s, o));
}
BENCHMARK(BM_CurveReferences)->Arg(5000)->Arg(20000)->Arg(0)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
