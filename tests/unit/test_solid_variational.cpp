// The Total-Lagrangian internal force is the exact negative gradient of the discrete stored
// energy (docs/solid.md "Total Lagrangian ... a variational operator"):
//   E(x) = sum_a V_a psi(F_a) + Phi_hg(x),  F_a = 1 + sum_b V_b (u_b - u_a) (x) g_ab,
// so that m_a dv_a/dt = -dE/dx_a and kinetic + E is conserved up to the time integrator. Checked
// against central finite differences of E on a disordered block with a non-uniform, large
// deformation, in 2D and 3D, without and with the conservative hourglass control; the pairwise
// (Ganzenmueller) hourglass spring is shown not to be a gradient (the check can fail). With a
// frozen damage field the damaged force is the gradient of the damaged energy (Eq. 4.17).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "physics/solid/solid_scenes.hpp"

using namespace poresph;
using namespace poresph::solid;

namespace {

template <int D>
std::unique_ptr<Simulation> disorderedBlock(int n, double hourglass, const std::string& section,
                                            unsigned seed, const std::string& extra = "") {
  const double dx = 0.01;
  auto sim = std::make_unique<Simulation>(D);
  addMaterial(*sim, "clay", "elastic",
              "{density: 2000, young_modulus: 1.0e9, poisson_ratio: 0.3, hourglass: " +
                  std::to_string(hourglass) + extra + "}");
  sim->spacing = dx;
  sim->kernel = Kernel(KernelType::WendlandC2, D, 1.3 * dx);
  sim->reorderEvery = 0;  // particle indices stay put between the evaluations
  buildBlock<D>(*sim, Vec<D>::Zero(), {n, n, n}, dx);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-0.2 * dx, 0.2 * dx);
  double* x = sim->store.data(sim->store.position());
  for (Index i = 0; i < D * sim->store.realCount(); ++i) x[i] += U(rng);  // disordered reference
  for (int a = 0; a < D; ++a) {
    sim->domain.lo[static_cast<size_t>(a)] = -2 * dx;
    sim->domain.hi[static_cast<size_t>(a)] = (n + 2) * dx;
  }
  addSolidModule(*sim, section);
  sim->module("solid")->initialise(*sim);
  // a large, non-uniform deformation: stretch, shear, a bend and random displacements
  std::uniform_real_distribution<double> V(-0.05 * dx, 0.05 * dx);
  const double L = n * dx;
  for (Index i = 0; i < sim->store.realCount(); ++i) {
    double* xi = x + i * D;
    const double X0 = xi[0], X1 = xi[1];
    xi[0] += 0.04 * X0 + 0.03 * X1 + V(rng);
    xi[1] += -0.02 * X1 + 0.05 * X0 * X0 / L + V(rng);
    for (int a = 2; a < D; ++a) xi[a] += 0.01 * X0 + V(rng);
  }
  return sim;
}

template <int D>
double storedEnergy(Simulation& sim) {
  auto* solid = dynamic_cast<ElasticSolidModule*>(sim.module("solid"));
  sim.evaluateRates();
  return solid->elasticEnergy(sim) + solid->hourglassEnergy(sim);
}

// max over the particles and components checked of |dE/dx + m a| / max |m a|
template <int D>
double gradientMismatch(Simulation& sim, int every) {
  ParticleStore& s = sim.store;
  const Index n = s.realCount();
  storedEnergy<D>(sim);
  std::vector<double> force(static_cast<size_t>(n * D));
  double fmax = 0.0;
  for (Index i = 0; i < n; ++i)
    for (int a = 0; a < D; ++a) {
      force[static_cast<size_t>(i * D + a)] = s.data(s.mass())[i] * s.data(sim.acceleration)[i * D + a];
      fmax = std::max(fmax, std::abs(force[static_cast<size_t>(i * D + a)]));
    }
  const double delta = 1e-6 * sim.spacing;
  double worst = 0.0;
  for (Index i = 0; i < n; i += every)
    for (int a = 0; a < D; ++a) {
      double& xi = s.data(s.position())[i * D + a];
      const double x0 = xi;
      xi = x0 + delta;
      const double ep = storedEnergy<D>(sim);
      xi = x0 - delta;
      const double em = storedEnergy<D>(sim);
      xi = x0;
      const double dEdx = (ep - em) / (2.0 * delta);
      worst = std::max(worst, std::abs(dEdx + force[static_cast<size_t>(i * D + a)]) / fmax);
    }
  return worst;
}

}  // namespace

TEST(SolidVariational, ForceIsTheGradientOfTheStoredEnergy2D) {
  auto sim = disorderedBlock<2>(7, 0.0, "", 3);
  const double err = gradientMismatch<2>(*sim, 1);
  std::printf("2D, no hourglass control: max |dE/dx + m a| / max |m a| = %.2e\n", err);
  EXPECT_LT(err, 1e-6);
}

TEST(SolidVariational, ForceIsTheGradientOfTheStoredEnergy3D) {
  auto sim = disorderedBlock<3>(4, 0.0, "", 5);
  const double err = gradientMismatch<3>(*sim, 3);
  std::printf("3D, no hourglass control: max |dE/dx + m a| / max |m a| = %.2e\n", err);
  EXPECT_LT(err, 1e-6);
}

TEST(SolidVariational, ConservativeHourglassForceIsTheGradientOfItsPenaltyEnergy) {
  for (double hg : {1.0, 50.0}) {
    auto sim = disorderedBlock<2>(7, hg, "", 7);
    auto* solid = dynamic_cast<ElasticSolidModule*>(sim->module("solid"));
    ASSERT_TRUE(solid->hourglassConservative());
    sim->evaluateRates();
    EXPECT_GT(solid->hourglassEnergy(*sim), 0.0);
    const double err = gradientMismatch<2>(*sim, 1);
    std::printf("2D, conservative hourglass %.0f: max |dE/dx + m a| / max |m a| = %.2e "
                "(hourglass energy %.3e of the elastic)\n",
                hg, err, solid->hourglassEnergy(*sim) / solid->elasticEnergy(*sim));
    EXPECT_LT(err, 1e-6) << "hourglass " << hg;
  }
  auto sim = disorderedBlock<3>(4, 1.0, "", 9);
  const double err = gradientMismatch<3>(*sim, 3);
  std::printf("3D, conservative hourglass 1: max |dE/dx + m a| / max |m a| = %.2e\n", err);
  EXPECT_LT(err, 1e-6);
}

TEST(SolidVariational, PairwiseHourglassSpringIsNotAGradient) {
  // Ganzenmueller's projected spring (hourglass_form: pairwise): its force is not -dE/dx of any
  // energy the module stores; the mismatch is its own size, far above round-off.
  auto sim = disorderedBlock<2>(7, 50.0, "{hourglass_form: pairwise}", 7);
  auto* solid = dynamic_cast<ElasticSolidModule*>(sim->module("solid"));
  EXPECT_FALSE(solid->hourglassConservative());
  EXPECT_EQ(solid->hourglassEnergy(*sim), 0.0);
  const double err = gradientMismatch<2>(*sim, 1);
  std::printf("2D, pairwise hourglass 50: max |dE/dx + m a| / max |m a| = %.2e\n", err);
  EXPECT_GT(err, 1e-2);
}

TEST(SolidVariational, DamagedForceIsTheGradientOfTheDamagedStoredEnergy) {
  // A frozen damage field (D between 0 and 0.9, no commit in the evaluation): the force
  // must be -dE/dx of sum V [g(D) psi+ + psi-] (Eq. 4.17 with the unilateral split 4.18), on a
  // deformation with both tensile and compressed particles.
  for (const char* law : {"at2, critical_energy_release: 2500", "at1, critical_energy_release: 2500",
                          "pcw, strain_onset: 0.022, strain_ultimate: 0.06"}) {
    auto sim = disorderedBlock<2>(7, 0.0, "", 11, std::string(", damage: {law: ") + law + "}");
    // the evaluation commits D at its strain (damage.cpp): frozen here
    dynamic_cast<ElasticSolidModule*>(sim->module("solid"))->freezeDamage = true;
    ParticleStore& s = sim->store;
    double* dm = s.data(s.real("damage"));
    for (Index i = 0; i < s.realCount(); ++i) dm[i] = 0.9 * (0.5 + 0.5 * std::sin(1.7 * i));
    // compress the upper half of the block (tr E < 0: the bulk part is not degraded), stretch
    // the lower (tr E > 0)
    double* x = s.data(s.position());
    int compressed = 0;
    for (Index i = 0; i < s.realCount(); ++i) {
      const double f = x[i * 2 + 1] > 0.035 ? 0.95 : 1.02;
      x[i * 2] *= f;
      x[i * 2 + 1] *= f;
    }
    sim->evaluateRates();
    for (Index i = 0; i < s.realCount(); ++i) compressed += s.mat<2>(s.real("strain"), i).trace() < 0.0;
    EXPECT_GT(compressed, 5);
    EXPECT_LT(compressed, s.realCount() - 5);
    const double err = gradientMismatch<2>(*sim, 1);
    std::printf("2D, damage %s (D in [0, 0.9]): max |dE/dx + m a| / max |m a| = %.2e\n", law, err);
    EXPECT_LT(err, 1e-6) << law;
  }
}

TEST(SolidVariational, HourglassPenaltyIsDegradedWithTheDamage) {
  // The conservative hourglass penalty is degraded by g(D) like the rest of the stored energy
  // (docs/damage.md "Hourglass control under damage"): with a uniform D its energy is g(D) times
  // the undamaged one (it was not degraded before 2026-11-27: ratio 1), and with a non-uniform
  // frozen D the force is still -dE/dx of the damaged energy plus the degraded penalty.
  const std::string law = ", damage: {law: at2, critical_energy_release: 2500}";
  auto sim = disorderedBlock<2>(7, 1.0, "", 11, law);
  auto* solid = dynamic_cast<ElasticSolidModule*>(sim->module("solid"));
  solid->freezeDamage = true;  // the evaluation commits D at its strain (damage.cpp): frozen here
  ParticleStore& s = sim->store;
  double* dm = s.data(s.real("damage"));
  sim->evaluateRates();
  const double undamaged = solid->hourglassEnergy(*sim);
  ASSERT_GT(undamaged, 0.0);
  for (Index i = 0; i < s.realCount(); ++i) dm[i] = 0.5;  // AT-2: g = (1 - D)^2 = 0.25
  sim->evaluateRates();
  const double ratio = solid->hourglassEnergy(*sim) / undamaged;
  std::printf("uniform D = 0.5 (AT-2, g = 0.25): hourglass energy ratio %.15f\n", ratio);
  EXPECT_NEAR(ratio, 0.25, 1e-12);
  for (Index i = 0; i < s.realCount(); ++i) dm[i] = 0.9 * (0.5 + 0.5 * std::sin(1.7 * i));
  const double err = gradientMismatch<2>(*sim, 1);
  std::printf("2D, AT-2, conservative hourglass 1, D in [0, 0.9]: max |dE/dx + m a| / max |m a| = %.2e\n",
              err);
  EXPECT_LT(err, 1e-6);
}

TEST(SolidVariational, HourglassFormKeyIsChecked) {
  Simulation sim(2);
  addMaterial(sim, "clay", "elastic", "{density: 2000, young_modulus: 1.0e9, poisson_ratio: 0.3}");
  try {
    addSolidModule(sim, "{hourglass_form: springy}");
    ADD_FAILURE() << "an unknown hourglass_form was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("hourglass_form"), std::string::npos) << what;
    EXPECT_NE(what.find("springy"), std::string::npos) << what;
  }
  Simulation small(2);
  addMaterial(small, "clay", "elastic",
              "{density: 2000, young_modulus: 1.0e9, poisson_ratio: 0.3, formulation: small_strain_stress}");
  EXPECT_THROW(addSolidModule(small, "{hourglass_form: pairwise}"), InputError);
}
