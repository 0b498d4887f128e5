// Unit tests of the constitutive-law interface (physics/solid/constitutive_law): the undamaged law
// is the isotropic one in every dimension, the unilateral split (4.17-4.20) is continuous at
// tr eps = 0, the closed-form damage of each law solves f = Y - Yc(D) = 0 (4.19), the stress is
// the derivative of the energy (4.18a), and bad `damage:` sections are refused naming the key.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>

#include "physics/solid/constitutive_law.hpp"
#include "physics/solid/elastic_solid.hpp"
#include "physics/solid/solid_scenes.hpp"

using namespace poresph;
using namespace poresph::solid;

namespace {

ConstitutiveLaw makeLaw(const std::string& yaml, int dim = 2, Plane plane = Plane::Strain,
                        double E = 12000e6, double nu = 0.25) {
  double lam = 0.0, mu = 0.0;
  lameParameters(E, nu, dim, plane, lam, mu);
  const int nb = dim == 3 || (dim == 2 && plane == Plane::Strain) ? 3 : dim;
  ConstitutiveLaw law(E, lam, mu, nb);
  if (!yaml.empty()) law.configureDamage(ParameterSet(YAML::Load(yaml), "test", "damage"));
  return law;
}

template <int D>
Mat<D> sample(double s) {
  Mat<D> e;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) e(i, j) = s * (0.3 + 0.1 * i - 0.07 * j + (i == j ? 0.5 : 0.0));
  return 0.5 * (e + e.transpose());
}

template <int D>
void checkUndamagedIsIsotropic(int dim, Plane plane) {
  for (const char* y : {"", "{law: pcw, strain_onset: 1e-3, strain_ultimate: 3e-3}",
                        "{law: at1, critical_energy_release: 2.5e3}",
                        "{law: at2, critical_energy_release: 2.5e3}"}) {
    const ConstitutiveLaw law = makeLaw(y, dim, plane);
    for (double s : {1e-4, -1e-4}) {
      const Mat<D> eps = sample<D>(s);
      const Mat<D> ref = law.lambda * eps.trace() * Mat<D>::Identity() + 2.0 * law.mu * eps;
      EXPECT_LT((law.stress<D>(eps, 0.0) - ref).norm(), 1e-9 * ref.norm()) << y << " D=" << D;
      // energy 1/2 sigma : eps
      EXPECT_NEAR(law.energy<D>(eps, 0.0), 0.5 * ref.cwiseProduct(eps).sum(),
                  1e-9 * std::abs(0.5 * ref.cwiseProduct(eps).sum()));
    }
  }
}

}  // namespace

TEST(ConstitutiveLaw, UndamagedIsTheIsotropicLawInEveryDimension) {
  checkUndamagedIsIsotropic<1>(1, Plane::Strain);
  checkUndamagedIsIsotropic<2>(2, Plane::Strain);
  checkUndamagedIsIsotropic<2>(2, Plane::Stress);
  checkUndamagedIsIsotropic<3>(3, Plane::Strain);
}

TEST(ConstitutiveLaw, StressIsTheDerivativeOfTheEnergy) {
  // sigma = d(rho w)/d eps (4.18a) by central differences, on both sides of tr eps = 0
  const ConstitutiveLaw law = makeLaw("{law: at2, critical_energy_release: 2.5e3}");
  for (double tr : {2e-4, -2e-4}) {
    Mat<2> eps;
    eps << 0.5 * tr + 3e-4, 1e-4, 1e-4, 0.5 * tr - 3e-4;
    const double D = 0.4;
    const Mat<2> s = law.stress<2>(eps, D);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        const double h = 1e-9;
        Mat<2> ep = eps, em = eps;
        ep(i, j) += h;
        em(i, j) -= h;
        const double d = (law.energy<2>(ep, D) - law.energy<2>(em, D)) / (2 * h);
        EXPECT_NEAR(d, s(i, j), 1e-5 * s.norm()) << "tr " << tr << " component " << i << j;
      }
  }
}

TEST(ConstitutiveLaw, UnilateralSplitIsContinuousAtZeroTrace) {
  const ConstitutiveLaw law = makeLaw("{law: pcw, strain_onset: 1e-3, strain_ultimate: 3e-3}");
  const double D = 0.6;
  Mat<2> dev;
  dev << 2e-4, 1e-4, 1e-4, -2e-4;
  const double eta = 1e-12;
  const Mat<2> sp = law.stress<2>(Mat<2>(dev + eta * Mat<2>::Identity()), D);
  const Mat<2> sm = law.stress<2>(Mat<2>(dev - eta * Mat<2>::Identity()), D);
  EXPECT_LT((sp - sm).norm(), 1e-6 * sp.norm());
  // at tr = 0 the stress is 2 mu(D) eps^d (with the plane-strain deviator = eps here)
  EXPECT_LT((law.stress<2>(dev, D) - 2.0 * law.g(D) * law.mu * dev).norm(), 1e-9 * sp.norm());
  // in compression the bulk part is the undamaged one: only the deviatoric stress (plane strain:
  // deviator of dimension 3, eps^d = eps - tr/3 1) changes with D
  const Mat<2> c = -1e-3 * Mat<2>::Identity();
  const Mat<2> cd = c - c.trace() / 3.0 * Mat<2>::Identity();
  EXPECT_LT((law.stress<2>(c, 0.9) - law.stress<2>(c, 0.0) - 2.0 * (law.g(0.9) - 1.0) * law.mu * cd).norm(),
            1e-9 * law.stress<2>(c, 0.0).norm());
}

TEST(ConstitutiveLaw, ClosedFormDamageSolvesTheCriterion) {
  for (const char* y : {"{law: pcw, strain_onset: 1e-3, strain_ultimate: 3e-3}",
                        "{law: at1, critical_energy_release: 2.5e3}",
                        "{law: at2, critical_energy_release: 2.5e3}"}) {
    const ConstitutiveLaw law = makeLaw(y);
    for (double psi : {0.3, 0.8, 1.5, 4.0, 20.0}) {
      const double P = psi * law.yc0;
      const double D = law.criterionDamage(P);
      if (D <= 0.0) {
        EXPECT_LE(-law.gPrime(0.0) * P, law.yc(0.0) * (1 + 1e-12)) << y << " psi " << psi;
      } else {
        // f = -g'(D) psi+ - Yc(D) = 0 (4.19)
        // (PCW passes D = 1 / a, where g = 0, at large psi+: the update clips at s_l < 1)
        EXPECT_NEAR(-law.gPrime(D) * P, law.yc(D), 1e-9 * law.yc0) << y << " psi " << psi;
      }
    }
    EXPECT_NEAR(law.criterionDamage(law.onsetEnergy() * 0.999), 0.0, 1e-15) << y;
  }
}

TEST(ConstitutiveLaw, UpdateIsIrreversibleAndClipped) {
  const ConstitutiveLaw law = makeLaw("{law: at1, critical_energy_release: 2.5e3, limit: 0.9}");
  double hist[kDamageHistory] = {0, 0};
  Mat<2> big = 1e-2 * Mat<2>::Identity();
  DamageUpdate u = law.update<2>(big, 0.0, hist);
  EXPECT_DOUBLE_EQ(u.D, 0.9);
  EXPECT_TRUE(u.clipped);
  EXPECT_GT(u.released, 0.0);
  DamageUpdate v = law.update<2>(Mat<2>::Zero(), 0.5, hist);
  EXPECT_DOUBLE_EQ(v.D, 0.5);  // no healing
  EXPECT_FALSE(v.clipped);
  EXPECT_DOUBLE_EQ(v.released, 0.0);
}

TEST(ConstitutiveLaw, BadDamageSectionsAreNamed) {
  auto msg = [](const std::string& y) {
    try {
      makeLaw(y);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(msg("{law: pcx}").find("law"), std::string::npos);
  EXPECT_NE(msg("{law: at1}").find("critical_energy_release"), std::string::npos);
  EXPECT_NE(msg("{law: at2, strain_onset: 1e-3}").find("strain_onset"), std::string::npos);
  EXPECT_NE(msg("{law: at2, critical_energy_release: 1, limt: 0.9}").find("limt"), std::string::npos);
  EXPECT_NE(msg("{law: pcw, strain_onset: 2e-3, strain_ultimate: 1e-3}").find("strain_ultimate"),
            std::string::npos);
  EXPECT_NE(msg("{law: at2, critical_energy_release: 1, limit: 1.0}").find("limit"), std::string::npos);
  EXPECT_NE(msg("{law: rankine_mohr_coulomb, tensile_strain_onset: 1e-3, tensile_strain_ultimate: "
                "2e-3, compressive_strain_onset: 1e-2}").find("friction_angle"),
            std::string::npos);
  EXPECT_NE(msg("{law: pcw, a: 1.2, b: 1, critical_energy_release: 1}").find("a < 1 / s_l"), std::string::npos);
  EXPECT_EQ(msg("{law: at2, critical_energy_release: 1}"), "no error");
}

// The solid registers the damage fields only when a material has `damage:`, and a bad key of the
// section is named with the material's path.

TEST(ConstitutiveLaw, DamageFieldsOnlyWithDamage) {
  for (bool damage : {false, true}) {
    Simulation sim(1);
    solid::addMaterial(sim, "bar", "elastic",
                       std::string("{density: 1000, young_modulus: 1e9") +
                           (damage ? ", damage: {law: at2, critical_energy_release: 100}}" : "}"));
    sim.spacing = 1e-3;
    sim.kernel = Kernel(KernelType::CubicSpline, 1, 1.3e-3);
    sim.store.addParticles(10);
    double* x = sim.store.data(sim.store.position());
    for (int i = 0; i < 10; ++i) x[i] = i * 1e-3;
    sim.domain.lo = {-1, 0, 0};
    sim.domain.hi = {1, 1, 1};
    solid::ElasticSolidModule& s = solid::addSolidModule(sim);
    EXPECT_EQ(s.hasDamage(), damage);
    EXPECT_EQ(sim.store.has("damage"), damage);
    EXPECT_EQ(sim.store.has("damage_dissipation"), damage);
    EXPECT_FALSE(sim.store.has("damage_history"));  // Rankine/Mohr-Coulomb only
  }
}

TEST(ConstitutiveLaw, BadDamageKeyInASceneIsNamedWithItsPath) {
  Simulation sim(2);
  solid::addMaterial(sim, "clay", "elastic",
                     "{density: 1000, young_modulus: 1e9, poisson_ratio: 0.2, "
                     "damage: {law: pcw, strain_onset: 1e-3, strain_ultimat: 2e-3}}");
  try {
    solid::addSolidModule(sim);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("damage"), std::string::npos) << m;
    EXPECT_NE(m.find("strain_ultimate"), std::string::npos) << m;  // missing (and suggested)
  }
  Simulation sim2(2);
  solid::addMaterial(sim2, "clay", "elastic",
                     "{density: 1000, young_modulus: 1e9, poisson_ratio: 0.2, "
                     "formulation: small_strain_displacement, "
                     "damage: {law: at2, critical_energy_release: 100}}");
  try {
    solid::addSolidModule(sim2);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("displacement-based"), std::string::npos) << e.what();
  }
}
