#pragma once
// Issue 15, validation case 2 (settling) in 3D, shared by tests/validation/test_rigid_stokes_3d.cpp
// (default) and test_rigid_stokes_3d_long.cpp (finer / bigger cells): a rigid sphere (lattice
// particles inside radius a) in a periodic cubic cell of viscous fluid, pushed along x by its own
// gravity; a uniform opposite body force on the fluid keeps the total force zero (the periodic
// version of settling, as the 2D disc of test_rigid_stokes.cpp: the box does not accelerate as a
// whole, and the fluid's uniform body force is the mean pressure gradient of a fixed array).
// At steady Stokes flow the sphere moves through the simple cubic array of its periodic images
// with the drag (Hasimoto 1959; Sangani & Acrivos 1982, Int. J. Multiphase Flow 8, 343)
//   F = 6 pi mu a U K(phi),
//   1/K = 1 - 1.7601 phi^(1/3) + phi - 1.5593 phi^2 + 3.9799 phi^(8/3) - 3.0734 phi^(10/3),
// phi = 4 pi a^3 / (3 L^3), U the superficial velocity of the fluid through the array (volume
// flux per unit area; Zick & Homsy 1982, Table 2, K(0.027) = 2.008: the series gives 2.0077).
// Settling (zero volume flux: equal densities and zero total momentum) maps onto the fixed array
// by a Galilean change of frame, which gives U = V_b - u_cell, u_cell the volume mean of the velocity
// over the whole cell (body included); the 2D test's V_b - (mean fluid velocity) equals
// U / (1 - phi), the interstitial velocity. Both are reported; the test asserts U.
// F = M_b g (the body's weight), a the radius of the body's particle volume (N dx^3 = 4/3 pi a^3).
//
// Closed container (issue 15's literal case, a single sphere settling in a closed box with the
// box's wall correction; test_rigid_stokes_3d_container_long.cpp): the same sphere, fluid and
// drive at the centre of a closed spherical cavity of radius R bounded by no-slip `wall`
// particles (a shell of 3.2 dx), nothing periodic, no fluid body force (the walls hold the fluid;
// the body's gravity at equal densities is the excess weight (rho_s - rho_f) g V of a heavy
// sphere). Reference: the exact Stokes solution for a sphere at the centre of a spherical
// container (Cunningham 1910, Williams 1915; Happel & Brenner 1965, Sec. 4-22; Haberman & Sayre
// 1958), F = 6 pi mu a K U with
//   K = (1 - l^5) / (1 - 9/4 l + 5/2 l^3 - 9/4 l^5 + l^6),   l = a / R
// (K = 1 + 9/4 l + ... for a small sphere); U = V_b (the walls are at rest), R the radius of the
// cavity's particle volume ((N_f + N_b) dx^3 = 4/3 pi R^3), a as above. The floor and ceiling are
// part of this closed container; the sphere moves ~1e-3 of its radius during the run (K is even
// in the offset from the centre, so the offset's effect is second order).
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

namespace poresph::test {

/// 1/K of a simple cubic array of spheres at volume fraction phi (Sangani & Acrivos 1982, the
/// first terms are Hasimoto's 1959): F = 6 pi mu a K U.
inline double cubicArrayInverseK(double phi) {
  const double c3 = std::cbrt(phi);
  return 1.0 - 1.7601 * c3 + phi - 1.5593 * phi * phi + 3.9799 * std::pow(c3, 8) -
         3.0734 * std::pow(c3, 10);
}

/// Wall correction K of a sphere (radius a) at the centre of a closed spherical container of
/// radius R, l = a / R: F = 6 pi mu a K U (Happel & Brenner 1965, Sec. 4-22; exact Stokes flow).
inline double sphericalContainerK(double l) {
  return (1.0 - std::pow(l, 5)) /
         (1.0 - 2.25 * l + 2.5 * l * l * l - 2.25 * std::pow(l, 5) + std::pow(l, 6));
}

struct Stokes3dResult {
  double U = 0.0;        ///< V_b - u_cell (superficial velocity, the reference's U), m/s
  double Uint = 0.0;     ///< V_b - mean fluid velocity (interstitial, the 2D test's measure)
  double Uexact = 0.0;   ///< M_b g / (6 pi mu a K)
  double err = 0.0;      ///< U / Uexact - 1
  double errInt = 0.0;   ///< Uint / Uexact - 1
  double Ulate = 0.0;    ///< U at 3/4 of the run (steadiness)
  double transverse = 0.0;  ///< |V_b,y| + |V_b,z| relative to U (should be ~0)
  double Re = 0.0, phi = 0.0, aEff = 0.0, K = 0.0, seconds = 0.0;
  double Rcav = 0.0;     ///< container: volume radius of the cavity (fluid + body), m
  double offset = 0.0;   ///< container: the body's displacement from its start, in dx
  long long particles = 0, steps = 0;
};

/// The scene text: sphere of radius a = perRadius dx in a periodic cube of cell x a, or
/// (container) at the centre of a closed spherical cavity of radius cell x a walled by `wall`
/// particles (shell 3.2 dx thick: more than the Wendland support 2.6 dx), in a box just holding it.
inline std::string stokes3dScene(int perRadius, double cell, double endTime, double G, double gFluid,
                                 double outputEvery = 0.0, bool container = false) {
  const double a = 0.002, dx = a / perRadius;
  const double shell = 3.2 * dx;
  const int n = container ? 2 * static_cast<int>(std::ceil((cell * a + shell) / dx + 1.0))
                          : static_cast<int>(std::lround(cell * perRadius));
  const double L = n * dx;
  std::ostringstream y;
  y.precision(12);
  y << "dimension: 3\n"
    << "domain: {lo: [0, 0, 0], hi: [" << L << ", " << L << ", " << L << "]"
    << (container ? "}\n" : ", periodic: [true, true, true]}\n")
    << "spacing: " << dx << "\nkernel: wendland_c2\nintegrator: leapfrog\n"
    << "end_time: " << endTime << "\ntime_step: {adaptive: true, cfl: 0.5}\n";
  if (outputEvery > 0.0)
    y << "output: {every_time: " << outputEvery << "}\n";
  else
    y << "output: {every_steps: 100000000}\n";
  y << "materials:\n"
    << "  - {name: oil, model: fluid, density: 1000, sound_speed: " << (container ? 5.0 : 0.5)
    << ", viscosity: 1.0}\n"
    << "  - {name: ball, model: rigid, density: 1000}\n";
  if (container) y << "  - {name: vessel, model: wall, density: 1000}\n";
  y << "geometry:\n";
  const double c = L / 2;
  if (container)
    y << "  - {shape: sphere, centre: [" << c << ", " << c << ", " << c << "], radius: " << cell * a + shell
      << ", material: vessel}\n"
      << "  - {shape: sphere, centre: [" << c << ", " << c << ", " << c << "], radius: " << cell * a
      << ", material: oil}\n";
  else
    y << "  - {shape: box, lo: [0, 0, 0], hi: [" << L << ", " << L << ", " << L << "], material: oil}\n";
  y << "  - {shape: sphere, centre: [" << c << ", " << c << ", " << c << "], radius: " << a
    << ", material: ball}\n"
    << "rigid: {gravity: [" << G << ", 0, 0]}\n"
    << "fluid: {gravity: [" << gFluid << ", 0, 0]}\n";
  return y.str();
}

/// Runs the settling sphere to endTime. RIGID_STOKES3D_TRACE=1 prints U every 10 % of the run.
/// container: the closed spherical cavity of radius cell x a instead of the periodic cell.
inline Stokes3dResult runStokes3d(int perRadius, double cell, double endTime, bool container = false) {
  Stopwatch clock;
  const double a = 0.002, dx = a / perRadius, mu = 1.0, rho = 1000.0, G = 1.0;
  // count the sphere's and the fluid's particles from a first load, then (periodic cell) balance
  // the sphere's weight on the fluid
  Scene probe = loadSceneText(stokes3dScene(perRadius, cell, endTime, G, 0.0, 0.0, container),
                              "rigid_stokes_3d.yaml");
  auto* r0 = dynamic_cast<RigidModule*>(probe.sim->module("rigid"));
  const double Nb = static_cast<double>(r0->bodies()[0].count);
  double Nf = 0.0;
  for (Index i = 0; i < probe.sim->store.realCount(); ++i)
    Nf += probe.sim->store.data(probe.sim->store.phase())[i] == kPhaseFluid ? 1.0 : 0.0;
  Scene s = loadSceneText(
      stokes3dScene(perRadius, cell, endTime, G, container ? 0.0 : -G * Nb / Nf, 0.0, container),
      "rigid_stokes_3d.yaml");
  Simulation& sim = *s.sim;
  auto* rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  auto integrator = makeIntegrator("leapfrog");
  // cell mean and fluid mean of the velocity (equal densities and spacing: the particles' volumes
  // are equal to within the fluid's density change, so mass weights are volume weights)
  auto measure = [&](double& sup, double& inter) {
    const ParticleStore& st = sim.store;
    const double* v = st.data(st.velocity());
    const double* m = st.data(st.mass());
    const std::int32_t* ph = st.data(st.phase());
    double pAll = 0.0, mAll = 0.0, pF = 0.0, mF = 0.0;
    for (Index i = 0; i < st.realCount(); ++i) {
      pAll += m[i] * v[i * 3];
      mAll += m[i];
      if (ph[i] == kPhaseFluid) {
        pF += m[i] * v[i * 3];
        mF += m[i];
      }
    }
    const double Vb = rigid->bodies()[0].state.V[0];
    sup = container ? Vb : Vb - pAll / mAll;  // container: the walls at rest are the frame
    inter = Vb - pF / mF;
  };
  const rigid::V3 X0 = rigid->bodies()[0].state.X;
  Stokes3dResult out;
  const bool trace = std::getenv("RIGID_STOKES3D_TRACE") != nullptr;
  bool late = false;
  double nextTrace = 0.1 * endTime;
  while (!s.finished()) {
    integrator->step(sim, s.nextTimeStep());
    if (!late && sim.time >= 0.75 * endTime) {
      double dummy = 0.0;
      measure(out.Ulate, dummy);
      late = true;
    }
    if (trace && sim.time >= nextTrace) {
      double u = 0.0, ui = 0.0;
      measure(u, ui);
      std::printf("    t = %.4f s (step %lld): U = %.5e, V_b - V_f = %.5e m/s\n", sim.time,
                  static_cast<long long>(sim.step), u, ui);
      std::fflush(stdout);
      nextTrace += 0.1 * endTime;
    }
  }
  measure(out.U, out.Uint);
  const auto& body = rigid->bodies()[0].state;
  out.transverse = (std::abs(body.V[1]) + std::abs(body.V[2])) / std::abs(out.U);
  out.aEff = std::cbrt(3.0 * Nb * dx * dx * dx / (4.0 * M_PI));
  out.offset = (body.X - X0).norm() / dx;
  if (container) {
    out.Rcav = std::cbrt(3.0 * (Nb + Nf) * dx * dx * dx / (4.0 * M_PI));
    out.phi = Nb / (Nb + Nf);
    out.K = sphericalContainerK(out.aEff / out.Rcav);
  } else {
    const double L = std::lround(cell * perRadius) * dx;
    out.phi = Nb * dx * dx * dx / (L * L * L);
    out.K = 1.0 / cubicArrayInverseK(out.phi);
  }
  out.Uexact = body.mass * G / (6.0 * M_PI * mu * out.aEff * out.K);
  out.err = out.U / out.Uexact - 1.0;
  out.errInt = out.Uint / out.Uexact - 1.0;
  out.Re = std::abs(out.U) * out.aEff * rho / mu;
  out.particles = static_cast<long long>(sim.store.realCount());
  out.steps = static_cast<long long>(sim.step);
  out.seconds = clock.seconds();
  char cavity[64] = "";
  if (container) std::snprintf(cavity, sizeof cavity, ", cavity volume radius %.3f dx", out.Rcav / dx);
  std::printf("  a/dx %d (a_eff %.3f dx, %.0f particles), %s %.0f a (%lld particles%s), phi = %.4f, "
              "K = %.4f, t = %.3f s (%lld steps): U = %s = %.5e m/s (at 3/4: %.5e), "
              "reference %.5e: %+.2f %%; V_b - V_f = %.5e: %+.2f %%; transverse %.1e; moved %.2e dx; "
              "Re %.1e; %.1f s\n",
              perRadius, out.aEff / dx, Nb, container ? "container" : "cell", cell, out.particles,
              cavity, out.phi,
              out.K, sim.time, out.steps, container ? "V_b" : "V_b - u_cell", out.U, out.Ulate,
              out.Uexact, 100 * out.err, out.Uint, 100 * out.errInt, out.transverse, out.offset, out.Re,
              out.seconds);
  std::fflush(stdout);
  return out;
}

}  // namespace poresph::test
