#pragma once
// The pressurised spherical pore on body-fitted shells (issue 11, item 3, 3D): one run used by
// test_pore_shells_3d.cpp (default suite) and test_pore_shells_3d_long.cpp (finer shells).
// A spherical cavity of water at pressure p in a thick elastic sphere a <= r <= b whose particles
// sit on body-fitted shells (Fibonacci spirals, physics/solid/solid_scenes.hpp appendShells); the
// water fills the cavity on shells a - (k + 1/2) dx down to the centre (the same layout), so that
// no lattice staircase or gap lies at the wall. The clay is loaded only through the fluid-solid
// pairs (Eqs. 1.37-1.38 by extended summation, Sec. 5.1). Dynamic relaxation (solid damping) to
// the static state; then the mean radial displacement and hoop stress of the innermost shells
// against Lame's thick sphere (outer surface free) at the mean pressure the water holds then:
//   u(r) = p a^3 / (E (b^3 - a^3)) [(1 - 2 nu) r + (1 + nu) b^3 / (2 r^2)],
//   sigma_t(r) = p a^3 / (b^3 - a^3) (1 + b^3 / (2 r^3)),
//   sigma_r(r) = p a^3 / (b^3 - a^3) (1 - b^3 / r^3)   (derivation: docs/coupling.md).
// The lattice (staircase) twin is CouplingPore.PressurisedSphericalVoxelPoreAgainstLame.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "libcore/fluid_pair_terms.hpp"
#include "libcore/integrator.hpp"
#include "libcore/output.hpp"
#include "libcore/phases.hpp"
#include "libcore/simulation.hpp"
#include "physics/solid/solid_scenes.hpp"
#include "tests/support/validation_record.hpp"

namespace poresph::test {

struct SphereResult {
  double u = 0, uExact = 0, uError = 0;           // innermost shell, radial displacement
  double hoop = 0, hoopExact = 0, hoopError = 0;  // innermost shell, mean tangential stress
  double hoop2 = 0, hoop2Exact = 0, hoop2Error = 0;  // second shell
  double pressure = 0;   // the water's mean pressure (time average), Lame's p
  double loadRatio = 0;  // the fluid's radial force on the clay / (4 pi a^2 p)
  double uAtLoadError = 0;  // displacement against Lame at that force's pressure (signed)
  double wall = 0;
  Index particles = 0, crossings = 0;
};

struct SphereOptions {
  int shells = 6;            // shells across the wall b - a
  double duration = 0.012;   // s of damped relaxation
  double averageFrom = 0.5;  // time averages over [averageFrom duration, duration]: one period
                             // (~6 ms) of the water's breathing mode, which is damped only slowly
  int waterShells = -1;      // outer water layers on shells, the lattice inside (-1: all shells)
  double soundSpeed = 3.0;   // the water's
  double viscosity = 0.05;   // the water's
  bool series = false;       // print a time series
  bool solidOnly = false;    // study: no water, the solid's consistent nodal pressure load
  std::string snapshot;      // study: write the end state (with a hoop_stress field) here
};

inline SphereResult runPressurisedSphere(const SphereOptions& o) {
  test::Stopwatch clock;
  const int shells = o.shells;
  const double a = 0.01, b = 0.02, p0 = 1000.0, E = 1.0e6, nu = 0.25;
  const double dx = (b - a) / shells;
  Simulation sim(3);
  char water[256];
  std::snprintf(water, sizeof water,
                "{density: 1000, sound_speed: %g, viscosity: %g, background_pressure: %g}",
                o.soundSpeed, o.viscosity, p0);
  if (!o.solidOnly) sim.addMaterial("water", "fluid", water);
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
  const int cavityShells = static_cast<int>(std::lround(a / dx));
  const int waterShells = o.solidOnly ? 0 : o.waterShells < 0 ? cavityShells : o.waterShells;
  if (waterShells > 0) {
    std::vector<double> wxyz, wvol;
    for (int k = 0; k < waterShells; ++k)
      solid::appendShells(a - (k + 1) * dx, dx, 1, wxyz, wvol);
    xyz.insert(xyz.end(), wxyz.begin(), wxyz.end());
    vol.insert(vol.end(), wvol.begin(), wvol.end());
    mat.resize(vol.size(), 0);
  }
  if (!o.solidOnly && waterShells < cavityShells) {
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
  }
  const Index n = static_cast<Index>(vol.size());
  if (o.solidOnly) {  // the solid alone under the consistent nodal load of -p 1 at the bore
    sim.store.addParticles(n);
    std::copy(xyz.begin(), xyz.end(), sim.store.data(sim.store.position()));
    for (Index k = 0; k < n; ++k) sim.store.data(sim.store.mass())[k] = 1000.0 * vol[static_cast<size_t>(k)];
    solid::ElasticSolidModule& module = solid::addSolidModule(
        sim, "{boundaries: [{name: bore, type: pressure, shell: {centre: [0, 0, 0], r_min: 0, r_max: " +
                 std::to_string(a + 2.0 * sim.kernel.support()) + "}, pressure: " + std::to_string(p0) +
                 ", ramp_time: 1.0e-3}]}");
    module.initialise(sim);
  } else {
    solid::setupWaterInClay(sim, xyz, vol, mat, 1000.0);
  }
  ParticleStore& st = sim.store;
  auto integrator = makeIntegrator("leapfrog");
  const double dt = 0.5 * std::min(sim.stableTimeStep(), cflTimeStep(sim, sim.kernel.h()));
  const long steps = static_cast<long>(o.duration / dt);
  const RealField X = st.real("reference_position"), sigma = st.real("stress");
  const RealField pressure = o.solidOnly ? RealField{} : st.real("pressure");
  FluidBoundaryForce<3> pairForce;
  if (!o.solidOnly)
    pairForce = FluidBoundaryForce<3>{
      st.data(st.position()), st.data(st.velocity()), st.data(st.mass()), st.data(st.density()),
      st.data(pressure), st.data(st.real("wall_velocity")),
      st.has("viscous_factor") ? st.data(st.real("viscous_factor")) : nullptr,
      st.data(st.material()), sim.materials.data(), &sim.kernel, sim.fluidPairSettings,
      BoundaryModel::Mirror};
  const double a3 = a * a * a, b3 = b * b * b;
  auto lameU = [&](double p, double r) {
    return p * a3 / (E * (b3 - a3)) * ((1.0 - 2.0 * nu) * r + (1.0 + nu) * b3 / (2.0 * r * r));
  };
  auto lameHoop = [&](double p, double r) { return p * a3 / (b3 - a3) * (1.0 + b3 / (2.0 * r * r * r)); };
  auto lameRadial = [&](double p, double r) { return p * a3 / (b3 - a3) * (1.0 - b3 / (r * r * r)); };
  double pSum = 0, pwSum = 0, fSum = 0, uSum = 0, tSum = 0, rSum = 0;
  Index nf = 0, nfw = 0, ns = 0, nSamples = 0;
  std::vector<double> lt(shells, 0.0), lr(shells, 0.0), lrad(shells, 0.0), lc(shells, 0.0);
  const long every = std::max(1L, steps / 40);
  for (long k = 0; k < steps; ++k) {
    integrator->step(sim, dt);
    const bool average = k >= static_cast<long>(o.averageFrom * steps) && k % 10 == 0;
    const bool print = o.series && k % every == 0;
    if (!average && !print) continue;
    double ps = 0, pws = 0, us = 0, fr = 0, ts = 0;
    Index cf = 0, cfw = 0, cs = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      const Vec<3> xi = st.vec<3>(st.position(), i);
      if (st.data(st.phase())[i] == kPhaseFluid) {
        ps += st.data(pressure)[i];
        ++cf;
        if (xi.norm() > a - 2.0 * dx) {
          pws += st.data(pressure)[i];
          ++cfw;
        }
        continue;
      }
      const Vec<3> Xi = st.vec<3>(X, i);
      const double r0 = Xi.norm();
      const Vec<3> er = Xi / r0;
      const Mat<3> S = st.mat<3>(sigma, i);
      const double hoop = 0.5 * (S.trace() - er.dot(S * er));
      if (average) {
        const int l = std::min(shells - 1, static_cast<int>((r0 - a) / dx));
        lt[l] += hoop;
        lr[l] += er.dot(S * er);
        lrad[l] += r0;
        lc[l] += 1.0;
      }
      if (r0 < a + 2.0 * sim.kernel.support()) {  // the fluid's force on the clay
        const auto& nl = sim.neighbours;
        for (auto q = nl.offset[i]; q < nl.offset[i + 1]; ++q) {
          const Index j = nl.index[static_cast<size_t>(q)];
          if (st.data(st.phase())[j] != kPhaseFluid) continue;
          double div = 0.0;
          fr -= pairForce(j, i, div).dot(xi.normalized());
        }
      }
      if (r0 > a + dx) continue;  // the innermost shell
      us += (xi - Xi).dot(er);
      ts += hoop;
      rSum += average ? r0 : 0.0;
      ++cs;
    }
    if (o.solidOnly) ps = p0, cf = 1, pws = p0, cfw = 1;
    if (print)
      std::printf("    t %.4f: p %.1f, p near wall %.1f, radial force / (4 pi a^2) %.1f, u %.4e "
                  "(Lame at p %.4e, at the force %.4e)\n",
                  (k + 1) * dt, ps / cf, pws / cfw, fr / (4 * M_PI * a * a), us / cs,
                  lameU(ps / cf, a + 0.5 * dx), lameU(fr / (4 * M_PI * a * a), a + 0.5 * dx));
    if (!average) continue;
    pSum += ps;
    nf += cf;
    pwSum += pws;
    nfw += cfw;
    fSum += fr;
    uSum += us;
    tSum += ts;
    ns += cs;
    ++nSamples;
  }
  SphereResult res;
  for (Index i = 0; i < st.realCount(); ++i)
    if (st.data(st.phase())[i] == kPhaseFluid && st.vec<3>(st.position(), i).norm() > a + 0.5 * dx)
      ++res.crossings;
  res.pressure = o.solidOnly ? p0 : pSum / static_cast<double>(nf);
  const double r = rSum / static_cast<double>(ns), p = res.pressure;
  double pForce = fSum / static_cast<double>(nSamples) / (4.0 * M_PI * a * a);
  res.u = uSum / static_cast<double>(ns);
  res.uExact = lameU(p, r);
  if (o.solidOnly) pForce = p0;
  res.uError = std::abs(res.u - res.uExact) / res.uExact;
  res.hoop = tSum / static_cast<double>(ns);
  res.hoopExact = lameHoop(p, r);
  res.hoopError = std::abs(res.hoop - res.hoopExact) / res.hoopExact;
  const double r2 = lrad[1] / lc[1];
  res.hoop2 = lt[1] / lc[1];
  res.hoop2Exact = lameHoop(p, r2);
  res.hoop2Error = std::abs(res.hoop2 - res.hoop2Exact) / res.hoop2Exact;
  res.uAtLoadError = res.u / lameU(pForce, r) - 1.0;
  res.loadRatio = pForce / p;
  res.particles = n;
  if (!o.snapshot.empty()) {  // the mean tangential stress of the clay as a field, for a picture
    const RealField hoopField = st.addReal("hoop_stress", 1, kFieldOutput, "test");
    for (Index i = 0; i < st.realCount(); ++i) {
      const Vec<3> Xi = st.vec<3>(X, i);
      const Vec<3> er = Xi / std::max(Xi.norm(), 1e-30);
      const Mat<3> S = st.mat<3>(sigma, i);
      st.data(hoopField)[i] = st.data(st.phase())[i] == kPhaseFluid ? 0.0 : 0.5 * (S.trace() - er.dot(S * er));
    }
    OutputWriter out(o.snapshot);
    std::printf("  snapshot %s\n", out.writeSnapshot(sim).c_str());
  }
  res.wall = clock.seconds();
  for (int l = 0; l < shells; ++l) {
    const double rl = lrad[l] / lc[l];
    std::printf("    shell %d r/a %.3f: hoop %.1f (Lame %.1f, %+.2f %%), radial %.1f (Lame %.1f, "
                "%+.2f %% of p)\n",
                l, rl / a, lt[l] / lc[l], lameHoop(p, rl), 100 * (lt[l] / lc[l] / lameHoop(p, rl) - 1),
                lr[l] / lc[l], lameRadial(p, rl), 100 * (lr[l] / lc[l] - lameRadial(p, rl)) / p);
  }
  std::printf("  shells, %d across (water shells %d, c %g, mu %g, %g s): water p = %.1f Pa (near the "
              "wall %.1f, radial force / (4 pi a^2) %.1f = %.4f p), u(%.5f) = %.4e m (Lame %.4e, "
              "%.2f %%; at the force %.2f %%), hoop %.1f Pa (Lame %.1f, %.2f %%), %lld crossings, "
              "%lld particles, %.1f s\n",
              shells, waterShells, o.soundSpeed, o.viscosity, o.duration, p, pwSum / nfw, pForce,
              res.loadRatio, r, res.u, res.uExact, 100.0 * res.uError,
              100.0 * (res.u / lameU(pForce, r) - 1.0), res.hoop, res.hoopExact,
              100.0 * res.hoopError, static_cast<long long>(res.crossings),
              static_cast<long long>(n), res.wall);
  return res;
}

/// Options from the study hooks: PORE_SHELLS_STUDY (duration, s), PORE_AVERAGE_FROM, PORE_WATER_SHELLS,
/// PORE_WATER_C, PORE_WATER_MU, PORE_SERIES, PORE_SOLID_ONLY, PORE_SNAPSHOT (a folder).
inline SphereOptions studyOptions(int shells) {
  SphereOptions o;
  o.shells = shells;
  auto env = [](const char* k, double d) { return std::getenv(k) ? std::atof(std::getenv(k)) : d; };
  o.duration = env("PORE_SHELLS_STUDY", o.duration);
  o.averageFrom = env("PORE_AVERAGE_FROM", o.averageFrom);
  o.waterShells = static_cast<int>(env("PORE_WATER_SHELLS", o.waterShells));
  o.soundSpeed = env("PORE_WATER_C", o.soundSpeed);
  o.viscosity = env("PORE_WATER_MU", o.viscosity);
  o.series = std::getenv("PORE_SERIES") != nullptr;
  o.solidOnly = std::getenv("PORE_SOLID_ONLY") != nullptr;
  if (const char* dir = std::getenv("PORE_SNAPSHOT")) o.snapshot = dir;
  return o;
}

}  // namespace poresph::test
