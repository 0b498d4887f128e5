// Kernel and kernel-gradient corrections (thesis Eqs. 2.56-2.63). See corrections.hpp.
#include "libcore/corrections.hpp"

#include <Eigen/Dense>
#include <atomic>
#include <cmath>
#include <limits>
#include <sstream>

#include "libcore/simulation.hpp"

namespace poresph {

namespace {

struct NamedCorrection {
  const char* name;
  Correction type;
};

// Canonical names first, then aliases.
const NamedCorrection kNames[] = {
    {"none", Correction::None},
    {"shepard", Correction::Shepard},
    {"gradient", Correction::Gradient},
    {"shepard_gradient_2.61a", Correction::ShepardGradient},
    {"shepard_ratio_2.61b", Correction::ShepardRatio},
    {"mixed_2.63b", Correction::Mixed},
    {"mixed_2.63c", Correction::MixedRatio},
    {"mixed_2.63a", Correction::Gradient},
    {"mixed", Correction::Mixed},
};

std::atomic<Index> gTotalFallbacks{0};

}  // namespace

Correction parseCorrection(const std::string& name, const std::string& where) {
  for (const auto& n : kNames)
    if (name == n.name) return n.type;
  std::ostringstream os;
  if (!where.empty()) os << where << ": ";
  os << "unknown correction '" << name << "'; valid names are:";
  bool first = true;
  for (const auto& n : kNames) {
    os << (first ? " " : ", ") << n.name;
    first = false;
  }
  throw InputError(os.str());
}

std::string correctionName(Correction c) {
  for (const auto& n : kNames)
    if (n.type == c) return n.name;
  return "none";
}

std::vector<std::string> correctionNames() {
  std::vector<std::string> out;
  for (const auto& n : kNames) out.emplace_back(n.name);
  return out;
}

Index totalCorrectionFallbacks() { return gTotalFallbacks.load(); }

void CorrectionBuffer::resize(int dim, Index n) {
  matrix.resize(static_cast<size_t>(dim * dim * n));
  shepardSum.resize(static_cast<size_t>(n));
  shepardGradient.resize(static_cast<size_t>(dim * n));
}

CorrectionArrays CorrectionBuffer::arrays() {
  return CorrectionArrays{matrix.data(), shepardSum.data(), shepardGradient.data()};
}

CorrectionView CorrectionBuffer::view(Correction c, const Kernel& kernel) const {
  CorrectionView v;
  v.type = c;
  v.matrix = matrix.data();
  v.shepardSum = shepardSum.data();
  v.shepardGradient = shepardGradient.data();
  v.selfKernel = kernel.value(0.0);
  return v;
}

CorrectionArrays CorrectionFields::arrays(ParticleStore& store) const {
  return CorrectionArrays{store.data(matrix), store.data(shepardSum), store.data(shepardGradient)};
}

CorrectionView CorrectionFields::view(const ParticleStore& store, Correction c,
                                      const Kernel& kernel) const {
  CorrectionView v;
  v.type = c;
  v.matrix = store.data(matrix);
  v.shepardSum = store.data(shepardSum);
  v.shepardGradient = store.data(shepardGradient);
  v.selfKernel = kernel.value(0.0);
  return v;
}

CorrectionFields registerCorrectionFields(ParticleStore& store, const std::string& prefix,
                                          const std::string& owner) {
  const int d = store.dimension();
  CorrectionFields f;
  f.matrix = store.addReal(prefix + "_matrix", d * d, kFieldNone, owner);
  f.shepardSum = store.addReal(prefix + "_shepard_sum", 1, kFieldNone, owner);
  f.shepardGradient = store.addReal(prefix + "_shepard_gradient", d, kFieldNone, owner);
  return f;
}

template <int D>
CorrectionStats computeCorrection(Correction type, const Kernel& kernel, const double* x,
                                  const double* volume, Index nReal,
                                  const NeighbourList& nl, const CorrectionArrays& out,
                                  double singularTolerance) {
  CorrectionStats stats;
  stats.particles = nReal;
  if (type == Correction::None) return stats;
  if (nReal > nl.realCount())
    throw std::invalid_argument("computeCorrection: neighbour list shorter than nReal");
  const bool needShepard = correctionUsesShepardKernel(type);
  const bool needMatrix = correctionUsesMatrix(type);
  const BaseGradient base = correctionBaseGradient(type);
  if ((needShepard && (!out.shepardSum || !out.shepardGradient)) || (needMatrix && !out.matrix))
    throw std::invalid_argument("computeCorrection: missing output array for '" +
                                correctionName(type) + "'");
  const double w0 = kernel.value(0.0);
  Index fallbacks = 0;
  double minDet = std::numeric_limits<double>::infinity();

#pragma omp parallel for schedule(dynamic, 64) reduction(+ : fallbacks) reduction(min : minDet)
  for (Index a = 0; a < nReal; ++a) {
    const Eigen::Map<const Vec<D>> xa(x + D * a);
    const auto begin = nl.offset[static_cast<size_t>(a)];
    const auto end = nl.offset[static_cast<size_t>(a) + 1];
    // Shepard sum (2.58, self included) and sum of volume-weighted kernel gradients.
    double S = volume[a] * w0;
    Vec<D> G = Vec<D>::Zero();
    if (needShepard) {
      for (auto k = begin; k < end; ++k) {
        const Index b = nl.index[static_cast<size_t>(k)];
        const Vec<D> rab = xa - Eigen::Map<const Vec<D>>(x + D * b);
        const double r = rab.norm();
        S += volume[b] * kernel.value(r);
        G += volume[b] * rab * kernel.F(r);
      }
      out.shepardSum[a] = S;
      Eigen::Map<Vec<D>>(out.shepardGradient + D * a) = G;
    }
    if (!needMatrix) continue;
    // M_a = sum_b V_b g_ab (x) r_ba (2.60, 2.62a, 2.62b); the self pair has r_aa = 0.
    Mat<D> M = Mat<D>::Zero();
    const double invS = 1.0 / S;
    for (auto k = begin; k < end; ++k) {
      const Index b = nl.index[static_cast<size_t>(k)];
      const Vec<D> rab = xa - Eigen::Map<const Vec<D>>(x + D * b);
      const double r = rab.norm();
      Vec<D> g = rab * kernel.F(r);
      if (base == BaseGradient::Quotient)
        g = (g * S - G * kernel.value(r)) * (invS * invS);
      else if (base == BaseGradient::Ratio)
        g *= invS;
      M.noalias() -= volume[b] * g * rab.transpose();  // r_ba = -r_ab
    }
    Eigen::Map<Mat<D>> K(out.matrix + D * D * a);
    const double norm = M.norm();
    const double det = M.determinant();
    double scale = 1.0;
    for (int d = 0; d < D; ++d) scale *= norm;
    const double rel = scale > 0.0 ? std::abs(det) / scale : 0.0;
    if (std::isfinite(det) && std::isfinite(norm) && rel > singularTolerance) {
      K = M.inverse();
      if (!K.allFinite()) {
        K.setIdentity();
        ++fallbacks;
      } else {
        minDet = std::min(minDet, rel);
      }
    } else {
      K.setIdentity();
      ++fallbacks;
    }
  }
  stats.fallbacks = fallbacks;
  stats.minDeterminant = std::isfinite(minDet) ? minDet : 0.0;
  gTotalFallbacks += fallbacks;
  return stats;
}

template CorrectionStats computeCorrection<1>(Correction, const Kernel&, const double*,
                                              const double*, Index, const NeighbourList&,
                                              const CorrectionArrays&, double);
template CorrectionStats computeCorrection<2>(Correction, const Kernel&, const double*,
                                              const double*, Index, const NeighbourList&,
                                              const CorrectionArrays&, double);
template CorrectionStats computeCorrection<3>(Correction, const Kernel&, const double*,
                                              const double*, Index, const NeighbourList&,
                                              const CorrectionArrays&, double);

CorrectionStats computeCorrection(int dim, Correction type, const Kernel& kernel,
                                  const double* x, const double* volume, Index nReal,
                                  const NeighbourList& neighbours, const CorrectionArrays& out,
                                  double singularTolerance) {
  return dispatchDimension(dim, [&](auto d) {
    return computeCorrection<decltype(d)::value>(type, kernel, x, volume, nReal, neighbours, out,
                                                 singularTolerance);
  });
}

void computeVolumes(const ParticleStore& store, std::vector<double>& volume) {
  const Index n = store.size();
  if (static_cast<Index>(volume.size()) < n) volume.resize(static_cast<size_t>(n));
  const double* m = store.data(store.mass());
  const double* rho = store.data(store.density());
  double* V = volume.data();
  Index bad = -1;
#pragma omp parallel for schedule(static) reduction(max : bad)
  for (Index i = 0; i < n; ++i) {
    if (!(rho[i] > 0.0)) {
      bad = std::max(bad, i);
      V[i] = 0.0;
    } else {
      V[i] = m[i] / rho[i];
    }
  }
  if (bad >= 0)
    throw NumericalError("computeVolumes: density of particle " + std::to_string(bad) +
                         " is not positive (" + std::to_string(rho[bad]) + ")");
}

CorrectionStats updateCorrection(Simulation& sim, Correction type, const CorrectionFields& fields,
                                 std::vector<double>& volumeScratch) {
  computeVolumes(sim.store, volumeScratch);
  return computeCorrection(sim.dimension(), type, sim.kernel,
                           sim.store.data(sim.store.position()), volumeScratch.data(),
                           sim.store.realCount(), sim.neighbours, fields.arrays(sim.store));
}

}  // namespace poresph
