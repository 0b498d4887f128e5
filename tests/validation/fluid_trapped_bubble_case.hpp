#pragma once
// The trapped-bubble scene (issue 14, Extremes: "a gas bubble trapped in a dead-end pore"): a
// periodic 2D channel of height H = 2 mm with a dead-end pore (1 mm x 1 mm) cut into its bottom
// wall, the pore full of gas, the channel of water (1000 kg/m^3, c 2 m/s, 0.01 Pa s) driven along x
// by a uniform body force; CSF surface tension (Eqs. 5.6-5.8, 1.9), wetting walls of 60 degrees
// (Eq. 1.10, prescribed contact-line normal), p_b = 100 Pa, dx = 0.1 mm, quintic h = dx. The gas
// is the water's twin by default (ratio 1); the constructor's arguments (or the hooks
// FLUID_GAS_RHO / _C / _MU and FLUID_EXTRA) make it another gas. Used by
// tests/validation/test_fluid_trapped_bubble.cpp (ratio 1) and
// tests/extreme/test_fluid_wetting_extreme.cpp (density ratio 1000, viscosity ratio 100).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"

namespace poresph::test {

inline double trappedEnv(const char* n, double d) { return std::getenv(n) ? std::atof(std::getenv(n)) : d; }

struct Trapped {
  Simulation sim{2};
  FluidModule* fluid = nullptr;
  fluidsetup::Stepper stepper;
  double dx = 1e-4, H = 2e-3, Lx = 6e-3, px0 = 2.5e-3, px1 = 3.5e-3, depth = 1e-3, Lw = 1.3e-3;
  int water = 0, gas = 1;
  // The gas (water: 1000 kg/m^3, 2 m/s, 0.01 Pa s) and extra `fluid:` keys: ratio 1 by default.
  double gasRho = 1000, gasC = 2, gasMu = 0.01;
  std::string extra;
  Trapped(double rhoG = 1000, double cG = 2, double muG = 0.01, std::string keys = "")
      : gasRho(trappedEnv("FLUID_GAS_RHO", rhoG)), gasC(trappedEnv("FLUID_GAS_C", cG)), gasMu(trappedEnv("FLUID_GAS_MU", muG)),
        extra(std::getenv("FLUID_EXTRA") ? std::getenv("FLUID_EXTRA") : keys) {
    namespace fs = poresph::fluidsetup;
    const double gamma = trappedEnv("FLUID_GAMMA", 0.05), f = trappedEnv("FLUID_FORCE", 2.0);
    sim.spacing = dx;
    sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
    const double t = 3 * dx;
    sim.domain.lo = {0, -Lw, 0};
    sim.domain.hi = {Lx, H + t, 0};
    sim.domain.periodic = {true, false, false};
    const char* mat = "{density: %.9g, sound_speed: %.9g, viscosity: %.9g, colour: %d, background_pressure: 100}";
    char buf[600];
    std::snprintf(buf, sizeof buf, mat, 1000.0, 2.0, 0.01, 1);
    water = fs::addMaterial(sim, "water", "fluid", buf);
    std::snprintf(buf, sizeof buf, mat, gasRho, gasC, gasMu, -1);
    gas = fs::addMaterial(sim, "gas", "fluid", buf);
    const int wall = fs::addMaterial(sim, "wall", "wall", "{density: 1000, contact_angle: 60}");
    std::snprintf(buf, sizeof buf, "{surface_tension: %g, gravity: [%.9g, 0]%s}", gamma, f, extra.c_str());
    fluid = fs::addFluidModule(sim, buf);
    const double a = px0, b = px1, d = depth;
    auto inPore = [=](const double* x) { return x[0] > a && x[0] < b && x[1] > -d; };
    fs::addLattice(sim, {0, 0}, {Lx, H}, water);
    fs::addLattice(sim, {0, -Lw}, {Lx, 0}, gas, inPore);
    fs::addLattice(sim, {0, -Lw}, {Lx, 0}, wall, [=](const double* x) { return !inPore(x); });
    fs::addLattice(sim, {0, H}, {Lx, H + t}, wall);
    fluid->initialise(sim);
  }
  struct State {
    double inPore = 0, xc = 0, yc = 0, uWater = 0;
  };
  // Fraction of the gas mass inside the pore (up to half a spacing above its mouth), the gas mass
  // centre, and the largest water speed.
  State measure() const {
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const double* v = st.data(st.velocity());
    const double* m = st.data(st.mass());
    const std::int32_t* mt = st.data(st.material());
    State s;
    double mg = 0, mi = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (mt[i] == water) s.uWater = std::max(s.uWater, std::hypot(v[2 * i], v[2 * i + 1]));
      if (mt[i] != gas) continue;
      mg += m[i];
      s.xc += m[i] * x[2 * i];
      s.yc += m[i] * x[2 * i + 1];
      if (x[2 * i] > px0 && x[2 * i] < px1 && x[2 * i + 1] > -depth && x[2 * i + 1] < 0.5 * dx) mi += m[i];
    }
    s.inPore = mi / mg;
    s.xc /= mg;
    s.yc /= mg;
    return s;
  }
};

/// The run: ten checks to T; the least gas fraction in the pore, the largest shift of the gas
/// mass centre, the water speed at T and the largest density variation seen at the checks.
struct TrappedRun {
  double minIn = 1.0, maxShift = 0.0, uEnd = 0.0, maxVar = 0.0;
};
inline TrappedRun runTrapped(Trapped& tr, double T) {
  TrappedRun r;
  const Trapped::State s0 = tr.measure();
  for (int k = 1; k <= 10; ++k) {
    tr.stepper.runTo(tr.sim, T * k / 10);
    const Trapped::State s = tr.measure();
    r.minIn = std::min(r.minIn, s.inPore);
    r.maxShift = std::max(r.maxShift, std::hypot(s.xc - s0.xc, s.yc - s0.yc));
    r.uEnd = s.uWater;
    r.maxVar = std::max(r.maxVar, tr.fluid->maxDensityVariation());
    std::printf("t = %.4f s: gas in pore %.4f, mass centre (%.4f, %.4f) mm, largest water speed %.4f m/s, "
                "density variation %.4f\n",
                tr.sim.time, s.inPore, 1e3 * s.xc, 1e3 * s.yc, s.uWater, tr.fluid->maxDensityVariation());
    std::fflush(stdout);
  }
  return r;
}

}  // namespace poresph::test
