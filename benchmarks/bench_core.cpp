// Speed of the core: neighbour-list build and one density-summation pass
// (rho_i = m_i W(0) + sum_j m_j W_ij, thesis Eq. 2.26 in summation form; gather, OpenMP over i).
//
// Particles: 3D cubic lattice of spacing dx with uniform random jitter of +-0.05 dx, cell-ordered
// once as the simulation does (NeighbourSearch::cellOrder + ParticleStore::permute), cubic
// spline (Eq. 2.11), h = 1.3 dx, support 2h. N = 1e4, 1e5, 1e6; 1 and 2 OpenMP threads.
//
// Counters: time_per_particle (wall time per particle per call, s), pairs_per_s (list entries visited
// per second), neighbours (mean list length), list_MB (memory of the neighbour list).
// Run: bench_core --benchmark_counters_tabular=true   (timings never decide a test)
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include "libcore/kernel.hpp"
#include "libcore/neighbour_search.hpp"
#include "libcore/particle_store.hpp"

using namespace poresph;

namespace {

struct Setup {
  explicit Setup(Index target) : store(3) {
    const int n = static_cast<int>(std::lround(std::cbrt(static_cast<double>(target))));
    dx = 1e-4;  // 0.1 mm, a pore-scale spacing (SI)
    kernel = Kernel(KernelType::CubicSpline, 3, 1.3 * dx);
    store.addParticles(static_cast<Index>(n) * n * n);
    double* x = store.data(store.position());
    double* m = store.data(store.mass());
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> jitter(-0.05 * dx, 0.05 * dx);
    Index p = 0;
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i, ++p) {
          x[3 * p + 0] = (i + 0.5) * dx + jitter(rng);
          x[3 * p + 1] = (j + 0.5) * dx + jitter(rng);
          x[3 * p + 2] = (k + 0.5) * dx + jitter(rng);
          m[p] = 1000.0 * dx * dx * dx;  // water, kg
        }
    std::vector<Index> order;
    search.cellOrder(x, 3, store.realCount(), kernel.support(), order);
    store.permute(order);
    // The particle nearest the centre of the block (for the density sanity counter).
    x = store.data(store.position());
    double best = 1e300;
    for (Index i = 0; i < store.realCount(); ++i) {
      double d2 = 0.0;
      for (int a = 0; a < 3; ++a) d2 += std::pow(x[3 * i + a] - 0.5 * n * dx, 2);
      if (d2 < best) best = d2, centre = i;
    }
  }
  Index centre = 0;
  ParticleStore store;
  double dx = 0.0;
  Kernel kernel;
  NeighbourSearch search;
  NeighbourList list;
};

// One set-up per size, shared by the benchmarks (the 1e6 lattice takes a while to make).
Setup& setup(Index n) {
  static std::map<Index, std::unique_ptr<Setup>> cache;
  auto& s = cache[n];
  if (!s) s = std::make_unique<Setup>(n);
  return *s;
}

void addCounters(benchmark::State& state, const Setup& s) {
  const double n = static_cast<double>(s.store.realCount());
  const double pairs = static_cast<double>(s.list.pairCount());
  state.counters["N"] = n;
  state.counters["threads"] = static_cast<double>(omp_get_max_threads());
  state.counters["neighbours"] = pairs / n;
  state.counters["list_MB"] = static_cast<double>(s.list.bytes()) / 1e6;
  // Per iteration: n particles and `pairs` list entries; kIsRate divides by the wall time.
  state.counters["pairs_per_s"] =
      benchmark::Counter(pairs, benchmark::Counter::kIsIterationInvariantRate);
  // Inverted rate: seconds per particle (printed with an SI prefix, e.g. 85n = 85 ns).
  state.counters["time_per_particle"] = benchmark::Counter(
      n, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["search_MB"] = static_cast<double>(s.search.bytes()) / 1e6;
}

void BM_NeighbourBuild(benchmark::State& state) {
  Setup& s = setup(state.range(0));
  omp_set_num_threads(static_cast<int>(state.range(1)));
  const double* x = s.store.data(s.store.position());
  const Index n = s.store.realCount();
  s.search.build(x, 3, n, n, s.kernel.support(), s.list);  // warm-up: lists reach their size
  for (auto _ : state) {
    s.search.build(x, 3, n, n, s.kernel.support(), s.list);
    benchmark::DoNotOptimize(s.list.index.data());
  }
  addCounters(state, s);
}

void BM_DensitySum(benchmark::State& state) {
  Setup& s = setup(state.range(0));
  omp_set_num_threads(static_cast<int>(state.range(1)));
  const Index n = s.store.realCount();
  const double* x = s.store.data(s.store.position());
  s.search.build(x, 3, n, n, s.kernel.support(), s.list);
  const double* m = s.store.data(s.store.mass());
  double* rho = s.store.data(s.store.density());
  const std::int64_t* off = s.list.offset.data();
  const std::uint32_t* nb = s.list.index.data();
  const Kernel& W = s.kernel;
  const double w0 = W.value(0.0);
  for (auto _ : state) {
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) {
      const double xi = x[3 * i], yi = x[3 * i + 1], zi = x[3 * i + 2];
      double sum = m[i] * w0;
      for (std::int64_t k = off[i]; k < off[i + 1]; ++k) {
        const Index j = nb[k];
        const double dx = xi - x[3 * j], dy = yi - x[3 * j + 1], dz = zi - x[3 * j + 2];
        sum += m[j] * W.value(std::sqrt(dx * dx + dy * dy + dz * dz));
      }
      rho[i] = sum;
    }
    benchmark::DoNotOptimize(rho);
    benchmark::ClobberMemory();
  }
  // Sanity: the density at the centre of the block is close to 1000 kg/m^3 (not a test, a
  // guard against timing a wrong loop).
  state.counters["rho_centre"] = rho[s.centre];
  addCounters(state, s);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (Index n : {10000, 100000, 1000000})
    for (int t : {1, 2}) b->Args({n, t});
  b->UseRealTime()->Unit(benchmark::kMillisecond);
}

}  // namespace

BENCHMARK(BM_NeighbourBuild)->Apply(sizes);
BENCHMARK(BM_DensitySum)->Apply(sizes);
BENCHMARK_MAIN();
