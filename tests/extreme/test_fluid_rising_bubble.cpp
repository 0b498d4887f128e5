// Extreme (issue 5): a gas bubble rising in water at density ratio 1000 and viscosity ratio 100
// (the thesis' mobility 1e-2) in a closed wall box under gravity, CSF surface tension
// (Eqs. 5.6-5.8, 1.9), `pressure_gradient: hu_adams`. The initial pressure is hydrostatic
// through the bubble (`hydrostatic_level`: the column integration gives the gas the water's
// pressure at its depth). Over many capillary relaxation times mu_l R / gamma the run must stay
// finite, no particle may leave the box, the bubble must stay one piece and rise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"

using namespace poresph;
namespace fs = poresph::fluidsetup;

TEST(FluidExtreme, RisingBubbleDensityRatio1000) {
  Simulation sim(2);
  // FLUID_RDX, FLUID_GAS_PB, FLUID_EXTRA (module keys): variants for the robustness study in
  // docs/fluid.md
  const double rdx = std::getenv("FLUID_RDX") ? std::atof(std::getenv("FLUID_RDX")) : 8.0;
  const double R = 1.5e-3, dx = R / rdx, Wd = 4 * R, H = 8 * R, gamma = 0.05, muL = 0.1;
  const double tRelax = muL * R / gamma;  // 3 ms
  const double t = 3 * dx;                // wall thickness (quintic support, h = dx)
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
  sim.domain.lo = {-t - dx, -t - dx, 0};
  sim.domain.hi = {Wd + t + dx, H + t + dx, 0};
  const int liq = fs::addMaterial(sim, "water", "fluid",
                                  "{density: 1000, sound_speed: 3, viscosity: 0.1, colour: 1, background_pressure: 100}");
  char buf[300];
  std::snprintf(buf, sizeof buf, "{density: 1, sound_speed: 40, viscosity: 1.0e-3, colour: -1, background_pressure: %s}",
                std::getenv("FLUID_GAS_PB") ? std::getenv("FLUID_GAS_PB") : "220");
  const int gas = fs::addMaterial(sim, "gas", "fluid", buf);
  const int wall = fs::addMaterial(sim, "wall", "wall", "{density: 1000}");
  std::snprintf(buf, sizeof buf,
                "{surface_tension: %g, pressure_gradient: hu_adams, wall_wetting: false, "
                "gravity: [0, -9.81], hydrostatic_level: %.17g%s}", gamma, H,
                std::getenv("FLUID_EXTRA") ? std::getenv("FLUID_EXTRA") : "");
  FluidModule* fluid = fs::addFluidModule(sim, buf);
  const double cx0 = 0.5 * Wd, cy0 = 2.0 * R;
  auto inBubble = [&](const double* x) { return std::hypot(x[0] - cx0, x[1] - cy0) < R; };
  fs::addLattice(sim, {0, 0}, {Wd, H}, gas, inBubble);
  fs::addLattice(sim, {0, 0}, {Wd, H}, liq, [&](const double* x) { return !inBubble(x); });
  fs::addLattice(sim, {-t, -t}, {Wd + t, H + t}, wall,
                 [&](const double* x) { return x[0] < 0 || x[0] > Wd || x[1] < 0 || x[1] > H; });
  fluid->initialise(sim);
  fs::Stepper stepper;
  const double tEnd = 8.0 * tRelax;  // 24 ms
  double worstVar = 0.0;
  auto centroid = [&](double& cx, double& cy, double& vy) {
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const double* v = st.data(st.velocity());
    const double* col = st.data(fluid->colour);
    const std::int32_t* ph = st.data(st.phase());
    double n = 0;
    cx = cy = vy = 0;
    for (Index i = 0; i < st.realCount(); ++i)
      if (ph[i] == kPhaseFluid && col[i] < 0) cx += x[2 * i], cy += x[2 * i + 1], vy += v[2 * i + 1], n += 1;
    cx /= n, cy /= n, vy /= n;
  };
  while (sim.time < tEnd * (1 - 1e-12)) {
    stepper.step(sim, tEnd - sim.time);
    worstVar = std::max(worstVar, fluid->maxDensityVariation());
    if (std::getenv("FLUID_DEBUG") && sim.step % 1000 == 0) {
      double cx, cy, vy;
      centroid(cx, cy, vy);
      std::printf("t %.4e  centroid y %.4f R  rise velocity %.4e m/s  variation %.3g %%\n", sim.time,
                  cy / R, vy, 100 * fluid->maxDensityVariation());
    }
  }
  sim.checkFinite();
  double cx, cy, vy;
  centroid(cx, cy, vy);
  const auto& st = sim.store;
  const double* x = st.data(st.position());
  const double* col = st.data(fluid->colour);
  const std::int32_t* ph = st.data(st.phase());
  int outside = 0;
  double farthestGas = 0.0, nearestLiquid = 1e9;
  for (Index i = 0; i < st.realCount(); ++i) {
    if (ph[i] != kPhaseFluid) continue;
    if (x[2 * i] < 0 || x[2 * i] > Wd || x[2 * i + 1] < 0 || x[2 * i + 1] > H) ++outside;
    const double r = std::hypot(x[2 * i] - cx, x[2 * i + 1] - cy);
    if (col[i] < 0) farthestGas = std::max(farthestGas, r);
    else nearestLiquid = std::min(nearestLiquid, r);
  }
  {
    std::ofstream f(std::string(PORESPH_BINARY_DIR) + "/fluid_rising_bubble.txt");
    const double* v = st.data(st.velocity());
    for (Index i = 0; i < st.realCount(); ++i)
      f << x[2 * i] << " " << x[2 * i + 1] << " " << (ph[i] == kPhaseFluid ? col[i] : 0.0) << " "
        << std::hypot(v[2 * i], v[2 * i + 1]) << "\n";
  }
  std::printf("rising bubble, density ratio 1000: %lld steps to %.1f relaxation times, max density "
              "variation %.3g %%, centroid rose %.3f R (x drift %.3f R), rise velocity %.3e m/s, "
              "farthest gas %.2f R, nearest liquid %.2f R, %d outside\n",
              static_cast<long long>(sim.step), sim.time / tRelax, 100 * worstVar, (cy - cy0) / R,
              (cx - cx0) / R, vy, farthestGas / R, nearestLiquid / R, outside);
  EXPECT_EQ(outside, 0);               // no particle crosses a wall
  EXPECT_GT(cy - cy0, 0.2 * R);        // it rises
  EXPECT_GT(vy, 0.0);
  EXPECT_LT(std::abs(cx - cx0), 0.2 * R);  // on the axis (symmetry)
  EXPECT_LT(farthestGas, 2.0 * R);     // one piece
  EXPECT_GT(nearestLiquid, 0.3 * R);   // no water inside
  EXPECT_LT(worstVar, 0.10);
}
