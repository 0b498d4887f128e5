// Kernel and kernel-gradient corrections (thesis Eqs. 2.56-2.63): names, exact linear
// consistency (2.57) on ordered and perturbed particles with free boundaries in 1D-3D, the
// singular-matrix fallback, and the store fields.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "libcore/corrections.hpp"
#include "libcore/simulation.hpp"
#include "tests/unit/test_operators_support.hpp"

using namespace poresph;
using namespace poresph::test;

TEST(Corrections, NamesRoundTripAndAliases) {
  for (const std::string& n : correctionNames()) {
    const Correction c = parseCorrection(n);
    EXPECT_EQ(parseCorrection(correctionName(c)), c) << n;
  }
  EXPECT_EQ(parseCorrection("mixed"), Correction::Mixed);
  EXPECT_EQ(parseCorrection("mixed_2.63a"), Correction::Gradient);
  EXPECT_EQ(correctionName(Correction::Mixed), "mixed_2.63b");
  EXPECT_EQ(correctionName(Correction::ShepardGradient), "shepard_gradient_2.61a");
}

TEST(Corrections, UnknownNameListsValidNames) {
  try {
    parseCorrection("randles", "scene.yaml:3 key 'correction'");
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("scene.yaml:3"), std::string::npos) << m;
    EXPECT_NE(m.find("'randles'"), std::string::npos) << m;
    for (const std::string& n : correctionNames()) EXPECT_NE(m.find(n), std::string::npos) << m;
  }
}

namespace {

// sum_b V_b grad~W~_ab (x) r_ba over the neighbours (self has r_aa = 0): must be the identity
// for the matrix corrections (Eq. 2.57).
template <int D>
Mat<D> consistencyMatrix(const ParticleBlock& b, const NeighbourList& nl, const Kernel& k,
                         const CorrectionView& v, Index a) {
  Mat<D> M = Mat<D>::Zero();
  const Eigen::Map<const Vec<D>> xa(b.x.data() + D * a);
  for (auto q = nl.offset[a]; q < nl.offset[a + 1]; ++q) {
    const Index j = nl.index[q];
    const Vec<D> rab = xa - Eigen::Map<const Vec<D>>(b.x.data() + D * j);
    const double r = rab.norm();
    const Vec<D> g = v.gradient<D>(a, Vec<D>(rab * k.F(r)), k.value(r));
    M -= b.volume[j] * g * rab.transpose();
  }
  return M;
}

template <int D>
void checkIdentity(double jitter) {
  const int n = D == 3 ? 6 : (D == 2 ? 9 : 20);
  const double dx = 0.1;
  const ParticleBlock b = makeBlock(D, n, dx, 3.0, jitter);
  const Kernel k(KernelType::CubicSpline, D, 1.3 * dx);
  const NeighbourList nl = buildNeighbours(b, k);
  for (Correction c : {Correction::Gradient, Correction::Mixed, Correction::MixedRatio}) {
    CorrectionBuffer buf;
    CorrectionStats st;
    const CorrectionView v = correct(b, nl, k, c, buf, &st);
    EXPECT_EQ(st.fallbacks, 0) << correctionName(c);
    EXPECT_EQ(st.particles, b.count());
    double worst = 0.0;
    for (Index a = 0; a < b.count(); ++a)
      worst = std::max(worst, (consistencyMatrix<D>(b, nl, k, v, a) - Mat<D>::Identity())
                                  .cwiseAbs()
                                  .maxCoeff());
    EXPECT_LT(worst, 1e-12) << correctionName(c) << " D=" << D << " jitter=" << jitter;
  }
}

}  // namespace

TEST(Corrections, MatrixCorrectionsSatisfyEq257Ordered) {
  checkIdentity<1>(0.0);
  checkIdentity<2>(0.0);
  checkIdentity<3>(0.0);
}

TEST(Corrections, MatrixCorrectionsSatisfyEq257Perturbed) {
  checkIdentity<1>(0.3);
  checkIdentity<2>(0.3);
  checkIdentity<3>(0.3);
}

TEST(Corrections, ShepardSumsAndQuotientGradientPartitionOfUnity) {
  // 2.58: sum_b V_b W~_ab = 1 (self included); 2.61a: sum_b V_b grad W~_ab = 0 (self included).
  const ParticleBlock b = makeBlock(2, 8, 0.1, 0.0, 0.25);
  const Kernel k(KernelType::WendlandC2, 2, 1.2 * 0.1);
  const NeighbourList nl = buildNeighbours(b, k);
  CorrectionBuffer buf;
  const CorrectionView v = correct(b, nl, k, Correction::ShepardGradient, buf);
  for (Index a = 0; a < b.count(); ++a) {
    const Eigen::Map<const Vec<2>> xa(b.x.data() + 2 * a);
    double s = b.volume[a] * v.kernel(a, k.value(0.0));
    Vec<2> g = b.volume[a] * v.selfGradient<2>(a);
    for (auto q = nl.offset[a]; q < nl.offset[a + 1]; ++q) {
      const Index j = nl.index[q];
      const Vec<2> rab = xa - Eigen::Map<const Vec<2>>(b.x.data() + 2 * j);
      const double r = rab.norm();
      s += b.volume[j] * v.kernel(a, k.value(r));
      g += b.volume[j] * v.gradient<2>(a, Vec<2>(rab * k.F(r)), k.value(r));
    }
    EXPECT_NEAR(s, 1.0, 1e-13);
    EXPECT_LT(g.norm() * k.h(), 1e-12);
  }
}

TEST(Corrections, Mixed263cEqualsGradient263aUpToRoundOff) {
  // The 2.61b factor 1/S_a is a per-particle scalar and cancels in K g (see corrections.hpp).
  const ParticleBlock b = makeBlock(3, 5, 0.2, 50.0, 0.3);
  const Kernel k(KernelType::CubicSpline, 3, 1.4 * 0.2);
  const NeighbourList nl = buildNeighbours(b, k);
  CorrectionBuffer ba, bc;
  const CorrectionView va = correct(b, nl, k, Correction::Gradient, ba);
  const CorrectionView vc = correct(b, nl, k, Correction::MixedRatio, bc);
  for (Index a = 0; a < b.count(); ++a) {
    const Eigen::Map<const Vec<3>> xa(b.x.data() + 3 * a);
    for (auto q = nl.offset[a]; q < nl.offset[a + 1]; ++q) {
      const Vec<3> rab = xa - Eigen::Map<const Vec<3>>(b.x.data() + 3 * nl.index[q]);
      const Vec<3> gw = rab * k.F(rab.norm());
      const Vec<3> ga = va.gradient<3>(a, gw, 0.0), gc = vc.gradient<3>(a, gw, 0.0);
      EXPECT_LE((ga - gc).norm(), 1e-12 * ga.norm() + 1e-300);
    }
  }
}

TEST(Corrections, SingularMatricesFallBackCountedAndFinite) {
  const Kernel k2(KernelType::CubicSpline, 2, 0.13);
  const Index before = totalCorrectionFallbacks();
  // (1) Collinear particles in 2D: M has rank 1 for every particle.
  ParticleBlock line;
  line.dim = 2;
  line.dx = 0.1;
  for (int i = 0; i < 10; ++i) {
    line.x.push_back(0.1 * i);
    line.x.push_back(0.5);
    line.volume.push_back(0.01);
  }
  const NeighbourList nlLine = buildNeighbours(line, k2);
  for (Correction c : {Correction::Gradient, Correction::Mixed, Correction::MixedRatio}) {
    CorrectionBuffer buf;
    CorrectionStats st;
    const CorrectionView v = correct(line, nlLine, k2, c, buf, &st);
    EXPECT_EQ(st.fallbacks, line.count()) << correctionName(c);
    for (Index a = 0; a < line.count(); ++a)
      EXPECT_TRUE((v.matrixOf<2>(a) - Mat<2>::Identity()).isZero(0.0));
    // Fallback = uncorrected base gradient: finite divergence of a field.
    std::vector<double> f(2 * line.count(), 1.0), div(line.count());
    divergence<2>(makeGeometry(line, nlLine, k2, v), DerivativeForm::Standard, f.data(),
                  div.data());
    for (double d : div) EXPECT_TRUE(std::isfinite(d));
  }
  // (2) One particle alone (no neighbour) in 1D, 2D, 3D; (3) two particles (one neighbour) in 3D.
  for (int dim = 1; dim <= 3; ++dim) {
    for (int count = 1; count <= 2; ++count) {
      ParticleBlock p;
      p.dim = dim;
      for (int i = 0; i < count; ++i) {
        for (int d = 0; d < dim; ++d) p.x.push_back(d == 0 ? 0.05 * i : 0.0);
        p.volume.push_back(1e-3);
      }
      const Kernel k(KernelType::CubicSpline, dim, 0.05);
      const NeighbourList nl = buildNeighbours(p, k);
      CorrectionBuffer buf;
      CorrectionStats st;
      correct(p, nl, k, Correction::Mixed, buf, &st);
      const Index expected = (count == 1 || dim > 1) ? count : 0;  // 1D pair is regular
      EXPECT_EQ(st.fallbacks, expected) << "dim " << dim << " count " << count;
      for (double m : buf.matrix) EXPECT_TRUE(std::isfinite(m));
      for (double s : buf.shepardSum) EXPECT_TRUE(std::isfinite(s) && s > 0.0);
    }
  }
  EXPECT_GE(totalCorrectionFallbacks() - before, 3 * line.count() + 7);
}

TEST(Corrections, CoplanarNeighboursIn3DFallBack) {
  // A flat 2D sheet of particles living in 3D: every M_a is singular (rank 2).
  ParticleBlock sheet = makeBlock(2, 6, 0.1, 0.0, 0.2);
  ParticleBlock b;
  b.dim = 3;
  for (Index i = 0; i < sheet.count(); ++i) {
    b.x.push_back(sheet.x[2 * i]);
    b.x.push_back(sheet.x[2 * i + 1]);
    b.x.push_back(1.0);
    b.volume.push_back(1e-3);
  }
  const Kernel k(KernelType::CubicSpline, 3, 0.13);
  const NeighbourList nl = buildNeighbours(b, k);
  CorrectionBuffer buf;
  CorrectionStats st;
  correct(b, nl, k, Correction::Gradient, buf, &st);
  EXPECT_EQ(st.fallbacks, b.count());
}

TEST(Corrections, StoreFieldsAreNotOutputAndFollowPermutation) {
  Simulation sim(2);
  sim.kernel = Kernel(KernelType::CubicSpline, 2, 0.13);
  const ParticleBlock b = makeBlock(2, 6, 0.1, 0.0, 0.2);
  sim.store.addParticles(b.count());
  double* x = sim.store.data(sim.store.position());
  double* m = sim.store.data(sim.store.mass());
  double* rho = sim.store.data(sim.store.density());
  for (Index i = 0; i < b.count(); ++i) {
    x[2 * i] = b.x[2 * i];
    x[2 * i + 1] = b.x[2 * i + 1];
    rho[i] = 1000.0;
    m[i] = 1000.0 * 0.01;
  }
  sim.search.build(x, 2, b.count(), b.count(), sim.kernel.support(), sim.neighbours);
  const CorrectionFields f = registerCorrectionFields(sim.store);
  EXPECT_EQ(sim.store.spec(f.matrix.id).components, 4);
  EXPECT_EQ(sim.store.spec(f.matrix.id).flags & kFieldOutput, 0u);
  EXPECT_TRUE(sim.store.has("correction_matrix"));
  std::vector<double> vol;
  const CorrectionStats st = updateCorrection(sim, parseCorrection("mixed_2.63b", "test"), f, vol);
  EXPECT_EQ(st.fallbacks, 0);
  EXPECT_NEAR(vol[0], 0.01, 1e-15);
  const Mat<2> K0 = sim.store.mat<2>(f.matrix, 0);
  const double S0 = sim.store.data(f.shepardSum)[0];
  std::vector<Index> order(static_cast<size_t>(b.count()));
  for (Index i = 0; i < b.count(); ++i) order[static_cast<size_t>(i)] = b.count() - 1 - i;
  sim.store.permute(order);
  EXPECT_TRUE((sim.store.mat<2>(f.matrix, b.count() - 1) - K0).isZero(0.0));
  EXPECT_EQ(sim.store.data(f.shepardSum)[b.count() - 1], S0);
  // An unknown name is an InputError naming where it came from.
  EXPECT_THROW(parseCorrection("bogus", "key 'x'"), InputError);
}
