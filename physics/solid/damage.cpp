// Damage part of the elastic solid module (issue 13, docs/damage.md): the end-of-step commit of
// the damage D (thesis Sec. 4.1.2 and 4.1.5, Fig. 4.4) and the damage energies (4.25-4.26b).
// The laws themselves are in constitutive_law.hpp; the stress that uses D is computed in
// ElasticSolidModule::constitutive (elastic_solid.cpp).
#include <cmath>

#include "libcore/simulation.hpp"
#include "physics/solid/elastic_solid.hpp"

namespace poresph::solid {

// After every completed step: D^{n+1} solves f(eps^{n+1}, D) = 0 (4.19) with D^{n+1} >= D^n
// (4.7) and D^{n+1} <= s_l. The total-Lagrangian strain is recomputed at x^{n+1} (the strain
// field holds that of the step's last rate evaluation); the small-strain forms use the strain of
// the last evaluation (their strain needs the current neighbour correction, rebuilt at the next
// evaluation). The energy released at fixed strain, (g(D^n) - g(D^{n+1})) psi+, is added to the
// particle's dissipation, so elastic + released energy is continuous across the commit.
void ElasticSolidModule::endOfStep(Simulation& sim, double /*dt*/) {
  if (!anyDamage_) return;
  if (formulation_ == Formulation::TotalLagrangian) kinematics(sim);  // F at x^{n+1} (2.67)
  dispatchDimension(sim.dimension(), [&](auto d) { commitDamageDim<decltype(d)::value>(sim); });
}

template <int D>
void ElasticSolidModule::commitDamageDim(Simulation& sim) {
  ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mat = s.data(s.material());
  double* eps = s.data(strain_);
  double* dmg = s.data(damage_);
  double* rel = s.data(damageReleased_);
  double* hist = damageHistory_.valid() ? s.data(damageHistory_) : nullptr;
  const bool tl = formulation_ == Formulation::TotalLagrangian;
  const double* F = tl ? s.data(defGrad_) : nullptr;
  long clipped = 0;
#pragma omp parallel for schedule(static) reduction(+ : clipped) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    const int k = slotOf(mat[i]);
    if (k < 0) continue;
    const ConstitutiveLaw& law = mats_[static_cast<size_t>(k)].law;
    if (!law.damages()) continue;
    Mat<D> E;
    if (tl) {
      const Mat<D> Fi = Eigen::Map<const Mat<D>>(F + i * D * D);
      E = 0.5 * (Fi.transpose() * Fi - Mat<D>::Identity());  // 2.71
      Eigen::Map<Mat<D>>(eps + i * D * D) = E;
    } else {
      E = Eigen::Map<const Mat<D>>(eps + i * D * D);
    }
    double local[kDamageHistory] = {0.0, 0.0};
    double* h = hist ? hist + i * kDamageHistory : local;
    const DamageUpdate u = law.update<D>(E, dmg[i], h);
    dmg[i] = u.D;
    rel[i] += u.released;
    clipped += u.clipped ? 1 : 0;
  }
  clippedUpdates_ += clipped;
}

double ElasticSolidModule::damageDissipation(const Simulation& sim) const {
  if (!anyDamage_) return 0.0;
  const ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mat = s.data(s.material());
  const double* m = s.data(s.mass());
  const double* rel = s.data(damageReleased_);
  const std::int32_t* src = anyMirror_ ? s.data(mirror_) : nullptr;
  double e = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : e) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    const int k = slotOf(mat[i]);
    if (k < 0 || (src && src[i] > 0)) continue;  // mirror layers are images
    e += m[i] / mats_[static_cast<size_t>(k)].density * rel[i];
  }
  return e;
}

double ElasticSolidModule::damageDissipationYc(const Simulation& sim) const {
  if (!anyDamage_) return 0.0;
  const ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mat = s.data(s.material());
  const double* m = s.data(s.mass());
  const double* dmg = s.data(damage_);
  const std::int32_t* src = anyMirror_ ? s.data(mirror_) : nullptr;
  double e = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : e) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    const int k = slotOf(mat[i]);
    if (k < 0 || (src && src[i] > 0)) continue;
    const ElasticMaterial& em = mats_[static_cast<size_t>(k)];
    e += m[i] / em.density * em.law.dissipationIntegral(dmg[i]);  // 4.26b with Yc(D)
  }
  return e;
}

}  // namespace poresph::solid
