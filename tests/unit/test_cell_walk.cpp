// Unit tests of the cell walk without a stored list (issue 17, memory; scene key
// `neighbour_list: cells`, libcore/cell_walk.hpp, physics/fluid/fluid_half.cpp):
//  - the walk of NeighbourSearch::sortCells' cells visits exactly the rows of the half list,
//    entry by entry in the same order (random clouds with ghosts in 2D and 3D, and a lattice
//    whose spacing puts neighbours exactly at the radius);
//  - cellWalkBlocks' spill ends cover every real particle a block's rows reach, and PairScatter
//    on those blocks adds every pair once to both sides for 1, 2, 3 and 5 threads (exact sums);
//  - runs with the walk equal the half-list runs: bit for bit on one thread (same pairs, same
//    order), to round-off (1e-12 of the largest coordinate) on 3 threads (other blocks): a 2D dam
//    break through the vectorised fluid-fluid block, a column across a periodic face (ghosts,
//    XSPH: the scalar pair path) and a coarse 3D case A;
//  - the scene key: cells with a Verlet skin or with surface tension is refused naming the key;
//    `poresph info`'s report counts no list.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "libcore/cell_walk.hpp"
#include "libcore/memory.hpp"
#include "libcore/neighbour_search.hpp"
#include "libcore/pair_scatter.hpp"
#include "libcore/runner.hpp"
#include "libcore/scene.hpp"
#include "libcore/simulation.hpp"

using namespace poresph;
namespace fsys = std::filesystem;

namespace {

std::vector<double> cloud(int d, Index n, double box, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, box);
  std::vector<double> x(static_cast<size_t>(n * d));
  for (double& c : x) c = u(rng);
  return x;
}

// A lattice of spacing dx with n points per axis (radius 2 dx: neighbours exactly at the radius,
// which the strict comparison must drop in both).
std::vector<double> lattice(int d, int n, double dx) {
  std::vector<double> x;
  const int nz = d > 2 ? n : 1, ny = d > 1 ? n : 1;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < n; ++i) {
        x.push_back(i * dx);
        if (d > 1) x.push_back(j * dx);
        if (d > 2) x.push_back(k * dx);
      }
  return x;
}

template <int D>
std::vector<std::vector<Index>> walkRows(const NeighbourSearch& s, const double* x, Index nReal,
                                         double radius) {
  const CellWalk<D> walk(s.grid(), x, radius);
  std::vector<std::vector<Index>> r(static_cast<size_t>(nReal));
  for (Index i = 0; i < nReal; ++i) walk.row(i, [&](Index j) { r[static_cast<size_t>(i)].push_back(j); });
  return r;
}

std::vector<std::vector<Index>> listRows(const NeighbourList& l) {
  std::vector<std::vector<Index>> r(static_cast<size_t>(l.realCount()));
  for (Index i = 0; i < l.realCount(); ++i)
    for (auto k = l.offset[i]; k < l.offset[i + 1]; ++k)
      r[static_cast<size_t>(i)].push_back(l.index[static_cast<size_t>(k)]);
  return r;
}

void expectWalkEqualsHalfList(int d, const std::vector<double>& x, Index nReal, double radius,
                              const std::string& what) {
  const Index nTotal = static_cast<Index>(x.size()) / d;
  NeighbourSearch listSearch, walkSearch;
  NeighbourList half;
  listSearch.build(x.data(), d, nReal, nTotal, radius, half, true);
  walkSearch.sortCells(x.data(), d, nTotal, radius);
  ASSERT_EQ(walkSearch.grid().count, nTotal);
  const auto walked = d == 2 ? walkRows<2>(walkSearch, x.data(), nReal, radius)
                             : walkRows<3>(walkSearch, x.data(), nReal, radius);
  const auto listed = listRows(half);
  std::int64_t pairs = 0;
  for (const auto& r : walked) pairs += static_cast<std::int64_t>(r.size());
  EXPECT_EQ(pairs, half.pairCount()) << what;
  EXPECT_GT(pairs, 0) << what;
  EXPECT_TRUE(walked == listed) << what << ": the walk's rows differ from the half list's";
}

}  // namespace

TEST(CellWalk, RowsEqualTheHalfListEntryByEntry) {
  for (int d = 2; d <= 3; ++d) {
    const Index nReal = d == 2 ? 2000 : 3000, nTotal = nReal + 400;  // the last 400 as ghosts
    const std::vector<double> x = cloud(d, nTotal, d == 2 ? 1.0 : 0.5, 11u + static_cast<unsigned>(d));
    expectWalkEqualsHalfList(d, x, nReal, 0.06, "cloud " + std::to_string(d) + "D");
    const std::vector<double> l = lattice(d, d == 2 ? 40 : 14, 0.01);
    const Index nl = static_cast<Index>(l.size()) / d;
    expectWalkEqualsHalfList(d, l, nl - nl / 10, 0.02, "lattice " + std::to_string(d) + "D");
  }
}

TEST(CellWalk, BlocksCoverEveryReachedParticleAndTheScatterAddsEachPairOnce) {
  const int d = 3;
  const Index nReal = 4000, nTotal = 4300;
  const std::vector<double> x = cloud(d, nTotal, 0.5, 99u);
  const double radius = 0.05;
  NeighbourSearch search;
  search.sortCells(x.data(), d, nTotal, radius);
  const CellWalk<3> walk(search.grid(), x.data(), radius);
  // Expected sums from a full list: c(a, b) is what b gives to a (small integers: exact sums).
  NeighbourSearch fs;
  NeighbourList full;
  fs.build(x.data(), d, nReal, nTotal, radius, full);
  auto c = [](Index a, Index b) { return static_cast<double>((a * 7 + b * 13) % 1000 + 1); };
  const int width = 2;
  std::vector<double> expect(static_cast<size_t>(nReal * width), 0.0);
  for (Index i = 0; i < nReal; ++i)
    for (auto k = full.offset[i]; k < full.offset[i + 1]; ++k) {
      expect[static_cast<size_t>(i * width)] += c(i, full.index[static_cast<size_t>(k)]);
      expect[static_cast<size_t>(i * width + 1)] += 1.0;
    }
  const int saved = omp_get_max_threads();
  for (int threads : {1, 2, 3, 5}) {
    std::vector<Index> blocks, spill;
    CellWalkScratch scratch;
    cellWalkBlocks(search.grid(), d, radius, nReal, threads, blocks, spill, scratch);
    ASSERT_EQ(blocks.size(), static_cast<size_t>(threads) + 1);
    ASSERT_EQ(blocks.front(), 0);
    ASSERT_EQ(blocks.back(), nReal);
    Index largestSpill = 0;
    for (int t = 0; t < threads; ++t) {
      ASSERT_LE(blocks[static_cast<size_t>(t)], blocks[static_cast<size_t>(t) + 1]);
      Index reached = blocks[static_cast<size_t>(t) + 1];
      for (Index i = blocks[static_cast<size_t>(t)]; i < blocks[static_cast<size_t>(t) + 1]; ++i)
        walk.row(i, [&](Index j) { if (j < nReal) reached = std::max(reached, j + 1); });
      EXPECT_GE(spill[static_cast<size_t>(t)], reached) << threads << " threads, block " << t;
      largestSpill = std::max(largestSpill, spill[static_cast<size_t>(t)] - blocks[static_cast<size_t>(t) + 1]);
    }
    if (threads > 1) {
      // Balanced: no block holds more than twice its share of the rows (uniform cloud).
      for (int t = 0; t < threads; ++t)
        EXPECT_LT(blocks[static_cast<size_t>(t) + 1] - blocks[static_cast<size_t>(t)], 2 * nReal / threads);
    }
    omp_set_num_threads(threads);
    PairScatter scatter;
    scatter.layoutBlocks(blocks, spill, nReal, width);
    scatter.use(width);
    std::vector<double> own(static_cast<size_t>(nReal * width), -1.0);
    double* o = own.data();
#pragma omp parallel num_threads(scatter.threads())
    {
      scatter.forBlocks([&](int t) {
        scatter.zero(t, o);
        for (Index i = scatter.begin(t); i < scatter.end(t); ++i)
          walk.row(i, [&](Index j) {
            o[i * width] += c(i, j);
            o[i * width + 1] += 1.0;
            if (j < nReal) {
              double* tj = scatter.at(t, o, j);
              tj[0] += c(j, i);
              tj[1] += 1.0;
            }
          });
      });
#pragma omp barrier
      scatter.forBlocks([&](int t) { scatter.reduce(t, o); });
    }
    omp_set_num_threads(saved);
    EXPECT_TRUE(own == expect) << threads << " threads";
    std::printf("%d threads: largest spill %lld rows of %lld\n", threads,
                static_cast<long long>(largestSpill), static_cast<long long>(nReal));
  }
}

namespace {

// A 2D dam break (no XSPH: the fluid-fluid pairs take the vectorised block).
std::string damBreak2D(const std::string& list) {
  return R"(
dimension: 2
domain: {lo: [-0.03, -0.03], hi: [0.83, 0.43]}
spacing: 0.01
h_over_dx: 1.3
kernel: wendland_c2
integrator: leapfrog
end_time: 1.0
max_steps: 150
time_step: {adaptive: true, cfl: 1.0}
output: {every_steps: 100000}
neighbour_list: )" + list + R"(
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 20, viscosity: 1.0e-3}
  - {name: tank, model: wall, density: 1000}
geometry:
  - {shape: box, lo: [-0.03, -0.03], hi: [0.83, 0.43], material: tank}
  - {shape: box, lo: [0.0, 0.0], hi: [0.8, 0.43], material: none}
  - {shape: box, lo: [0.0, 0.0], hi: [0.2, 0.3], material: water}
fluid:
  gravity: [0, -9.81]
  artificial_viscosity: 0.1
  density_diffusion: 0.1
)";
}

// A water column moving across the periodic face of a 2D channel, with XSPH (scalar pair path).
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
  xsph: 0.3
)";
}

// Case A of docs/performance.md (DualSPHysics 01_DamBreak settings) at dx = 3 cm.
std::string caseA(const std::string& list) {
  return R"(
dimension: 3
domain: {lo: [-0.09, -0.09, -0.09], hi: [1.69, 0.75, 0.49]}
spacing: 0.03
h_over_dx: 1.7320508
kernel: cubic_spline
integrator: verlet
end_time: 1.0
max_steps: 40
time_step: {adaptive: true, cfl: 0.8}
output: {every_steps: 100000}
neighbour_list: )" + list + R"(
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 33.7337, viscosity: 0.0, eos: tait, tait_gamma: 7}
  - {name: tank, model: wall, density: 1000}
geometry:
  - {shape: box, lo: [-0.09, -0.09, -0.09], hi: [1.69, 0.75, 0.40], material: tank}
  - {shape: box, lo: [0.0, 0.0, 0.0], hi: [1.60, 0.66, 0.40], material: none}
  - {shape: box, lo: [0.0, 0.0, 0.0], hi: [0.42, 0.66, 0.30], material: water}
fluid:
  gravity: [0, 0, -9.81]
  artificial_viscosity: 0.1
  density_diffusion: 0.1
  hydrostatic_level: 0.30
)";
}

std::vector<Index> rowsById(const Simulation& s) {
  std::vector<Index> at(static_cast<size_t>(s.store.realCount()));
  const std::int32_t* id = s.store.data(s.store.id());
  for (Index i = 0; i < s.store.realCount(); ++i) at[static_cast<size_t>(id[i])] = i;
  return at;
}

struct Compared {
  double relative = 1.0;  // largest position difference / largest coordinate
  double moved = 0.0;     // largest displacement since the start, in dx
};

Compared runBoth(const std::string& halfText, const std::string& cellsText, const std::string& name,
                 int threads, double spacing) {
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-cell-walk" / name;
  fsys::remove_all(dir);
  fsys::create_directories(dir);
  RunOptions o;
  o.handleSignals = false;
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  Scene half = loadSceneText(halfText, (dir / "half.yaml").string());
  EXPECT_TRUE(half.sim->halfNeighbourList);
  EXPECT_FALSE(half.sim->cellWalk);
  const auto id0 = rowsById(*half.sim);
  const int d = half.sim->dimension();
  std::vector<double> x0(id0.size() * static_cast<size_t>(d));
  for (size_t k = 0; k < id0.size(); ++k)
    for (int c = 0; c < d; ++c)
      x0[k * static_cast<size_t>(d) + c] = half.sim->store.data(half.sim->store.position())[id0[k] * d + c];
  o.outDir = (dir / "half").string();
  const RunStatus sh = runScene(half, o).status;
  omp_set_num_threads(threads);
  Scene cells = loadSceneText(cellsText, (dir / "cells.yaml").string());
  EXPECT_TRUE(cells.sim->cellWalk);
  o.outDir = (dir / "cells").string();
  const RunStatus sc = runScene(cells, o).status;
  omp_set_num_threads(saved);
  Compared r;
  EXPECT_EQ(sh, RunStatus::Finished);
  EXPECT_EQ(sc, RunStatus::Finished);
  if (sh != RunStatus::Finished || sc != RunStatus::Finished) return r;
  EXPECT_EQ(half.sim->step, cells.sim->step);
  EXPECT_EQ(cells.sim->neighbours.pairCount(), 0);  // no stored list
  const auto ia = rowsById(*half.sim), ib = rowsById(*cells.sim);
  const double* xa = half.sim->store.data(half.sim->store.position());
  const double* xb = cells.sim->store.data(cells.sim->store.position());
  double diff = 0.0, extent = 0.0;
  for (size_t k = 0; k < ia.size(); ++k) {
    double m2 = 0.0;
    for (int c = 0; c < d; ++c) {
      diff = std::max(diff, std::abs(xa[ia[k] * d + c] - xb[ib[k] * d + c]));
      extent = std::max(extent, std::abs(xa[ia[k] * d + c]));
      const double m = xa[ia[k] * d + c] - x0[k * static_cast<size_t>(d) + c];
      m2 += m * m;
    }
    r.moved = std::max(r.moved, std::sqrt(m2) / spacing);
  }
  r.relative = diff / extent;
  std::printf("%s, walk on %d threads against the half list on 1: %lld steps, positions differ "
              "by %.3g of the largest coordinate; largest displacement %.3g dx\n",
              name.c_str(), threads, static_cast<long long>(cells.sim->step), r.relative, r.moved);
  return r;
}

}  // namespace

TEST(CellWalk, DamBreak2DEqualsTheHalfListRunAt1And3Threads) {
  const Compared one = runBoth(damBreak2D("half"), damBreak2D("cells"), "dam2d_1", 1, 0.01);
  EXPECT_GT(one.moved, 0.5);  // the flow moved: a lost pair would show
  EXPECT_EQ(one.relative, 0.0);  // same pairs in the same order: the same bits
  const Compared three = runBoth(damBreak2D("half"), damBreak2D("cells"), "dam2d_3", 3, 0.01);
  EXPECT_LT(three.relative, 1e-12);
}

TEST(CellWalk, PeriodicCollapseEqualsTheHalfListRun) {
  const Compared three =
      runBoth(periodicCollapse("half"), periodicCollapse("cells"), "periodic_3", 3, 0.01);
  EXPECT_GT(three.moved, 0.5);
  EXPECT_LT(three.relative, 1e-12);
}

TEST(CellWalk, CaseA3DEqualsTheHalfListRun) {
  const Compared three = runBoth(caseA("half"), caseA("cells"), "caseA_3", 3, 0.03);
  EXPECT_GT(three.moved, 0.03);
  EXPECT_LT(three.relative, 1e-12);
}

TEST(CellWalk, SceneKeyAndMemoryReport) {
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-cell-walk";
  fsys::create_directories(dir);
  // With a skin: refused, naming the file and key.
  {
    std::string t = damBreak2D("cells");
    t.replace(t.find("neighbour_list: cells"), 21, "neighbour_list: cells\nneighbour_skin: 0.3");
    try {
      loadSceneText(t, (dir / "cells_skin.yaml").string());
      FAIL() << "neighbour_list: cells with a skin was accepted";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("cells_skin.yaml"), std::string::npos) << m;
      EXPECT_NE(m.find("neighbour_skin"), std::string::npos) << m;
    }
  }
  // With surface tension (the fluid's CSF loops gather over a full list): refused naming it.
  try {
    loadSceneText(damBreak2D("cells") + "  surface_tension: 0.07\n", (dir / "cells_st.yaml").string());
    FAIL() << "neighbour_list: cells with surface tension was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("neighbour_list: cells"), std::string::npos) << m;
    EXPECT_NE(m.find("'fluid'"), std::string::npos) << m;
  }
  // The report after a step: no list, the search's cells measured.
  Scene s = loadSceneText(damBreak2D("cells"), (dir / "cells_mem.yaml").string());
  s.sim->evaluateRates();
  double list = -1.0, search = -1.0;
  for (const auto& l : memoryReport(*s.sim, 0, 0.0).lines) {
    if (l.what == "neighbour list") list = l.bytesPerParticle;
    if (l.what == "neighbour search") search = l.bytesPerParticle;
  }
  EXPECT_EQ(list, 0.0);
  EXPECT_GT(search, 8.0 * 2);  // at least the sorted positions
  EXPECT_EQ(s.sim->neighbours.offset.capacity(), 0u);
}
