// Validation 5b of issue 4: thick-walled cylinder under internal pressure (Lame), 2D plane
// strain, quarter model with two symmetry (mirror) planes, pressure on the inner surface,
// dynamic relaxation with viscous damping to the static state. Radial and hoop stress profiles
// against sigma_r = A - B/r^2, sigma_t = A + B/r^2 (A = p a^2/(b^2 - a^2), B = A b^2), within 5 %
// of the pressure (radially binned), for the TL and the stress-based small-strain forms.
//
// The wall is built of body-fitted concentric rings (solid_scenes.hpp appendRings: the particles'
// annular cells tile a <= r <= b, so both surfaces are exactly circular). The pressure is the
// consistent nodal load of a uniform stress -p 1 (f_a = p V_a sum_b V_b (g_ab - g_ba), on the
// particles within two supports of the bore). Measured (TL): 20 rings across the wall: radial
// 2.4 %, hoop 0.9 % of p; 28 rings: 1.5 %, 0.7 %. The same wall on a Cartesian lattice
// (staircase surfaces, what a voxel image gives) is asserted at its measured level (5.1 % / 17 %
// at 20 across: the staircase of the bore, not the strain operator, is the error; docs/solid.md
// case 5). The stress-based small-strain form is accurate at 2 ms of relaxation and then
// unstable (its error grows with time): asserted as such, not validated.
#include <gtest/gtest.h>

#include <cmath>

#include "physics/solid/solid_scenes.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
using namespace poresph::solid;

namespace {

struct LameResult {
  double radialError = 0.0;  // max over radial bins of |mean sigma_r - exact| / p
  double hoopError = 0.0;
  double wall = 0.0;
  Index particles = 0;
};

/// Runs the relaxation to each time of `times` (increasing; default 4 ms) and returns the errors
/// at each.
std::vector<LameResult> runLameAt(const std::string& formulation, int perThickness, double hOverDx, bool rings,
                                  const std::vector<double>& times);

LameResult runLame(const std::string& formulation, int perThickness, double hOverDx, bool rings) {
  return runLameAt(formulation, perThickness, hOverDx, rings, {4.0e-3}).back();
}

std::vector<LameResult> runLameAt(const std::string& formulation, int perThickness, double hOverDx, bool rings,
                                  const std::vector<double>& times) {
  test::Stopwatch clock;
  const double a = 0.01, b = 0.02, p = 1.0e5;
  const double dx = (b - a) / perThickness;
  Simulation sim(2);
  addMaterial(sim, "clay", "elastic",
              "{density: 2000, young_modulus: 1.0e8, poisson_ratio: 0.25, formulation: " +
                  formulation + ", damping: 2.0e4}");
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::CubicSpline, 2, hOverDx * dx);
  const double depth = 2.0 * sim.kernel.support() + dx;  // mirror layers: two supports
  std::vector<double> pts, vol;
  if (rings) {  // body-fitted: perThickness concentric rings filling a <= r <= b
    std::vector<double> all, allV;
    appendRings(a, dx, perThickness, all, allV);
    for (size_t k = 0; k < allV.size(); ++k)
      if (all[2 * k] > -depth && all[2 * k + 1] > -depth) {
        pts.push_back(all[2 * k]);
        pts.push_back(all[2 * k + 1]);
        vol.push_back(allV[k]);
      }
  } else {  // Cartesian lattice: staircase surfaces at r = a and r = b
    const int m = static_cast<int>(std::ceil((b + depth) / dx)) + 1;
    for (int j = -m; j < m; ++j)
      for (int i = -m; i < m; ++i) {
        const double x = (i + 0.5) * dx, y = (j + 0.5) * dx, r = std::hypot(x, y);
        if (r < a || r > b || x < -depth || y < -depth) continue;
        pts.push_back(x);
        pts.push_back(y);
        vol.push_back(dx * dx);
      }
  }
  const Index n = static_cast<Index>(pts.size() / 2);
  sim.store.addParticles(n);
  std::copy(pts.begin(), pts.end(), sim.store.data(sim.store.position()));
  for (Index k = 0; k < n; ++k) sim.store.data(sim.store.mass())[k] = 2000.0 * vol[static_cast<size_t>(k)];
  sim.domain.lo = {-b - depth, -b - depth, 0};
  sim.domain.hi = {b + depth, b + depth, 1};
  const std::string rmax = std::to_string(a + 2.0 * sim.kernel.support());  // two supports deep
  ElasticSolidModule& solid = addSolidModule(
      sim, "{boundaries: ["
           "{name: bore, type: pressure, shell: {centre: [0, 0], r_min: 0, r_max: " + rmax +
           "}, pressure: " + std::to_string(p) + ", ramp_time: 1.0e-3},"
           "{name: symmetry_x, type: symmetry, box: {min: [-1, -1], max: [0, 1]}, mirror: {point: [0, 0], normal: [1, 0]}},"
           "{name: symmetry_y, type: symmetry, box: {min: [-1, -1], max: [1, 0]}, mirror: {point: [0, 0], normal: [0, 1]}}]}");
  solid.initialise(sim);
  auto integrator = makeIntegrator("leapfrog");
  const double dt = 0.5 * solid.elasticTimeStepLimit(sim);
  std::vector<LameResult> out;
  for (const double tEnd : times) {
  const long steps = static_cast<long>(tEnd / dt);
  while (sim.step < steps) integrator->step(sim, dt);

  const double A = p * a * a / (b * b - a * a), B = A * b * b;
  const int bins = 8;
  std::vector<double> sr(bins, 0.0), st(bins, 0.0), rs(bins, 0.0);
  std::vector<int> cnt(bins, 0);
  ParticleStore& s = sim.store;
  const RealField X = s.real("reference_position"), sigma = s.real("stress");
  for (Index i = 0; i < s.realCount(); ++i) {
    const Vec<2> Xi = s.vec<2>(X, i);
    if (Xi.minCoeff() < 0.0) continue;  // mirror layers
    const double r = Xi.norm();
    const Vec<2> er = Xi / r, et(-er[1], er[0]);
    const Mat<2> S = s.mat<2>(sigma, i);
    const int k = std::min(bins - 1, static_cast<int>((r - a) / (b - a) * bins));
    sr[k] += er.dot(S * er);
    st[k] += et.dot(S * et);
    rs[k] += r;
    ++cnt[k];
  }
  LameResult res;
  double hoopIntegral = 0.0;
  for (int k = 0; k < bins; ++k) hoopIntegral += st[k] / cnt[k] * (b - a) / bins;
  std::printf("  hoop resultant / (p a) = %.4f (exact 1)\n", hoopIntegral / (p * a));
  for (int k = 0; k < bins; ++k) {
    const double r = rs[k] / cnt[k];
    const double er = std::abs(sr[k] / cnt[k] - (A - B / (r * r))) / p;
    const double et = std::abs(st[k] / cnt[k] - (A + B / (r * r))) / p;
    std::printf("  r = %.4f: sigma_r %.4f (exact %.4f), sigma_t %.4f (exact %.4f) [p]\n", r,
                sr[k] / cnt[k] / p, (A - B / (r * r)) / p, st[k] / cnt[k] / p, (A + B / (r * r)) / p);
    res.radialError = std::max(res.radialError, er);
    res.hoopError = std::max(res.hoopError, et);
  }
  res.wall = clock.seconds();
  res.particles = n;
  out.push_back(res);
  }
  return out;
}

const char* kLameRef = "Lame closed form (thick-walled cylinder)";

void check(const std::string& f) {
  const std::string res = "20 body-fitted rings across the wall (a = 10 mm, b = 20 mm), h = 1.3 dx, quarter + mirrors";
  if (f != "total_lagrangian") {
    // The stress-based small-strain form is as accurate as TL after 2 ms of relaxation (radial
    // 2.4 %, hoop 0.98 % of p), but its error then GROWS with time on the same particles (hoop
    // 10.9 % at 4 ms; at 28 rings 2.8 % at 2 ms, 41 % at 4 ms; TL stays at 0.7 % to 8 ms): an
    // instability of the current-configuration kernel under the tensile hoop stress (the
    // tensile instability, which the Lagrangian kernel of TL does not have; docs/solid.md,
    // "Which formulation carries damage"). Asserted as what the form does: accurate at 2 ms,
    // then the hoop error grows more than five-fold by 4 ms.
    const std::vector<LameResult> r = runLameAt(f, 20, 1.3, true, {2.0e-3, 4.0e-3});
    std::printf("%s, rings, 20 across: at 2 ms radial %.2f %% p, hoop %.2f %% p; at 4 ms radial %.2f %% p, hoop %.2f %% p; %.1f s\n",
                f.c_str(), 100 * r[0].radialError, 100 * r[0].hoopError, 100 * r[1].radialError,
                100 * r[1].hoopError, r[1].wall);
    test::recordValidation({"solid_lame_" + f + "_2ms", "max radial-stress error over 8 radial bins / p (2 ms)",
                            r[0].radialError, 0.0, r[0].radialError, res, r[1].wall, "< 5 %", kLameRef});
    test::recordValidation({"solid_lame_" + f + "_2ms", "max hoop-stress error over 8 radial bins / p (2 ms)",
                            r[0].hoopError, 0.0, r[0].hoopError, res, r[1].wall, "< 2 %", kLameRef});
    test::recordValidation({"solid_lame_" + f + "_4ms", "max hoop-stress error over 8 radial bins / p (4 ms)",
                            r[1].hoopError, 0.0, r[1].hoopError, res, r[1].wall,
                            "> 5 x the 2 ms error (instability, not validated)", kLameRef});
    EXPECT_LT(r[0].radialError, 0.05);
    EXPECT_LT(r[0].hoopError, 0.02);
    EXPECT_GT(r[1].hoopError, 5.0 * r[0].hoopError);
    return;
  }
  const LameResult r = runLame(f, 20, 1.3, true);
  std::printf("%s, rings: max radial error %.2f %% p, max hoop error %.2f %% p, %lld particles, %.1f s\n",
              f.c_str(), 100 * r.radialError, 100 * r.hoopError, static_cast<long long>(r.particles), r.wall);
  test::recordValidation({"solid_lame_" + f, "max radial-stress error over 8 radial bins / p", r.radialError, 0.0,
                          r.radialError, res, r.wall, "< 5 %", kLameRef});
  test::recordValidation({"solid_lame_" + f, "max hoop-stress error over 8 radial bins / p", r.hoopError, 0.0,
                          r.hoopError, res, r.wall, "< 5 %", kLameRef});
  EXPECT_LT(r.radialError, 0.05);
  EXPECT_LT(r.hoopError, 0.05);
  // convergence: finer wall, smaller error
  const LameResult fine = runLame(f, 28, 1.3, true);
  std::printf("  28 rings across the wall: radial %.2f %% p, hoop %.2f %% p, %.1f s\n",
              100 * fine.radialError, 100 * fine.hoopError, fine.wall);
  const std::string resFine = "28 body-fitted rings across the wall, h = 1.3 dx";
  test::recordValidation({"solid_lame_" + f + "_28", "max radial-stress error over 8 radial bins / p",
                          fine.radialError, 0.0, fine.radialError, resFine, fine.wall,
                          "< 5 %, falling with resolution", kLameRef});
  test::recordValidation({"solid_lame_" + f + "_28", "max hoop-stress error over 8 radial bins / p",
                          fine.hoopError, 0.0, fine.hoopError, resFine, fine.wall,
                          "< 5 %, falling with resolution", kLameRef});
  EXPECT_LT(fine.hoopError, r.hoopError);
  EXPECT_LT(fine.radialError, r.radialError);
  // The same wall on a Cartesian lattice (staircase surfaces, as from imaged rock): the relaxed
  // solution next to the staircase is wrong (docs/solid.md case 5: the first particles carry a
  // flattened peak); measured 5.1 % / 17 % at 20 across, falling at first order with resolution
  // (3.0 / 10 % at 28, 1.6 / 6.8 % at 40). Asserted at the measured level.
  const LameResult stair = runLame(f, 20, 1.3, false);
  std::printf("  lattice (staircase), 20 across: radial %.2f %% p, hoop %.2f %% p, %.1f s\n",
              100 * stair.radialError, 100 * stair.hoopError, stair.wall);
  const std::string resStair = "20 across the wall on a Cartesian lattice (staircase surfaces), h = 1.3 dx";
  test::recordValidation({"solid_lame_" + f + "_lattice", "max radial-stress error over 8 radial bins / p",
                          stair.radialError, 0.0, stair.radialError, resStair, stair.wall,
                          "< 6 % (staircase surfaces)", kLameRef});
  test::recordValidation({"solid_lame_" + f + "_lattice", "max hoop-stress error over 8 radial bins / p",
                          stair.hoopError, 0.0, stair.hoopError, resStair, stair.wall,
                          "< 20 % (staircase surfaces)", kLameRef});
  EXPECT_LT(stair.radialError, 0.06);
  EXPECT_LT(stair.hoopError, 0.20);
}

}  // namespace

TEST(SolidLame, TotalLagrangian) { check("total_lagrangian"); }
TEST(SolidLame, SmallStrainStress) { check("small_strain_stress"); }

// Resolution study on the Cartesian lattice, not part of the suite (about 20 s): run with
//   validation_test_solid_lame --gtest_also_run_disabled_tests --gtest_filter=*Study*
TEST(SolidLame, DISABLED_StudyFortyAcrossTheWallLattice) {
  const LameResult r = runLame("total_lagrangian", 40, 1.3, false);
  std::printf("Lame 40 across (lattice): radial %.2f %% p, hoop %.2f %% p, %lld particles, %.1f s\n",
              100 * r.radialError, 100 * r.hoopError, static_cast<long long>(r.particles), r.wall);
}

// The stress-based form on rings, 20 / 28 / 40 across, at 2, 4 and 8 ms of relaxation (a few
// minutes): the error grows with time (see check() above); TL on the same particles for
// comparison.
TEST(SolidLame, DISABLED_StudyStressBasedRings) {
  for (const std::string f : {"small_strain_stress", "total_lagrangian"})
    for (int nw : {20, 28, 40}) {
      const std::vector<LameResult> r = runLameAt(f, nw, 1.3, true, {2.0e-3, 4.0e-3, 8.0e-3});
      for (size_t k = 0; k < r.size(); ++k)
        std::printf("Lame %s, %d rings, %g ms: radial %.2f %% p, hoop %.2f %% p, %.1f s\n", f.c_str(), nw,
                    2.0 * (1 << k), 100 * r[k].radialError, 100 * r[k].hoopError, r[k].wall);
    }
}
