// Rigid bodies (physics/rigid, docs/rigid.md), validation case 2 of issue 15 (settling): a rigid
// disc (2D cylinder) in a periodic square array, pushed along x by its own gravity through a
// viscous fluid whose opposite uniform body force keeps the total force zero (the periodic
// version of settling: no net acceleration of the box). At steady Stokes flow the disc moves
// relative to the fluid's mean velocity at U with Hasimoto's (1959) drag of a square array,
//   F = 4 pi mu U / (-ln(c)/2 - 0.738 + c - 0.887 c^2 + 2.039 c^3),   c = pi a^2 / L^2,
// where F = M_b g is the disc's weight per unit length and a the radius of the disc's particle
// area (N dx^2 = pi a^2). Re = U a / nu ~ 1e-3.
// RIGID_STOKES_PROBE="perRadius cellInRadii endTime" runs one more case and prints it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"
#include "physics/rigid/rigid_module.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

namespace {

struct StokesResult {
  double U = 0.0, Uexact = 0.0, err = 0.0, Re = 0.0, drift = 0.0, seconds = 0.0;
  double Uhalf = 0.0;  // relative velocity at 3/4 of the run (steadiness)
};

StokesResult runStokes(int perRadius, double cell, double endTime) {
  test::Stopwatch clock;
  const double a = 0.002, dx = a / perRadius;
  const int n = static_cast<int>(std::lround(cell * a / dx));
  const double L = n * dx, rho = 1000.0, mu = 1.0, G = 1.0;
  // fluid gravity balancing the disc's weight: -G M_b / M_f with M_b / M_f from the particle counts
  std::ostringstream y;
  y.precision(10);
  y << "dimension: 2\n"
    << "domain: {lo: [0, 0], hi: [" << L << ", " << L << "], periodic: [true, true]}\n"
    << "spacing: " << dx << "\nkernel: wendland_c2\nintegrator: leapfrog\n"
    << "end_time: " << endTime << "\ntime_step: {adaptive: true, cfl: 0.5}\n"
    << "output: {every_steps: 100000000}\nmaterials:\n"
    << "  - {name: oil, model: fluid, density: " << rho << ", sound_speed: 0.5, viscosity: " << mu << "}\n"
    << "  - {name: disc, model: rigid, density: " << rho << "}\n"
    << "geometry:\n"
    << "  - {shape: box, lo: [0, 0], hi: [" << L << ", " << L << "], material: oil}\n"
    << "  - {shape: sphere, centre: [" << L / 2 << ", " << L / 2 << "], radius: " << a
    << ", material: disc}\n";
  // count the disc's particles from a first load, then set the balancing fluid gravity
  const char* model = std::getenv("RIGID_STOKES_MODEL");  // probe: fluid_rigid boundary model
  const std::string extra = model ? std::string(", fluid_rigid: ") + model : std::string();
  Scene probe = loadSceneText(y.str() + "rigid: {gravity: [1, 0]}\n", "rigid_stokes.yaml");
  auto* r0 = dynamic_cast<RigidModule*>(probe.sim->module("rigid"));
  const double Nb = static_cast<double>(r0->bodies()[0].count);
  const double Nf = static_cast<double>(probe.sim->store.realCount()) - Nb;
  std::ostringstream g;
  g.precision(12);
  g << "rigid: {gravity: [" << G << ", 0]" << extra << "}\nfluid: {gravity: [" << -G * Nb / Nf << ", 0]}\n";
  Scene s = loadSceneText(y.str() + g.str(), "rigid_stokes.yaml");
  Simulation& sim = *s.sim;
  auto* rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  auto integrator = makeIntegrator("leapfrog");
  auto relative = [&]() {
    const ParticleStore& st = sim.store;
    const double* v = st.data(st.velocity());
    const double* m = st.data(st.mass());
    const std::int32_t* ph = st.data(st.phase());
    double p = 0.0, mf = 0.0;
    for (Index i = 0; i < st.realCount(); ++i)
      if (ph[i] == kPhaseFluid) {
        p += m[i] * v[i * 2];
        mf += m[i];
      }
    return rigid->bodies()[0].state.V[0] - p / mf;
  };
  StokesResult out;
  bool half = false;
  while (!s.finished()) {
    integrator->step(sim, s.nextTimeStep());
    if (!half && sim.time >= 0.75 * endTime) {
      out.Uhalf = relative();
      half = true;
    }
  }
  out.U = relative();
  const double aEff = std::sqrt(Nb * dx * dx / M_PI), c = Nb * dx * dx / (L * L);
  const double F = rigid->bodies()[0].state.mass * G;
  out.Uexact = F * (-0.5 * std::log(c) - 0.738 + c - 0.887 * c * c + 2.039 * c * c * c) / (4 * M_PI * mu);
  out.err = out.U / out.Uexact - 1.0;
  out.Re = std::abs(out.U) * aEff * rho / mu;
  out.seconds = clock.seconds();
  std::printf("  a/dx %d (a_eff %.3f dx), cell %.0f a (%lld particles), c = %.4f, t = %.3f s (%lld "
              "steps): U = %.5e m/s (at 3/4: %.5e), Hasimoto %.5e: %+.2f %%; Re %.1e; %.1f s\n",
              perRadius, aEff / dx, cell, static_cast<long long>(sim.store.realCount()), c, sim.time,
              static_cast<long long>(sim.step), out.U, out.Uhalf, out.Uexact, 100 * out.err, out.Re,
              out.seconds);
  return out;
}

}  // namespace

TEST(RigidStokes, Probe) {
  const char* env = std::getenv("RIGID_STOKES_PROBE");
  if (!env) GTEST_SKIP() << "set RIGID_STOKES_PROBE=\"perRadius cellInRadii endTime\"";
  std::istringstream in(env);
  int n = 4;
  double cell = 10.0, T = 0.5;
  in >> n >> cell >> T;
  runStokes(n, cell, T);
}

// a = 4 dx, cell 10 a (1,600 particles), 0.15 s (~5,700 steps): measured U +8.4 % above Hasimoto
// (steady: the velocity at 3/4 of the run equals the final one to 0.03 %); a = 6 dx at 0.1 s
// +6.9 % at 0.2 s (steady); a = 4 dx in a cell of 16 a: +3.6 % (docs/rigid.md).
TEST(RigidStokes, DiscInAPeriodicArraySettlesAtHasimotosVelocity) {
  const StokesResult r = runStokes(4, 10.0, 0.15);
  EXPECT_LT(std::abs(r.err), 0.10) << "terminal velocity against Hasimoto";
  EXPECT_LT(std::abs(r.Uhalf / r.U - 1.0), 0.01) << "not steady";
  EXPECT_LT(r.Re, 0.01) << "not Stokes flow";
  test::recordValidation({"rigid_stokes_hasimoto", "terminal velocity of a disc in a periodic array (m/s)",
                          r.U, r.Uexact, std::abs(r.err), "2D, a = 4 dx, cell 10 a, 1,600 particles",
                          r.seconds, "< 10 %", "Hasimoto 1959, square array of cylinders, Stokes flow"});
}
