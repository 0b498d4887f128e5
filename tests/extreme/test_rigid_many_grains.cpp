// Rigid bodies (physics/rigid, docs/rigid.md), extreme of issue 15: 1e3 bodies in one scene, in a
// fluid matrix. The scene is samples/rigid_many_grains.yaml (read here): 1000 free grains of 2 x 2
// particles in a periodic viscous fluid, a checkerboard of two densities settling under a body
// force balanced by the fluid's (total force zero), every heavy grain catching up with the light
// one below it (rigid-rigid contacts, A.18, through the fluid). Asserted over the run: every body
// finite, no two bodies closer than 0.5 dx (no body crossing another), the grains settling
// relative to the fluid (heavy faster than light), the total linear momentum of fluid + bodies
// conserved to 1e-10 of the bodies' momentum. Reported (timings of a loaded machine, not
// asserted): the CPU per step and body against the same scene with the bodies `fixed: true` and
// with the grains' particles made fluid.
// Study switches: RIGID_GRAINS_STEPS (steps of the free run, default 300), RIGID_GRAINS_COMPARE
// (steps of each timed run, default 30, 0: none), RIGID_GRAINS_REPEAT (timed runs of each variant,
// by turns, the fastest kept; default 1), RIGID_GRAINS_QUARTER=1 (the lower-left
// quarter of the scene: 20 x 13 = 260 grains, the per-body cost at a quarter of the bodies),
// RIGID_GRAINS_SCENE (a variant of the sample file to read instead).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"
#include "physics/rigid/rigid_module.hpp"
#include "tests/extreme/rigid_many_bodies_case.hpp"

using namespace poresph;

namespace {

enum class Variant { Free, Fixed, Fluid };

int envInt(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : fallback;
}

/// The sample, with the grains free (as written), held (`fixed: true`) or made of the fluid (no
/// bodies, no body force); `quarter`: only the grains of the lower-left quarter of the box, in a
/// box of that size. The fluid's body force is recomputed from the grains kept (the sample's
/// value for the whole scene, checked).
std::string sceneText(Variant v, bool quarter, double* sampleFluidG = nullptr) {
  const char* other = std::getenv("RIGID_GRAINS_SCENE");  // (study: a variant of the sample)
  std::ifstream in(other ? std::string(other) : std::string(PORESPH_SOURCE_DIR) + "/samples/rigid_many_grains.yaml");
  EXPECT_TRUE(in.good()) << "samples/rigid_many_grains.yaml not found";
  const double hiX = quarter ? 0.08 : 0.16, hiY = quarter ? 0.052 : 0.1;
  double grainMass = 0.0, G = 0.0;
  long grains = 0;
  std::ostringstream out, geometry;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("domain:", 0) == 0) {
      out << "domain: {lo: [0, 0], hi: [" << hiX << ", " << hiY << "], periodic: [true, true]}\n";
    } else if (line.rfind("rigid:", 0) == 0) {
      const size_t p = line.find(", ");
      G = -std::atof(line.c_str() + p + 2);
      if (v != Variant::Fluid) out << line << "\n";
    } else if (line.rfind("fluid:", 0) == 0) {
      if (sampleFluidG) *sampleFluidG = std::atof(line.c_str() + line.find(", ") + 2);
    } else if (line.rfind("  - {shape: box", 0) == 0 && line.find("material: water") != std::string::npos) {
      geometry << "  - {shape: box, lo: [0, 0], hi: [" << hiX << ", " << hiY << "], material: water}\n";
    } else if (line.rfind("  - {shape: box", 0) == 0) {
      const double lx = std::atof(line.c_str() + line.find("lo: [") + 5);
      const double ly = std::atof(line.c_str() + line.find(", ", line.find("lo: [")) + 2);
      if (lx > hiX || ly > hiY) continue;
      const bool heavy = line.find("material: heavy") != std::string::npos;
      grainMass += 4.0 * (heavy ? 3000.0 : 1500.0) * 1e-6;
      ++grains;
      if (v == Variant::Fluid) {
        const size_t p = line.find(heavy ? "heavy" : "light");
        line.replace(p, 5, "water");
      }
      geometry << line << "\n";
    } else if (v == Variant::Fixed && line.find("model: rigid") != std::string::npos) {
      const size_t p = line.find(", contact_modulus");
      out << line.substr(0, p) << ", fixed: true" << line.substr(p) << "\n";
    } else if (line.rfind("geometry:", 0) != 0) {
      out << line << "\n";
    }
  }
  const double fluidMass = 1000.0 * 1e-6 * (std::llround(hiX * 1e3) * std::llround(hiY * 1e3) - 4 * grains);
  if (v != Variant::Fluid) out << "fluid: {gravity: [0, " << G * grainMass / fluidMass << "]}\n";
  if (sampleFluidG && !quarter) {
    EXPECT_NEAR(*sampleFluidG, G * grainMass / fluidMass, 1e-12);
  }
  out << "geometry:\n" << geometry.str();
  return out.str();
}

Vec<2> totalMomentum(const Simulation& sim) {
  const ParticleStore& st = sim.store;
  Vec<2> p = Vec<2>::Zero();
  for (Index i = 0; i < st.realCount(); ++i) p += st.data(st.mass())[i] * st.vec<2>(st.velocity(), i);
  return p;
}

/// CPU seconds per step of `steps` steps of the scene (after one untimed step).
double cpuPerStep(const std::string& text, int steps) {
  Scene s = loadSceneText(text, "rigid_many_grains.yaml");
  auto integrator = makeIntegrator("leapfrog");
  const double dt = s.nextTimeStep();
  integrator->step(*s.sim, dt);
  const double c0 = static_cast<double>(std::clock());
  for (int k = 0; k < steps; ++k) integrator->step(*s.sim, dt);
  return (static_cast<double>(std::clock()) - c0) / CLOCKS_PER_SEC / steps;
}

}  // namespace

TEST(RigidManyGrains, ThousandGrainsSettleThroughAFluidWithoutCrossing) {
  const bool quarter = envInt("RIGID_GRAINS_QUARTER", 0) != 0;
  const int steps = envInt("RIGID_GRAINS_STEPS", 300), compare = envInt("RIGID_GRAINS_COMPARE", 30);
  double sampleG = 0.0;
  Scene s = loadSceneText(sceneText(Variant::Free, quarter, &sampleG), "rigid_many_grains.yaml");
  Simulation& sim = *s.sim;
  auto* rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  ASSERT_NE(rigid, nullptr);
  const auto& bodies = rigid->bodies();
  const size_t nb = bodies.size();
  if (!std::getenv("RIGID_GRAINS_SCENE")) {
    ASSERT_EQ(nb, quarter ? 260u : 1000u);
  }
  const double dx = sim.spacing;
  auto integrator = makeIntegrator("leapfrog");
  const Vec<2> p0 = totalMomentum(sim);
  double gapMin = test::minBodyGap2D(sim), drift = 0.0;
  const double gap0 = gapMin;
  const double dt = s.nextTimeStep();
  integrator->step(sim, dt);  // (untimed: first neighbour lists)
  const double c0 = static_cast<double>(std::clock());
  double inChecks = 0.0;
  for (int k = 2; k <= steps; ++k) {
    integrator->step(sim, dt);
    if (k % 10 != 0 && k != steps) continue;
    const double t0 = static_cast<double>(std::clock());
    gapMin = std::min(gapMin, test::minBodyGap2D(sim));
    double pBodies = 0.0;
    for (const RigidBody& b : bodies) pBodies += b.state.mass * b.state.V.norm();
    drift = std::max(drift, (totalMomentum(sim) - p0).norm() / pBodies);
    inChecks += static_cast<double>(std::clock()) - t0;
  }
  const double cpuFree = (static_cast<double>(std::clock()) - c0 - inChecks) / CLOCKS_PER_SEC / (steps - 1);
  // settling: mean velocities of the heavy and light grains relative to the fluid's mean
  const ParticleStore& st = sim.store;
  const std::int32_t* ph = st.data(st.phase());
  double fluidVy = 0.0, fluidM = 0.0, heavyVy = 0.0, lightVy = 0.0, heavyN = 0.0, lightN = 0.0;
  bool finite = true;
  for (Index i = 0; i < st.realCount(); ++i)
    if (ph[i] == kPhaseFluid) {
      fluidVy += st.data(st.mass())[i] * st.vec<2>(st.velocity(), i)[1];
      fluidM += st.data(st.mass())[i];
    }
  fluidVy /= fluidM;
  double rhoVar = 0.0;  // largest |rho - rho0| / rho0 of the fluid (the health check's limit is 0.1)
  for (Index i = 0; i < st.realCount(); ++i)
    if (ph[i] == kPhaseFluid) rhoVar = std::max(rhoVar, std::abs(st.data(st.density())[i] / 1000.0 - 1.0));
  double omegaMax = 0.0;
  for (const RigidBody& b : bodies) {
    finite = finite && std::isfinite(b.state.X[0]) && std::isfinite(b.state.X[1]) && std::isfinite(b.state.V[1]);
    const bool heavy = b.state.mass > 1.5 * 4 * 1500.0 * dx * dx;
    (heavy ? heavyVy : lightVy) += b.state.V[1] - fluidVy;
    (heavy ? heavyN : lightN) += 1.0;
    omegaMax = std::max(omegaMax, std::abs(b.state.omega().z()));
  }
  heavyVy /= heavyN;
  lightVy /= lightN;
  std::printf("  %zu grains (%lld particles), %d steps of %.3g s to t = %.4f s: heavy grains %.4f m/s, light %.4f m/s "
              "relative to the fluid (fluid mean %.2e m/s); closest approach of two bodies %.3f dx (start 3 dx; read capped at %.0f dx); "
              "largest spin %.3g rad/s; momentum drift %.2e of the bodies' momentum; fluid density variation %.3f\n",
              nb, static_cast<long long>(st.realCount()), steps, dt, sim.time, heavyVy, lightVy, fluidVy, gapMin / dx,
              gap0 / dx, omegaMax, drift, rhoVar);
  EXPECT_TRUE(finite);
  // the grains squeeze the fluid between them: 7.6 % at 0.06 s (c = 1 m/s keeps the test cheap;
  // `poresph run` of the sample stops at 0.096 s on the health check's 10 %)
  EXPECT_LT(rhoVar, 0.1) << "the fluid is no longer weakly compressible";
  EXPECT_LT(heavyVy, lightVy) << "the heavy grains should settle faster";
  EXPECT_LT(lightVy, 0.0) << "the light grains (1.5 x the fluid's density) should settle";
  EXPECT_LT(heavyVy, 0.0);
  EXPECT_GT(gapMin, 0.5 * dx) << "bodies cross each other";
  EXPECT_LT(gapMin, dx) << "no two grains came within the A.18 contact range (dx): no contact tested";
  EXPECT_LT(drift, 1e-10) << "total momentum not conserved";
  std::printf("  cost of the run: %.1f ms CPU per step, %.1f us per step and body (%lld particles; one thread, "
              "loaded machine)\n",
              1e3 * cpuFree, 1e6 * cpuFree / nb, static_cast<long long>(st.realCount()));
  if (compare > 0) {
    // the three variants by turns, the fastest of `repeat` runs each (a loaded machine)
    const int repeat = std::max(1, envInt("RIGID_GRAINS_REPEAT", 1));
    double tFree = 1e300, tFixed = 1e300, tFluid = 1e300;
    for (int r = 0; r < repeat; ++r) {
      tFree = std::min(tFree, cpuPerStep(sceneText(Variant::Free, quarter), compare));
      tFixed = std::min(tFixed, cpuPerStep(sceneText(Variant::Fixed, quarter), compare));
      tFluid = std::min(tFluid, cpuPerStep(sceneText(Variant::Fluid, quarter), compare));
    }
    std::printf("  CPU per step (%d steps, fastest of %d): bodies free %.2f ms, fixed %.2f ms, grains as fluid %.2f ms; "
                "per step and body: free - fluid %.2f us, fixed - fluid %.2f us, free - fixed %.2f us (one thread, "
                "loaded machine)\n",
                compare, repeat, 1e3 * tFree, 1e3 * tFixed, 1e3 * tFluid, 1e6 * (tFree - tFluid) / nb,
                1e6 * (tFixed - tFluid) / nb, 1e6 * (tFree - tFixed) / nb);
  }
}

// Study (RIGID_GRAINS_PROBE=free|fixed|fluid [steps]): the total momentum of a variant of the
// scene (RIGID_GRAINS_SCENE or the sample), fluid and bodies apart, every 10 steps.
TEST(RigidManyGrains, MomentumProbe) {
  const char* env = std::getenv("RIGID_GRAINS_PROBE");
  if (!env) GTEST_SKIP() << "set RIGID_GRAINS_PROBE=free|fixed|fluid [steps]";
  std::istringstream in(env);
  std::string kind;
  int steps = 50;
  in >> kind >> steps;
  const Variant v = kind == "fixed" ? Variant::Fixed : kind == "fluid" ? Variant::Fluid : Variant::Free;
  Scene s = loadSceneText(sceneText(v, false), "rigid_many_grains.yaml");
  Simulation& sim = *s.sim;
  const ParticleStore& st = sim.store;
  const std::int32_t* ph = st.data(st.phase());
  auto split = [&](Vec<2>& pf, Vec<2>& pr, double& scale) {
    pf.setZero();
    pr.setZero();
    scale = 0.0;
    for (Index i = 0; i < st.realCount(); ++i) {
      const Vec<2> mv = st.data(st.mass())[i] * st.vec<2>(st.velocity(), i);
      (ph[i] == kPhaseFluid ? pf : pr) += mv;
      scale += mv.norm();
    }
  };
  auto integrator = makeIntegrator("leapfrog");
  const double dt = s.nextTimeStep();
  Vec<2> pf0, pr0;
  double scale0 = 0.0;
  split(pf0, pr0, scale0);
  for (int k = 1; k <= steps; ++k) {
    integrator->step(sim, dt);
    if (k % 10 && k > 5) continue;
    Vec<2> pf, pr;
    double scale = 0.0;
    split(pf, pr, scale);
    std::printf("  step %d: fluid dP (%.3e, %.3e), bodies dP (%.3e, %.3e), total dP (%.3e, %.3e), / sum |m v| %.3e\n", k,
                pf[0] - pf0[0], pf[1] - pf0[1], pr[0] - pr0[0], pr[1] - pr0[1], pf[0] + pr[0] - pf0[0] - pr0[0],
                pf[1] + pr[1] - pf0[1] - pr0[1], (pf + pr - pf0 - pr0).norm() / scale);
  }
}
