// Rigid bodies (physics/rigid, docs/rigid.md), validation case 5 of issue 15 at 150 x 150 points
// (label validation_long, tests/long-tests.txt): the plate with a rigid inclusion of thesis
// Sec. 4.3 (Tab. 4.2; damage_plate_case.hpp) at the damage module's long-test resolution and
// support (dx = 2 mm, 2h = 5 mm, AT-2 in tension, bottom layer held, TL without hourglass control,
// `damage_commit: evaluation`), with the inclusion as a FREE rigid body bonded to the clay
// (`bonded: true`, A.6) against the fixed-inclusion run at the same resolution (the rigid body
// held, `fixed: true`; it reads the clamped-material run of the damage module within 1 %: onset
// 25.07 vs 25.26 um, crossing 29.70 vs 30.00 um, measured with the bottom clamped).
// Loading: the damage studies' rate (2.5 um per P-wave crossing L / c_p) and dt = 0.9 x Eq. 2.50
// (docs/damage.md "Cost levers": the same onset and crossing as dt 0.5 to 0.04 %); the fixed runs
// to 40 um (past their crossing), the free run to 70 um (its body rises with the clay, so its
// crack needs more of the imposed displacement).
// "Free" under this loading (docs/rigid.md, validation 5): the top layer is pulled along y and the
// bottom layer held, so a free body bonded to the clay between them is carried up with it (about
// half of u_top); the ligament above it is stretched by u_top - u_body, the one below by u_body.
// The onset compared with the fixed run is that of the larger stretch.
// RIGID_PLATE_LONG_DUMP=prefix writes the D fields (CSV: X, Y, x, y, D) at onset, crossing and
// end of each run (prefix_fixed_*.csv, ...; scripts/render_plate_damage.py renders them).
// Two runs, 591 s wall at load ~8 (313 s fixed + 278 s free).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "tests/support/validation_record.hpp"
#include "tests/validation/damage_plate_case.hpp"
#include "tests/validation/rigid_damage_plate_case.hpp"

using namespace poresph;
using namespace poresph::solid::plate;

namespace {

PlateSetup fine(Inclusion k) {
  const bool free = k == Inclusion::RigidFree;
  // 2.5 um per crossing; bottom held, no hourglass control, evaluation commit (damage_plate_case.hpp)
  PlateSetup s = tensionPlate(2e-3, 5e-3, free ? 70e-6 : 40e-6, free ? 28 : 16);
  s.dtFactor = 0.9;
  s.inclusion = k;
  if (const char* d = std::getenv("RIGID_PLATE_LONG_DUMP"))
    s.dump = std::string(d) + (k == Inclusion::Clamped ? "_clamped" : k == Inclusion::RigidFixed ? "_fixed" : "_free");
  return s;
}

void print(const char* name, const PlateResult& r) {
  std::printf("  %-8s onset D>=0.5 u = %.2f um at (%.1f, %.1f) mm, D>=0.1 u = %.2f um at (%.1f, %.1f) mm, "
              "crossing u = %.2f um, asymmetry %.2e, width %.1f mm at crossing, balance %.4f; body up at "
              "onset %.3g um (D>=0.1: %.3g, crossing %.3g), sideways %.3g um, rot %.3g rad, at the end %.3g um; "
              "%ld particles, dt %.3g s, %ld steps, %.1f s wall\n",
              name, 1e6 * r.uOnset, 1e3 * r.xOnset, 1e3 * r.yOnset, 1e6 * r.uOnsetLow, 1e3 * r.xOnsetLow,
              1e3 * r.yOnsetLow, 1e6 * r.uCross, r.asymmetry, 1e3 * r.widthCross, r.balance, 1e6 * r.bodyUyOnset,
              1e6 * r.bodyUyOnsetLow, 1e6 * r.bodyUyCross, 1e6 * r.bodyUx, r.bodyRot, 1e6 * r.bodyUy, r.particles,
              r.dt, r.steps, r.wall);
  std::fflush(stdout);
}

}  // namespace

// Study: RIGID_PLATE_LONG_PROBE="clamped|fixed|free [roller] [symmetric] [uMax_um]" runs one variant
// (roller: the bottom layer held along y only, PlateSetup::bottomRoller; symmetric: the bottom
// pulled by -uMax as the top by +uMax, docs/rigid.md "Symmetric pull") and prints it.
TEST(RigidDamagePlateLong, Probe) {
  const char* env = std::getenv("RIGID_PLATE_LONG_PROBE");
  if (!env) GTEST_SKIP() << "set RIGID_PLATE_LONG_PROBE=\"clamped|fixed|free [roller] [uMax_um]\"";
  const std::string text = env;
  const Inclusion k = text.rfind("clamped", 0) == 0 ? Inclusion::Clamped
                      : text.rfind("fixed", 0) == 0 ? Inclusion::RigidFixed : Inclusion::RigidFree;
  PlateSetup s = fine(k);
  s.bottomRoller = text.find("roller") != std::string::npos;
  const size_t digit = text.find_first_of("0123456789");
  if (digit != std::string::npos) {
    const double u = std::atof(text.c_str() + digit) * 1e-6;
    s.rampCrossings *= u / s.uMax;  // the same rate
    s.uMax = u;
  }
  if (text.find("symmetric") != std::string::npos) {  // top +uMax, bottom (a roller) -uMax
    s.bottomRoller = true;
    s.bottomUy = -s.uMax;
  }
  if (!s.dump.empty()) s.dump += s.bottomRoller ? "_roller" : "";
  const PlateResult r = runPlate(s);
  print(text.c_str(), r);
  const double a = 0.05;
  const Crack kc = crackBeside(r, s.dx, a + 2 * s.support, a, 4 * s.support);
  std::printf("  crack beside the inclusion at crossing: mean height %.1f mm, %.0f %% within 4 supports of y = +-a, "
              "%ld sites\n", 1e3 * kc.height, 100 * kc.inBand, kc.count);
}

// Validation 5 of issue 15 at 150 x 150. The bottom layer is held along y only (a roller, as the
// top): with it clamped, the free body's run damages first at the clamped layer's ends (the corner
// singularity of a clamped edge, which the fixed inclusion shields) and the plate tears along the
// bottom layer (measured: D >= 0.5 at (-149, -145) mm at u_top = 41.9 um, crossing at y = -145
// mm); the fixed runs do not notice the change (onset 25.06 um roller, 25.07 um clamped).
// Asserted: the free body's onset at the larger ligament stretch within 10 % of the fixed run's
// (measured +7.9 % at D >= 0.5, +8.8 % at D >= 0.1); the same crack topology (a crack over the
// inclusion's top through both sides, 90 % of its particles beside the inclusion within 4
// supports of y = a, left-right symmetric); the body on the axis and unrotated. Recorded, not
// met: the crack's height beside the inclusion (45.4 mm against 34.1 mm, +33 %) and the crossing
// (stretch +75 %: once the crack opens the body drops back with the lower half).
TEST(RigidDamagePlateLong, FreeRigidInclusionAt150x150OnsetAsTheFixedOne) {
  PlateSetup sf = fine(Inclusion::RigidFixed), sr = fine(Inclusion::RigidFree);
  sf.bottomRoller = sr.bottomRoller = true;
  const PlateResult f = runPlate(sf);
  print("fixed", f);
  const PlateResult r = runPlate(sr);
  print("free", r);
  const double a = 0.05, support = 5e-3, dx = 2e-3;
  ASSERT_GT(f.uOnset, 0.0) << "no damage with the fixed rigid body";
  ASSERT_GT(f.uCross, 0.0) << "the crack did not reach both sides with the fixed rigid body";
  ASSERT_GT(r.uOnset, 0.0) << "no damage with the free rigid body";
  ASSERT_GT(r.uCross, 0.0) << "the crack did not reach both sides with the free rigid body";
  auto rel = [](double x, double ref) { return std::abs(x / ref - 1.0); };
  auto stretch = [](double uTop, double uBody) { return std::max(uTop - uBody, uBody); };
  const double sOnset = stretch(r.uOnset, r.bodyUyOnset), sLow = stretch(r.uOnsetLow, r.bodyUyOnsetLow),
               sCross = stretch(r.uCross, r.bodyUyCross);
  // the pattern beside the inclusion (outside two supports of it) at crossing
  const double from = a + 2 * support;
  const Crack kF = crackBeside(f, dx, from, a, 4 * support), kR = crackBeside(r, dx, from, a, 4 * support);
  const double overlap = crackOverlap(f, r, false);
  std::printf("  free, max(u_top - u_body, u_body) vs fixed: onset %.2f um (%+.1f %%), D>=0.1 %.2f um (%+.1f %%), "
              "crossing %.2f um (%+.1f %%); u_top alone %.2f x / %.2f x / %.2f x; crack beside the inclusion at "
              "%.1f mm vs %.1f mm (%+.1f %%; %.0f / %.0f %% within 4 supports of y = a), overlap %.2f\n",
              1e6 * sOnset, 100 * (sOnset / f.uOnset - 1), 1e6 * sLow, 100 * (sLow / f.uOnsetLow - 1), 1e6 * sCross,
              100 * (sCross / f.uCross - 1), r.uOnset / f.uOnset, r.uOnsetLow / f.uOnsetLow, r.uCross / f.uCross,
              1e3 * kR.height, 1e3 * kF.height, 100 * (kR.height / kF.height - 1), 100 * kR.inBand, 100 * kF.inBand,
              overlap);
  EXPECT_LT(rel(sOnset, f.uOnset), 0.10);
  EXPECT_LT(rel(sLow, f.uOnsetLow), 0.10);
  for (const PlateResult* p : {&f, &r}) {
    EXPECT_LT(p->asymmetry, 0.10);
    EXPECT_GT(p->uCross, p->uOnset);
  }
  for (const Crack* k : {&kF, &kR}) {
    EXPECT_GT(k->count, 0);
    EXPECT_GT(k->height, 0.0) << "the crack should pass over the inclusion's top";
    EXPECT_GT(k->inBand, 0.9);
  }
  EXPECT_GT(r.bodyUyOnset, 0.25 * r.uOnset);
  EXPECT_LT(r.bodyUyOnset, 0.75 * r.uOnset);
  EXPECT_LT(std::abs(r.bodyUx), 1e-6 * dx);
  EXPECT_LT(std::abs(r.bodyRot), 1e-9);
  const std::string res = "150 x 150 points (dx = 2 mm), 2h = 5 mm, TL, AT-2, bottom layer on a roller, dt 0.9";
  const double secs = f.wall + r.wall;
  test::recordValidation({"rigid_damage_plate_free_150", "onset (D >= 0.5): ligament stretch max(u_top - u_body, u_body) [um], free vs fixed rigid body",
                          1e6 * sOnset, 1e6 * f.uOnset, rel(sOnset, f.uOnset), res, secs, "< 10 %",
                          "issue 15 item 5; fixed run = the same rigid body held"});
  test::recordValidation({"rigid_damage_plate_free_150", "onset (D >= 0.1): ligament stretch [um], free vs fixed rigid body",
                          1e6 * sLow, 1e6 * f.uOnsetLow, rel(sLow, f.uOnsetLow), res, secs, "< 10 %", "issue 15 item 5"});
  test::recordValidation({"rigid_damage_plate_free_150", "crack height beside the inclusion at crossing [mm], free vs fixed rigid body",
                          1e3 * kR.height, 1e3 * kF.height, rel(kR.height, kF.height), res, secs,
                          "recorded (not met: 10 %); asserted: above the inclusion, through both sides",
                          "issue 15 item 5 (same crack pattern)"});
  test::recordValidation({"rigid_damage_plate_free_150", "crossing: ligament stretch [um], free vs fixed rigid body",
                          1e6 * sCross, 1e6 * f.uCross, rel(sCross, f.uCross), res, secs, "recorded (not met)",
                          "issue 15 item 5"});
}
