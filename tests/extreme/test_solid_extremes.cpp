// Extremes of issue 4 for the elastic solid: large rigid rotation (TL gives zero stress; the
// small-strain forms do not - documented), Poisson's ratio 0 and 0.49, h/dx from 1.0 to 2.5,
// disordered particles, and blow-ups that stop with a message naming the particle and quantity.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "physics/solid/solid_scenes.hpp"

using namespace poresph;
using namespace poresph::solid;

namespace {

constexpr double kE = 1.0e9;

std::unique_ptr<Simulation> block2D(const std::string& formulation, double nu, int n, double hOverDx,
                                    double disorder = 0.0, unsigned seed = 1) {
  const double dx = 0.01;
  auto sim = std::make_unique<Simulation>(2);
  addMaterial(*sim, "clay", "elastic",
              "{density: 2000, young_modulus: 1.0e9, poisson_ratio: " + std::to_string(nu) +
                  ", formulation: " + formulation + "}");
  sim->spacing = dx;
  sim->kernel = Kernel(KernelType::CubicSpline, 2, hOverDx * dx);
  buildBlock<2>(*sim, Vec<2>::Zero(), {n, n, 1}, dx);
  if (disorder > 0.0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(-disorder * dx, disorder * dx);
    double* x = sim->store.data(sim->store.position());
    for (Index i = 0; i < 2 * sim->store.realCount(); ++i) x[i] += U(rng);
  }
  sim->domain.lo = {-dx, -dx, 0};
  sim->domain.hi = {(n + 1) * dx, (n + 1) * dx, 1};
  addSolidModule(*sim);
  sim->module("solid")->initialise(*sim);
  return sim;
}

// Max relative stress error of a uniform deformation x = X + G X against the closed form.
double patchError(Simulation& sim, const std::string& f, double nu, const Mat<2>& G) {
  ParticleStore& s = sim.store;
  const RealField X = s.real("reference_position");
  for (Index i = 0; i < s.realCount(); ++i) s.vec<2>(s.position(), i) = s.vec<2>(X, i) + G * s.vec<2>(X, i);
  sim.evaluateRates();
  double lambda, mu;
  lameParameters(kE, nu, 2, Plane::Strain, lambda, mu);
  const Mat<2> I = Mat<2>::Identity();
  Mat<2> ref;
  if (f == "total_lagrangian") {
    const Mat<2> F = I + G, E = 0.5 * (F.transpose() * F - I);
    ref = F * (lambda * E.trace() * I + 2 * mu * E) * F.transpose() / F.determinant();
  } else {
    const Mat<2> H = G * (I + G).inverse(), eps = 0.5 * (H + H.transpose());
    ref = lambda * eps.trace() * I + 2 * mu * eps;
  }
  double err = 0.0;
  for (Index i = 0; i < s.realCount(); ++i)
    err = std::max(err, (s.mat<2>(s.real("stress"), i) - ref).norm() / ref.norm());
  return err;
}

// The energy each form conserves: TL and the stress-based form sum V0 1/2 S:E (their elastic
// energy); the displacement form (Eq. 2.90) is a sum of linear pair forces whose potential is
// Phi = -1/4 sum_a sum_b V_a V_b F_ab [(mu - lambda) |u_ab|^2 + (lambda + mu)(D + 2)(e . u_ab)^2]
// (F_ab = W'(r)/r < 0; -dPhi/du_a is m_a a_a of elastic_solid.cpp), not 1/2 sigma:eps.
template <int D>
double storedEnergy(Simulation& sim) {
  auto* solid = dynamic_cast<ElasticSolidModule*>(sim.module("solid"));
  if (solid->formulation() != Formulation::SmallStrainDisplacement) return solid->elasticEnergy(sim);
  const ElasticMaterial& e = solid->elasticMaterials()[0];
  ParticleStore& s = sim.store;
  const RealField u = s.real("displacement");
  const double* m = s.data(s.mass());
  const double* rho = s.data(s.density());
  const NeighbourList& nl = sim.neighbours;
  double phi = 0.0;
  for (Index i = 0; i < s.realCount(); ++i)
    for (auto p = nl.offset[static_cast<size_t>(i)]; p < nl.offset[static_cast<size_t>(i) + 1]; ++p) {
      const Index j = nl.index[static_cast<size_t>(p)];
      const Vec<D> r = s.vec<D>(s.position(), i) - s.vec<D>(s.position(), j);
      const Vec<D> uij = s.vec<D>(u, i) - s.vec<D>(u, j);
      const double q = r.dot(uij) / r.norm();
      phi -= 0.25 * m[i] / rho[i] * m[j] / rho[j] * sim.kernel.F(r.norm()) *
             ((e.mu - e.lambda) * uij.squaredNorm() + (e.lambda + e.mu) * (D + 2) * q * q);
    }
  return phi;
}

// Free vibration of a block from a smooth velocity field; returns max relative drift of the
// energy each form conserves (kinetic + storedEnergy) and whether everything stayed finite.
double vibrate(Simulation& sim, int steps, bool& finite) {
  auto* solid = dynamic_cast<ElasticSolidModule*>(sim.module("solid"));
  ParticleStore& s = sim.store;
  for (Index i = 0; i < s.realCount(); ++i) {
    const Vec<2> x = s.vec<2>(s.position(), i);
    s.vec<2>(s.velocity(), i) = Vec<2>(std::sin(30 * x[1]), std::cos(25 * x[0])) * 0.01;
  }
  auto integrator = makeIntegrator("leapfrog");
  const double dt = 0.3 * solid->elasticTimeStepLimit(sim);
  double e0 = -1, drift = 0.0;
  finite = true;
  try {
    for (int k = 0; k < steps; ++k) {
      integrator->step(sim, dt);
      sim.checkFinite();
      const double e = solid->kineticEnergy(sim) + storedEnergy<2>(sim);
      if (e0 < 0) e0 = e;
      drift = std::max(drift, std::abs(e - e0) / e0);
    }
  } catch (const NumericalError&) {
    finite = false;
  }
  return drift;
}

}  // namespace

TEST(SolidExtremes, LargeRigidRotation) {
  const double theta = 60.0 * 3.14159265358979323846 / 180.0;
  Mat<2> R;
  R << std::cos(theta), -std::sin(theta), std::sin(theta), std::cos(theta);
  for (const std::string f : {"total_lagrangian", "small_strain_stress", "small_strain_displacement"}) {
    auto sim = block2D(f, 0.25, 10, 1.3);
    ParticleStore& s = sim->store;
    const RealField X = s.real("reference_position");
    for (Index i = 0; i < s.realCount(); ++i) s.vec<2>(s.position(), i) = R * s.vec<2>(X, i);
    sim->evaluateRates();
    double worst = 0.0;
    for (Index i = 0; i < s.realCount(); ++i)
      worst = std::max(worst, s.mat<2>(s.real("stress"), i).norm() / kE);
    std::printf("%s: max |sigma| / E after a 60 degree rigid rotation = %.3e\n", f.c_str(), worst);
    if (f == "total_lagrangian") {
      EXPECT_LT(worst, 1e-12);  // SVK is objective: a rotation is stress-free
    } else {
      // small strain reads R - 1 as a strain: sym(R - 1) = (cos theta - 1) 1, a spurious
      // isotropic compression of order E (1 - cos theta)
      EXPECT_GT(worst, 0.1);
    }
  }
}

TEST(SolidExtremes, PoissonRatioZeroAndNearlyIncompressible) {
  const Mat<2> G = (Mat<2>() << 1e-3, 2e-4, -5e-4, 3e-4).finished();
  for (const double nu : {0.0, 0.49})
    for (const std::string f : {"total_lagrangian", "small_strain_stress", "small_strain_displacement"}) {
      if (f == "small_strain_displacement" && nu > 0.25) {
        // refused: pair-wise Navier terms are unstable for lambda > mu (docs/solid.md)
        EXPECT_THROW(block2D(f, nu, 10, 1.3), InputError);
        continue;
      }
      auto sim = block2D(f, nu, 10, 1.3);
      EXPECT_LT(patchError(*sim, f, nu, G), 1e-9) << f << " nu = " << nu;
      auto dyn = block2D(f, nu, 12, 1.3);
      bool finite = false;
      const double drift = vibrate(*dyn, 400, finite);
      EXPECT_TRUE(finite) << f << " nu = " << nu;
      // each form conserves its own energy (storedEnergy): measured drifts 1.5e-3 (TL and
      // stress-based, identical at this amplitude), 1.3e-3 (displacement form, pair potential)
      EXPECT_LT(drift, 0.01) << f << " nu = " << nu;
      std::printf("%s nu = %.2f: energy drift over 400 steps %.2e\n", f.c_str(), nu, drift);
    }
}

TEST(SolidExtremes, SmoothingLengthRange) {
  const Mat<2> G = (Mat<2>() << 1e-3, 2e-4, -5e-4, 3e-4).finished();
  for (const double hdx : {1.0, 1.5, 2.0, 2.5})
    for (const std::string f : {"total_lagrangian", "small_strain_stress"}) {
      auto sim = block2D(f, 0.25, 12, hdx);
      EXPECT_LT(patchError(*sim, f, 0.25, G), 1e-9) << f << " h/dx = " << hdx;
      auto dyn = block2D(f, 0.25, 12, hdx);
      bool finite = false;
      const double drift = vibrate(*dyn, 300, finite);
      EXPECT_TRUE(finite) << f << " h/dx = " << hdx;
      EXPECT_LT(drift, 0.01) << f << " h/dx = " << hdx;  // measured 6e-4 ... 3.3e-3, both forms
      std::printf("%s h/dx = %.1f: energy drift %.2e\n", f.c_str(), hdx, drift);
    }
}

TEST(SolidExtremes, DisorderedParticles) {
  const Mat<2> G = (Mat<2>() << 1e-3, 2e-4, -5e-4, 3e-4).finished();
  for (const std::string f : {"total_lagrangian", "small_strain_stress"}) {
    auto sim = block2D(f, 0.3, 12, 1.5, 0.25);
    EXPECT_LT(patchError(*sim, f, 0.3, G), 1e-8) << f;  // the correction keeps linear exactness
    auto dyn = block2D(f, 0.3, 12, 1.5, 0.25, 7);
    bool finite = false;
    const double drift = vibrate(*dyn, 400, finite);
    EXPECT_TRUE(finite) << f;
    EXPECT_LT(drift, 0.01) << f;  // measured 1.05e-3, both forms
    std::printf("%s disordered (+-0.25 dx): energy drift %.2e\n", f.c_str(), drift);
  }
}

TEST(SolidExtremes, InvertedParticleStopsWithItsName) {
  auto sim = block2D("total_lagrangian", 0.3, 8, 1.3);
  sim->evaluateRates();
  // crush one particle through its neighbours
  ParticleStore& s = sim->store;
  s.vec<2>(s.velocity(), 27) = Vec<2>(-1.0e5, 0.0);
  const std::int32_t id = s.data(s.id())[27];
  auto integrator = makeIntegrator("leapfrog");
  try {
    for (int k = 0; k < 100; ++k) integrator->step(*sim, 1e-7);
    FAIL() << "no error";
  } catch (const NumericalError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("J = det F"), std::string::npos) << m;
    EXPECT_NE(m.find("particle"), std::string::npos) << m;
    (void)id;
  }
}

TEST(SolidExtremes, NaNIsNamedByCheckFinite) {
  auto sim = block2D("small_strain_stress", 0.3, 6, 1.3);
  ParticleStore& s = sim->store;
  s.vec<2>(s.velocity(), 5)[1] = std::nan("");
  auto integrator = makeIntegrator("leapfrog");
  try {
    integrator->step(*sim, 1e-8);
    sim->checkFinite();
    FAIL() << "NaN not detected";
  } catch (const NumericalError& e) {
    const std::string m = e.what();
    std::printf("%s\n", m.c_str());
    EXPECT_NE(m.find("particle"), std::string::npos) << m;
  }
}

// Periodic domains (small-strain forms): a rigid translation by 0.7 of the period wraps half of
// the particles; displacements are taken by minimum image, so the strain stays zero.
TEST(SolidExtremes, PeriodicTranslationIsStressFree) {
  const double dx = 0.01;
  const int n = 12;
  Simulation sim(2);
  addMaterial(sim, "clay", "elastic",
              "{density: 2000, young_modulus: 1.0e9, poisson_ratio: 0.25, formulation: small_strain_stress}");
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::CubicSpline, 2, 1.3 * dx);
  buildBlock<2>(sim, Vec<2>::Zero(), {n, 6, 1}, dx);
  sim.domain.lo = {0.0, -dx, 0};
  sim.domain.hi = {n * dx, 7 * dx, 1};
  sim.domain.periodic = {true, false, false};
  addSolidModule(sim);
  sim.module("solid")->initialise(sim);
  ParticleStore& s = sim.store;
  for (Index i = 0; i < s.realCount(); ++i) s.vec<2>(s.position(), i)[0] += 0.7 * n * dx;
  sim.evaluateRates();
  double worst = 0.0;
  for (Index i = 0; i < s.realCount(); ++i) worst = std::max(worst, s.mat<2>(s.real("stress"), i).norm() / kE);
  EXPECT_LT(worst, 1e-12);

}

// Periodic domains, total Lagrangian (issue 13: the drainage sample is periodic along its flow
// axis with the solid crossing that face): the reference families cross the periodic face
// (images at initialise, minimum-image separations). A strip periodic along x: a rigid
// translation by 0.7 of the period is stress-free; a periodic displacement u_x = A sin(k X)
// gives F_xx = 1 + A k cos(k X) as accurately next to the face as in the middle; a standing
// wave through the face keeps its energy; a period shorter than two supports is refused.
namespace {
std::unique_ptr<Simulation> periodicStrip(int n, double hOverDx, std::string extra = "") {
  const double dx = 0.01;
  auto sim = std::make_unique<Simulation>(2);
  addMaterial(*sim, "clay", "elastic",
              "{density: 2000, young_modulus: 1.0e9, poisson_ratio: 0.25" + extra + "}");
  sim->spacing = dx;
  sim->kernel = Kernel(KernelType::CubicSpline, 2, hOverDx * dx);
  buildBlock<2>(*sim, Vec<2>::Zero(), {n, 6, 1}, dx);
  sim->domain.lo = {0.0, -dx, 0};
  sim->domain.hi = {n * dx, 7 * dx, 1};
  sim->domain.periodic = {true, false, false};
  addSolidModule(*sim);
  sim->module("solid")->initialise(*sim);
  return sim;
}
}  // namespace

TEST(SolidExtremes, PeriodicTotalLagrangianFamiliesCrossTheFace) {
  const int n = 24;
  const double dx = 0.01, L = n * dx;
  {  // rigid translation
    auto sim = periodicStrip(n, 1.3);
    ParticleStore& s = sim->store;
    for (Index i = 0; i < s.realCount(); ++i) s.vec<2>(s.position(), i)[0] += 0.7 * L;
    sim->evaluateRates();
    double worst = 0.0;
    for (Index i = 0; i < s.realCount(); ++i) worst = std::max(worst, s.mat<2>(s.real("stress"), i).norm() / kE);
    std::printf("periodic TL: translation by 0.7 period: max |sigma| / E = %.2e\n", worst);
    EXPECT_LT(worst, 1e-12);
  }
  {  // periodic displacement field: F_xx next to the face as accurate as in the middle
    auto sim = periodicStrip(n, 1.3);
    ParticleStore& s = sim->store;
    const RealField X = s.real("reference_position");
    const double A = 1e-4, k = 2 * 3.14159265358979323846 / L;
    for (Index i = 0; i < s.realCount(); ++i) {
      const Vec<2> Xi = s.vec<2>(X, i);
      s.vec<2>(s.position(), i) = Xi + Vec<2>(A * std::sin(k * Xi[0]), 0.0);
    }
    sim->evaluateRates();
    double nearFace = 0.0, middle = 0.0;
    const RealField F = s.real("deformation_gradient");
    for (Index i = 0; i < s.realCount(); ++i) {
      const Vec<2> Xi = s.vec<2>(X, i);
      if (Xi[1] < 2 * dx || Xi[1] > 4 * dx) continue;  // away from the free edges
      const double err = std::abs(s.mat<2>(F, i)(0, 0) - 1.0 - A * k * std::cos(k * Xi[0])) / (A * k);
      const double toFace = std::min(Xi[0], L - Xi[0]);
      if (toFace < 3 * dx) nearFace = std::max(nearFace, err);
      if (std::abs(Xi[0] - 0.5 * L) < 3 * dx || std::abs(Xi[0] - 0.25 * L) < 3 * dx) middle = std::max(middle, err);
    }
    std::printf("periodic TL: F_xx error / (A k): next to the face %.3e, away from it %.3e\n", nearFace, middle);
    EXPECT_LT(nearFace, 0.05);                 // the O((k h)^2) error of the operator
    EXPECT_LT(nearFace, 1.5 * middle + 1e-12);  // no face: the strip is seamless
  }
  {  // standing wave through the face: energy conserved (TL + leapfrog)
    auto sim = periodicStrip(n, 1.3);
    auto* solid = dynamic_cast<ElasticSolidModule*>(sim->module("solid"));
    ParticleStore& s = sim->store;
    const double k = 2 * 3.14159265358979323846 / L;
    for (Index i = 0; i < s.realCount(); ++i)
      s.vec<2>(s.velocity(), i) = Vec<2>(0.01 * std::sin(k * s.vec<2>(s.position(), i)[0] + 0.3), 0.0);
    auto integrator = makeIntegrator("leapfrog");
    const double dt = 0.3 * solid->elasticTimeStepLimit(*sim);
    double e0 = -1, drift = 0.0, maxKe = 0.0;
    for (int step = 0; step < 400; ++step) {
      integrator->step(*sim, dt);
      sim->checkFinite();
      const double e = solid->kineticEnergy(*sim) + solid->elasticEnergy(*sim);
      if (e0 < 0) e0 = e;
      drift = std::max(drift, std::abs(e - e0) / e0);
      maxKe = std::max(maxKe, solid->kineticEnergy(*sim));
    }
    std::printf("periodic TL: standing wave through the face, energy drift over 400 steps %.2e\n", drift);
    EXPECT_LT(drift, 0.01);
  }
  // a period shorter than two supports, with families crossing the face: refused, named
  try {
    periodicStrip(4, 1.3);  // period 4 dx < 2 x 2.6 dx
    FAIL() << "short period accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("shorter than two kernel supports"), std::string::npos) << m;
  }
}

// 3D free vibration of a small cube: finite, and the TL energy is conserved.
TEST(SolidExtremes, ThreeDimensionalVibration) {
  for (const std::string f : {"total_lagrangian", "small_strain_stress", "small_strain_displacement"}) {
    const double dx = 0.01;
    Simulation sim(3);
    addMaterial(sim, "clay", "elastic",
                "{density: 2000, young_modulus: 1.0e9, poisson_ratio: 0.2, formulation: " + f + "}");
    sim.spacing = dx;
    sim.kernel = Kernel(KernelType::CubicSpline, 3, 1.3 * dx);
    buildBlock<3>(sim, Vec<3>::Zero(), {7, 7, 7}, dx);
    sim.domain.lo = {-dx, -dx, -dx};
    sim.domain.hi = {8 * dx, 8 * dx, 8 * dx};
    auto& solid = addSolidModule(sim);
    solid.initialise(sim);
    ParticleStore& s = sim.store;
    for (Index i = 0; i < s.realCount(); ++i) {
      const Vec<3> x = s.vec<3>(s.position(), i);
      s.vec<3>(s.velocity(), i) = 0.01 * Vec<3>(std::sin(40 * x[1]), std::sin(35 * x[2]), std::cos(30 * x[0]));
    }
    auto integrator = makeIntegrator("leapfrog");
    const double dt = 0.3 * solid.elasticTimeStepLimit(sim);
    double e0 = -1, drift = 0.0;
    for (int k = 0; k < 300; ++k) {
      integrator->step(sim, dt);
      sim.checkFinite();
      const double e = solid.kineticEnergy(sim) + storedEnergy<3>(sim);
      if (e0 < 0) e0 = e;
      drift = std::max(drift, std::abs(e - e0) / e0);
    }
    std::printf("3D %s: energy drift over 300 steps %.2e\n", f.c_str(), drift);
    EXPECT_LT(drift, 0.01) << f;  // measured 9.8e-4 (TL, stress-based), 6.6e-4 (displacement, pair potential)
  }
}
