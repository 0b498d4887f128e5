#pragma once
// Consistent nodal load of a uniform stress (thesis Eq. 2.76, reference corrected gradients of
// Eqs. 2.63b and 2.67-2.68).
//
// The total-Lagrangian internal force of a uniform first Piola stress P is, by Eq. 2.76,
//   f_a = sum_b V_a V_b (P g_ab - P g_ba) = P s_a,   s_a = V_a sum_b V_b (g_ab - g_ba),
// with g_ab = grad~_{a,0} W~_{ab,0} the mixed-corrected (2.63b) reference gradient of the pair seen
// from a. s_a vanishes in the bulk (symmetric families) and is non-zero within two kernel supports
// of a free surface. The external load -P s_a therefore holds the uniform stress P in exact
// discrete equilibrium: the "consistent nodal load" of the solid's pressure boundaries and of the
// rigid plates' weighted bond (docs/rigid.md). Since the corrected gradients reproduce linear
// fields (2.57), sum_a s_a (x) X_a = -(sum_a V_a) 1: a load spread as s_a acts, in the discrete
// virtual work, at the body's surface, not at the first particle row dx/2 inside.
//
// consistentLoadVectors() builds the reference families of a set of particles (neighbours within
// one kernel support, images across periodic faces), their mixed correction and s_a, once.
#include <Eigen/Dense>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include "libcore/corrections.hpp"
#include "libcore/domain.hpp"
#include "libcore/kernel.hpp"
#include "libcore/neighbour_search.hpp"
#include "libcore/periodic_images.hpp"
#include "libcore/types.hpp"

namespace poresph {

/// s_a = V_a sum_b V_b (g_ab - g_ba) for the n particles at X (D per particle; reference
/// positions) with volumes V: D values per particle in the result. Families are the particles of
/// the set within one support of `kernel`; across a periodic axis of `domain` (a period of at
/// least two supports) the families cross the face through images, so a periodic face is not a
/// surface. Corrected gradients: mixed (2.63b), computed by libcore/corrections.
template <int D>
std::vector<double> consistentLoadVectors(const Kernel& kernel, const Domain& domain,
                                          const double* X, const double* V, Index n) {
  const double support = kernel.support();
  std::vector<double> Xm(X, X + static_cast<size_t>(n) * D);
  if (n > 0)
    for (int a = 0; a < D; ++a)
      if (domain.periodic[static_cast<size_t>(a)] && domain.length(a) < 2.0 * support)
        throw std::invalid_argument("consistentLoadVectors: a periodic period shorter than "
                                    "two kernel supports");
  std::vector<Index> origin;
  appendPeriodicImages<D>(domain, support, Xm, origin);
  const Index nx = static_cast<Index>(origin.size());
  std::vector<double> Vm(static_cast<size_t>(nx));
  for (Index k = 0; k < nx; ++k) Vm[static_cast<size_t>(k)] = V[origin[static_cast<size_t>(k)]];
  std::vector<double> out(static_cast<size_t>(n) * D, 0.0);
  if (n == 0) return out;
  NeighbourSearch search;
  NeighbourList ref;
  search.build(Xm.data(), D, n, nx, support, ref);
  CorrectionBuffer buffer;
  buffer.resize(D, n);
  computeCorrection<D>(Correction::Mixed, kernel, Xm.data(), Vm.data(), n, ref, buffer.arrays());
  const CorrectionView view = buffer.view(Correction::Mixed, kernel);
#pragma omp parallel for schedule(static) if (n > 512)
  for (Index k = 0; k < n; ++k) {
    Vec<D> s = Vec<D>::Zero();
    const Eigen::Map<const Vec<D>> Xa(Xm.data() + k * D);
    for (auto p = ref.offset[static_cast<size_t>(k)]; p < ref.offset[static_cast<size_t>(k) + 1];
         ++p) {
      const Index kx = ref.index[static_cast<size_t>(p)];
      const Index b = origin[static_cast<size_t>(kx)];
      const Vec<D> r = Xa - Eigen::Map<const Vec<D>>(Xm.data() + kx * D);
      const double w = kernel.value(r.norm());
      const Vec<D> gab = view.gradient<D>(k, kernel.gradient<D>(r), w);
      const Vec<D> gba = view.gradient<D>(b, kernel.gradient<D>(Vec<D>(-r)), w);
      s += V[b] * (gab - gba);
    }
    s *= V[k];
    for (int a = 0; a < D; ++a) out[static_cast<size_t>(k) * D + a] = s[a];
  }
  return out;
}

}  // namespace poresph
