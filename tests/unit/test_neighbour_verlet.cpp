// Unit tests of the Verlet (skin) neighbour list (libcore/neighbour_search.hpp, VerletNeighbours)
// and its use by Simulation::updateNeighbours (scene key neighbour_skin):
//  - the list filtered from the candidates equals a fresh search's list, pair for pair, over
//    random motions in 1D/2D/3D (steps with and without a rebuild both happen);
//  - the rebuild criterion is exact: a displacement just below skin/2 keeps the candidates (and
//    no pair is then missing), skin/2 itself asks for a rebuild, as does a change of the
//    particle count, radius or skin;
//  - a 2D dam break run with a skin equals the run without one to round-off (the lists hold the
//    same pairs; only the order of a row may differ), and the skin did save searches.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "libcore/neighbour_search.hpp"
#include "libcore/runner.hpp"
#include "libcore/scene.hpp"

using namespace poresph;
namespace fsys = std::filesystem;

namespace {

std::vector<std::vector<Index>> rows(const NeighbourList& l) {
  std::vector<std::vector<Index>> r(static_cast<size_t>(l.realCount()));
  for (Index i = 0; i < l.realCount(); ++i) {
    for (auto k = l.offset[i]; k < l.offset[i + 1]; ++k)
      r[static_cast<size_t>(i)].push_back(l.index[static_cast<size_t>(k)]);
    std::sort(r[static_cast<size_t>(i)].begin(), r[static_cast<size_t>(i)].end());
  }
  return r;
}

void randomMotion(int d) {
  std::mt19937 rng(12345u + static_cast<unsigned>(d));
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Index n = d == 1 ? 400 : (d == 2 ? 1500 : 3000);
  const double box = d == 1 ? 4.0 : (d == 2 ? 1.0 : 0.6);
  const double radius = 0.08, skin = 0.02;
  std::vector<double> x(static_cast<size_t>(n * d));
  for (double& c : x) c = box * u(rng);
  NeighbourSearch search, fresh;
  VerletNeighbours verlet;
  NeighbourList exact, reference;
  ASSERT_FALSE(verlet.valid(x.data(), d, n, n, radius, skin));
  verlet.rebuild(search, x.data(), d, n, n, radius, skin);
  int reused = 0, rebuilt = 0;
  for (int step = 0; step < 40; ++step) {
    // Each particle moves by up to 0.003 per step in a random direction: about half the steps
    // keep the candidates, the others ask for a rebuild.
    for (Index i = 0; i < n; ++i) {
      double dir[3] = {0, 0, 0}, len = 0.0;
      for (int a = 0; a < d; ++a) {
        dir[a] = u(rng) - 0.5;
        len += dir[a] * dir[a];
      }
      len = std::sqrt(len) + 1e-300;
      const double s = 0.003 * u(rng) / len;
      for (int a = 0; a < d; ++a) x[static_cast<size_t>(i * d + a)] += s * dir[a];
    }
    if (verlet.valid(x.data(), d, n, n, radius, skin)) {
      ++reused;
      EXPECT_LT(verlet.maxDisplacement(x.data(), d, n), 0.5 * skin);
    } else {
      ++rebuilt;
      EXPECT_GE(verlet.maxDisplacement(x.data(), d, n), 0.5 * skin * (1.0 - 1e-9));
      verlet.rebuild(search, x.data(), d, n, n, radius, skin);
    }
    verlet.filter(x.data(), d, radius, exact);
    fresh.build(x.data(), d, n, n, radius, reference);
    ASSERT_EQ(exact.pairCount(), reference.pairCount()) << "step " << step;
    ASSERT_EQ(rows(exact), rows(reference)) << "step " << step;
  }
  EXPECT_GT(reused, 5);
  EXPECT_GT(rebuilt, 2);
  EXPECT_EQ(verlet.rebuildCount(), rebuilt + 1);
}

}  // namespace

TEST(VerletNeighbours, FilteredListEqualsAFreshSearch1D) { randomMotion(1); }
TEST(VerletNeighbours, FilteredListEqualsAFreshSearch2D) { randomMotion(2); }
TEST(VerletNeighbours, FilteredListEqualsAFreshSearch3D) { randomMotion(3); }

TEST(VerletNeighbours, RebuildCriterionIsExact) {
  // Two particles on x just outside the candidate radius (radius + skin), two far away.
  const double radius = 1.0, skin = 0.2;
  const double gap = radius + skin + 1e-9;
  std::vector<double> x = {0.0, 0.0, gap, 0.0, 10.0, 10.0, 20.0, 20.0};
  const Index n = 4;
  NeighbourSearch search;
  VerletNeighbours verlet;
  NeighbourList list;
  verlet.rebuild(search, x.data(), 2, n, n, radius, skin);
  EXPECT_EQ(verlet.candidates().pairCount(), 0);
  // Both move towards each other by just under skin/2: still valid, and still no pair (their
  // distance stays above the radius: the criterion never loses a pair).
  const double almost = 0.5 * skin * (1.0 - 4e-9);
  x[0] += almost;
  x[2] -= almost;
  EXPECT_TRUE(verlet.valid(x.data(), 2, n, n, radius, skin));
  verlet.filter(x.data(), 2, radius, list);
  EXPECT_EQ(list.pairCount(), 0);
  EXPECT_GT(x[2] - x[0], radius);
  // One of them reaches skin/2: a rebuild is due.
  x[2] = gap - 0.5 * skin;
  EXPECT_FALSE(verlet.valid(x.data(), 2, n, n, radius, skin));
  x[2] = gap - almost;
  EXPECT_TRUE(verlet.valid(x.data(), 2, n, n, radius, skin));
  // Any other radius, skin or particle count: a rebuild is due.
  EXPECT_FALSE(verlet.valid(x.data(), 2, n, n, radius * 1.01, skin));
  EXPECT_FALSE(verlet.valid(x.data(), 2, n, n, radius, skin * 0.5));
  EXPECT_FALSE(verlet.valid(x.data(), 2, n - 1, n - 1, radius, skin));
  EXPECT_FALSE(verlet.valid(x.data(), 2, n, n + 1, radius, skin));
  // A non-finite position: a rebuild is due (the search then reports it).
  x[5] = std::nan("");
  EXPECT_FALSE(verlet.valid(x.data(), 2, n, n, radius, skin));
  verlet.invalidate();
  x[5] = 10.0;
  EXPECT_FALSE(verlet.valid(x.data(), 2, n, n, radius, skin));
}

namespace {

// A small 2D dam break (water column collapsing in a tank, walls by the fluid module).
std::string damBreak(double skin) {
  return std::string(R"(
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
neighbour_skin: )") + std::to_string(skin) + R"(
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
)";
}

std::vector<Index> rowsById(const Simulation& s) {
  std::vector<Index> at(static_cast<size_t>(s.store.realCount()));
  const std::int32_t* id = s.store.data(s.store.id());
  for (Index i = 0; i < s.store.realCount(); ++i) at[static_cast<size_t>(id[i])] = i;
  return at;
}

}  // namespace

TEST(VerletNeighbours, DamBreakWithASkinEqualsTheRunWithout) {
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-neighbour-verlet";
  fsys::remove_all(dir);
  fsys::create_directories(dir);
  RunOptions o;
  o.handleSignals = false;
  Scene plain = loadSceneText(damBreak(0.0), (dir / "plain.yaml").string());
  o.outDir = (dir / "plain").string();
  ASSERT_EQ(runScene(plain, o).status, RunStatus::Finished);
  Scene skinned = loadSceneText(damBreak(0.3), (dir / "skin.yaml").string());
  o.outDir = (dir / "skin").string();
  ASSERT_EQ(runScene(skinned, o).status, RunStatus::Finished);
  const Simulation& a = *plain.sim;
  const Simulation& b = *skinned.sim;
  ASSERT_EQ(a.step, b.step);
  EXPECT_EQ(a.verlet.rebuildCount(), 0);
  // The skin saved searches (the column is still accelerating: ~1 search per few steps).
  EXPECT_GT(b.verlet.rebuildCount(), 1);
  EXPECT_LT(b.verlet.rebuildCount(), b.step / 2);
  EXPECT_EQ(b.neighbourBuilds(), b.verlet.rebuildCount());
  const auto ia = rowsById(a), ib = rowsById(b);
  const int d = a.dimension();
  const double* xa = a.store.data(a.store.position());
  const double* xb = b.store.data(b.store.position());
  const double* va = a.store.data(a.store.velocity());
  const double* vb = b.store.data(b.store.velocity());
  double dx = 0.0, dv = 0.0, vmax = 0.0, moved = 0.0;
  for (size_t k = 0; k < ia.size(); ++k)
    for (int c = 0; c < d; ++c) {
      dx = std::max(dx, std::abs(xa[ia[k] * d + c] - xb[ib[k] * d + c]));
      dv = std::max(dv, std::abs(va[ia[k] * d + c] - vb[ib[k] * d + c]));
      vmax = std::max(vmax, std::abs(va[ia[k] * d + c]));
    }
  moved = vmax * a.time;
  std::printf("skin 0.3 dx: %lld searches in %lld steps; positions %.3g dx, velocities %.3g of "
              "vmax %.3g m/s\n",
              static_cast<long long>(b.verlet.rebuildCount()), static_cast<long long>(b.step),
              dx / a.spacing, dv / vmax, vmax);
  ASSERT_GT(moved, 0.5 * a.spacing);  // the flow moved: the test can see a lost pair
  EXPECT_LT(dx, 1e-10 * a.spacing);
  EXPECT_LT(dv, 1e-9 * vmax);
}
