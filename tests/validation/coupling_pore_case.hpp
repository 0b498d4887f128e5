#pragma once
// The pressurised circular pore of issue 11 item 3 (2D, plane strain), shared by
// test_coupling.cpp (rings and lattice at 16 / 24 across, default) and
// test_coupling_pore_long.cpp (lattice at 32 across). Moved here unchanged from test_coupling.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "libcore/fluid_pair_terms.hpp"
#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"
#include "physics/solid/solid_scenes.hpp"
#include "physics/solid/wall_stress.hpp"
#include "tests/support/validation_record.hpp"

// ---------------------------------------------------------------------------------------------
// 3. Pressurised pore (2D, plane strain): a ring a <= r <= b of elastic clay around a cavity of
// water at pressure p (the water's background pressure: at rho0 the EOS gives p). The solid is
// loaded only through the fluid-solid pairs. Dynamic relaxation (solid damping) to the static
// state; then the mean radial displacement and hoop stress of the innermost solid layer against
// Lame at the mean pressure the water holds then:
//   u(r) = (1 + nu) p a^2 / (E (b^2 - a^2)) [(1 - 2 nu) r + b^2 / r],
//   sigma_t(r) = p a^2 / (b^2 - a^2) (1 + b^2 / r^2).
namespace poresph::pore {

struct PoreResult {
  double displacementError = 0.0, hoopError = 0.0, pressure = 0.0, uMeasured = 0.0, uExact = 0.0;
  double hoopMeasured = 0.0, hoopExact = 0.0, maxFluidSpeed = 0.0, wall = 0.0;
  // the wall value of solid::estimateWallStress (extrapolated from behind the staircase to the
  // smooth wall) against Lame at the mean radius of its wall points
  double wallHoop = 0.0, wallHoopExact = 0.0, wallHoopError = 0.0, wallRadius = 0.0;
  Index particles = 0, crossings = 0;
};

inline PoreResult runPressurisedPore(bool rings, int perThickness, double duration) {
  test::Stopwatch clock;
  const double a = 0.01, b = 0.02, p = 1000.0, E = 1.0e6, nu = 0.25;
  const double dx = (b - a) / perThickness;
  Simulation sim(2);
  sim.addMaterial("water", "fluid",
                  "{density: 1000, sound_speed: 3, viscosity: 0.05, background_pressure: " +
                      std::to_string(p) + "}");
  sim.addMaterial("clay", "elastic",
                  "{density: 1000, young_modulus: 1.0e6, poisson_ratio: 0.25, "
                  "formulation: total_lagrangian, damping: 3000}");
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::WendlandC2, 2, 1.3 * dx);
  sim.domain.lo = {-2.0 * b, -2.0 * b, 0};
  sim.domain.hi = {2.0 * b, 2.0 * b, 1};
  std::vector<double> xy, vol;
  std::vector<int> mat;
  if (rings) {
    solid::appendRings(a, dx, perThickness, xy, vol);
    mat.assign(vol.size(), 1);
  }
  const int m = static_cast<int>(std::ceil(b / dx)) + 1;
  for (int j = -m; j < m; ++j)
    for (int i = -m; i < m; ++i) {
      const double x = (i + 0.5) * dx, y = (j + 0.5) * dx, r = std::hypot(x, y);
      const bool water = r < a - (rings ? 0.25 * dx : 0.0);
      const bool clay = !rings && r >= a && r <= b;
      if (!water && !clay) continue;
      xy.push_back(x);
      xy.push_back(y);
      vol.push_back(dx * dx);
      mat.push_back(water ? 0 : 1);
    }
  const Index n = static_cast<Index>(vol.size());
  solid::setupWaterInClay(sim, xy, vol, mat, 1000.0);
  ParticleStore& st = sim.store;
  auto integrator = makeIntegrator("leapfrog");
  const double dt = 0.5 * std::min(sim.stableTimeStep(), cflTimeStep(sim, sim.kernel.h()));
  const long steps = static_cast<long>(duration / dt);
  PoreResult res;
  const RealField X = st.real("reference_position"), sigma = st.real("stress");
  const RealField pressure = st.real("pressure");
  // Time averages over the last third of the run (the water's slosh is damped only slowly).
  double pSum = 0.0, uSum = 0.0, tSum = 0.0, rSum = 0.0, wSum = 0.0, wrSum = 0.0;
  Index nf = 0, ns = 0, nw = 0;
  // Study output (PORE_PROFILE): hoop / radial stress per radial layer of width dx, the first
  // layer's hoop stress per angular bin (folded onto 0-45 deg), and the fluid's radial force
  // per unit angle against p a (the load the pairs put on the wall).
  const bool profile = std::getenv("PORE_PROFILE") != nullptr;
  const int nLayers = perThickness, nAng = 6;
  std::vector<double> lt(nLayers, 0.0), lr(nLayers, 0.0), lrad(nLayers, 0.0), lc(nLayers, 0.0);
  std::vector<double> at(nAng, 0.0), ac(nAng, 0.0), af(nAng, 0.0);
  double fRadial = 0.0, fSamples = 0.0;
  const FluidBoundaryForce<2> pairForce{
      st.data(st.position()), st.data(st.velocity()), st.data(st.mass()), st.data(st.density()),
      st.data(pressure), st.data(st.real("wall_velocity")),
      st.has("viscous_factor") ? st.data(st.real("viscous_factor")) : nullptr,
      st.data(st.material()), sim.materials.data(), &sim.kernel, sim.fluidPairSettings,
      BoundaryModel::Mirror};
  for (long k = 0; k < steps; ++k) {
    integrator->step(sim, dt);
    if (k < 2 * steps / 3 || k % 10 != 0) continue;
    // study hooks: PORE_WALL_REACH / PORE_WALL_DEPTH (units of dx), PORE_WALL_QUAD (quadratic)
    for (const auto& e : solid::estimateWallStress<2>(
             sim, dx, std::getenv("PORE_WALL_REACH") ? std::atof(std::getenv("PORE_WALL_REACH")) : 5.0,
             std::getenv("PORE_WALL_DEPTH") ? std::atof(std::getenv("PORE_WALL_DEPTH")) : 1.5,
             std::getenv("PORE_WALL_QUAD") != nullptr)) {
      const Vec<2> er = e.wallPoint.normalized(), et(-er[1], er[0]);
      wSum += et.dot(e.stress * et);
      wrSum += e.wallPoint.norm();
      ++nw;
    }
    if (profile) {
      for (Index i = 0; i < st.realCount(); ++i) {
        if (st.data(st.phase())[i] == kPhaseFluid) continue;
        const Vec<2> Xi = st.vec<2>(X, i);
        const double r0 = Xi.norm();
        const Vec<2> er = Xi / r0, et(-er[1], er[0]);
        const int l = std::min(nLayers - 1, static_cast<int>((r0 - a) / dx));
        const Mat<2> S = st.mat<2>(sigma, i);
        lt[l] += et.dot(S * et);
        lr[l] += er.dot(S * er);
        lrad[l] += r0;
        lc[l] += 1.0;
        if (l == 0) {
          double th = std::atan2(std::abs(Xi[1]), std::abs(Xi[0]));
          if (th > M_PI / 4) th = M_PI / 2 - th;
          const int ab = std::min(nAng - 1, static_cast<int>(th / (M_PI / 4) * nAng));
          at[ab] += et.dot(S * et);
          ac[ab] += 1.0;
        }
        const auto& nl = sim.neighbours;
        Vec<2> f = Vec<2>::Zero();
        for (auto q = nl.offset[i]; q < nl.offset[i + 1]; ++q) {
          const Index j = nl.index[static_cast<size_t>(q)];
          if (st.data(st.phase())[j] != kPhaseFluid) continue;
          double div = 0.0;
          f -= pairForce(j, i, div);
        }
        fRadial += f.dot(st.vec<2>(st.position(), i).normalized());
        double th = std::atan2(std::abs(Xi[1]), std::abs(Xi[0]));
        if (th > M_PI / 4) th = M_PI / 2 - th;
        af[std::min(nAng - 1, static_cast<int>(th / (M_PI / 4) * nAng))] +=
            f.dot(st.vec<2>(st.position(), i).normalized());
      }
      fSamples += 1.0;
    }
    for (Index i = 0; i < st.realCount(); ++i) {
      const Vec<2> xi = st.vec<2>(st.position(), i);
      if (st.data(st.phase())[i] == kPhaseFluid) {
        pSum += st.data(pressure)[i];
        ++nf;
        continue;
      }
      const Vec<2> Xi = st.vec<2>(X, i);
      const double r0 = Xi.norm();
      if (r0 > a + dx) continue;  // the innermost layer (ring or staircase)
      const Vec<2> er = Xi / r0, et(-er[1], er[0]);
      uSum += (xi - Xi).dot(er);
      tSum += et.dot(st.mat<2>(sigma, i) * et);
      rSum += r0;
      ++ns;
    }
  }
  for (Index i = 0; i < st.realCount(); ++i) {
    if (st.data(st.phase())[i] != kPhaseFluid) continue;
    res.maxFluidSpeed = std::max(res.maxFluidSpeed, st.vec<2>(st.velocity(), i).norm());
    if (st.vec<2>(st.position(), i).norm() > a + 0.5 * dx) ++res.crossings;  // water in the clay
  }
  res.pressure = pSum / nf;
  const double r = rSum / ns;
  const double A = res.pressure * a * a / (b * b - a * a);
  res.uExact = (1.0 + nu) * res.pressure * a * a / (E * (b * b - a * a)) *
               ((1.0 - 2.0 * nu) * r + b * b / r);
  res.uMeasured = uSum / ns;
  res.displacementError = std::abs(res.uMeasured - res.uExact) / res.uExact;
  const double hoopExact = A * (1.0 + b * b / (r * r));
  res.hoopError = std::abs(tSum / ns - hoopExact) / hoopExact;
  res.hoopMeasured = tSum / ns;
  res.hoopExact = hoopExact;
  res.wallRadius = wrSum / nw;
  res.wallHoop = wSum / nw;
  res.wallHoopExact = A * (1.0 + b * b / (res.wallRadius * res.wallRadius));
  res.wallHoopError = std::abs(res.wallHoop - res.wallHoopExact) / res.wallHoopExact;
  res.wall = clock.seconds();
  res.particles = n;
  std::printf("  wall estimate: hoop %.1f Pa at r = %.5f (Lame %.1f, %.2f %%)\n", res.wallHoop,
              res.wallRadius, res.wallHoopExact, 100.0 * res.wallHoopError);
  if (profile) {
    const double P = res.pressure;
    std::printf("  [profile] fluid radial force / (2 pi a p) = %.4f\n",
                fRadial / fSamples / (2.0 * M_PI * a * P));
    for (int l = 0; l < std::min(nLayers, 8); ++l) {
      const double rl = lrad[l] / lc[l];
      const double Al = P * a * a / (b * b - a * a);
      std::printf("  [profile] layer %d r/a %.4f n %.0f: hoop %.1f (Lame %.1f, %+.2f %%), radial "
                  "%.1f (Lame %.1f, %+.2f %% of p)\n",
                  l, rl / a, lc[l] / fSamples, lt[l] / lc[l], Al * (1 + b * b / (rl * rl)),
                  100 * (lt[l] / lc[l] / (Al * (1 + b * b / (rl * rl))) - 1), lr[l] / lc[l],
                  Al * (1 - b * b / (rl * rl)),
                  100 * (lr[l] / lc[l] - Al * (1 - b * b / (rl * rl))) / P);
    }
    for (int q = 0; q < nAng; ++q)
      std::printf("  [profile] first layer, %.1f-%.1f deg: hoop %.1f (n %.0f); radial force per "
                  "unit angle / (p a) %.4f\n", 45.0 * q / nAng, 45.0 * (q + 1) / nAng,
                  at[q] / ac[q], ac[q] / fSamples, af[q] / fSamples / (8 * M_PI / 4 / nAng) / (P * a));
  }
  std::printf("  %s, %d across: water p = %.1f Pa (loaded with %.0f), u(%.5f) = %.4e m (Lame "
              "%.4e, %.2f %%), hoop %.1f Pa (Lame %.1f, %.2f %%), max water speed %.2e m/s, "
              "%lld crossings, %lld particles, %.1f s\n",
              rings ? "rings" : "lattice", perThickness, res.pressure, p, r, res.uMeasured,
              res.uExact, 100.0 * res.displacementError, tSum / ns, hoopExact,
              100.0 * res.hoopError, res.maxFluidSpeed, static_cast<long long>(res.crossings),
              static_cast<long long>(n), res.wall);
  return res;
}

}  // namespace poresph::pore
