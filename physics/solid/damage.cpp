// Damage part of the elastic solid module (issue 13, docs/damage.md): the commit of the damage D
// at each evaluation (thesis Sec. 4.1.2 and 4.1.5, Fig. 4.4) and the damage energies (4.25-4.26b).
// The laws themselves are in constitutive_law.hpp; the stress that uses D is computed in
// ElasticSolidModule::constitutive (elastic_solid.cpp).
#include <array>
#include <cmath>

#include "libcore/simulation.hpp"
#include "physics/solid/elastic_solid.hpp"

namespace poresph::solid {

// With `damage_commit: evaluation`, at every evaluation of the rates, before the stress
// (ElasticSolidModule::constitutive); with `step_end` after the step (endOfStep above): D
// solves f(eps, D) = 0 (4.19) at the strain of this evaluation with D >= D^n (4.7) and D <= s_l;
// the stress, forces and hourglass stiffness of the same evaluation use it. In the leapfrog and
// Verlet schemes the evaluation is at x^{n+1}, so a^{n+1} holds D^{n+1} (committed after the step,
// a^{n+1} holds D^n for the next half kick: a one-step lag whose crack path moves with dt,
// docs/damage.md "The commit lag"). Repeating an
// evaluation at the same positions changes nothing (D, the history and the release are
// idempotent at a fixed strain).
// Energy released: the leapfrog's work over a step is the trapezoid of the forces at x^n (with
// D^n) and x^{n+1} (with D^{n+1}), so the energy that leaves the stored energy at the commit is
// (g(D^n) - g(D^{n+1})) times the step's mean degradable energy (phi^n + phi^{n+1}) / 2
// (phi = psi+, plus the hourglass penalty share below), which closes the balance to O(dt^2) with
// the evaluation commit (the step_end commit keeps the end point phi^{n+1});
// the end-point phi^{n+1} left an O(dt) residual. phi^n is kept per particle
// (damage_degradable_energy). With the conservative hourglass control (TL) the penalty stiffness
// of a particle's pairs is degraded by the same g(D) (hourglassPairStiffness): its share of the
// penalty energy is 1/4 alpha_a E_a sum_b V_b W0_ab |r_ab|^2 / |X_ab|^2 per unit volume of a
// (r_ab = x_ab - (F_a + F_b)/2 X_ab; half of each pair's energy 1/2 c_ab |r_ab|^2 changes with
// a's share; docs/damage.md "Hourglass control under damage").
// `damage_commit: step_end` (the default): the commit after the integrator finished the step,
// from the strain at x^{n+1} (TL: F there, the evaluation's own F when the solid has not moved
// since; the small-strain forms use the strain of the last evaluation). a^{n+1} was evaluated with D^n and acts with it for the next half kick.
void ElasticSolidModule::endOfStep(Simulation& sim, double /*dt*/) {
  if (!anyDamage_ || commitAtEvaluation_) return;
  if (formulation_ == Formulation::TotalLagrangian) {  // F at x^{n+1} (2.67)
    // the evaluation's F when the solid has not moved since (elastic_solid.cpp, kinematics)
    reuseDeformationGradient_ = true;
    kinematics(sim);
    reuseDeformationGradient_ = false;
  }
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
  double* phi = s.data(damageDegradable_);
  double* hist = damageHistory_.valid() ? s.data(damageHistory_) : nullptr;
  const bool tl = formulation_ == Formulation::TotalLagrangian;
  const double* F = tl ? s.data(defGrad_) : nullptr;
  long clipped = 0;
  // conservative hourglass control: the family and reference positions for the released penalty
  const bool hg = tl && anyHourglass_ && hourglassConservative_;
  const double* x = s.data(s.position());
  const double* m = s.data(s.mass());
  const double* X = tl ? s.data(refPos_) : nullptr;
  const std::int32_t* row = tl ? s.data(familyRow_) : nullptr;
  const Kernel& W = solidKernel(sim);
  const std::array<double, 3> L = period_;
  auto minimumImage = [&](Vec<D> d) {
    for (int a = 0; a < D; ++a)
      if (L[static_cast<size_t>(a)] > 0.0 && std::abs(d[a]) >= 0.25 * L[static_cast<size_t>(a)])
        d[a] -= L[static_cast<size_t>(a)] * std::round(d[a] / L[static_cast<size_t>(a)]);  // |d| < L/4: 0
    return d;
  };
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
    const double d0 = dmg[i];
    // step_end commit (phi is read only by the evaluation commit): skip the eigenproblem where
    // the criterion cannot move D (constitutive_law.hpp commitCannotChange; D bit for bit)
    if (!commitAtEvaluation_ && hist && law.commitCannotChange<D>(E, d0, h)) continue;
    const DamageUpdate u = law.update<D>(E, d0, h);
    dmg[i] = u.D;
    double phiNow = u.psiPlus;  // psi+ of E (the split update() made)
    const ElasticMaterial& e = mats_[static_cast<size_t>(k)];
    if (hg && e.hourglass > 0.0 && (commitAtEvaluation_ || u.D > d0)) {
      const Mat<D> Fi = Eigen::Map<const Mat<D>>(F + i * D * D);
      const Vec<D> Xi = Eigen::Map<const Vec<D>>(X + i * D);
      const Vec<D> xi = Eigen::Map<const Vec<D>>(x + i * D);
      double sum = 0.0;
      for (std::int64_t q = famOffset_[static_cast<size_t>(row[i])];
           q < famOffset_[static_cast<size_t>(row[i]) + 1]; ++q) {
        const Index j = idToIndex_[static_cast<size_t>(famIds_[static_cast<size_t>(q)])];
        const ElasticMaterial& ej = mats_[static_cast<size_t>(slotOf(mat[j]))];
        const Vec<D> Xji = minimumImage(Vec<D>(Eigen::Map<const Vec<D>>(X + j * D) - Xi));
        const Vec<D> xji = minimumImage(Vec<D>(Eigen::Map<const Vec<D>>(x + j * D) - xi));
        const double r0 = Xji.norm();
        const Vec<D> res = xji - 0.5 * (Fi + Eigen::Map<const Mat<D>>(F + j * D * D)) * Xji;
        sum += (m[j] / ej.density) * W.value(r0) / (r0 * r0) * res.squaredNorm();
      }
      phiNow += 0.25 * e.hourglass * e.young * sum;
    }
    // step_end: the end-point phi^{n+1} (the trapezoid doubles that commit's O(dt) residual on the
    // damaged bar: 7.1e-4 against 3.6e-4 of the work at dt 0.5, its lag and the end point
    // partly cancel); evaluation: the trapezoid
    const double phiPrev = phi[i] < 0.0 || !commitAtEvaluation_ ? phiNow : phi[i];
    rel[i] += (law.g(d0) - law.g(u.D)) * 0.5 * (phiPrev + phiNow);
    phi[i] = phiNow;
    // an update that raised D to s_l (once per particle: the evaluation that repeats at the cap
    // or at the same positions, e.g. after a restart, counts nothing)
    clipped += u.clipped && u.D > d0 ? 1 : 0;
  }
  clippedUpdates_ += clipped;
}

// called from constitutive() (elastic_solid.cpp)
template void ElasticSolidModule::commitDamageDim<1>(Simulation&);
template void ElasticSolidModule::commitDamageDim<2>(Simulation&);
template void ElasticSolidModule::commitDamageDim<3>(Simulation&);

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
