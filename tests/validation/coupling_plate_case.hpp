#pragma once
// Validation case 2 of issue 11 (docs/coupling.md, "Hydrostatic water on a clamped plate"):
// a 2 m water column on a clamped aluminium plate (Fourey et al. 2017), and the same plate alone
// under the equivalent uniform traction. Shared by test_coupling_plate.cpp (coarse, default
// suite) and test_coupling_plate_long.cpp (label validation_long).
//
// Set-up (all SI, 2D plane strain): water 1 m x 2 m (rho 1000, c = 63 m/s, just above 10 sqrt(2 g H)),
// aluminium plate L = 1 m, t = 0.05 m, E = 67.5 GPa, nu = 0.34, under it, mirror-clamped at
// x = 0 and x = L (6 layers, > two kernel supports, under the side walls). The side walls are
// clamped elastic particles (a fluid `wall` material cannot sit in a scene with solid particles:
// no module owns the wall-solid pair class). Static benchmark: the plate's density is scaled by
// kMassScale (wave speed / 31.6, its step no smaller than the water's) and damped; the static
// deflection depends on E, nu, t and the load only. No gravity acts on the plate (the solid
// module has no body force), so the reference is the water-only closed form. Fluid-solid pairs:
// the extrapolated (Adami) model by default, i.e. the side walls act on the water as a fluid
// `wall` would; with the mirror model the water near the side walls keeps circulating
// (docs/coupling.md).
//
// Kernel: Wendland C2 with h = kFluidHOverDx = 2.0 dx for the run (the fluid and the fluid-solid
// pairs) and the solid's own `smoothing_length: 1.3 dx` (the plate as before). With the fluid at
// h = 1.3 dx the water at 6 across did not come to rest: the square lattice of Wendland C2 at
// 1.3 dx is unstable under a positive pressure (adjacent columns sliding along the side walls,
// docs/fluid.md "Water at rest on the lattice"); at 2.0 dx it is stable (docs/coupling.md,
// "Not at rest at 6 across: the cause"; test CouplingRest.*).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "libcore/integrator.hpp"
#include "libcore/scene.hpp"
#include "libcore/phases.hpp"
#include "tests/support/validation_record.hpp"

namespace poresph::plate {

constexpr double kL = 1.0, kT = 0.05, kH = 2.0, kE = 67.5e9, kNu = 0.34, kRhoW = 1000.0,
                 kG = 9.81;
constexpr double kMassScale = 1000.0;  // plate density 2700 -> 2.7e6 (static benchmark)
constexpr double kDamping = 70.0;  // 1/s: near-critical for the slowest (bending) mode
/// h / dx of the run's kernel (Wendland C2) in the scenes with water: the fluid's square lattice
/// is stable under pressure at 2.0 (unstable at 1.3, docs/fluid.md); the solid keeps its own
/// h = hOverDx dx (`solid: {smoothing_length}`).
constexpr double kFluidHOverDx = 2.0;

/// Euler-Bernoulli clamped-clamped beam, plane strain: w = q L^4 / (384 D).
inline double bendingStiffness() { return kE * kT * kT * kT / (12.0 * (1.0 - kNu * kNu)); }
inline double closedForm() { return kRhoW * kG * kH * std::pow(kL, 4) / (384.0 * bendingStiffness()); }
/// Shear (Timoshenko) correction of the clamped beam under a uniform load: w_s / w_b =
/// 48 D / (kappa G t L^2) with G = E / (2 (1 + nu)), kappa = 5/6 (about +3.6 % here).
inline double shearCorrection() {
  const double G = kE / (2.0 * (1.0 + kNu));
  return 48.0 * bendingStiffness() / (5.0 / 6.0 * G * kT * kL * kL);
}

inline std::string num(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

/// The scene: `across` particles through the thickness; water = false: the plate alone under a
/// traction rho_w g H on its top particle row (area dx per particle), ramped over 0.05 s.
/// model: the fluid-solid boundary model (coupling section key fluid_solid). hOverDx: the
/// solid's h / dx (the run's with water = false); fluidHOverDx: the run's h / dx with water.
inline std::string plateScene(int across, double endTime, bool water, double hOverDx = 1.3,
                              const std::string& model = "extrapolated",
                              double fluidHOverDx = kFluidHOverDx) {
  const double dx = kT / across;
  // two solid supports (the mirror clamp), and at least one fluid support (the side walls)
  const int layers = static_cast<int>(std::ceil(
      std::max(2.0 * 2.0 * hOverDx, water ? 2.0 * fluidHOverDx : 0.0) - 1e-9));
  const double c = layers * dx;
  const double rhoS = 2700.0 * kMassScale;
  std::ostringstream s;
  s << "dimension: 2\n";
  if (water) s << "coupling: {fluid_solid: " << model << "}\n";
  s
    << "domain: {lo: [0.0, 0.0], hi: [1.0, 2.0]}\n"
    << "spacing: " << num(dx) << "\nh_over_dx: " << (water ? fluidHOverDx : hOverDx)
    << "\nkernel: wendland_c2\n"
    << "integrator: leapfrog\nend_time: " << endTime << "\n"
    << "time_step: {adaptive: true, cfl: 0.9}\noutput: {every_time: 0.05}\nmaterials:\n"
    << "  - {name: water, model: fluid, density: 1000, sound_speed: 63, viscosity: 1.0e-3}\n"
    << "  - {name: tank, model: elastic, density: " << rhoS
    << ", young_modulus: 67.5e9, poisson_ratio: 0.34, plane: strain}\n"
    << "  - {name: plate, model: elastic, density: " << rhoS
    << ", young_modulus: 67.5e9, poisson_ratio: 0.34, plane: strain, hourglass: 1.0, damping: "
    << kDamping << "}\ngeometry:\n";
  if (water)
    s << "  - {shape: box, lo: [" << num(-c) << ", 0.0], hi: [" << num(kL + c) << ", "
      << num(kH + c) << "], material: tank}\n";
  s << "  - {shape: box, lo: [" << num(-c) << ", " << num(-kT) << "], hi: [" << num(kL + c)
    << ", 0.0], material: plate}\n";
  if (water)
    s << "  - {shape: box, lo: [0.0, 0.0], hi: [1.0, 2.0], material: water}\n"
      << "fluid:\n  gravity: [0, -9.81]\n  hydrostatic_level: 2.0\n  artificial_viscosity: 0.2\n";
  s << "solid:\n";
  if (water) s << "  smoothing_length: " << num(hOverDx * dx) << "\n";  // the plate's own h
  s << "  boundaries:\n";
  if (water) s << "    - {name: walls, type: clamped, material: tank}\n";
  else
    s << "    - {name: load, type: traction, box: {min: [0, " << num(-0.75 * dx) << "], max: [1, 0]}, "
      << "traction: [0, " << num(-kRhoW * kG * kH) << "], area: " << num(dx) << ", ramp_time: 0.05}\n";
  s << "    - {name: left, type: clamped, box: {min: [-1, -1], max: [0, 0]}, mirror: {point: [0, 0], "
       "normal: [1, 0]}}\n"
    << "    - {name: right, type: clamped, box: {min: [1, -1], max: [2, 0]}, mirror: {point: [1, 0], "
       "normal: [-1, 0]}}\n";
  return s.str();
}

/// The cheap reproducer of the water that did not come to rest at 6 across (docs/coupling.md,
/// "Not at rest at 6 across: the cause"): the plate case's water (c, viscosity, artificial
/// viscosity, kernel, hydrostatic start) at `across` particles per plate thickness in a narrow,
/// short tank of clamped elastic particles (side walls and floor: fluid-solid pairs of the
/// coupling, `model`), with gravity raised so that the bottom pressure is the plate case's
/// rho_w g H = 19 620 Pa (sqrt(2 g H) and the sound speed's margin unchanged).
/// plateFloor: the floor is the plate case's damped elastic plate (t = 0.05 m, mirror-clamped
/// under the side walls, its own h = 1.3 dx) instead of clamped particles: a moving solid.
inline std::string tankScene(int across, double width, double height, double endTime,
                             double fluidHOverDx = kFluidHOverDx,
                             const std::string& model = "extrapolated", bool plateFloor = false) {
  const double dx = kT / across;
  // one fluid support; with the plate two plate supports (its mirror clamps)
  const double c =
      std::ceil(std::max(2.0 * fluidHOverDx, plateFloor ? 4.0 * 1.3 : 0.0) - 1e-9) * dx;
  const double g = kG * kH / height;
  const double rhoS = 2700.0 * kMassScale;
  std::ostringstream s;
  s << "dimension: 2\ncoupling: {fluid_solid: " << model << "}\n"
    << "domain: {lo: [0.0, 0.0], hi: [" << num(width) << ", " << num(height) << "]}\n"
    << "spacing: " << num(dx) << "\nh_over_dx: " << fluidHOverDx << "\nkernel: wendland_c2\n"
    << "integrator: leapfrog\nend_time: " << endTime << "\n"
    << "time_step: {adaptive: true, cfl: 0.9}\noutput: {every_time: 0.05}\nmaterials:\n"
    << "  - {name: water, model: fluid, density: 1000, sound_speed: 63, viscosity: 1.0e-3}\n"
    << "  - {name: tank, model: elastic, density: " << rhoS
    << ", young_modulus: 67.5e9, poisson_ratio: 0.34, plane: strain}\n";
  if (plateFloor)
    s << "  - {name: plate, model: elastic, density: " << rhoS
      << ", young_modulus: 67.5e9, poisson_ratio: 0.34, plane: strain, hourglass: 1.0, damping: "
      << kDamping << "}\n";
  s << "geometry:\n"
    << "  - {shape: box, lo: [" << num(-c) << ", " << num(plateFloor ? 0.0 : -c) << "], hi: ["
    << num(width + c) << ", " << num(height + c) << "], material: tank}\n";
  if (plateFloor)
    s << "  - {shape: box, lo: [" << num(-c) << ", " << num(-kT) << "], hi: [" << num(width + c)
      << ", 0.0], material: plate}\n";
  s << "  - {shape: box, lo: [0.0, 0.0], hi: [" << num(width) << ", " << num(height)
    << "], material: water}\n"
    << "fluid:\n  gravity: [0, " << num(-g) << "]\n  hydrostatic_level: " << num(height)
    << "\n  artificial_viscosity: 0.2\n"
    << "solid:\n";
  if (plateFloor) s << "  smoothing_length: " << num(1.3 * dx) << "\n";
  s << "  boundaries:\n    - {name: walls, type: clamped, material: tank}\n";
  if (plateFloor)
    s << "    - {name: left, type: clamped, box: {min: [-1, -1], max: [0, 0]}, mirror: {point: "
         "[0, 0], normal: [1, 0]}}\n"
      << "    - {name: right, type: clamped, box: {min: [" << num(width) << ", -1], max: ["
      << num(width + 1.0) << ", 0]}, mirror: {point: [" << num(width) << ", 0], normal: [-1, 0]}}\n";
  return s.str();
}

struct PlateResult {
  double deflection = 0.0;     ///< mid-span u_y (mean over the thickness and the last 0.05 s)
  double fluidMaxSpeed = 0.0;  ///< at the end
  double forceRatio = 0.0;     ///< -(vertical fluid force on all solids) / water weight, averaged
  double wall = 0.0;
  Index particles = 0;
  long steps = 0;
};

/// Mid-span deflection: mean u_y of the plate particles in the two columns next to x = L/2.
inline double midSpan(const Simulation& sim, double dx) {
  const ParticleStore& st = sim.store;
  const double* X = st.data(st.real("reference_position"));
  const double* u = st.data(st.real("displacement"));
  const std::int32_t* mt = st.data(st.material());
  double sum = 0.0;
  int count = 0;
  for (Index i = 0; i < st.realCount(); ++i) {
    if (mt[i] != 2 || std::abs(X[2 * i] - 0.5 * kL) > 0.6 * dx) continue;
    sum += u[2 * i + 1];
    ++count;
  }
  EXPECT_GT(count, 0);
  return count ? sum / count : 0.0;
}

inline double diagnostic(const Simulation& sim, const std::string& name) {
  for (const auto& [k, v] : sim.diagnostics())
    if (k == name) return v;
  ADD_FAILURE() << "no column " << name;
  return 0.0;
}

inline PlateResult runPlate(int across, double endTime, bool water, double hOverDx = 1.3,
                            const std::string& model = "extrapolated",
                            double fluidHOverDx = kFluidHOverDx) {
  test::Stopwatch clock;
  Scene s = loadSceneText(plateScene(across, endTime, water, hOverDx, model, fluidHOverDx),
                          water ? "coupling_plate.yaml" : "plate_alone.yaml");
  Simulation& sim = *s.sim;
  const double dx = kT / across;
  auto integrator = makeIntegrator("leapfrog");
  double weight = 0.0;
  if (water) {
    const ParticleStore& st = sim.store;
    for (Index i = 0; i < st.realCount(); ++i)
      if (st.data(st.phase())[i] == kPhaseFluid) weight += st.data(st.mass())[i] * kG;
  }
  PlateResult r;
  r.particles = sim.store.realCount();
  double wSum = 0.0, fSum = 0.0;
  int samples = 0;
  double nextPrint = 0.0;
  while (!s.finished()) {
    integrator->step(sim, s.nextTimeStep());
    ++r.steps;
    if (sim.time >= nextPrint) {
      std::printf("    t = %.3f s  w_mid = %.4e m%s\n", sim.time, midSpan(sim, dx),
                  water ? ("  fluid max speed " + num(diagnostic(sim, "fluid_max_speed"))).c_str()
                        : "");
      nextPrint += 0.05;
    }
    if (sim.time > endTime - 0.05 && r.steps % 10 == 0) {
      wSum += midSpan(sim, dx);
      if (water) fSum += -diagnostic(sim, "fluid_solid_force_y") / weight;
      ++samples;
    }
  }
  r.deflection = -wSum / samples;
  if (water) {
    r.fluidMaxSpeed = diagnostic(sim, "fluid_max_speed");
    r.forceRatio = fSum / samples;
  }
  r.wall = clock.seconds();
  std::printf("  %s, %d across (dx %.4g m, h/dx %.2f), %lld particles, %ld steps: w_mid = %.4e m "
              "(closed form %.4e, %+.1f %%)%s, %.1f s\n",
              water ? "water + plate" : "plate alone", across, dx, hOverDx,
              static_cast<long long>(r.particles), r.steps, r.deflection, closedForm(),
              100.0 * (r.deflection / closedForm() - 1.0),
              water ? (", fluid max speed " + num(r.fluidMaxSpeed) + " m/s, load / weight " +
                       num(r.forceRatio)).c_str()
                    : "",
              r.wall);
  return r;
}

}  // namespace poresph::plate
