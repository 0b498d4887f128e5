// A restart continues the run to round-off for every integrator (docs/output.md, "Checkpoints"):
// the checkpoint carries the integrator state (Integrator::saveState: the rates evaluated at the
// last step's prediction, lagged fields, the scheme's scratch and numbers), so a run stopped
// after N steps and restarted to 2N takes the same steps as the run that went to 2N in one go.
// Without that state the restarted scheme re-primes from the synchronised state: measured
// 1.1e-5 dx in positions and 2.3e-4 of vmax in velocities after 40 more steps of this drop (all
// three schemes fail the bounds then); with it 6e-15 dx and 1e-14. Also: the field packing behind it maps rows by particle id and refuses a state
// that does not fit the store.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "libcore/integrator.hpp"
#include "libcore/runner.hpp"
#include "libcore/scene.hpp"

using namespace poresph;
namespace fsys = std::filesystem;

namespace {

// The oscillating drop sample (surface tension, viscosity, periodic box), with `integrator` and
// a step limit; steps are adaptive (the restarted run must choose the same dt too).
std::string sceneText(const std::string& integrator, long maxSteps,
                      const std::string& sample = "fluid_oscillating_droplet.yaml") {
  std::ifstream in(std::string(PORESPH_SOURCE_DIR) + "/samples/" + sample);
  std::stringstream buf;
  buf << in.rdbuf();
  std::string text = buf.str();
  const size_t k = text.find("integrator: leapfrog");
  EXPECT_NE(k, std::string::npos);
  text.replace(k, 20, "integrator: " + integrator + "\nmax_steps: " + std::to_string(maxSteps));
  return text;
}

std::vector<Index> rowsById(const Simulation& s) {
  std::vector<Index> at(static_cast<size_t>(s.store.realCount()));
  const std::int32_t* id = s.store.data(s.store.id());
  for (Index i = 0; i < s.store.realCount(); ++i) at[static_cast<size_t>(id[i])] = i;
  return at;
}

void expectSameState(const Simulation& a, const Simulation& b, long steps, const std::string& what);

}  // namespace

class RestartExact : public ::testing::TestWithParam<std::string> {};

TEST_P(RestartExact, SplitRunEqualsTheUninterruptedOne) {
  const std::string scheme = GetParam();
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / ("test-restart-exact-" + scheme);
  fsys::remove_all(dir);
  fsys::create_directories(dir);
  const long n = 40;
  RunOptions o;
  o.handleSignals = false;

  Scene whole = loadSceneText(sceneText(scheme, 2 * n), (dir / "whole.yaml").string());
  o.outDir = (dir / "whole").string();
  ASSERT_EQ(runScene(whole, o).status, RunStatus::Finished);
  Scene first = loadSceneText(sceneText(scheme, n), (dir / "first.yaml").string());
  o.outDir = (dir / "split").string();
  ASSERT_EQ(runScene(first, o).status, RunStatus::Finished);
  Scene second = loadSceneText(sceneText(scheme, 2 * n), (dir / "second.yaml").string());
  o.restartFrom = (dir / "split" / "checkpoint.h5").string();
  ASSERT_EQ(runScene(second, o).status, RunStatus::Finished);

  expectSameState(*whole.sim, *second.sim, 2 * n, scheme);
}

INSTANTIATE_TEST_SUITE_P(Schemes, RestartExact,
                         ::testing::Values("leapfrog", "verlet", "predictor_corrector"));

// The contact angle with `wetting_curvature` (docs/fluid.md) reads the previous evaluation's
// curvature at the contact line, a field the checkpoint does not carry. The restart still repeats
// the uninterrupted run exactly: its priming evaluation at the checkpoint's state recomputes the
// curvature the uninterrupted run's last evaluation left (the same state), and that evaluation's
// rates are discarded for the checkpointed ones. This pins it (measured: 0 difference, 20 + 20
// steps of the drop on a cylinder; 1.1 s CPU).
TEST(RestartExactWetting, CurvatureCorrectedContactAngleRestartsExactly) {
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-restart-exact-wetting";
  fsys::remove_all(dir);
  fsys::create_directories(dir);
  const long n = 20;
  const std::string sample = "fluid_drop_on_cylinder_120.yaml";
  RunOptions o;
  o.handleSignals = false;
  Scene whole = loadSceneText(sceneText("leapfrog", 2 * n, sample), (dir / "whole.yaml").string());
  o.outDir = (dir / "whole").string();
  ASSERT_EQ(runScene(whole, o).status, RunStatus::Finished);
  Scene first = loadSceneText(sceneText("leapfrog", n, sample), (dir / "first.yaml").string());
  o.outDir = (dir / "split").string();
  ASSERT_EQ(runScene(first, o).status, RunStatus::Finished);
  Scene second = loadSceneText(sceneText("leapfrog", 2 * n, sample), (dir / "second.yaml").string());
  o.restartFrom = (dir / "split" / "checkpoint.h5").string();
  ASSERT_EQ(runScene(second, o).status, RunStatus::Finished);
  expectSameState(*whole.sim, *second.sim, 2 * n, "wetting_curvature");
}

namespace {

void expectSameState(const Simulation& a, const Simulation& b, long steps, const std::string& what) {
  ASSERT_EQ(a.step, steps);
  ASSERT_EQ(b.step, steps);
  EXPECT_DOUBLE_EQ(a.time, b.time) << "the restarted run chose other time steps";
  const auto ia = rowsById(a), ib = rowsById(b);
  const int d = a.dimension();
  const double* xa = a.store.data(a.store.position());
  const double* xb = b.store.data(b.store.position());
  const double* va = a.store.data(a.store.velocity());
  const double* vb = b.store.data(b.store.velocity());
  double dx = 0.0, dv = 0.0, vmax = 0.0;
  for (size_t k = 0; k < ia.size(); ++k)
    for (int c = 0; c < d; ++c) {
      dx = std::max(dx, std::abs(xa[ia[k] * d + c] - xb[ib[k] * d + c]));
      dv = std::max(dv, std::abs(va[ia[k] * d + c] - vb[ib[k] * d + c]));
      vmax = std::max(vmax, std::abs(va[ia[k] * d + c]));
    }
  ASSERT_GT(vmax, 0.0);
  std::printf("%s: positions %.3g m (%.3g dx), velocities %.3g of vmax %.3g\n", what.c_str(), dx,
              dx / a.spacing, dv / vmax, vmax);
  EXPECT_LT(dx, 1e-11 * a.spacing);
  EXPECT_LT(dv, 1e-10 * vmax);
}

}  // namespace

TEST(StoreState, RowsFollowTheParticleIdsAndBadStatesAreRefused) {
  ParticleStore s(2);
  s.addParticles(3);
  RealField f = s.addReal("f", 2);
  IntField g = s.addInt("g", 1);
  for (Index i = 0; i < 3; ++i) {
    s.data(s.id())[i] = static_cast<std::int32_t>(i);
    s.data(f)[2 * i] = 10.0 * i;
    s.data(f)[2 * i + 1] = 10.0 * i + 1.0;
    s.data(g)[i] = -7 * static_cast<std::int32_t>(i);
  }
  const ModuleState saved = packStoreFields(s, true);  // f, g and the core fields are checkpointed
  s.permute({2, 0, 1});                                 // new row r holds old particle newToOld[r]
  for (Index i = 0; i < 3; ++i) {                       // scramble the values
    s.data(f)[2 * i] = -1.0;
    s.data(g)[i] = 99;
  }
  unpackStoreFields(s, saved);
  for (Index i = 0; i < 3; ++i) {
    const std::int32_t id = s.data(s.id())[i];
    EXPECT_EQ(s.data(f)[2 * i], 10.0 * id);
    EXPECT_EQ(s.data(f)[2 * i + 1], 10.0 * id + 1.0);
    EXPECT_EQ(s.data(g)[i], -7 * id);
  }
  ModuleState noId(saved.begin() + 1, saved.end());
  EXPECT_THROW(unpackStoreFields(s, noId), std::invalid_argument);
  ModuleState unknown = saved;
  unknown.emplace_back("field:no_such_field", std::vector<double>(3, 0.0));
  EXPECT_THROW(unpackStoreFields(s, unknown), std::invalid_argument);
  ModuleState shortField = saved;
  for (auto& [key, values] : shortField)
    if (key == "field:f") values.pop_back();
  EXPECT_THROW(unpackStoreFields(s, shortField), std::invalid_argument);
  ModuleState otherParticle = saved;
  otherParticle[0].second[1] = 42.0;  // an id the store does not have
  EXPECT_THROW(unpackStoreFields(s, otherParticle), std::invalid_argument);
}
