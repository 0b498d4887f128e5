// Only what a scene needs is allocated and run (issue 16 "Scene assembly", issue 17 memory):
// the modules a scene builds are its stage list (Simulation::evaluateRates calls each stage of
// each module in sim.modules, nothing else), and the store holds only the fields those modules
// registered. Also the per-owner memory report of `poresph info` (libcore/memory.hpp) and the
// run loop's rollback copy (RollbackState, libcore/health.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "libcore/health.hpp"
#include "libcore/memory.hpp"
#include "libcore/runner.hpp"
#include "libcore/scene.hpp"

using namespace poresph;

namespace {

// 2D water column between wall layers: fluid only.
const char* kFluid = R"(dimension: 2
domain: {lo: [-0.003, -0.003], hi: [0.013, 0.013]}
spacing: 0.001
kernel: wendland_c2
end_time: 1.0
time_step: {adaptive: true}
output: {every_steps: 100}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 10, viscosity: 1.0e-3}
  - {name: steel, model: wall, density: 1000}
geometry:
  - {shape: box, lo: [-0.003, -0.003], hi: [0.013, 0.013], material: steel}
  - {shape: box, lo: [0.0, 0.0], hi: [0.01, 0.01], material: water}
fluid:
  gravity: [0, -9.81]
)";

// A free 2D Total-Lagrangian clay block: solid only; DAMAGE is replaced by a damage law or "".
const char* kSolid = R"(dimension: 2
domain: {lo: [0, 0], hi: [0.01, 0.01]}
spacing: 0.001
end_time: 1.0
time_step: {adaptive: true}
output: {every_steps: 100}
materials:
  - {name: clay, model: elastic, density: 2000, young_modulus: 1.0e7, poisson_ratio: 0.25, formulation: total_lagrangian, hourglass: 1.0DAMAGE}
geometry:
  - {shape: box, lo: [0, 0], hi: [0.01, 0.01], material: clay}
)";

std::string solidScene(const std::string& damage) {
  std::string s = kSolid;
  s.replace(s.find("DAMAGE"), 6, damage);
  return s;
}

std::vector<std::string> moduleNames(const Simulation& sim) {
  std::vector<std::string> n;
  for (const auto& m : sim.modules) n.push_back(m->name());
  return n;
}

std::set<std::string> owners(const Simulation& sim) {
  std::set<std::string> o;
  for (const auto& f : sim.store.fields()) o.insert(f.owner);
  return o;
}

bool hasFieldContaining(const Simulation& sim, const std::string& part) {
  for (const auto& f : sim.store.fields())
    if (f.name.find(part) != std::string::npos) return true;
  return false;
}

// Advances a loaded scene by a few steps (the integrator registers its scratch then).
void step(Scene& s, long n) {
  const RunEstimate e = estimateRun(s, n, 30.0);
  ASSERT_TRUE(e.failure.empty()) << e.failure;
  ASSERT_GE(s.sim->step, n);
}

}  // namespace

TEST(OnlyWhatASceneNeeds, FluidOnlySceneRunsOnlyTheFluidAndHasNoSolidDamageOrRigidField) {
  Scene s = loadSceneText(kFluid, "fluid_only.yaml");
  step(s, 3);
  // The stage list: every stage of evaluateRates loops over sim.modules only.
  EXPECT_EQ(moduleNames(*s.sim), std::vector<std::string>{"fluid"});
  EXPECT_EQ(owners(*s.sim), (std::set<std::string>{"core", "fluid", "integrator"}));
  for (const char* part : {"solid", "damage", "stress", "strain", "deformation", "family",
                           "reference_position", "body", "bond", "piola"})
    EXPECT_FALSE(hasFieldContaining(*s.sim, part)) << part;
  // What the fluid registered is what it uses: pressure, density rate, wall velocity.
  EXPECT_TRUE(s.sim->store.has("pressure"));
  EXPECT_TRUE(s.sim->store.has("density_rate"));
}

// An inviscid fluid (every fluid material at viscosity 0; artificial viscosity only, as case A
// of docs/performance.md) holds neither the viscous normalisation factors nor the boundary's
// no-slip velocity, and its symmetric loops' sums are narrower (issue 17, memory); and it moves
// exactly as the full path does: with viscosity 1e-300 every viscous field, sum and pass is
// there, but the viscous term (~1e-296 m/s^2) is below the round-off of every acceleration, so
// the two runs must agree bit for bit, for the half list and the cell walk, with the artificial
// viscosity and density diffusion against the walls on.
TEST(OnlyWhatASceneNeeds, InviscidFluidHoldsNoViscousFactorsNorNoSlipVelocityAndMovesTheSame) {
  auto scene = [](const std::string& viscosity, const std::string& list) {
    std::string t = kFluid;
    t.replace(t.find("viscosity: 1.0e-3"), 17, "viscosity: " + viscosity);
    return t + "  artificial_viscosity: 0.1\n  density_diffusion: 0.1\nneighbour_list: " + list + "\n";
  };
  auto stateById = [](const Simulation& sim) {
    const ParticleStore& st = sim.store;
    const Index n = st.realCount();
    const int d = sim.dimension();
    std::vector<double> out(static_cast<size_t>(n) * (2 * d + 1));
    const std::int32_t* id = st.data(st.id());
    for (Index i = 0; i < n; ++i) {
      double* o = out.data() + static_cast<size_t>(id[i]) * (2 * d + 1);
      for (int a = 0; a < d; ++a) {
        o[a] = st.data(st.position())[i * d + a];
        o[d + a] = st.data(st.velocity())[i * d + a];
      }
      o[2 * d] = st.data(st.density())[i];
    }
    return out;
  };
  for (const char* list : {"half", "cells"}) {
    Scene lean = loadSceneText(scene("0.0", list), "inviscid.yaml");
    Scene full = loadSceneText(scene("1.0e-300", list), "tiny_viscosity.yaml");
    step(lean, 40);
    step(full, 40);
    for (const char* f : {"viscous_factor", "viscous_factor_next", "wall_velocity"}) {
      EXPECT_FALSE(lean.sim->store.has(f)) << list << " " << f;
      EXPECT_TRUE(full.sim->store.has(f)) << list << " " << f;
    }
    // 32 B per particle less in the store in 2D (2 factors, 2 no-slip components) and narrower
    // sums (2D: force loop 4 instead of 5, wall extrapolation 4 instead of 6 per particle).
    EXPECT_EQ(full.sim->store.bytesPerParticle() - lean.sim->store.bytesPerParticle(), 32u) << list;
    EXPECT_LT(lean.sim->module("fluid")->heldBytes(), full.sim->module("fluid")->heldBytes()) << list;
    ASSERT_EQ(lean.sim->step, full.sim->step);
    const std::vector<double> a = stateById(*lean.sim), b = stateById(*full.sim);
    ASSERT_EQ(a.size(), b.size());
    double moved = 0.0;
    size_t differ = 0;
    for (size_t k = 0; k < a.size(); ++k) differ += a[k] != b[k];
    const int d = lean.sim->dimension();
    for (size_t k = 0; k < a.size(); k += 2 * d + 1) moved = std::max(moved, std::abs(a[k + d + 1]));
    EXPECT_EQ(differ, 0u) << list;
    EXPECT_GT(moved, 1e-4) << list << ": the column must move (gravity) for the test to mean anything";
  }
}

// The integrator's position copy r^n is read by the predictor-corrector only: verlet and
// leapfrog register just the velocity copy (and one per integrated field; issue 17, memory).
TEST(OnlyWhatASceneNeeds, PositionCopyOnlyForThePredictorCorrector) {
  for (const char* scheme : {"verlet", "leapfrog", "predictor_corrector"}) {
    Scene s = loadSceneText(std::string(kFluid) + "integrator: " + scheme + "\n", "scheme.yaml");
    step(s, 2);
    EXPECT_TRUE(s.sim->store.has("integrator_velocity")) << scheme;
    EXPECT_EQ(s.sim->store.has("integrator_position"), std::string(scheme) == "predictor_corrector")
        << scheme;
  }
}

TEST(OnlyWhatASceneNeeds, SolidOnlySceneBuildsNoFluidSumsAndWithoutDamageNoDamageField) {
  Scene s = loadSceneText(solidScene(""), "solid_only.yaml");
  step(s, 2);
  EXPECT_EQ(moduleNames(*s.sim), std::vector<std::string>{"solid"});
  EXPECT_EQ(owners(*s.sim), (std::set<std::string>{"core", "solid", "integrator"}));
  for (const char* part : {"pressure", "colour", "curvature", "interface", "wall_velocity",
                           "viscous", "damage", "body"})
    EXPECT_FALSE(hasFieldContaining(*s.sim, part)) << part;
  // The TL family exists for a TL solid (the test sees the solid's fields at all): a row field in
  // the store, the rows held by the module.
  EXPECT_TRUE(s.sim->store.has("solid_family_row"));
  EXPECT_TRUE(s.sim->store.has("deformation_gradient"));
}

TEST(OnlyWhatASceneNeeds, DamageFieldsOnlyWhenAMaterialHasADamageLaw) {
  Scene s = loadSceneText(
      solidScene(", damage: {law: pcw, strain_onset: 0.022, strain_ultimate: 0.060}"),
      "solid_damage.yaml");
  EXPECT_EQ(moduleNames(*s.sim), std::vector<std::string>{"solid"});
  EXPECT_TRUE(s.sim->store.has("damage"));
  EXPECT_TRUE(s.sim->store.has("damage_dissipation"));
  Scene plain = loadSceneText(solidScene(""), "solid_plain.yaml");
  EXPECT_LT(plain.sim->store.bytesPerParticle(), s.sim->store.bytesPerParticle());
}

TEST(MemoryReport, LinesAddUpAndNameEveryOwnerOfTheStore) {
  Scene s = loadSceneText(kFluid, "fluid_report.yaml");
  step(s, 2);
  const Simulation& sim = *s.sim;
  const MemoryReport r = memoryReport(sim, 0, 0.0);
  EXPECT_EQ(r.particles, static_cast<std::uint64_t>(sim.store.realCount()));
  double sum = 0.0, fields = 0.0, rollback = -1.0, list = -1.0;
  for (const auto& l : r.lines) {
    sum += l.bytesPerParticle;
    if (l.what.rfind("fields: ", 0) == 0) fields += l.bytesPerParticle;
    if (l.what == "rollback copy") rollback = l.bytesPerParticle;
    if (l.what == "neighbour list") list = l.bytesPerParticle;
  }
  EXPECT_DOUBLE_EQ(sum, r.bytesPerParticle);
  EXPECT_DOUBLE_EQ(fields, static_cast<double>(sim.store.bytesPerParticle()));
  EXPECT_DOUBLE_EQ(rollback, static_cast<double>(RollbackState::bytesPerParticle(sim.store)));
  EXPECT_DOUBLE_EQ(list, static_cast<double>(sim.neighbours.bytes()) /
                             static_cast<double>(sim.store.realCount()));
  // Fluid-only: nothing is held for another module's particles (walls are the fluid's).
  EXPECT_EQ(r.foreignBytesPerParticle, 0.0);
  const std::string text = describeMemory(r);
  for (const char* part : {"fields: core", "fields: fluid", "fields: integrator", "rollback copy",
                           "neighbour list", "neighbour search", "total"})
    EXPECT_NE(text.find(part), std::string::npos) << part << "\n" << text;
}

TEST(MemoryReport, BeforeTheFirstStepTheIntegratorScratchIsCountedFromTheIntegratedFields) {
  SceneOptions opt;
  opt.initialise = false;
  // The full neighbour list (the default half list of a fluid-only scene holds half the entries:
  // tests/unit/test_half_neighbour_list.cpp).
  Scene s = loadSceneText(std::string(kFluid) + "neighbour_list: full\n", "fluid_unstepped.yaml", opt);
  const Simulation& sim = *s.sim;
  ASSERT_EQ(owners(sim).count("integrator"), 0u);
  const MemoryReport r = memoryReport(sim, 1000, 20.0);
  EXPECT_EQ(r.particles, 1000u);
  double integrator = -1.0, list = -1.0;
  for (const auto& l : r.lines) {
    if (l.what == "fields: integrator") integrator = l.bytesPerParticle;
    if (l.what == "neighbour list") list = l.bytesPerParticle;
  }
  // Velocity and position copies (2 x 2 doubles in 2D) plus the integrated density (1 double).
  EXPECT_DOUBLE_EQ(integrator, 5.0 * 8.0);
  EXPECT_DOUBLE_EQ(list, 20.0 * 4.0 + 8.0);
  EXPECT_EQ(r.totalBytes(), static_cast<std::uint64_t>(r.bytesPerParticle * 1000.0 + 0.5));
}

TEST(MemoryReport, SolidFieldsHeldForFluidParticlesAreCountedAsForeign) {
  // Water on a TL clay block: the solid's fields are allocated for the water particles too.
  const char* text = R"(dimension: 2
domain: {lo: [0, 0], hi: [0.01, 0.02]}
spacing: 0.001
end_time: 1.0
time_step: {adaptive: true}
output: {every_steps: 100}
materials:
  - {name: clay, model: elastic, density: 2000, young_modulus: 1.0e7, poisson_ratio: 0.25, formulation: total_lagrangian, hourglass: 1.0}
  - {name: water, model: fluid, density: 1000, sound_speed: 10, viscosity: 1.0e-3}
geometry:
  - {shape: box, lo: [0, 0], hi: [0.01, 0.01], material: clay}
  - {shape: box, lo: [0, 0.01], hi: [0.01, 0.02], material: water}
)";
  Scene s = loadSceneText(text, "mixed.yaml");
  const Simulation& sim = *s.sim;
  const MemoryReport r = memoryReport(sim, 0, 0.0);
  double solidBytes = 0.0;
  for (const auto& f : sim.store.fields())
    if (f.owner == "solid")
      solidBytes += f.components * (f.type == FieldType::Real ? 8.0 : 4.0);
  ASSERT_GT(solidBytes, 0.0);
  const std::vector<Index> count = sim.phaseCounts();
  const double waterShare = static_cast<double>(count[kPhaseFluid]) /
                            static_cast<double>(sim.store.realCount());
  ASSERT_GT(waterShare, 0.3);
  bool found = false;
  for (const auto& l : r.lines)
    if (l.what == "fields: solid") {
      found = true;
      EXPECT_NEAR(l.foreignBytesPerParticle, solidBytes * waterShare, 1e-9 * solidBytes);
    }
  EXPECT_TRUE(found);
  EXPECT_GT(r.foreignBytesPerParticle, 0.0);
}

TEST(MemoryReport, PeriodicGhostsAreEstimatedBeforeTheHaloAndMeasuredAfter) {
  // Water periodic along x (length 0.02 m), walls below: ghosts are the particles within the
  // support (2 x 1.3 dx) of the two x faces, every field each.
  const char* text = R"(dimension: 2
domain: {lo: [0.0, -0.003], hi: [0.02, 0.013], periodic: [true, false]}
spacing: 0.001
kernel: wendland_c2
end_time: 1.0
time_step: {adaptive: true}
output: {every_steps: 100}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 10, viscosity: 1.0e-3}
  - {name: steel, model: wall, density: 1000}
geometry:
  - {shape: box, lo: [0.0, -0.003], hi: [0.02, 0.0], material: steel}
  - {shape: box, lo: [0.0, 0.0], hi: [0.02, 0.01], material: water}
fluid:
  gravity: [0, -9.81]
)";
  SceneOptions opt;
  opt.buildParticles = false;
  Scene before = loadSceneText(text, "periodic_count.yaml", opt);
  const MemoryReport r = memoryReport(*before.sim, 0, 20.0);
  double fields = 0.0, ghosts = -1.0;
  for (const auto& l : r.lines) {
    if (l.what.rfind("fields: ", 0) == 0) fields += l.bytesPerParticle;
    if (l.what == "periodic ghosts") ghosts = l.bytesPerParticle;
  }
  const double support = before.sim->kernel.support();
  EXPECT_NEAR(ghosts, fields * 2.0 * support / 0.02, 1e-9 * fields);
  // The scene's estimate counts them with the fields.
  EXPECT_GE(before.memory.fieldBytesPerParticle, static_cast<std::uint64_t>(fields + ghosts));

  // After the halo: measured, close to the estimate (2 x 2.6 columns of 20: 2 x 3 columns built).
  Scene after = loadSceneText(text, "periodic_built.yaml");
  ASSERT_GT(after.sim->store.ghostCount(), 0);
  const MemoryReport m = memoryReport(*after.sim, 0, 0.0);
  double measured = -1.0, allFields = 0.0;  // fields incl. the integrator's (not yet bound)
  for (const auto& l : m.lines) {
    if (l.what == "periodic ghosts") measured = l.bytesPerParticle;
    if (l.what.rfind("fields: ", 0) == 0) allFields += l.bytesPerParticle;
  }
  const double share = static_cast<double>(after.sim->store.ghostCount()) /
                       static_cast<double>(after.sim->store.realCount());
  EXPECT_NEAR(share, 6.0 / 20.0, 1e-12);
  EXPECT_GT(allFields, static_cast<double>(after.sim->store.bytesPerParticle()));
  EXPECT_NEAR(measured, allFields * share, 1e-9);
}
