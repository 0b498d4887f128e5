#pragma once
// Scene and protocol of the validation (issue 5, beyond its list): the rising-bubble benchmark of Hysing et al. (2009),
// test case 1 - the standard quantitative check of two-phase surface-tension codes:
//   domain [0,1] x [0,2], no-slip walls at y = 0 and y = 2, free slip at x = 0 and x = 1,
//   bubble of radius 0.25 centred at (0.5, 0.5); rho1 = 1000, rho2 = 100, mu1 = 10, mu2 = 1,
//   g = 0.98, sigma = 24.5 (Re = 35, Eo = 10), t in [0, 3].
// Reference values (finest grid of the TP2D code in Hysing et al. 2009, Table 4, the three codes
// agree to < 1 %): maximum rise velocity 0.2417 at t = 0.921, centroid height 1.0813 at t = 3.
// Free slip at x = 0 and x = 1 is obtained exactly with a periodic x axis of width 1: the flow is
// symmetric about x = 0.5, so u_x vanishes on x = 0 and x = 1 (the periodic image is the mirror
// image). Weakly compressible: c = 10 m/s in both phases (Mach 0.024 at the peak velocity; rho g H
// / (rho c^2) = 2 % in the water).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"
#include "tests/support/validation_record.hpp"

namespace poresph::test {


struct RiseResult {
  double vMax = 0, tvMax = 0, yEnd = 0, xDrift = 0;
  long long steps = 0;
  double wall = 0;
};

inline RiseResult runHysing1(int rOverDx, const std::string& dumpName) {
  Stopwatch clock;
  Simulation sim(2);
  const double R = 0.25, dx = R / rOverDx, Lx = 1.0, Ly = 2.0, t = 3 * dx;
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
  sim.domain.lo = {0, -t - dx, 0};
  sim.domain.hi = {Lx, Ly + t + dx, 0};
  sim.domain.periodic = {true, false, false};
  const int liq = fluidsetup::addMaterial(sim, "liquid", "fluid", "{density: 1000, sound_speed: 10, viscosity: 10, colour: 1, background_pressure: 100}");
  const int gas = fluidsetup::addMaterial(sim, "gas", "fluid", "{density: 100, sound_speed: 30, viscosity: 1, colour: -1, background_pressure: 100}");
  const int wall = fluidsetup::addMaterial(sim, "wall", "wall", "{density: 1000}");
  // FLUID_EXTRA: extra fluid keys (", key: value") for studies, e.g. ", shifting: 1"
  const std::string extra = std::getenv("FLUID_EXTRA") ? std::getenv("FLUID_EXTRA") : "";
  FluidModule* fluid = fluidsetup::addFluidModule(
      sim, "{surface_tension: 24.5, pressure_gradient: hu_adams, wall_wetting: false, "
           "gravity: [0, -0.98], hydrostatic_level: 2.0" + extra + "}");
  auto inBubble = [&](const double* x) { return std::hypot(x[0] - 0.5, x[1] - 0.5) < R; };
  fluidsetup::addLattice(sim, {0, 0}, {Lx, Ly}, gas, inBubble);
  fluidsetup::addLattice(sim, {0, 0}, {Lx, Ly}, liq, [&](const double* x) { return !inBubble(x); });
  fluidsetup::addLattice(sim, {0, -t}, {Lx, 0}, wall);
  fluidsetup::addLattice(sim, {0, Ly}, {Lx, Ly + t}, wall);
  fluid->initialise(sim);
  auto centroid = [&](double& cx, double& cy, double& vy) {
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const double* v = st.data(st.velocity());
    const double* col = st.data(fluid->colour);
    const double* m = st.data(st.mass());
    const std::int32_t* ph = st.data(st.phase());
    double n = 0;
    cx = cy = vy = 0;
    for (Index i = 0; i < st.realCount(); ++i)
      if (ph[i] == kPhaseFluid && col[i] < 0) {
        const double X = x[2 * i] - Lx * std::round(x[2 * i] - 0.5);  // unwrap about 0.5
        cx += m[i] * X, cy += m[i] * x[2 * i + 1], vy += m[i] * v[2 * i + 1], n += m[i];
      }
    cx /= n, cy /= n, vy /= n;
  };
  fluidsetup::Stepper stepper;
  RiseResult r;
  std::ofstream hist(std::string(PORESPH_BINARY_DIR) + "/" + dumpName + "_history.txt");
  const double tEnd = std::getenv("FLUID_TEND") ? std::atof(std::getenv("FLUID_TEND")) : 3.0;
  double nextOut = 0.0;
  while (sim.time < tEnd * (1 - 1e-12)) {
    stepper.step(sim, tEnd - sim.time);
    double cx, cy, vy;
    centroid(cx, cy, vy);
    if (vy > r.vMax) r.vMax = vy, r.tvMax = sim.time;
    if (sim.time >= nextOut) {
      hist << sim.time << " " << cy << " " << vy << " " << fluid->maxDensityVariation() << "\n";
      nextOut += 0.05;
    }
  }
  sim.checkFinite();
  double cx, cy, vy;
  centroid(cx, cy, vy);
  r.yEnd = cy;
  r.xDrift = cx - 0.5;
  r.steps = sim.step;
  const auto& st = sim.store;
  const double* x = st.data(st.position());
  const double* col = st.data(fluid->colour);
  const std::int32_t* ph = st.data(st.phase());
  std::ofstream f(std::string(PORESPH_BINARY_DIR) + "/" + dumpName + ".txt");
  for (Index i = 0; i < st.realCount(); ++i)
    f << x[2 * i] << " " << x[2 * i + 1] << " " << (ph[i] == kPhaseFluid ? col[i] : 0.0) << "\n";
  r.wall = clock.seconds();
  return r;
}


/// Runs case 1 at R/dx = rdx, prints, asserts (velocity and height within 5 %) and records.
inline void checkHysing1(int rdx) {
  const RiseResult r = runHysing1(rdx, "fluid_rising_bubble_hysing1_r" + std::to_string(rdx));
  const double vRef = 0.2417, yRef = 1.0813, tRef = 0.921;
  const double eV = std::abs(r.vMax - vRef) / vRef, eY = std::abs(r.yEnd - yRef) / yRef;
  std::printf("Hysing case 1, R/dx = %d: max rise velocity %.4f at t = %.3f (ref %.4f at %.3f, %.2f %%), "
              "centroid at t = 3: %.4f (ref %.4f, %.2f %%), x drift %.2e, %lld steps, %.1f s\n",
              rdx, r.vMax, r.tvMax, vRef, tRef, 100 * eV, r.yEnd, yRef, 100 * eY, r.xDrift, r.steps, r.wall);
  const std::string res = "R/dx = " + std::to_string(rdx) +
                          " (dx = 1/" + std::to_string(4 * rdx) + "), quintic h = dx, c = 10 (water) / 30 (gas) m/s, hu_adams";
  EXPECT_LT(eV, 0.05);
  EXPECT_LT(eY, 0.05);
  EXPECT_LT(std::abs(r.xDrift), 0.01);
  recordValidation({"fluid_rising_bubble_hysing1_r" + std::to_string(rdx), "maximum rise velocity", r.vMax, vRef, eV, res,
                          r.wall, "< 5 %", "Hysing et al. 2009, case 1 (TP2D, finest grid)"});
  recordValidation({"fluid_rising_bubble_hysing1_r" + std::to_string(rdx), "centroid height at t = 3", r.yEnd, yRef, eY, res,
                          r.wall, "< 5 %", "Hysing et al. 2009, case 1 (TP2D, finest grid)"});
}

}  // namespace poresph::test
