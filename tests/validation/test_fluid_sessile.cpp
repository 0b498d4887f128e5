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
  Sessile(double thetaDeg, double radius, int rOverDx) {
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
    const char* extra = std::getenv("FLUID_EXTRA") ? std::getenv("FLUID_EXTRA") : "";
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
