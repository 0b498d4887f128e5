// Rigid bodies (physics/rigid, docs/rigid.md), validation case 5 of issue 15: the plate with a
// rigid inclusion of thesis Sec. 4.3 (Tab. 4.2; tests/validation/damage_plate_case.hpp) with the
// inclusion as a rigid body of the rigid module, bonded to the clay (`bonded: true`, A.6), against
// the damage module's run with the inclusion as a clamped undamageable material. Coarse
// resolution of the damage module's default test (60 x 60, dx = 5 mm, 2h = 12.5 mm, AT-2 in
// tension, bottom layer held, TL without hourglass control).
// RIGID_PLATE_PROBE="clamped|fixed|free [dumpPrefix]" runs one variant and prints it (the dumps:
// CSV of X, Y, x, y, D at onset, crossing and end, rendered in docs/rigid.md); RIGID_PLATE_UMAX
// (m) and RIGID_PLATE_RAMP (P-wave crossings) change the ramp, RIGID_PLATE_SYMMETRIC=1 pulls the
// top by +UMAX/2 and the bottom (a roller) by -UMAX/2 (docs/rigid.md "Symmetric pull").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "tests/support/validation_record.hpp"
#include "tests/validation/damage_plate_case.hpp"
#include "tests/validation/rigid_damage_plate_case.hpp"

using namespace poresph;
using namespace poresph::solid::plate;

namespace {

// The coarse tension plate of DamagePlate.CoarseTensionAT2CrackFromTheInclusionTopToBothSides
// (damage_plate_case.hpp), but with the damage committed at the end of the step (PlateSetup's
// default), as this test was measured with (docs/rigid.md).
PlateSetup coarse(Inclusion inclusion) {
  PlateSetup s = coarseTensionPlate();
  s.damageCommit = "step_end";
  s.inclusion = inclusion;
  return s;
}

const char* nameOf(Inclusion k) {
  return k == Inclusion::Clamped ? "clamped material" : k == Inclusion::RigidFixed ? "rigid, fixed" : "rigid, free";
}

void print(Inclusion k, const PlateResult& r) {
  std::printf("  %-16s onset D>=0.5 u = %.2f um at (%.1f, %.1f) mm, D>=0.1 u = %.2f um at (%.1f, %.1f) mm, "
              "crossing u = %.2f um, asymmetry %.4f, width %.1f mm at crossing, D max %.3f, balance %.3f; "
              "body at onset (%.3g, %.3g) um rot %.3g rad, at the end (%.3g, %.3g) um rot %.3g rad, "
              "F_y %.4g N/m; dt %.3g s, %ld steps, %.1f s\n",
              nameOf(k), 1e6 * r.uOnset, 1e3 * r.xOnset, 1e3 * r.yOnset, 1e6 * r.uOnsetLow, 1e3 * r.xOnsetLow,
              1e3 * r.yOnsetLow, 1e6 * r.uCross, r.asymmetry, 1e3 * r.widthCross, r.dmax, r.balance,
              1e6 * r.bodyUxOnset, 1e6 * r.bodyUyOnset, r.bodyRotOnset, 1e6 * r.bodyUx, 1e6 * r.bodyUy,
              r.bodyRot, r.bodyFy, r.dt, r.steps, r.wall);
}

}  // namespace

TEST(RigidDamagePlate, Probe) {
  const char* env = std::getenv("RIGID_PLATE_PROBE");
  if (!env) GTEST_SKIP() << "set RIGID_PLATE_PROBE=\"clamped|fixed|free [dumpPrefix]\"";
  std::istringstream in(env);
  std::string kind, dump;
  in >> kind >> dump;
  const Inclusion k = kind == "clamped" ? Inclusion::Clamped : kind == "fixed" ? Inclusion::RigidFixed : Inclusion::RigidFree;
  PlateSetup s = coarse(k);
  s.dump = dump;
  if (const char* u = std::getenv("RIGID_PLATE_UMAX")) s.uMax = std::atof(u);
  if (const char* t = std::getenv("RIGID_PLATE_RAMP")) s.rampCrossings = std::atof(t);
  if (std::getenv("RIGID_PLATE_SYMMETRIC")) {  // top +uMax/2, bottom -uMax/2 (a roller)
    s.uMax *= 0.5;
    s.bottomRoller = true;
    s.bottomUy = -s.uMax;
  }
  const PlateResult r = runPlate(s);
  print(k, r);
  const double a = 0.05;
  const Crack kr = crackBeside(r, s.dx, a + 2 * s.support, a, s.support);
  std::printf("  crack beside the inclusion at crossing: mean height %.1f mm, %.0f %% within 2h of y = +-a, %ld sites\n",
              1e3 * kr.height, 100 * kr.inBand, kr.count);
}

// Validation 5 of issue 15. Three runs of the coarse plate: the damage module's clamped material
// (the fixed-inclusion reference), the rigid body held (`fixed: true`: the same boundary, but the
// rigid module's bonded interface, A.6, instead of clamped particles in the clay's families), and
// the rigid body free. "Free" under this loading: the top layer is pulled along y and the bottom
// layer held, so a free inclusion bonded to the clay between them is carried up with it (0.47 of
// the imposed displacement: it sits half way between the two); by symmetry it neither drifts
// sideways nor turns. The clay ligament above it is then stretched by u_top - u_body and the one
// below (as long) by u_body: nearly alike, and either may crack (above in this run; the scene-file
// sample, with an adaptive step, cracks below). The onset compared with the fixed run is that of
// the larger stretch (asserted within 10 % at D >= 0.5 and 0.1); against the imposed
// displacement alone the free run damages ~1.9 x later (recorded). The crossing of the free run is
// recorded, not asserted (+35 %: once the crack opens the body drops back with the lower half).
// Asserted also: the fixed rigid body's onset and crossing within 10 % of the clamped run's, the
// same crack pattern (a crack through both sides tangent to the inclusion), left-right symmetry
// within 10 %, the free body on the axis and unrotated.
TEST(RigidDamagePlate, FreeRigidInclusionCracksAsTheFixedOneRelativeToItsDisplacement) {
  const PlateResult c = runPlate(coarse(Inclusion::Clamped));
  print(Inclusion::Clamped, c);
  const PlateResult f = runPlate(coarse(Inclusion::RigidFixed));
  print(Inclusion::RigidFixed, f);
  const PlateResult r = runPlate(coarse(Inclusion::RigidFree));
  print(Inclusion::RigidFree, r);
  const double a = 0.05, support = 12.5e-3, dx = 5e-3;
  ASSERT_GT(c.uOnset, 0.0);
  ASSERT_GT(c.uCross, 0.0);
  ASSERT_GT(f.uOnset, 0.0) << "no damage with the fixed rigid body";
  ASSERT_GT(r.uOnset, 0.0) << "no damage with the free rigid body";
  ASSERT_GT(r.uCross, 0.0) << "the crack did not reach both sides with the free rigid body";
  auto rel = [](double x, double ref) { return std::abs(x / ref - 1.0); };
  // the fixed rigid body against the clamped material (interface model only)
  const double fOnset = rel(f.uOnset, c.uOnset), fLow = rel(f.uOnsetLow, c.uOnsetLow), fCross = rel(f.uCross, c.uCross);
  // the free body: the imposed displacement relative to the body's own
  // (the ligament above the body is stretched by u_top - u_body, the one below by u_body: the
  // larger of the two; above in this run)
  auto stretch = [](double uTop, double uBody) { return std::max(uTop - uBody, uBody); };
  const double rOnsetU = stretch(r.uOnset, r.bodyUyOnset), rLowU = stretch(r.uOnsetLow, r.bodyUyOnsetLow),
               rCrossU = stretch(r.uCross, r.bodyUyCross);
  const double rOnset = rel(rOnsetU, c.uOnset), rLow = rel(rLowU, c.uOnsetLow), rCross = rel(rCrossU, c.uCross);
  // the pattern: a crack through the ligaments at the height of the inclusion's top (y = a)
  const double from = a + 2 * support;
  const Crack kC = crackBeside(c, dx, from, a, support), kF = crackBeside(f, dx, from, a, support),
              kR = crackBeside(r, dx, from, a, support);
  const double hC = kC.height, hF = kF.height, hR = kR.height;
  std::printf("  clamped: crack beside the inclusion at %.1f mm, %.0f %% of it within 2h of y = a\n", 1e3 * hC,
              100 * kC.inBand);
  std::printf("  fixed rigid vs clamped: onset %+.1f %% (D>=0.1: %+.1f %%), crossing %+.1f %%, crack at %.1f mm "
              "(%.0f %% within 2h of y = a)\n",
              100 * (f.uOnset / c.uOnset - 1), 100 * (f.uOnsetLow / c.uOnsetLow - 1), 100 * (f.uCross / c.uCross - 1),
              1e3 * hF, 100 * kF.inBand);
  std::printf("  free rigid, max(u_top - u_body, u_body): onset %.2f um (%+.1f %%), D>=0.1 %.2f um (%+.1f %%), crossing %.2f um "
              "(%+.1f %%); u_top alone %.2f x / %.2f x / %.2f x; body up %.1f / %.1f / %.1f um "
              "(%.2f / %.2f / %.2f of u_top); crack at %.1f mm (%.0f %% within 2h of y = a); body at the end %.3g um, "
              "largest %.1f um\n",
              1e6 * rOnsetU, 100 * (rOnsetU / c.uOnset - 1), 1e6 * rLowU, 100 * (rLowU / c.uOnsetLow - 1),
              1e6 * rCrossU, 100 * (rCrossU / c.uCross - 1), r.uOnset / c.uOnset, r.uOnsetLow / c.uOnsetLow,
              r.uCross / c.uCross, 1e6 * r.bodyUyOnset, 1e6 * r.bodyUyOnsetLow, 1e6 * r.bodyUyCross,
              r.bodyUyOnset / r.uOnset, r.bodyUyOnsetLow / r.uOnsetLow, r.bodyUyCross / r.uCross,
              1e3 * hR, 100 * kR.inBand, 1e6 * r.bodyUy, 1e6 * r.bodyUyMax);
  EXPECT_LT(fOnset, 0.10);
  EXPECT_LT(fLow, 0.10);
  EXPECT_LT(fCross, 0.10);
  EXPECT_LT(rOnset, 0.10) << "free body: onset of the ligament stretch against the fixed run";
  EXPECT_LT(rLow, 0.10);
  // (the free run's crossing is not asserted: +35 % of the stretch, docs/rigid.md)
  EXPECT_GT(f.yOnset, 0.0) << "onset not on the upper half";
  for (const PlateResult* p : {&f, &r}) {
    EXPECT_GE(std::hypot(p->xOnset, p->yOnset), a);
    EXPECT_LT(std::hypot(p->xOnset, p->yOnset), a + 2 * support);
    EXPECT_LT(p->asymmetry, 0.10);
    EXPECT_GT(p->uCross, p->uOnset);
  }
  // same pattern: in every run the crack runs through the ligaments to both sides tangent to the
  // inclusion, 90 % of its damaged particles there within one support of y = a (the free body:
  // of y = +-a, as the ligaments above and below it are stretched alike and either may crack; a
  // crack wrapping down the inclusion's sides, as without the bottom held, would not pass)
  for (const Crack* k : {&kC, &kF, &kR}) {
    EXPECT_GT(k->count, 0);
    EXPECT_GT(k->inBand, 0.9);
    EXPECT_LT(std::abs(std::abs(k->height) - a), support);
  }
  EXPECT_GT(kC.height, 0.0);
  EXPECT_GT(kF.height, 0.0);
  // the free body is carried up with the clay, on the axis and unrotated (symmetry)
  EXPECT_GT(r.bodyUyOnset, 0.25 * r.uOnset);
  EXPECT_LT(r.bodyUyOnset, 0.75 * r.uOnset);
  EXPECT_LT(std::abs(r.bodyUx), 1e-6 * dx);
  EXPECT_LT(std::abs(r.bodyUxOnset), 1e-6 * dx);
  EXPECT_LT(std::abs(r.bodyRot), 1e-9);
  const std::string res = "60 x 60 points (dx = 5 mm), 2h = 12.5 mm, TL, AT-2, bottom layer held";
  const double secs = c.wall + f.wall + r.wall;
  test::recordValidation({"rigid_damage_plate_free", "onset (D >= 0.5): ligament stretch max(u_top - u_body, u_body) [um], free rigid body",
                          1e6 * rOnsetU, 1e6 * c.uOnset, rOnset, res, secs, "< 10 %",
                          "issue 15 item 5; fixed run = clamped inclusion (thesis Sec. 4.3)"});
  test::recordValidation({"rigid_damage_plate_free", "onset (D >= 0.1): ligament stretch max(u_top - u_body, u_body) [um], free rigid body",
                          1e6 * rLowU, 1e6 * c.uOnsetLow, rLow, res, secs, "< 10 %", "issue 15 item 5"});
  test::recordValidation({"rigid_damage_plate_free", "crossing: ligament stretch max(u_top - u_body, u_body) [um], free rigid body",
                          1e6 * rCrossU, 1e6 * c.uCross, rCross, res, secs, "recorded (not met)", "issue 15 item 5"});
  test::recordValidation({"rigid_damage_plate_free", "onset (D >= 0.5): imposed u_top [um], free rigid body",
                          1e6 * r.uOnset, 1e6 * c.uOnset, rel(r.uOnset, c.uOnset), res, secs,
                          "recorded (the body moves with the clay)", "issue 15 item 5"});
  test::recordValidation({"rigid_damage_plate_free", "left-right asymmetry of D, free rigid body", r.asymmetry, 0.0,
                          r.asymmetry, res, secs, "< 10 %", "symmetric pattern"});
  test::recordValidation({"rigid_damage_plate_free", "crack height beside the inclusion at crossing [mm]", 1e3 * hR,
                          1e3 * hC, std::abs(hR - hC) / hC, res, secs, "within 2h of the inclusion's top or bottom",
                          "same crack pattern"});
  test::recordValidation({"rigid_damage_plate_free", "crossing: imposed u_top [um], free rigid body", 1e6 * r.uCross,
                          1e6 * c.uCross, rel(r.uCross, c.uCross), res, secs,
                          "recorded (not met: the plate is strained ~1.9x as far at onset)", "issue 15 item 5"});
  test::recordValidation({"rigid_damage_plate_fixed", "onset (D >= 0.5) [um], rigid body fixed (bonded)",
                          1e6 * f.uOnset, 1e6 * c.uOnset, fOnset, res, secs, "< 10 %",
                          "interface model: bonds (A.6) vs clamped particles"});
  test::recordValidation({"rigid_damage_plate_fixed", "crossing [um], rigid body fixed (bonded)", 1e6 * f.uCross,
                          1e6 * c.uCross, fCross, res, secs, "< 10 %", "issue 15 item 5"});
}
