#pragma once
// The 2D capillary-entry scene (issue 5 item 6, issue 14): a periodic channel of height H = 3 mm
// with a slit of width w = 1 mm and length 3 mm (walls of contact angle theta, Eq. 1.10 with the
// prescribed contact-line normal), a gas column of 2.5 mm ending at the slit entrance, water
// elsewhere, driven by a uniform body force f along x. Threshold (statics of the two menisci):
// f* times the loop's mass per area = 2 gamma cos(theta) (1/w - 1/H). Used by
// tests/validation/test_fluid_capillary_entry.cpp (equal densities) and
// tests/extreme/test_fluid_wetting_extreme.cpp (density ratio 1000).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"
#include "tests/support/fluid_channel_2d.hpp"
#include "tests/support/validation_record.hpp"

namespace poresph::test {

inline constexpr double kEntryPi = 3.14159265358979323846;

struct Entry {
  Simulation sim{2};
  FluidModule* fluid = nullptr;
  fluidsetup::Stepper stepper;
  double dx = 1e-4, H = 3e-3, w = 1e-3, Lx = 8e-3, xs = 4e-3, Ls = 3e-3;
  double gamma = 0.05, mu = 0.01, rho = 1000.0, c = 2.0, pb = 100.0, thetaDeg = 60.0;
  int gas = 1;
  double gasRho = 1000.0, gasC = 2.0, gasMu = 0.01;  // the gas: the water's twin unless given
  static double env(const char* n, double d) { return std::getenv(n) ? std::atof(std::getenv(n)) : d; }
  // The loop's pressure rise is the body force times the mass per area along the centreline,
  // rho f Lx at equal densities; with a lighter gas column of length Lg (2.5 mm at the start)
  // f (rho (Lx - Lg) + rho_g Lg).
  double threshold() const {
    const double loop = gasRho == rho ? rho * Lx : rho * (Lx - 2.5e-3) + gasRho * 2.5e-3;
    return 2.0 * gamma * std::cos(thetaDeg * kEntryPi / 180.0) * (1.0 / w - 1.0 / H) / loop;
  }
  /// gas: density, sound speed, viscosity of the gas (0: the water's); keys: extra fluid keys.
  explicit Entry(double forceRatio, const double* gasProps = nullptr, const std::string& keys = "") {
    mu = env("FLUID_MU", mu);
    gasRho = gasProps ? gasProps[0] : rho, gasC = gasProps ? gasProps[1] : c, gasMu = gasProps ? gasProps[2] : mu;
    thetaDeg = env("FLUID_THETA", thetaDeg);  // manual studies of other angles (issue 14)
    dx = env("FLUID_DX", dx);  // manual resolution studies: same geometry, w = 1 mm / dx (issue 14)
    namespace fs = poresph::fluidsetup;
    char buf[300];
    const test::ChannelMaterials ids =
        test::setUpChannel2D(sim, dx, Lx, H, {rho, c, mu}, {gasRho, gasC, gasMu}, pb, thetaDeg);
    const int water = ids.water;
    gas = ids.gas;
    const int wall = ids.wall;
    const double t = 3 * dx;  // the walls' thickness (setUpChannel2D)
    // FLUID_EXTRA: extra fluid keys (", key: value") for manual studies (issue 14)
    std::snprintf(buf, sizeof buf, "{surface_tension: %g, gravity: [%.9g, 0]%s%s}", gamma, forceRatio * threshold(),
                  keys.c_str(), std::getenv("FLUID_EXTRA") ? std::getenv("FLUID_EXTRA") : "");
    fluid = fs::addFluidModule(sim, buf);
    const double y0 = 0.5 * (H - w), y1 = 0.5 * (H + w);
    auto inSlitWall = [=](const double* x) { return x[0] > xs && x[0] < xs + Ls && (x[1] < y0 || x[1] > y1); };
    const double g0 = xs - 2.5e-3;  // gas column [g0, xs)
    fs::addLattice(sim, {0, 0}, {Lx, H}, gas, [=](const double* x) { return x[0] > g0 && x[0] < xs; });
    fs::addLattice(sim, {0, 0}, {Lx, H}, water,
                   [=](const double* x) { return !(x[0] > g0 && x[0] < xs) && !inSlitWall(x); });
    fs::addLattice(sim, {0, 0}, {Lx, H}, wall, inSlitWall);
    fs::addLattice(sim, {0, -t}, {Lx, 0}, wall);
    fs::addLattice(sim, {0, H}, {Lx, H + t}, wall);
    fluid->initialise(sim);
  }
  // Largest x of a gas particle inside the slit's y-range (distance past the entrance xs).
  double front() const {
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const std::int32_t* mt = st.data(st.material());
    double f = -1e300;
    for (Index i = 0; i < st.realCount(); ++i)
      if (mt[i] == gas && x[2 * i] < xs + Ls + 1e-3) f = std::max(f, x[2 * i] - xs);
    return f;
  }
  void dump(const std::string& name) const {
    const auto& st = sim.store;
    std::ofstream f(std::string(PORESPH_BINARY_DIR) + "/" + name);
    const double* x = st.data(st.position());
    const std::int32_t* mt = st.data(st.material());
    for (Index i = 0; i < st.realCount(); ++i)
      f << x[2 * i] << " " << x[2 * i + 1] << " " << (mt[i] == 0 ? 1 : mt[i] == gas ? -1 : 0.5) << "\n";
  }
};

struct EntryResult {
  double frontEnd = 0, frontHalf = 0;  // gas front past the entrance / w at T and T/2
  double wall = 0, threshold = 0, maxVar = 0;  // f* (m/s^2); largest density variation at the checks
  long long steps = 0;
};

inline EntryResult runEntry(double ratio, double tEnd, const double* gasProps = nullptr, const std::string& keys = "",
                           const char* tag = "") {
  Stopwatch clock;
  ratio = Entry::env("FLUID_RATIO", ratio);  // manual studies of the threshold (issue 14)
  Entry e(ratio, gasProps, keys);
  const double T = Entry::env("FLUID_TEND", tEnd);
  EntryResult r;
  r.threshold = e.threshold();
  for (int k = 1; k <= 8; ++k) {
    e.stepper.runTo(e.sim, T * k / 8);
    const double f = e.front();
    if (k == 4) r.frontHalf = f / e.w;
    r.maxVar = std::max(r.maxVar, e.fluid->maxDensityVariation());
    std::printf("f/f* = %.2f: t = %.4f s, gas front %.3e m past the entrance (w = %.1e), max var %.3g\n", ratio,
                e.sim.time, f, e.w, e.fluid->maxDensityVariation());
    std::fflush(stdout);
  }
  r.frontEnd = e.front() / e.w;
  r.wall = clock.seconds();
  r.steps = e.sim.step;
  char name[64];
  std::snprintf(name, sizeof name, "fluid_capillary_entry_%.2f%s.txt", ratio, tag);
  e.dump(name);
  return r;
}

}  // namespace poresph::test
