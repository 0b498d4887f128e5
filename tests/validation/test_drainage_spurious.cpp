// Validation (issue 14, "Surface tension and pressure", first item, drainage side): the imposed
// flow of a drainage run against the fluid motion that capillarity alone drives in the same
// scene. The spurious-current floor of the surface tension (docs/fluid.md: mu u_max / gamma
// ~4e-3 on a droplet at R/dx 20, ~1e-2 at R/dx 10) is measured where it matters: in a small 2D
// drainage slab with the main job's fluids, surface tension, contact angle and clay (scene()
// below: one slit of 5 dx, the 2D sample's throat). Two runs of the same slab:
//   - dP = 0: every fluid speed in the slab is capillarity's (the menisci at the slit's two ends
//     relaxing, spurious currents at the lattice-cut interfaces; with gamma = 0 the slab's fluid
//     stays at rest, 4e-14 m/s);
//     sampled every 0.1 ms from 2 to 6 ms: time means of the largest and of the rms speed of the
//     slab's fluid particles;
//   - dP = 300 Pa (the samples' drop, ramped over 2 ms): v_g, the drainage module's mean gas
//     velocity in the slab along the push (drainage_gas_velocity, the imposed flow of
//     docs/drainage.md), time mean over the same samples once gas is in the slab.
// Asserted (issue 14: "the imposed flow at least 10x the measured spurious speed"): v_g over the
// floor's largest and rms speeds, each bound ~15 % below its measured value (12.7 and 50,
// measured 2026-11-27), so that a louder surface tension (or a slower imposed flow) fails. The
// main job's own ratio (3D, 5.6 / 25 as shipped, 11 / 46 at gamma = 0.0025) and the 2D sample's
// are in docs/drainage.md "Imposed flow against the capillary floor".
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
namespace fsys = std::filesystem;

namespace {

constexpr double kFrom = 0.002, kEnd = 0.006, kEvery = 1e-4;  // s
constexpr double kSampleLo = 0.001, kSampleHi = 0.005;        // the slab along y
constexpr double kGamma = 0.005;                              // N/m, the samples'

struct Speeds {
  double maxMean = 0.0, rmsMean = 0.0, maxPeak = 0.0;  // slab fluid, m/s
  double vgMean = 0.0, gasSaturation = 0.0;            // drainage columns
  int samples = 0, gasSamples = 0;
  long steps = 0;
  long long particles = 0;
  double wall = 0.0;
};

double column(const Simulation& sim, const std::string& name) {
  for (const auto& [k, v] : sim.diagnostics())
    if (k == name) return v;
  ADD_FAILURE() << "no column " << name;
  return NAN;
}

// The slab: clay 16 x 40 dx (E = 1.2e5 Pa, nu 0.1 as the samples, no damage), crossed along y by
// one slit of w = 5 dx (the 2D sample's throat), water in the slit, gas reservoirs of 10 and 5 dx
// on the two ends of the periodic axis; the main job's fluids (density 1000, c 5 m/s, mu 0.01 /
// 0.001 Pa s), gamma = 0.005 N/m, contact angle 60, p_b 600 Pa as a gauge, the pressure drop
// ramped over 2 ms. The clay is clamped over 3 rows at the outlet face (the gas is pushed towards
// -y) instead of the samples' plates: the plates' 2-ms confinement ramp alone moves the 2D
// sample's throat water at up to 0.15 m/s (docs/drainage.md), which would hide capillarity's
// share.
std::string scene(double pressureDrop, double gamma) {
  char text[4096];
  std::snprintf(text, sizeof text, R"(dimension: 2
domain: {lo: [-0.0003, 0.0], hi: [0.0019, 0.0055], periodic: [false, true]}
spacing: 1.0e-4
h_over_dx: 1.0
kernel: quintic_spline
integrator: leapfrog
end_time: %g
time_step: {adaptive: true, cfl: 1.0}
output: {every_time: 0.01}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 5, viscosity: 0.01, colour: 1, background_pressure: 600}
  - {name: gas, model: fluid, density: 1000, sound_speed: 5, viscosity: 0.001, colour: -1, background_pressure: 600}
  - {name: wall, model: wall, density: 1000, contact_angle: 60}
  - {name: clay, model: elastic, density: 2000, young_modulus: 1.2e5, poisson_ratio: 0.1, formulation: total_lagrangian, hourglass: 1, damping: 200, contact_angle: 60}
geometry:
  - {shape: box, lo: [-0.0003, 0.0], hi: [0.0019, 0.0055], material: wall}
  - {shape: box, lo: [0.0, 0.0], hi: [0.0016, 0.0055], material: gas}
  - {shape: box, lo: [0.0, 0.001], hi: [0.0016, 0.005], material: clay}
  - {shape: box, lo: [0.00055, 0.001], hi: [0.00105, 0.005], material: water}
fluid:
  surface_tension: %g
  pressure_reference: background
drainage: {invading: gas, defending: water, axis: y, sample: [0.001, 0.005], pressure_drop: %g, ramp_time: 0.002}
solid:
  boundaries:
    - {name: outlet, type: clamped, box: {min: [0.0, 0.001], max: [0.0016, 0.0013]}, material: clay}
)",
                kEnd, gamma, pressureDrop);
  return text;
}

Speeds run(double pressureDrop, double gamma = kGamma) {
  const std::string text = scene(pressureDrop, gamma);
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-drainage-spurious";
  fsys::create_directories(dir);
  char name[64];
  std::snprintf(name, sizeof name, "dp_%g_gamma_%g.yaml", pressureDrop, gamma);
  test::Stopwatch clock;
  Scene scene = loadSceneText(text, (dir / name).string());
  Simulation& sim = *scene.sim;
  auto integrator = makeIntegrator(scene.integrator);
  Speeds s;
  double next = kFrom, sumVg = 0.0;
  while (!scene.finished()) {
    integrator->step(sim, scene.nextTimeStep());
    sim.checkFinite();
    if (sim.time < next - 1e-9) continue;
    next += kEvery;
    const ParticleStore& st = sim.store;
    const double* x = st.data(st.position());
    const double* v = st.data(st.velocity());
    const std::int32_t* ph = st.data(st.phase());
    double vmax = 0.0, v2 = 0.0;
    long count = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (ph[i] != kPhaseFluid || x[2 * i + 1] < kSampleLo || x[2 * i + 1] > kSampleHi) continue;
      const double q = v[2 * i] * v[2 * i] + v[2 * i + 1] * v[2 * i + 1];
      vmax = std::max(vmax, q);
      v2 += q;
      ++count;
    }
    EXPECT_GT(count, 0);
    if (count == 0) continue;
    s.maxMean += std::sqrt(vmax);
    s.rmsMean += std::sqrt(v2 / count);
    s.maxPeak = std::max(s.maxPeak, std::sqrt(vmax));
    ++s.samples;
    const double sg = column(sim, "drainage_gas_saturation");
    if (sg > 0.0) {
      sumVg += column(sim, "drainage_gas_velocity");
      ++s.gasSamples;
    }
    s.gasSaturation = sg;
  }
  s.maxMean /= std::max(1, s.samples);
  s.rmsMean /= std::max(1, s.samples);
  s.vgMean = s.gasSamples > 0 ? sumVg / s.gasSamples : 0.0;
  s.steps = static_cast<long>(sim.step);
  s.particles = static_cast<long long>(sim.store.realCount());
  s.wall = clock.seconds();
  std::printf("dP = %g Pa: %lld particles, %ld steps, %d samples: slab fluid speed max %.4e (peak "
              "%.4e), rms %.4e m/s; v_g %.4e m/s over %d samples with gas, S_g %.4f at %g ms; %.1f s\n",
              pressureDrop, s.particles, s.steps, s.samples, s.maxMean, s.maxPeak, s.rmsMean,
              s.vgMean, s.gasSamples, s.gasSaturation, 1e3 * sim.time, s.wall);
  std::fflush(stdout);
  return s;
}

}  // namespace

// Measured ratios 50 (rms) and 12.7 (largest), 2026-11-27: bounds ~14 % below them.
constexpr double kBoundRms = 43.0, kBoundMax = 11.0;

TEST(DrainageSpurious, ImposedFlowAgainstTheCapillaryFloor2D) {
  const Speeds floor = run(0.0);
  const Speeds imposed = run(300.0);
  ASSERT_GT(floor.samples, 30);
  ASSERT_GT(imposed.gasSamples, 20) << "the gas did not enter the slab";
  const double overRms = imposed.vgMean / floor.rmsMean;
  const double overMax = imposed.vgMean / floor.maxMean;
  std::printf("v_g / rms floor %.2f, v_g / max floor %.2f\n", overRms, overMax);
  EXPECT_GT(overRms, kBoundRms);
  EXPECT_GT(overMax, kBoundMax);

  const std::string res = "2D slab 16 x 40 dx, slit 5 dx, dx = 0.1 mm, " +
                          std::to_string(imposed.particles) + " particles, quintic h = dx, 2-6 ms";
  test::ValidationRecord rec;
  rec.caseName = "drainage_spurious_floor_2d";
  rec.resolution = res;
  rec.wallSeconds = floor.wall + imposed.wall;
  rec.reference = NAN;
  rec.reference_source = "issue 14: imposed flow >= 10 x the spurious speed";
  char tol[64];
  rec.quantity = "imposed v_g / rms fluid speed at dP = 0 (capillarity alone)";
  rec.measured = overRms;
  std::snprintf(tol, sizeof tol, "> %.1f", kBoundRms);
  rec.tolerance = tol;
  test::recordValidation(rec);
  rec.quantity = "imposed v_g / largest fluid speed at dP = 0 (capillarity alone)";
  rec.measured = overMax;
  std::snprintf(tol, sizeof tol, "> %.1f", kBoundMax);
  rec.tolerance = tol;
  test::recordValidation(rec);
}

// Probe (skipped unless DRAIN_SPUR=1): the ratios at another gamma / pressure drop
// (DRAIN_SPUR_GAMMA, DRAIN_SPUR_DP), for choosing a scaling.
TEST(DrainageSpurious, Probe) {
  if (!std::getenv("DRAIN_SPUR")) GTEST_SKIP() << "set DRAIN_SPUR=1";
  const double gamma = std::getenv("DRAIN_SPUR_GAMMA") ? std::atof(std::getenv("DRAIN_SPUR_GAMMA")) : kGamma;
  const double dP = std::getenv("DRAIN_SPUR_DP") ? std::atof(std::getenv("DRAIN_SPUR_DP")) : 300.0;
  const Speeds floor = run(0.0, gamma);
  const Speeds imposed = run(dP, gamma);
  std::printf("gamma %g, dP %g: v_g / rms floor %.2f, v_g / max floor %.2f\n", gamma, dP,
              imposed.vgMean / floor.rmsMean, imposed.vgMean / floor.maxMean);
}
