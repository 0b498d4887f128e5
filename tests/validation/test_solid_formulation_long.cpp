// Long part of the formulation study of issue 13 (label validation_long, tests/long-tests.txt):
// Lame in 3D (slab periodic along z, 6 layers) at nu = 0.1 and 0.25, Kirsch in 3D at nu = 0.1 and
// 0.25 with the 2D Kirsch at the same resolutions (three each). See test_solid_formulation.cpp.
#include "tests/validation/test_solid_formulation_cases.hpp"

using namespace poresph;
using namespace poresph::solid;
using namespace poresph::solid::formulation_cases;

TEST(SolidFormulationLong, Lame3DConvergesAtNu010And025) {
  for (const double nu : {0.1, 0.25}) checkLame<3>(nu, {8, 11, 14});
}

// Kirsch in 3D at nu = 0.1 (COx, thesis Table 5.1) and 0.25 (Table 4.2) (issue 13: Lame and
// Kirsch converge in 2D and 3D at both ratios). The 3D case is the slab of 6 layers periodic
// along z: the plane-strain problem computed with the 3D kernel, families and law, so its
// continuum reference is the plane-strain one (K_t = 3 for the infinite plate), not a hole
// through a plate of finite thickness with free faces (whose K_t varies through the thickness:
// not computed here). The 2D study (checkKirsch, 4 / 6 / 8 per radius: K_t within tol of 3,
// rising, observed order of its increments > 1) gives the limit of this K_t measure (Richardson);
// asserted for the slab at the same resolutions: K_t rising, within 1.5 % of the 2D K_t at each,
// its distance to the 2D limit falling with an observed order > 1 between each pair, and K_t
// within tol of 3 at 8 per radius. (The slab's own increments at nu = 0.25, 0.034 then 0.025,
// give no order: not yet asymptotic at 8 per radius, where it is 0.28 % from 2D.)
static void checkKirsch3DAgainst2D(double nu, double tol2D, double tol3D) {
  const std::vector<int> n = {4, 6, 8};
  const std::vector<KirschResult> r2 = checkKirsch<2>(nu, n, tol2D);
  const KirschOrder o2 = kirschOrder(n, r2);
  std::vector<KirschResult> r3;
  std::vector<double> e;  // |K_t(3D) - 2D limit|
  for (const int k : n) {
    r3.push_back(runKirsch<3>(nu, k));
    e.push_back(std::abs(r3.back().kt - o2.limit));
  }
  const KirschOrder o3 = kirschOrder(n, r3);
  std::printf("Kirsch nu = %.2f: 2D limit %.4f (order %.2f); 3D increments %.4f, %.4f (own order %.2f)\n", nu,
              o2.limit, o2.order, r3[1].kt - r3[0].kt, r3[2].kt - r3[1].kt, o3.order);
  for (size_t k = 0; k < n.size(); ++k) {
    const double diff = std::abs(r3[k].kt - r2[k].kt) / r2[k].kt, err = std::abs(r3[k].kt - 3.0) / 3.0;
    const double order = k > 0 ? std::log(e[k - 1] / e[k]) / std::log(static_cast<double>(n[k]) / n[k - 1]) : 0.0;
    std::printf("Kirsch 3D nu = %.2f, %d per radius: K_t = %.4f (%.1f %% from 3), 2D %.4f (difference %.2f %%), "
                "%.4f from the 2D limit (order %.2f), %lld particles, %.1f s\n",
                nu, n[k], r3[k].kt, 100 * err, r2[k].kt, 100 * diff, e[k], order,
                static_cast<long long>(r3[k].particles), r3[k].wall);
    const std::string c = "solid_tl_kirsch_" + label(3, nu) + "_" + std::to_string(n[k]);
    const std::string res = "hole radius " + std::to_string(n[k]) +
                            " dx, rings to 2 a, W = 8 a, h = 1.3 dx, 3D slab of 6 layers periodic along z";
    char tol_s[96];
    std::snprintf(tol_s, sizeof tol_s, k + 1 == n.size() ? "< %.0f %%; rising" : "rising", 100 * tol3D);
    test::recordValidation({c, "K_t: sigma_tt(r, 90 deg) of the first 3 rings extrapolated to r = a", r3[k].kt, 3.0,
                            err, res, r3[k].wall, tol_s, "Kirsch (infinite plate, plane strain)"});
    test::recordValidation({c, "|K_t(3D slab) - K_t(2D)| / K_t(2D)", diff, 0.0, diff, res, r3[k].wall + r2[k].wall,
                            "< 1.5 %", "the same plane-strain problem in 2D"});
    EXPECT_LT(diff, 0.015) << "nu = " << nu << ", " << n[k] << " per radius";
    if (k == 0) continue;
    test::recordValidation({c, "observed order of |K_t(3D) - 2D limit| from " + std::to_string(n[k - 1]) + " per radius",
                            order, 1.0, 0.0, res, r3[k].wall, "> 1", "Richardson limit of the 2D runs at 4 / 6 / 8"});
    EXPECT_GT(r3[k].kt, r3[k - 1].kt) << "nu = " << nu << ", " << n[k] << " per radius";
    EXPECT_GT(order, 1.0) << "nu = " << nu << ", " << n[k] << " per radius";
  }
  EXPECT_LT(std::abs(r3.back().kt - 3.0) / 3.0, tol3D) << "nu = " << nu;
}

// Measured 2026-11-28: 3D K_t 2.836 / 2.886 / 2.899 (5.5 / 3.8 / 3.4 % from 3; own increments
// 0.049 / 0.013, order 2.81), from the 2D limit 2.905: 0.068 / 0.019 / 0.006 (orders 3.2, 4.0);
// 3D - 2D 0.64 / 0.50 / 0.18 %; 303 s CPU (28 368 particles at 8 per radius), 325 s on one core.
TEST(SolidFormulationLong, Kirsch3DConvergesAtNu010) { checkKirsch3DAgainst2D(0.1, 0.05, 0.05); }

// Measured 2026-11-28: 2D 2.812 / 2.851 / 2.863 (< 6 %, limit 2.874); 3D 2.796 / 2.830 / 2.855
// (6.8 / 5.7 / 4.8 % from 3), from the 2D limit 0.077 / 0.044 / 0.019 (orders 1.4, 2.9);
// 3D - 2D 0.57 / 0.75 / 0.28 %; ~10 min of one core.
TEST(SolidFormulationLong, Kirsch3DConvergesAtNu025) { checkKirsch3DAgainst2D(0.25, 0.06, 0.06); }

// ---- Cost of the thesis' artificial viscosity (issue 13, item 5) ----
// A damageable block (Table 4.2 material: E = 12000 N/mm2, nu = 0.25, rho = 1e6 kg/m3,
// AT-2 with Yc0 = 2.5e-3 N/mm2; 0.1 m square, dx = 2.5 mm, 2h = 6.5 mm) pulled along y between
// roller grips (Eq. 4.31) to a mean strain of 2e-3 over 12 L / c_p, with the stabilisations of
// the thesis (artificial viscosity alpha = 41, whose step limit is h / (c (1 + 1.2 alpha)), ~50x
// smaller) and without it (hourglass control, viscous damping) at 0.9 x their step limit. The
// response (peak mean sigma_yy and the imposed displacement at the peak, final max D) and the
// cost (steps, wall) are printed; asserted: every run stays finite, hourglass + damping at the
// full Eq. 2.50 step gives the peak of alpha = 1 within 3 %, and alpha = 41 needs > 40 x the
// steps for a peak at most 10 % above (about 4 min on a loaded core).
namespace {
struct AvResult {
  bool finite = true;
  double peak = 0, uPeak = 0, dmax = 0, wall = 0;
  long steps = 0;
};
AvResult pullDamageBlock(double alpha, double hourglass, double damping, double dtFactor) {
  test::Stopwatch clock;
  const double L = 0.1, dx = 2.5e-3, E = 1.2e10, nu = 0.25, rho = 1e6, uMax = 2e-4;
  Simulation sim(2);
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "{density: %g, young_modulus: %g, poisson_ratio: %g, hourglass: %g, damping: %g, "
                "artificial_viscosity: {alpha: %g, beta: 0}, damage: {law: at2, critical_energy_release: 2500}}",
                rho, E, nu, hourglass, damping, alpha);
  addMaterial(sim, "clay", "elastic", buf);
  const int n = static_cast<int>(std::lround(L / dx));
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::CubicSpline, 2, 1.3 * dx);
  buildBlock<2>(sim, Vec<2>::Zero(), {n, n, 1}, dx);
  sim.domain.lo = {-dx, -dx, 0};
  sim.domain.hi = {L + dx, L + dx, 1};
  const double grip = 3 * dx;
  double lambda, mu;
  lameParameters(E, nu, 2, Plane::Strain, lambda, mu);
  const double c = std::sqrt((lambda + 2 * mu) / rho), ramp = 12 * L / c;
  ElasticSolidModule& solid = addSolidModule(
      sim, "{boundaries: [{name: bottom, type: velocity, box: {min: [-1, -1], max: [1, " + std::to_string(grip) +
               "]}, velocity: [0, 0], components: [y]}, {name: top, type: displacement, box: {min: [-1, " +
               std::to_string(L - grip) + "], max: [1, 1]}, displacement: [0, " + std::to_string(uMax) +
               "], ramp_time: " + std::to_string(ramp) + ", components: [y]}]}");
  solid.initialise(sim);
  auto integrator = makeIntegrator("leapfrog");
  const double dt = dtFactor * solid.elasticTimeStepLimit(sim);
  AvResult r;
  ParticleStore& s = sim.store;
  const long steps = static_cast<long>(ramp / dt);
  try {
    for (long k = 0; k < steps; ++k) {
      integrator->step(sim, dt);
      if (k % 10 != 0 && k != steps - 1) continue;
      sim.checkFinite();
      const RealField X = s.real("reference_position"), sig = s.real("stress");
      double m = 0;
      int cnt = 0;
      for (Index i = 0; i < s.realCount(); ++i) {
        const double Y = s.vec<2>(X, i)[1];
        if (Y < grip || Y > L - grip) continue;
        m += s.mat<2>(sig, i)(1, 1);
        ++cnt;
      }
      m /= cnt;
      if (m > r.peak) {
        r.peak = m;
        r.uPeak = uMax * sim.time / ramp;
      }
    }
    const double* D = s.data(s.real("damage"));
    for (Index i = 0; i < s.realCount(); ++i) r.dmax = std::max(r.dmax, D[i]);
  } catch (const std::exception&) {
    r.finite = false;
  }
  r.steps = sim.step;
  r.wall = clock.seconds();
  return r;
}
}  // namespace

TEST(SolidFormulationLong, ArtificialViscosityCost) {
  // lowest mode of the block: omega_1 ~ pi c / (2 L) = 1.9e3 1/s
  struct Case { const char* name; double alpha, hourglass, damping, dt; };
  const Case cases[] = {{"thesis: alpha = 41", 41, 0, 0, 0.9},
                        {"alpha = 1", 1, 0, 0, 0.9},
                        {"hourglass 1 + damping 1900/s", 0, 1, 1900, 0.9},
                        {"damping 1900/s", 0, 0, 1900, 0.9},
                        {"nothing", 0, 0, 0, 0.9}};
  std::vector<AvResult> res;
  for (const Case& c : cases) {
    res.push_back(pullDamageBlock(c.alpha, c.hourglass, c.damping, c.dt));
    const AvResult& r = res.back();
    std::printf("%-30s finite %d, peak sigma_yy %.4e Pa at u = %.3e m, max D %.3f, %ld steps, %.1f s\n", c.name,
                r.finite ? 1 : 0, r.peak, r.uPeak, r.dmax, r.steps, r.wall);
    EXPECT_TRUE(r.finite) << c.name;
  }
  // measured (loaded machine): alpha = 41: peak 2.356 MPa, 20594 steps, 117 s; alpha = 1:
  // 2.226 MPa, 902 steps; hourglass + damping: 2.234 MPa, 410 steps, 3.8 s; damping only:
  // 1.919 MPa at a smaller displacement (early localisation on zero-energy modes); nothing:
  // 2.265 MPa. alpha = 41 is not quasi-static at this ramp: its viscous pairs slow the Poisson
  // contraction (a stiffer, nearer uniaxial-strain response, +5 %).
  const std::string resol = "0.1 m AT-2 block, dx = 2.5 mm, 2h = 6.5 mm, roller pull to 2e-3 over 12 L/c, 0.9 x each step limit";
  test::recordValidation({"solid_av_cost", "peak mean sigma_yy, hourglass 1 + damping vs alpha = 1", res[2].peak,
                          res[1].peak, std::abs(res[2].peak - res[1].peak) / res[1].peak, resol, res[2].wall, "< 3 %",
                          "the same block with artificial viscosity alpha = 1"});
  test::recordValidation({"solid_av_cost", "steps of alpha = 41 / steps of hourglass 1 + damping",
                          static_cast<double>(res[0].steps) / res[2].steps, 1.0 + 1.2 * 41,
                          std::abs(static_cast<double>(res[0].steps) / res[2].steps - 50.2) / 50.2, resol, res[0].wall,
                          "> 40", "Eq. 2.50 with c (1 + 1.2 alpha)"});
  EXPECT_NEAR(res[2].peak, res[1].peak, 0.03 * res[1].peak);  // hourglass + damping = alpha = 1
  EXPECT_GT(res[0].steps, 40 * res[2].steps);                  // the cost of alpha = 41
  EXPECT_GT(res[0].peak, res[2].peak);                          // its viscous overshoot
  EXPECT_LT(res[0].peak, 1.1 * res[2].peak);
}
