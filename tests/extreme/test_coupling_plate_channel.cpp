// A one-voxel water channel in clay that opens onto a force-controlled plate (issues 11 / 16:
// docs/coupling.md and docs/drainage.md, "Pores opening onto a plate"). The main job's Ketton crop
// moved so that such a channel touches the front plate stopped at 2.08 ms: the channel's water
// was sucked into the 1-dx contact between the plate's first row and the clay's first row. The
// cause: the fluid saw the clay through the coupling's mirror model (continuity with the
// reflected relative velocity, twice the plain one) and the plate through the rigid module's
// extrapolated model (plain relative velocity), so a water particle moving down the channel
// towards the plate read as an expansion (the clay above counted twice against the plate below);
// its gauge pressure fell, the plate's extrapolated pressure followed, and the tension pulled it
// into the contact. The rigid module now takes the coupling's model where both act on a fluid.
//
// Minimal reproducer: a 7 x 9 x 7 clay block (periodic in x and z, top rows held) on a plate of
// 3 rows pushed up at 160 Pa (ramped over 2 ms, the main job's plate), a closed water column of
// 5 particles on the block's axis whose lowest particle sits in the clay's first row, next to
// the plate. Asserted: no water particle below the clay's first row (crossings into the
// plate-clay contact: 0), the density variation of the water within 3 % (the fluid's warning
// bound), the health checks passed, over 3.5 ms (~700 steps). With `fluid_rigid: extrapolated`
// (the former default) the same scene stops: the control case asserts that it still does, so
// the scene keeps its power to show the failure.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "libcore/health.hpp"
#include "libcore/integrator.hpp"
#include "libcore/scene.hpp"

using namespace poresph;

namespace {

std::string scene(const std::string& extra) {
  return std::string(R"(dimension: 3
domain: {lo: [0.0, -0.0003, 0.0], hi: [0.0007, 0.0009, 0.0007], periodic: [true, false, true]}
spacing: 1.0e-4
h_over_dx: 1.0
kernel: quintic_spline
integrator: leapfrog
end_time: 0.0035
time_step: {adaptive: true, cfl: 1.0}
output: {every_time: 0.001}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 5, viscosity: 0.01, background_pressure: 600}
  - {name: clay, model: elastic, density: 2000, young_modulus: 1.2e5, poisson_ratio: 0.1, formulation: total_lagrangian, hourglass: 1, damping: 200}
  - {name: plate, model: rigid, density: 2000, damping: 200, plate: {direction: [0, 1, 0], stress: 160, area: 4.9e-7, ramp_time: 0.002}}
geometry:
  - {shape: box, lo: [0.0, 0.0, 0.0], hi: [0.0007, 0.0009, 0.0007], material: clay}
  - {shape: box, lo: [0.0003, 0.0, 0.0003], hi: [0.0004, 0.0005, 0.0004], material: water}
  - {shape: box, lo: [0.0, -0.0003, 0.0], hi: [0.0007, 0.0, 0.0007], material: plate}
fluid: {pressure_reference: background}
solid:
  boundaries:
    - {name: top, type: displacement, components: [x, y, z], box: {min: [0.0, 0.0007, 0.0], max: [0.0007, 0.0009, 0.0007]}, material: clay, displacement: [0, 0, 0], ramp_time: 0.001}
)") + extra;
}

struct Outcome {
  double time = 0.0;
  double maxVariation = 0.0;  // max |rho - rho0| / rho0 of the water over the run
  Index crossings = 0;        // water particles found below the clay's first row (any check)
  double lowestWater = 1e300; // lowest water particle relative to the clay's first row, in dx
  std::vector<HealthIssue> issues;
};

Outcome run(const std::string& text, double endTime) {
  Scene s = loadSceneText(text, "plate_channel.yaml");
  Simulation& sim = *s.sim;
  ParticleStore& st = sim.store;
  auto integrator = makeIntegrator("leapfrog");
  HealthMonitor health(s.health);
  health.start(sim, s.initialStableTimeStep);
  const double dx = sim.spacing;
  Outcome o;
  int k = 0;
  while (sim.time < endTime) {
    integrator->step(sim, s.nextTimeStep());
    sim.checkFinite();
    ++k;
    const double* x = st.data(st.position());
    const double* rho = st.data(st.density());
    const std::int32_t* ph = st.data(st.phase());
    // the clay's first row: its particles that started within half a dx of y = 0.5 dx
    double yClay = 0.0;
    int nClay = 0;
    const double* x0 = st.has("reference_position") ? st.data(st.real("reference_position")) : nullptr;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (ph[i] != kPhaseSolid) continue;
      const double y0 = x0 ? x0[3 * i + 1] : x[3 * i + 1];
      if (std::abs(y0 - 0.5 * dx) > 0.25 * dx) continue;
      yClay += x[3 * i + 1];
      ++nClay;
    }
    yClay /= std::max(nClay, 1);
    for (Index i = 0; i < st.realCount(); ++i) {
      if (ph[i] != kPhaseFluid) continue;
      o.maxVariation = std::max(o.maxVariation, std::abs(rho[i] - 1000.0) / 1000.0);
      const double rel = (x[3 * i + 1] - yClay) / dx;
      o.lowestWater = std::min(o.lowestWater, rel);
      if (rel < -0.5) ++o.crossings;  // past the midline of the plate-clay contact
    }
    if (k % 10 == 0) {
      o.issues = health.check(sim);
      if (!o.issues.empty()) break;
    }
  }
  o.time = sim.time;
  return o;
}

}  // namespace

TEST(CouplingPlateChannel, WaterStaysInTheChannelUnderAStressedPlate) {
  const Outcome o = run(scene(""), 0.0035);
  std::printf("  one model (default): %.3f ms, max density variation %.2f %%, lowest water "
              "%.3f dx from the clay's first row, %lld crossings\n",
              o.time * 1e3, 100.0 * o.maxVariation, o.lowestWater,
              static_cast<long long>(o.crossings));
  EXPECT_GE(o.time, 0.0035 - 1e-9);
  EXPECT_EQ(o.crossings, 0);
  EXPECT_LT(o.maxVariation, 0.03);
  EXPECT_GT(o.lowestWater, -0.25);
  for (const auto& i : o.issues) ADD_FAILURE() << i.check << " " << i.value << " " << i.detail;
}

TEST(CouplingPlateChannel, MixedBoundaryModelsStillFail) {
  // Control: mirror clay, extrapolated plate (the former default) in one support.
  const Outcome o = run(scene("rigid: {fluid_rigid: extrapolated}\n"), 0.0035);
  std::printf("  mixed models (control): stopped at %.3f ms, max density variation %.2f %%, "
              "lowest water %.3f dx from the clay's first row, %lld crossings\n",
              o.time * 1e3, 100.0 * o.maxVariation, o.lowestWater,
              static_cast<long long>(o.crossings));
  EXPECT_GT(o.maxVariation, 0.05);
  EXPECT_FALSE(o.issues.empty());
}
