// Fluid under a negative gauge pressure at fixed walls (issue 14 H5): with
// `pressure_reference: background` the pressure forces use p - p_b, and where it is negative the
// walls' extrapolated pressure (Adami et al. 2012) pulls the fluid into the wall. Found in the
// main job (samples/drainage_ketton_3d.yaml): gas of the outlet reservoir, at p - p_b ~ -45 to
// -67 Pa, went up to 0.66 dx beyond the x / y wall faces; the wall pairs pulled it in at
// 300-800 m/s^2 while its CSF acceleration (Eq. 1.9) was ~1 m/s^2 (docs/fluid.md "Fluid at the
// walls under a negative gauge pressure").
// Scene: a closed 2D box 20 x 16 dx (dx = 0.1 mm, quintic h = dx, three wall layers, contact
// angle 60 degrees), water below gas at equal densities (c = 5 m/s, p_b = 600 Pa, viscosities
// 0.01 / 0.001 Pa s, gamma = 0.002 N/m: the main job's fluids), gravity 150 m/s^2 downwards with
// the hydrostatic start from the floor (hydrostatic_level 0): p - p_b = -rho g y, -240 Pa at the
// ceiling. Without fluid.wall_background_pressure (default false) fluid particles go beyond the
// wall faces (2 particles, up to 0.143 dx, from ~12 ms); with it none do. The second case runs
// fluid.wall_push_only (issue 16, the drainage scenes' setting): the fixed walls' pair force with
// the positive parts of the gauge pressures, so it never pulls; none beyond either.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

namespace {

struct WallTensionResult {
  int worstCount = 0;
  double worstDepth = -1e300;  // m, < 0: inside
  double densityVariation = 0.0;
  long long steps = 0;
  double seconds = 0.0;
};

// The box below with `key` (", wall_background_pressure: true" or ", wall_push_only: true") in
// the fluid section; WALL_TENSION_FORMER=1 runs without it (the former behaviour, which both
// cases fail); WALL_TENSION_EXTRA: extra fluid keys (", k: v").
WallTensionResult runWallTensionBox(const std::string& key) {
  namespace fs = poresph::fluidsetup;
  test::Stopwatch clock;
  const double dx = 1e-4, L = 2e-3, H = 1.6e-3, t = 3 * dx;
  Simulation sim(2);
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
  sim.domain.lo = {-t, -t, 0};
  sim.domain.hi = {L + t, H + t, 0};
  sim.domain.periodic = {false, false, false};
  const int water = fs::addMaterial(sim, "water", "fluid",
                                    "{density: 1000, sound_speed: 5, viscosity: 0.01, colour: 1, background_pressure: 600}");
  const int gas = fs::addMaterial(sim, "gas", "fluid",
                                  "{density: 1000, sound_speed: 5, viscosity: 0.001, colour: -1, background_pressure: 600}");
  const int wall = fs::addMaterial(sim, "wall", "wall", "{density: 1000, contact_angle: 60}");
  std::string extra = std::getenv("WALL_TENSION_FORMER") ? "" : key;
  if (std::getenv("WALL_TENSION_EXTRA")) extra += std::getenv("WALL_TENSION_EXTRA");
  FluidModule* fluid = fs::addFluidModule(
      sim, "{surface_tension: 0.002, pressure_reference: background, gravity: [0, -150], hydrostatic_level: 0" +
               extra + "}");
  auto inside = [=](const double* x) { return x[0] > 0 && x[0] < L && x[1] > 0 && x[1] < H; };
  fs::addLattice(sim, {0, 0}, {L, H}, water, [=](const double* x) { return x[1] < 0.5 * H; });
  fs::addLattice(sim, {0, 0}, {L, H}, gas, [=](const double* x) { return x[1] > 0.5 * H; });
  fs::addLattice(sim, {-t, -t}, {L + t, H + t}, wall, [=](const double* x) { return !inside(x); });
  fluid->initialise(sim);
  fs::Stepper stepper;
  // Depth of the deepest fluid particle beyond a wall face (< 0: inside the box; the first
  // layer sits 0.5 dx from the faces) and the count of those beyond, every 0.5 ms to 20 ms.
  WallTensionResult res;
  for (int k = 1; k <= 40; ++k) {
    stepper.runTo(sim, 0.0005 * k);
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const std::int32_t* mt = st.data(st.material());
    int count = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (mt[i] != water && mt[i] != gas) continue;
      const double d = std::max({-x[2 * i], x[2 * i] - L, -x[2 * i + 1], x[2 * i + 1] - H});
      res.worstDepth = std::max(res.worstDepth, d);
      if (d > 0.0) ++count;
    }
    res.worstCount = std::max(res.worstCount, count);
  }
  res.densityVariation = fluid->maxDensityVariation();
  res.steps = static_cast<long long>(sim.step);
  res.seconds = clock.seconds();
  std::printf("%s: fluid beyond the wall faces: at most %d particles, deepest %.3f dx (< 0: inside), max density "
              "variation %.3g, %lld steps, %.1f s\n",
              key.c_str(), res.worstCount, res.worstDepth / dx, res.densityVariation, res.steps, res.seconds);
  return res;
}

}  // namespace

TEST(FluidWallTension, NoFluidBeyondTheWallFacesUnderNegativeGaugePressure) {
  const double dx = 1e-4;
  const WallTensionResult r = runWallTensionBox(", wall_background_pressure: true");
  EXPECT_EQ(r.worstCount, 0);
  EXPECT_LT(r.worstDepth, 0.0);
  test::recordValidation({"fluid_wall_tension_2d", "deepest fluid particle beyond the wall faces / dx (< 0: none beyond)",
                          r.worstDepth / dx, 0.0, r.worstDepth / dx,
                          "closed box 20 x 16 dx, quintic h = dx, water / gas at equal densities, c = 5 m/s, "
                          "p_b = 600 Pa (pressure_reference: background), gamma 0.002 N/m, 60 deg, g = 150 m/s^2, "
                          "p - p_b = -240 Pa at the ceiling, 20 ms",
                          r.seconds, "< 0 (no fluid particle beyond a wall face)",
                          "impermeable wall (Adami et al. 2012 with a positive pressure in the force)"});
}

// wall_push_only (the drainage scenes' setting): the same box, none beyond the faces; without
// the key (WALL_TENSION_FORMER=1) 2 particles go 0.143 dx beyond, and the test fails.
TEST(FluidWallTension, WallPushOnlyKeepsTheFluidInsideUnderNegativeGaugePressure) {
  const double dx = 1e-4;
  const WallTensionResult r = runWallTensionBox(", wall_push_only: true");
  EXPECT_EQ(r.worstCount, 0);
  EXPECT_LT(r.worstDepth, 0.0);
  test::recordValidation({"fluid_wall_tension_push_only_2d",
                          "deepest fluid particle beyond the wall faces / dx (< 0: none beyond)",
                          r.worstDepth / dx, 0.0, r.worstDepth / dx,
                          "closed box 20 x 16 dx, quintic h = dx, water / gas at equal densities, c = 5 m/s, "
                          "p_b = 600 Pa (pressure_reference: background, wall_push_only), gamma 0.002 N/m, 60 deg, "
                          "g = 150 m/s^2, p - p_b = -240 Pa at the ceiling, 20 ms",
                          r.seconds, "< 0 (no fluid particle beyond a wall face)",
                          "impermeable wall (Adami et al. 2012; the wall pair with max(p - p_b, 0))"});
}
