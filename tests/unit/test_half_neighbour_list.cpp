// Unit tests of the half neighbour list and the symmetric pair loops (issue 17; scene key
// neighbour_list, libcore/neighbour_search.hpp NeighbourList::half, libcore/pair_scatter.hpp,
// physics/fluid/fluid_half.cpp):
//  - a half search keeps exactly the pairs j > i of the full search (ghosts: every pair), also
//    through the Verlet candidates;
//  - PairScatter adds every pair once to each side, whatever the thread count (exact integer
//    sums), and does not allocate again for the same layout;
//  - the fluid rates (accelerations, density rates) of one evaluation on the half list equal
//    those of the full list to 1e-12 of their largest value, and dropping one pair from the
//    half list breaks that (the comparison can see a lost pair);
//  - 2D dam breaks (two option sets), a column collapsing across periodic faces (ghost pairs)
//    and a coarse 3D case A run equal the full-list runs to 1e-12 relative in positions after
//    100-150 steps, run on 3 threads (spills exercised);
//  - the scene key: half with surface tension is refused naming the key and the module; auto
//    (the default) picks half only when every module supports it.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "libcore/memory.hpp"
#include "libcore/neighbour_search.hpp"
#include "libcore/pair_scatter.hpp"
#include "libcore/runner.hpp"
#include "libcore/scene.hpp"
#include "libcore/simulation.hpp"
#include "physics/fluid/fluid_module.hpp"

using namespace poresph;
namespace fsys = std::filesystem;

namespace {

std::vector<std::vector<Index>> rows(const NeighbourList& l, bool onlyAbove) {
  std::vector<std::vector<Index>> r(static_cast<size_t>(l.realCount()));
  for (Index i = 0; i < l.realCount(); ++i) {
    for (auto k = l.offset[i]; k < l.offset[i + 1]; ++k) {
      const Index j = l.index[static_cast<size_t>(k)];
      if (!onlyAbove || j > i) r[static_cast<size_t>(i)].push_back(j);
    }
    std::sort(r[static_cast<size_t>(i)].begin(), r[static_cast<size_t>(i)].end());
  }
  return r;
}

std::vector<double> cloud(int d, Index n, double box, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, box);
  std::vector<double> x(static_cast<size_t>(n * d));
  for (double& c : x) c = u(rng);
  return x;
}

}  // namespace

TEST(HalfNeighbourList, SearchKeepsEachRealPairOnceAndEveryGhostPair) {
  for (int d = 2; d <= 3; ++d) {
    const Index nReal = d == 2 ? 2000 : 3000, nTotal = nReal + 400;  // the last 400 as ghosts
    const std::vector<double> x = cloud(d, nTotal, d == 2 ? 1.0 : 0.5, 7u + static_cast<unsigned>(d));
    const double radius = 0.06;
    NeighbourSearch search;
    NeighbourList full, half;
    search.build(x.data(), d, nReal, nTotal, radius, full);
    search.build(x.data(), d, nReal, nTotal, radius, half, true);
    EXPECT_FALSE(full.half);
    EXPECT_TRUE(half.half);
    EXPECT_EQ(rows(half, false), rows(full, true)) << "dimension " << d;
    // Real pairs once, ghost pairs (j >= nReal > i) in full: the count follows.
    std::int64_t realPairs = 0, ghostPairs = 0;
    for (Index i = 0; i < nReal; ++i)
      for (auto k = full.offset[i]; k < full.offset[i + 1]; ++k)
        (full.index[static_cast<size_t>(k)] < nReal ? realPairs : ghostPairs) += 1;
    EXPECT_EQ(half.pairCount(), realPairs / 2 + ghostPairs);
    EXPECT_GT(ghostPairs, 0);
    // Through the Verlet candidates: the filtered half list is a half list of the same pairs.
    VerletNeighbours verlet;
    NeighbourList filtered;
    verlet.rebuild(search, x.data(), d, nReal, nTotal, radius, 0.01, true);
    verlet.filter(x.data(), d, radius, filtered);
    EXPECT_TRUE(filtered.half);
    EXPECT_EQ(rows(filtered, false), rows(full, true));
  }
}

TEST(HalfNeighbourList, ScatterAddsEveryPairOnceToBothSidesWhateverTheThreads) {
  const int d = 3;
  const Index nReal = 4000, nTotal = 4300;
  const std::vector<double> x = cloud(d, nTotal, 0.5, 99u);
  NeighbourSearch search;
  NeighbourList full, half;
  search.build(x.data(), d, nReal, nTotal, 0.05, full);
  search.build(x.data(), d, nReal, nTotal, 0.05, half, true);
  // c(a, b): what b gives to a; small integers, so every sum is exact in any order.
  auto c = [](Index a, Index b) { return static_cast<double>((a * 7 + b * 13) % 1000 + 1); };
  const int width = 2;
  std::vector<double> expect(static_cast<size_t>(nReal * width), 0.0);
  for (Index i = 0; i < nReal; ++i)
    for (auto k = full.offset[i]; k < full.offset[i + 1]; ++k) {
      const Index j = full.index[static_cast<size_t>(k)];
      expect[static_cast<size_t>(i * width)] += c(i, j);
      expect[static_cast<size_t>(i * width + 1)] += 1.0;
    }
  const int saved = omp_get_max_threads();
  for (int threads : {1, 2, 3, 5, 8}) {
    omp_set_num_threads(threads);
    PairScatter scatter;
    std::vector<double> own(static_cast<size_t>(nReal * width), -1.0);
    for (int pass = 0; pass < 2; ++pass) {
      scatter.prepare(half, nReal, width);
      const std::int64_t allocations = scatter.allocations();
      double* o = own.data();
#pragma omp parallel num_threads(scatter.threads())
      {
        scatter.forBlocks([&](int t) {
          scatter.zero(t, o);
          for (Index i = scatter.begin(t); i < scatter.end(t); ++i) {
            double si = 0.0, ni = 0.0;
            for (auto k = half.offset[i]; k < half.offset[i + 1]; ++k) {
              const Index j = half.index[static_cast<size_t>(k)];
              si += c(i, j);
              ni += 1.0;
              if (j < nReal) {
                double* tj = scatter.at(t, o, j);
                tj[0] += c(j, i);
                tj[1] += 1.0;
              }
            }
            o[i * width] += si;
            o[i * width + 1] += ni;
          }
        });
#pragma omp barrier
        scatter.forBlocks([&](int t) { scatter.reduce(t, o); });
      }
      ASSERT_EQ(own, expect) << threads << " threads, pass " << pass;
      if (pass == 1) {
        EXPECT_EQ(scatter.allocations(), allocations);  // same layout: no growth
      }
    }
    if (threads > 1) {
      EXPECT_GT(scatter.largestSpill(), 0);
    }
    // A loop wider than the layout was sized for is refused, never grown in the loop.
    EXPECT_THROW(scatter.use(width + 1), std::logic_error);
  }
  omp_set_num_threads(saved);
}

TEST(HalfNeighbourList, WeightedBlocksBalanceTheWeightAndScatterTheSameSums) {
  // layoutWeighted (issue 17): blocks split by a weight per row, here the entries of every third
  // row of the first quarter only (the others weigh 0, as a dry boundary row does in the fluid
  // loops; blocks by entries would give the first block all of it). Each block
  // holds total / threads of the weight to within one row, and the scatter's sums (exact small
  // integers) are those of every pair once to each side, whatever the thread count.
  const int d = 3;
  const Index nReal = 4000, nTotal = 4300;
  const std::vector<double> x = cloud(d, nTotal, 0.5, 7u);
  NeighbourSearch search;
  NeighbourList half;
  search.build(x.data(), d, nReal, nTotal, 0.05, half, true);
  const std::int64_t* off = half.offset.data();
  auto weight = [&](Index i) -> std::int64_t { return i % 3 == 0 && i < nReal / 4 ? off[i + 1] - off[i] : 0; };
  std::int64_t total = 0, heaviest = 0;
  for (Index i = 0; i < nReal; ++i) {
    total += weight(i);
    heaviest = std::max(heaviest, weight(i));
  }
  auto c = [](Index a, Index b) { return static_cast<double>((a * 5 + b * 11) % 997 + 1); };
  std::vector<double> expect(static_cast<size_t>(nReal), 0.0);
  for (Index i = 0; i < nReal; ++i)
    for (auto k = off[i]; k < off[i + 1]; ++k) {
      const Index j = half.index[static_cast<size_t>(k)];
      expect[static_cast<size_t>(i)] += c(i, j);
      if (j < nReal) expect[static_cast<size_t>(j)] += c(j, i);
    }
  const int saved = omp_get_max_threads();
  for (int threads : {1, 2, 3, 7}) {
    omp_set_num_threads(threads);
    PairScatter scatter;
    scatter.layoutWeighted(half, nReal, 1, weight);
    scatter.use(1);
    ASSERT_EQ(scatter.threads(), threads);
    EXPECT_EQ(scatter.begin(0), 0);
    EXPECT_EQ(scatter.end(threads - 1), nReal);
    for (int t = 0; t < threads; ++t) {
      if (t > 0) EXPECT_EQ(scatter.begin(t), scatter.end(t - 1));
      std::int64_t w = 0;
      for (Index i = scatter.begin(t); i < scatter.end(t); ++i) w += weight(i);
      EXPECT_LE(std::abs(static_cast<double>(w) - static_cast<double>(total) / threads),
                static_cast<double>(heaviest) + 1.0)
          << threads << " threads, block " << t;
    }
    std::vector<double> own(static_cast<size_t>(nReal), -1.0);
    double* o = own.data();
#pragma omp parallel num_threads(scatter.threads())
    {
      scatter.forBlocks([&](int t) {
        scatter.zero(t, o);
        for (Index i = scatter.begin(t); i < scatter.end(t); ++i)
          for (auto k = off[i]; k < off[i + 1]; ++k) {
            const Index j = half.index[static_cast<size_t>(k)];
            o[i] += c(i, j);
            if (j < nReal) *scatter.at(t, o, j) += c(j, i);
          }
      });
#pragma omp barrier
      scatter.forBlocks([&](int t) { scatter.reduce(t, o); });
    }
    ASSERT_EQ(own, expect) << threads << " threads";
  }
  omp_set_num_threads(saved);
}

namespace {

// A 2D dam break with walls, viscosity, artificial viscosity, density diffusion and XSPH (set
// 0), or a filled tank set in motion with the Hu-Adams pressure, density summation, Tait and
// shifting (set 1).
std::string damBreak2D(const std::string& list, int set) {
  // Set 1: a closed tank (lid at 0.43 m) filled with water set in motion, since the density
  // summation needs no free surface.
  const std::string top = set == 0 ? "0.43" : "0.46";
  std::string s = R"(
dimension: 2
domain: {lo: [-0.03, -0.03], hi: [0.83, )" + top + R"(]}
spacing: 0.01
h_over_dx: 1.3
kernel: wendland_c2
integrator: leapfrog
end_time: 1.0
max_steps: 150
time_step: {adaptive: true, cfl: 1.0}
output: {every_steps: 100000}
neighbour_skin: 0.3
neighbour_list: )" + list + R"(
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 20, viscosity: 1.0e-3)";
  s += set == 1 ? ", eos: tait}\n" : "}\n";
  s += R"(  - {name: tank, model: wall, density: 1000}
geometry:
  - {shape: box, lo: [-0.03, -0.03], hi: [0.83, )" + top + R"(], material: tank}
  - {shape: box, lo: [0.0, 0.0], hi: [0.8, 0.43], material: none}
)";
  s += set == 0 ? "  - {shape: box, lo: [0.0, 0.0], hi: [0.2, 0.3], material: water}\n"
                : "  - {shape: box, lo: [0.0, 0.0], hi: [0.8, 0.43], material: water, velocity: [0.5, 0.2]}\n";
  s += R"(fluid:
  gravity: [0, -9.81]
  artificial_viscosity: 0.1
)";
  s += set == 0 ? "  density_diffusion: 0.1\n  xsph: 0.3\n"
                : "  pressure_gradient: hu_adams\n  density: summation\n  shifting: 0.5\n";
  return s;
}

// Case A of docs/performance.md (DualSPHysics 01_DamBreak settings) at dx = 2 cm.
std::string caseA(const std::string& list) {
  return R"(
dimension: 3
domain: {lo: [-0.06, -0.06, -0.06], hi: [1.66, 0.72, 0.46]}
spacing: 0.02
h_over_dx: 1.7320508
kernel: cubic_spline
integrator: verlet
end_time: 1.0
max_steps: 100
time_step: {adaptive: true, cfl: 0.8}
output: {every_steps: 100000}
neighbour_skin: 0.3
neighbour_list: )" + list + R"(
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 33.7337, viscosity: 0.0, eos: tait, tait_gamma: 7}
  - {name: tank, model: wall, density: 1000}
geometry:
  - {shape: box, lo: [-0.06, -0.06, -0.06], hi: [1.66, 0.72, 0.40], material: tank}
  - {shape: box, lo: [0.0, 0.0, 0.0], hi: [1.60, 0.66, 0.40], material: none}
  - {shape: box, lo: [0.88, 0.22, 0.0], hi: [1.02, 0.36, 0.44], material: tank}
  - {shape: box, lo: [0.94, 0.28, 0.0], hi: [0.96, 0.30, 0.42], material: none}
  - {shape: box, lo: [0.0, 0.0, 0.0], hi: [0.40, 0.66, 0.30], material: water}
fluid:
  gravity: [0, 0, -9.81]
  artificial_viscosity: 0.1
  density_diffusion: 0.1
  hydrostatic_level: 0.30
)";
}

// A water column against the periodic face of a 2D channel, collapsing and moving across it
// (fluid-fluid and fluid-wall pairs with ghosts, particles wrapped, the halo kept between
// searches with the skin).
std::string periodicCollapse(const std::string& list) {
  return R"(
dimension: 2
domain: {lo: [0.0, -0.03], hi: [0.4, 0.3], periodic: [true, false]}
spacing: 0.01
h_over_dx: 1.3
kernel: wendland_c2
integrator: leapfrog
end_time: 1.0
max_steps: 150
time_step: {adaptive: true, cfl: 1.0}
output: {every_steps: 100000}
neighbour_skin: 0.3
neighbour_list: )" + list + R"(
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 20, viscosity: 1.0e-3}
  - {name: floor, model: wall, density: 1000}
geometry:
  - {shape: box, lo: [0.0, -0.03], hi: [0.4, 0.0], material: floor}
  - {shape: box, lo: [0.3, 0.0], hi: [0.4, 0.25], material: water, velocity: [0.5, 0.0]}
fluid:
  gravity: [0, -9.81]
  artificial_viscosity: 0.1
  density_diffusion: 0.1
)";
}

std::vector<Index> rowsById(const Simulation& s) {
  std::vector<Index> at(static_cast<size_t>(s.store.realCount()));
  const std::int32_t* id = s.store.data(s.store.id());
  for (Index i = 0; i < s.store.realCount(); ++i) at[static_cast<size_t>(id[i])] = i;
  return at;
}

struct Difference {
  double position = 0.0, extent = 0.0, moved = 0.0;
};

// Largest position difference between two runs of the same scene (particles matched by id),
// the largest coordinate, and the largest displacement of a particle since the start.
Difference compare(const Simulation& a, const Simulation& b, const std::vector<double>& x0) {
  Difference r;
  const auto ia = rowsById(a), ib = rowsById(b);
  const int d = a.dimension();
  const double* xa = a.store.data(a.store.position());
  const double* xb = b.store.data(b.store.position());
  for (size_t k = 0; k < ia.size(); ++k) {
    double m2 = 0.0;
    for (int c = 0; c < d; ++c) {
      r.position = std::max(r.position, std::abs(xa[ia[k] * d + c] - xb[ib[k] * d + c]));
      r.extent = std::max(r.extent, std::abs(xa[ia[k] * d + c]));
      const double m = xa[ia[k] * d + c] - x0[k * static_cast<size_t>(d) + c];
      m2 += m * m;
    }
    r.moved = std::max(r.moved, std::sqrt(m2));
  }
  return r;
}

std::vector<double> positionsById(const Simulation& s) {
  const auto at = rowsById(s);
  const int d = s.dimension();
  const double* x = s.store.data(s.store.position());
  std::vector<double> out(at.size() * static_cast<size_t>(d));
  for (size_t k = 0; k < at.size(); ++k)
    for (int c = 0; c < d; ++c) out[k * static_cast<size_t>(d) + c] = x[at[k] * d + c];
  return out;
}

void runBoth(const std::string& fullText, const std::string& halfText, const std::string& name,
             double* relative, double* moved, double spacing) {
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-half-neighbour-list" / name;
  fsys::remove_all(dir);
  fsys::create_directories(dir);
  RunOptions o;
  o.handleSignals = false;
  Scene full = loadSceneText(fullText, (dir / "full.yaml").string());
  ASSERT_FALSE(full.sim->halfNeighbourList);
  const std::vector<double> x0 = positionsById(*full.sim);
  o.outDir = (dir / "full").string();
  ASSERT_EQ(runScene(full, o).status, RunStatus::Finished);
  const int saved = omp_get_max_threads();
  omp_set_num_threads(3);  // three blocks: the spills and their reduction take part
  Scene half = loadSceneText(halfText, (dir / "half.yaml").string());
  ASSERT_TRUE(half.sim->halfNeighbourList);
  o.outDir = (dir / "half").string();
  const RunResult rh = runScene(half, o);
  omp_set_num_threads(saved);
  ASSERT_EQ(rh.status, RunStatus::Finished);
  ASSERT_EQ(full.sim->step, half.sim->step);
  // The half list holds half the pairs of real particles and every pair with a ghost.
  if (half.sim->store.ghostCount() == 0)
    EXPECT_EQ(2 * half.sim->neighbours.pairCount(), full.sim->neighbours.pairCount());
  else
    EXPECT_LT(2 * half.sim->neighbours.pairCount(), 2 * full.sim->neighbours.pairCount());
  // No allocation in the time loop: the symmetric loops' buffers stopped growing early.
  const auto* fm = dynamic_cast<const FluidModule*>(half.sim->module("fluid"));
  ASSERT_NE(fm, nullptr);
  // The buffers are sized at the layouts (once per neighbour search), for the widest loop;
  // the loops never allocate (PairScatter::use). After the first layout none grew.
  const PairScatter& sc = fm->pairScatter();
  std::printf("%s: %lld layouts, %lld of them grew a buffer (%lld allocations)\n", name.c_str(),
              static_cast<long long>(sc.layouts()), static_cast<long long>(sc.layoutsThatGrew()),
              static_cast<long long>(sc.allocations()));
  EXPECT_GT(sc.layouts(), 1);
  EXPECT_EQ(sc.layoutsThatGrew(), 1);  // the first layout only
  EXPECT_LE(sc.allocations(), 3);      // one buffer per block at most
  const Difference diff = compare(*full.sim, *half.sim, x0);
  *relative = diff.position / diff.extent;
  *moved = diff.moved / spacing;
  std::printf("%s: %lld steps, positions differ by %.3g of the largest coordinate (%.3g dx); "
              "largest displacement %.3g dx\n",
              name.c_str(), static_cast<long long>(half.sim->step), *relative,
              diff.position / spacing, *moved);
}

}  // namespace

TEST(HalfNeighbourList, DamBreak2DEqualsTheFullListRun) {
  for (int set = 0; set < 2; ++set) {
    double relative = 1.0, moved = 0.0;
    runBoth(damBreak2D("full", set), damBreak2D("half", set), "dam2d_" + std::to_string(set),
            &relative, &moved, 0.01);
    EXPECT_GT(moved, 0.5);  // the flow moved: a lost pair would show
    EXPECT_LT(relative, 1e-12) << "option set " << set;
  }
}

TEST(HalfNeighbourList, PeriodicCollapseEqualsTheFullListRun) {
  double relative = 1.0, moved = 0.0;
  runBoth(periodicCollapse("full"), periodicCollapse("half"), "periodic", &relative, &moved, 0.01);
  EXPECT_GT(moved, 0.5);
  EXPECT_LT(relative, 1e-12);
}

TEST(HalfNeighbourList, CaseA3DEqualsTheFullListRun) {
  double relative = 1.0, moved = 0.0;
  runBoth(caseA("full"), caseA("half"), "caseA", &relative, &moved, 0.02);
  EXPECT_GT(moved, 0.1);
  EXPECT_LT(relative, 1e-12);
}

namespace {

// Largest difference of accelerations and density rates of two stores of the same particles
// (matched by id), relative to the largest value of each.
std::pair<double, double> rateDifference(const Simulation& a, const Simulation& b) {
  const auto ia = rowsById(a), ib = rowsById(b);
  const int d = a.dimension();
  const double* aa = a.store.data(a.acceleration);
  const double* ab = b.store.data(b.acceleration);
  const auto* fa = dynamic_cast<const FluidModule*>(a.module("fluid"));
  const auto* fb = dynamic_cast<const FluidModule*>(b.module("fluid"));
  const double* ra = a.store.data(fa->densityRate);
  const double* rb = b.store.data(fb->densityRate);
  double da = 0.0, ma = 0.0, dr = 0.0, mr = 0.0;
  for (size_t k = 0; k < ia.size(); ++k) {
    const Index i = ia[k], j = ib[k];
    for (int c = 0; c < d; ++c) {
      da = std::max(da, std::abs(aa[i * d + c] - ab[j * d + c]));
      ma = std::max(ma, std::abs(aa[i * d + c]));
    }
    dr = std::max(dr, std::abs(ra[i] - rb[j]));
    mr = std::max(mr, std::abs(ra[i]));
  }
  return {da / ma, dr / mr};
}

}  // namespace

TEST(HalfNeighbourList, RatesEqualTheFullListsAndALostPairIsSeen) {
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-half-neighbour-list";
  fsys::create_directories(dir);
  // Set 0 run for 60 steps on the full list, so that the flow is not at rest.
  Scene full = loadSceneText(damBreak2D("full", 0), (dir / "rates_full.yaml").string());
  RunOptions o;
  o.handleSignals = false;
  full.maxSteps = 60;
  o.outDir = (dir / "rates_full").string();
  ASSERT_EQ(runScene(full, o).status, RunStatus::Finished);
  // The same scene on the half list, given the full run's state field by field.
  Scene half = loadSceneText(damBreak2D("half", 0), (dir / "rates_half.yaml").string());
  {
    ParticleStore& from = full.sim->store;
    ParticleStore& to = half.sim->store;
    ASSERT_EQ(from.size(), to.size());
    for (const FieldSpec& f : from.fields()) {
      if (!to.has(f.name)) continue;  // the integrator's scratch (registered at a first step)
      const size_t count = static_cast<size_t>(from.size() * f.components);
      if (f.type == FieldType::Real)
        std::memcpy(to.data(to.real(f.name)), from.data(from.real(f.name)), count * sizeof(double));
      else
        std::memcpy(to.data(to.integer(f.name)), from.data(from.integer(f.name)),
                    count * sizeof(std::int32_t));
    }
    half.sim->time = full.sim->time;
    half.sim->dt = full.sim->dt;
    half.sim->step = full.sim->step;
  }
  Simulation& a = *full.sim;
  Simulation& b = *half.sim;
  ASSERT_EQ(a.step, b.step);
  // The same state (particles matched by id): one evaluation each.
  a.updateNeighbours();
  b.updateNeighbours();
  ASSERT_TRUE(b.neighbours.half);
  ASSERT_EQ(positionsById(a), positionsById(b));
  a.evaluateRatesOnTheList();
  b.evaluateRatesOnTheList();
  const auto same = rateDifference(a, b);
  std::printf("one evaluation: accelerations %.3g, density rates %.3g of their largest\n",
              same.first, same.second);
  EXPECT_LT(same.first, 1e-12);
  EXPECT_LT(same.second, 1e-12);
  // Drop one fluid-fluid pair of the half list (the entry becomes the particle itself, r = 0:
  // no contribution): the comparison sees it.
  const std::int32_t* ph = b.store.data(b.store.phase());
  bool dropped = false;
  for (Index i = 0; i < b.store.realCount() && !dropped; ++i) {
    if (ph[i] != kPhaseFluid) continue;
    for (auto k = b.neighbours.offset[i]; k < b.neighbours.offset[i + 1]; ++k) {
      const Index j = b.neighbours.index[static_cast<size_t>(k)];
      if (j < b.store.realCount() && ph[j] == kPhaseFluid) {
        b.neighbours.index[static_cast<size_t>(k)] = static_cast<std::uint32_t>(i);
        dropped = true;
        break;
      }
    }
  }
  ASSERT_TRUE(dropped);
  b.evaluateRatesOnTheList();
  const auto lost = rateDifference(a, b);
  std::printf("one pair dropped: accelerations %.3g, density rates %.3g of their largest\n",
              lost.first, lost.second);
  EXPECT_GT(std::max(lost.first, lost.second), 1e-8);
}

TEST(HalfNeighbourList, SceneKey) {
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-half-neighbour-list";
  fsys::create_directories(dir);
  // Default: auto (half for this fluid-only scene).
  {
    std::string t = damBreak2D("full", 0);
    t.replace(t.find("neighbour_list: full\n"), 21, "");
    Scene s = loadSceneText(t, (dir / "default.yaml").string());
    EXPECT_TRUE(s.sim->halfNeighbourList);
  }
  // Explicit full.
  {
    Scene s = loadSceneText(damBreak2D("full", 0), (dir / "full.yaml").string());
    EXPECT_FALSE(s.sim->halfNeighbourList);
  }
  // The memory estimate before any particle exists counts half the entries of a half list.
  {
    SceneOptions opt;
    opt.initialise = false;
    std::string t = damBreak2D("half", 0);
    t.replace(t.find("neighbour_skin: 0.3\n"), 20, "");
    Scene h = loadSceneText(t, (dir / "estimate_half.yaml").string(), opt);
    t.replace(t.find("neighbour_list: half"), 20, "neighbour_list: full");
    Scene f = loadSceneText(t, (dir / "estimate_full.yaml").string(), opt);
    double listHalf = -1.0, listFull = -1.0;
    for (const auto& l : memoryReport(*h.sim, 1000, 20.0).lines)
      if (l.what == "neighbour list") listHalf = l.bytesPerParticle;
    for (const auto& l : memoryReport(*f.sim, 1000, 20.0).lines)
      if (l.what == "neighbour list") listFull = l.bytesPerParticle;
    EXPECT_DOUBLE_EQ(listHalf, 10.0 * 4.0 + 8.0);
    EXPECT_DOUBLE_EQ(listFull, 20.0 * 4.0 + 8.0);
  }
  // auto on a fluid-only scene without surface tension: half.
  {
    Scene s = loadSceneText(damBreak2D("auto", 0), (dir / "auto.yaml").string());
    EXPECT_TRUE(s.sim->halfNeighbourList);
  }
  // Surface tension needs the full list: auto gives full, half is refused naming key and module.
  std::string st = damBreak2D("auto", 0) + "  surface_tension: 0.07\n";
  {
    Scene s = loadSceneText(st, (dir / "auto_st.yaml").string());
    EXPECT_FALSE(s.sim->halfNeighbourList);
  }
  st.replace(st.find("neighbour_list: auto"), 20, "neighbour_list: half");
  try {
    loadSceneText(st, (dir / "half_st.yaml").string());
    FAIL() << "a half list with surface tension was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("half_st.yaml"), std::string::npos) << m;
    EXPECT_NE(m.find("neighbour_list"), std::string::npos) << m;
    EXPECT_NE(m.find("'fluid'"), std::string::npos) << m;
  }
  try {
    loadSceneText(damBreak2D("halves", 0), (dir / "bad.yaml").string());
    FAIL() << "an unknown neighbour_list value was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("neighbour_list"), std::string::npos) << e.what();
  }
}
