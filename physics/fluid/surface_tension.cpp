#include "physics/fluid/surface_tension.hpp"

#include <cmath>

#include "libcore/phases.hpp"
#include "libcore/simulation.hpp"

namespace poresph {

template <int D>
void addBalancedSurfaceForce(const NeighbourList& nl, const Kernel& W, Index n,
                             const BalancedCsfArrays& a, const BalancedCsfSettings& s,
                             std::vector<double>& kappaWork) {
  if (s.gamma <= 0.0) return;
  if (kappaWork.size() < static_cast<size_t>(n)) kappaWork.resize(static_cast<size_t>(n));
  const double* x = a.x;
  const double* m = a.m;
  const double* rho = a.rho;
  const std::int32_t* ph = a.phase;
  const double* col = a.colour;
  const double* kap = a.curvature;
  double* ks = kappaWork.data();
  const double rs = s.smoothingRadius * W.h();

  // Curvature of the particle: the Shepard mean (kernel weights) of the curvatures of Eq. 5.8
  // defined within rs (self included), so that every particle whose neighbourhood straddles the
  // interface gets the interface's curvature, and its particle noise is averaged.
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) {
    ks[i] = 0.0;
    // Only the interface particles (a neighbour of another colour): elsewhere grad(C) is the
    // lattice residual alone, and the cost stays proportional to the interface.
    if (ph[i] != kPhaseFluid || !a.interface[i]) continue;
    double sw = 0.0, sk = 0.0;
    if (kap[i] != 0.0) {
      sw = W.value(0.0);
      sk = sw * kap[i];
    }
    if (rs > 0.0) {
      for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
        const Index j = nl.index[static_cast<size_t>(k)];
        if (ph[j] != kPhaseFluid || kap[j] == 0.0) continue;
        double r2 = 0.0;
        for (int c = 0; c < D; ++c) r2 += (x[i * D + c] - x[j * D + c]) * (x[i * D + c] - x[j * D + c]);
        const double r = std::sqrt(r2);
        if (r >= rs) continue;
        const double w = W.value(r);
        sw += w;
        sk += w * kap[j];
      }
    }
    ks[i] = sw > 0.0 ? sk / sw : 0.0;
  }

  // f_a = gamma kappa_a grad(C)_a with grad(C) in the pressure gradient's operator:
  //   Eq. 5.2b:  (1/rho_a)... as a_p = -sum m_b (p_a/rho_a^2 + p_b/rho_b^2) grad W_ab, so
  //              a_s = +gamma kappa_a sum m_b (C_a/rho_a^2 + C_b/rho_b^2) grad W_ab;
  //   Hu-Adams:  a_p = -(1/m_a) sum (V_a^2 + V_b^2) p~_ab grad W_ab, p~ = (rho_b p_a + rho_a p_b)
  //              / (rho_a + rho_b), so a_s = +(gamma kappa_a/m_a) sum (V_a^2 + V_b^2) C~_ab grad W.
  //   Eq. 5.2a:  a_p = -sum m_b (p_a + p_b)/(rho_a rho_b) grad W_ab, so
  //              a_s = +gamma kappa_a sum m_b (C_a + C_b)/(rho_a rho_b) grad W_ab.
  // Only fluid neighbours (the wall pairs carry no surface force here).
  const double gamma = s.gamma;
  const bool hu = s.huAdams;
  const bool vol = s.volumeForm;
#pragma omp parallel for schedule(dynamic, 256)
  for (Index i = 0; i < n; ++i) {
    if (ph[i] != kPhaseFluid || a.motion[i] == kMotionFixed || ks[i] == 0.0) continue;
    const double Ca = 0.5 * (col[i] + 1.0), rhoa = rho[i], Va = m[i] / rhoa;
    Vec<D> g = Vec<D>::Zero();
    for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
      const Index j = nl.index[static_cast<size_t>(k)];
      if (ph[j] != kPhaseFluid) continue;
      const double Cb = 0.5 * (col[j] + 1.0);
      Vec<D> r;
      for (int c = 0; c < D; ++c) r[c] = x[i * D + c] - x[j * D + c];
      const double F = W.F(r.norm());
      if (F == 0.0) continue;
      const double rhob = rho[j];
      if (hu) {
        const double Vb = m[j] / rhob;
        const double ct = (rhob * Ca + rhoa * Cb) / (rhoa + rhob);
        g += ((Va * Va + Vb * Vb) * ct / m[i] * F) * r;
      } else if (vol) {
        g += (m[j] * (Ca + Cb) / (rhoa * rhob) * F) * r;
      } else {
        g += (m[j] * (Ca / (rhoa * rhoa) + Cb / (rhob * rhob)) * F) * r;
      }
    }
    const double f = gamma * ks[i];
    for (int c = 0; c < D; ++c) a.acceleration[i * D + c] += f * g[c];
  }
}

template void addBalancedSurfaceForce<1>(const NeighbourList&, const Kernel&, Index,
                                         const BalancedCsfArrays&, const BalancedCsfSettings&,
                                         std::vector<double>&);
template void addBalancedSurfaceForce<2>(const NeighbourList&, const Kernel&, Index,
                                         const BalancedCsfArrays&, const BalancedCsfSettings&,
                                         std::vector<double>&);
template void addBalancedSurfaceForce<3>(const NeighbourList&, const Kernel&, Index,
                                         const BalancedCsfArrays&, const BalancedCsfSettings&,
                                         std::vector<double>&);

}  // namespace poresph
