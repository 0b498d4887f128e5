// Restart of a coupled drainage run (issue 16, "Checkpoint and restart"): fluids, a TL clay with
// damage history, force-controlled rigid plates (module state), a free rigid grain bonded in the
// clay (an inclusion of the sample: `drainage.inclusions`; its body state - centre, velocity,
// angle, angular velocity), the drainage monitor. A run stopped at t1 and restarted from its
// checkpoint to t2 must reproduce the run that went to t2 in one go: same particles, positions,
// velocities, damage, plate and grain states and timeseries row to round-off. (The grain was
// added 2026-11-27: by 3 ms it has moved 31 um = 0.3 dx and turns at -0.056 rad/s.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "libcore/runner.hpp"
#include "libcore/scene.hpp"

using namespace poresph;
namespace fsys = std::filesystem;

namespace {

std::string sceneText(double endTime) {
  std::ifstream in(std::string(PORESPH_SOURCE_DIR) + "/samples/drainage_pores_2d.yaml");
  std::stringstream buf;
  buf << in.rdbuf();
  std::string text = buf.str();
  const size_t e = text.find("end_time: 0.04");
  EXPECT_NE(e, std::string::npos);
  text.replace(e, 14, "end_time: " + std::to_string(endTime));
  // A fixed step: with an adaptive one, the run that stops at t1 shortens its last step to land
  // on t1, so the two histories would differ by that step, not by the restart.
  const size_t t = text.find("time_step: {adaptive: true, cfl: 1.0}");
  EXPECT_NE(t, std::string::npos);
  text.replace(t, 37, "time_step: {adaptive: false, dt: 4.0e-6}");
  // A free rigid grain (r = 2 dx) bonded in the clay, away from the pores and the plates.
  const std::string clay = "  - name: clay\n    model: elastic";
  const size_t c = text.find(clay);
  EXPECT_NE(c, std::string::npos);
  text.insert(c, "  - {name: grain, model: rigid, density: 2650, bonded: true, contact_angle: 60}\n");
  const std::string box = "  - {shape: box, lo: [0.0, 0.0015], hi: [0.004, 0.0055], material: clay}\n";
  const size_t b = text.find(box);
  EXPECT_NE(b, std::string::npos);
  text.insert(b + box.size(), "  - {shape: sphere, centre: [0.0010, 0.0024], radius: 0.0002, material: grain}\n");
  const size_t g = text.find("drainage: {invading: gas,");
  EXPECT_NE(g, std::string::npos);
  text.insert(g + 11, "inclusions: [grain], ");
  return text;
}

}  // namespace

TEST(DrainageRestart, RestartedRunMatchesTheUninterruptedOne) {
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-drainage-restart";
  fsys::remove_all(dir);
  fsys::create_directories(dir);
  const double t1 = 0.0015, t2 = 0.003;  // across the load ramps (2 ms): damage and plates move

  Scene whole = loadSceneText(sceneText(t2), (dir / "whole.yaml").string());
  RunOptions o;
  o.handleSignals = false;
  o.outDir = (dir / "whole").string();
  ASSERT_EQ(runScene(whole, o).status, RunStatus::Finished);

  Scene first = loadSceneText(sceneText(t1), (dir / "first.yaml").string());
  o.outDir = (dir / "split").string();
  ASSERT_EQ(runScene(first, o).status, RunStatus::Finished);
  Scene second = loadSceneText(sceneText(t2), (dir / "second.yaml").string());
  o.restartFrom = (dir / "split" / "checkpoint.h5").string();
  ASSERT_EQ(runScene(second, o).status, RunStatus::Finished);

  const Simulation& a = *whole.sim;
  const Simulation& b = *second.sim;
  ASSERT_EQ(a.store.realCount(), b.store.realCount());
  EXPECT_EQ(a.step, b.step);
  EXPECT_DOUBLE_EQ(a.time, b.time);
  // Particles may be stored in another order (cell reordering): compare by id.
  auto byId = [](const Simulation& s) {
    std::vector<Index> at(static_cast<size_t>(s.store.realCount()));
    const std::int32_t* id = s.store.data(s.store.id());
    for (Index i = 0; i < s.store.realCount(); ++i) at[static_cast<size_t>(id[i])] = i;
    return at;
  };
  const auto ia = byId(a), ib = byId(b);
  const int d = a.dimension();
  double dx = 0.0, dv = 0.0, dd = 0.0, vmax = 0.0, dmax = 0.0;
  const double* xa = a.store.data(a.store.position());
  const double* xb = b.store.data(b.store.position());
  const double* va = a.store.data(a.store.velocity());
  const double* vb = b.store.data(b.store.velocity());
  const double* Da = a.store.data(a.store.real("damage"));
  const double* Db = b.store.data(b.store.real("damage"));
  for (size_t k = 0; k < ia.size(); ++k) {
    const Index p = ia[k], q = ib[k];
    for (int c = 0; c < d; ++c) {
      dx = std::max(dx, std::abs(xa[p * d + c] - xb[q * d + c]));
      dv = std::max(dv, std::abs(va[p * d + c] - vb[q * d + c]));
      vmax = std::max(vmax, std::abs(va[p * d + c]));
    }
    dd = std::max(dd, std::abs(Da[p] - Db[q]));
    dmax = std::max(dmax, Da[p]);
  }
  ASSERT_GT(vmax, 0.0);
  ASSERT_GT(dmax, 0.0) << "no damage yet: the test would not check the damage history";
  // Round-off: the checkpoint carries the integrator state (every non-checkpoint field: the
  // rates evaluated at the last step's prediction, lagged fields such as the previous
  // acceleration and the viscous normalisation, leapfrog's v^{n+1/2}), so the restarted run
  // takes the same steps. Measured after 375 steps: 2.8e-17 m (2.8e-13 dx) in positions,
  // 3.3e-12 vmax in velocities, 6e-12 in the columns. Before (re-primed from the synchronised
  // state) 8e-9 m and 2e-5 vmax, and 2e-3 in porosity: the bounds below fail on that.
  EXPECT_LT(dx, 1e-10 * a.spacing) << "positions";
  EXPECT_LT(dv, 1e-9 * vmax) << "velocities";
  EXPECT_LT(dd, 1e-12) << "damage";
  // Module columns (plates, the grain's body state, drainage, solid energies) of the last row agree.
  const auto ca = a.diagnostics(), cb = b.diagnostics();
  double grainX = NAN;
  for (const auto& [name, value] : ca)
    if (name == "body2_x") grainX = value;
  ASSERT_FALSE(std::isnan(grainX)) << "no grain body: the test would not check a free body";
  EXPECT_GT(std::abs(grainX - 0.0010), 0.05 * a.spacing) << "the grain did not move";
  ASSERT_EQ(ca.size(), cb.size());
  double worst = 0.0, omegaWorst = 0.0, plateForce = 0.0;
  for (const auto& [name, value] : ca)
    if (name.rfind("plate", 0) == 0 && name.find("_force") != std::string::npos)
      plateForce = std::max(plateForce, std::abs(value));
  ASSERT_GT(plateForce, 0.0);
  for (size_t k = 0; k < ca.size(); ++k) {
    EXPECT_EQ(ca[k].first, cb[k].first);
    // NaN in both (e.g. the gas velocity while no gas is in the slab) is the same state.
    if (std::isnan(ca[k].second) && std::isnan(cb[k].second)) continue;
    if (ca[k].first.find("_omega") != std::string::npos) {
      // A body's angular velocity is a small net of nearly cancelling torques (the grain's bond
      // forces are mostly radial): measured 7.6e-10 rad/s apart at 3 ms (1.3e-8 relative of
      // -0.056 rad/s) while positions agree to 1e-18 m. Compared as the velocity it gives a
      // particle 10 dx from the centre, against the particles' bound (a restart that lost L
      // would be ~1e5 times over it).
      omegaWorst = std::max(omegaWorst, std::abs(ca[k].second - cb[k].second));
      EXPECT_LT(std::abs(ca[k].second - cb[k].second) * 10.0 * a.spacing, 1e-9 * vmax) << ca[k].first;
      continue;
    }
    double scale = std::max({std::abs(ca[k].second), std::abs(cb[k].second), 1e-30});
    // The grain's net force is such a net too (body2_fy measured 7.8e-9 relative of 8e-4 N/m):
    // compared against the scene's force level, the plates' load.
    if (ca[k].first.rfind("body", 0) == 0 && ca[k].first.find("_f") != std::string::npos)
      scale = std::max(scale, plateForce);
    EXPECT_LT(std::abs(ca[k].second - cb[k].second) / scale, 1e-8) << ca[k].first;
    worst = std::max(worst, std::abs(ca[k].second - cb[k].second) / scale);
  }
  std::printf("restart: positions %.3g m, velocities %.3g (vmax %.3g), damage %.3g, columns %.3g, "
              "angular velocity %.3g rad/s\n",
              dx, dv, vmax, dd, worst, omegaWorst);
}
