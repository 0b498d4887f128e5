// A Total-Lagrangian solid that slides more than half a period along a periodic axis (issue 11,
// the bug found at stop 30): the displacement u = x - X is kept as the minimum image of each
// particle's own offset, which jumps by one period where the offset passes L/2. The deformation
// gradient (Eq. 2.67: F = I + sum_b V_b (u_b - u_a) (x) G_ab) then took the difference of two
// displacements on different sides of the jump, |u_b - u_a| ~ L, and the strip inverted (J < 0)
// the moment any part of it had slid half a period. The pair's relative displacement is the
// minimum image of u_b - u_a (the reference pair X_b - X_a and the current one x_b - x_a shifted
// by the same whole periods); docs/solid.md "Periodic domains".
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <vector>

#include "libcore/integrator.hpp"
#include "physics/solid/solid_scenes.hpp"

using namespace poresph;
using namespace poresph::solid;

namespace {

constexpr int kN = 24;  // particles along the periodic axis
constexpr double kDx = 0.01, kL = kN * kDx, kPi = 3.14159265358979323846;

// A 24 x 6 clay strip periodic along x (total_lagrangian, the default), reference families built.
std::unique_ptr<Simulation> strip() {
  auto sim = std::make_unique<Simulation>(2);
  addMaterial(*sim, "clay", "elastic", "{density: 2000, young_modulus: 1.0e9, poisson_ratio: 0.25}");
  sim->spacing = kDx;
  sim->kernel = Kernel(KernelType::CubicSpline, 2, 1.3 * kDx);
  buildBlock<2>(*sim, Vec<2>::Zero(), {kN, 6, 1}, kDx);
  sim->domain.lo = {0.0, -kDx, 0};
  sim->domain.hi = {kL, 7 * kDx, 1};
  sim->domain.periodic = {true, false, false};
  addSolidModule(*sim);
  sim->module("solid")->initialise(*sim);
  return sim;
}

// Places every particle at X + (shift + A sin(k X), 0), wrapped into the domain as a run keeps it.
void place(Simulation& sim, double shift, double A) {
  ParticleStore& s = sim.store;
  const RealField X = s.real("reference_position");
  const double k = 2 * kPi / kL;
  for (Index i = 0; i < s.realCount(); ++i) {
    const Vec<2> Xi = s.vec<2>(X, i);
    double x = Xi[0] + shift + A * std::sin(k * Xi[0]);
    x -= kL * std::floor(x / kL);
    s.vec<2>(s.position(), i) = Vec<2>(x, Xi[1]);
  }
}

// Largest |F_a - F_b| over the particles of two strips, particle by particle (matched by id:
// the store reorders its particles).
double largestDifference(Simulation& a, Simulation& b, const char* field) {
  const RealField Fa = a.store.real(field), Fb = b.store.real(field);
  const Index n = a.store.realCount();
  EXPECT_EQ(n, b.store.realCount());
  std::vector<Index> inB(static_cast<size_t>(n), -1);
  for (Index j = 0; j < n; ++j) inB[static_cast<size_t>(b.store.data(b.store.id())[j])] = j;
  double worst = 0.0;
  for (Index i = 0; i < n; ++i) {
    const Index j = inB[static_cast<size_t>(a.store.data(a.store.id())[i])];
    worst = std::max(worst, (a.store.mat<2>(Fa, i) - b.store.mat<2>(Fb, j)).cwiseAbs().maxCoeff());
  }
  return worst;
}

}  // namespace

// A strip with a small periodic stretch u_x = A sin(k X), slid by exactly half a period: the
// particles where sin > 0 have passed L/2 and those where sin < 0 have not. F must be the
// unshifted strip's (a translation changes nothing), F_xx = 1 + A k cos(k X) up to the operator's
// error; before the fix the pairs across the jump gave |F| ~ L / dx and J < 0.
TEST(SolidPeriodicSlide, DeformationGradientIgnoresASlideOfHalfAPeriod) {
  const double A = 1e-4;
  auto still = strip(), slid = strip();
  place(*still, 0.0, A);
  still->evaluateRates();
  for (double shift : {0.5 * kL, 0.75 * kL, 1.5 * kL}) {
    place(*slid, shift, A);
    ASSERT_NO_THROW(slid->evaluateRates()) << "shift " << shift / kL << " L";
    const double dF = largestDifference(*still, *slid, "deformation_gradient");
    std::printf("slide %.2f L: largest |F - F(no slide)| %.2e, |sigma - sigma(no slide)| %.2e Pa\n",
                shift / kL, dF, largestDifference(*still, *slid, "stress"));
    EXPECT_LT(dF, 1e-10) << "shift " << shift / kL << " L";  // round-off of (x - X) at 0.24 m
    const double dP = largestDifference(*still, *slid, "stress");
    EXPECT_LT(dP, 1.0) << "shift " << shift / kL << " L";  // Pa; the stress is ~E A k = 2.6 MPa
  }
}

// A uniform velocity on top of the stretched strip: over 0.75 of a period of travel (leapfrog,
// fixed step) J stays positive and the deformation gradient is the resting strip's at every step
// to round-off (Galilean invariance); a strip without the stretch keeps J = 1 and zero stress.
TEST(SolidPeriodicSlide, AStripTravellingThreeQuartersOfAPeriodKeepsItsDeformation) {
  const double A = 1e-3, V = 50.0;
  auto still = strip(), moving = strip(), rigid = strip();
  place(*still, 0.0, A);
  place(*moving, 0.0, A);
  place(*rigid, 0.0, 0.0);
  for (Simulation* s : {moving.get(), rigid.get()})
    for (Index i = 0; i < s->store.realCount(); ++i) s->store.vec<2>(s->store.velocity(), i) = Vec<2>(V, 0.0);
  auto* solid = dynamic_cast<ElasticSolidModule*>(still->module("solid"));
  ASSERT_NE(solid, nullptr);
  const double dt = 0.3 * solid->elasticTimeStepLimit(*still);
  const int steps = static_cast<int>(std::ceil(0.75 * kL / (V * dt)));
  ASSERT_GT(steps, 50);
  auto i1 = makeIntegrator("leapfrog"), i2 = makeIntegrator("leapfrog"), i3 = makeIntegrator("leapfrog");
  double worstF = 0.0, worstJ = 0.0, worstStress = 0.0;
  for (int step = 0; step < steps; ++step) {
    i1->step(*still, dt);
    ASSERT_NO_THROW(i2->step(*moving, dt)) << "step " << step << ", travelled "
                                           << V * dt * step / kL << " L";
    ASSERT_NO_THROW(i3->step(*rigid, dt)) << "step " << step;
    worstF = std::max(worstF, largestDifference(*still, *moving, "deformation_gradient"));
    const RealField F = rigid->store.real("deformation_gradient"), P = rigid->store.real("stress");
    for (Index i = 0; i < rigid->store.realCount(); ++i) {
      worstJ = std::max(worstJ, std::abs(rigid->store.mat<2>(F, i).determinant() - 1.0));
      worstStress = std::max(worstStress, rigid->store.mat<2>(P, i).cwiseAbs().maxCoeff());
    }
  }
  std::printf("travel %.3f L in %d steps: largest |F - F(at rest)| %.2e; rigid strip |J - 1| %.2e, "
              "|sigma| %.2e Pa\n", V * dt * steps / kL, steps, worstF, worstJ, worstStress);
  EXPECT_GT(V * dt * steps, 0.75 * kL);
  EXPECT_LT(worstF, 1e-9);         // stretch A k = 2.6e-3; round-off of positions at 0.24 m
  EXPECT_LT(worstJ, 1e-12);        // rigid translation: J = 1
  EXPECT_LT(worstStress, 1e-3);    // Pa, against E = 1e9 Pa: zero to round-off
}
