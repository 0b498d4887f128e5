// The drainage driver and monitor (physics/drainage, docs/drainage.md): the reservoir body force
// of Sec. 5.2 (f = dP / (rho_g L_r), on the invading fluid outside the sample slab only), the
// porosity and saturations of the slab, the percolation flag (a cluster of invading particles
// spanning the slab face to face, never through the periodic face), its time kept
// across checkpoints, and the scene errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>

#include "libcore/checkpoint.hpp"
#include "libcore/runner.hpp"
#include "libcore/scene.hpp"
#include "physics/drainage/drainage_module.hpp"

using namespace poresph;

namespace {

// 2D, 20 x 30 particles (dx = 1 mm), periodic in both directions. The sample slab is
// y in [0.01, 0.02]: clay with a vertical channel x in [0.008, 0.012] of water; gas below and
// above (the reservoirs).
std::string scene(const std::string& drainage, const std::string& periodic = "[true, true]") {
  return R"(dimension: 2
domain: {lo: [0, 0], hi: [0.02, 0.03], periodic: )" +
         periodic + R"(}
spacing: 0.001
kernel: wendland_c2
end_time: 0.001
time_step: {adaptive: true}
output: {every_steps: 10}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 10, viscosity: 1.0e-3, colour: 1}
  - {name: gas, model: fluid, density: 10, sound_speed: 10, viscosity: 1.0e-5, colour: -1}
  - {name: clay, model: elastic, density: 2000, young_modulus: 1.0e6, poisson_ratio: 0.1, formulation: small_strain_stress}
geometry:
  - {shape: box, lo: [0, 0], hi: [0.02, 0.03], material: gas}
  - {shape: box, lo: [0, 0.01], hi: [0.02, 0.02], material: clay}
  - {shape: box, lo: [0.008, 0.01], hi: [0.012, 0.02], material: water}
drainage: )" + drainage + "\n";
}

const std::string kDrainage =
    "{invading: gas, defending: water, axis: y, sample: [0.01, 0.02], pressure_drop: 0.4}";

std::string message(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

double column(const Simulation& sim, const std::string& name) {
  for (const auto& [k, v] : sim.diagnostics())
    if (k == name) return v;
  ADD_FAILURE() << "no column " << name;
  return NAN;
}

DrainageModule& drainage(Scene& s) {
  auto* m = dynamic_cast<DrainageModule*>(s.sim->module("drainage"));
  EXPECT_NE(m, nullptr);
  return *m;
}

/// Sets every particle of material `from` inside the box to material `to`.
void recolour(Simulation& sim, int from, int to, double x0, double x1, double y0, double y1) {
  ParticleStore& st = sim.store;
  const double* x = st.data(st.position());
  std::int32_t* mt = st.data(st.material());
  for (Index i = 0; i < st.realCount(); ++i)
    if (mt[i] == from && x[2 * i] > x0 && x[2 * i] < x1 && x[2 * i + 1] > y0 &&
        x[2 * i + 1] < y1)
      mt[i] = to;
}

}  // namespace

TEST(Drainage, BodyForceActsOnReservoirGasOnly) {
  Scene s = loadSceneText(scene(kDrainage), "drainage.yaml");
  Simulation& sim = *s.sim;
  DrainageModule& d = drainage(s);
  // f = dP / (rho_g L_r), L_r = 0.03 - 0.01 = 0.02 m, pushing towards -y by default.
  EXPECT_NEAR(d.bodyForce(), -0.4 / (10.0 * 0.02), 1e-12);
  ParticleStore& st = sim.store;
  const Index n = st.realCount();
  double* acc = st.data(sim.acceleration);
  std::fill(acc, acc + 2 * n, 0.0);
  d.forces(sim);
  const double* x = st.data(st.position());
  const std::int32_t* mt = st.data(st.material());
  Index pushed = 0;
  for (Index i = 0; i < n; ++i) {
    const bool reservoirGas = mt[i] == 1 && (x[2 * i + 1] < 0.01 || x[2 * i + 1] > 0.02);
    EXPECT_EQ(acc[2 * i], 0.0);
    EXPECT_EQ(acc[2 * i + 1], reservoirGas ? d.bodyForce() : 0.0) << "particle " << i;
    pushed += reservoirGas;
  }
  EXPECT_EQ(pushed, 20 * 20);  // 10 rows below and 10 above the slab, 20 across
}

TEST(Drainage, PorosityAndSaturationsOfTheSlab) {
  Scene s = loadSceneText(scene(kDrainage), "drainage.yaml");
  Simulation& sim = *s.sim;
  // Equal particle volumes dx^2 at rest: the porosity is the channel's share, 4 of 20 columns.
  EXPECT_NEAR(column(sim, "drainage_porosity"), 0.2, 1e-12);
  EXPECT_NEAR(column(sim, "drainage_water_saturation"), 1.0, 1e-12);
  EXPECT_NEAR(column(sim, "drainage_gas_saturation"), 0.0, 1e-12);
  // Gas in the lower half of the channel: saturation 1/2 (5 of 10 rows).
  recolour(sim, 0, 1, 0.0, 1.0, 0.0, 0.015);
  EXPECT_NEAR(column(sim, "drainage_gas_saturation"), 0.5, 1e-12);
  EXPECT_NEAR(column(sim, "drainage_water_saturation"), 0.5, 1e-12);
  // A dilated solid (lower density = larger volume m/rho) lowers the porosity.
  ParticleStore& st = sim.store;
  double* rho = st.data(st.density());
  const std::int32_t* mt = st.data(st.material());
  for (Index i = 0; i < st.realCount(); ++i)
    if (mt[i] == 2) rho[i] *= 0.5;
  EXPECT_NEAR(column(sim, "drainage_porosity"), 40.0 / (40.0 + 2.0 * 160.0), 1e-12);
}

TEST(Drainage, PercolationNeedsAGasPathThroughTheSample) {
  Scene s = loadSceneText(scene(kDrainage), "drainage.yaml");
  Simulation& sim = *s.sim;
  DrainageModule& d = drainage(s);
  sim.updateNeighbours();
  // The reservoirs touch each other through the periodic face: that is not a percolation.
  EXPECT_FALSE(d.percolates(sim));
  // Gas in the channel except one row of water: still not percolated.
  recolour(sim, 0, 1, 0.0, 1.0, 0.0, 0.0149);
  recolour(sim, 0, 1, 0.0, 1.0, 0.0151 + 0.001, 1.0);
  EXPECT_FALSE(d.percolates(sim));
  EXPECT_EQ(column(sim, "drainage_percolated"), 0.0);
  EXPECT_EQ(column(sim, "drainage_percolation_time"), -1.0);
  // The last water row replaced: the gas spans the slab. Breakthrough counts also when the
  // displaced water covers the outlet face (here: the whole low reservoir turned to water).
  recolour(sim, 0, 1, 0.0, 1.0, 0.0, 1.0);
  EXPECT_TRUE(d.percolates(sim));
  recolour(sim, 1, 0, 0.0, 1.0, 0.0, 0.0099);
  EXPECT_TRUE(d.percolates(sim));
  sim.time = 0.25;
  EXPECT_EQ(column(sim, "drainage_percolated"), 1.0);
  EXPECT_EQ(column(sim, "drainage_percolation_time"), 0.25);
  // The first time is kept (later rows do not move it) and travels with checkpoints.
  sim.time = 0.5;
  EXPECT_EQ(column(sim, "drainage_percolation_time"), 0.25);
  const std::string file = std::string(PORESPH_BINARY_DIR) + "/test-drainage-checkpoint.h5";
  writeCheckpoint(sim, file);
  Scene fresh = loadSceneText(scene(kDrainage), "drainage.yaml");
  EXPECT_EQ(drainage(fresh).percolationTime(), -1.0);
  readCheckpoint(*fresh.sim, file);
  EXPECT_EQ(drainage(fresh).percolationTime(), 0.25);
}

TEST(Drainage, SceneErrorsNameTheKeyAndValue) {
  auto err = [&](const std::string& sec, const std::string& periodic = "[true, true]") {
    return message([&] { loadSceneText(scene(sec, periodic), "drainage.yaml"); });
  };
  std::string m = err("{invading: gass, defending: water, axis: y, sample: [0.01, 0.02]}");
  EXPECT_NE(m.find("drainage.invading"), std::string::npos) << m;
  EXPECT_NE(m.find("did you mean 'gas'"), std::string::npos) << m;
  m = err("{invading: clay, defending: water, axis: y, sample: [0.01, 0.02]}");
  EXPECT_NE(m.find("must be fluids"), std::string::npos) << m;
  m = err("{invading: gas, defending: gas, axis: y, sample: [0.01, 0.02]}");
  EXPECT_NE(m.find("drainage.defending"), std::string::npos) << m;
  m = err("{invading: gas, defending: water, axis: y, sample: [0.0, 0.02]}");
  EXPECT_NE(m.find("drainage.sample"), std::string::npos) << m;
  EXPECT_NE(m.find("strictly inside the domain"), std::string::npos) << m;
  m = err("{invading: gas, defending: water, axis: w, sample: [0.01, 0.02]}");
  EXPECT_NE(m.find("drainage.axis"), std::string::npos) << m;
  m = err(kDrainage, "[true, false]");
  EXPECT_NE(m.find("drainage.pressure_drop"), std::string::npos) << m;
  EXPECT_NE(m.find("periodic along the flow axis y"), std::string::npos) << m;
  m = err("{invading: gas, defending: water, sample: [0.01, 0.02], presure_drop: 1}");
  EXPECT_NE(m.find("did you mean 'pressure_drop'"), std::string::npos) << m;
}

TEST(Drainage, RampRaisesTheBodyForceLinearly) {
  Scene s = loadSceneText(
      scene("{invading: gas, defending: water, axis: y, sample: [0.01, 0.02], pressure_drop: 0.4, "
            "ramp_time: 0.002}"),
      "drainage.yaml");
  Simulation& sim = *s.sim;
  DrainageModule& d = drainage(s);
  ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const std::int32_t* mt = st.data(st.material());
  const double* x = st.data(st.position());
  Index probe = -1;  // a reservoir gas particle
  for (Index i = 0; i < n && probe < 0; ++i)
    if (mt[i] == 1 && x[2 * i + 1] < 0.01) probe = i;
  ASSERT_GE(probe, 0);
  double* acc = st.data(sim.acceleration);
  for (double t : {0.0, 0.0005, 0.002, 0.01}) {
    sim.time = t;
    std::fill(acc, acc + 2 * n, 0.0);
    d.forces(sim);
    EXPECT_NEAR(acc[2 * probe + 1], d.bodyForce() * std::min(1.0, t / 0.002), 1e-12) << t;
  }
}

// Dimensionless numbers of Eqs. 5.11-5.14: the pore size is the hydraulic diameter 4 V / S of the
// slab's pore space (a slit of width w: 2 w), the gas velocity the volume-weighted mean of the
// invading fluid along the push direction, Ca = mu_g v_g / gamma and Re = rho_g v_g L / mu_g.
TEST(Drainage, PoreSizeIsTheHydraulicDiameterOfTheSlabsPores) {
  // The channel is a slit 4 dx wide and 10 dx long: V = 40 dx^2, S = 20 dx faces: L = 8 dx.
  Scene s = loadSceneText(scene(kDrainage), "drainage.yaml");
  EXPECT_NEAR(drainage(s).poreSize(), 0.008, 1e-12);
  EXPECT_NEAR(drainage(s).measurePoreSize(*s.sim), 0.008, 1e-12);
  // A given pore size is used as given.
  Scene given = loadSceneText(
      scene("{invading: gas, defending: water, axis: y, sample: [0.01, 0.02], pore_size: 0.003}"),
      "given.yaml");
  EXPECT_NEAR(drainage(given).poreSize(), 0.003, 1e-15);
}

TEST(Drainage, CapillaryAndReynoldsNumbersFromTheMeasuredGasVelocity) {
  std::string text = scene(kDrainage);
  text += "fluid: {surface_tension: 0.02}\n";
  Scene s = loadSceneText(text, "numbers.yaml");
  Simulation& sim = *s.sim;
  ParticleStore& st = sim.store;
  const double* x = st.data(st.position());
  double* v = st.data(st.velocity());
  std::int32_t* mt = st.data(st.material());
  // Gas in the lower half of the channel moving at -0.3 m/s (the push is towards -y) and the
  // water above it at rest: v_g = 0.3 m/s along the push.
  for (Index i = 0; i < st.realCount(); ++i) {
    v[2 * i] = v[2 * i + 1] = 0.0;
    if (mt[i] == 0 && x[2 * i + 1] < 0.015) {
      mt[i] = 1;
      v[2 * i + 1] = -0.3;
      v[2 * i] = 0.7;  // across the push: not counted
    }
  }
  EXPECT_NEAR(column(sim, "drainage_gas_velocity"), 0.3, 1e-12);
  EXPECT_NEAR(column(sim, "drainage_capillary_number"), 1.0e-5 * 0.3 / 0.02, 1e-15);  // 5.12a
  EXPECT_NEAR(column(sim, "drainage_reynolds_number"), 10.0 * 0.3 * 0.008 / 1.0e-5,
              1e-9);  // 5.14a with L = 8 dx
}

TEST(Drainage, InfoPrintsSimulatedAndPhysicalNumbers) {
  std::string text = scene(
      "{invading: gas, defending: water, axis: y, sample: [0.01, 0.02], pressure_drop: 0.4,"
      " physical: {invading_density: 700, defending_density: 1000, invading_viscosity: 5.0e-5,"
      " defending_viscosity: 1.0e-3, surface_tension: 0.03, pore_size: 1.0e-4,"
      " velocity: 1.0e-5}}");
  text += "fluid: {surface_tension: 0.02, gravity: [0, -9.81]}\n";
  Scene s = loadSceneText(text, "info.yaml");
  const std::string d = drainage(s).describe(*s.sim);
  // simulated: Bo = (1000 - 10) 9.81 0.008^2 / 0.02 = 31.1, M = 0.01; physical:
  // Bo = 300 9.81 1e-8 / 0.03 = 9.81e-4, Ca = 5e-5 1e-5 / 0.03 = 1.67e-8, M = 0.05,
  // Re = 700 1e-5 1e-4 / 5e-5 = 0.014.
  for (const char* expect : {"Bo (5.11a)    31.1        0.000981", "Ca (5.12a)", "1.67e-08",
                             "M (5.13a)     0.01        0.05", "0.014", "L = 0.008 m"})
    EXPECT_NE(d.find(expect), std::string::npos) << expect << "\n" << d;
  // An unknown key of `physical:` is named.
  const std::string bad = message([] {
    loadSceneText(scene("{invading: gas, defending: water, axis: y, sample: [0.01, 0.02],"
                        " physical: {gas_viscocity: 1}}"),
                  "bad.yaml");
  });
  EXPECT_NE(bad.find("gas_viscocity"), std::string::npos) << bad;
}

// stop_after_percolation: a run whose gas already spans the sample ends that long after the
// percolation time, not at end_time, and its log reason names the key; a restart from that
// checkpoint is refused naming it; without the key the run goes on to end_time.
TEST(Drainage, StopAfterPercolationEndsTheRun) {
  // The channel holds gas from the start: the gas spans the slab at the first check.
  auto gasChannel = [](const std::string& keys) {
    std::string t = scene(keys);
    const std::string from = "hi: [0.012, 0.02], material: water}";
    t.replace(t.find(from), from.size(), "hi: [0.012, 0.02], material: gas}");
    return t;
  };
  const std::string fast =
      "{invading: gas, defending: water, axis: y, sample: [0.01, 0.02], pressure_drop: 0.4, "
      "percolation_every: 1";
  const std::string dir = std::string(PORESPH_BINARY_DIR) + "/test-drainage-stop";
  auto run = [&](const std::string& drainageKeys, const std::string& out) {
    Scene s = loadSceneText(gasChannel(drainageKeys), "drainage.yaml");
    RunOptions o;
    o.outDir = dir + "/" + out;
    o.handleSignals = false;
    const RunResult r = runScene(s, o);
    EXPECT_EQ(r.status, RunStatus::Finished);
    return std::make_pair(r, drainage(s).percolationTime());
  };
  std::filesystem::remove_all(dir);
  const auto [stopped, tp] = run(fast + ", stop_after_percolation: 0.0002}", "stop");
  ASSERT_GE(tp, 0.0);
  EXPECT_LT(tp, 1e-4);                       // percolated within the first steps
  EXPECT_GE(stopped.time, tp + 0.0002 - 1e-12);
  EXPECT_LT(stopped.time, tp + 0.0002 + 1e-4);  // within one step (dt ~ 2e-5 s here) of it
  const auto [full, tp2] = run(fast + "}", "full");
  EXPECT_DOUBLE_EQ(full.time, 0.001);         // end_time
  EXPECT_DOUBLE_EQ(tp2, tp);

  Scene again = loadSceneText(gasChannel(fast + ", stop_after_percolation: 0.0002}"), "drainage.yaml");
  const std::string m = message([&] { restoreCheckpoint(again, stopped.checkpoint); });
  EXPECT_NE(m.find("drainage.stop_after_percolation"), std::string::npos) << m;
  // It is a clock key: a run continues with another value (or none), as with end_time.
  Scene other = loadSceneText(gasChannel(fast + ", stop_after_percolation: 0.01}"), "drainage.yaml");
  Scene none = loadSceneText(gasChannel(fast + "}"), "drainage.yaml");
  EXPECT_EQ(sceneSignature(other), sceneSignature(again));
  EXPECT_EQ(sceneSignature(none), sceneSignature(again));
  EXPECT_NE(drainage(again).describe(*again.sim).find("ends 0.0002 s after percolation"), std::string::npos)
      << drainage(again).describe(*again.sim);
  EXPECT_EQ(drainage(none).describe(*none.sim).find("after percolation"), std::string::npos);
  EXPECT_NE(message([&] { loadSceneText(scene(fast + ", stop_after_percolation: -1}"), "d.yaml"); })
                .find("drainage.stop_after_percolation"),
            std::string::npos);
}
