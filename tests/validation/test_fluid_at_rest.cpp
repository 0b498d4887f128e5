// Water at rest under a free surface stays at rest (issue 15 validation 2's tank, fluid quality;
// docs/fluid.md "Water at rest on the lattice"). A 2D tank of water under gravity, started on the
// square lattice with the hydrostatic density (hydrostatic_level = the surface), with the
// floating test's dx (6.25 mm), sound speed (20 m/s), viscosity (1e-3 Pa s) and artificial
// viscosity (0.1), narrowed to 16 x 16 particles so that it runs in seconds.
//
// With the symmetric pressure force (Eq. 5.2b) every pair pushes with p_a/rho_a^2 + p_b/rho_b^2,
// so under a positive pressure a particle is driven down the gradient of its own kernel sum
// sum_b W_ab. On a square lattice a transverse mode changes no density to first order (no
// restoring force from the EOS, Eq. 1.4), and the lattice is stable only where the kernel sum is
// a minimum for every transverse displacement: with Wendland C2 at h = 1.3 dx it is not (adjacent
// rows sliding against each other, k dx = pi, grow at 0.249 sqrt(p / rho) / dx: 48 /s at the
// floating tank's bottom), with the quintic spline at h = 1.3 dx it is (lattice sums:
// scripts/lattice_stability.py). The test runs the fixed set-up (quintic spline), disturbs it by
// rows sliding against each other at 1e-4 m/s, and asserts that the water returns to rest: rms
// speed over the last third of 1 s below 3e-4 m/s (measured 4.9e-5 m/s; 11 s CPU, loaded).
// FLUID_REST_KERNEL=wendland_c2 runs the unstable lattice: 1.9e-3 m/s, the test fails.
// Studies: FLUID_REST_T (end time), FLUID_REST_SEED (m/s), FLUID_REST_TRACE.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

namespace {

std::string restTank(const std::string& kernel, double endTime) {
  char buf[1536];
  std::snprintf(buf, sizeof buf, R"(dimension: 2
domain: {lo: [-0.01875, -0.01875], hi: [0.11875, 0.2]}
spacing: 0.00625
kernel: %s
integrator: leapfrog
end_time: %g
time_step: {adaptive: true, cfl: 0.5}
output: {every_steps: 1000000}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 20, viscosity: 1.0e-3}
  - {name: tank, model: wall, density: 1000}
geometry:
  - {shape: box, lo: [-0.01875, -0.01875], hi: [0.11875, 0.15], material: tank}
  - {shape: box, lo: [0.0, 0.0], hi: [0.1, 0.15], material: none}
  - {shape: box, lo: [0.0, 0.0], hi: [0.1, 0.1], material: water}
fluid: {gravity: [0, -9.81], hydrostatic_level: 0.1, artificial_viscosity: 0.1}
)",
                kernel.c_str(), endTime);
  return buf;
}

struct RestResult {
  double rmsLate = 0.0;   // largest rms speed of the water over the last third of the run
  double rmsStart = 0.0;  // largest rms speed over the first 0.1 s (the start's settling)
  double seconds = 0.0;
};

RestResult runRest(const std::string& kernel, double endTime, double seed) {
  test::Stopwatch clock;
  Scene s = loadSceneText(restTank(kernel, endTime), "rest_tank.yaml");
  Simulation& sim = *s.sim;
  auto integrator = makeIntegrator("leapfrog");
  RestResult r;
  {  // the disturbance: rows of particles sliding against each other, v_x = +-seed by row
    ParticleStore& st = sim.store;
    double* v = st.data(st.velocity());
    const double* x = st.data(st.position());
    const std::int32_t* ph = st.data(st.phase());
    for (Index i = 0; i < st.realCount(); ++i)
      if (ph[i] == kPhaseFluid)
        v[2 * i] = (static_cast<long>(std::floor(x[2 * i + 1] / sim.spacing)) % 2 == 0 ? seed : -seed);
  }
  while (!s.finished()) {
    integrator->step(sim, s.nextTimeStep());
    if (sim.step % 50 != 0) continue;
    const ParticleStore& st = sim.store;
    const double* v = st.data(st.velocity());
    const std::int32_t* ph = st.data(st.phase());
    double v2 = 0.0;
    int n = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (ph[i] != kPhaseFluid) continue;
      v2 += v[2 * i] * v[2 * i] + v[2 * i + 1] * v[2 * i + 1];
      ++n;
    }
    const double rms = std::sqrt(v2 / n);
    if (sim.time < 0.1) r.rmsStart = std::max(r.rmsStart, rms);
    if (sim.time > endTime * 2.0 / 3.0) r.rmsLate = std::max(r.rmsLate, rms);
    if (std::getenv("FLUID_REST_TRACE") && sim.step % 2000 == 0)
      std::printf("    t %.3f  rms speed %.3e m/s\n", sim.time, rms);
  }
  r.seconds = clock.seconds();
  std::printf("  %s: rms speed of the water, first 0.1 s max %.3e m/s, last third max %.3e m/s "
              "(%.1f s)\n", kernel.c_str(), r.rmsStart, r.rmsLate, r.seconds);
  return r;
}

}  // namespace

TEST(FluidAtRest, FreeSurfaceTankOnAStableLatticeStaysAtRest) {
  const char* env = std::getenv("FLUID_REST_KERNEL");
  const std::string kernel = env ? env : "quintic_spline";
  const double endTime = std::getenv("FLUID_REST_T") ? std::atof(std::getenv("FLUID_REST_T")) : 1.0;
  const double seed = std::getenv("FLUID_REST_SEED") ? std::atof(std::getenv("FLUID_REST_SEED")) : 1.0e-4;
  const RestResult r = runRest(kernel, endTime, seed);
  // Measured over 0.67-1 s (rows disturbed at 1e-4 m/s, the start's settling 8e-4 m/s): quintic
  // spline 4.9e-5 m/s (decaying), Wendland C2 1.9e-3 m/s (rows sliding from ~0.4 s on, saturated
  // by 0.9 s). The bound, 3e-4 m/s (0.1 % of sqrt(g H) = 0.31 m/s), is 6x either way.
  EXPECT_LT(r.rmsLate, 3.0e-4);
  test::recordValidation({"fluid_rest_free_surface", "largest rms speed of water at rest over 0.67-1 s (m/s)",
                          r.rmsLate, 0.0, r.rmsLate,
                          "2D tank 16 x 16 dx of water, free surface, dx 6.25 mm, " + kernel + " h = 1.3 dx",
                          r.seconds, "< 3e-4 m/s", "hydrostatics: water at rest stays at rest"});
}
