// Validation: capillary rise between two parallel plates (Jurin's law, issue 14 "Wetting on real
// walls"). 2D, periodic along x: a water reservoir (colour +1) below a lighter fluid (colour -1),
// gravity along -y, two vertical plates of contact angle theta (Eq. 1.10) dipping into the
// reservoir with a slit of width w between them. Young-Laplace (Eq. 1.5) across the meniscus of
// the slit, a circular arc of radius w / (2 cos theta), lifts the column until its weight balances
// the two contact lines' pull:
//   (rho_l - rho_g) g A = 2 gamma cos(theta)  per unit depth,  h = A / w = 2 gamma cos(theta) / (drho g w),
// A the liquid area in the slit above the flat reservoir level. In this form (the mean height of
// the column, meniscus included) the balance is exact at any Bond number; the height of the
// meniscus bottom is lower by the meniscus area / w, w (1/(2 cos t) - (pi/2 - t) / (4 cos^2 t) -
// tan(t) / 4) for a circular arc (t = theta), reported beside it.
// The plates' outer faces and lower ends are walls of 90 degrees (a separate material, 3 dx deep),
// so the reservoir stays flat and its level is read far from the plates.
// The run starts with a flat level everywhere (slit included), not from the answer.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"
#include "tests/support/validation_record.hpp"


namespace poresph::capillary_rise {
namespace fs = poresph::fluidsetup;

constexpr double kPi = 3.14159265358979323846;
inline double env(const char* n, double d) { return std::getenv(n) ? std::atof(std::getenv(n)) : d; }

struct Rise {
  Simulation sim{2};
  FluidModule* fluid = nullptr;
  fs::Stepper stepper;
  // geometry in units of dx
  double dx = 1e-4;
  int nw = 10, nPlate = 6, nRes = 24, nFloorGap = 4, nLevel = 14, nPlateTop = 42, nTop = 47;
  double gamma = 0.05, rhoL = 1000.0, rhoG = 500.0, muL = 0.01, muG = 0.01, c = 3.0, pb = 200.0;
  double thetaDeg = 60.0, g = 100.0;  // Jurin: 10 dx at 60 degrees, 17.3 dx at 30
  int water = 0, gas = 1;
  double Lx = 0, xs0 = 0, xs1 = 0;  // slit [xs0, xs1)

  double jurin() const { return 2.0 * gamma * std::cos(thetaDeg * kPi / 180.0) / ((rhoL - rhoG) * g * w()); }
  double w() const { return nw * dx; }

  Rise(double theta, const std::string& extra) {
    thetaDeg = theta;
    muL = env("RISE_MU", muL);
    muG = env("RISE_MUG", muL);
    rhoG = env("RISE_RHOG", rhoG);
    g = env("RISE_G", g);
    c = env("RISE_C", c);
    sim.spacing = dx;
    sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
    const int nx = nw + 2 * nPlate + nRes;
    Lx = nx * dx;
    xs0 = (nRes / 2 + nPlate) * dx;
    xs1 = xs0 + w();
    const double t = 3 * dx, H = nTop * dx;
    sim.domain.lo = {0, -t, 0};
    sim.domain.hi = {Lx, H + t, 0};
    sim.domain.periodic = {true, false, false};
    char buf[300];
    std::snprintf(buf, sizeof buf, "{density: %g, sound_speed: %g, viscosity: %g, colour: 1, background_pressure: %g}", rhoL, c, muL, pb);
    water = fs::addMaterial(sim, "water", "fluid", buf);
    std::snprintf(buf, sizeof buf, "{density: %g, sound_speed: %g, viscosity: %g, colour: -1, background_pressure: %g}", rhoG, c, muG, pb);
    gas = fs::addMaterial(sim, "gas", "fluid", buf);
    std::snprintf(buf, sizeof buf, "{density: 1000, contact_angle: %g}", thetaDeg);
    const int plate = fs::addMaterial(sim, "plate", "wall", buf);
    const int neutral = fs::addMaterial(sim, "neutral", "wall", "{density: 1000, contact_angle: 90}");
    std::string sec = "{surface_tension: " + std::to_string(gamma) + ", gravity: [0, " + std::to_string(-g) +
                      "], hydrostatic_level: " + std::to_string(H) + extra + "}";
    fluid = fs::addFluidModule(sim, sec);
    const double y0 = nFloorGap * dx, y1 = nPlateTop * dx, lvl = nLevel * dx, d3 = 3 * dx;
    const double a0 = xs0 - nPlate * dx, b1 = xs1 + nPlate * dx;
    auto inPlate = [=](const double* x) { return x[1] > y0 && x[1] < y1 && ((x[0] > a0 && x[0] < xs0) || (x[0] > xs1 && x[0] < b1)); };
    // theta on the slit faces (3 dx deep, the quintic support), 90 degrees on the outer faces and the lower ends
    auto inPlateInner = [=](const double* x) {
      return inPlate(x) && x[1] > y0 + d3 && ((x[0] > xs0 - d3 && x[0] < xs0) || (x[0] > xs1 && x[0] < xs1 + d3));
    };
    fs::addLattice(sim, {0, 0}, {Lx, H}, water, [=](const double* x) { return !inPlate(x) && x[1] < lvl; });
    fs::addLattice(sim, {0, 0}, {Lx, H}, gas, [=](const double* x) { return !inPlate(x) && x[1] >= lvl; });
    fs::addLattice(sim, {0, 0}, {Lx, H}, plate, inPlateInner);
    fs::addLattice(sim, {0, 0}, {Lx, H}, neutral, [=](const double* x) { return inPlate(x) && !inPlateInner(x); });
    fs::addLattice(sim, {0, -t}, {Lx, 0}, neutral);
    fs::addLattice(sim, {0, H}, {Lx, H + t}, neutral);
    fluid->initialise(sim);
  }
  // Liquid area (sum of m / rho) in the x-range [a, b) over its width: the level of that strip.
  double level(double a, double b) const {
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const double* m = st.data(st.mass());
    const double* r = st.data(st.density());
    const std::int32_t* mt = st.data(st.material());
    double A = 0;
    for (Index i = 0; i < st.realCount(); ++i)
      if (mt[i] == water && x[2 * i] >= a && x[2 * i] < b) A += m[i] / r[i];
    return A / (b - a);
  }
  double reservoirLevel() const { return level(0.0, 8 * dx) * 0.5 + level(Lx - 8 * dx, Lx) * 0.5; }
  /// mean rise of the column in the slit above the reservoir's level
  double meanRise() const { return level(xs0, xs1) - reservoirLevel(); }
  /// meniscus bottom: midway between the highest liquid and lowest gas particle of the slit's
  /// two central columns (above the plates' lower end), minus the reservoir level
  double bottomRise() const {
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const std::int32_t* mt = st.data(st.material());
    const double xc = 0.5 * (xs0 + xs1);
    double top = -1e300, low = 1e300;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (std::abs(x[2 * i] - xc) > dx || x[2 * i + 1] < nFloorGap * dx) continue;
      if (mt[i] == water) top = std::max(top, x[2 * i + 1]);
      if (mt[i] == gas) low = std::min(low, x[2 * i + 1]);
    }
    return 0.5 * (top + low) - reservoirLevel();
  }
  double maxSpeed() const {
    const auto& st = sim.store;
    const double* v = st.data(st.velocity());
    const std::int32_t* mt = st.data(st.material());
    double s = 0;
    for (Index i = 0; i < st.realCount(); ++i)
      if (mt[i] == water || mt[i] == gas) s = std::max(s, std::hypot(v[2 * i], v[2 * i + 1]));
    return s;
  }
  void dump(const std::string& name) const {
    const auto& st = sim.store;
    std::ofstream f(std::string(PORESPH_BINARY_DIR) + "/" + name);
    const double* x = st.data(st.position());
    const std::int32_t* mt = st.data(st.material());
    for (Index i = 0; i < st.realCount(); ++i)
      f << x[2 * i] << " " << x[2 * i + 1] << " " << (mt[i] == water ? 1 : mt[i] == gas ? -1 : 0.5) << "\n";
  }
};

/// circular-arc meniscus: area between the arc and the horizontal through its bottom, over w
inline double meniscusCorrection(double w, double thetaDeg) {
  const double t = thetaDeg * kPi / 180.0, ct = std::cos(t);
  if (ct < 1e-9) return 0.0;
  const double R = w / (2 * ct);
  // area above the bottom within the slit = w * (R - R sin t) ... minus the circular segment
  const double sag = R - R * std::sin(t);           // height of the contact line above the bottom
  const double segment = R * R * (kPi / 2 - t) - 0.5 * w * R * std::sin(t);  // segment below the chord
  return (w * sag - segment) / w;
}

struct RiseResult {
  double mean = 0, meanPrev = 0, bottom = 0, jurin = 0, wall = 0, cpu = 0, maxSpeed = 0, dx = 0;
  long long steps = 0;
  int particles = 0;
};

// Runs to tEnd, printing the mean rise 20 times; meanPrev is the mean rise at 0.8 tEnd (the
// settling reading: the change over the last 20 % of the run).
inline RiseResult runRise(double theta, const std::string& extra, double tEnd, const std::string& tag) {
  test::Stopwatch clock;
  const std::clock_t c0 = std::clock();
  Rise r(theta, extra);
  const double T = env("RISE_TEND", tEnd);
  RiseResult out;
  out.jurin = r.jurin();
  out.dx = r.dx;
  const int K = 20;
  for (int k = 1; k <= K; ++k) {
    r.stepper.runTo(r.sim, T * k / K);
    const double m = r.meanRise();
    if (k == K - 4) out.meanPrev = m;
    std::printf("theta %.0f%s: t = %.4f s  mean rise %.3f dx (%.4f of Jurin), bottom %.3f dx, max speed %.3g, max var %.3g\n",
                theta, tag.c_str(), r.sim.time, m / r.dx, m / out.jurin, r.bottomRise() / r.dx, r.maxSpeed(),
                r.fluid->maxDensityVariation());
    std::fflush(stdout);
  }
  out.mean = r.meanRise();
  out.bottom = r.bottomRise();
  out.maxSpeed = r.maxSpeed();
  out.wall = clock.seconds();
  out.cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  out.steps = r.sim.step;
  out.particles = static_cast<int>(r.sim.store.realCount());
  char name[80];
  std::snprintf(name, sizeof name, "fluid_capillary_rise_%.0f%s.txt", theta, tag.c_str());
  r.dump(name);
  std::printf("theta %.0f%s: Jurin %.4e m (%.2f dx); mean %.4e (%+.2f %%), at 0.8 T %.4e, meniscus bottom %.4e "
              "(circular-arc estimate %.4e), %lld steps, %d particles, %.1f s wall, %.1f s CPU\n",
              theta, tag.c_str(), out.jurin, out.jurin / r.dx, out.mean, 100 * (out.mean / out.jurin - 1), out.meanPrev,
              out.bottom, out.jurin - meniscusCorrection(r.w(), theta), out.steps, out.particles, out.wall, out.cpu);
  return out;
}

inline constexpr const char* kRes = "dx = 0.1 mm: slit w = 10 dx, plates 6 dx (3 dx at theta), reservoir 24 dx, height 47 dx, "
                   "quintic h = dx, rho 1000 / 500, mu 0.01 Pa s both, gamma 0.05 N/m, g 100 m/s^2, p_b 200 Pa";
inline constexpr const char* kGhost = ", wetting: normal, wetting_scale: 0.05, wetting_ghost: true";

}  // namespace poresph::capillary_rise
