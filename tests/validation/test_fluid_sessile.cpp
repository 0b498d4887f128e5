// Validation: wetting (thesis Eq. 1.10, wall colour cos(theta) entering the colour gradient of
// Eq. 5.7 and hence the CSF force 1.9). A 2D liquid drop starts as a half disc (90 degrees) on a
// flat wall and relaxes to a circular cap; the contact angle is measured by a circle fit to the
// liquid-gas interface above the first rows and taken where the circle meets the wall plane.
// Spec (issue 5, item 5): within 5 degrees of 60, 90 and 120 degrees. Wetting model: the default
// "wetting: normal" (prescribed contact-line normal near the wall, wetting_scale 0.15); the
// plain wall colour in Eq. 5.7 ("wetting: colour") stalls at ~88 / ~98 degrees for 60 / 120.
// Both phases carry a background pressure of 100 Pa (without it the gas pressure is ~0 and the
// tensile instability lets gas creep under the drop's edge).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"
#include "tests/support/interface_circle.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
using poresph::test::FittedCircle;
using poresph::test::kasaCircle;
using poresph::test::liquidGasMidpoints;
namespace fs = poresph::fluidsetup;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Periodic in x; fluid in [0, Lx) x [0, Ly), 3 wall rows below y = 0 (contact angle theta) and a
// lid of 3 rows above Ly with angle 180 degrees (colour -1 = the gas colour: no interface there).
struct Sessile {
  Simulation sim{2};
  FluidModule* fluid = nullptr;
  fs::Stepper stepper;
  double R0, dx, Lx, Ly, gamma = 0.05, mu = 0.05, rho = 1000.0, c = 2.0, pb = 100.0;
  int liquid = 0;
  Sessile(double thetaDeg, double radius, int rOverDx, const char* keys = nullptr) {
    R0 = radius;
    if (std::getenv("FLUID_MU")) mu = std::atof(std::getenv("FLUID_MU"));
    dx = R0 / rOverDx;
    Lx = 5.0 * R0;
    Ly = 2.5 * R0;
    sim.spacing = dx;
    sim.kernel = Kernel(KernelType::QuinticSpline, 2, 1.0 * dx);
    const double t = 3 * dx;
    sim.domain.lo = {0, -t, 0};
    sim.domain.hi = {Lx, Ly + t, 0};
    sim.domain.periodic = {true, false, false};
    if (std::getenv("FLUID_PB")) pb = std::atof(std::getenv("FLUID_PB"));
    char buf[300];
    std::snprintf(buf, sizeof buf, "{density: %g, sound_speed: %g, viscosity: %g, colour: 1, background_pressure: %g}", rho, c, mu, pb);
    liquid = fs::addMaterial(sim, "liquid", "fluid", buf);
    std::snprintf(buf, sizeof buf, "{density: %g, sound_speed: %g, viscosity: %g, colour: -1, background_pressure: %g}", rho, c, mu, pb);
    const int gas = fs::addMaterial(sim, "gas", "fluid", buf);
    std::snprintf(buf, sizeof buf, "{density: %g, contact_angle: %g}", rho, thetaDeg);
    const int wall = fs::addMaterial(sim, "wall", "wall", buf);
    const int lid = fs::addMaterial(sim, "lid", "wall", "{density: 1000, contact_angle: 180}");
    const char* extra = keys ? keys : std::getenv("FLUID_EXTRA") ? std::getenv("FLUID_EXTRA") : "";
    std::snprintf(buf, sizeof buf, "{surface_tension: %g%s}", gamma, extra);
    fluid = fs::addFluidModule(sim, buf);
    const double xc = 0.5 * Lx;
    auto inDrop = [=](const double* x) { return std::hypot(x[0] - xc, x[1]) < R0; };
    fs::addLattice(sim, {0, 0}, {Lx, Ly}, liquid, inDrop);
    fs::addLattice(sim, {0, 0}, {Lx, Ly}, gas, [&](const double* x) { return !inDrop(x); });
    fs::addLattice(sim, {0, -t}, {Lx, 0}, wall);
    fs::addLattice(sim, {0, Ly}, {Lx, Ly + t}, lid);
    fluid->initialise(sim);
  }

  // Algebraic (Kasa) circle fit to the liquid-gas pair midpoints above y = 2 dx
  // (tests/support/interface_circle.hpp); contact angle (degrees, through the liquid) where the
  // circle meets the wall plane y = 0: cos(theta) = -yc / r.
  double contactAngle(double& rc, double& yc, int& npts) {
    std::vector<Eigen::Vector2d> pts;
    for (const auto& q : liquidGasMidpoints(sim, liquid, liquid + 1, dx))
      if (q.y() > 2.0 * dx) pts.push_back(q);
    npts = static_cast<int>(pts.size());
    const FittedCircle fit = kasaCircle(pts);
    yc = fit.centre.y();
    rc = fit.radius;
    return std::acos(std::clamp(-yc / rc, -1.0, 1.0)) * 180.0 / kPi;
  }

  void dump(const std::string& name) const {
    const auto& st = sim.store;
    std::ofstream f(std::string(PORESPH_BINARY_DIR) + "/" + name);
    const double* x = st.data(st.position());
    const double* col = st.data(fluid->colour);
    for (Index i = 0; i < st.realCount(); ++i)
      f << x[2 * i] << " " << x[2 * i + 1] << " " << col[i] << "\n";
  }
};

double runCase(double thetaDeg, double tEnd) {
  test::Stopwatch clock;
  const int rdx = std::getenv("FLUID_RDX") ? std::atoi(std::getenv("FLUID_RDX")) : 10;
  Sessile s(thetaDeg, 1.5e-3, rdx);
  const double T = std::getenv("FLUID_TEND") ? std::atof(std::getenv("FLUID_TEND")) : tEnd;
  double rc = 0, yc = 0;
  int np = 0;
  for (int k = 1; k <= 4; ++k) {
    s.stepper.runTo(s.sim, T * k / 4);
    const double th = s.contactAngle(rc, yc, np);
    std::printf("theta %.0f: t = %.4f s, measured %.2f deg (r = %.3e, yc = %.3e, %d points), max density var %.3g\n",
                thetaDeg, s.sim.time, th, rc, yc, np, s.fluid->maxDensityVariation());
  }
  const double th = s.contactAngle(rc, yc, np);
  // equilibrium cap of the same area A = pi R0^2 / 2: r^2 (theta - sin theta cos theta) = A
  const double q = thetaDeg * kPi / 180.0;
  const double rEq = std::sqrt(0.5 * kPi * s.R0 * s.R0 / (q - std::sin(q) * std::cos(q)));
  const double wall = clock.seconds();
  std::printf("theta %.0f: measured %.2f deg, cap radius %.3e (equilibrium %.3e), %lld steps, %.1f s\n",
              thetaDeg, th, rc, rEq, static_cast<long long>(s.sim.step), wall);
  char name[64];
  std::snprintf(name, sizeof name, "fluid_sessile_%.0f%s.txt", thetaDeg, std::getenv("FLUID_TAG") ? std::getenv("FLUID_TAG") : "");
  s.dump(name);
  char res[200];
  std::snprintf(res, sizeof res,
                "R0/dx = %d (half disc start), quintic h = dx, Oh = 0.18, equal densities, p_b = 100 Pa, t = %.0f ms", rdx,
                1e3 * T);
  char cs[64];
  std::snprintf(cs, sizeof cs, "fluid_sessile_droplet_%.0f", thetaDeg);
  test::recordValidation({cs, "contact angle (degrees), circle fit above 2 dx", th, thetaDeg,
                          std::abs(th - thetaDeg) / thetaDeg, res, wall, "|error| < 5 degrees",
                          "prescribed wall angle, colour cos(theta) (Eq. 1.10)"});
  return th;
}

}  // namespace

TEST(FluidSessile, ContactAngle90) { EXPECT_NEAR(runCase(90.0, 0.06), 90.0, 5.0); }
TEST(FluidSessile, ContactAngle60) { EXPECT_NEAR(runCase(60.0, 0.06), 60.0, 5.0); }
TEST(FluidSessile, ContactAngle120) { EXPECT_NEAR(runCase(120.0, 0.06), 120.0, 5.0); }

// The thesis' own wetting model taken literally (issue 14 "The thesis' colour model (1.10) either
// reaches the angle (fix it) or is documented with its measured failure as a validation row"):
// `wetting: colour` puts the wall colour cos(theta) into the colour-gradient sum of Eq. 5.7 and
// nothing else. Same scene, start and time as the tests above (half disc, Oh 0.18, 60 ms). The
// model does not reach the angle (the wall colour only tilts the normal of the first rows by a
// fraction of what the prescribed angle needs; docs/fluid.md, "Validation"). Recorded as a
// validation row with the 5 degrees NOT met; asserted: the reading within 5 degrees of the
// measured one (a regression bound on the documented failure) and more than 5 degrees from the
// prescribed angle (if the model is fixed, the row and the docs must change). Measured (R0/dx 10,
// ~9 s CPU per angle): 69.66 / 107.35 at 60 ms; run on (probe FLUID_COLOUR_TEND=0.18) the
// 60-degree drop stays at 66-71 to 180 ms and the 120-degree one swings between 103 and 120.
namespace {
// Measured with this test (R0/dx 10, 60 ms): see docs/fluid.md.
constexpr double kColour60 = 69.66, kColour120 = 107.35;
double runColourModel(double thetaDeg) {
  test::Stopwatch clock;
  Sessile s(thetaDeg, 1.5e-3, 10, ", wetting: colour");
  // Probe hook: FLUID_COLOUR_TEND runs longer and records nothing.
  const char* probe = std::getenv("FLUID_COLOUR_TEND");
  const double tEnd = probe ? std::atof(probe) : 0.06;
  double rc = 0, yc = 0;
  int np = 0;
  for (double t = 0.015; t <= tEnd * (1 + 1e-9); t += 0.015) {
    s.stepper.runTo(s.sim, t);
    std::printf("literal colour model, prescribed %.0f: t = %.0f ms, %.2f deg\n", thetaDeg, 1e3 * t, s.contactAngle(rc, yc, np));
  }
  s.sim.checkFinite();
  const double th = s.contactAngle(rc, yc, np);
  const double wall = clock.seconds();
  std::printf("literal colour model (Eq. 1.10), prescribed %.0f: measured %.2f deg (%d points), %lld steps, %.1f s\n",
              thetaDeg, th, np, static_cast<long long>(s.sim.step), wall);
  if (probe) return th;
  char cs[64];
  std::snprintf(cs, sizeof cs, "fluid_sessile_droplet_colour_model_%.0f", thetaDeg);
  test::recordValidation({cs, "contact angle (degrees), circle fit above 2 dx, thesis' colour model taken literally", th,
                          thetaDeg, std::abs(th - thetaDeg) / thetaDeg,
                          "R0/dx = 10 (half disc start), quintic h = dx, Oh = 0.18, equal densities, p_b = 100 Pa, "
                          "t = 60 ms, wetting: colour",
                          wall, "issue 14: 5 degrees NOT met (documented failure; regression bound 5 degrees about it)",
                          "prescribed wall angle; wall colour cos(theta) in the sum of Eq. 5.7 (Eq. 1.10 literal)"});
  return th;
}
}  // namespace

TEST(FluidSessile, LiteralColourModelMissesTheAngle) {
  const double m60 = runColourModel(60.0), m120 = runColourModel(120.0);
  EXPECT_NEAR(m60, kColour60, 5.0);
  EXPECT_NEAR(m120, kColour120, 5.0);
  EXPECT_GT(std::abs(m60 - 60.0), 5.0);  // the documented failure: fixed, the row and docs must change
  EXPECT_GT(std::abs(m120 - 120.0), 5.0);
}
