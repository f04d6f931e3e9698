// Google Benchmark: cost of each stage and of the whole automatic estimate on Lorenz x.
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>

#include "mlce/estimate.hpp"
#include "mlce/neighbours.hpp"
#include "mlce/surrogate.hpp"
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
  // Not DoNotOptimize(lambda = ...) nor DoNotOptimize(result.lambda): Google Benchmark 1.7's "+r,m"
  // constraint on a double reads back garbage (6.95e-310, 0) with g++ 12 at -O2 and -O3. The whole
  // result goes through it instead: a struct takes the memory alternative.
  mlce::MlceResult result;
  for (auto _ : state) {
    result = mlce::estimate_mlce(s, {});
    benchmark::DoNotOptimize(result);
  }
  state.counters["lambda"] = result.lambda;
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

// The default surrogate test of a chaotic reading (MlceOptions::surrogates): 19 IAAFT surrogates of
// the first 4096 samples, 30 passes each, curves of 2000 references over the fit region, as the
// estimate runs it on Lorenz x (its embedding and fit region at N = 10^5). Its cost does not grow with N.
void BM_SurrogateTest(benchmark::State& state) {
  const auto& s = lorenz(100000);
  mlce::SurrogateSetup setup;
  setup.dim = 3, setup.delay = 18, setup.theiler = 160, setup.first = 81, setup.last = 375;
  setup.max_references = 2000, setup.align_phase = true;
  const mlce::SurrogateOptions options = mlce::MlceOptions{}.surrogates;
  mlce::SurrogateTest test;  // as BM_EstimateAutomatic's result
  for (auto _ : state) {
    test = mlce::surrogate_test(s, setup, options);
    benchmark::DoNotOptimize(test);
  }
  state.counters["sigmas"] = test.sigmas;
}
BENCHMARK(BM_SurrogateTest)->Unit(benchmark::kMillisecond)->UseRealTime();

// The kd-tree's leaf size (NeighbourOptions::leaf_size) trades the depth of the tree (its build and
// memory) against the points scanned per leaf. Lorenz x in unit deviations, delay 17, Theiler window
// 170: the nearest neighbour of 20000 evenly spread points among N (the divergence curve's and FNN's
// search), at m = 3 and m = 8, and the balls of Kantz's method (radius 0.05, m = 3).
// Args: N, leaf size, m, 0 = nearest / 1 = balls.
void BM_NeighbourLeafSize(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const auto scaled = mlce::scaled_to_unit_deviation(lorenz(n));
  const std::size_t dim = static_cast<std::size_t>(state.range(2)), delay = 17;
  const std::span<const double> x(scaled.channels[0]);
  const mlce::DelayEmbedding embedding({x}, dim, delay, mlce::DelayEmbedding::max_points(n, dim, delay));
  mlce::NeighbourOptions o;
  o.theiler = 170;
  o.leaf_size = static_cast<std::size_t>(state.range(1));
  const auto queries = mlce::strided_indices(embedding.size(), 20000);
  const bool balls = state.range(3) == 1;
  std::size_t found = 0;
  for (auto _ : state) {
    const mlce::NeighbourIndex index(embedding, o);  // the build counts: each estimate builds its trees
    found = 0;
    if (balls) {
      // The radius grows with sqrt(m) so that each coordinate's share stays that of m = 3.
      const double radius = 0.05 * std::sqrt(static_cast<double>(dim) / 3.0);
      std::vector<std::uint32_t> out;
      for (std::size_t q = 0; q < queries.size(); q += 10) {
        index.within(queries[q], radius, embedding.size(), out);
        found += out.size();
      }
    } else {
      const auto nearest = index.nearest(queries, embedding.size());
      for (const auto j : nearest.neighbour) found += j != mlce::NeighbourResult::none;
    }
    benchmark::DoNotOptimize(found);
  }
  state.counters["found"] = static_cast<double>(found);
}
BENCHMARK(BM_NeighbourLeafSize)
    ->ArgsProduct({{100000, 1000000}, {10, 20, 40, 64}, {3, 8}, {0}})
    ->ArgsProduct({{1000000}, {10, 20, 40, 64}, {3, 8}, {1}})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
