// Validation (issue 13 / 16): damage that stays near the pores under confinement.
// samples/damage_two_pores_confined_2d.yaml is the two-isolated-pores drainage sample (thesis
// Sec. 5.5 in miniature: plates at 80 Pa, dP = 300 Pa, Rankine / Mohr-Coulomb clay with the
// Table 5.1 strains) with the two law options `tensile_measure: stress` and `split: spectral`
// (docs/damage.md "Damage under confinement"). The same scene without the two keys is the
// reference: there the damage starts beside the lower pore, in clay compressed along the flow
// axis by the dP thrust (E_yy ~ -3.8 eps_t0) where the shear makes the largest principal
// strain exceed eps_t0 with the principal stress below f_t, and spreads through the clay (the
// unilateral split of Eq. 4.17 takes the shear stiffness of every damaged point, compressed or
// not). Checked at 4.5 ms:
//   - with the options the pores are still linked by damage (drainage_flow_path = 1, a third of
//     the ligament between the tips damaged): the options do not simply suppress damage;
//   - with the options the damaged fraction of the clay is below 0.2 and below half of the
//     reference's (measured 0.110 vs 0.395, 1 thread, 2026-11-24).
// Before the options existed the reference was the only behaviour: 0.37 fails the first bound.
//
// SlowRampHourglassDegraded (docs/damage.md "Why it still spreads", hourglass item): the same
// scene with the default law and both ramps over 10 ms (quasi-static onset at the upper pore's
// tip), to 10 ms. The conservative hourglass penalty used the undamaged E on damaged particles
// and bridged the damaged band: damaged fraction 0.515 at 10 ms (0.399 without hourglass
// control, 0.480 with the pairwise form). With the penalty degraded by g(D) like the rest of the
// stiffness: 0.237 (2026-11-27, 1 thread). Asserted: < 0.35 (fails with the undegraded penalty)
// and the pores still linked by damage (the fix does not simply suppress damage).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "libcore/runner.hpp"
#include "libcore/scene.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
namespace fsys = std::filesystem;

namespace {

struct Outcome {
  double flowPath = -1.0, flowPathTime = -1.0, damagedFraction = -1.0, wall = 0.0;
  int ligament = 0, ligamentDamaged = 0;
};

double column(const Simulation& sim, const std::string& name) {
  for (const auto& [k, v] : sim.diagnostics())
    if (k == name) return v;
  ADD_FAILURE() << "no column " << name;
  return NAN;
}

Outcome run(bool options, bool slow = false) {
  std::ifstream in(std::string(PORESPH_SOURCE_DIR) + "/samples/damage_two_pores_confined_2d.yaml");
  std::stringstream buf;
  buf << in.rdbuf();
  std::string text = buf.str();
  if (!options) {  // the same scene with the thesis' split and the strain measure (defaults)
    const std::string keys = ",\n             tensile_measure: stress, split: spectral}";
    const size_t k = text.find(keys);
    EXPECT_NE(k, std::string::npos) << "the sample's option keys moved";
    if (k != std::string::npos) text.replace(k, keys.size(), "}");
  }
  if (slow) {  // plates and dP ramped over 10 ms instead of 2 ms, run to 10 ms
    auto replaceAll = [&](const std::string& from, const std::string& to) {
      int count = 0;
      for (size_t k = text.find(from); k != std::string::npos; k = text.find(from, k + to.size())) {
        text.replace(k, from.size(), to);
        ++count;
      }
      return count;
    };
    EXPECT_EQ(replaceAll("ramp_time: 0.002}", "ramp_time: 0.01}"), 3) << "the sample's ramps moved";
    EXPECT_EQ(replaceAll("end_time: 0.0045", "end_time: 0.01"), 1);
    EXPECT_EQ(replaceAll("output: {every_time: 0.0005}", "output: {every_time: 0.01}"), 1);
  }
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-damage-confinement";
  fsys::create_directories(dir);
  const std::string name = std::string(options ? "options" : "reference") + (slow ? "-slow" : "");
  Scene scene = loadSceneText(text, (dir / (name + ".yaml")).string());
  RunOptions ro;
  ro.outDir = (dir / name).string();
  fsys::remove_all(ro.outDir);
  ro.handleSignals = false;
  test::Stopwatch clock;
  const RunResult r = runScene(scene, ro);
  EXPECT_EQ(r.status, RunStatus::Finished) << r.message;
  Outcome o;
  o.wall = clock.seconds();
  const Simulation& sim = *scene.sim;
  o.flowPath = column(sim, "drainage_flow_path");
  o.flowPathTime = column(sim, "drainage_flow_path_time");
  o.damagedFraction = column(sim, "drainage_damaged_fraction");
  // the ligament between the upper tip (1.8, 3.6 mm, r 0.2) and the lower one (2.5, 3.4 mm)
  const ParticleStore& s = sim.store;
  const double* x = s.data(s.position());
  const std::int32_t* ph = s.data(s.phase());
  const double* D = s.data(s.real("damage"));
  for (Index i = 0; i < s.realCount(); ++i) {
    if (ph[i] != kPhaseSolid) continue;
    if (x[2 * i] < 0.0019 || x[2 * i] > 0.0024 || x[2 * i + 1] < 0.0032 || x[2 * i + 1] > 0.0038)
      continue;
    ++o.ligament;
    if (D[i] > 0.5) ++o.ligamentDamaged;
  }
  return o;
}

}  // namespace

TEST(DamageConfinement, TwoPoresLinkedWhileTheDamageStaysNearThePores) {
  const Outcome opt = run(true);
  const Outcome ref = run(false);
  std::printf("options: damaged fraction %.3f, flow path %g at %g s, ligament %d/%d, %.1f s\n"
              "reference: damaged fraction %.3f, flow path %g at %g s, ligament %d/%d, %.1f s\n",
              opt.damagedFraction, opt.flowPath, opt.flowPathTime, opt.ligamentDamaged,
              opt.ligament, opt.wall, ref.damagedFraction, ref.flowPath, ref.flowPathTime,
              ref.ligamentDamaged, ref.ligament, ref.wall);
  ASSERT_GT(opt.ligament, 15);
  EXPECT_EQ(opt.flowPath, 1.0) << "with the options damage no longer links the pores";
  EXPECT_GE(3 * opt.ligamentDamaged, opt.ligament) << "the ligament between the tips did not fail";
  EXPECT_LT(opt.damagedFraction, 0.2) << "damage spread through the clay";
  EXPECT_LT(opt.damagedFraction, 0.5 * ref.damagedFraction)
      << "the options do not localise the damage against the thesis' split";
  EXPECT_GT(ref.damagedFraction, 0.0);

  const std::string res = "2D, dx = 0.1 mm, 3220 particles, quintic h = dx, to 4.5 ms";
  test::ValidationRecord rec;
  rec.caseName = "damage_two_pores_confined_2d";
  rec.quantity = "damaged clay fraction (D > 0.5) at 4.5 ms, tensile_measure stress + spectral split";
  rec.measured = opt.damagedFraction;
  rec.reference = NAN;  // no reference value: the bound below; the default law's in the text
  rec.resolution = res;
  rec.wallSeconds = opt.wall;
  char refText[160];
  std::snprintf(refText, sizeof refText,
                "< 0.2 and < 0.5 x the default law's %.3f (same scene, strain measure, Eq. 4.17 split)",
                ref.damagedFraction);
  rec.tolerance = refText;
  rec.reference_source = "thesis Sec. 5.5, Figs. 5.9-5.11 (damage at the pore tips, a fracture "
                         "links the pores); reference = this scene with the default law";
  test::recordValidation(rec);
  rec.quantity = "time the damaged clay links the isolated pores (flow path) [s], options";
  rec.measured = opt.flowPathTime;
  rec.reference = NAN;
  rec.tolerance = "linked by 4.5 ms, ligament >= 1/3 damaged";
  test::recordValidation(rec);
}

TEST(DamageConfinement, SlowRampHourglassDegraded) {
  const Outcome ref = run(false, true);
  std::printf("default law, 10 ms ramp, at 10 ms: damaged fraction %.3f, flow path %g at %g s, %.1f s\n",
              ref.damagedFraction, ref.flowPath, ref.flowPathTime, ref.wall);
  EXPECT_LT(ref.damagedFraction, 0.35)
      << "the damaged zone spreads as a block (0.515 with the undegraded hourglass penalty)";
  EXPECT_EQ(ref.flowPath, 1.0) << "damage no longer links the pores";

  test::ValidationRecord rec;
  rec.caseName = "damage_two_pores_confined_2d";
  rec.quantity = "damaged clay fraction (D > 0.5) at 10 ms, default law, 10 ms ramps";
  rec.measured = ref.damagedFraction;
  rec.reference = NAN;
  rec.resolution = "2D, dx = 0.1 mm, 3220 particles, quintic h = dx, to 10 ms";
  rec.wallSeconds = ref.wall;
  rec.tolerance = "< 0.35 (0.515 with the hourglass penalty undegraded by D)";
  rec.reference_source = "thesis Sec. 5.4 (damage localised in bands from the pore tips); "
                         "docs/damage.md 'Why it still spreads'";
  test::recordValidation(rec);
}
