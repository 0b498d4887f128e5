#include "libcore/halo.hpp"

#include <cmath>

namespace poresph {

void PeriodicHalo::wrap(ParticleStore& store, const Domain& domain) const {
  const int d = store.dimension();
  double* x = store.data(store.position());
  const Index n = store.realCount();
  for (int a = 0; a < d; ++a) {
    if (!domain.periodic[static_cast<size_t>(a)]) continue;
    const double lo = domain.lo[static_cast<size_t>(a)], len = domain.length(a);
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) {
      double& xi = x[i * d + a];
      if (xi < lo || xi >= lo + len) {
        xi = lo + (xi - lo) - len * std::floor((xi - lo) / len);
        if (xi >= lo + len) xi = lo;  // rounding guard
      }
    }
  }
}

void PeriodicHalo::build(ParticleStore& store, const Domain& domain, double width) {
  store.clearGhosts();
  sources_.clear();
  shifts_.clear();
  if (!domain.anyPeriodic()) return;
  const int d = store.dimension();
  for (int a = 0; a < d; ++a)
    if (domain.periodic[static_cast<size_t>(a)] && domain.length(a) < width)
      throw InputError("periodic length along axis " + std::to_string(a) + " (" +
                       std::to_string(domain.length(a)) +
                       " m) is shorter than the halo width (the kernel support, plus the Verlet "
                       "skin when one is set: " + std::to_string(width) + " m)");
  wrap(store, domain);
  const double* x = store.data(store.position());
  const Index n = store.realCount();
  // Serial append keeps the ghost order deterministic (independent of the thread count); the
  // test per particle is cheap compared with any pair loop.
  for (Index i = 0; i < n; ++i) {
    // Per axis the candidate shifts: 0, +L when near the lo face, -L when near the hi face
    // (both when the box is shorter than twice the support).
    double cand[3][3];
    int ncand[3] = {1, 1, 1};
    bool near = false;
    for (int a = 0; a < d; ++a) {
      cand[a][0] = 0.0;
      if (!domain.periodic[static_cast<size_t>(a)]) continue;
      const double xi = x[i * d + a], len = domain.length(a);
      if (xi < domain.lo[static_cast<size_t>(a)] + width) cand[a][ncand[a]++] = len, near = true;
      if (xi >= domain.hi[static_cast<size_t>(a)] - width) cand[a][ncand[a]++] = -len, near = true;
    }
    if (!near) continue;
    for (int k0 = 0; k0 < ncand[0]; ++k0)
      for (int k1 = 0; k1 < (d > 1 ? ncand[1] : 1); ++k1)
        for (int k2 = 0; k2 < (d > 2 ? ncand[2] : 1); ++k2) {
          if (k0 == 0 && k1 == 0 && k2 == 0) continue;
          sources_.push_back(i);
          const int k[3] = {k0, k1, k2};
          for (int a = 0; a < d; ++a) shifts_.push_back(cand[a][k[a]]);
        }
  }
  store.addGhosts(sources_, shifts_);
}

void PeriodicHalo::refresh(ParticleStore& store) const {
  if (store.ghostCount() == 0) return;
  store.refreshAllGhosts(shifts_);
}

}  // namespace poresph
