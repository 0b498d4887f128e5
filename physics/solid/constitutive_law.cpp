// Constitutive laws of the elastic solid: see constitutive_law.hpp and docs/damage.md. Equation
// numbers are those of the thesis (../shared/seeds/002_*.txt from the repository root), Chapter 4.
#include "physics/solid/constitutive_law.hpp"

#include <cmath>
#include <sstream>

namespace poresph::solid {

std::string damageLawName(DamageLawType t) {
  switch (t) {
    case DamageLawType::PCW: return "pcw";
    case DamageLawType::AT1: return "at1";
    case DamageLawType::AT2: return "at2";
    case DamageLawType::RankineMohrCoulomb: return "rankine_mohr_coulomb";
    default: return "elastic";
  }
}

ConstitutiveLaw::ConstitutiveLaw(double youngModulus, double lam, double shear, int bulkDimension)
    : young(youngModulus), lambda(lam), mu(shear), bulkDim(bulkDimension) {
  k0 = lambda + 2.0 * mu / bulkDim;
}

void ConstitutiveLaw::configureDamage(const ParameterSet& p) {
  const std::string law = p.choice("law", {"pcw", "at1", "at2", "rankine_mohr_coulomb"});
  type = law == "pcw"   ? DamageLawType::PCW
         : law == "at1" ? DamageLawType::AT1
         : law == "at2" ? DamageLawType::AT2
                        : DamageLawType::RankineMohrCoulomb;
  const Range unitOpen{0.0, 1.0, true, true};
  limit = p.real("limit", 0.99, unitOpen);  // s_l, Tab. 4.2
  // energy split: the thesis' unilateral one (4.17) or the spectral option (docs/damage.md,
  // "Damage under confinement")
  splitType = p.choice("split", "volumetric", {"volumetric", "spectral"}) == "spectral"
                  ? EnergySplit::Spectral
                  : EnergySplit::Volumetric;

  if (type == DamageLawType::RankineMohrCoulomb) {
    // Strain-based Rankine (tension) + Mohr-Coulomb (compression, shear), Table 5.1.
    epsT0 = p.real("tensile_strain_onset", Range::positive());
    epsTu = p.real("tensile_strain_ultimate", Range::positive());
    if (!(epsTu > epsT0))
      p.fail("tensile_strain_ultimate", "must exceed tensile_strain_onset (" +
                                            std::to_string(epsT0) + ")");
    epsC0 = p.real("compressive_strain_onset", Range::positive());
    epsCu = p.real("compressive_strain_ultimate", epsC0 * epsTu / epsT0, Range::positive());
    if (!(epsCu > epsC0))
      p.fail("compressive_strain_ultimate", "must exceed compressive_strain_onset (" +
                                                std::to_string(epsC0) + ")");
    const double phi = p.real("friction_angle", Range{0.0, 90.0, false, true});
    sinPhi = std::sin(phi * M_PI / 180.0);
    tensileMeasure = p.choice("tensile_measure", "strain", {"strain", "stress"}) == "stress"
                         ? TensileMeasure::Stress
                         : TensileMeasure::Strain;
    p.finish();
    return;
  }

  // GSM laws (Sec. 4.1): Yc0 given, or set from the uniaxial-stress strain at which the law
  // peaks (psi+ = 1/2 E eps^2 in uniaxial stress, whatever the dimension).
  const bool hasYc = p.has("critical_energy_release");
  const bool hasOnset = p.has("strain_onset");
  if (type == DamageLawType::PCW) {
    a = p.real("a", 1.0, Range::positive());  // 4.27: a = 1
    if (p.has("b") && p.has("strain_ultimate"))
      p.fail("b", "give either b or strain_ultimate (b = strain_ultimate / strain_onset - 1, "
                  "Eq. 4.27), not both");
    if (p.has("b")) {
      b = p.real("b", Range::positive());
    } else {
      const double e0 = p.real("strain_onset", Range::positive());
      const double eu = p.real("strain_ultimate", Range::positive());
      if (!(eu > e0))
        p.fail("strain_ultimate", "must exceed strain_onset (" + std::to_string(e0) +
                                      "): b = eps_u / eps_0 - 1 > 0 (Eq. 4.27)");
      b = eu / e0 - 1.0;
    }
  }
  if (type == DamageLawType::AT2 && hasOnset)
    p.fail("strain_onset", "AT-2 (Yc = 2 D Yc0, Eq. 4.23b) has no elastic range, so no onset "
                           "strain: give critical_energy_release");
  if (hasYc && hasOnset && type != DamageLawType::PCW)
    p.fail("strain_onset", "give either critical_energy_release or strain_onset, not both");
  if (hasYc) {
    yc0 = p.real("critical_energy_release", Range::positive());
  } else {
    if (!hasOnset)
      p.fail("law", "law '" + law + "' needs critical_energy_release (Yc0 [Pa])" +
                        std::string(type == DamageLawType::AT2 ? "" : " or strain_onset"));
    const double e0 = p.real("strain_onset", Range::positive());
    const double psi0 = 0.5 * young * e0 * e0;
    // onset psi+ = Yc0 / (a + b) (PCW) or Yc0 / 2 (AT-1): Yc0 from psi+ at eps_0
    yc0 = type == DamageLawType::PCW ? (a + b) * psi0 : 2.0 * psi0;
  }
  if (type == DamageLawType::PCW && a * limit >= 1.0)
    p.fail("a", "g(D) = (1 - a D)/(1 + b D) must stay positive up to the damage limit s_l = " +
                    std::to_string(limit) + ": a < 1 / s_l");
  p.finish();
}

double ConstitutiveLaw::criterionDamage(double psi) const {
  if (!(psi > 0.0)) return 0.0;
  switch (type) {
    case DamageLawType::PCW: {
      // Y = (a + b) psi+ / (1 + b D)^2 = Yc0 (g' of 4.21 in 4.18b, Yc of 4.27)
      const double r = std::sqrt((a + b) * psi / yc0);
      return r > 1.0 ? (r - 1.0) / b : 0.0;
    }
    case DamageLawType::AT1:  // 2 (1 - D) psi+ = Yc0 (4.22, 4.30a)
      return psi > 0.5 * yc0 ? 1.0 - 0.5 * yc0 / psi : 0.0;
    case DamageLawType::AT2:  // 2 (1 - D) psi+ = 2 D Yc0 (4.22, 4.30b)
      return psi / (psi + yc0);
    default: return 0.0;
  }
}

}  // namespace poresph::solid
