#pragma once
// Pairwise contact repulsion between two solid phases (thesis Eq. A.18), written once for every
// module that applies it (physics/rigid: rigid-solid, rigid-rigid, rigid-wall pairs).
//
//   F_a = -w_ab B(r) n_a,   B(r) = 2 k dx^(D-1) (1 - r / dx)  for r < dx, 0 beyond,
//
// with k a bulk modulus (A.17: k_s = rho0 c_s^2 of the stiffer side), dx the lattice spacing and
// n_a the unit vector from a to b (so -n_a pushes a away from b). The per-pair stiffness
// k dx^(D-2) gives the contact the wave speed sqrt(k / rho0) of the material.
//
// Weight: A.18 writes w_ab = m_b / (m_a + m_b), which is not symmetric in a and b when the masses
// differ (action != reaction). pairRepulsion() uses the symmetric weight
//   w_ab = 2 m_a m_b / (m_a + m_b)^2   (= 1/2 = m_b / (m_a + m_b) for equal masses),
// so the force on b is exactly minus the force on a.
#include <cmath>

#include "libcore/types.hpp"

namespace poresph {

/// Strength B(r) of Eq. A.18 (N in 3D, N/m in 2D): 2 k dx^(D-1) (1 - r / dx) for r < dx, else 0.
template <int D>
inline double repulsionStrength(double r, double k, double dx) {
  if (r >= dx) return 0.0;
  double area = 1.0;
  for (int c = 1; c < D; ++c) area *= dx;
  return 2.0 * k * area * (1.0 - r / dx);
}

/// Force on particle a from particle b (symmetric A.18); r = x_a - x_b, d = |r| (> 0).
/// The force on b is minus this.
template <int D>
inline Vec<D> pairRepulsion(const Vec<D>& r, double d, double ma, double mb, double k, double dx) {
  if (d >= dx || !(d > 0.0)) return Vec<D>::Zero();
  const double s = ma + mb;
  const double w = 2.0 * ma * mb / (s * s);
  return (w * repulsionStrength<D>(d, k, dx) / d) * r;
}

}  // namespace poresph
