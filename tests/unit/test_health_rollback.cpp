// The run loop's rollback copy (RollbackState, libcore/health.hpp): only the checkpoint and
// output fields are copied, constant fields follow their particles through a reorder, the copy
// is taken every `rollback_every` steps, and the scene key is checked.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <sstream>

#include "libcore/health.hpp"
#include "libcore/parameters.hpp"
#include "libcore/runner.hpp"
#include "libcore/scene.hpp"
#include "libcore/simulation.hpp"

using namespace poresph;

namespace {

struct Fields {
  RealField out, ckpt, none, constant;
  IntField intCkpt;
};

// A 2D simulation of n particles with one field of each kind, values tagged by particle id.
Fields fill(Simulation& sim, Index n) {
  ParticleStore& st = sim.store;
  Fields f;
  f.out = st.addReal("out", 2, kFieldOutput, "test");
  f.ckpt = st.addReal("ckpt", 1, kFieldCheckpoint, "test");
  f.none = st.addReal("scratch", 3, kFieldNone, "test");
  f.constant = st.addReal("constant", 4, kFieldCheckpoint | kFieldConstant, "test");
  f.intCkpt = st.addInt("int_ckpt", 2, kFieldCheckpoint, "test");
  st.addParticles(n);
  const std::int32_t* id = st.data(st.id());
  for (Index i = 0; i < n; ++i) {
    for (int q = 0; q < 2; ++q) st.data(f.out)[2 * i + q] = 10.0 * id[i] + q;
    st.data(f.ckpt)[i] = -1.0 * id[i];
    for (int q = 0; q < 3; ++q) st.data(f.none)[3 * i + q] = 7.0;
    for (int q = 0; q < 4; ++q) st.data(f.constant)[4 * i + q] = 100.0 * id[i] + q;
    for (int q = 0; q < 2; ++q) st.data(f.intCkpt)[2 * i + q] = 3 * id[i] + q;
    for (int q = 0; q < 2; ++q) st.data(st.position())[2 * i + q] = 0.5 * id[i] + q;
  }
  return f;
}

}  // namespace

TEST(Rollback, CopiesCheckpointAndOutputFieldsButNotScratchOrConstantOnes) {
  Simulation sim(2);
  const Fields f = fill(sim, 50);
  // Core fields: position, velocity (2 doubles each), mass, density (1 each), phase, material, id,
  // motion (ints) are all output or checkpoint; acceleration (2 doubles, output) too.
  const std::size_t core = (2 + 2 + 1 + 1 + 2) * 8 + 4 * 4;
  const std::size_t mine = 2 * 8 + 1 * 8 + 2 * 4;  // out, ckpt, int_ckpt
  EXPECT_EQ(RollbackState::bytesPerParticle(sim.store), core + mine);
  EXPECT_EQ(sim.store.bytesPerParticle(), core + mine + 3 * 8 + 4 * 8);

  RollbackState r;
  EXPECT_FALSE(r.restore(sim));  // nothing captured yet
  ASSERT_TRUE(r.capture(sim));
  EXPECT_EQ(r.bytes(), 50 * (core + mine));
  sim.time = 1.0;
  sim.step = 1;
  ParticleStore& st = sim.store;
  for (Index i = 0; i < 50; ++i) {
    st.data(f.out)[2 * i] = -5.0;
    st.data(f.ckpt)[i] = -5.0;
    st.data(f.none)[3 * i] = -5.0;
    st.data(f.intCkpt)[2 * i] = -5;
  }
  ASSERT_TRUE(r.restore(sim));
  EXPECT_EQ(sim.step, 0);
  EXPECT_EQ(sim.time, 0.0);
  const std::int32_t* id = st.data(st.id());
  for (Index i = 0; i < 50; ++i) {
    EXPECT_EQ(st.data(f.out)[2 * i], 10.0 * id[i]);
    EXPECT_EQ(st.data(f.ckpt)[i], -1.0 * id[i]);
    EXPECT_EQ(st.data(f.intCkpt)[2 * i], 3 * id[i]);
    EXPECT_EQ(st.data(f.none)[3 * i], -5.0);  // scratch is not copied: left as it was
  }
}

TEST(Rollback, AReorderAfterTheCopyIsUndoneSoConstantFieldsStayWithTheirParticles) {
  Simulation sim(2);
  const Fields f = fill(sim, 64);
  RollbackState r;
  ASSERT_TRUE(r.capture(sim));
  // A cell reorder during the failed step, then the copied fields change.
  std::vector<Index> order(64);
  std::iota(order.begin(), order.end(), Index{0});
  std::shuffle(order.begin(), order.end(), std::mt19937(7));
  sim.store.permute(order);
  ParticleStore& st = sim.store;
  for (Index i = 0; i < 64; ++i) st.data(f.ckpt)[i] = 1e9;
  ASSERT_TRUE(r.restore(sim));
  const std::int32_t* id = st.data(st.id());
  for (Index i = 0; i < 64; ++i) {
    EXPECT_EQ(id[i], i);  // the captured order (ids were 0..63 in order)
    EXPECT_EQ(st.data(f.ckpt)[i], -1.0 * id[i]);
    for (int q = 0; q < 4; ++q) EXPECT_EQ(st.data(f.constant)[4 * i + q], 100.0 * id[i] + q);
    EXPECT_EQ(st.data(st.position())[2 * i + 1], 0.5 * id[i] + 1);
  }
}

TEST(Rollback, EveryKStepsCopiesAtMultiplesOfKAndRestoresTheLastCopy) {
  Simulation sim(2);
  const Fields f = fill(sim, 10);
  RollbackState r(3);
  std::vector<Index> copied;
  for (Index s = 0; s <= 10; ++s) {
    sim.step = s;
    sim.time = 0.1 * static_cast<double>(s);
    sim.store.data(f.ckpt)[0] = static_cast<double>(s);
    if (r.capture(sim)) copied.push_back(s);
  }
  EXPECT_EQ(copied, (std::vector<Index>{0, 3, 6, 9}));
  ASSERT_TRUE(r.restore(sim));
  EXPECT_EQ(sim.step, 9);
  EXPECT_EQ(r.capturedStep(), 9);
  EXPECT_EQ(sim.store.data(f.ckpt)[0], 9.0);
}

TEST(Rollback, RollbackEveryIsAWholePositiveNumberOfSteps) {
  auto read = [](const std::string& yaml) {
    ParameterSet p(YAML::Load(yaml), "scene.yaml", "health");
    return readHealthLimits(&p);
  };
  EXPECT_EQ(readHealthLimits(nullptr).rollbackEvery, 1);
  EXPECT_EQ(read("{rollback_every: 20}").rollbackEvery, 20);
  for (const char* bad : {"{rollback_every: 0}", "{rollback_every: 2.5}", "{rollback_every: -3}"}) {
    try {
      read(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("rollback_every"), std::string::npos) << e.what();
    }
  }
}

namespace {

namespace fs = std::filesystem;

// A 2D water column whose sound speed is far too low for its height (tests/unit/test_health.cpp):
// the density-variation check stops it after some tens of steps.
std::string lowSoundSpeedColumn(const std::string& extra) {
  return R"(dimension: 2
domain: {lo: [-0.003, -0.003], hi: [0.023, 0.023]}
spacing: 0.001
kernel: wendland_c2
end_time: 0.5
time_step: {adaptive: true}
output: {every_time: 10.0}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 0.7, viscosity: 1.0e-3}
  - {name: steel, model: wall, density: 1000}
geometry:
  - {shape: box, lo: [-0.003, -0.003], hi: [0.023, 0.023], material: steel}
  - {shape: box, lo: [0.0, 0.0], hi: [0.02, 0.02], material: water}
fluid:
  gravity: [0, -9.81]
)" + extra;
}

Scene loadText(const std::string& name, const std::string& text) {
  const fs::path dir = fs::path(PORESPH_BINARY_DIR) / "tmp_test_health_rollback";
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return loadScene((dir / name).string());
}

RunResult runQuiet(Scene& s, const std::string& name) {
  // Reorder the store along the cells every 3 neighbour builds (default 50), so that reorders
  // fall between a copy and the failure.
  s.sim->reorderEvery = 3;
  RunOptions o;
  o.outDir = (fs::path(PORESPH_BINARY_DIR) / "tmp_test_health_rollback" / name).string();
  fs::remove_all(o.outDir);
  o.handleSignals = false;
  return runScene(s, o);
}

std::map<std::int32_t, std::vector<double>> positionsById(const Simulation& sim) {
  std::map<std::int32_t, std::vector<double>> m;
  const ParticleStore& st = sim.store;
  const int d = sim.dimension();
  for (Index i = 0; i < st.realCount(); ++i)
    m[st.data(st.id())[i]] = std::vector<double>(st.data(st.position()) + d * i,
                                                 st.data(st.position()) + d * (i + 1));
  return m;
}

}  // namespace

TEST(Rollback, AFailedRunWritesTheStateOfTheLastCopyExactly) {
  // rollback_every 1: the state before the failed step.
  Scene every = loadText("every.yaml", lowSoundSpeedColumn(""));
  const RunResult r1 = runQuiet(every, "every");
  ASSERT_EQ(r1.status, RunStatus::Failed) << r1.message;
  const Index last = every.sim->step;
  ASSERT_GE(last, 6);
  // rollback_every 4: the same trajectory, written back to the last multiple of 4.
  Scene sparse = loadText("sparse.yaml", lowSoundSpeedColumn("health: {rollback_every: 4}\n"));
  const RunResult r4 = runQuiet(sparse, "sparse");
  ASSERT_EQ(r4.status, RunStatus::Failed) << r4.message;
  EXPECT_EQ(sparse.sim->step, last / 4 * 4);
  // The restored state equals the state of a run stopped at that step, particle by particle
  // (the store was cell-reordered in between: the restore puts the captured order back).
  Scene stopped = loadText("stopped.yaml", lowSoundSpeedColumn("max_steps: " +
                                                               std::to_string(last / 4 * 4) + "\n"));
  const RunResult rs = runQuiet(stopped, "stopped");
  ASSERT_EQ(rs.status, RunStatus::Finished) << rs.message;
  ASSERT_EQ(stopped.sim->step, sparse.sim->step);
  EXPECT_EQ(stopped.sim->time, sparse.sim->time);
  EXPECT_EQ(positionsById(*stopped.sim), positionsById(*sparse.sim));
  // The same for the state before the failed step.
  Scene stopped1 = loadText("stopped1.yaml",
                            lowSoundSpeedColumn("max_steps: " + std::to_string(last) + "\n"));
  ASSERT_EQ(runQuiet(stopped1, "stopped1").status, RunStatus::Finished);
  EXPECT_EQ(positionsById(*stopped1.sim), positionsById(*every.sim));
}
