// Validation 4 of issue 4: 2D cantilever plate in free vibration (the benchmark of Gray, Monaghan
// and Swift 2001), plane strain, clamped by a mirror layer at x = 0, released with the first
// bending mode shape as initial velocity. First-mode frequency against thin-plate theory
// omega^2 = E H^2 k^4 / (12 rho (1 - nu^2)), k L = 1.875, within 5 %. Total Lagrangian with the
// conservative hourglass control (material key `hourglass`, docs/solid.md): kinetic + elastic +
// hourglass penalty energy conserved to 1 %.
#include <gtest/gtest.h>

#include <cmath>

#include "physics/solid/solid_scenes.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
using namespace poresph::solid;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Result {
  double omega = 0.0, reference = 0.0, wall = 0.0, energyDrift = 0.0;
  Index particles = 0;
};

Result runCantilever(const std::string& formulation, int layersAcross, const std::string& extra = "", double cfl = 0.9) {
  test::Stopwatch clock;
  const double L = 0.2, H = 0.02, E = 2.0e6, nu = 0.3, rho = 1000.0;
  const double dx = H / layersAcross;
  Simulation sim(2);
  addMaterial(sim, "plate", "elastic",
              "{density: 1000, young_modulus: 2.0e6, poisson_ratio: 0.3, formulation: " + formulation + extra + "}");
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::CubicSpline, 2, 1.3 * dx);
  const int clampLayers = 2 * static_cast<int>(std::ceil(sim.kernel.support() / dx)) + 1;
  const int nx = static_cast<int>(std::lround(L / dx));
  buildBlock<2>(sim, Vec<2>(-clampLayers * dx, -0.5 * H), {nx + clampLayers, layersAcross, 1}, dx);
  sim.domain.lo = {-(clampLayers + 1) * dx, -H, 0};
  sim.domain.hi = {L + dx, H, 1};
  ElasticSolidModule& solid = addSolidModule(
      sim, "{boundaries: [{name: clamp, type: clamped, box: {min: [-1, -1], max: [0, 1]}, "
           "mirror: {point: [0, 0], normal: [1, 0]}}]}");
  solid.initialise(sim);
  // first bending mode of a clamped-free beam as the initial vertical velocity
  const double kL = 1.875104068711961, k = kL / L;
  auto mode = [&](double x) {
    return (std::cos(kL) + std::cosh(kL)) * (std::cosh(k * x) - std::cos(k * x)) +
           (std::sin(kL) - std::sinh(kL)) * (std::sinh(k * x) - std::sin(k * x));
  };
  const double vTip = 0.01;
  ParticleStore& s = sim.store;
  std::int32_t probe = -1;
  double best = 1e9;
  for (Index i = 0; i < s.realCount(); ++i) {
    const Vec<2> x = s.vec<2>(s.position(), i);
    if (s.data(sim.motion)[i] == kMotionFree) s.vec<2>(s.velocity(), i) = Vec<2>(0.0, vTip * mode(x[0]) / mode(L));
    const double d = std::abs(x[0] - (L - 0.5 * dx)) + std::abs(x[1] - 0.5 * dx);
    if (d < best) { best = d; probe = s.data(s.id())[i]; }
  }
  Result r;
  r.reference = std::sqrt(E * H * H * std::pow(k, 4) / (12.0 * rho * (1.0 - nu * nu)));
  auto integrator = makeIntegrator("leapfrog");
  const double dt = cfl * solid.elasticTimeStepLimit(sim);
  const long steps = static_cast<long>(1.65 * 2.0 * kPi / r.reference / dt);
  std::vector<double> ts, vs;
  double e0 = -1.0;
  for (long n = 0; n < steps; ++n) {
    integrator->step(sim, dt);
    const std::int32_t* id = s.data(s.id());
    for (Index i = 0; i < s.realCount(); ++i)
      if (id[i] == probe) {
        ts.push_back(sim.time);
        vs.push_back(s.vec<2>(s.real("displacement"), i)[1]);  // tip deflection: zero at T/2, T, 3T/2
        break;
      }
    if (n % 200 == 0) {
      // the conservative hourglass control stores a penalty energy (docs/solid.md); dissipated:
      // 0 here (no damping, no artificial viscosity), kept so the sum is the module's balance
      const double e = solid.kineticEnergy(sim) + solid.elasticEnergy(sim) +
                       solid.hourglassEnergy(sim) + solid.work(sim)[2];
      if (e0 < 0) e0 = e;
      r.energyDrift = std::max(r.energyDrift, std::abs(e - e0) / e0);
    }
  }
  const auto cr = zeroCrossings(ts, vs);
  const double period = periodFromCrossings(cr);
  r.omega = period > 0.0 ? 2.0 * kPi / period : 0.0;
  r.wall = clock.seconds();
  r.particles = s.realCount();
  return r;
}

}  // namespace

TEST(SolidCantilever, FirstModeAgainstThinPlateTheory) {
  // Plain TL (hourglass: 0) develops zero-energy modes in bending and inverts a particle after
  // about one period (measured: J < 0 at t = 0.30 s). Conservative hourglass control (the
  // default form): 3 keeps it stable with the energy to 0.3 %; 1 and 2 let the zero-energy mode
  // that the mirror clamp excites grow after one period (energy +7.5 % / +2.3 % at 1.65
  // periods). The pairwise form at 1 dissipates 13 % of the energy over the same time, about
  // what the clamp injects (docs/solid.md "Hourglass control").
  const Result r = runCantilever("total_lagrangian", 12, ", hourglass: 3.0");
  const double err = std::abs(r.omega - r.reference) / r.reference;
  std::printf("cantilever: omega = %.4f rad/s, thin plate %.4f (%.2f %%), energy drift %.2e, %lld particles, %.1f s\n",
              r.omega, r.reference, 100 * err, r.energyDrift, static_cast<long long>(r.particles), r.wall);
  test::recordValidation({"solid_cantilever_2d", "first bending frequency omega", r.omega, r.reference, err,
                          "L/H = 10, 12 particles across, h = 1.3 dx, plane strain, nu = 0.3, TL + hourglass 3", r.wall,
                          "< 5 %", "thin-plate theory omega^2 = E H^2 k^4 / (12 rho (1 - nu^2)), kL = 1.875"});
  test::recordValidation({"solid_cantilever_2d", "energy drift over 1.65 periods", r.energyDrift, 0.0,
                          r.energyDrift, "12 particles across, TL + conservative hourglass 3", r.wall, "< 1 %",
                          "energy conservation (kinetic + elastic + hourglass penalty)"});
  EXPECT_LT(err, 0.05);
  EXPECT_LT(r.energyDrift, 0.01);
}
