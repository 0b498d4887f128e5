#pragma once
// Kernel and kernel-gradient corrections (thesis Sec. 2.3, Eqs. 2.51-2.63).
//
// A correction is selected by name (parseCorrection; a module chooses the one it uses: the solid
// uses 2.63b; there is no scene-level key):
//
//   name                      kernel W~_ab            gradient used for grad~ W~_ab
//   "none"                    W_ab                    grad W_ab                          (2.36)
//   "shepard"                 W_ab / S_a      (2.58)  grad W_ab
//   "gradient"                W_ab                    K_a grad W_ab         (2.59-2.60 = 2.63a)
//   "shepard_gradient_2.61a"  W_ab / S_a      (2.58)  grad W~_ab (quotient rule)         (2.61a)
//   "shepard_ratio_2.61b"     W_ab / S_a      (2.58)  grad W_ab / S_a                     (2.61b)*
//   "mixed_2.63a"             alias of "gradient"                                          (2.63a)
//   "mixed_2.63b" ("mixed")   W_ab / S_a      (2.58)  K~_a grad W~_ab   (2.61a, 2.62a, 2.63b)
//   "mixed_2.63c"             W_ab / S_a      (2.58)  K~~_a grad W~~_ab (2.61b, 2.62b, 2.63c)
//
// with S_a = sum_b V_b W_ab (self b = a included, so S_a >= V_a W(0) > 0), G_a = sum_b V_b
// grad_a W_ab, and K_a = (sum_b V_b g_ab (x) r_ba)^-1 for the base gradient g_ab (2.60, 2.62).
// "mixed_2.63b" is the thesis' choice (Sec. 2.5). (*) The thesis prints 2.61b with the sum of the
// kernel gradients in the denominator, which is a vector (and zero at any symmetric interior
// point); we read it as "the gradient normalised by the Shepard sum" ([141]), a per-particle
// scalar factor. Any per-particle scalar factor cancels in K g, so 2.63c equals 2.63a up to
// round-off; both are kept for the study.
//
// Matrix corrections satisfy sum_b V_b grad~W_ab (x) r_ba = 1 (2.57): the corrected gradient and
// divergence of any linear field are exact, also at free boundaries (truncated support).
//
// Singular matrices (isolated particle, one neighbour in 2D/3D, collinear or coplanar neighbours):
// if |det M_a| <= singularTolerance * ||M_a||_F^D (or M_a is not finite), K_a is set to the
// identity, i.e. the particle falls back to its uncorrected base gradient, and the fallback is
// counted (CorrectionStats::fallbacks, and totalCorrectionFallbacks() over the process). No NaN
// is ever produced.
//
// The state is computed for any positions (current or reference configuration), any volumes
// V_b = m_b / rho_b and any neighbour list, so that e.g. the elastic solid can build its
// reference-configuration gradients grad~_0 W~_ab,0 (Eqs. 2.67-2.68) once and keep them.
#include <Eigen/LU>  // determinant() and inverse() of Mat<D> for callers of matrixOf()
#include <string>
#include <vector>

#include "libcore/kernel.hpp"
#include "libcore/neighbour_search.hpp"
#include "libcore/particle_store.hpp"
#include "libcore/types.hpp"

namespace poresph {

class Simulation;

enum class Correction {
  None,             ///< "none"
  Shepard,          ///< "shepard" (2.58), gradient uncorrected
  Gradient,         ///< "gradient" = Randles-Libersky (2.59-2.60) = 2.63a
  ShepardGradient,  ///< "shepard_gradient_2.61a": gradient of the Shepard kernel (2.61a)
  ShepardRatio,     ///< "shepard_ratio_2.61b": gradient over the Shepard sum (2.61b)
  Mixed,            ///< "mixed_2.63b": 2.61a + matrix 2.62a (2.63b), the thesis' choice
  MixedRatio,       ///< "mixed_2.63c": 2.61b + matrix 2.62b (2.63c)
};

/// Which base kernel gradient g_ab a correction uses before its matrix.
enum class BaseGradient {
  Plain,     ///< grad W_ab
  Quotient,  ///< (grad W_ab S_a - G_a W_ab) / S_a^2   (2.61a)
  Ratio,     ///< grad W_ab / S_a                       (2.61b)
};

/// Parses a correction name (see the table above; also "mixed_2.63a" and "mixed"). Throws
/// InputError naming `where` (e.g. "scene.yaml:12 key 'correction'"), the value and the valid
/// names.
Correction parseCorrection(const std::string& name, const std::string& where = "");
/// Canonical name of a correction.
std::string correctionName(Correction c);
/// All accepted names (canonical first, then aliases).
std::vector<std::string> correctionNames();

/// Gradient, Mixed, MixedRatio carry a matrix K_a.
inline bool correctionUsesMatrix(Correction c) {
  return c == Correction::Gradient || c == Correction::Mixed || c == Correction::MixedRatio;
}
/// W~ = W / S_a (2.58).
inline bool correctionUsesShepardKernel(Correction c) {
  return c != Correction::None && c != Correction::Gradient;
}
inline BaseGradient correctionBaseGradient(Correction c) {
  switch (c) {
    case Correction::ShepardGradient:
    case Correction::Mixed: return BaseGradient::Quotient;
    case Correction::ShepardRatio:
    case Correction::MixedRatio: return BaseGradient::Ratio;
    default: return BaseGradient::Plain;
  }
}
/// True when grad~W~_aa (the self pair) is not zero (base gradient Quotient): operators that sum
/// f_b grad W_ab over b (not f_b - f_a) must then add the self term.
inline bool correctionHasSelfGradient(Correction c) {
  return correctionBaseGradient(c) == BaseGradient::Quotient;
}

/// Result of one computeCorrection call.
struct CorrectionStats {
  Index particles = 0;  ///< particles corrected
  Index fallbacks = 0;  ///< particles whose matrix was singular -> identity (uncorrected)
  double minDeterminant = 0.0;  ///< smallest |det M_a| / ||M_a||^D over the non-fallback ones
};

/// Cumulative fallbacks over every computeCorrection call of the process (diagnostics).
Index totalCorrectionFallbacks();

/// Writable per-particle correction state (raw arrays indexed by real particle; null where the
/// correction does not need them). matrix: D*D per particle, column-major K_a; shepardSum: S_a;
/// shepardGradient: G_a (D per particle).
struct CorrectionArrays {
  double* matrix = nullptr;
  double* shepardSum = nullptr;
  double* shepardGradient = nullptr;
};

/// Read-only view of the per-particle correction state, used inside pair loops.
struct CorrectionView {
  Correction type = Correction::None;
  const double* matrix = nullptr;
  const double* shepardSum = nullptr;
  const double* shepardGradient = nullptr;
  double selfKernel = 0.0;  ///< W(0) of the kernel the state was computed with

  /// Corrected kernel value W~_ab from W_ab (2.58 when Shepard-based).
  double kernel(Index a, double W) const {
    return shepardSum && correctionUsesShepardKernel(type) ? W / shepardSum[a] : W;
  }
  /// Corrected kernel gradient grad~_a W~_ab from gradW = grad_a W_ab and W = W_ab
  /// (2.59, 2.61a, 2.61b, 2.63a-c). For b = a pass gradW = 0 and W = W(0) (or use selfGradient).
  template <int D>
  Vec<D> gradient(Index a, const Vec<D>& gradW, double W) const {
    Vec<D> g;
    switch (correctionBaseGradient(type)) {
      case BaseGradient::Plain: g = gradW; break;
      case BaseGradient::Quotient: {
        const double S = shepardSum[a];
        const Eigen::Map<const Vec<D>> G(shepardGradient + D * a);
        g = (gradW * S - G * W) / (S * S);
        break;
      }
      case BaseGradient::Ratio: g = gradW / shepardSum[a]; break;
    }
    if (matrix && correctionUsesMatrix(type)) {
      const Eigen::Map<const Mat<D>> K(matrix + D * D * a);
      return K * g;
    }
    return g;
  }
  /// grad~_a W~_aa: zero unless the base gradient is the quotient rule (2.61a).
  template <int D>
  Vec<D> selfGradient(Index a) const {
    if (!correctionHasSelfGradient(type)) return Vec<D>::Zero();
    return gradient<D>(a, Vec<D>::Zero(), selfKernel);
  }
  /// K_a (identity when the correction has no matrix).
  template <int D>
  Mat<D> matrixOf(Index a) const {
    if (matrix && correctionUsesMatrix(type)) return Eigen::Map<const Mat<D>>(matrix + D * D * a);
    return Mat<D>::Identity();
  }
};

/// Owning storage for a correction state (e.g. a module's reference-configuration correction
/// that is not kept in the store). resize() allocates only when the size grows.
struct CorrectionBuffer {
  std::vector<double> matrix, shepardSum, shepardGradient;
  void resize(int dim, Index n);
  CorrectionArrays arrays();
  CorrectionView view(Correction c, const Kernel& kernel) const;
};

/// Handles of the store fields holding a correction state (permuted with the particles, not
/// output, not checkpointed).
struct CorrectionFields {
  RealField matrix;           ///< prefix + "_matrix", D*D
  RealField shepardSum;       ///< prefix + "_shepard_sum", 1
  RealField shepardGradient;  ///< prefix + "_shepard_gradient", D
  CorrectionArrays arrays(ParticleStore& store) const;
  CorrectionView view(const ParticleStore& store, Correction c, const Kernel& kernel) const;
};
/// Registers (or finds) the fields "<prefix>_matrix", "<prefix>_shepard_sum" and
/// "<prefix>_shepard_gradient". Default prefix "correction"; use e.g. "reference_correction" for
/// a reference-configuration state.
CorrectionFields registerCorrectionFields(ParticleStore& store,
                                          const std::string& prefix = "correction",
                                          const std::string& owner = "core");

/// Default singularity tolerance on |det M| / ||M||_F^D.
constexpr double kCorrectionSingularTolerance = 1e-10;

/// Computes S_a, G_a and K_a for the real particles [0, nReal) (OpenMP over a).
/// x: positions (D per particle, real and ghost, the indices of `neighbours`); volume: V_b for
/// every particle (real and ghost); neighbours: lists of the real particles, self excluded.
/// Arrays not needed by `type` may be null; needed ones must hold nReal entries.
template <int D>
CorrectionStats computeCorrection(Correction type, const Kernel& kernel, const double* x,
                                  const double* volume, Index nReal,
                                  const NeighbourList& neighbours, const CorrectionArrays& out,
                                  double singularTolerance = kCorrectionSingularTolerance);

/// Runtime-dimension version of computeCorrection.
CorrectionStats computeCorrection(int dim, Correction type, const Kernel& kernel,
                                  const double* x, const double* volume, Index nReal,
                                  const NeighbourList& neighbours, const CorrectionArrays& out,
                                  double singularTolerance = kCorrectionSingularTolerance);

/// Volumes V_b = m_b / rho_b of every particle of the store (real and ghost) into `volume`
/// (resized; no allocation once large enough). Throws NumericalError on rho <= 0.
void computeVolumes(const ParticleStore& store, std::vector<double>& volume);

/// Convenience for modules: computes correction `type` at the store's current positions with
/// V = m / rho and sim.neighbours into `fields`; returns the stats.
CorrectionStats updateCorrection(Simulation& sim, Correction type, const CorrectionFields& fields,
                                 std::vector<double>& volumeScratch);

}  // namespace poresph
