// The rock scene's step, solid side (issues 16 and 17, docs/performance.md "The rock scene's
// step"): the three shortcuts of the TL solid are checked against the computation they replace.
//  - the step_end damage commit reuses the evaluation's F when the solid has not moved: F equals
//    a fresh F bit for bit, and the reuse happens at every step of a TL damage run;
//  - the Rankine/Mohr-Coulomb commit skips its eigenproblem only where update() would leave D
//    and every history value above its onset unchanged (random and near-threshold 3D strains);
//  - family_storage fast keeps W0 / |X|^2 per member for the conservative hourglass control:
//    the run agrees with compact (which recomputes it) to round-off, 8 B more per member.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "libcore/parameters.hpp"
#include "libcore/runner.hpp"
#include "libcore/scene.hpp"
#include "libcore/simulation.hpp"
#include "physics/solid/constitutive_law.hpp"
#include "physics/solid/elastic_solid.hpp"

using namespace poresph;
using namespace poresph::solid;

namespace {

// A 3D clay block (8^3 particles), clamped at the base and pulled at the top fast enough that
// part of it damages within the run (Rankine/Mohr-Coulomb, spectral split, stress measure, as
// the rock scenes), with the conservative hourglass control.
std::string block(const std::string& storage) {
  return std::string(R"(dimension: 3
domain: {lo: [-0.002, -0.002, -0.002], hi: [0.010, 0.010, 0.012], periodic: [false, false, false]}
spacing: 1.0e-3
h_over_dx: 1.0
kernel: quintic_spline
integrator: leapfrog
end_time: 1.0
max_steps: 40
time_step: {adaptive: true, cfl: 1.0}
output: {every_time: 100}
materials:
  - name: clay
    model: elastic
    density: 2000
    young_modulus: 1.2e5
    poisson_ratio: 0.1
    formulation: total_lagrangian
    hourglass: 1
    damage: {law: rankine_mohr_coulomb, tensile_strain_onset: 0.002, tensile_strain_ultimate: 0.004, compressive_strain_onset: 0.015, friction_angle: 25, split: spectral, tensile_measure: stress}
geometry:
  - {shape: box, lo: [0.0, 0.0, 0.0], hi: [0.008, 0.008, 0.008], material: clay}
solid:
)") + (storage.empty() ? "" : "  family_storage: " + storage + "\n") +
         R"(  boundaries:
    - {name: base, type: clamped, box: {min: [-1, -1, -1], max: [1, 1, 0.0015]}}
    - {name: top, type: velocity, velocity: [0, 0, 0.05], box: {min: [-1, -1, 0.0065], max: [1, 1, 1]}}
)";
}

const ElasticSolidModule& solidOf(const Scene& s) {
  for (const auto& m : s.sim->modules)
    if (const auto* e = dynamic_cast<const ElasticSolidModule*>(m.get())) return *e;
  throw std::logic_error("no solid module");
}

Scene runBlock(const std::string& storage, const std::string& dir) {
  Scene scene = loadSceneText(block(storage), dir + ".yaml");
  RunOptions o;
  o.handleSignals = false;
  o.outDir = std::string(PORESPH_BINARY_DIR) + "/test-solid-step-levers/" + dir;
  EXPECT_EQ(runScene(scene, o).status, RunStatus::Finished);
  return scene;
}

}  // namespace

TEST(SolidStepLevers, CommitReusesTheEvaluationsDeformationGradientBitForBit) {
  Scene scene = runBlock("", "fast");
  Simulation& sim = *scene.sim;
  ASSERT_EQ(sim.step, 40);
  const ElasticSolidModule& m = solidOf(scene);
  // one reuse per step: the evaluation of the step computed F at x^{n+1} already
  EXPECT_EQ(m.deformationGradientReuses(), 40);
  const ParticleStore& s = sim.store;
  const double* dmg = s.data(s.real("damage"));
  int damaged = 0, intact = 0;
  for (Index i = 0; i < s.realCount(); ++i) (dmg[i] > 0.0 ? damaged : intact) += 1;
  EXPECT_GT(damaged, 0) << "the block must damage in part for the commit to be exercised";
  EXPECT_GT(intact, 0);
  // F as kept, against F computed afresh at the same positions (kinematics outside a commit
  // never reuses)
  const RealField Fid = s.real("deformation_gradient");
  const size_t count = static_cast<size_t>(s.realCount()) * 9;
  std::vector<double> kept(s.data(Fid), s.data(Fid) + count);
  for (auto& mod : sim.modules)
    if (dynamic_cast<ElasticSolidModule*>(mod.get())) mod->kinematics(sim);
  EXPECT_EQ(std::memcmp(kept.data(), sim.store.data(Fid), count * sizeof(double)), 0);
  EXPECT_EQ(m.deformationGradientReuses(), 40);
}

TEST(SolidStepLevers, RankineCommitSkipsOnlyWhereNothingCanChange) {
  for (const char* measure : {"strain", "stress"}) {
    double lam = 0.0, mu = 0.0;
    lameParameters(1.2e5, 0.1, 3, Plane::Strain, lam, mu);
    ConstitutiveLaw law(1.2e5, lam, mu, 3);
    law.configureDamage(ParameterSet(
        YAML::Load(std::string("{law: rankine_mohr_coulomb, tensile_strain_onset: 0.0013, "
                               "tensile_strain_ultimate: 0.0026, compressive_strain_onset: 0.015, "
                               "friction_angle: 25, split: spectral, tensile_measure: ") +
                   measure + "}"),
        "test", "damage"));
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int skipped = 0, checked = 0;
    for (int k = 0; k < 20000; ++k) {
      // strains of 0.1-10 x the tensile onset, confined (negative trace) or not; histories
      // zero, below, at or above the onsets
      const double scale = 1.3e-3 * std::pow(10.0, 2.0 * (0.5 * (u(rng) + 1.0)) - 1.0);
      Mat<3> a;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j <= i; ++j) a(i, j) = a(j, i) = scale * u(rng);
      if (k % 2) a.diagonal().array() -= scale;  // confined
      const double pick[4] = {0.0, 0.5, 1.0, 1.5};
      double h0[2] = {pick[k % 4] * law.epsT0 * (1.0 + 0.1 * u(rng)),
                      pick[(k / 4) % 4] * law.epsC0 * (1.0 + 0.1 * u(rng))};
      double D0 = (k % 3 == 0) ? 0.0 : 0.3 * (u(rng) + 1.0);
      // mostly the states a run holds: D at least the damage its histories ask for
      if (k % 5 != 0)
        D0 = std::max({D0, ConstitutiveLaw::linearSoftening(h0[0], law.epsT0, law.epsTu),
                       ConstitutiveLaw::linearSoftening(h0[1], law.epsC0, law.epsCu)});
      D0 = std::min(D0, law.limit);
      double h[2] = {h0[0], h0[1]};
      const DamageUpdate r = law.update<3>(a, D0, h);
      ++checked;
      if (!law.commitCannotChange<3>(a, D0, h0)) continue;
      ++skipped;
      ASSERT_EQ(r.D, D0) << measure << " sample " << k;
      ASSERT_FALSE(r.clipped);
      if (h[0] > law.epsT0) {
        ASSERT_EQ(h[0], h0[0]) << measure << " sample " << k;
      }
      if (h[1] > law.epsC0) {
        ASSERT_EQ(h[1], h0[1]) << measure << " sample " << k;
      }
    }
    // the skip must be common (or the lever does nothing) and not universal
    std::cout << measure << ": " << skipped << " of " << checked << " commits skipped\n";
    EXPECT_GT(skipped, checked / 5) << measure;
    EXPECT_LT(skipped, checked) << measure;
  }
}

TEST(SolidStepLevers, StoredHourglassFactorAgreesWithCompactToRoundOff) {
  Scene fast = runBlock("", "fast2");
  Scene compact = runBlock("compact", "compact");
  const ParticleStore& a = fast.sim->store;
  const ParticleStore& b = compact.sim->store;
  ASSERT_EQ(a.realCount(), b.realCount());
  double umax = 0.0, dmax = 0.0;
  const double* xa = a.data(a.position());
  const double* xb = b.data(b.position());
  const double* Xa = a.data(a.real("reference_position"));
  for (Index q = 0; q < a.realCount() * 3; ++q) {
    umax = std::max(umax, std::abs(xa[q] - Xa[q]));
    dmax = std::max(dmax, std::abs(xa[q] - xb[q]));
  }
  EXPECT_GT(umax, 1e-5);  // the block moved (the top by 40 steps x 0.05 m/s x dt)
  // re-associated product per member: differences at round-off of the displacement
  EXPECT_LT(dmax, 1e-10 * umax);
  std::cout << "fast - compact: max |dx| = " << dmax << " m, max |u| = " << umax << " m\n";
  const ElasticSolidModule& ma = solidOf(fast);
  const ElasticSolidModule& mb = solidOf(compact);
  ASSERT_TRUE(ma.hourglassConservative());
  const std::int64_t members = ma.familyMembers();
  EXPECT_EQ(ma.heldBytes() - mb.heldBytes(),
            static_cast<std::uint64_t>(members) *
                (3 * sizeof(double) - sizeof(std::int32_t) + sizeof(double)));
}
