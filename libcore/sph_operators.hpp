#pragma once
// SPH interpolation and differential operators (thesis Sec. 2.1.4, Eqs. 2.33-2.46).
//
// Every operator works on raw per-particle arrays (particle store fields or any other arrays) and
// a neighbour list of the real particles over real + ghost particles (self excluded, see
// neighbour_search.hpp). Results are written for the real particles [0, nReal) only, in gather
// form (OpenMP over a, each thread writes only row a). Self contributions (b = a) are added
// explicitly where they are not zero: W(0) in interpolations, and grad~W~_aa for the Shepard
// quotient corrections (2.61a, 2.63b) in the non-difference forms.
//
// Field layout: a field with nc components stores f_a at f[nc*a .. nc*a+nc). The gradient of an
// nc-component field writes nc*D values per particle, column-major: out[nc*D*a + i + nc*j] =
// d f_i / d x_j, i.e. for nc = 1 the gradient vector and for nc = D the D x D tensor
// (grad f)_ij = df_i/dx_j = sum_b V_b f_b,i (grad W_ab)_j (Eq. 2.34, f (x) grad W), which maps on
// ParticleStore::mat<D>.
//
// Corrections (corrections.hpp) enter through SphGeometry::correction: the kernel value W_ab is
// replaced by W~_ab and grad_a W_ab by grad~_a W~_ab in interpolation, gradient and divergence.
// The second-derivative operators (2.44-2.46) always use the plain F_ab (2.38).
#include <utility>
#include <vector>

#include "libcore/corrections.hpp"
#include "libcore/kernel.hpp"
#include "libcore/neighbour_search.hpp"
#include "libcore/types.hpp"

namespace poresph {

/// Which discrete first-derivative form (Eqs. 2.34-2.35, 2.40-2.42).
enum class DerivativeForm {
  /// sum_b V_b f_b (x) grad~W~_ab, self term included (2.34, 2.35; 2.91a "without symmetry
  /// terms").
  Standard,
  /// sum_b V_b (f_b - f_a) (x) grad~W~_ab, Phi = 1 (2.40a, 2.42a; 2.91b "with symmetry terms").
  /// Exactly zero for a constant field.
  Difference,
  /// (1/rho_a) sum_b m_b (f_b - f_a) (x) grad~W~_ab, Phi = rho (2.40b, 2.42b). Exactly zero for a
  /// constant field. Needs mass and density.
  DensityWeighted,
  /// rho_a sum_b m_b (f_b/rho_b^2 + f_a/rho_a^2) (x) grad~W~_ab, Phi = 1/rho (2.40c, 2.42c), the
  /// symmetrical (momentum-conserving) form: with the plain gradient sum_a V_a grad f_a = 0 exactly
  /// (pairwise antisymmetric). Not zero for a constant field at a truncated support. Needs mass
  /// and density.
  Symmetric,
};

/// Mean of Phi across a pair in the diffusion operator.
enum class PairMean {
  Arithmetic,  ///< Phi_a + Phi_b (2.44)
  Harmonic,    ///< 4 Phi_a Phi_b / (Phi_a + Phi_b) (2.45, Cleary and Monaghan, for jumps)
};

/// The particle set an operator runs on (non-owning).
struct SphGeometry {
  int dim = 0;                  ///< must equal the template D of the operator called
  Index nReal = 0;              ///< results are written for [0, nReal)
  const double* x = nullptr;    ///< positions, D per particle (real and ghost)
  const double* volume = nullptr;   ///< V_b = m_b / rho_b, every particle (real and ghost)
  const double* mass = nullptr;     ///< m_b (DensityWeighted, Symmetric only)
  const double* density = nullptr;  ///< rho_b (DensityWeighted, Symmetric only)
  const NeighbourList* neighbours = nullptr;
  const Kernel* kernel = nullptr;
  CorrectionView correction;    ///< type None by default
};

/// Interpolation f_a = sum_b V_b f_b W~_ab, self included (Eq. 2.33; 2.58 with Shepard).
/// f: nc per particle; out: nc per real particle.
template <int D>
void interpolate(const SphGeometry& g, const double* f, int nc, double* out);

/// Gradient of an nc-component field (Eqs. 2.34, 2.40a-c). out: nc*D per real particle (layout
/// above).
template <int D>
void gradient(const SphGeometry& g, DerivativeForm form, const double* f, int nc, double* out);

/// Divergence of a D-vector field (Eqs. 2.35, 2.42a-c). out: 1 per real particle.
template <int D>
void divergence(const SphGeometry& g, DerivativeForm form, const double* f, double* out);

/// Diffusion term div(Phi grad f) of an nc-component field (Eqs. 2.44, 2.45):
/// sum_b V_b mean(Phi_a, Phi_b) (f_a - f_b) F_ab. phi: 1 per particle, or null for Phi = 1 (then
/// mean = 2, the Laplacian in any dimension). out: nc per real particle.
template <int D>
void diffusion(const SphGeometry& g, const double* f, int nc, const double* phi, PairMean mean,
               double* out);

/// All second derivatives d2f/dx_alpha dx_gamma of a scalar field (Eqs. 2.46a-c, Phi = 1).
/// out: D*D per real particle (column-major, symmetric).
template <int D>
void secondDerivatives(const SphGeometry& g, const double* f, double* out);

/// Pairwise contributions of the divergence at one particle a, in neighbour-list order, self pair
/// last (for the Tables 2.1-2.2 breakdown). Returns pairs (b, contribution).
template <int D>
std::vector<std::pair<Index, double>> divergencePairs(const SphGeometry& g, DerivativeForm form,
                                                      const double* f, Index a);

// ---- run-time dimension versions (dispatch on g.dim to the templates above) ----
void interpolate(const SphGeometry& g, const double* f, int nc, double* out);
void gradient(const SphGeometry& g, DerivativeForm form, const double* f, int nc, double* out);
void divergence(const SphGeometry& g, DerivativeForm form, const double* f, double* out);
void diffusion(const SphGeometry& g, const double* f, int nc, const double* phi, PairMean mean,
               double* out);
void secondDerivatives(const SphGeometry& g, const double* f, double* out);

}  // namespace poresph
