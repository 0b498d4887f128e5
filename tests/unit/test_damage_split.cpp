// Unit tests of the two damage-law options for confined clay (issue 13, docs/damage.md "Damage
// under confinement"): the spectral energy split (`split: spectral`) and the stress measure of
// the Rankine branch (`tensile_measure: stress`). Each option is checked against what it must
// keep (undamaged law, energy-consistent stress, the uniaxial-tension onset) and what it changes
// (a compressed, sheared point of the two-pores drainage sample).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <string>

#include "libcore/types.hpp"
#include "physics/solid/constitutive_law.hpp"
#include "physics/solid/elastic_solid.hpp"

using namespace poresph;
using namespace poresph::solid;

namespace {

ConstitutiveLaw makeLaw(const std::string& yaml, int dim = 2, Plane plane = Plane::Strain,
                        double E = 1.2e5, double nu = 0.1) {
  double lam = 0.0, mu = 0.0;
  lameParameters(E, nu, dim, plane, lam, mu);
  const int nb = dim == 3 || (dim == 2 && plane == Plane::Strain) ? 3 : dim;
  ConstitutiveLaw law(E, lam, mu, nb);
  law.configureDamage(ParameterSet(YAML::Load(yaml), "test", "damage"));
  return law;
}

const char* kRankine =
    "{law: rankine_mohr_coulomb, tensile_strain_onset: 0.0013, tensile_strain_ultimate: 0.0026, "
    "compressive_strain_onset: 0.015, friction_angle: 25";

std::string rankine(const std::string& extra) {
  return std::string(kRankine) + (extra.empty() ? "" : ", " + extra) + "}";
}

// A strain state measured in samples/drainage_two_pores_2d.yaml at 2.7 ms (TL Green-Lagrange
// strain of particle x = 3.44, y = 2.65 mm, right of the lower pore, just before it damaged):
// compressed along y by the dP thrust (E_yy = -3.8 eps_t0), e_1 = 1.2 eps_t0 from the shear,
// while the largest principal stress is 0.75 f_t (f_t = E eps_t0 = 156 Pa).
Mat<2> confinedSheared() {
  Mat<2> e;
  e << 1.40e-3, 1.00e-3, 1.00e-3, -5.00e-3;
  return e;
}

}  // namespace

TEST(DamageSplit, SpectralUndamagedIsTheIsotropicLaw) {
  for (int dim : {1, 2, 3}) {
    const ConstitutiveLaw law =
        makeLaw("{law: pcw, strain_onset: 1e-3, strain_ultimate: 2e-3, split: spectral}", dim);
    ASSERT_EQ(law.splitType, EnergySplit::Spectral);
    auto check = [&](auto eps) {
      using M = decltype(eps);
      constexpr int D = M::RowsAtCompileTime;
      const M ref = law.lambda * eps.trace() * M::Identity() + 2.0 * law.mu * eps;
      EXPECT_LT((law.stress<D>(eps, 0.0) - ref).norm(), 1e-9 * ref.norm()) << "dim " << dim;
      const double w = 0.5 * ref.cwiseProduct(eps).sum();
      EXPECT_NEAR(law.energy<D>(eps, 0.0), w, 1e-9 * std::abs(w)) << "dim " << dim;
    };
    if (dim == 1) {
      check(Mat<1>(Mat<1>::Constant(2e-4)));
      check(Mat<1>(Mat<1>::Constant(-2e-4)));
    } else if (dim == 2) {
      check(confinedSheared());
      check(Mat<2>(Mat<2>::Identity() * 1e-4));
    } else {
      Mat<3> e;
      e << 3e-4, 1e-4, -2e-4, 1e-4, -5e-4, 0.5e-4, -2e-4, 0.5e-4, 1e-4;
      check(e);
    }
  }
}

TEST(DamageSplit, SpectralStressIsTheDerivativeOfItsEnergy) {
  // sigma = d(rho w)/d eps by central differences at D = 0.6, principal strains of both signs
  // and both signs of the trace (the split is continuous, so its derivative is the stress)
  const ConstitutiveLaw law = makeLaw(rankine("split: spectral"));
  for (double shift : {2e-4, -2e-4}) {
    Mat<2> eps = confinedSheared() * 0.3;
    eps.diagonal().array() += shift;
    const double D = 0.6;
    const Mat<2> s = law.stress<2>(eps, D);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        const double h = 1e-9;
        // symmetric perturbation (the eigen-solver reads one triangle): dW = 2 s_ij h off the
        // diagonal
        Mat<2> ep = eps, em = eps;
        ep(i, j) += h;
        em(i, j) -= h;
        if (i != j) ep(j, i) += h, em(j, i) -= h;
        const double d =
            (law.energy<2>(ep, D) - law.energy<2>(em, D)) / (2 * h) / (i != j ? 2.0 : 1.0);
        EXPECT_NEAR(d, s(i, j), 1e-5 * s.norm()) << "shift " << shift << " component " << i << j;
      }
  }
}

TEST(DamageSplit, SpectralKeepsTheCompressedDirectionsOfADamagedPoint) {
  // Fully compressed state (both principal strains < 0, deviatoric): the thesis' split (4.17)
  // degrades the shear and the stress changes with D; the spectral split keeps it whole.
  Mat<2> eps;
  eps << -1.0e-3, 0.4e-3, 0.4e-3, -4.0e-3;
  const ConstitutiveLaw vol = makeLaw(rankine(""));
  const ConstitutiveLaw spec = makeLaw(rankine("split: spectral"));
  const Mat<2> s0 = vol.stress<2>(eps, 0.0);
  EXPECT_LT((spec.stress<2>(eps, 0.9) - s0).norm(), 1e-12 * s0.norm());
  EXPECT_GT((vol.stress<2>(eps, 0.9) - s0).norm(), 0.2 * s0.norm());
  EXPECT_EQ(spec.psiPlus(spec.split<2>(eps)), 0.0);
  // Tension along x with a negative lateral strain (trace > 0): the x direction and the
  // lambda tr part degrade, the compressive 2 mu e_yy is kept.
  Mat<2> t;
  t << 2e-3, 0.0, 0.0, -0.2e-3;
  const Mat<2> st = spec.stress<2>(t, 0.99);
  EXPECT_NEAR(st(1, 1), 2.0 * spec.mu * (-0.2e-3) + 0.01 * spec.lambda * t.trace(), 1e-9);
  EXPECT_NEAR(st(0, 0), 0.01 * (2.0 * spec.mu * 2e-3 + spec.lambda * t.trace()), 1e-9);
}

TEST(DamageSplit, StressMeasureKeepsTheUniaxialOnsetAndIgnoresConfinedShear) {
  // Uniaxial tension (1D, sigma = E eps): both measures start damage at eps_t0.
  for (const char* m : {"tensile_measure: strain", "tensile_measure: stress"}) {
    const ConstitutiveLaw law = makeLaw(rankine(m), 1);
    double h[kDamageHistory] = {0.0, 0.0};
    EXPECT_EQ(law.update<1>(Mat<1>::Constant(0.999 * 0.0013), 0.0, h).D, 0.0) << m;
    h[0] = h[1] = 0.0;
    EXPECT_GT(law.update<1>(Mat<1>::Constant(1.01 * 0.0013), 0.0, h).D, 0.0) << m;
  }
  // Plane strain, in-plane uniaxial stress sigma_xx only (eps_yy = -nu/(1 - nu) eps_xx): the
  // stress measure's onset is sigma_xx = E eps_t0, the strain measure's eps_xx = eps_t0.
  const ConstitutiveLaw stress = makeLaw(rankine("tensile_measure: stress"));
  const double nu = 0.1, Ep = stress.young / (1.0 - nu * nu);  // plane-strain modulus
  const double exxOnset = stress.young * 0.0013 / Ep;
  for (double f : {0.999, 1.001}) {
    Mat<2> e;
    e << f * exxOnset, 0.0, 0.0, -nu / (1.0 - nu) * f * exxOnset;
    double h[kDamageHistory] = {0.0, 0.0};
    const double D = stress.update<2>(e, 0.0, h).D;
    EXPECT_NEAR(stress.stress<2>(e, 0.0)(0, 0), f * stress.young * 0.0013, 1e-6);
    if (f < 1.0) EXPECT_EQ(D, 0.0);
    else EXPECT_GT(D, 0.0);
  }
  // The measured confined, sheared point: e_1 > eps_t0 but sigma_1 < f_t.
  const Mat<2> e = confinedSheared();
  const ConstitutiveLaw strain = makeLaw(rankine(""));
  ASSERT_GT(ConstitutiveLaw::principal<2>(e)[0], 0.0013);
  ASSERT_LT(stress.maxEffectiveStress<2>(e), stress.young * 0.0013);
  double h1[kDamageHistory] = {0.0, 0.0}, h2[kDamageHistory] = {0.0, 0.0};
  EXPECT_GT(strain.update<2>(e, 0.0, h1).D, 0.0);
  EXPECT_EQ(stress.update<2>(e, 0.0, h2).D, 0.0);
}

TEST(DamageSplit, BadOptionsAreRefusedNamingTheKey) {
  for (const char* y : {"{law: pcw, strain_onset: 1e-3, strain_ultimate: 2e-3, split: miehe}",
                        "{law: rankine_mohr_coulomb, tensile_strain_onset: 0.0013, "
                        "tensile_strain_ultimate: 0.0026, compressive_strain_onset: 0.015, "
                        "friction_angle: 25, tensile_measure: energy}",
                        "{law: pcw, strain_onset: 1e-3, strain_ultimate: 2e-3, "
                        "tensile_measure: stress}"}) {
    try {
      makeLaw(y);
      ADD_FAILURE() << "accepted " << y;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_TRUE(msg.find("split") != std::string::npos ||
                  msg.find("tensile_measure") != std::string::npos)
          << msg;
    }
  }
}
