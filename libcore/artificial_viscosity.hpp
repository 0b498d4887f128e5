#pragma once
// Monaghan's artificial viscosity, thesis Eqs. 2.64-2.65, written once for every module (fluid,
// solid, coupling). The acceleration of particle a from neighbour b is -m_b Pi_ab grad_a W_ab.
#include "libcore/types.hpp"

namespace poresph {

/// Pi_ab = (alpha c_ab nu_ab + beta nu_ab^2) / rho_ab for approaching pairs (v_ab . r_ab < 0),
/// 0 otherwise, with nu_ab = -h v_ab . r_ab / (|r_ab|^2 + 0.01 h^2) (Eq. 2.65), c_ab and rho_ab
/// the means of the two particles' sound speeds and densities (Eq. 2.64). v_ab = v_a - v_b,
/// r_ab = x_a - x_b.
template <int D>
inline double artificialViscosityPi(const Vec<D>& vab, const Vec<D>& rab, double h, double alpha,
                                    double beta, double ca, double cb, double rhoa,
                                    double rhob) {
  const double vr = vab.dot(rab);
  if (vr >= 0.0) return 0.0;
  const double nu = -h * vr / (rab.squaredNorm() + 0.01 * h * h);           // 2.65
  return (alpha * 0.5 * (ca + cb) * nu + beta * nu * nu) / (0.5 * (rhoa + rhob));  // 2.64
}

}  // namespace poresph
