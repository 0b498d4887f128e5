// Validation item 3 of issue 13 at a coarse resolution the default suite affords: the plate with
// a rigid inclusion of thesis Sec. 4.3 (see damage_plate_case.hpp). `Explore` (skipped unless
// PORESPH_PLATE=dx,2h,u,ramp,damping,hourglass,law,Yc0 is set; PORESPH_PLATE_BOTTOM,
// PORESPH_PLATE_DUMP, PORESPH_PLATE_STEPS, PORESPH_PLATE_THRESHOLD = onset D, PORESPH_PLATE_DT = dt / step limit,
// PORESPH_PLATE_AV = alpha,beta of the artificial viscosity, PORESPH_PLATE_CROSS = D,depth in dx
// of the crossing measure, PORESPH_PLATE_COMMIT = step_end or evaluation, default evaluation, PORESPH_PLATE_RECORD = case name of
// validation records of the run, PORESPH_PLATE_FORM = total_lagrangian (default) or small_strain_stress,
// PORESPH_PLATE_PLANE = strain (default) or stress, PORESPH_PLATE_HOLD = L/c_p to hold the end
// displacement after the ramp) is the driver of the studies quoted in docs/damage.md.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>

#include "tests/support/validation_record.hpp"
#include "tests/validation/damage_plate_case.hpp"

using namespace poresph;
using namespace poresph::solid::plate;

TEST(DamagePlate, Explore) {
  const char* e = std::getenv("PORESPH_PLATE");
  if (!e) GTEST_SKIP();
  PlateSetup s;
  char law[200] = "at2";
  double yc = 2500;
  std::sscanf(e, "%lf,%lf,%lf,%lf,%lf,%lf,%199[^,],%lf", &s.dx, &s.support, &s.uMax, &s.rampCrossings,
              &s.damping, &s.hourglass, law, &yc);
  std::string lawName = law;  // ';' stands for ',' (extra keys: "pcw; b: 1")
  for (char& ch : lawName)
    if (ch == ';') ch = ',';
  s.law = "{law: " + lawName + ", critical_energy_release: " + std::to_string(yc) + "}";
  if (const char* d = std::getenv("PORESPH_PLATE_DUMP")) s.dump = d;
  s.clampBottom = std::getenv("PORESPH_PLATE_BOTTOM") != nullptr;
  if (const char* m = std::getenv("PORESPH_PLATE_STEPS")) s.maxSteps = std::atol(m);
  if (const char* t = std::getenv("PORESPH_PLATE_THRESHOLD")) s.threshold = std::atof(t);
  if (const char* c = std::getenv("PORESPH_PLATE_DT")) s.dtFactor = std::atof(c);
  if (const char* c = std::getenv("PORESPH_PLATE_AV")) std::sscanf(c, "%lf,%lf", &s.avAlpha, &s.avBeta);
  if (const char* c = std::getenv("PORESPH_PLATE_CROSS")) std::sscanf(c, "%lf,%lf", &s.crossThreshold, &s.crossDepth);
  s.damageCommit = "evaluation";
  if (const char* c = std::getenv("PORESPH_PLATE_COMMIT")) s.damageCommit = c;
  if (const char* c = std::getenv("PORESPH_PLATE_FORM")) s.formulation = c;
  if (const char* c = std::getenv("PORESPH_PLATE_PLANE")) s.plane = c;
  if (const char* c = std::getenv("PORESPH_PLATE_HOLD")) s.holdCrossings = std::atof(c);
  if (lawName == "none") s.law.clear();
  const PlateResult r = runPlate(s);
  std::printf("%s, plane %s, commit %s: crossing at D >= 0.1 / 0.5 / 0.9 / 0.99 within %g dx of the sides: "
              "%.2f / %.2f / %.2f / %.2f um, mean width (70-140 mm) at crossing %.2f mm, hold %g L/c_p: "
              "crossed %.2f L/c_p after the ramp's end\n",
              s.formulation.c_str(), s.plane.c_str(), s.damageCommit.c_str(), s.crossDepth,
              1e6 * r.uCrossAt[0], 1e6 * r.uCrossAt[1], 1e6 * r.uCrossAt[2], 1e6 * r.uCrossAt[3],
              1e3 * r.widthMeanCross, s.holdCrossings, r.holdCross);
  std::printf("dx %g 2h %g u %g ramp %g damp %g hg %g %s: %ld particles %ld steps (dt %.4g s), onset u = %.2f um at "
              "(%.1f, %.1f) mm, onset D >= %g u = %.2f um at (%.1f, %.1f) mm, crossing %.2f um, asym %.3f, "
              "width %.1f mm (crossing %.1f), Dmax %.3f, diss %.3g, balance %.3g, clipped %ld, %.1f s\n",
              s.dx, s.support, s.uMax, s.rampCrossings, s.damping, s.hourglass, s.law.c_str(),
              r.particles, r.steps, r.dt, 1e6 * r.uOnset, 1e3 * r.xOnset, 1e3 * r.yOnset, s.lowThreshold,
              1e6 * r.uOnsetLow, 1e3 * r.xOnsetLow, 1e3 * r.yOnsetLow, 1e6 * r.uCross,
              r.asymmetry, 1e3 * r.width, 1e3 * r.widthCross, r.dmax, r.dissipated, r.balance, r.clipped, r.wall);
  // PORESPH_PLATE_RECORD=<case>: the run's numbers as validation records (docs/validation.md) for
  // the resolutions the suite cannot afford (docs/damage.md "The plate at 200 / 300 points").
  // AT-2 tension: onset and crossing beside the thesis' 17.4 / 19.8 um (Sec. 4.3.2.1, Fig. 4.14).
  const char* rec = std::getenv("PORESPH_PLATE_RECORD");
  if (!rec) return;
  char res[300];
  std::snprintf(res, sizeof res,
                "%d x %d points (dx = %g mm), 2h = %g mm, TL, hourglass %g, damping %g/s, dt %g x Eq. 2.50, "
                "ramp %g um per L/c_p, bottom %s, damage_commit: %s (DamagePlate.Explore)",
                static_cast<int>(std::lround(0.3 / s.dx)), static_cast<int>(std::lround(0.3 / s.dx)), 1e3 * s.dx,
                1e3 * s.support, s.hourglass, s.damping, s.dtFactor, 1e6 * std::abs(s.uMax) / s.rampCrossings,
                s.clampBottom ? "held" : "free", s.damageCommit.c_str());
  const bool tension = s.uMax > 0.0;
  const double thOnset = tension ? 17.4 : 24.0, thCross = tension ? 19.8 : 27.8;
  const std::string src = "thesis Sec. 4.3.2.1, Fig. 4.14 (300 x 300 points, 2h = 5 mm)";
  auto rel = [](double m, double ref) { return std::abs(m - ref) / std::abs(ref); };
  const double on = 1e6 * std::abs(r.uOnset), low = 1e6 * std::abs(r.uOnsetLow), cr = 1e6 * std::abs(r.uCross);
  char q[120];
  std::snprintf(q, sizeof q, "imposed displacement at onset, first D >= %g [um]", s.threshold);
  test::recordValidation({rec, q, on, thOnset, rel(on, thOnset), res, r.wall, "recorded (run by hand)", src});
  std::snprintf(q, sizeof q, "imposed displacement at onset, first D >= %g [um]", s.lowThreshold);
  test::recordValidation({rec, q, low, thOnset, rel(low, thOnset), res, r.wall, "recorded (run by hand)", src});
  test::recordValidation({rec, "imposed displacement at full crossing [um]", cr, thCross, rel(cr, thCross), res,
                          r.wall, "recorded (run by hand)", src});
  std::snprintf(q, sizeof q, "damaged width (D >= %g) across the crack at crossing / 2h", s.threshold);
  test::recordValidation({rec, q, r.widthCross / s.support, 1.0,
                          rel(r.widthCross / s.support, 1.0), res, r.wall, "recorded (run by hand)",
                          "thesis Fig. 4.14c (width ~ 2h); issue 13 item 4"});
  test::recordValidation({rec, "left-right asymmetry of D", r.asymmetry, 0.0, r.asymmetry, res, r.wall,
                          "recorded (run by hand)", "thesis Sec. 4.3.2.1 (symmetric pattern)"});
  test::recordValidation({rec, "energy balance residual / boundary work", r.balance, 0.0, r.balance, res, r.wall,
                          "recorded (run by hand)", "Eqs. 4.25-4.26 with the boundary work"});
}

// The coarse plate in tension of both coarse tension tests (60 x 60 points, 2h = 12.5 mm,
// bottom clamped with the inclusion, no hourglass control, damage committed at the evaluation)
// and their onset / crossing / symmetry checks are coarseTensionPlate() and
// expectCrackFromTheInclusionTopToBothSides() of damage_plate_case.hpp (no hourglass control:
// energy balance 0.05 % of the work without it, 14-18 % with hourglass 1, docs/damage.md).

// Coarse plate (dx = 5 mm, 2h = 12.5 mm, 60 x 60 points), AT-2 in tension, the bottom layer
// clamped with the inclusion (see docs/damage.md: with the inclusion alone the crack wraps around
// it and runs down to the bottom edge). Asserted: onset on the upper half of the inclusion boundary, a crack that
// reaches both sides, left-right symmetry within 10 %, damaged width within a factor 2 of 2h,
// energy balance within 0.2 % of the boundary work.
// The imposed displacements at onset and crossing are recorded beside the thesis' 17.4 / 19.8 um
// (2h = 5 mm, 300 x 300 points: not comparable at this resolution, not asserted).
TEST(DamagePlate, CoarseTensionAT2CrackFromTheInclusionTopToBothSides) {
  const PlateSetup s = coarseTensionPlate();
  const PlateResult r = runPlate(s);
  const double a = 0.05;
  std::printf("coarse plate: %ld particles, %ld steps, onset u = %.2f um at (%.1f, %.1f) mm, crossing "
              "u = %.2f um, asymmetry %.4f, width %.1f mm at crossing, %.1f mm at the end (2h = %.1f), balance %.3f, "
              "D max %.3f, %.1f s\n",
              r.particles, r.steps, 1e6 * r.uOnset, 1e3 * r.xOnset, 1e3 * r.yOnset, 1e6 * r.uCross,
              r.asymmetry, 1e3 * r.widthCross, 1e3 * r.width, 1e3 * s.support, r.balance, r.dmax, r.wall);
  expectCrackFromTheInclusionTopToBothSides(r, s, a);
  if (HasFatalFailure()) return;
  // the damaged width at the end of the ramp (the crack formed): at the instant the tip reaches
  // the sides the band at x = +-(a + L/6) is one or two particles (5 / 10 mm at dt 0.5 / 0.25 x
  // Eq. 2.50, the same u), at the end 10 mm at every dt (docs/damage.md "The commit lag")
  EXPECT_GT(r.width, 0.5 * s.support);
  EXPECT_LT(r.width, 2.0 * s.support);
  // measured 5.0e-4 with the damage committed at the evaluation and the trapezoidal release
  // (2.6e-4 / 1.9e-4 at dt 0.25 / 0.125); 1.3 % when it was committed after the step
  EXPECT_LT(r.balance, 0.002) << "energy balance residual / work of the boundaries";
  const std::string res = "60 x 60 points (dx = 5 mm), 2h = 12.5 mm, TL, no hourglass control, damping 600/s, "
                          "damage_commit: evaluation";
  test::recordValidation({"damage_plate_coarse_at2_tension", "imposed displacement at onset [um]",
                          1e6 * r.uOnset, 17.4, std::abs(1e6 * r.uOnset - 17.4) / 17.4, res, r.wall,
                          "recorded (thesis at 300 x 300, 2h = 5 mm)", "thesis Sec. 4.3.2.1, Fig. 4.14"});
  test::recordValidation({"damage_plate_coarse_at2_tension", "imposed displacement at full crossing [um]",
                          1e6 * r.uCross, 19.8, std::abs(1e6 * r.uCross - 19.8) / 19.8, res, r.wall,
                          "crossing > onset (thesis at 300 x 300, 2h = 5 mm)", "thesis Sec. 4.3.2.1, Fig. 4.14"});
  test::recordValidation({"damage_plate_coarse_at2_tension", "energy balance residual / boundary work",
                          r.balance, 0.0, r.balance, res, r.wall, "< 0.2 %", "Eqs. 4.25-4.26 with the boundary work"});
  test::recordValidation({"damage_plate_coarse_at2_tension", "left-right asymmetry of D", r.asymmetry, 0.0,
                          r.asymmetry, res, r.wall, "< 10 %", "thesis Sec. 4.3.2.1 (symmetric pattern)"});
  test::recordValidation({"damage_plate_coarse_at2_tension", "damaged width (D >= 0.5) at the end of the ramp [m]",
                          r.width, s.support, std::abs(r.width - s.support) / s.support, res, r.wall,
                          "0.5-2 x 2h", "thesis Fig. 4.14c (width ~ 2h)"});
}

// The energy balance of the laws with an elastic range and a snapping crack (PCW of App. B with
// b = 1, Yc = Yc0; AT-1, Eq. 4.30a) on the coarse plate in tension (issue 13: "the balance closes
// to 1 % in every validation"): their release is a second-order time-step error that the snap
// makes large (docs/damage.md "The PCW balance"): measured 0.49 % (PCW) and 0.57 % (AT-1) at
// dt = 0.5 x Eq. 2.50, 1.56 % / 1.83 % at 0.9 (which fails this test). Asserted as well: onset on
// the upper half of the inclusion boundary, a crack through both sides, symmetry within 10 %.
// ~5 s CPU per law.
TEST(DamagePlate, CoarseTensionPCWAndAT1EnergyBalanceWithinOnePercent) {
  for (const char* law : {"pcw, b: 1", "at1"}) {
    SCOPED_TRACE(law);
    PlateSetup s = coarseTensionPlate();
    s.dtFactor = 0.5;
    s.law = std::string("{law: ") + law + ", critical_energy_release: 2500}";
    const PlateResult r = runPlate(s);
    const double a = 0.05;
    std::printf("coarse plate, %s: %ld steps, onset u = %.2f um at (%.1f, %.1f) mm, crossing u = %.2f um, "
                "asymmetry %.4f, released %.3g J/m, balance %.4f, %.1f s\n",
                law, r.steps, 1e6 * r.uOnset, 1e3 * r.xOnset, 1e3 * r.yOnset, 1e6 * r.uCross, r.asymmetry,
                r.dissipated, r.balance, r.wall);
    expectCrackFromTheInclusionTopToBothSides(r, s, a);
    if (HasFatalFailure()) return;
    EXPECT_LT(r.balance, 0.01) << "energy balance residual / work of the boundaries";
    const std::string name = std::string("damage_plate_coarse_") + (law[0] == 'p' ? "pcw" : "at1") + "_tension";
    test::recordValidation({name, "energy balance residual / boundary work", r.balance, 0.0, r.balance,
                            "60 x 60 points (dx = 5 mm), 2h = 12.5 mm, TL, no hourglass control, damping 600/s, "
                            "dt 0.5 x Eq. 2.50, damage_commit: evaluation",
                            r.wall, "< 1 % (issue 13)", "Eqs. 4.25-4.26 with the boundary work"});
  }
}
