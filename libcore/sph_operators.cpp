// SPH interpolation and differential operators (thesis Eqs. 2.33-2.46). See sph_operators.hpp.
#include "libcore/sph_operators.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace poresph {

namespace {

template <int D>
void check(const SphGeometry& g, const char* what) {
  if (g.dim != D)
    throw std::invalid_argument(std::string(what) + ": geometry dimension " +
                                std::to_string(g.dim) + " != operator dimension " +
                                std::to_string(D));
  if (!g.x || !g.volume || !g.neighbours || !g.kernel)
    throw std::invalid_argument(std::string(what) + ": geometry incomplete (x, volume, "
                                "neighbours and kernel are required)");
  if (g.nReal > g.neighbours->realCount())
    throw std::invalid_argument(std::string(what) + ": neighbour list shorter than nReal");
}

void checkMassDensity(const SphGeometry& g, DerivativeForm form, const char* what) {
  if ((form == DerivativeForm::DensityWeighted || form == DerivativeForm::Symmetric) &&
      (!g.mass || !g.density))
    throw std::invalid_argument(std::string(what) +
                                ": the density-weighted and symmetric forms need mass and density");
}

// Weights of f_b and f_a in a pair term of a first-derivative form:
// term = (wb f_b + wa f_a) (x) grad~W~_ab; the sum is then multiplied by 1/rho_a (2.40b) or
// rho_a (2.40c).
struct FormWeights {
  double wb = 0.0;
  double wa = 0.0;
};

inline FormWeights pairWeights(const SphGeometry& g, DerivativeForm form, Index a, Index b) {
  switch (form) {
    case DerivativeForm::Standard: return {g.volume[b], 0.0};
    case DerivativeForm::Difference: return {g.volume[b], -g.volume[b]};
    case DerivativeForm::DensityWeighted: return {g.mass[b], -g.mass[b]};
    case DerivativeForm::Symmetric: {
      const double rb = g.density[b], ra = g.density[a];
      return {g.mass[b] / (rb * rb), g.mass[b] / (ra * ra)};
    }
  }
  return {};
}

// Self pair (b = a) weights: only the Standard and Symmetric forms have a non-zero f weight.
inline double selfWeight(const SphGeometry& g, DerivativeForm form, Index a) {
  switch (form) {
    case DerivativeForm::Standard: return g.volume[a];
    case DerivativeForm::Symmetric: return 2.0 * g.mass[a] / (g.density[a] * g.density[a]);
    default: return 0.0;
  }
}

// grad~W~_ab for the pair (a, b) with r_ab = x_a - x_b.
template <int D>
inline Vec<D> pairGradient(const SphGeometry& g, Index a, const Vec<D>& rab) {
  const double r = rab.norm();
  const Vec<D> gradW = rab * g.kernel->F(r);
  if (g.correction.type == Correction::None) return gradW;
  const double W = correctionBaseGradient(g.correction.type) == BaseGradient::Quotient
                       ? g.kernel->value(r)
                       : 0.0;
  return g.correction.gradient<D>(a, gradW, W);
}

}  // namespace

template <int D>
void interpolate(const SphGeometry& g, const double* f, int nc, double* out) {
  check<D>(g, "interpolate");
  const NeighbourList& nl = *g.neighbours;
  const double w0 = g.kernel->value(0.0);
#pragma omp parallel for schedule(dynamic, 64)
  for (Index a = 0; a < g.nReal; ++a) {
    const Eigen::Map<const Vec<D>> xa(g.x + D * a);
    double* oa = out + nc * a;
    const double wself = g.volume[a] * g.correction.kernel(a, w0);
    for (int c = 0; c < nc; ++c) oa[c] = wself * f[nc * a + c];
    for (auto k = nl.offset[static_cast<size_t>(a)]; k < nl.offset[static_cast<size_t>(a) + 1];
         ++k) {
      const Index b = nl.index[static_cast<size_t>(k)];
      const double r = (xa - Eigen::Map<const Vec<D>>(g.x + D * b)).norm();
      const double w = g.volume[b] * g.correction.kernel(a, g.kernel->value(r));
      for (int c = 0; c < nc; ++c) oa[c] += w * f[nc * b + c];
    }
  }
}

template <int D>
void gradient(const SphGeometry& g, DerivativeForm form, const double* f, int nc, double* out) {
  check<D>(g, "gradient");
  checkMassDensity(g, form, "gradient");
  const NeighbourList& nl = *g.neighbours;
  const bool self = correctionHasSelfGradient(g.correction.type);
#pragma omp parallel for schedule(dynamic, 64)
  for (Index a = 0; a < g.nReal; ++a) {
    const Eigen::Map<const Vec<D>> xa(g.x + D * a);
    double* oa = out + nc * D * a;
    for (int c = 0; c < nc * D; ++c) oa[c] = 0.0;
    const double* fa = f + nc * a;
    for (auto k = nl.offset[static_cast<size_t>(a)]; k < nl.offset[static_cast<size_t>(a) + 1];
         ++k) {
      const Index b = nl.index[static_cast<size_t>(k)];
      const Vec<D> rab = xa - Eigen::Map<const Vec<D>>(g.x + D * b);
      const Vec<D> gw = pairGradient<D>(g, a, rab);
      const FormWeights w = pairWeights(g, form, a, b);
      const double* fb = f + nc * b;
      for (int j = 0; j < D; ++j)
        for (int i = 0; i < nc; ++i) oa[i + nc * j] += (w.wb * fb[i] + w.wa * fa[i]) * gw[j];
    }
    if (self) {
      const double ws = selfWeight(g, form, a);
      if (ws != 0.0) {
        const Vec<D> gs = g.correction.selfGradient<D>(a);
        for (int j = 0; j < D; ++j)
          for (int i = 0; i < nc; ++i) oa[i + nc * j] += ws * fa[i] * gs[j];
      }
    }
    double outer = 1.0;
    if (form == DerivativeForm::DensityWeighted) outer = 1.0 / g.density[a];
    if (form == DerivativeForm::Symmetric) outer = g.density[a];
    if (outer != 1.0)
      for (int c = 0; c < nc * D; ++c) oa[c] *= outer;
  }
}

template <int D>
void divergence(const SphGeometry& g, DerivativeForm form, const double* f, double* out) {
  check<D>(g, "divergence");
  checkMassDensity(g, form, "divergence");
  const NeighbourList& nl = *g.neighbours;
  const bool self = correctionHasSelfGradient(g.correction.type);
#pragma omp parallel for schedule(dynamic, 64)
  for (Index a = 0; a < g.nReal; ++a) {
    const Eigen::Map<const Vec<D>> xa(g.x + D * a);
    const Eigen::Map<const Vec<D>> fa(f + D * a);
    double sum = 0.0;
    for (auto k = nl.offset[static_cast<size_t>(a)]; k < nl.offset[static_cast<size_t>(a) + 1];
         ++k) {
      const Index b = nl.index[static_cast<size_t>(k)];
      const Vec<D> rab = xa - Eigen::Map<const Vec<D>>(g.x + D * b);
      const Vec<D> gw = pairGradient<D>(g, a, rab);
      const FormWeights w = pairWeights(g, form, a, b);
      sum += (w.wb * Eigen::Map<const Vec<D>>(f + D * b) + w.wa * fa).dot(gw);
    }
    if (self) {
      const double ws = selfWeight(g, form, a);
      if (ws != 0.0) sum += ws * fa.dot(g.correction.selfGradient<D>(a));
    }
    if (form == DerivativeForm::DensityWeighted) sum /= g.density[a];
    if (form == DerivativeForm::Symmetric) sum *= g.density[a];
    out[a] = sum;
  }
}

template <int D>
void diffusion(const SphGeometry& g, const double* f, int nc, const double* phi, PairMean mean,
               double* out) {
  check<D>(g, "diffusion");
  const NeighbourList& nl = *g.neighbours;
#pragma omp parallel for schedule(dynamic, 64)
  for (Index a = 0; a < g.nReal; ++a) {
    const Eigen::Map<const Vec<D>> xa(g.x + D * a);
    double* oa = out + nc * a;
    for (int c = 0; c < nc; ++c) oa[c] = 0.0;
    for (auto k = nl.offset[static_cast<size_t>(a)]; k < nl.offset[static_cast<size_t>(a) + 1];
         ++k) {
      const Index b = nl.index[static_cast<size_t>(k)];
      const double r = (xa - Eigen::Map<const Vec<D>>(g.x + D * b)).norm();
      double m = 2.0;
      if (phi) {
        const double pa = phi[a], pb = phi[b];
        if (mean == PairMean::Arithmetic) {
          m = pa + pb;  // Eq. 2.44
        } else {
          const double s = pa + pb;  // Eq. 2.45
          m = s != 0.0 ? 4.0 * pa * pb / s : 0.0;
        }
      }
      const double w = g.volume[b] * m * g.kernel->F(r);
      for (int c = 0; c < nc; ++c) oa[c] += w * (f[nc * a + c] - f[nc * b + c]);
    }
  }
}

template <int D>
void secondDerivatives(const SphGeometry& g, const double* f, double* out) {
  check<D>(g, "secondDerivatives");
  const NeighbourList& nl = *g.neighbours;
  // Eqs. 2.46a-c: [(D + 2) r_alpha r_gamma / r^2 - delta] in 2D and 3D, 2 in 1D.
  constexpr double c = D + 2.0;
#pragma omp parallel for schedule(dynamic, 64)
  for (Index a = 0; a < g.nReal; ++a) {
    const Eigen::Map<const Vec<D>> xa(g.x + D * a);
    Mat<D> H = Mat<D>::Zero();
    for (auto k = nl.offset[static_cast<size_t>(a)]; k < nl.offset[static_cast<size_t>(a) + 1];
         ++k) {
      const Index b = nl.index[static_cast<size_t>(k)];
      const Vec<D> rab = xa - Eigen::Map<const Vec<D>>(g.x + D * b);
      const double r2 = rab.squaredNorm();
      if (r2 <= 0.0) continue;  // coincident particles carry no direction
      const double w = g.volume[b] * (f[a] - f[b]) * g.kernel->F(std::sqrt(r2));
      if constexpr (D == 1) {
        H(0, 0) += 2.0 * w;  // Eq. 2.46a
      } else {
        H.noalias() += w * (c * rab * rab.transpose() / r2 - Mat<D>::Identity());
      }
    }
    Eigen::Map<Mat<D>>(out + D * D * a) = H;
  }
}

template <int D>
std::vector<std::pair<Index, double>> divergencePairs(const SphGeometry& g, DerivativeForm form,
                                                      const double* f, Index a) {
  check<D>(g, "divergencePairs");
  checkMassDensity(g, form, "divergencePairs");
  const NeighbourList& nl = *g.neighbours;
  std::vector<std::pair<Index, double>> out;
  const Eigen::Map<const Vec<D>> xa(g.x + D * a);
  const Eigen::Map<const Vec<D>> fa(f + D * a);
  double outer = 1.0;
  if (form == DerivativeForm::DensityWeighted) outer = 1.0 / g.density[a];
  if (form == DerivativeForm::Symmetric) outer = g.density[a];
  for (auto k = nl.offset[static_cast<size_t>(a)]; k < nl.offset[static_cast<size_t>(a) + 1]; ++k) {
    const Index b = nl.index[static_cast<size_t>(k)];
    const Vec<D> rab = xa - Eigen::Map<const Vec<D>>(g.x + D * b);
    const Vec<D> gw = pairGradient<D>(g, a, rab);
    const FormWeights w = pairWeights(g, form, a, b);
    out.emplace_back(b, outer * (w.wb * Eigen::Map<const Vec<D>>(f + D * b) + w.wa * fa).dot(gw));
  }
  double selfTerm = 0.0;
  if (correctionHasSelfGradient(g.correction.type)) {
    const double ws = selfWeight(g, form, a);
    selfTerm = outer * ws * fa.dot(g.correction.selfGradient<D>(a));
  }
  out.emplace_back(a, selfTerm);
  return out;
}

#define PORESPH_INSTANTIATE_OPERATORS(D)                                                        \
  template void interpolate<D>(const SphGeometry&, const double*, int, double*);               \
  template void gradient<D>(const SphGeometry&, DerivativeForm, const double*, int, double*);  \
  template void divergence<D>(const SphGeometry&, DerivativeForm, const double*, double*);     \
  template void diffusion<D>(const SphGeometry&, const double*, int, const double*, PairMean,  \
                             double*);                                                         \
  template void secondDerivatives<D>(const SphGeometry&, const double*, double*);              \
  template std::vector<std::pair<Index, double>> divergencePairs<D>(                           \
      const SphGeometry&, DerivativeForm, const double*, Index);

PORESPH_INSTANTIATE_OPERATORS(1)
PORESPH_INSTANTIATE_OPERATORS(2)
PORESPH_INSTANTIATE_OPERATORS(3)

#undef PORESPH_INSTANTIATE_OPERATORS

void interpolate(const SphGeometry& g, const double* f, int nc, double* out) {
  dispatchDimension(g.dim, [&](auto d) { interpolate<decltype(d)::value>(g, f, nc, out); });
}
void gradient(const SphGeometry& g, DerivativeForm form, const double* f, int nc, double* out) {
  dispatchDimension(g.dim,
                    [&](auto d) { gradient<decltype(d)::value>(g, form, f, nc, out); });
}
void divergence(const SphGeometry& g, DerivativeForm form, const double* f, double* out) {
  dispatchDimension(g.dim, [&](auto d) { divergence<decltype(d)::value>(g, form, f, out); });
}
void diffusion(const SphGeometry& g, const double* f, int nc, const double* phi, PairMean mean,
               double* out) {
  dispatchDimension(g.dim,
                    [&](auto d) { diffusion<decltype(d)::value>(g, f, nc, phi, mean, out); });
}
void secondDerivatives(const SphGeometry& g, const double* f, double* out) {
  dispatchDimension(g.dim, [&](auto d) { secondDerivatives<decltype(d)::value>(g, f, out); });
}

}  // namespace poresph
