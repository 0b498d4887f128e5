#pragma once
// The water tank of issue 15's validation case 2 (floating, neutral buoyancy), shared by
// tests/validation/test_rigid_floating.cpp (default) and test_rigid_floating_long.cpp (the
// issue's 10 s in a closed tank). The body feels the water only through the fluid-rigid pairs
// (extrapolated boundary pressure and the shared pair terms, reaction on the body particles) and
// its own gravity.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"
#include "physics/rigid/rigid_module.hpp"
#include "tests/support/validation_record.hpp"

namespace poresph::test {

// Tank [0, 0.3] x [0, 0.25], water to 0.15, a 0.1 x 0.1 box of density rhoB centred at x = 0.15
// with its bottom at `bottom`; dx = spacing. `kernel`: Wendland C2 (h = 1.3 dx) by default; the
// water at rest on its square lattice is unstable under the hydrostatic pressure (docs/fluid.md
// "Water at rest on the lattice"), the quintic spline (h = 1.3 dx) holds it.
inline std::string tankScene(double dx, double rhoB, double bottom, double damping, double endTime,
                      double level = 0.15, bool lid = false, const char* boxMaterial = "box",
                      const char* kernel = "wendland_c2") {
  char buf[2048];
  std::snprintf(buf, sizeof buf, R"(dimension: 2
domain: {lo: [%g, %g], hi: [%g, %g]}
spacing: %g
kernel: %s
end_time: %g
time_step: {adaptive: true, cfl: 0.5}
output: {every_steps: 1000000}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 20, viscosity: 1.0e-3}
  - {name: tank, model: wall, density: 1000}
  - {name: box, model: rigid, density: %g, damping: %g}
geometry:
  - {shape: box, lo: [%g, %g], hi: [%g, %g], material: tank}
  - {shape: box, lo: [0.0, 0.0], hi: [0.3, %g], material: none}
  - {shape: box, lo: [0.0, 0.0], hi: [0.3, %g], material: water}
  - {shape: box, lo: [0.1, %g], hi: [0.2, %g], material: %s}
fluid: {gravity: [0, -9.81], hydrostatic_level: %g, artificial_viscosity: 0.1}
rigid: {gravity: [0, -9.81]}
health: {domain_margin: 1.0}
)",
                -3 * dx, -3 * dx, 0.3 + 3 * dx, level + 0.15, dx, kernel, endTime, rhoB, damping, -3 * dx,
                -3 * dx, 0.3 + 3 * dx, level + 0.1, lid ? level : level + 0.1, level, bottom,
                bottom + 0.1, boxMaterial, level);
  return buf;
}

/// A neutrally buoyant box (the density of the model's water at its depth) in mid-water of the
/// tank over `endTime`: the largest distance of its centre from the start, in dx (asserted < 0.1
/// dx and recorded under `recordName`). lid: the tank closed by a wall lid on the water (no free
/// surface). Studies: RIGID_DX (spacing), RIGID_LEVEL, RIGID_TRACE (height, sideways offset, tilt,
/// the water beside, the density excess, the force), RIGID_NOBOX (water in place of the box: how
/// far that water moves), RIGID_NOROTATE (the box may not turn), RIGID_KERNEL (the kernel).
/// kernel: wendland_c2 (the floating test's) or quintic_spline (square lattice stable under
/// pressure, docs/fluid.md "Water at rest on the lattice").
inline void neutralDrift(double endTime, bool lid, const std::string& recordName,
                         std::string kernel = "wendland_c2") {
  Stopwatch clock;
  if (std::getenv("RIGID_KERNEL")) kernel = std::getenv("RIGID_KERNEL");
  const double dx = std::getenv("RIGID_DX") ? std::atof(std::getenv("RIGID_DX")) : 0.00625;
  const double level = std::getenv("RIGID_LEVEL") ? std::atof(std::getenv("RIGID_LEVEL")) : 0.15;
  // Neutral in the model's water: the weakly compressible water (linear EOS, c = 20 m/s) at the
  // box's centre depth is denser than rho0 by rho0 g depth / c^2 (0.18 %; a box of density rho0
  // rises, 0.37 dx in 1 s measured at depth 0.175 m).
  const double rhoB = 1000.0 * (1.0 + 9.81 * (level - 0.075) / (20.0 * 20.0));
  // RIGID_NOBOX=1: water where the box would be; the trace follows that water parcel instead
  // (how far the model's water itself moves in the tank; study of the drift)
  if (std::getenv("RIGID_NOBOX")) {
    Scene s = loadSceneText(tankScene(dx, rhoB, 0.025, 0.0, endTime, level, lid, "water", kernel.c_str()), "still.yaml");
    Simulation& sim = *s.sim;
    auto integrator = makeIntegrator("leapfrog");
    const auto inParcel = [&](const double* p) {
      return p[0] > 0.1 && p[0] < 0.2 && p[1] > 0.025 && p[1] < 0.125;
    };
    std::vector<char> member;
    std::vector<double> p0;
    {
      const double* x = sim.store.data(sim.store.position());
      const std::int32_t* id = sim.store.data(sim.store.id());
      for (Index i = 0; i < sim.store.realCount(); ++i) {
        const size_t k = static_cast<size_t>(id[i]);
        if (k >= member.size()) { member.resize(k + 1, 0); p0.resize(2 * k + 2, 0.0); }
        member[k] = inParcel(x + 2 * i) && sim.store.data(sim.store.phase())[i] == kPhaseFluid;
        p0[2 * k] = x[2 * i];
        p0[2 * k + 1] = x[2 * i + 1];
      }
    }
    double drift = 0.0;
    while (!s.finished()) {
      integrator->step(sim, s.nextTimeStep());
      if (sim.step % 2000 != 0) continue;
      const double* x = sim.store.data(sim.store.position());
      const std::int32_t* id = sim.store.data(sim.store.id());
      double d[2] = {0, 0};
      int cnt = 0;
      for (Index i = 0; i < sim.store.realCount(); ++i) {
        const size_t k = static_cast<size_t>(id[i]);
        if (k >= member.size() || !member[k]) continue;
        d[0] += x[2 * i] - p0[2 * k];
        d[1] += x[2 * i + 1] - p0[2 * k + 1];
        ++cnt;
      }
      drift = std::max(drift, std::hypot(d[0] / cnt, d[1] / cnt));
      std::printf("    t %.3f  water parcel mean displacement (%.3e, %.3e) m, max drift %.3e m\n",
                  sim.time, d[0] / cnt, d[1] / cnt, drift);
    }
    std::printf("  water parcel in place of the box: max drift %.3e m = %.3f dx over %.1f s\n",
                drift, drift / dx, sim.time);
    return;
  }
  // RIGID_NOROTATE=1: the box may translate but not turn (`rotate: false`): is the sideways mode
  // of the free-surface run (docs/rigid.md, Open) a rocking of the box?
  std::string text = tankScene(dx, rhoB, 0.025, 0.0, endTime, level, lid, "box", kernel.c_str());
  if (std::getenv("RIGID_NOROTATE")) {
    const std::string key = "damping: 0}";
    const auto at = text.find(key);
    if (at == std::string::npos) throw std::runtime_error("tank scene: no '" + key + "' to stop the box turning");
    text.replace(at, key.size(), "damping: 0, rotate: false}");
  }
  Scene s = loadSceneText(text, "neutral.yaml");
  Simulation& sim = *s.sim;
  auto* rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  auto integrator = makeIntegrator("leapfrog");
  const rigid::V3 X0 = rigid->bodies()[0].state.X;
  double drift = 0.0;
  // RIGID_TRACE: the box's height, the mean height change of the water beside it (the band of
  // the box's depth, more than 2 supports from its sides: does the water column itself settle?),
  // and the running time average of the net vertical force over the box's weight.
  const bool trace = std::getenv("RIGID_TRACE") != nullptr;
  std::vector<double> y0;
  const auto beside = [&](const double* p) {
    return p[1] > X0[1] - 0.05 && p[1] < X0[1] + 0.05 && std::abs(p[0] - X0[0]) > 0.05 + 2.0 * sim.kernel.support();
  };
  if (trace) {
    const double* x = sim.store.data(sim.store.position());
    const std::int32_t* id = sim.store.data(sim.store.id());
    for (Index i = 0; i < sim.store.realCount(); ++i) {
      if (static_cast<size_t>(id[i]) >= y0.size()) y0.resize(static_cast<size_t>(id[i]) + 1, 0.0);
      y0[static_cast<size_t>(id[i])] = x[2 * i + 1];
    }
  }
  double fIntegral = 0.0;
  while (!s.finished()) {
    const double dt = s.nextTimeStep();
    integrator->step(sim, dt);
    fIntegral += dt * rigid->bodies()[0].force[1];
    drift = std::max(drift, (rigid->bodies()[0].state.X - X0).norm());
    if (trace && (sim.step % 2000 == 0 || sim.step <= 3)) {
      const double* x = sim.store.data(sim.store.position());
      const std::int32_t* id = sim.store.data(sim.store.id());
      const std::int32_t* ph = sim.store.data(sim.store.phase());
      const double* rho = sim.store.data(sim.store.density());
      double dy = 0.0, rw = 0.0;
      int cnt = 0;
      for (Index i = 0; i < sim.store.realCount(); ++i) {
        if (ph[i] != kPhaseFluid || !beside(x + 2 * i)) continue;
        const size_t k = static_cast<size_t>(id[i]);
        dy += k < y0.size() ? x[2 * i + 1] - y0[k] : 0.0;
        rw += rho[i];
        ++cnt;
      }
      // (mean water density beside the box - box density) / box density: the buoyancy excess;
      // in the stratified weakly compressible water it sets the neutral level eps c^2 / g away
      const double eps = cnt ? (rw / cnt - rhoB) / rhoB : 0.0;
      const double weight = rigid->bodies()[0].state.mass * 9.81;
      std::printf("    t %.3f  drift %.3e  Y - Y0 %.3e  X - X0 %.3e  tilt %.3e rad  F_x/W %.3e  "
                  "water beside dy %.3e  "
                  "(rho_w - rho_b) / rho_b %.3e (neutral level %.3e m)  <F_y>/W %.3e  F_y/W %.3e\n", sim.time,
                  drift, rigid->bodies()[0].state.X[1] - X0[1],
                  rigid->bodies()[0].state.X[0] - X0[0], 2.0 * std::asin(rigid->bodies()[0].state.q.z()),
                  rigid->bodies()[0].force[0] / weight, cnt ? dy / cnt : 0.0, eps,
                  eps * 400.0 / 9.81, fIntegral / sim.time / weight,
                  rigid->bodies()[0].force[1] / weight);
    }
  }
  std::printf("  neutrally buoyant box: max drift %.3e m = %.3f dx over %.1f s (%.1f s)\n", drift,
              drift / dx, sim.time, clock.seconds());
  EXPECT_LT(drift, 0.1 * dx);
  char quantity[160];
  std::snprintf(quantity, sizeof quantity, "max drift of a neutrally buoyant box over %g s / dx%s%s%s%s",
                endTime, lid ? " (closed tank)" : "", kernel == "wendland_c2" ? "" : " (",
                kernel == "wendland_c2" ? "" : kernel.c_str(), kernel == "wendland_c2" ? "" : ")");
  recordValidation({recordName, quantity, drift / dx, 0.0, drift / dx,
                          std::string("2D, dx = h_b / 16, tank 48 x 24 dx of water") +
                              (lid ? " under a wall lid" : "") + ", density of the water at its depth, " +
                              kernel + " h = 1.3 dx",
                          clock.seconds(), "< 0.1 dx", "hydrostatics: buoyancy = weight"});
}

}  // namespace poresph::test
