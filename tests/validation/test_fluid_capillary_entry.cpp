// Validation: capillary entry (issue 5, item 6). A periodic 2D channel of height H with a slit of
// width w (walls of contact angle theta, Eq. 1.10 with the prescribed contact-line normal).
// Gas fills the wide channel just before the slit, water the rest. A uniform body force f along x
// (equal densities: a pressure rise rho f Lx around the loop) must beat the difference of the
// Young-Laplace pressures of the slit and the wide channel:
//   rho f* Lx = 2 gamma cos(theta) (1/w - 1/H).
// Below f* the gas stays at the slit entrance, above it the gas enters.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
namespace fs = poresph::fluidsetup;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Entry {
  Simulation sim{2};
  FluidModule* fluid = nullptr;
  fs::Stepper stepper;
  double dx = 1e-4, H = 3e-3, w = 1e-3, Lx = 8e-3, xs = 4e-3, Ls = 3e-3;
  double gamma = 0.05, mu = 0.01, rho = 1000.0, c = 2.0, pb = 100.0, thetaDeg = 60.0;
  int gas = 1;
  static double env(const char* n, double d) { return std::getenv(n) ? std::atof(std::getenv(n)) : d; }
  double threshold() const {
    return 2.0 * gamma * std::cos(thetaDeg * kPi / 180.0) * (1.0 / w - 1.0 / H) / (rho * Lx);
  }
  explicit Entry(double forceRatio) {
    mu = env("FLUID_MU", mu);
    thetaDeg = env("FLUID_THETA", thetaDeg);  // manual studies of other angles (issue 14)
    dx = env("FLUID_DX", dx);  // manual resolution studies: same geometry, w = 1 mm / dx (issue 14)
    sim.spacing = dx;
    sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
    const double t = 3 * dx;
    sim.domain.lo = {0, -t, 0};
    sim.domain.hi = {Lx, H + t, 0};
    sim.domain.periodic = {true, false, false};
    char buf[300];
    std::snprintf(buf, sizeof buf, "{density: %g, sound_speed: %g, viscosity: %g, colour: 1, background_pressure: %g}", rho, c, mu, pb);
    const int water = fs::addMaterial(sim, "water", "fluid", buf);
    std::snprintf(buf, sizeof buf, "{density: %g, sound_speed: %g, viscosity: %g, colour: -1, background_pressure: %g}", rho, c, mu, pb);
    gas = fs::addMaterial(sim, "gas", "fluid", buf);
    std::snprintf(buf, sizeof buf, "{density: 1000, contact_angle: %g}", thetaDeg);
    const int wall = fs::addMaterial(sim, "wall", "wall", buf);
    // FLUID_EXTRA: extra fluid keys (", key: value") for manual studies (issue 14)
    std::snprintf(buf, sizeof buf, "{surface_tension: %g, gravity: [%.9g, 0]%s}", gamma, forceRatio * threshold(),
                  std::getenv("FLUID_EXTRA") ? std::getenv("FLUID_EXTRA") : "");
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
  double wall = 0;
  long long steps = 0;
};

EntryResult runEntry(double ratio, double tEnd) {
  test::Stopwatch clock;
  ratio = Entry::env("FLUID_RATIO", ratio);  // manual studies of the threshold (issue 14)
  Entry e(ratio);
  const double T = Entry::env("FLUID_TEND", tEnd);
  EntryResult r;
  for (int k = 1; k <= 8; ++k) {
    e.stepper.runTo(e.sim, T * k / 8);
    const double f = e.front();
    if (k == 4) r.frontHalf = f / e.w;
    std::printf("f/f* = %.2f: t = %.4f s, gas front %.3e m past the entrance (w = %.1e), max var %.3g\n", ratio,
                e.sim.time, f, e.w, e.fluid->maxDensityVariation());
  }
  r.frontEnd = e.front() / e.w;
  r.wall = clock.seconds();
  r.steps = e.sim.step;
  char name[64];
  std::snprintf(name, sizeof name, "fluid_capillary_entry_%.2f.txt", ratio);
  e.dump(name);
  return r;
}

// Records of FLUID_DX studies go beside the default ones, not over them (kRes names dx = 0.1 mm).
std::string recordDir() {
  return std::getenv("FLUID_DX") ? std::string(PORESPH_BINARY_DIR) + "/validation-records-explore" : std::string();
}

const char* kRes = "dx = 0.1 mm: slit w = 10 dx, channel H = 30 dx, loop Lx = 80 dx, slit length 30 dx, theta = 60 deg, "
                   "quintic h = dx, mu = 0.01 Pa s, equal densities, p_b = 100 Pa, t = 80 ms";

}  // namespace

// Below the Young-Laplace threshold (f = 0.9 f*) the meniscus bulges into the slit entrance and
// stops; above it (f = 1.1 f*) the gas front keeps advancing: the threshold is within 10 %.
TEST(FluidCapillaryEntry, GasStaysOutBelowThreshold) {
  const double ratio = Entry::env("FLUID_RATIO", 0.9);
  const EntryResult r = runEntry(ratio, 0.08);
  char q[120];
  std::snprintf(q, sizeof q, "gas front past the slit entrance / w at f = %.2f f* (stays out)", ratio);
  std::printf("%.2f f*: front %.3f w at T/2, %.3f w at T, %lld steps, %.1f s\n", ratio, r.frontHalf, r.frontEnd, r.steps, r.wall);
  EXPECT_LT(r.frontEnd, 0.5);                  // the meniscus cap stays near the entrance
  EXPECT_LT(r.frontEnd - r.frontHalf, 0.1);    // and does not advance
  test::recordValidation({"fluid_capillary_entry_2d", q,
                          r.frontEnd, 0.0, r.frontEnd, kRes, r.wall, "< 0.5 w and advance over the second half < 0.1 w",
                          "Young-Laplace entry 2 gamma cos(theta) / w (minus the wide channel's)"},
                         recordDir());
}

TEST(FluidCapillaryEntry, GasEntersAboveThreshold) {
  const double ratio = Entry::env("FLUID_RATIO", 1.1);
  const EntryResult r = runEntry(ratio, 0.08);
  char q[120];
  std::snprintf(q, sizeof q, "gas front past the slit entrance / w at f = %.2f f* (enters)", ratio);
  std::printf("%.2f f*: front %.3f w at T/2, %.3f w at T, %lld steps, %.1f s\n", ratio, r.frontHalf, r.frontEnd, r.steps, r.wall);
  EXPECT_GT(r.frontEnd, 0.6);
  EXPECT_GT(r.frontEnd - r.frontHalf, 0.15);  // still advancing
  test::recordValidation({"fluid_capillary_entry_2d", q,
                          r.frontEnd, 0.0, r.frontEnd, kRes, r.wall, "> 0.6 w and advance over the second half > 0.15 w",
                          "Young-Laplace entry 2 gamma cos(theta) / w (minus the wide channel's)"},
                         recordDir());
}
