#pragma once
// Surface-tension forms beside the CSF of FluidModule::forcesD (Eq. 1.9 with the colour gradient
// of Eq. 5.7 and the curvature of Eq. 5.8). Issue 14: spurious currents.
//
// Balanced-force CSF (option `surface_tension_form: balanced`): the CSF force
// f = gamma kappa grad(C) (Eq. 1.9, C = (colour + 1)/2 the liquid indicator, 1 inside the liquid,
// 0 in the gas) with grad(C) discretised by the SAME operator as the pressure gradient of the
// run (Eq. 5.2b, or Hu & Adams' inter-particle-averaged form with its density-weighted pair
// value), and kappa the particle's own curvature (Eq. 5.8, smoothed over its neighbours). For a
// pressure field p = p_0 + gamma kappa C with kappa uniform the pressure force and the surface
// force cancel particle by particle, whatever the particle arrangement: a circle at rest with
// its Laplace jump is a discrete equilibrium (the Francois et al. 2006 balanced-force idea in
// the SPH operator). The standard CSF instead spreads gamma kappa n over a band with another
// operator, so the residual between the two is a force that drives spurious currents.
#include <cstdint>
#include <vector>

#include "libcore/kernel.hpp"
#include "libcore/neighbour_search.hpp"
#include "libcore/types.hpp"

namespace poresph {

/// Arrays read by the balanced-force surface tension (the store's; ghosts included where noted).
struct BalancedCsfArrays {
  const double* x = nullptr;      ///< positions (ghosts)
  const double* m = nullptr;      ///< masses (ghosts)
  const double* rho = nullptr;    ///< densities (ghosts)
  const std::int32_t* phase = nullptr;   ///< phases (ghosts)
  const std::int32_t* motion = nullptr;  ///< motion flags (real particles)
  const double* colour = nullptr;        ///< colour +1 liquid / -1 gas (ghosts)
  const double* curvature = nullptr;     ///< kappa of Eq. 5.8, 0 where not defined (ghosts)
  const std::int32_t* interface = nullptr;  ///< 1: a neighbour of another colour (real)
  double* acceleration = nullptr;        ///< accumulated into (real particles)
};

struct BalancedCsfSettings {
  double gamma = 0.0;     ///< surface tension (N/m)
  bool huAdams = false;   ///< pressure gradient of the run: Hu & Adams (true) or Eq. 5.2b
  bool volumeForm = false;  ///< pressure gradient of the run: Eq. 5.2a (`pressure_gradient: volume`)
  /// Curvature used: the Shepard mean of the nonzero curvatures over the neighbours within
  /// smoothing_radius x h (0: the particle's own kappa only).
  double smoothingRadius = 2.0;
};

/// Adds the balanced-force CSF acceleration to the fluid particles [0, n). kappaWork is resized
/// when it is smaller than n (once: not inside the time loop after the first step).
template <int D>
void addBalancedSurfaceForce(const NeighbourList& nl, const Kernel& W, Index n,
                             const BalancedCsfArrays& a, const BalancedCsfSettings& s,
                             std::vector<double>& kappaWork);

}  // namespace poresph
