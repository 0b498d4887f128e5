#pragma once
// Constitutive laws of the elastic solid (issue 13): one small interface for the isotropic
// elastic law and the elasto-damage laws of thesis Chapter 4 (GSM framework, Eqs. 4.1-4.20) with
// the degradation functions PCW (4.21, 4.27 / 5.9 / B.1), AT (4.22) and the critical energy
// releases Yc = Yc0 (AT-1, PCW) or 2 D Yc0 (AT-2) (4.23, 4.30), plus the strain-based Rankine
// (tension) + Mohr-Coulomb (compression, shear) criterion of Table 5.1. See docs/damage.md.
//
// The law is written for a strain tensor of the run's dimension. It works with any strain
// measure: the Green-Lagrange strain E_GL (total Lagrangian: S from E_GL) or the small strain eps
// (small-strain forms: sigma from eps). All laws share the unilateral split of Eqs. 4.17-4.20:
//   psi(eps, D) = g(D) psi+(eps) + psi-(eps),
//   psi+ = 1/2 k0 <tr eps>+^2 + mu0 eps^d : eps^d,   psi- = 1/2 k0 <tr eps>-^2,
// i.e. the bulk stiffness is degraded only for tr eps >= 0 and the shear always; psi, sigma and
// Y are continuous at tr eps = 0 (Eq. 4.17-4.18). k(D)/k0 = mu(D)/mu0 = g(D) (4.21, 4.22).
// The bulk/deviatoric split uses the 3D trace/deviator in 3D and plane strain (eps_zz = 0), the
// 2D one in plane stress (k0 = lambda* + mu) and the 1D one in 1D (uniaxial stress: k0 = E, no
// deviator), so that with D = 0 every law is exactly sigma = lambda tr(eps) 1 + 2 mu eps.
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "libcore/parameters.hpp"
#include "libcore/types.hpp"

namespace poresph::solid {

enum class DamageLawType { Elastic, PCW, AT1, AT2, RankineMohrCoulomb };

/// Which part of the energy the damage degrades (key `split:` of a `damage:` section).
/// Volumetric: the thesis' unilateral split (4.17): bulk degraded for tr eps >= 0, shear always.
/// Spectral: Miehe-type split on the principal strains e_i (issue 13, localisation under
/// confinement, docs/damage.md): psi+ = lambda/2 <tr eps>+^2 + mu sum <e_i>+^2, psi- = the
/// rest; a compressed principal direction keeps its stiffness and so does the shear between two
/// compressed directions. Not in the thesis; an option, never the default.
enum class EnergySplit { Volumetric, Spectral };

/// Tensile measure of the Rankine branch (key `tensile_measure:`). Strain: the largest
/// principal strain (the default, as in [126] "strain based"). Stress: the largest principal
/// undamaged (effective) stress over E, i.e. Rankine's sigma_1 <= f_t with f_t = E eps_t0
/// (Tab. 5.1: 4 MPa / 3 GPa = 0.0013): the same onset in uniaxial tension, but a compressed
/// point whose Poisson or shear strain makes e_1 > eps_t0 with sigma_1 < f_t does not damage.
enum class TensileMeasure { Strain, Stress };

/// Name of a law as written in scenes (elastic, pcw, at1, at2, rankine_mohr_coulomb).
std::string damageLawName(DamageLawType t);

/// Number of history values per particle besides D (Rankine/Mohr-Coulomb: the largest tensile
/// and compressive equivalent strains reached; GSM laws: none, D is its own history).
constexpr int kDamageHistory = 2;

/// Result of one damage update at a material point.
struct DamageUpdate {
  double D = 0.0;         ///< new damage, >= the old one, <= the limit s_l
  bool clipped = false;   ///< the criterion asked for more than s_l
  double released = 0.0;  ///< energy density released at fixed strain: (g(D0) - g(D)) psi+ >= 0
  double psiPlus = 0.0;   ///< the degradable energy psi+ of the strain (the commit's phi)
};

class ConstitutiveLaw {
 public:
  ConstitutiveLaw() = default;
  /// Elastic law with Lame parameters of the run's dimension (lameParameters()) and the
  /// dimension of the bulk/deviator split (3: 3D and plane strain, 2: plane stress, 1: 1D).
  ConstitutiveLaw(double young, double lambda, double mu, int bulkDim);

  /// Reads the `damage:` section of an elastic material (keys: law, critical_energy_release or
  /// the strains that set it, limit, ...); unknown and missing keys are named by ParameterSet.
  void configureDamage(const ParameterSet& section);

  // ---- parameters (after configure) ----
  DamageLawType type = DamageLawType::Elastic;
  double young = 0.0, lambda = 0.0, mu = 0.0;
  int bulkDim = 3;
  double k0 = 0.0;       ///< bulk modulus of the split, lambda + 2 mu / bulkDim
  double a = 1.0;        ///< PCW alpha^ (4.21)
  double b = 0.0;        ///< PCW beta^ (4.21), = eps_u / eps_0 - 1 (4.27)
  double yc0 = 0.0;      ///< initial critical energy release Yc0 [Pa = J/m^3] (4.23)
  double limit = 0.99;   ///< s_l: damage never exceeds it (Tab. 4.2)
  // Rankine / Mohr-Coulomb (strain based, Table 5.1)
  double epsT0 = 0.0, epsTu = 0.0;  ///< tensile onset / ultimate strain (max principal strain)
  double epsC0 = 0.0, epsCu = 0.0;  ///< compressive onset / ultimate Mohr-Coulomb equivalent strain
  double sinPhi = 0.0;              ///< sin of the friction angle
  EnergySplit splitType = EnergySplit::Volumetric;    ///< `split:` (all damage laws)
  TensileMeasure tensileMeasure = TensileMeasure::Strain;  ///< `tensile_measure:` (Rankine)

  bool damages() const { return type != DamageLawType::Elastic; }

  // ---- scalar functions of D ----
  /// Degradation g(D) = k(D)/k0 = mu(D)/mu0: PCW (1 - a D)/(1 + b D) (4.21), AT (1 - D)^2
  /// (4.22), Rankine/Mohr-Coulomb 1 - D, elastic 1.
  double g(double D) const {
    switch (type) {
      case DamageLawType::PCW: return (1.0 - a * D) / (1.0 + b * D);
      case DamageLawType::AT1:
      case DamageLawType::AT2: return (1.0 - D) * (1.0 - D);
      case DamageLawType::RankineMohrCoulomb: return 1.0 - D;
      default: return 1.0;
    }
  }
  /// g'(D) (< 0 for every damage law).
  double gPrime(double D) const {
    switch (type) {
      case DamageLawType::PCW: return -(a + b) / ((1.0 + b * D) * (1.0 + b * D));
      case DamageLawType::AT1:
      case DamageLawType::AT2: return -2.0 * (1.0 - D);
      case DamageLawType::RankineMohrCoulomb: return -1.0;
      default: return 0.0;
    }
  }
  /// Critical energy release Yc(D): Yc0 (AT-1, PCW, 4.23a) or 2 D Yc0 (AT-2, 4.23b / 4.30b).
  double yc(double D) const { return type == DamageLawType::AT2 ? 2.0 * D * yc0 : yc0; }
  /// Dissipated energy density of Eq. 4.26b with Yc(D) (Sec. 4.3.1): int_0^D Yc = Yc0 D or
  /// Yc0 D^2 (AT-2). Rankine/Mohr-Coulomb has no Yc: 0 (its dissipation is the released energy).
  double dissipationIntegral(double D) const {
    if (type == DamageLawType::AT2) return yc0 * D * D;
    if (type == DamageLawType::PCW || type == DamageLawType::AT1) return yc0 * D;
    return 0.0;
  }
  /// psi+ at which damage starts from D = 0 (f = 0 in 4.19): Yc0/(a + b) (PCW), Yc0/2 (AT-1),
  /// 0 (AT-2, no elastic range).
  double onsetEnergy() const {
    if (type == DamageLawType::PCW) return yc0 / (a + b);
    if (type == DamageLawType::AT1) return 0.5 * yc0;
    return 0.0;
  }

  // ---- strain split (4.17) ----
  struct Split {
    double tr = 0.0;    ///< tr eps (in-plane trace in 2D: eps_zz = 0 in plane strain)
    double dev2 = 0.0;  ///< eps^d : eps^d with the deviator of dimension bulkDim
    // spectral split only: sum of the squared positive / negative principal strains (the
    // out-of-plane one is 0 in plane strain and not part of the plane-stress law)
    bool spectral = false;
    double pos2 = 0.0, neg2 = 0.0;
  };
  template <int D>
  Split split(const Mat<D>& eps) const {
    if (splitType == EnergySplit::Spectral) return splitSpectral<D>(eps, eigenvalues<D>(eps));
    Split s;
    s.tr = eps.trace();
    const double m = s.tr / bulkDim;
    s.dev2 = eps.squaredNorm() - 2.0 * m * s.tr + D * m * m;  // in-plane part of eps^d : eps^d
    if (bulkDim > D) s.dev2 += (bulkDim - D) * m * m;         // out-of-plane (plane strain)
    if (s.dev2 < 0.0) s.dev2 = 0.0;                            // round-off (1D: exactly 0)
    return s;
  }
  /// Degradable energy psi+ = 1/2 k0 <tr>+^2 + mu0 eps^d:eps^d (4.17, tr >= 0 branch).
  /// Spectral split: lambda/2 <tr>+^2 + mu sum <e_i>+^2.
  double psiPlus(const Split& s) const {
    const double tp = std::max(s.tr, 0.0);
    if (s.spectral) return 0.5 * lambda * tp * tp + mu * s.pos2;
    return 0.5 * k0 * tp * tp + mu * s.dev2;
  }
  /// Energy kept whatever D: psi- = 1/2 k0 <tr>-^2 (4.17, tr <= 0 branch).
  /// Spectral split: lambda/2 <tr>-^2 + mu sum <e_i>-^2.
  double psiMinus(const Split& s) const {
    const double tm = std::min(s.tr, 0.0);
    if (s.spectral) return 0.5 * lambda * tm * tm + mu * s.neg2;
    return 0.5 * k0 * tm * tm;
  }
  /// The spectral split from the principal strains e already computed (update() solves the
  /// eigenproblem once for the split, the principal strains and the effective stress).
  template <int D>
  Split splitSpectral(const Mat<D>& eps, const Vec<D>& e) const {
    Split s;
    s.tr = eps.trace();
    s.spectral = true;
    for (int k = 0; k < D; ++k) (e[k] > 0.0 ? s.pos2 : s.neg2) += e[k] * e[k];
    return s;
  }
  /// Free energy rho w(eps, D) of Eq. 4.17 (4.1 for D = 0).
  double energy(const Split& s, double D) const { return g(D) * psiPlus(s) + psiMinus(s); }
  template <int D>
  double energy(const Mat<D>& eps, double dmg) const { return energy(split<D>(eps), dmg); }
  /// Energy release rate Y = -d(rho w)/dD = -g'(D) psi+ (4.6, 4.18b).
  double energyRelease(const Split& s, double D) const { return -gPrime(D) * psiPlus(s); }

  /// Stress of Eq. 4.18a: k tr(eps) 1 + 2 mu(D) eps^d with k = k(D) for tr >= 0, k0 otherwise
  /// (continuous at tr = 0). With D = 0: lambda tr(eps) 1 + 2 mu eps (2.74, 2.84).
  /// Spectral split: g [lambda <tr>+ 1 + 2 mu eps+] + lambda <tr>- 1 + 2 mu eps-, eps+- the
  /// positive / negative principal parts (the derivative of its energy; continuous).
  template <int D>
  Mat<D> stress(const Mat<D>& eps, double dmg) const {
    const double gd = g(dmg);
    const double tr = eps.trace();
    if (splitType == EnergySplit::Spectral) {
      if (gd == 1.0) {
        // undamaged (g(0) = 1 for every law): sum_k 2 mu e_k n_k n_k^T = 2 mu eps, so the split
        // cannot matter and the eigenproblem is skipped (equal to round-off of the eigenvectors;
        // docs/performance.md "The rock scene's step"). The damage criterion's principal values
        // are solved in update(), at the commit, not here.
        Mat<D> s = 2.0 * mu * eps;
        s.diagonal().array() += lambda * tr;
        return s;
      }
      Mat<D> s = Mat<D>::Zero();
      if constexpr (D == 1) {
        s(0, 0) = 2.0 * mu * eps(0, 0) * (eps(0, 0) > 0.0 ? gd : 1.0);
      } else {
        Eigen::SelfAdjointEigenSolver<Mat<D>> es(eps);
        for (int k = 0; k < D; ++k) {
          const double ek = es.eigenvalues()[k];
          const Vec<D> nk = es.eigenvectors().col(k);
          s.noalias() += (2.0 * mu * ek * (ek > 0.0 ? gd : 1.0)) * (nk * nk.transpose());
        }
      }
      s.diagonal().array() += lambda * tr * (tr > 0.0 ? gd : 1.0);
      return s;
    }
    const double kEff = tr >= 0.0 ? gd * k0 : k0;
    const double muEff = gd * mu;
    Mat<D> s = 2.0 * muEff * eps;
    s.diagonal().array() += (kEff - 2.0 * muEff / bulkDim) * tr;
    return s;
  }

  /// Modulus lambda + 2 mu of the fastest wave the law can carry in any state: g(D) <= 1 and k0
  /// is kept in compression, so the undamaged P-wave modulus bounds the tangent (secant) one;
  /// the time step of Eq. 2.50 is taken with it (a softening branch has a negative tangent,
  /// which only slows waves down).
  double waveModulus() const { return lambda + 2.0 * mu; }

  /// Solves f = Y - Yc(D) = 0 (4.19) for D at the energy psi+ (closed forms, see damage.md):
  ///   PCW:  (1 + b D)^2 = (a + b) psi+ / Yc0,  AT-1: D = 1 - Yc0 / (2 psi+),
  ///   AT-2: D = psi+ / (psi+ + Yc0);  0 below the onset. Not clipped, not made irreversible.
  double criterionDamage(double psiPlusValue) const;

  /// End-of-step commit at one material point: D from the new strain, never below D0
  /// (irreversibility, 4.7) nor above s_l; `history` holds kDamageHistory values
  /// (Rankine/Mohr-Coulomb equivalent strains; untouched by the GSM laws).
  template <int D>
  DamageUpdate update(const Mat<D>& eps, double D0, double* history) const {
    // one eigenproblem for the split, the principal strains and the effective stress (the
    // three used to solve it each: the same values, ~3x less work per commit)
    const bool rmc = type == DamageLawType::RankineMohrCoulomb;
    Vec<D> ev = Vec<D>::Zero();
    if (rmc || splitType == EnergySplit::Spectral) ev = eigenvalues<D>(eps);
    const Split s = splitType == EnergySplit::Spectral ? splitSpectral<D>(eps, ev) : split<D>(eps);
    double target = 0.0;
    if (rmc) {
      const Vec<3> e = principalOf<D>(ev);  // descending, with eps_zz = 0 in plane strain
      history[0] = std::max(history[0], tensileMeasure == TensileMeasure::Stress
                                            ? maxEffectiveStressOf<D>(eps.trace(), ev) / young
                                            : e[0]);
      // Mohr-Coulomb on the undamaged (effective) stress: ((s1 - s3) + (s1 + s3) sin phi) /
      // (1 - sin phi) = f_c in uniaxial compression; as a strain: divided by E.
      const double trv = s.tr;
      const double s1 = lambda * trv + 2.0 * mu * e[0], s3 = lambda * trv + 2.0 * mu * e[2];
      const double mc = ((s1 - s3) + (s1 + s3) * sinPhi) / ((1.0 - sinPhi) * young);
      history[1] = std::max(history[1], mc);
      target = std::max(linearSoftening(history[0], epsT0, epsTu),
                        linearSoftening(history[1], epsC0, epsCu));
    } else if (damages()) {
      target = criterionDamage(psiPlus(s));
    }
    DamageUpdate r;
    r.D = std::max(D0, target);
    if (r.D > limit) {
      r.D = limit;
      r.clipped = target > limit;
    }
    r.psiPlus = psiPlus(s);
    r.released = (g(D0) - g(r.D)) * r.psiPlus;
    return r;
  }

  /// True when the commit at this strain can change neither D nor a history value above its
  /// onset (Rankine/Mohr-Coulomb in 3D): Gershgorin bounds of the principal strains,
  /// e_1 <= max_i (eps_ii + sum_{j!=i} |eps_ij|), e_3 >= min_i (eps_ii - sum_{j!=i} |eps_ij|),
  /// bound both equivalent strains of update() from above; where each bound (with a margin far
  /// above the round-off of the eigenvalues) is at most max(history, onset), update() would
  /// return D0 bit for bit (D0 at least the damage of the histories, as after every commit), so
  /// its eigenproblem is not needed. Only the history values below
  /// the onset (which enter nothing) and psi+ are then not refreshed (docs/performance.md).
  template <int D>
  bool commitCannotChange(const Mat<D>& eps, double D0, const double* history) const {
    if constexpr (D != 3) {
      return false;
    } else {
      if (type != DamageLawType::RankineMohrCoulomb) return false;
      // D0 already holds what the histories ask for (always so after a commit; checked, cheap)
      if (!(D0 <= limit) || !(std::max(linearSoftening(history[0], epsT0, epsTu),
                                       linearSoftening(history[1], epsC0, epsCu)) <= D0))
        return false;
      double up = -std::numeric_limits<double>::infinity(), lo = -up, norm2 = 0.0;
      for (int i = 0; i < 3; ++i) {
        double r = 0.0;
        for (int j = 0; j < 3; ++j) {
          norm2 += eps(i, j) * eps(i, j);
          if (j != i) r += std::abs(eps(i, j));
        }
        up = std::max(up, eps(i, i) + r);
        lo = std::min(lo, eps(i, i) - r);
      }
      const double tr = eps.trace();
      // margin: 1e-9 of the largest term (the eigenvalues are good to ~1e-15 of |eps|)
      const double margin = 1e-9 * (std::abs(lambda) * std::abs(tr) + 2.0 * mu * std::sqrt(norm2) + 1e-300) / young;
      const double tensile = tensileMeasure == TensileMeasure::Stress
                                 ? (lambda * tr + 2.0 * mu * up) / young
                                 : up;
      if (!(tensile + margin <= std::max(history[0], epsT0))) return false;
      const double s1 = lambda * tr + 2.0 * mu * up, s3 = lambda * tr + 2.0 * mu * lo;
      const double mc = ((s1 - s3) + (s1 + s3) * sinPhi) / ((1.0 - sinPhi) * young);
      return mc + 4.0 * margin / (1.0 - sinPhi) <= std::max(history[1], epsC0);
    }
  }

  /// Damage of a linear softening of the equivalent stress E kappa from its onset kappa0 to zero
  /// at kappaU: 1 - kappa0 (kappaU - kappa) / (kappa (kappaU - kappa0)); 0 below the onset.
  static double linearSoftening(double kappa, double kappa0, double kappaU) {
    if (!(kappa > kappa0)) return 0.0;
    if (kappa >= kappaU) return 1.0;
    return 1.0 - kappa0 * (kappaU - kappa) / (kappa * (kappaU - kappa0));
  }

  /// Eigenvalues of a symmetric D x D matrix (any order).
  template <int D>
  static Vec<D> eigenvalues(const Mat<D>& m) {
    if constexpr (D == 1) {
      return Vec<D>(m(0, 0));
    } else {
      Eigen::SelfAdjointEigenSolver<Mat<D>> es(m, Eigen::EigenvaluesOnly);
      return es.eigenvalues();
    }
  }

  /// Largest principal value of the undamaged stress lambda tr(eps) 1 + 2 mu eps, the
  /// out-of-plane sigma_zz = lambda tr(eps) included in plane strain (bulkDim 3 in 2D) and 0
  /// in plane stress; 1D: E eps.
  template <int D>
  double maxEffectiveStress(const Mat<D>& eps) const {
    return maxEffectiveStressOf<D>(eps.trace(), eigenvalues<D>(eps));
  }
  /// The same from the trace and the eigenvalues e of eps.
  template <int D>
  double maxEffectiveStressOf(double tr, const Vec<D>& e) const {
    double s1 = lambda * tr + 2.0 * mu * e.maxCoeff();
    if (D == 2) s1 = std::max(s1, bulkDim == 3 ? lambda * tr : 0.0);
    return s1;
  }

  /// Principal strains in descending order, as 3 values (1D: eps, 0, 0 sorted; 2D plane strain
  /// and plane stress: the in-plane ones and 0 for the out-of-plane direction).
  template <int D>
  static Vec<3> principal(const Mat<D>& eps) {
    return principalOf<D>(eigenvalues<D>(eps));
  }
  /// The same from the eigenvalues e of eps (any order).
  template <int D>
  static Vec<3> principalOf(const Vec<D>& e) {
    double v[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < D; ++k) v[k] = e[k];
    std::sort(v, v + 3, [](double x, double y) { return x > y; });
    return Vec<3>(v[0], v[1], v[2]);
  }
};

}  // namespace poresph::solid
