// Validation item 1 of issue 13: material-point driver (no SPH) of every damage law of
// physics/solid/constitutive_law (PCW 4.21/4.27, AT-1 4.22/4.30a, AT-2 4.22/4.30b, strain-based
// Rankine/Mohr-Coulomb of Table 5.1). Strain paths are applied in small increments and D is
// committed after each increment with the same ConstitutiveLaw::update the solid calls at the
// end of every step. Asserted: the uniaxial peak at the strain the law predicts; secant
// unloading with no damage growth on unloading and reloading; stiffness recovered in
// compression after tensile damage (unilateral effect, 4.17-4.20) while shear stays degraded;
// dissipation increments never negative; the released energy equal to the dissipation of
// Eq. 4.26b (int Yc dD) within 1 %.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <vector>

#include "physics/solid/constitutive_law.hpp"
#include "physics/solid/elastic_solid.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
using namespace poresph::solid;

namespace {

constexpr double kE = 3e9, kNu = 0.1;  // COx, Table 5.1
constexpr double kEps0 = 0.0013, kEpsU = 0.0026;

ConstitutiveLaw makeLaw(const std::string& yaml, int dim) {
  double lam = 0.0, mu = 0.0;
  lameParameters(kE, kNu, dim, Plane::Strain, lam, mu);
  ConstitutiveLaw law(kE, lam, mu, dim == 1 ? 1 : 3);
  law.configureDamage(ParameterSet(YAML::Load(yaml), "test", "damage"));
  return law;
}

struct Law {
  const char* name;
  const char* yaml;
};
const Law kLaws[] = {
    {"pcw", "{law: pcw, strain_onset: 0.0013, strain_ultimate: 0.0026}"},
    {"at1", "{law: at1, strain_onset: 0.0013}"},
    {"at2", "{law: at2, critical_energy_release: 2535.0}"},  // = 1/2 E eps0^2 x 1 (see below)
    {"rankine_mohr_coulomb",
     "{law: rankine_mohr_coulomb, tensile_strain_onset: 0.0013, tensile_strain_ultimate: 0.0026, "
     "compressive_strain_onset: 0.015, friction_angle: 25}"},
};

// Expected uniaxial-stress peak strain of each law (docs/damage.md): eps_0 for PCW, AT-1 and
// Rankine; AT-2 peaks at psi = Yc0/3, eps = sqrt(2 Yc0 / (3 E)).
double expectedPeak(const ConstitutiveLaw& law) {
  if (law.type == DamageLawType::AT2) return std::sqrt(2.0 * law.yc0 / (3.0 * kE));
  return kEps0;
}

template <int D>
struct Driver {
  const ConstitutiveLaw& law;
  Mat<D> eps = Mat<D>::Zero();
  double dmg = 0.0;
  double hist[kDamageHistory] = {0.0, 0.0};
  double released = 0.0, minIncrement = 0.0;
  double work = 0.0;  ///< int sigma : d eps along the path (trapezoid of each increment)
  // one increment to eps1: D committed at the new strain (as at the end of an SPH step)
  void to(const Mat<D>& e1) {
    const Mat<D> s0 = sigma(), de = e1 - eps;
    eps = e1;
    const DamageUpdate u = law.update<D>(eps, dmg, hist);
    EXPECT_GE(u.D, dmg);
    minIncrement = std::min(minIncrement, u.released);
    released += u.released;
    dmg = u.D;
    work += 0.5 * (s0 + sigma()).cwiseProduct(de).sum();
  }
  Mat<D> sigma() const { return law.stress<D>(eps, dmg); }
  // energy balance (Eq. 4.25 at a point, no kinetic energy): work in = stored (4.17 with the
  // committed D) + released (4.26), relative to the work; it needs the released energy: the
  // check below also asserts that the released share is far above the tolerance
  double balance() const { return (work - law.energy<D>(eps, dmg) - released) / work; }
};

// Asserts the point's energy balance within 1 % of the work (issue 13: "the balance closes to
// 1 % in every validation"), with a released share of at least 5 % of the work (so a law that
// released nothing, or stored the undamaged energy, fails), and records it.
template <int D>
void checkBalance(const Driver<D>& d, const std::string& what, const std::string& path, double secs) {
  EXPECT_LT(std::abs(d.balance()), 0.01) << what << " " << path << ": work " << d.work << ", stored "
                                         << d.law.template energy<D>(d.eps, d.dmg) << ", released " << d.released;
  EXPECT_GT(d.released / d.work, 0.05) << what << " " << path;
  test::recordValidation({"damage_material_point_" + what, "energy balance residual / work in, " + path,
                          std::abs(d.balance()), 0.0, std::abs(d.balance()), "2000-4000 increments per leg", secs,
                          "< 1 %", "Eq. 4.25 at a material point (stored 4.17 + released 4.26 = work)"});
}

}  // namespace

// Uniaxial stress (1D): 0 -> 1.6 eps_peak -> 0 -> 1.6 eps_peak -> 2 eps_peak -> -2 eps_peak.
TEST(DamageMaterialPoint, UniaxialLoadingUnloadingReloadingThenCompression) {
  for (const Law& L : kLaws) {
    SCOPED_TRACE(L.name);
    test::Stopwatch clock;
    const ConstitutiveLaw law = makeLaw(L.yaml, 1);
    Driver<1> d{law};
    const double ep = expectedPeak(law);
    const int n = 4000;
    auto leg = [&](double a, double b, auto&& each) {
      for (int k = 1; k <= n; ++k) {
        Mat<1> e;
        e(0, 0) = a + (b - a) * k / n;
        d.to(e);
        each(e(0, 0), d.sigma()(0, 0));
      }
    };
    // loading: peak
    double peakS = 0.0, peakE = 0.0;
    leg(0.0, 1.6 * ep, [&](double e, double s) {
      if (s > peakS) { peakS = s; peakE = e; }
    });
    const double errPeak = std::abs(peakE - ep) / ep;
    EXPECT_LT(errPeak, 2e-3) << "peak at " << peakE << " expected " << ep;
    EXPECT_GT(d.dmg, 0.05);
    // unloading: D frozen, secant sigma = g(D) E eps
    const double D1 = d.dmg, secant = law.g(D1) * kE;
    double secErr = 0.0;
    leg(1.6 * ep, 0.0, [&](double e, double s) {
      EXPECT_EQ(d.dmg, D1);
      if (e > 0.0) secErr = std::max(secErr, std::abs(s - secant * e) / (secant * 1.6 * ep));
    });
    EXPECT_LT(secErr, 1e-12);
    // reloading to the previous maximum: no growth
    leg(0.0, 1.6 * ep, [&](double, double) { EXPECT_EQ(d.dmg, D1); });
    leg(1.6 * ep, 2.0 * ep, [&](double, double) {});
    EXPECT_GT(d.dmg, D1);
    const double D2 = d.dmg;
    // compression after tensile damage: undamaged stiffness (1D: all bulk), D frozen until the
    // compressive branch (Rankine/Mohr-Coulomb only, far beyond -2 eps_peak here)
    leg(2.0 * ep, -2.0 * ep, [&](double, double) {});
    EXPECT_EQ(d.dmg, D2);
    Mat<1> e1;
    e1(0, 0) = -2.0 * ep;
    const double s1 = law.stress<1>(e1, d.dmg)(0, 0);
    e1(0, 0) = -1.0 * ep;
    const double s2 = law.stress<1>(e1, d.dmg)(0, 0);
    const double kc = (s2 - s1) / ep;
    EXPECT_NEAR(kc / kE, 1.0, 1e-12);
    EXPECT_GE(d.minIncrement, 0.0);
    checkBalance(d, L.name, "uniaxial", clock.seconds());
    // dissipation: released energy against int_0^D Yc dD (4.26b with Yc(D))
    if (law.type != DamageLawType::RankineMohrCoulomb) {
      const double phi = law.dissipationIntegral(d.dmg);
      EXPECT_NEAR(d.released / phi, 1.0, 0.01);
      test::recordValidation(
          {std::string("damage_material_point_") + L.name,
           "released energy / int Yc dD (Eq. 4.26b), uniaxial", d.released / phi, 1.0,
           std::abs(d.released / phi - 1.0), "4000 increments per leg", clock.seconds(), "< 1 %",
           "Eq. 4.26b with Yc(D) (Sec. 4.3.1)"});
    }
    test::recordValidation({std::string("damage_material_point_") + L.name,
                            "uniaxial peak strain", peakE, ep, errPeak,
                            "4000 increments per leg", clock.seconds(), "< 0.2 %",
                            "closed form of the law (docs/damage.md)"});
  }
}

// Volumetric tension then compression in plane strain and 3D: the bulk stiffness comes back in
// compression (unilateral effect), the shear stiffness stays g(D) mu.
template <int D>
void volumetric(const Law& L) {
  const ConstitutiveLaw law = makeLaw(L.yaml, D);
  Driver<D> d{law};
  const int n = 2000;
  // tension up to damage ~0.3-0.9, then compression
  const double emax = 2.0 * kEps0 / std::sqrt(3.0), emin = -emax;
  for (int k = 1; k <= n; ++k) d.to(Mat<D>(emax * k / n * Mat<D>::Identity()));
  const double Dt = d.dmg;
  EXPECT_GT(Dt, 0.05);
  // tension: secant bulk modulus degraded
  const double s = d.sigma().trace() / (D * emax);  // = g(D) (k0 + ...) per direction
  const ConstitutiveLaw& l = law;
  const double undamaged = l.stress<D>(Mat<D>(emax * Mat<D>::Identity()), 0.0).trace() / (D * emax);
  EXPECT_NEAR(s / undamaged, l.g(Dt), 1e-12);
  for (int k = 1; k <= n; ++k)
    d.to(Mat<D>((emax + (emin - emax) * k / n) * Mat<D>::Identity()));
  EXPECT_EQ(d.dmg, Dt);  // pure compression: no deviator, Mohr-Coulomb equivalent 0
  // compression: bulk recovered, i.e. only the deviatoric stress differs from the undamaged one
  // (in plane strain e 1 has the deviator e 1 - 2e/3 1 of the 3D split, eps_zz = 0)
  const Mat<D> c = emin * Mat<D>::Identity();
  const Mat<D> cd = c - c.trace() / l.bulkDim * Mat<D>::Identity();
  const Mat<D> bulkChange =
      l.stress<D>(c, d.dmg) - l.stress<D>(c, 0.0) - 2.0 * (l.g(d.dmg) - 1.0) * l.mu * cd;
  EXPECT_LT(bulkChange.norm(), 1e-9 * l.stress<D>(c, 0.0).norm());
  // shear increment on the compressed state: mu(D) = g(D) mu0
  Mat<D> g = Mat<D>::Zero();
  g(0, 1) = g(1, 0) = 1e-5;
  const double tau = (l.stress<D>(Mat<D>(c + g), d.dmg) - l.stress<D>(c, d.dmg))(0, 1);
  EXPECT_NEAR(tau / (2.0 * l.mu * 1e-5), l.g(d.dmg), 1e-9);
  EXPECT_GE(d.minIncrement, 0.0);
  checkBalance(d, L.name, D == 2 ? "volumetric, plane strain" : "volumetric, 3D", 0.0);
}

TEST(DamageMaterialPoint, VolumetricTensionThenCompressionPlaneStrainAnd3D) {
  for (const Law& L : kLaws) {
    SCOPED_TRACE(L.name);
    volumetric<2>(L);
    volumetric<3>(L);
  }
}

// Rankine/Mohr-Coulomb compressive branch (3D uniaxial strain in compression, a path with a
// deviator: the unilateral split keeps the bulk part, so only the deviatoric stress softens): no
// damage below the Mohr-Coulomb onset eps_c0, then the equivalent stress (1 - D) E kappa_c
// peaks at kappa_c = eps_c0 and falls linearly to 0 at eps_cu (D capped at s_l).
TEST(DamageMaterialPoint, MohrCoulombCompressiveBranch) {
  const ConstitutiveLaw law = makeLaw(kLaws[3].yaml, 3);
  Driver<3> d{law};
  // kappa_c per unit compressive strain along this path (undamaged effective stress)
  Mat<3> unit = Mat<3>::Zero();
  unit(0, 0) = -1.0;
  double hist[kDamageHistory] = {0.0, 0.0};
  law.update<3>(Mat<3>(1e-6 * unit), 0.0, hist);
  const double ratio = hist[1] / 1e-6;
  const double eOnset = law.epsC0 / ratio, eUlt = law.epsCu / ratio;
  double peakQ = 0.0, peakE = 0.0, firstDamage = 0.0;
  const int n = 4000;
  for (int k = 1; k <= n; ++k) {
    const double e = 1.2 * eUlt * k / n;
    d.to(Mat<3>(e * unit));
    if (d.dmg > 0.0 && firstDamage == 0.0) firstDamage = e;
    const double q = (1.0 - d.dmg) * law.young * d.hist[1];  // equivalent stress
    if (q > peakQ) { peakQ = q; peakE = e; }
  }
  EXPECT_NEAR(firstDamage / eOnset, 1.0, 2e-3);
  EXPECT_NEAR(peakE / eOnset, 1.0, 2e-3);
  EXPECT_NEAR(peakQ / (law.young * law.epsC0), 1.0, 2e-3);
  EXPECT_DOUBLE_EQ(d.dmg, law.limit);
  // the deviatoric stress has softened to (1 - s_l) of the undamaged one, the mean stress not
  const Mat<3> s = d.sigma(), s0 = law.stress<3>(d.eps, 0.0);
  EXPECT_NEAR((s(0, 0) - s(1, 1)) / (s0(0, 0) - s0(1, 1)), 1.0 - law.limit, 1e-9);
  EXPECT_NEAR(s.trace() / s0.trace(), 1.0, 1e-12);
  EXPECT_GE(d.minIncrement, 0.0);
  checkBalance(d, "rankine_mohr_coulomb", "Mohr-Coulomb compressive branch, 3D", 0.0);
}
