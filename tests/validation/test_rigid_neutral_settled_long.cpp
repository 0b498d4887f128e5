// Issue 15, validation case 2 (neutral buoyancy) with the free surface, a study (label
// validation_long; its one test is a probe, skipped unless RIGID_SETTLE is set):
// the tank of rigid_floating_case.hpp, but the water first settles to its discrete equilibrium
// (docs/rigid.md, Open: the free-surface drift of 0.174 dx over 10 s is the water's own settling
// from its initial lattice, not the body's coupling). Phase 1: the box is a fixed rigid body of
// the same particles and the water relaxes dynamically (fluid velocities damped by exp(-c dt) each
// step). Phase 2: the same scene with the box free; every particle starts where phase 1 left it
// (positions and densities copied by particle id, velocities zero) and the box gets the density
// that is neutral in the settled discrete water: the formula's (the water's density at its centre
// depth) times 1 + the held box's mean net force over its weight in the last 0.5 s of phase 1.
// Drift of the box's centre over phase 2, in dx.
// RIGID_SETTLE="settleTime damping endTime" runs it (e.g. "2 5 3").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "tests/validation/rigid_floating_case.hpp"

using namespace poresph;

namespace {

struct SettledResult {
  double drift = 0.0, dx = 0.0, rhoB = 0.0, heldForce = 0.0, settleSpeed = 0.0, seconds = 0.0, endTime = 0.0;
};

SettledResult runSettled(double settleTime, double damping, double endTime) {
  test::Stopwatch clock;
  const double dx = 0.00625, level = 0.15, bottom = 0.025;
  const double rhoGuess = 1000.0 * (1.0 + 9.81 * (level - 0.075) / (20.0 * 20.0));
  const auto fixedBox = [](std::string text) {
    const std::string key = "damping: 0}";
    const auto at = text.find(key);
    if (at == std::string::npos) throw std::runtime_error("tank scene: no '" + key + "' to fix the box");
    text.replace(at, key.size(), "damping: 0, fixed: true}");
    return text;
  };
  // phase 1: water settles around the fixed box
  Scene a = loadSceneText(fixedBox(test::tankScene(dx, rhoGuess, bottom, 0.0, settleTime, level)), "settle.yaml");
  Simulation& sa = *a.sim;
  auto ia = makeIntegrator("leapfrog");
  double vmax = 0.0, fAverage = 0.0, fTime = 0.0;
  double nextPrint = 0.25;
  while (!a.finished()) {
    const double dt = a.nextTimeStep();
    ia->step(sa, dt);
    if (sa.time > settleTime - 0.5) {  // the held box's net force over the last 0.5 s
      auto* rig = dynamic_cast<RigidModule*>(sa.module("rigid"));
      fAverage += dt * rig->bodies()[0].force[1] / (rig->bodies()[0].state.mass * 9.81);
      fTime += dt;
    }
    const RealField vhField = sa.store.real("integrator_velocity");  // the leapfrog's v^{n+1/2}
    const double f = std::exp(-damping * dt);
    ParticleStore& st = sa.store;
    double* v = st.data(st.velocity());
    double* vh = st.data(vhField);
    const std::int32_t* ph = st.data(st.phase());
    vmax = 0.0;
    double v2 = 0.0;
    Index fastest = 0, nf = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (ph[i] != kPhaseFluid) continue;
      for (int q = 0; q < 2; ++q) {
        v[2 * i + q] *= f;
        vh[2 * i + q] *= f;
      }
      const double sp = std::hypot(v[2 * i], v[2 * i + 1]);
      v2 += sp * sp;
      ++nf;
      if (sp > vmax) {
        vmax = sp;
        fastest = i;
      }
    }
    if (sa.time >= nextPrint) {
      const double* x = st.data(st.position());
      auto* rig = dynamic_cast<RigidModule*>(sa.module("rigid"));
      const double weight = rig->bodies()[0].state.mass * 9.81;
      std::printf("    settling t %.2f s: largest water speed %.3e m/s at (%.4f, %.4f), rms %.3e m/s; "
                  "net force on the held box / its weight %.3e\n",
                  sa.time, vmax, x[2 * fastest], x[2 * fastest + 1], std::sqrt(v2 / nf),
                  rig->bodies()[0].force[1] / weight);
      std::fflush(stdout);
      nextPrint += 0.25;
    }
  }
  std::unordered_map<std::int32_t, Index> byId;
  {
    const ParticleStore& st = sa.store;
    const std::int32_t* id = st.data(st.id());
    for (Index i = 0; i < st.realCount(); ++i) byId[id[i]] = i;
  }
  SettledResult out;
  out.dx = dx;
  // neutral in the settled discrete water: the held box's mean net force (gravity included, over
  // the last 0.5 s of the settling) removed by its density
  out.heldForce = fAverage / fTime;
  out.rhoB = std::getenv("RIGID_SETTLE_FORMULA") ? rhoGuess : rhoGuess * (1.0 + out.heldForce);
  out.settleSpeed = vmax;
  out.endTime = endTime;
  // phase 2: the same particles, the box free with the settled water's density
  Scene b = loadSceneText(test::tankScene(dx, out.rhoB, bottom, 0.0, endTime, level), "neutral.yaml");
  Simulation& sb = *b.sim;
  {
    ParticleStore& st = sb.store;
    const ParticleStore& sta = sa.store;
    EXPECT_EQ(st.realCount(), sta.realCount());
    double* x = st.data(st.position());
    double* v = st.data(st.velocity());
    double* rho = st.data(st.density());
    const std::int32_t* id = st.data(st.id());
    const double* xa = sta.data(sta.position());
    const double* rhoa = sta.data(sta.density());
    for (Index i = 0; i < st.realCount(); ++i) {
      const auto it = byId.find(id[i]);
      EXPECT_NE(it, byId.end());
      if (it == byId.end()) continue;
      const Index j = it->second;
      for (int q = 0; q < 2; ++q) {
        x[2 * i + q] = xa[2 * j + q];
        v[2 * i + q] = 0.0;
      }
      rho[i] = rhoa[j];
    }
  }
  auto* rigid = dynamic_cast<RigidModule*>(sb.module("rigid"));
  const rigid::V3 X0 = rigid->bodies()[0].state.X;
  auto ib = makeIntegrator("leapfrog");
  nextPrint = 0.5;
  while (!b.finished()) {
    ib->step(sb, b.nextTimeStep());
    out.drift = std::max(out.drift, (rigid->bodies()[0].state.X - X0).norm());
    if (sb.time >= nextPrint) {
      const rigid::V3 d = rigid->bodies()[0].state.X - X0;
      std::printf("    released t %.2f s: X - X0 (%.3e, %.3e) m, max drift %.4f dx\n", sb.time, d[0], d[1],
                  out.drift / dx);
      std::fflush(stdout);
      nextPrint += 0.5;
    }
  }
  out.seconds = clock.seconds();
  std::printf("  settled %.2f s (damping %.1f /s, last largest water speed %.2e m/s, held box's net force "
              "%.3e of its weight), box density %.4f (formula %.4f): max drift %.3e m = %.4f dx over %.1f s (%.0f s)\n",
              settleTime, damping, vmax, out.heldForce, out.rhoB, rhoGuess, out.drift, out.drift / dx, endTime, out.seconds);
  return out;
}

}  // namespace

// A study, not a check (docs/rigid.md, Open, neutral buoyancy (5)): skipped unless RIGID_SETTLE
// is set. Measured (dx = 6.25 mm, one core, loaded machine): the water does not reach a discrete
// equilibrium in a few seconds; damped at 5 /s its rms speed stays 0.8-3e-3 m/s over 4 s and
// the held box's net force swings from +0.9 % to -0.5 % of its weight (a slow mode of the
// stratified weakly compressible water, N = g / c = 0.49 rad/s, overdamped by the damping); the
// released box: after "4 5 10" with RIGID_SETTLE_FORMULA=1, 0.041 dx by 6 s, then a sideways
// excursion grown from round-off takes it to 0.136 dx over 10 s (no settling: 0.174 dx; 258 s
// CPU); after "2 5 3" with the held-force density 0.099 dx in 3 s (no settling: 0.029 dx).
TEST(RigidNeutralSettled, Probe) {
  const char* env = std::getenv("RIGID_SETTLE");
  if (!env) GTEST_SKIP() << "set RIGID_SETTLE=\"settleTime damping endTime\" (RIGID_SETTLE_FORMULA=1: "
                            "the box's density from the formula, not from the held box's force)";
  double settle = 2.0, damping = 5.0, T = 10.0;
  std::istringstream in(env);
  in >> settle >> damping >> T;
  runSettled(settle, damping, T);
}
