// Validation 3 of issue 4: the tensile-instability bar of thesis Sec. 2.6 (Table 2.3): 40 points,
// E = 200 GPa, rho = 7833, L = 0.1333 m, dt = 1e-7 s, v0 = -5 m/s on the left quarter, free left
// end, clamped right end (mirror/ghost layers). For each of the three formulations the run must
// stay stable (bounded, finite) over three periods, and the free-end displacement must follow
// the d'Alembert solution of the 1D wave equation within 5 % (RMS over the first period,
// relative to the amplitude v0 L / (4 c)), with the XSPH and artificial viscosity of Sec. 2.6.3.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "physics/solid/solid_scenes.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
using namespace poresph::solid;

namespace {

constexpr double E = 200e9, rho = 7833.0, L = 0.1333, v0 = -5.0;
constexpr int kPoints = 40;
// Table 2.3 does not give h; h = dx (support 2 dx) is the value used here (docs/solid.md lists the
// sweep h/dx = 1.0 ... 2.0). XSPH and artificial viscosity as in Sec. 2.6.3.
constexpr double kHOverDx = 1.0;
const std::string kImprovements =
    ", xsph_epsilon: 0.5, artificial_viscosity: {alpha: 0.2, beta: 0.4}";

// d'Alembert: u(x, t) = (1/2c) int_{x-ct}^{x+ct} psi_ext(s) ds with psi extended evenly about the
// free end x = 0 and oddly about the clamped end x = L (period 4L).
double psiExt(double s) {
  s = std::fmod(std::abs(s), 4.0 * L);
  if (s > 2.0 * L) s = 4.0 * L - s;
  auto psi = [](double x) { return x < 0.25 * L ? v0 : 0.0; };
  return s <= L ? psi(s) : -psi(2.0 * L - s);
}
double exactDisplacement(double x, double t) {
  const double c = std::sqrt(E / rho);
  const int n = 8000;
  const double a = x - c * t, ds = 2.0 * c * t / n;
  double sum = 0.0;
  for (int k = 0; k < n; ++k) sum += psiExt(a + (k + 0.5) * ds) * ds;
  return sum / (2.0 * c);
}

struct Result {
  double rmsError = 0.0;   // over the first period, relative to the amplitude
  double maxError = 0.0;
  double maxDisplacement = 0.0;  // over the whole run
  double wall = 0.0;
  bool finite = true;
};

Result run(const std::string& formulation, double periods, const std::string& extra) {
  test::Stopwatch clock;
  Simulation sim(1);
  addMaterial(sim, "steel", "elastic",
              "{density: 7833, young_modulus: 2.0e11, formulation: " + formulation + extra + "}");
  const double dx = L / kPoints;
  sim.kernel = Kernel(KernelType::CubicSpline, 1, kHOverDx * dx);
  const int layers = 2 * static_cast<int>(std::ceil(sim.kernel.support() / dx)) + 1;
  buildBar(sim, kPoints, L, 0, layers);
  ElasticSolidModule& solid = addSolidModule(
      sim, "{boundaries: [{name: clamp, type: clamped, box: {min: [" + std::to_string(L) +
               "], max: [1]}, mirror: {point: [" + std::to_string(L) + "], normal: [1]}}]}");
  solid.initialise(sim);
  double* v = sim.store.data(sim.store.velocity());
  const double* x = sim.store.data(sim.store.position());
  const std::int32_t* ids = sim.store.data(sim.store.id());
  std::int32_t probe = -1;
  for (Index i = 0; i < sim.store.realCount(); ++i) {
    if (x[i] < 0.25 * L) v[i] = v0;
    if (std::abs(x[i] - 0.5 * dx) < 1e-3 * dx) probe = ids[i];
  }
  auto integrator = makeIntegrator("leapfrog");
  const double c = std::sqrt(E / rho), T = 4.0 * L / c, dt = 1e-7;
  const double amplitude = std::abs(v0) * L / (4.0 * c);
  const long steps = static_cast<long>(periods * T / dt);
  Result r;
  double sq = 0.0;
  long count = 0;
  try {
    for (long k = 0; k < steps; ++k) {
      integrator->step(sim, dt);
      sim.checkFinite();
      const std::int32_t* id = sim.store.data(sim.store.id());
      const double* u = sim.store.data(sim.store.real("displacement"));
      for (Index i = 0; i < sim.store.realCount(); ++i) {
        if (id[i] != probe) continue;
        r.maxDisplacement = std::max(r.maxDisplacement, std::abs(u[i]));
        if (sim.time <= T) {
          const double e = u[i] - exactDisplacement(0.5 * dx, sim.time);
          sq += e * e;
          ++count;
          r.maxError = std::max(r.maxError, std::abs(e) / amplitude);
        }
      }
    }
  } catch (const NumericalError& e) {
    std::printf("%s: %s\n", formulation.c_str(), e.what());
    r.finite = false;
  }
  r.rmsError = std::sqrt(sq / std::max<long>(count, 1)) / amplitude;
  r.maxDisplacement /= amplitude;
  r.wall = clock.seconds();
  return r;
}

void check(const std::string& formulation) {
  const Result r = run(formulation, 3.0, kImprovements);
  std::printf("%s: RMS error %.2f %%, max error %.2f %% of the amplitude, max |u|/amplitude %.3f "
              "over 3 periods, %.2f s\n",
              formulation.c_str(), 100 * r.rmsError, 100 * r.maxError, r.maxDisplacement, r.wall);
  test::recordValidation({"solid_tensile_bar_" + formulation,
                          "free-end displacement vs d'Alembert, RMS over the first period / amplitude",
                          r.rmsError, 0.0, r.rmsError,
                          "40 points, h = dx, dt = 1e-7 s, mirror clamp, XSPH 0.5, AV 0.2/0.4",
                          r.wall, "< 5 %", "d'Alembert solution of the 1D wave equation (thesis Sec. 2.6)"});
  EXPECT_TRUE(r.finite);
  EXPECT_LT(r.rmsError, 0.05);
  // stable: the free end never exceeds the exact amplitude by more than 20 % over three periods
  EXPECT_LT(r.maxDisplacement, 1.2);
}

}  // namespace

TEST(SolidTensileBar, TotalLagrangian) { check("total_lagrangian"); }
TEST(SolidTensileBar, SmallStrainStress) { check("small_strain_stress"); }
TEST(SolidTensileBar, SmallStrainDisplacement) { check("small_strain_displacement"); }
