// Unit tests of the pair-class filter of the neighbour lists (issue 17; libcore/phases.hpp
// PairMask, Module::neighbourPairsRead, Simulation::neighbourPairMask, PairFilter in
// libcore/neighbour_search.hpp; docs/performance.md "Pair classes no loop reads"):
//  - a filtered search keeps exactly the unfiltered search's pairs of the kept classes, row by
//    row in the same order (full and half lists, ghosts, Verlet candidates and their filter);
//    a row whose phase keeps no class is empty; an unknown phase turns the filter off;
//  - a fluid-and-wall scene keeps every neighbour of a fluid row and every fluid neighbour of a
//    wall row, and no wall-wall pair; a module without a declaration keeps every pair;
//  - runs with the filter equal the runs that keep every pair bit for bit (a dam break on the
//    full and the half list, a rigid body in water with walls);
//  - the comparison sees a left-out class that a module reads: a fluid row's wall neighbours,
//    or a wall row's fluid neighbours (read by the wall pressure extrapolation).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "libcore/neighbour_search.hpp"
#include "libcore/runner.hpp"
#include "libcore/scene.hpp"
#include "libcore/simulation.hpp"

using namespace poresph;
namespace fsys = std::filesystem;

namespace {

using Rows = std::vector<std::vector<Index>>;

Rows rowsOf(const NeighbourList& l) {
  Rows r(static_cast<size_t>(l.realCount()));
  for (Index i = 0; i < l.realCount(); ++i)
    for (auto k = l.offset[i]; k < l.offset[i + 1]; ++k)
      r[static_cast<size_t>(i)].push_back(static_cast<Index>(l.index[static_cast<size_t>(k)]));
  return r;
}

// Each row sorted: a list filtered from Verlet candidates holds the pairs of a fresh search in
// the candidates' order (libcore/neighbour_search.hpp VerletNeighbours).
Rows sorted(Rows r) {
  for (auto& row : r) std::sort(row.begin(), row.end());
  return r;
}

// The rows of `all` with only the pairs whose bit phase[i] * kPhaseCount + phase[j] is in mask.
Rows restricted(const Rows& all, const std::vector<std::int32_t>& ph, PairMask mask) {
  Rows r(all.size());
  for (size_t i = 0; i < all.size(); ++i)
    for (Index j : all[i])
      if ((mask >> (ph[i] * kPhaseCount + ph[static_cast<size_t>(j)])) & 1u) r[i].push_back(j);
  return r;
}

std::vector<double> cloud(int d, Index n, double box, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, box);
  std::vector<double> x(static_cast<size_t>(n * d));
  for (double& c : x) c = u(rng);
  return x;
}

// 2D dam break with walls (fluid and wall phases), 0.2 x 0.3 m of water, dx 1 cm.
std::string damBreak(const std::string& list, int steps) {
  return R"(
dimension: 2
domain: {lo: [-0.03, -0.03], hi: [0.83, 0.43]}
spacing: 0.01
h_over_dx: 1.3
kernel: wendland_c2
integrator: leapfrog
end_time: 1.0
max_steps: )" + std::to_string(steps) + R"(
time_step: {adaptive: true, cfl: 1.0}
output: {every_steps: 100000}
neighbour_skin: 0.3
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
  xsph: 0.3
)";
}

// A rigid block falling into water in a walled tank: fluid, wall and rigid phases (the rigid
// module reads every class with a rigid side, the fluid every class with a fluid side).
std::string rigidInWater(int steps) {
  return R"(
dimension: 2
domain: {lo: [-0.03, -0.03], hi: [0.33, 0.33]}
spacing: 0.01
h_over_dx: 1.3
kernel: wendland_c2
integrator: leapfrog
end_time: 1.0
max_steps: )" + std::to_string(steps) + R"(
time_step: {adaptive: true, cfl: 0.5}
output: {every_steps: 100000}
neighbour_skin: 0.3
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 20, viscosity: 1.0e-3}
  - {name: tank, model: wall, density: 1000}
  - {name: block, model: rigid, density: 1500}
geometry:
  - {shape: box, lo: [-0.03, -0.03], hi: [0.33, 0.33], material: tank}
  - {shape: box, lo: [0.0, 0.0], hi: [0.3, 0.33], material: none}
  - {shape: box, lo: [0.0, 0.0], hi: [0.3, 0.15], material: water}
  - {shape: box, lo: [0.1, 0.16], hi: [0.18, 0.22], material: block}
fluid:
  gravity: [0, -9.81]
rigid:
  gravity: [0, -9.81]
)";
}

fsys::path testDir(const std::string& name) {
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-neighbour-pair-classes" / name;
  fsys::remove_all(dir);
  fsys::create_directories(dir);
  return dir;
}

// Runs a scene to its max_steps; `keepAll`: every pair kept (extraNeighbourPairs).
Scene runTo(const std::string& text, const std::string& name, bool keepAll) {
  const fsys::path dir = testDir(name);
  Scene s = loadSceneText(text, (dir / "scene.yaml").string());
  if (keepAll) s.sim->extraNeighbourPairs = kAllPairClasses;
  RunOptions o;
  o.handleSignals = false;
  o.outDir = (dir / "out").string();
  EXPECT_EQ(runScene(s, o).status, RunStatus::Finished) << name;
  return s;
}

// Number of real fields (and int fields) of the real particles that differ in any bit.
int differingFields(const Simulation& a, const Simulation& b, std::string* first) {
  const ParticleStore& p = a.store;
  const ParticleStore& q = b.store;
  if (p.realCount() != q.realCount()) return -1;
  int differ = 0;
  for (const FieldSpec& f : p.fields()) {
    if (!q.has(f.name)) continue;
    const size_t count = static_cast<size_t>(p.realCount() * f.components);
    const bool same =
        f.type == FieldType::Real
            ? std::memcmp(p.data(p.real(f.name)), q.data(q.real(f.name)),
                          count * sizeof(double)) == 0
            : std::memcmp(p.data(p.integer(f.name)), q.data(q.integer(f.name)),
                          count * sizeof(std::int32_t)) == 0;
    if (!same) {
      if (differ == 0 && first) *first = f.name;
      ++differ;
    }
  }
  return differ;
}

// A module that keeps the default declaration (it may read every class).
class ReadsEverything : public Module {
 public:
  std::string name() const override { return "reads_everything"; }
  std::vector<std::string> materialModels() const override { return {}; }
  void configure(Simulation&, const std::vector<const Material*>&, const ParameterSet*) override {}
};

}  // namespace

TEST(NeighbourPairClasses, MaskBits) {
  EXPECT_EQ(kAllPairClasses, 0xFFFFu);
  EXPECT_EQ(pairClassBits(kPhaseFluid, kPhaseWall),
            (1u << (kPhaseFluid * kPhaseCount + kPhaseWall)) |
                (1u << (kPhaseWall * kPhaseCount + kPhaseFluid)));
  EXPECT_EQ(pairClassBits(kPhaseSolid, kPhaseSolid),
            1u << (kPhaseSolid * kPhaseCount + kPhaseSolid));
  PairMask all = 0;
  for (int p = 0; p < kPhaseCount; ++p) all |= pairClassesWith(p);
  EXPECT_EQ(all, kAllPairClasses);
  EXPECT_EQ(pairClassesWith(kPhaseFluid) & pairClassBits(kPhaseWall, kPhaseWall), 0u);
}

TEST(NeighbourPairClasses, SearchKeepsExactlyTheClassesOfTheMask) {
  const std::vector<PairMask> masks = {
      pairClassesWith(kPhaseFluid),
      pairClassesWith(kPhaseFluid) | pairClassBits(kPhaseSolid, kPhaseSolid),
      pairClassBits(kPhaseSolid, kPhaseWall),  // the fluid and rigid rows empty
      // one direction only: the fluid rows' wall neighbours
      pairClassBits(kPhaseFluid, kPhaseWall) & ~(1u << (kPhaseWall * kPhaseCount + kPhaseFluid)),
      0u};
  for (int d = 2; d <= 3; ++d) {
    const Index nReal = d == 2 ? 2000 : 3000, nTotal = nReal + 400;  // the last 400 as ghosts
    const std::vector<double> x =
        cloud(d, nTotal, d == 2 ? 1.0 : 0.5, 11u + static_cast<unsigned>(d));
    std::vector<std::int32_t> ph(static_cast<size_t>(nTotal));
    std::mt19937 rng(5u);
    for (auto& p : ph) p = static_cast<std::int32_t>(rng() % kPhaseCount);
    const double radius = 0.06;
    for (bool half : {false, true}) {
      NeighbourSearch search;
      NeighbourList all, some;
      search.build(x.data(), d, nReal, nTotal, radius, all, half);
      const Rows allRows = rowsOf(all);
      for (PairMask m : masks) {
        search.build(x.data(), d, nReal, nTotal, radius, some, half, PairFilter{ph.data(), m});
        EXPECT_EQ(some.half, half);
        EXPECT_EQ(rowsOf(some), restricted(allRows, ph, m)) << "dimension " << d << " half " << half
                                                             << " mask " << m;
      }
      // The Verlet candidates keep the mask, and so does every list filtered from them.
      const PairMask m = masks[1];
      VerletNeighbours verlet;
      verlet.rebuild(search, x.data(), d, nReal, nTotal, radius, 0.3 * radius, half,
                     PairFilter{ph.data(), m});
      EXPECT_EQ(verlet.pairMask(), m);
      verlet.filter(x.data(), d, radius, some);
      EXPECT_EQ(sorted(rowsOf(some)), sorted(restricted(allRows, ph, m)))
          << "Verlet, dimension " << d;
      // Without the phases, or with every class, nothing is left out.
      search.build(x.data(), d, nReal, nTotal, radius, some, half, PairFilter{nullptr, m});
      EXPECT_EQ(rowsOf(some), allRows);
      search.build(x.data(), d, nReal, nTotal, radius, some, half,
                   PairFilter{ph.data(), kAllPairClasses});
      EXPECT_EQ(rowsOf(some), allRows);
      // A particle of an unknown phase (here a ghost): every pair kept.
      std::vector<std::int32_t> odd = ph;
      odd.back() = kPhaseUnset;
      search.build(x.data(), d, nReal, nTotal, radius, some, half, PairFilter{odd.data(), m});
      EXPECT_EQ(rowsOf(some), allRows);
    }
  }
}

TEST(NeighbourPairClasses, FluidRowsKeepEveryNeighbourAndWallRowsTheirFluidOnes) {
  for (const char* list : {"full", "half"}) {
    const fsys::path dir = testDir(std::string("rows_") + list);
    Scene s = loadSceneText(damBreak(list, 1), (dir / "scene.yaml").string());
    Simulation& sim = *s.sim;
    EXPECT_EQ(sim.neighbourPairMask(), pairClassesWith(kPhaseFluid));
    sim.updateNeighbours();
    const Index n = sim.store.realCount();
    const std::int32_t* ph = sim.store.data(sim.store.phase());
    // The unfiltered exact list of the same positions.
    NeighbourSearch search;
    NeighbourList ref;
    search.build(sim.store.data(sim.store.position()), 2, n, sim.store.size(), sim.kernel.support(),
                 ref, sim.halfNeighbourList);
    const Rows all = sorted(rowsOf(ref)), kept = sorted(rowsOf(sim.neighbours));
    std::int64_t fluidWall = 0, wallFluid = 0, wallWall = 0, leftOut = 0;
    for (Index i = 0; i < n; ++i) {
      std::vector<Index> want;
      for (Index j : all[static_cast<size_t>(i)]) {
        const bool fi = ph[i] == kPhaseFluid, fj = ph[j] == kPhaseFluid;
        if (fi || fj) want.push_back(j);
        else ++leftOut;
        if (fi && !fj) ++fluidWall;
        if (!fi && fj) ++wallFluid;
      }
      for (Index j : kept[static_cast<size_t>(i)])
        if (ph[i] != kPhaseFluid && ph[j] != kPhaseFluid) ++wallWall;
      // A fluid row keeps all its neighbours, walls included; a wall row its fluid ones.
      ASSERT_EQ(kept[static_cast<size_t>(i)], want) << list << " row " << i << " phase " << ph[i];
    }
    EXPECT_EQ(wallWall, 0);
    EXPECT_GT(fluidWall + wallFluid, 0) << "the scene has fluid-wall pairs";
    EXPECT_GT(leftOut, sim.neighbours.pairCount() / 10) << "the walls' own pairs are left out";
    std::printf("%s list: %lld pairs kept, %lld wall-wall pairs left out\n", list,
                static_cast<long long>(sim.neighbours.pairCount()),
                static_cast<long long>(leftOut));
  }
}

TEST(NeighbourPairClasses, AModuleWithoutADeclarationKeepsEveryPair) {
  // A module keeping the default (every class), or none at all: nothing is left out; the
  // classes of a reader outside the modules (extraNeighbourPairs) are added, and a change of
  // the mask searches the candidates again.
  Simulation empty(2);
  EXPECT_EQ(empty.neighbourPairMask(), kAllPairClasses);
  const fsys::path dir = testDir("declaration");
  Scene s = loadSceneText(damBreak("full", 1), (dir / "scene.yaml").string());
  s.sim->extraNeighbourPairs = pairClassBits(kPhaseWall, kPhaseWall);
  EXPECT_EQ(s.sim->neighbourPairMask(),
            pairClassesWith(kPhaseFluid) | pairClassBits(kPhaseWall, kPhaseWall));
  s.sim->updateNeighbours();
  const Index before = s.sim->neighbours.pairCount();
  s.sim->extraNeighbourPairs = 0;  // a new mask: the candidates are searched again
  const Index builds = s.sim->neighbourBuilds();
  s.sim->updateNeighbours();
  EXPECT_EQ(s.sim->neighbourBuilds(), builds + 1);
  const Index fluidOnly = s.sim->neighbours.pairCount();
  EXPECT_LT(fluidOnly, before);
  s.sim->addModule(std::make_unique<ReadsEverything>());
  EXPECT_EQ(s.sim->neighbourPairMask(), kAllPairClasses);
  s.sim->updateNeighbours();
  EXPECT_EQ(s.sim->neighbourBuilds(), builds + 2);
  NeighbourSearch search;
  NeighbourList ref;
  search.build(s.sim->store.data(s.sim->store.position()), 2, s.sim->store.realCount(),
               s.sim->store.size(), s.sim->kernel.support(), ref, s.sim->halfNeighbourList);
  EXPECT_EQ(sorted(rowsOf(s.sim->neighbours)), sorted(rowsOf(ref)));
}

TEST(NeighbourPairClasses, DamBreakEqualsTheRunKeepingEveryPairBitForBit) {
  for (const char* list : {"full", "half"}) {
    Scene a = runTo(damBreak(list, 40), std::string("dam_") + list, false);
    Scene b = runTo(damBreak(list, 40), std::string("dam_all_") + list, true);
    ASSERT_EQ(a.sim->step, 40);
    ASSERT_EQ(b.sim->step, 40);
    EXPECT_LT(a.sim->neighbours.pairCount(), b.sim->neighbours.pairCount()) << list;
    std::string first;
    EXPECT_EQ(differingFields(*a.sim, *b.sim, &first), 0) << list << ": first field " << first;
    EXPECT_EQ(a.sim->time, b.sim->time) << list;
  }
}

TEST(NeighbourPairClasses, RigidBodyInWaterEqualsTheRunKeepingEveryPairBitForBit) {
  Scene a = runTo(rigidInWater(30), "rigid", false);
  Scene b = runTo(rigidInWater(30), "rigid_all", true);
  EXPECT_EQ(a.sim->neighbourPairMask(),
            pairClassesWith(kPhaseFluid) | pairClassesWith(kPhaseRigid));
  EXPECT_LT(a.sim->neighbours.pairCount(), b.sim->neighbours.pairCount());
  std::string first;
  EXPECT_EQ(differingFields(*a.sim, *b.sim, &first), 0) << "first field " << first;
  EXPECT_EQ(a.sim->time, b.sim->time);
}

TEST(NeighbourPairClasses, ALeftOutClassThatAModuleReadsIsSeen) {
  // One evaluation of the dam break after 30 steps on its own lists, then on lists that leave
  // out a class the fluid reads: a fluid row's wall neighbours (the boundary force), or a wall
  // row's fluid neighbours (the wall pressure extrapolation). The rates must change.
  Scene a = runTo(damBreak("full", 30), "left_out_a", false);
  Simulation& sim = *a.sim;
  sim.updateNeighbours();
  const NeighbourList good = sim.neighbours;
  sim.evaluateRatesOnTheList();
  const std::vector<double> acc(sim.store.data(sim.acceleration),
                                sim.store.data(sim.acceleration) + sim.store.realCount() * 2);
  const std::vector<double> p(sim.store.data(sim.store.real("pressure")),
                              sim.store.data(sim.store.real("pressure")) + sim.store.realCount());
  const PairMask fluidRowsWall = 1u << (kPhaseFluid * kPhaseCount + kPhaseWall);
  const PairMask wallRowsFluid = 1u << (kPhaseWall * kPhaseCount + kPhaseFluid);
  for (PairMask drop : {fluidRowsWall, wallRowsFluid}) {
    const PairFilter keep{sim.store.data(sim.store.phase()), pairClassesWith(kPhaseFluid) & ~drop};
    sim.search.build(sim.store.data(sim.store.position()), 2, sim.store.realCount(),
                     sim.store.size(), sim.kernel.support(), sim.neighbours, false, keep);
    EXPECT_LT(sim.neighbours.pairCount(), good.pairCount());
    sim.evaluateRatesOnTheList();
    double da = 0.0, dp = 0.0;
    for (size_t k = 0; k < acc.size(); ++k)
      da = std::max(da, std::abs(sim.store.data(sim.acceleration)[k] - acc[k]));
    for (size_t k = 0; k < p.size(); ++k)
      dp = std::max(dp, std::abs(sim.store.data(sim.store.real("pressure"))[k] - p[k]));
    std::printf("left out bit %u: accelerations change by %.3g m/s^2, pressures by %.3g Pa\n", drop,
                da, dp);
    EXPECT_GT(da, 1e-3) << "bit " << drop;
    if (drop == wallRowsFluid) {
      EXPECT_GT(dp, 1.0) << "the walls' pressure";
    }
  }
}
