// Validation: capillary entry into a square tube in 3D (issue 14, "Drainage physics against
// closed forms" item 1). A periodic 3D cell (H x H across, Lx long) holds a wall plate of length
// Ls pierced by a square tube of side w (walls of contact angle theta, Eq. 1.10). A gas slab fills
// the whole cross-section just before the plate, water the rest; the slab's rear interface spans
// the periodic cross-section and is flat (no capillary pressure there). A uniform body force f
// along x (equal densities: a pressure rise rho f Lx around the loop, the pressure drop between
// the two reservoirs) must beat the entry pressure of the tube:
//   rho f* Lx = Pc(w, theta).
// Closed form for a square tube (Mayer-Stowe-Princen, derivation in docs/fluid.md
// "Capillary entry into a square tube in 3D"): with the force balance on the invading gas column
//   Pc A_g = gamma (L_gw + cos(theta) L_gs)        (Young-Laplace, Eq. 1.5, with Young's law)
//   theta >= 45 deg: Pc = 4 gamma cos(theta) / w  (no water left in the corners: the piston form),
//   theta <  45 deg: Pc = (2 gamma / w) (cos(theta) + sqrt(pi/4 - theta + sin(theta) cos(theta))),
// (theta = 0: (gamma / (w/2)) (1 + sqrt(pi)/2)); the circular-tube estimate 4 gamma cos(theta) / w
// (tube diameter w) is reported beside it.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"
#include "tests/support/validation_record.hpp"

namespace poresph::entry3d {
namespace fs = poresph::fluidsetup;

constexpr double kPi = 3.14159265358979323846;
/// The wetting setting validated for 30-150 degrees on flat walls (test::kWettingGhostSettings of
/// fluid_wetting_case.hpp, same text).
inline constexpr const char* kGhost = ", wetting: normal, wetting_scale: 0.05, wetting_ghost: true";
inline double env(const char* n, double d) { return std::getenv(n) ? std::atof(std::getenv(n)) : d; }

/// Mayer-Stowe-Princen entry pressure of a square tube of side w (units of gamma / w).
inline double mspSquare(double thetaDeg) {
  const double t = thetaDeg * kPi / 180.0;
  if (thetaDeg >= 45.0) return 4.0 * std::cos(t);
  return 2.0 * (std::cos(t) + std::sqrt(kPi / 4.0 - t + std::sin(t) * std::cos(t)));
}
/// Circular-tube estimate (diameter w), units of gamma / w.
inline double circularTube(double thetaDeg) { return 4.0 * std::cos(thetaDeg * kPi / 180.0); }

struct Entry3D {
  Simulation sim{3};
  FluidModule* fluid = nullptr;
  fs::Stepper stepper;
  // lengths in units of dx: tube side nw, cell nH across, plate nLs long, gas slab nGas, cell nLx
  double dx = 1e-4;
  int nw = 6, nH = 10, nLs = 12, nGas = 8, nLx = 36, nXs = 16;
  double gamma = 0.05, mu = 0.01, rho = 1000.0, c = 2.0, pb = 200.0, thetaDeg = 60.0;
  double ratio = 1.0;
  int water = 0, gas = 1, wall = 2;

  double w() const { return nw * dx; }
  double Lx() const { return nLx * dx; }
  double xs() const { return nXs * dx; }
  double Ls() const { return nLs * dx; }
  double entryPressure() const { return mspSquare(thetaDeg) * gamma / w(); }
  /// Pressure the force ratio refers to: the entry pressure, or at 90 degrees (where it is 0) the
  /// 60-degree one, 2 gamma / w.
  double drivePressure() const { return thetaDeg > 89.999 ? 2.0 * gamma / w() : entryPressure(); }
  double threshold() const { return entryPressure() / (rho * Lx()); }

  /// ratio: f / f* (at 90 degrees: rho f Lx / (2 gamma / w)); extra: fluid keys appended to the section (", key: value").
  /// nwIn: tube side in dx (the cell is nw + 4 across, the plate 2 nw long).
  Entry3D(double thetaIn, double ratioIn, const std::string& extra, int nwIn = 6) : thetaDeg(thetaIn), ratio(ratioIn) {
    mu = env("ENTRY3D_MU", mu);
    c = env("ENTRY3D_C", c);
    pb = env("ENTRY3D_PB", pb);
    nw = static_cast<int>(env("ENTRY3D_NW", nwIn));
    nH = static_cast<int>(env("ENTRY3D_NH", nw + 4));
    nLs = static_cast<int>(env("ENTRY3D_NLS", 2 * nw));
    nGas = static_cast<int>(env("ENTRY3D_NGAS", nGas));
    nXs = 8 + nGas;
    nLx = nXs + nLs + static_cast<int>(env("ENTRY3D_NRES", 8));
    sim.spacing = dx;
    sim.kernel = Kernel(KernelType::QuinticSpline, 3, dx);
    const double H = nH * dx;
    sim.domain.lo = {0, 0, 0};
    sim.domain.hi = {Lx(), H, H};
    sim.domain.periodic = {true, true, true};
    char buf[300];
    std::snprintf(buf, sizeof buf, "{density: %g, sound_speed: %g, viscosity: %g, colour: 1, background_pressure: %g}", rho, c, mu, pb);
    water = fs::addMaterial(sim, "water", "fluid", buf);
    std::snprintf(buf, sizeof buf, "{density: %g, sound_speed: %g, viscosity: %g, colour: -1, background_pressure: %g}", rho, c, mu, pb);
    gas = fs::addMaterial(sim, "gas", "fluid", buf);
    std::snprintf(buf, sizeof buf, "{density: 1000, contact_angle: %g}", thetaDeg);
    wall = fs::addMaterial(sim, "wall", "wall", buf);
    std::snprintf(buf, sizeof buf, "{surface_tension: %g, gravity: [%.9g, 0, 0]%s}", gamma, ratio * drivePressure() / (rho * Lx()), extra.c_str());
    fluid = fs::addFluidModule(sim, buf);
    const double x0 = xs(), x1 = xs() + Ls(), lo = 0.5 * (H - w()), hi = 0.5 * (H + w());
    auto inPlate = [=](const double* x) {
      const bool inTube = x[1] > lo && x[1] < hi && x[2] > lo && x[2] < hi;
      return x[0] > x0 && x[0] < x1 && !inTube;
    };
    const double g0 = x0 - nGas * dx;
    auto inGas = [=](const double* x) { return x[0] > g0 && x[0] < x0; };
    fs::addLattice(sim, {0, 0, 0}, {Lx(), H, H}, gas, inGas);
    fs::addLattice(sim, {0, 0, 0}, {Lx(), H, H}, water, [=](const double* x) { return !inGas(x) && !inPlate(x); });
    fs::addLattice(sim, {0, 0, 0}, {Lx(), H, H}, wall, inPlate);
    fluid->initialise(sim);
  }

  /// Largest x of a gas particle in the tube or the reservoir after it, as distance past the
  /// tube's entrance (gas that has gone through the periodic loop is not counted).
  double front() const {
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const std::int32_t* mt = st.data(st.material());
    const double xMax = xs() + Ls() + 0.5 * (Lx() - xs() - Ls());
    double f = -1e300;
    for (Index i = 0; i < st.realCount(); ++i)
      if (mt[i] == gas && x[3 * i] < xMax) f = std::max(f, x[3 * i] - xs());
    return f;
  }
  /// Volume of gas inside the tube (x in [xs, xs + Ls)) over the tube's cross-section w^2, in w.
  double gasLengthInTube() const {
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const std::int32_t* mt = st.data(st.material());
    Index n = 0;
    for (Index i = 0; i < st.realCount(); ++i)
      if (mt[i] == gas && x[3 * i] >= xs() && x[3 * i] < xs() + Ls()) ++n;
    return n * dx * dx * dx / (w() * w()) / w();
  }
  /// x y z code (1 water, -1 gas, 0.5 wall) per particle, for pictures.
  void dump(const std::string& path) const {
    const auto& st = sim.store;
    std::ofstream f(path);
    const double* x = st.data(st.position());
    const std::int32_t* mt = st.data(st.material());
    for (Index i = 0; i < st.realCount(); ++i)
      f << x[3 * i] << " " << x[3 * i + 1] << " " << x[3 * i + 2] << " "
        << (mt[i] == water ? 1 : mt[i] == gas ? -1 : 0.5) << "\n";
  }
  std::string resolution() const {
    char b[400];
    std::snprintf(b, sizeof b,
                  "dx = 0.1 mm: square tube w = %d dx, plate %d dx long, periodic cell %d x %d x %d dx (%lld particles), "
                  "theta = %g deg, quintic h = dx, mu = %g Pa s, equal densities, c = %g m/s, p_b = %g Pa",
                  nw, nLs, nLx, nH, nH, static_cast<long long>(sim.store.realCount()), thetaDeg, mu, c, pb);
    return b;
  }
};

struct EntryResult {
  double frontHalf = 0, frontEnd = 0;  // gas front past the entrance / w at T/2 and T
  double tubeHalf = 0, tubeEnd = 0;    // gas volume in the tube / w^3 at T/2 and T
  double tubeMax = 0;                  // largest of the 8 readings of it (a column that has gone
                                       // through the tube and on round the loop leaves it again)
  double maxVar = 0;
  double wall = 0;
  long long steps = 0;
  std::string resolution;
};

/// Runs f = ratio f* to tEnd and reads the front at 8 instants (printed).
inline EntryResult runEntry3D(double thetaDeg, double ratio, double tEnd, const std::string& extra,
                              const std::string& dumpPath = "", int nw = 6) {
  test::Stopwatch clock;
  Entry3D e(thetaDeg, ratio, extra, nw);
  EntryResult r;
  for (int k = 1; k <= 8; ++k) {
    e.stepper.runTo(e.sim, tEnd * k / 8);
    const double f = e.front() / e.w(), v = e.gasLengthInTube();
    r.maxVar = std::max(r.maxVar, e.fluid->maxDensityVariation());
    r.tubeMax = std::max(r.tubeMax, v);
    if (k == 4) { r.frontHalf = f; r.tubeHalf = v; }
    std::printf("theta %g, f/f* = %.2f: t = %.4f s, front %.3f w, gas in tube %.3f w, max var %.3g (%lld steps, %.0f s)\n",
                thetaDeg, ratio, e.sim.time, f, v, e.fluid->maxDensityVariation(),
                static_cast<long long>(e.sim.step), clock.seconds());
    std::fflush(stdout);
  }
  r.frontEnd = e.front() / e.w();
  r.tubeEnd = e.gasLengthInTube();
  r.wall = clock.seconds();
  r.steps = e.sim.step;
  r.resolution = e.resolution();
  if (!dumpPath.empty()) e.dump(dumpPath);
  return r;
}

}  // namespace poresph::entry3d
