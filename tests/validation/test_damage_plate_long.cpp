// Long study (label validation_long, tests/long-tests.txt) of the plate with a rigid inclusion
// (thesis Sec. 4.3, Tab. 4.2; damage_plate_case.hpp): AT-2 in tension at 150 x 150 points
// (dx = 2 mm) with the thesis' support 2h = 5 mm, bottom + inclusion held. Asserted as in the
// coarse test: onset on the upper half of the inclusion's boundary, a crack through both sides,
// left-right symmetry within 10 %, width at crossing within 0.5-2 x 2h. Onset and crossing are
// recorded beside the thesis' 17.4 / 19.8 um (300 x 300 points). ~10 min of one core. The same at
// 200 x 200 points with the onset (D >= 0.1) and the width asserted against the thesis: below.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "tests/support/validation_record.hpp"
#include "tests/validation/damage_plate_case.hpp"

using namespace poresph;
using namespace poresph::solid::plate;

TEST(DamagePlateLong, TensionAT2At150x150With2h5mm) {
  // bottom held, no hourglass control (balance 0.14 % without it, 14-18 % of the work with
  // hourglass 1), damage committed at the evaluation (docs/damage.md "The commit lag"; measured:
  // onset 25.25 um, crossing 30.00 um, width 4 mm, balance 0.14 %; step_end: 25.4 / 30.5 um,
  // 4 mm, 1.8 %): tensionPlate() of damage_plate_case.hpp
  PlateSetup s = tensionPlate(2e-3, 5e-3, 70e-6, 28);
  if (const char* d = std::getenv("PORESPH_PLATE_DUMP")) s.dump = d;
  const PlateResult r = runPlate(s);
  const double a = 0.05;
  std::printf("plate 150 x 150: %ld particles, %ld steps, onset u = %.2f um at (%.1f, %.1f) mm, "
              "crossing u = %.2f um, asymmetry %.4f, width %.1f mm at crossing (2h = %.1f), "
              "balance %.3f, %.1f s\n",
              r.particles, r.steps, 1e6 * r.uOnset, 1e3 * r.xOnset, 1e3 * r.yOnset, 1e6 * r.uCross,
              r.asymmetry, 1e3 * r.widthCross, 1e3 * s.support, r.balance, r.wall);
  // onset on the upper half of the inclusion's boundary (within two supports of it), a crack
  // through both sides, left-right symmetry within 10 %
  expectCrackFromTheInclusionTopToBothSides(r, s, a);
  if (HasFatalFailure()) return;
  EXPECT_GT(r.widthCross, 0.5 * s.support);
  EXPECT_LT(r.widthCross, 2.0 * s.support);
  // the 1 % (measured 0.14 % with the evaluation commit; 1.8 % with step_end)
  EXPECT_LT(r.balance, 0.01) << "energy balance residual / work of the boundaries";
  const std::string res = "150 x 150 points (dx = 2 mm), 2h = 5 mm, TL, no hourglass control, damping 600/s";
  test::recordValidation({"damage_plate_150_at2_tension", "imposed displacement at onset [um]",
                          1e6 * r.uOnset, 17.4, std::abs(1e6 * r.uOnset - 17.4) / 17.4, res, r.wall,
                          "recorded (thesis at 300 x 300)", "thesis Sec. 4.3.2.1, Fig. 4.14"});
  test::recordValidation({"damage_plate_150_at2_tension", "imposed displacement at full crossing [um]",
                          1e6 * r.uCross, 19.8, std::abs(1e6 * r.uCross - 19.8) / 19.8, res, r.wall,
                          "crossing > onset (thesis at 300 x 300)", "thesis Sec. 4.3.2.1, Fig. 4.14"});
  test::recordValidation({"damage_plate_150_at2_tension", "energy balance residual / boundary work",
                          r.balance, 0.0, r.balance, res, r.wall, "< 3 %", "Eqs. 4.25-4.26 with the boundary work"});
  test::recordValidation({"damage_plate_150_at2_tension", "damaged width (D >= 0.5) at crossing [m]",
                          r.widthCross, s.support, std::abs(r.widthCross - s.support) / s.support, res,
                          r.wall, "0.5-2 x 2h", "thesis Fig. 4.14c (width ~ 2h)"});
}

// Item 3 of issue 13 at 200 x 200 points (dx = 1.5 mm), the thesis' support 2h = 5 mm (thesis
// Sec. 4.3.2.1, Fig. 4.14; 4.3.2.3 runs 200 / 300 / 400 / 500 points), AT-2 in tension, bottom +
// inclusion held, no hourglass control, `damage_commit: evaluation`, ramp 2.5 um per L/c_p
// stopped at 40 um (the same run as the 70 um ramp up to 40 um: onset and crossing unchanged,
// docs/damage.md "The plate at 200 / 300 / 400 points"). Asserted: onset (first D >= 0.1) within
// 10 % of the thesis' 17.4 um, on the upper half of the inclusion's boundary; the crack reaches
// both sides; left-right symmetry within 10 %; damaged width (D >= 0.5) at x = +-100 mm when the
// crack reaches the sides within 15 % of 2h; energy balance within 1 % of the boundary work.
// Recorded, not asserted: the crossing (29.5 um measured against the thesis' 19.8 um: +49 %, the
// gap documented in docs/damage.md, the same at 150 / 300 / 400 points) and the D >= 0.5 onset.
// Measured 2026-11-27: 153 s CPU on one thread.
TEST(DamagePlateLong, TensionAT2At200x200With2h5mmOnsetWidthSymmetry) {
  PlateSetup s = tensionPlate(1.5e-3, 5e-3, 40e-6, 16);
  if (const char* d = std::getenv("PORESPH_PLATE_DUMP")) s.dump = d;
  const PlateResult r = runPlate(s);
  const double a = 0.05, thOnset = 17.4, thCross = 19.8;
  const double onLow = 1e6 * r.uOnsetLow, on = 1e6 * r.uOnset, cross = 1e6 * r.uCross;
  std::printf("plate 200 x 200: %ld particles, %ld steps, onset D >= 0.1 u = %.2f um at (%.1f, %.1f) mm, "
              "D >= 0.5 u = %.2f um at (%.1f, %.1f) mm, crossing u = %.2f um, asymmetry %.2e, width %.2f mm at "
              "x = +-100 mm (mean over 70-140 mm %.2f) at crossing (2h = %.1f), balance %.2e, %.1f s\n",
              r.particles, r.steps, onLow, 1e3 * r.xOnsetLow, 1e3 * r.yOnsetLow, on, 1e3 * r.xOnset,
              1e3 * r.yOnset, cross, r.asymmetry, 1e3 * r.widthCross, 1e3 * r.widthMeanCross,
              1e3 * s.support, r.balance, r.wall);
  ASSERT_GT(r.uOnsetLow, 0.0) << "no damage";
  EXPECT_LT(std::abs(onLow - thOnset) / thOnset, 0.10) << "onset (D >= 0.1) against the thesis' 17.4 um";
  const double rOnset = std::hypot(r.xOnsetLow, r.yOnsetLow);
  EXPECT_GT(r.yOnsetLow, 0.0);
  EXPECT_GE(rOnset, a);
  EXPECT_LT(rOnset, a + 2 * s.support);
  ASSERT_GT(r.uCross, 0.0) << "the crack did not reach both sides by 40 um";
  EXPECT_GT(r.uCross, r.uOnset);
  EXPECT_LT(r.asymmetry, 0.10);
  EXPECT_LT(std::abs(r.widthCross - s.support) / s.support, 0.15) << "width at x = +-100 mm: " << r.widthCross;
  EXPECT_LT(r.balance, 0.01) << "energy balance residual / work of the boundaries";
  const std::string rec = "damage_plate_200_at2_tension";
  const std::string res = "200 x 200 points (dx = 1.5 mm), 2h = 5 mm, TL, no hourglass control, damping 600/s, "
                          "dt 0.5 x Eq. 2.50, ramp 2.5 um per L/c_p to 40 um, bottom held, damage_commit: evaluation";
  const std::string src = "thesis Sec. 4.3.2.1, Fig. 4.14 (300 x 300 points, 2h = 5 mm)";
  auto rel = [](double m, double ref) { return std::abs(m - ref) / std::abs(ref); };
  test::recordValidation({rec, "imposed displacement at onset, first D >= 0.1 [um]", onLow, thOnset,
                          rel(onLow, thOnset), res, r.wall, "< 10 %", src});
  test::recordValidation({rec, "imposed displacement at onset, first D >= 0.5 [um]", on, thOnset, rel(on, thOnset),
                          res, r.wall, "recorded (threshold of the thesis not stated)", src});
  test::recordValidation({rec, "imposed displacement at full crossing [um]", cross, thCross, rel(cross, thCross), res,
                          r.wall, "recorded (gap documented in docs/damage.md)", src});
  test::recordValidation({rec, "damaged width (D >= 0.5) at x = +-100 mm at crossing / 2h", r.widthCross / s.support,
                          1.0, rel(r.widthCross / s.support, 1.0), res, r.wall, "< 15 %",
                          "thesis Fig. 4.14c (width ~ 2h); issue 13 item 4"});
  test::recordValidation({rec, "damaged width (D >= 0.5) over 70 <= |x| <= 140 mm at crossing / 2h",
                          r.widthMeanCross / s.support, 1.0, rel(r.widthMeanCross / s.support, 1.0), res, r.wall,
                          "recorded", "thesis Fig. 4.14c (width ~ 2h); issue 13 item 4"});
  test::recordValidation({rec, "left-right asymmetry of D", r.asymmetry, 0.0, r.asymmetry, res, r.wall, "< 10 %",
                          "thesis Sec. 4.3.2.1 (symmetric pattern)"});
  test::recordValidation({rec, "energy balance residual / boundary work", r.balance, 0.0, r.balance, res, r.wall,
                          "< 1 %", "Eqs. 4.25-4.26 with the boundary work"});
}
