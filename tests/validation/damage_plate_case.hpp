#pragma once
// The plate with a rigid circular inclusion of thesis Sec. 4.3 (Tab. 4.2, Fig. 4.13, loading
// 4.31), shared by tests/validation/test_damage_plate*.cpp: side L = 300 mm, inclusion of
// diameter L/3 at the centre held fixed (u = 0, D = 0 on it: an undamageable material clamped in
// place), the top layer (one support deep) pulled or pushed along y with x free (roller,
// `components: [y]`), other sides free. E = 12000 N/mm2, nu = 0.25 (plane strain),
// rho = 1000 mg/mm3 (1e6 kg/m3), Yc0 = 2.5e-3 N/mm2, s_l = 0.99. Total-Lagrangian SVK with
// hourglass control; quasi-static by a slow displacement ramp and viscous damping (instead of
// the thesis' artificial viscosity alpha = 41, which cuts the step ~50x).
// Variants of the inclusion (PlateSetup::inclusion, issue 15 validation 5): the clamped
// undamageable material above, or a rigid body of the rigid module (physics/rigid) bonded to the
// clay (`bonded: true`: the clay's first layer held to anchor points fixed in the body frame,
// A.6), either held (`fixed: true`) or free (translates and rotates with the clay it is bonded to).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "libcore/phases.hpp"
#include "physics/rigid/rigid_module.hpp"
#include "physics/solid/solid_scenes.hpp"

namespace poresph::solid::plate {

/// How the inclusion is held.
enum class Inclusion {
  Clamped,     ///< an undamageable elastic material clamped at u = 0 (the thesis' Gamma_1)
  RigidFixed,  ///< a rigid body (rigid module), bonded to the clay, `fixed: true`
  RigidFree,   ///< the same body free: Newton-Euler under the bond forces of the clay
};

struct PlateSetup {
  double dx = 3e-3;           ///< particle spacing [m]
  double support = 15e-3;     ///< 2h [m]
  std::string law = "{law: at2, critical_energy_release: 2500}";
  double uMax = 30e-6;        ///< imposed top displacement at the end of the ramp (sign: tension +)
  double rampCrossings = 12;  ///< ramp time in units of L / c_p
  double damping = 600.0;     ///< 1/s (~ the lowest mode, pi c_p / (2 L))
  double hourglass = 1.0;
  double threshold = 0.5;     ///< a particle is "damaged" at D >= threshold
  double lowThreshold = 0.1;  ///< a second onset: the first particle at D >= lowThreshold
  std::string dump;           ///< CSV of X, Y, D at the end (and at onset/crossing: suffixed)
  bool clampBottom = false;   ///< also hold the bottom layer (one support deep) at u = 0
  /// with clampBottom: hold the bottom layer along y only (a roller, x free, as the top), so its
  /// ends are no clamped corners (a free rigid inclusion, issue 15 validation 5)
  bool bottomRoller = false;
  /// with bottomRoller: the bottom's imposed y displacement at the end of the ramp (0: held; a
  /// symmetric pull, top +uMax and bottom -uMax, keeps a free inclusion at rest: issue 15 item 5)
  double bottomUy = 0.0;
  long maxSteps = -1;         ///< stop after so many steps (cost measurements), -1: the whole ramp
  Inclusion inclusion = Inclusion::Clamped;
  double bodyDamping = 600.0; ///< 1/s, the free body's `damping` (as the clay's: quasi-static)
  double dtFactor = 0.5;      ///< dt = dtFactor x the solid's step limit (Eq. 2.50 with the AV term)
  double avAlpha = 0.0;       ///< Monaghan artificial viscosity (Eqs. 2.64-2.65; thesis Tab. 4.2: 41)
  double avBeta = 0.0;        ///< its beta
  /// crack-crossing measure: a lateral side counts as reached when a particle within
  /// `crossDepth` x dx of it has D >= crossThreshold (< 0: the onset threshold)
  double crossThreshold = -1.0;
  double crossDepth = 1.5;
  /// the solid's `damage_commit` (docs/damage.md "The commit lag"): step_end or evaluation
  std::string damageCommit = "step_end";
  /// the solid's formulation: total_lagrangian (hourglass control possible) or
  /// small_strain_stress (the thesis' infinitesimal strain, but its stress form: docs/solid.md)
  std::string formulation = "total_lagrangian";
  std::string plane = "strain";  ///< plane strain or stress (the thesis does not say)
  /// after the ramp, hold the imposed displacement for so many L / c_p (quasi-static test: does
  /// the crack cross at a fixed load?)
  double holdCrossings = 0.0;
};

struct PlateResult {
  double uOnset = 0.0;      ///< imposed displacement when the first particle reached the threshold (0: never)
  double xOnset = 0.0, yOnset = 0.0;
  double uOnsetLow = 0.0;   ///< ... when the first particle reached lowThreshold (0: never)
  double xOnsetLow = 0.0, yOnsetLow = 0.0;
  double uCross = 0.0;      ///< ... when damaged particles touch both lateral sides (0: never)
  /// the crossing (within crossDepth x dx of both sides) at D >= 0.1 / 0.5 / 0.9 / 0.99 (0: never)
  double uCrossAt[4] = {0.0, 0.0, 0.0, 0.0};
  double asymmetry = 0.0;   ///< sum |D(x, y) - D(-x, y)| / sum D at the end
  double width = 0.0;       ///< damaged width across the crack at x = +-(a + L/6) [m], at the end
  double widthCross = 0.0;  ///< the same when the crack first reached both sides
  /// at the crossing, the width (D >= threshold) averaged over the columns 70 <= |x| <= 140 mm
  double widthMeanCross = 0.0;
  /// time after the end of the ramp at which the crack reached both sides, in L / c_p (0: during
  /// the ramp or never)
  double holdCross = 0.0;
  double balance = 0.0;     ///< energy balance residual / work in
  double dissipated = 0.0;  ///< released energy [J per m of thickness]
  double dmax = 0.0;
  long particles = 0, steps = 0, clipped = 0;
  double wall = 0.0;
  double dt = 0.0;
  // rigid inclusion: the body's displacement [m] and rotation [rad] at onset and at the end,
  // and the force of the clay on it along y at the end [N per m of thickness]
  double bodyUxOnset = 0.0, bodyUyOnset = 0.0, bodyRotOnset = 0.0;
  double bodyUyOnsetLow = 0.0, bodyUyCross = 0.0;  ///< at the D >= lowThreshold onset, at crossing
  double bodyUyMax = 0.0;  ///< largest displacement along y during the run
  /// D on the reference lattice (row iy = floor((Y + L/2) / dx) times gridN plus column) when the
  /// crack first reached both sides (crack pattern comparisons)
  std::vector<double> gridCross;
  int gridN = 0;
  double bodyUx = 0.0, bodyUy = 0.0, bodyRot = 0.0, bodyFy = 0.0;
};

inline void dumpCsv(const std::string& path, const Simulation& sim) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return;
  const double* X = sim.store.data(sim.store.real("reference_position"));
  const double* x = sim.store.data(sim.store.position());
  const double* D = sim.store.data(sim.store.real("damage"));
  std::fprintf(f, "X,Y,x,y,D\n");
  for (Index i = 0; i < sim.store.realCount(); ++i)
    std::fprintf(f, "%.6g,%.6g,%.9g,%.9g,%.5g\n", X[2 * i], X[2 * i + 1], x[2 * i], x[2 * i + 1], D[i]);
  std::fclose(f);
}

inline PlateResult runPlate(const PlateSetup& s) {
  PlateResult r;
  const auto t0 = std::chrono::steady_clock::now();
  const double L = 0.3, a = 0.05, E = 12000e6, nu = 0.25, rho = 1e6;
  Simulation sim(2);
  char buf[512];
  char av[120] = "";  // the solid's own artificial-viscosity term (elastic_solid.cpp), both materials
  if (s.avAlpha > 0.0 || s.avBeta > 0.0)
    std::snprintf(av, sizeof av, ", artificial_viscosity: {alpha: %g, beta: %g}", s.avAlpha, s.avBeta);
  std::snprintf(buf, sizeof buf,
                "{density: %g, young_modulus: %g, poisson_ratio: %g, formulation: %s, plane: %s, "
                "hourglass: %g, damping: %g%s%s%s}",
                rho, E, nu, s.formulation.c_str(), s.plane.c_str(), s.hourglass, s.damping, av,
                s.law.empty() ? "" : ", damage: ", s.law.c_str());
  addMaterial(sim, "matrix", "elastic", buf);
  std::snprintf(buf, sizeof buf,
                "{density: %g, young_modulus: %g, poisson_ratio: %g, formulation: %s, plane: %s, "
                "hourglass: %g, damping: %g%s}",
                rho, E, nu, s.formulation.c_str(), s.plane.c_str(), s.hourglass, s.damping, av);
  const bool rigidInclusion = s.inclusion != Inclusion::Clamped;
  if (rigidInclusion) {
    std::snprintf(buf, sizeof buf, "{density: %g, bonded: true, damping: %g%s}", rho, s.bodyDamping,
                  s.inclusion == Inclusion::RigidFixed ? ", fixed: true" : "");
    addMaterial(sim, "inclusion", "rigid", buf);
  } else {
    addMaterial(sim, "inclusion", "elastic", buf);
  }
  const int n = static_cast<int>(std::lround(L / s.dx));
  const double dx = L / n;
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::CubicSpline, 2, 0.5 * s.support);
  const Index first = buildBlock<2>(sim, Vec<2>(-0.5 * L, -0.5 * L), {n, n, 1}, dx, 0);
  {
    double* x = sim.store.data(sim.store.position());
    std::int32_t* mat = sim.store.data(sim.store.material());
    for (Index i = first; i < sim.store.realCount(); ++i)
      if (std::hypot(x[2 * i], x[2 * i + 1]) <= a) mat[i] = 1;
  }
  sim.domain.lo = {-L, -L, 0};
  sim.domain.hi = {L, L, 1};
  const double yTop = 0.5 * L - s.support;
  const double c = std::sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) / rho);
  const double ramp = s.rampCrossings * L / c;
  char bottomBuf[200];
  if (s.bottomRoller)
    std::snprintf(bottomBuf, sizeof bottomBuf,
                  "{name: bottom, type: displacement, displacement: [0, %.9g], components: [y], "
                  "ramp_time: %.9g, box: {min: [-1, -1], max: [1, %.9g]}}, ",
                  s.bottomUy, ramp, -0.5 * L + s.support);
  else
    std::snprintf(bottomBuf, sizeof bottomBuf,
                  "{name: bottom, type: clamped, box: {min: [-1, -1], max: [1, %.9g]}}, ",
                  -0.5 * L + s.support);
  const std::string bottom = bottomBuf;
  const std::string commitKey = s.law.empty() ? "" : "damage_commit: " + s.damageCommit + ", ";
  std::snprintf(buf, sizeof buf,
                "{%sboundaries: [%s%s"
                "{name: top, type: displacement, displacement: [0, %.9g], components: [y], "
                "ramp_time: %.9g, box: {min: [-1, %.9g], max: [1, 1]}}]}",
                commitKey.c_str(), s.clampBottom ? bottom.c_str() : "",
                rigidInclusion ? "" : "{name: inclusion, type: clamped, material: inclusion}, ", s.uMax,
                ramp, yTop);
  ElasticSolidModule& solid = addSolidModule(sim, buf);
  RigidModule* rigid = nullptr;
  if (rigidInclusion) {
    std::unique_ptr<Module> mod = ModuleRegistry::create("rigid");
    mod->configure(sim, {&sim.materials[1]}, nullptr);
    rigid = dynamic_cast<RigidModule*>(mod.get());
    sim.addModule(std::move(mod));
    // the body's particles: rigid phase, mass rho dx^2 (the scene loader's job in a scene file)
    std::int32_t* ph = sim.store.data(sim.store.phase());
    double* m = sim.store.data(sim.store.mass());
    double* den = sim.store.data(sim.store.density());
    const std::int32_t* mt = sim.store.data(sim.store.material());
    for (Index i = first; i < sim.store.realCount(); ++i)
      if (mt[i] == 1) {
        ph[i] = kPhaseRigid;
        m[i] = rho * dx * dx;
        den[i] = rho;
      }
  }
  solid.initialise(sim);
  if (rigid) {
    sim.checkPairOwners();  // solid-rigid: the rigid module's (the solid set its phase above)
    rigid->initialise(sim);
  }
  r.particles = sim.store.realCount();
  // the bonds' own limit (RigidModule::timeStepLimit; no motion yet) where they are present
  const double dt = std::min(s.dtFactor * solid.elasticTimeStepLimit(sim),
                             rigid ? rigid->timeStepLimit(sim) : 1e300);
  r.dt = dt;
  auto bodyMotion = [&](double& ux, double& uy, double& rot) {
    if (!rigid) return;
    const RigidBody& B = rigid->bodies()[0];
    ux = B.state.X[0] - B.X0[0];
    uy = B.state.X[1] - B.X0[1];
    rot = 2.0 * std::atan2(B.state.q.z(), B.state.q.w());  // about z (2D)
  };
  auto integrator = makeIntegrator("leapfrog");
  const double* X = sim.store.data(sim.store.real("reference_position"));
  const std::int32_t* mat = sim.store.data(sim.store.material());
  const std::int32_t* mo = sim.store.data(sim.motion);
  auto balance = [&] {
    const auto w = solid.work(sim);
    return solid.kineticEnergy(sim) + solid.elasticEnergy(sim) + solid.hourglassEnergy(sim) + w[2] +
           solid.damageDissipation(sim) - w[0] - w[1];
  };
  if (s.maxSteps >= 0) {  // cost measurement
    const auto c0 = std::chrono::steady_clock::now();
    while (r.steps < s.maxSteps) {
      integrator->step(sim, dt);
      ++r.steps;
    }
    r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count();
    return r;
  }
  // left-right asymmetry and damaged width of the current damage field
  std::vector<double> grid;
  double widthMean = 0.0;  // set by measure: the width averaged over 70 <= |x| <= 140 mm
  auto measure = [&](double& asym, double& width) {
    const double* Dm = sim.store.data(sim.store.real("damage"));
    grid.assign(static_cast<size_t>(n) * n, 0.0);
    for (Index i = first; i < sim.store.realCount(); ++i) {
      const int ix = static_cast<int>(std::floor((X[2 * i] + 0.5 * L) / dx));
      const int iy = static_cast<int>(std::floor((X[2 * i + 1] + 0.5 * L) / dx));
      grid[static_cast<size_t>(iy) * n + ix] = Dm[i];
    }
    double diff = 0.0, sum = 0.0;
    for (int iy = 0; iy < n; ++iy)
      for (int ix = 0; ix < n; ++ix) {
        diff += std::abs(grid[static_cast<size_t>(iy) * n + ix] - grid[static_cast<size_t>(iy) * n + (n - 1 - ix)]);
        sum += grid[static_cast<size_t>(iy) * n + ix];
      }
    asym = sum > 0.0 ? 0.5 * diff / sum : 0.0;
    // on the columns at x = +-(a + L/6) (half way from the inclusion to the sides): the number of
    // particles at D >= threshold times dx, averaged over the two columns
    width = 0.0;
    for (int side : {-1, 1}) {
      const double xc = side * (a + L / 6.0);
      const int ix = std::clamp(static_cast<int>(std::floor((xc + 0.5 * L) / dx)), 0, n - 1);
      int count = 0;
      for (int iy = 0; iy < n; ++iy) count += grid[static_cast<size_t>(iy) * n + ix] >= s.threshold;
      width += 0.5 * count * dx;
    }
    int columns = 0, count = 0;
    for (int ix = 0; ix < n; ++ix) {
      const double xc = std::abs(-0.5 * L + (ix + 0.5) * dx);
      if (xc < 0.07 || xc > 0.14) continue;
      ++columns;
      for (int iy = 0; iy < n; ++iy) count += grid[static_cast<size_t>(iy) * n + ix] >= s.threshold;
    }
    widthMean = columns > 0 ? count * dx / columns : 0.0;
  };
  bool onset = false, crossed = false;  // (u < 0 in compression)
  r.uOnset = r.uCross = 0.0;
  const double tEnd = ramp + s.holdCrossings * L / c;
  while (sim.time < tEnd * (1 - 1e-9)) {
    integrator->step(sim, std::min(dt, (sim.time < ramp * (1 - 1e-9) ? ramp : tEnd) - sim.time));
    ++r.steps;
    if (rigid) {
      double ux = 0.0, uy = 0.0, rot = 0.0;
      bodyMotion(ux, uy, rot);
      r.bodyUyMax = std::max(r.bodyUyMax, uy);
    }
    if (s.law.empty()) continue;  // elastic reference run (no damage field)
    const double u = s.uMax * std::min(1.0, sim.time / ramp);
    const double* D = sim.store.data(sim.store.real("damage"));
    bool left = false, right = false;
    const double crossD = s.crossThreshold < 0.0 ? s.threshold : s.crossThreshold;
    static constexpr double kCrossLevels[4] = {0.1, 0.5, 0.9, 0.99};
    bool leftAt[4] = {false, false, false, false}, rightAt[4] = {false, false, false, false};
    for (Index i = 0; i < sim.store.realCount(); ++i) {
      if (mat[i] != 0 || mo[i] == kMotionPrescribed) continue;
      for (int k = 0; k < 4; ++k)
        if (D[i] >= kCrossLevels[k]) {
          if (X[2 * i] < -0.5 * L + s.crossDepth * dx) leftAt[k] = true;
          if (X[2 * i] > 0.5 * L - s.crossDepth * dx) rightAt[k] = true;
        }
      if (D[i] >= crossD) {
        if (X[2 * i] < -0.5 * L + s.crossDepth * dx) left = true;
        if (X[2 * i] > 0.5 * L - s.crossDepth * dx) right = true;
      }
      if (r.uOnsetLow == 0.0 && D[i] >= s.lowThreshold) {
        r.uOnsetLow = u;
        r.xOnsetLow = X[2 * i];
        r.yOnsetLow = X[2 * i + 1];
        double ux = 0.0, rot = 0.0;
        bodyMotion(ux, r.bodyUyOnsetLow, rot);
      }
      if (D[i] < s.threshold) continue;
      if (!onset) {
        onset = true;
        r.uOnset = u;
        r.xOnset = X[2 * i];
        r.yOnset = X[2 * i + 1];
        bodyMotion(r.bodyUxOnset, r.bodyUyOnset, r.bodyRotOnset);
        if (!s.dump.empty()) dumpCsv(s.dump + "_onset.csv", sim);
      }
    }
    for (int k = 0; k < 4; ++k)
      if (leftAt[k] && rightAt[k] && r.uCrossAt[k] == 0.0) r.uCrossAt[k] = u;
    if (left && right && !crossed) {
      crossed = true;
      r.uCross = u;
      if (sim.time > ramp * (1 + 1e-9)) r.holdCross = (sim.time - ramp) * c / L;
      double asym = 0.0;
      measure(asym, r.widthCross);
      r.widthMeanCross = widthMean;
      r.gridCross = grid;
      r.gridN = n;
      double ux = 0.0, rot = 0.0;
      bodyMotion(ux, r.bodyUyCross, rot);
      if (!s.dump.empty()) dumpCsv(s.dump + "_cross.csv", sim);
    }
  }
  if (!s.law.empty()) {
    const double* D = sim.store.data(sim.store.real("damage"));
    for (Index i = first; i < sim.store.realCount(); ++i) r.dmax = std::max(r.dmax, D[i]);
    measure(r.asymmetry, r.width);
  }
  const auto w = solid.work(sim);
  r.balance = std::abs(balance()) / std::max(std::abs(w[0]), 1e-300);
  r.dissipated = solid.damageDissipation(sim);
  r.clipped = solid.clippedDamageUpdates();
  bodyMotion(r.bodyUx, r.bodyUy, r.bodyRot);
  if (rigid) r.bodyFy = rigid->bodies()[0].force[1];
  if (!s.dump.empty() && !s.law.empty()) dumpCsv(s.dump + "_end.csv", sim);
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

/// The tension plate of the tests and studies (docs/damage.md "The plate at 200 / 300 / 400
/// points"): the top pulled along y to uMax over rampCrossings L / c_p, the bottom layer held with
/// the inclusion (with the inclusion alone the crack wraps around it and runs down to the bottom
/// edge), no hourglass control (with hourglass 1, E-stiff springs that the damage does not soften
/// and whose energy is not in the stored energy, the crack needs ~2x the onset displacement to
/// cross and the energy balance leaves 14-18 % of the work), the damage committed at the
/// evaluation (a^{n+1} with D^{n+1}, "The commit lag"); AT-2 with Yc0 = 2500 Pa and dt = 0.5 x
/// Eq. 2.50 unless the caller changes them.
inline PlateSetup tensionPlate(double dx, double support, double uMax, double rampCrossings) {
  PlateSetup s;
  s.dx = dx;
  s.support = support;
  s.uMax = uMax;
  s.rampCrossings = rampCrossings;
  s.clampBottom = true;
  s.hourglass = 0.0;
  s.damageCommit = "evaluation";
  return s;
}

/// The coarse tension plate of the default tests: 60 x 60 points (dx = 5 mm), 2h = 12.5 mm, to
/// 60 um over 24 L / c_p (2.5 um per L / c_p).
inline PlateSetup coarseTensionPlate() { return tensionPlate(5e-3, 12.5e-3, 60e-6, 24); }

/// Onset (first D >= threshold) on the upper half of the inclusion's boundary (radius a, within
/// two supports of it), a crack that reaches both sides, left-right symmetry within 10 %.
inline void expectCrackFromTheInclusionTopToBothSides(const PlateResult& r, const PlateSetup& s, double a) {
  ASSERT_GT(r.uOnset, 0.0) << "no damage";
  const double rOnset = std::hypot(r.xOnset, r.yOnset);
  EXPECT_GT(r.yOnset, 0.0);
  EXPECT_GE(rOnset, a);
  EXPECT_LT(rOnset, a + 2 * s.support);
  EXPECT_GT(r.uCross, r.uOnset) << "the crack did not reach both sides";
  EXPECT_LT(r.asymmetry, 0.10);
}

}  // namespace poresph::solid::plate
