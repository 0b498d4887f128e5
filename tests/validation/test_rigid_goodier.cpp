// Rigid bodies (physics/rigid, docs/rigid.md), validation case 3 of issue 15: a rigid circular
// inclusion bonded to an elastic plate under remote uniaxial tension S along x (2D plane strain,
// small strain), against the closed form of the perfectly bonded rigid inclusion (Goodier 1933;
// Airy stress function with u = 0 on r = a, kappa = 3 - 4 nu):
//   sigma_rr(a, 0) = S (1 - nu)(5 - 4 nu) / (3 - 4 nu)            (= 1.5 S at nu = 0.25),
// and the whole field (scripts in docs/rigid.md):
//   phi = S r^2 / 4 + B ln r + (-S r^2 / 4 + D + E / r^2) cos 2 theta,
//   B = S a^2 (1 - 2 nu) / 2,  D = -S a^2 / (2 (3 - 4 nu)),  E = S a^4 / (4 (3 - 4 nu)).
// The inclusion is a free rigid body (`bonded: true`: the first layer of clay particles is held
// to anchor points that move with the body, A.6 in tension and shear); the plate is a Cartesian
// lattice with the disc cut out (a staircase interface, as from an image), TL clay with hourglass
// control 1, traction on the two x faces, dynamic relaxation. Measured: sigma_xx along the x axis
// (the two rows y = +-dx/2) at the first three clay particles, extrapolated quadratically to
// r = a: the stress concentration, within 10 % of Goodier's; and the inclusion's drift.
// RIGID_GOODIER_PROBE="perRadius halfWidthInRadii" runs one more case and prints it
// (RIGID_GOODIER_CLAMPED=1: the inclusion as clamped solid particles instead of a rigid body)
// (RIGID_GOODIER_FORM=small_strain_stress: the clay's other formulation; RIGID_GOODIER_K: the
// grain's contact_modulus, i.e. the bond stiffness, default the clay's rho c^2 = 1.2e9 Pa).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>

#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"
#include "physics/rigid/rigid_module.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

namespace {

constexpr double kS = 1.0e5, kNu = 0.25, kE = 1.0e9;

/// Goodier's sigma_xx at (x, y) (plane strain, bonded rigid inclusion of radius a).
double goodierSxx(double x, double y, double a) {
  const double r = std::hypot(x, y), t = std::atan2(y, x), k = 3.0 - 4.0 * kNu;
  const double B = kS * a * a * (1 - 2 * kNu) / 2, D = -kS * a * a / (2 * k), E = kS * a * a * a * a / (4 * k);
  const double A = kS / 4, C = -kS / 4, c2 = std::cos(2 * t), s2 = std::sin(2 * t);
  const double r2 = r * r, r4 = r2 * r2;
  const double srr = 2 * A + B / r2 + (-2 * C - 4 * D / r2 - 6 * E / r4) * c2;
  const double stt = 2 * A - B / r2 + (2 * C + 6 * E / r4) * c2;
  const double srt = (2 * C - 2 * D / r2 - 6 * E / r4) * s2;
  const double c = std::cos(t), s = std::sin(t);
  return srr * c * c + stt * s * s - 2 * srt * s * c;
}

struct GoodierResult {
  double concentration = 0.0;  // extrapolated sigma_xx(a, 0) / S
  double first = 0.0, firstExact = 0.0;  // sigma_xx / S at the first clay particle and Goodier there
  double profileErr = 0.0;     // max |sigma_xx - Goodier| / S at the axis particles within 3 a
  double farErr = 0.0;         // the same from 1.4 a to 3 a
  double drift = 0.0;          // inclusion centre displacement / dx
  double rotation = 0.0;       // inclusion rotation (rad)
  double seconds = 0.0;
  long long particles = 0;
  double interfaceRr = 0.0;    // sigma_rr(a, 0) / S from the bond tractions (Fourier moments)
  double interfaceRt = 0.0;    // amplitude of sigma_rt(a, theta) = C2 sin 2 theta, / S
};

GoodierResult runGoodier(int perRadius, double halfWidth) {
  test::Stopwatch clock;
  const double a = 0.01, dx = a / perRadius, W = halfWidth * a;
  // RIGID_GOODIER_CLAMPED=1: the inclusion as solid particles clamped at u = 0 (in the clay's
  // reference families, as the damage plate's inclusion), the same problem by symmetry
  const bool clamped = std::getenv("RIGID_GOODIER_CLAMPED") != nullptr;
  std::ostringstream y;
  y.precision(10);
  y << "dimension: 2\n"
    << "domain: {lo: [" << -W - 2 * dx << ", " << -W - 2 * dx << "], hi: [" << W + 2 * dx << ", "
    << W + 2 * dx << "]}\n"
    << "spacing: " << dx << "\nh_over_dx: 1.3\nkernel: wendland_c2\nintegrator: leapfrog\n"
    << "end_time: 5.0e-3\ntime_step: {adaptive: true, cfl: 0.9}\n"
    << "output: {every_steps: 100000000}\nmaterials:\n"
    << "  - {name: clay, model: elastic, density: 2000, young_modulus: " << kE
    << ", poisson_ratio: " << kNu << ", plane: strain, "
    << (std::getenv("RIGID_GOODIER_FORM") ? std::string("formulation: ") + std::getenv("RIGID_GOODIER_FORM")
                                          : std::string("formulation: total_lagrangian, hourglass: 1"))
    << ", damping: 2.0e4}\n"
    << (clamped ? std::string("  - {name: grain, model: elastic, density: 2000, young_modulus: 1.0e9, "
                              "poisson_ratio: 0.25, plane: strain}\n")
                : "  - {name: grain, model: rigid, density: 2000, bonded: true" +
                      (std::getenv("RIGID_GOODIER_K") ? std::string(", contact_modulus: ") + std::getenv("RIGID_GOODIER_K")
                                                      : std::string()) + "}\n")
    << "geometry:\n"
    << "  - {shape: box, lo: [" << -W << ", " << -W << "], hi: [" << W << ", " << W
    << "], material: clay}\n"
    << "  - {shape: sphere, centre: [0.0, 0.0], radius: " << a << ", material: grain}\n"
    << "solid:\n  boundaries:\n"
    << (clamped ? "    - {name: inclusion, type: clamped, material: grain}\n" : "")
    << "    - {name: right, type: traction, box: {min: [" << W - dx << ", -1], max: [1, 1]}, "
    << "traction: [" << kS << ", 0], ramp_time: 1.5e-3}\n"
    << "    - {name: left, type: traction, box: {min: [-1, -1], max: [" << -W + dx << ", 1]}, "
    << "traction: [" << -kS << ", 0], ramp_time: 1.5e-3}\n";
  Scene s = loadSceneText(y.str(), "rigid_goodier.yaml");
  Simulation& sim = *s.sim;
  auto* rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  if (!clamped) {
    EXPECT_NE(rigid, nullptr);
    EXPECT_EQ(rigid->bodies().size(), 1u);
  }
  auto integrator = makeIntegrator("leapfrog");
  while (!s.finished()) integrator->step(sim, s.nextTimeStep());
  GoodierResult out;
  out.particles = static_cast<long long>(sim.store.realCount());
  const ParticleStore& st = sim.store;
  const RealField stress = st.real("stress");
  const RealField ref = st.real("reference_position");
  // sigma_xx on the rows y = +-dx/2 by column (reference x), both sides of the inclusion
  std::map<long long, std::pair<double, int>> col;
  std::map<long long, double> colX;
  for (Index i = 0; i < st.realCount(); ++i) {
    if (st.data(st.phase())[i] != kPhaseSolid || st.data(st.material())[i] != 0) continue;
    const Vec<2> X = st.vec<2>(ref, i);
    if (std::abs(std::abs(X[1]) - 0.5 * dx) > 0.01 * dx) continue;
    const double r = std::abs(X[0]);
    if (r > 3.0 * a) continue;
    const long long k = std::llround(r / dx - 0.5);
    auto& e = col[k];
    e.first += st.mat<2>(stress, i)(0, 0);
    e.second += 1;
    colX[k] = r;
    const double err = std::abs(st.mat<2>(stress, i)(0, 0) - goodierSxx(X[0], X[1], a)) / kS;
    out.profileErr = std::max(out.profileErr, err);
    if (r >= 1.4 * a) out.farErr = std::max(out.farErr, err);
  }
  if (std::getenv("RIGID_GOODIER_PROFILE"))
    for (const auto& [k, e] : col)
      std::printf("    r/a %.4f  sigma_xx/S %.4f  Goodier %.4f\n", colX[k] / a, e.first / e.second / kS,
                  goodierSxx(colX[k], 0.5 * dx, a) / kS);
  // first three columns outside the inclusion: quadratic through them, evaluated at r = a
  std::vector<double> rs, ss;
  for (const auto& [k, e] : col) {
    if (rs.size() == 3) break;
    rs.push_back(colX[k]);
    ss.push_back(e.first / e.second / kS);
  }
  if (rs.size() == 3) {
    double v = 0.0;
    for (int p = 0; p < 3; ++p) {
      double l = 1.0;
      for (int q = 0; q < 3; ++q)
        if (q != p) l *= (a - rs[static_cast<size_t>(q)]) / (rs[static_cast<size_t>(p)] - rs[static_cast<size_t>(q)]);
      v += l * ss[static_cast<size_t>(p)];
    }
    out.concentration = v;
    out.first = ss[0];
    out.firstExact = goodierSxx(rs[0], 0.5 * dx, a) / kS;
  }
  // Interface traction carried by the bonds (A.6: what the body receives, minus): with the bond
  // force F_i on clay particle i at angle theta_i, sum F_r = 2 pi a B0 and sum F_r cos 2 theta =
  // pi a B2 for sigma_rr(a, theta) = B0 + B2 cos 2 theta; sigma_rr(a, 0) = B0 + B2. Likewise
  // sum F_t sin 2 theta = pi a C2 for sigma_rt(a, theta) = C2 sin 2 theta. The force on the
  // clay is minus the body's: sigma . n_e with n_e = -e_r, so sigma_rr = -F_r / ds.
  if (rigid) {
    const RealField pos = st.position();
    const RigidBody& B = rigid->bodies()[0];
    double s0 = 0, s2 = 0, t2 = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      const rigid::V3 f = rigid->bondForceOn(sim, i);
      if (f.isZero(0.0)) continue;
      const Vec<2> x = st.vec<2>(pos, i);
      const double th = std::atan2(x[1] - B.state.X[1], x[0] - B.state.X[0]);
      const double fr = f[0] * std::cos(th) + f[1] * std::sin(th);
      const double ft = -f[0] * std::sin(th) + f[1] * std::cos(th);
      s0 += fr;
      s2 += fr * std::cos(2 * th);
      t2 += ft * std::sin(2 * th);
    }
    const double B0 = -s0 / (2 * M_PI * a), B2 = -s2 / (M_PI * a), C2 = -t2 / (M_PI * a);
    out.interfaceRr = (B0 + B2) / kS;
    out.interfaceRt = C2 / kS;
  }
  if (rigid) {
    const RigidBody& B = rigid->bodies()[0];
    out.drift = (B.state.X - B.X0).norm() / dx;
    out.rotation = 2.0 * std::asin(std::min(1.0, B.state.q.vec().norm()));
  }
  out.seconds = clock.seconds();
  std::printf("  interface traction from the bonds: sigma_rr(a, 0) %.4f S (Goodier %.4f S), "
              "sigma_rt amplitude %.4f S (Goodier %.4f S)\n", out.interfaceRr,
              (1 - kNu) * (5 - 4 * kNu) / (3 - 4 * kNu), out.interfaceRt,
              -2 * (1 - kNu) / (3 - 4 * kNu));
  std::printf("  a/dx %d, W %.0f a (%lld particles): sigma_xx(a, 0) extrapolated %.4f S (Goodier "
              "%.4f S: %.2f %%); first particle (r = %.4f a) %.4f S vs %.4f S; axis profile "
              "within 3 a max |err| %.3f S (from 1.4 a: %.3f S); drift %.2e dx, rotation %.1e rad; t = %.4f s, %lld "
              "steps, %.1f s\n",
              perRadius, halfWidth, out.particles, out.concentration,
              (1 - kNu) * (5 - 4 * kNu) / (3 - 4 * kNu),
              100 * (out.concentration / ((1 - kNu) * (5 - 4 * kNu) / (3 - 4 * kNu)) - 1),
              rs.empty() ? 0.0 : rs[0] / a, out.first, out.firstExact, out.profileErr, out.farErr, out.drift,
              out.rotation, sim.time, static_cast<long long>(sim.step), out.seconds);
  return out;
}

}  // namespace

TEST(RigidGoodier, Probe) {
  const char* env = std::getenv("RIGID_GOODIER_PROBE");
  if (!env) GTEST_SKIP() << "set RIGID_GOODIER_PROBE=\"perRadius halfWidthInRadii\"";
  std::istringstream in(env);
  int n = 6;
  double w = 6.0;
  in >> n >> w;
  runGoodier(n, w);
}

// a = 6 dx, plate 10 a across (3,600 particles, ~4,000 steps). Measured: interface sigma_rr(a, 0)
// 1.4906 S (Goodier 1.5 S, -0.6 %), sigma_rt amplitude 0.796 S (0.75 S, +6.1 %) when written
// (2026-11-23); 1.4875 S (-0.8 %) / 0.808 S (+7.8 %) at the 2026-11-27 HEAD; at 4 dx per
// radius 1.537 S (+2.5 %) / 0.843 S (+12 %); at 8, 1.496 S (-0.2 %) / 0.804 S (+7.2 %); the
// sigma_xx profile of the clay from 1.4 a outward within 0.045 S of Goodier's (the finite width
// W = 5 a adds ~0.04 S: with W = 8 a the interface values are 1.536 / 0.831 S). The clay's own
// stress on the first two layers is low (0.95 S and 1.18 S at 1.08 a and 1.25 a against 1.52 S
// and 1.49 S): its TL family ends at the interface (docs/rigid.md, open).
TEST(RigidGoodier, BondedInclusionCarriesGoodiersInterfaceStressAndStaysPut) {
  const double a = 0.01;
  const GoodierResult r = runGoodier(6, 5.0);
  const double rr = (1 - kNu) * (5 - 4 * kNu) / (3 - 4 * kNu), rt = 2 * (1 - kNu) / (3 - 4 * kNu);
  const double errRr = std::abs(r.interfaceRr / rr - 1), errRt = std::abs(-r.interfaceRt / rt - 1);
  EXPECT_LT(errRr, 0.10) << "interface sigma_rr(a, 0)";
  EXPECT_LT(errRt, 0.10) << "interface sigma_rt amplitude";
  EXPECT_LT(r.farErr, 0.08) << "clay sigma_xx on the axis beyond 1.4 a (0.056 S measured, ~0.04 S of it the finite width)";
  EXPECT_LT(r.drift, 1e-9) << "the inclusion drifts";
  EXPECT_LT(r.rotation, 1e-9) << "the inclusion turns";
  (void)a;
  test::recordValidation({"rigid_goodier_interface_rr", "interface sigma_rr(a, 0) / S from the bonds",
                          r.interfaceRr, rr, errRr, "2D, a = 6 dx, plate 10 a across, 3,600 particles",
                          r.seconds, "< 10 %", "Goodier 1933, bonded rigid inclusion, plane strain"});
  test::recordValidation({"rigid_goodier_interface_rt", "interface sigma_rt amplitude / S from the bonds",
                          -r.interfaceRt, rt, errRt, "2D, a = 6 dx, plate 10 a across, 3,600 particles",
                          r.seconds, "< 10 %", "Goodier 1933, bonded rigid inclusion, plane strain"});
}
