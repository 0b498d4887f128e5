// Validation 5a of issue 4: plate with a circular hole under remote tension (Kirsch). 2D plane
// stress, quarter model (symmetry mirrors on x = 0 and y = 0), traction sigma0 on the far edge
// x = W, dynamic relaxation with damping. Profile sigma_xx(0, y) against Kirsch's
// sigma0 (1 + a^2/(2 y^2) + 3 a^4/(2 y^4)).
//
// The hole is surrounded by body-fitted rings (solid_scenes.hpp appendRings, out to r = 2 a; the
// Cartesian lattice beyond): the particles' annular cells tile a <= r <= 2 a, so the surface is
// the circle r = a. The hoop stress of each ring at 90 deg is interpolated from its two particles
// nearest 90 deg (sigma_tt is even about 90 deg), and K_t is the quadratic extrapolation of the
// first three rings (r = a + dx/2, a + 3 dx/2, a + 5 dx/2) to the surface r = a. Measured at 8
// particles per radius: K_t = 2.87 (4.4 % low), asserted < 10 %. The same plate on a Cartesian
// lattice (staircase hole, what a voxel image gives) gives K_t = 2.06, asserted at that level
// (< 35 % low) and below the rings' value by more than 0.5. Imposing Kirsch's exact displacement shows that the strain operator is not the cause
// (first particle 2.42 vs 2.61 on the lattice, 2.48 vs 2.62 on the rings): the staircase changes
// the discrete equilibrium. See docs/solid.md, case 5.
#include <gtest/gtest.h>

#include <cmath>

#include "physics/solid/solid_scenes.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
using namespace poresph::solid;

namespace {

struct Result {
  double kt = 0.0, wall = 0.0, profileError = 0.0, first = 0.0;  // first: sigma/sigma0 at the first particle or ring
  Index particles = 0;
};

Result runKirsch(int perRadius, bool rings, bool exactField = false) {
  test::Stopwatch clock;
  const double a = 0.01, W = 8.0 * a, sigma0 = 1.0e5;
  const double dx = a / perRadius;
  Simulation sim(2);
  addMaterial(sim, "plate", "elastic",
              "{density: 2000, young_modulus: 1.0e9, poisson_ratio: 0.3, plane: stress, "
              "formulation: total_lagrangian, damping: 2.0e4}");
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::CubicSpline, 2, 1.3 * dx);
  const double depth = 2.0 * sim.kernel.support() + dx;
  const int n = static_cast<int>(std::lround(W / dx)), m = static_cast<int>(std::ceil(depth / dx));
  // rings: body-fitted rings out to R = 2 a, the Cartesian lattice beyond; otherwise the lattice
  // with the cells whose centre lies in the hole removed (a staircase surface)
  const int ringCount = rings ? perRadius : 0;
  const double lattice = a + ringCount * dx;
  std::vector<double> all, allV, pts, vol;
  appendRings(a, dx, ringCount, all, allV);
  for (int j = -m; j < n; ++j)
    for (int i = -m; i < n; ++i) {
      const double x = (i + 0.5) * dx, y = (j + 0.5) * dx;
      if (std::hypot(x, y) < lattice) continue;
      all.push_back(x);
      all.push_back(y);
      allV.push_back(dx * dx);
    }
  for (size_t k = 0; k < allV.size(); ++k)
    if (all[2 * k] > -depth && all[2 * k + 1] > -depth) {
      pts.push_back(all[2 * k]);
      pts.push_back(all[2 * k + 1]);
      vol.push_back(allV[k]);
    }
  sim.store.addParticles(static_cast<Index>(pts.size() / 2));
  std::copy(pts.begin(), pts.end(), sim.store.data(sim.store.position()));
  for (size_t k = 0; k < vol.size(); ++k) sim.store.data(sim.store.mass())[k] = 2000.0 * vol[k];
  sim.domain.lo = {-depth - dx, -depth - dx, 0};
  sim.domain.hi = {W + dx, W + dx, 1};
  const std::string edge = std::to_string(W - dx);
  ElasticSolidModule& solid = addSolidModule(
      sim, "{boundaries: ["
           "{name: pull, type: traction, box: {min: [" + edge + ", 0], max: [1, 1]}, traction: [" +
           std::to_string(sigma0) + ", 0], ramp_time: 1.5e-3},"
           "{name: symmetry_x, type: symmetry, box: {min: [-1, -1], max: [0, 1]}, mirror: {point: [0, 0], normal: [1, 0]}},"
           "{name: symmetry_y, type: symmetry, box: {min: [-1, -1], max: [1, 0]}, mirror: {point: [0, 0], normal: [0, 1]}}]}");
  solid.initialise(sim);
  auto integrator = makeIntegrator("leapfrog");
  const double dt = 0.9 * solid.elasticTimeStepLimit(sim);
  const long steps = static_cast<long>(5.0e-3 / dt);
  if (exactField) {
    // Kirsch's displacement field (infinite plate, plane stress) imposed on every particle: the
    // stress then measures the strain operator alone, without the discrete equilibrium.
    const double E = 1.0e9, nu = 0.3, mu = E / (2 * (1 + nu)), kap = (3 - nu) / (1 + nu);
    ParticleStore& st = sim.store;
    const double* Xr = st.data(st.real("reference_position"));
    double* xp = st.data(st.position());
    for (Index i = 0; i < st.realCount(); ++i) {
      const double X0 = Xr[2 * i], Y0 = Xr[2 * i + 1], r = std::hypot(X0, Y0), th = std::atan2(Y0, X0);
      const double c2 = std::cos(2 * th), s2 = std::sin(2 * th), k = sigma0 / (4 * mu);
      const double ur = k * (r * ((kap - 1) / 2 + c2) + a * a / r * (1 + (1 + kap) * c2) - std::pow(a, 4) / std::pow(r, 3) * c2);
      const double ut = k * ((1 - kap) * a * a / r - r - std::pow(a, 4) / std::pow(r, 3)) * s2;
      xp[2 * i] = X0 + ur * std::cos(th) - ut * std::sin(th);
      xp[2 * i + 1] = Y0 + ur * std::sin(th) + ut * std::cos(th);
    }
    solid.kinematics(sim);
    solid.constitutive(sim);
  } else {
    for (long k = 0; k < steps; ++k) integrator->step(sim, dt);
  }
  // Hoop stress on the y axis (theta = 90 deg), where Kirsch's sigma_tt = sigma_xx =
  // sigma0 (1 + a^2/(2 r^2) + 3 a^4/(2 r^4)).
  ParticleStore& s = sim.store;
  const RealField X = s.real("reference_position"), sig = s.real("stress");
  std::vector<std::pair<double, double>> prof;
  if (!rings) {  // lattice: sigma_xx of the first column x = dx/2
    for (Index i = 0; i < s.realCount(); ++i) {
      const Vec<2> Xi = s.vec<2>(X, i);
      if (std::abs(Xi[0] - 0.5 * dx) < 1e-9 && Xi[1] > 0.0) prof.emplace_back(Xi.norm(), s.mat<2>(sig, i)(0, 0) / sigma0);
    }
  } else {  // rings: sigma_tt of the two particles of each ring nearest to 90 deg, at 90 -
            // dth/2 and 90 - 3 dth/2; sigma_tt is even about 90 deg, so the quadratic through
            // them gives sigma_tt(90 deg) = (9 f1 - f2) / 8
    for (int k = 0; k < ringCount; ++k) {
      const double r = a + (k + 0.5) * dx;
      double f[2] = {0, 0}, th[2] = {-1, -1};
      for (Index i = 0; i < s.realCount(); ++i) {
        const Vec<2> Xi = s.vec<2>(X, i);
        if (std::abs(Xi.norm() - r) > 1e-3 * dx || Xi[0] < 0.0) continue;
        const double t = std::atan2(Xi[1], Xi[0]);
        const Vec<2> e(-std::sin(t), std::cos(t));
        const double st = e.dot(s.mat<2>(sig, i) * e) / sigma0;
        if (t > th[0]) { th[1] = th[0]; f[1] = f[0]; th[0] = t; f[0] = st; }
        else if (t > th[1]) { th[1] = t; f[1] = st; }
      }
      prof.emplace_back(r, (9.0 * f[0] - f[1]) / 8.0);
    }
  }
  std::sort(prof.begin(), prof.end());
  Result res;
  res.profileError = 0.0;
  for (size_t k = 1; k < std::min<size_t>(prof.size(), 6); ++k) {
    const double r = prof[k].first;
    const double ref = 1 + a * a / (2 * r * r) + 1.5 * std::pow(a / r, 4);
    res.profileError = std::max(res.profileError, std::abs(prof[k].second - ref) / ref);
  }
  res.first = prof[0].second;
  for (size_t k = 0; k < std::min<size_t>(prof.size(), 6); ++k) {
    const double r = prof[k].first;
    std::printf("  r/a = %.3f: sigma_tt/sigma0 = %.3f (Kirsch %.3f)\n", r / a, prof[k].second,
                1 + a * a / (2 * r * r) + 1.5 * std::pow(a / r, 4));
  }
  // quadratic extrapolation of the first three particles to r = a
  const double r0 = prof[0].first, r1 = prof[1].first, r2 = prof[2].first;
  const double f0 = prof[0].second, f1 = prof[1].second, f2 = prof[2].second;
  const double x = a;
  res.kt = f0 * (x - r1) * (x - r2) / ((r0 - r1) * (r0 - r2)) + f1 * (x - r0) * (x - r2) / ((r1 - r0) * (r1 - r2)) +
           f2 * (x - r0) * (x - r1) / ((r2 - r0) * (r2 - r1));
  res.wall = clock.seconds();
  res.particles = s.realCount();
  return res;
}

}  // namespace

const char* kKirschRef = "Kirsch (infinite plate); finite width W = 8 a raises the profile by up to ~10 %";

TEST(SolidKirsch, HoopStressConcentration) {
  const Result r = runKirsch(8, true);
  const double err = std::abs(r.kt - 3.0) / 3.0;
  std::printf("Kirsch, rings: K_t (extrapolated) = %.3f (3.0, %.1f %%), first ring %.3f, profile error "
              "1.19 a <= r <= 1.7 a: %.1f %%, %lld particles, %.1f s\n", r.kt, 100 * err, r.first,
              100 * r.profileError, static_cast<long long>(r.particles), r.wall);
  const std::string res = "hole radius 8 dx, 8 body-fitted rings to 2 a, lattice beyond, W = 8 a, h = 1.3 dx, plane stress, TL";
  test::recordValidation({"solid_kirsch_2d", "K_t: sigma_tt(r, 90 deg) of the first 3 rings extrapolated to r = a",
                          r.kt, 3.0, err, res, r.wall, "< 10 %", "Kirsch (infinite plate)"});
  test::recordValidation({"solid_kirsch_2d", "max error of sigma_tt(r, 90 deg) for 1.19 a <= r <= 1.7 a",
                          r.profileError, 0.0, r.profileError, res, r.wall, "< 12 %", kKirschRef});
  EXPECT_LT(err, 0.10);
  EXPECT_LT(r.profileError, 0.12);

  // The same plate on a Cartesian lattice (staircase hole, what a voxel image gives): recorded.
  const Result q = runKirsch(8, false);
  const double errq = std::abs(q.kt - 3.0) / 3.0;
  std::printf("Kirsch, lattice: K_t (extrapolated) = %.3f (%.1f %%), first particle %.3f, profile error %.1f %%, %.1f s\n",
              q.kt, 100 * errq, q.first, 100 * q.profileError, q.wall);
  // The staircase deficit (docs/solid.md case 5: the relaxed solution next to the staircase
  // flattens the peak; 2.36 at 16 per radius) asserted at its measured level: 2.06, 31 % low.
  test::recordValidation({"solid_kirsch_2d_lattice", "K_t: sigma_xx(dx/2, y) of the first 3 particles extrapolated to r = a",
                          q.kt, 3.0, errq, "hole radius 8 dx on a Cartesian lattice (staircase), h = 1.3 dx", q.wall,
                          "< 35 % (staircase hole; rings: < 10 %)", "Kirsch (infinite plate)"});
  EXPECT_LT(errq, 0.35);
  EXPECT_GT(r.kt, q.kt + 0.5);  // the body-fitted surface is what removes the deficit
}

// The strain operator alone: Kirsch's displacement imposed on every particle (no equilibrium
// solve). Separates the error of the corrected gradient at the truncated support of the surface
// particles from that of the discrete equilibrium.
TEST(SolidKirsch, StrainOperatorOnExactField) {
  for (bool rings : {true, false}) {
    const Result r = runKirsch(8, rings, true);
    const double ref0 = [&] {  // Kirsch at the first measured radius
      const double q = rings ? 1.0 + 0.5 / 8 : std::hypot(0.5, 8.5) / 8;
      return 1 + 1 / (2 * q * q) + 1.5 / std::pow(q, 4);
    }();
    std::printf("exact field, %s: first %.3f (Kirsch %.3f), profile error %.2f %%\n", rings ? "rings" : "lattice",
                r.first, ref0, 100 * r.profileError);
    EXPECT_LT(std::abs(r.first - ref0) / ref0, 0.08);
    EXPECT_LT(r.profileError, 0.015);
  }
}

// Resolution study, not part of the suite (about a minute): run with
//   validation_test_solid_kirsch --gtest_also_run_disabled_tests --gtest_filter=*Study*
TEST(SolidKirsch, DISABLED_StudySixteenPerRadius) {
  for (bool rings : {true, false}) {
    const Result r = runKirsch(16, rings);
    std::printf("Kirsch 16 per radius, %s: K_t (extrapolated) = %.3f, first %.3f, profile error %.1f %%, %lld particles, %.1f s\n",
                rings ? "rings" : "lattice", r.kt, r.first, 100 * r.profileError, static_cast<long long>(r.particles), r.wall);
  }
}
