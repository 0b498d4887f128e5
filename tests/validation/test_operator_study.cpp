// The thesis' Sec. 2.5 study of SPH divergence with and without symmetry terms and with the
// kernel/gradient corrections (Eqs. 2.61-2.63, 2.91-2.95, Tables 2.1-2.2, Figs. 2.11-2.25).
//
// Set-up (thesis Sec. 2.5, Fig. 2.10): bar of length L = 1 m, N material points at the centres of
// N equal parts starting at x = 50 m (N = 5: 50.1 ... 50.9 m), volumes V = L / N, smoothing length
// h = 2.8 dx(N = 5) = 0.56 m kept for N = 50 and 500 ("without changing ... the smoothing length",
// Sec. 2.5.2), kappa = 1, so the support radius is 0.56 m: our cubic spline (2.11, support 2h)
// with h_kernel = 0.28 m. Disordered bars (Sec. 2.5.3): every point moved by a uniform amount in
// [-0.3, 0.3] dx (mt19937, seed 2026; the thesis does not give its amplitude). 2D 5x5 and 3D
// 5x5x5 (Sec. 2.5.4): the same points on every axis, fields 2.94-2.95. Relative errors in % as
// Eq. 2.93.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "tests/support/validation_record.hpp"
#include "tests/unit/test_operators_support.hpp"

using namespace poresph;
using namespace poresph::test;

namespace {

constexpr double kOrigin = 50.0;
constexpr double kKernelH = 0.28;  // support 0.56 m = 2.8 dx for N = 5 (kappa h with kappa = 1)
constexpr double kJitter = 0.3;
constexpr std::uint32_t kSeed = 2026u;

double quartic(double x) { return -4 * x * x * x * x + 3 * x * x * x + 15 * x * x - x + 15; }  // 2.92c
double quarticSlope(double x) { return -16 * x * x * x + 9 * x * x + 30 * x - 1; }

enum class Field { Constant, Linear, Quartic };  // 2.92a-c, 2.94, 2.95

struct StudyResult {
  std::vector<double> div;  // per point
  std::vector<double> ref;  // analytical
  Index fallbacks = 0;
  double maxRelPercent() const {  // Eq. 2.93
    double e = 0.0;
    for (size_t a = 0; a < div.size(); ++a)
      e = std::max(e, 100.0 * std::abs(ref[a] - div[a]) / std::abs(ref[a]));
    return e;
  }
  double maxAbs() const {
    double e = 0.0;
    for (double d : div) e = std::max(e, std::abs(d));
    return e;
  }
};

template <int D>
StudyResult runStudy(int n, bool disordered, Field field, Correction c, DerivativeForm form) {
  const double dx = 1.0 / n;
  const ParticleBlock b = makeBlock(D, n, dx, kOrigin, disordered ? kJitter : 0.0, kSeed);
  const Kernel k(KernelType::CubicSpline, D, kKernelH);
  const NeighbourList nl = buildNeighbours(b, k);
  CorrectionBuffer buf;
  CorrectionStats st;
  const CorrectionView view = correct(b, nl, k, c, buf, &st);
  const Index count = b.count();
  std::vector<double> u(static_cast<size_t>(D * count));
  StudyResult r;
  r.fallbacks = st.fallbacks;
  r.div.resize(static_cast<size_t>(count));
  r.ref.assign(static_cast<size_t>(count), 0.0);
  for (Index a = 0; a < count; ++a)
    for (int d = 0; d < D; ++d) {
      const double x = b.x[D * a + d];
      switch (field) {
        case Field::Constant: u[D * a + d] = 20.0; break;
        case Field::Linear: u[D * a + d] = 20.0 * x; r.ref[a] += 20.0; break;
        case Field::Quartic: u[D * a + d] = quartic(x); r.ref[a] += quarticSlope(x); break;
      }
    }
  divergence<D>(makeGeometry(b, nl, k, view), form, u.data(), r.div.data());
  return r;
}

std::string res1D(int n, bool dis) {
  return std::to_string(n) + " points, dx = " + std::to_string(1.0 / n).substr(0, 6) +
         " m, support 0.56 m (h = 2.8 dx of N = 5)" + (dis ? ", disordered +-0.3 dx" : ", ordered");
}

const Correction kMatrixCorrections[] = {Correction::Gradient, Correction::Mixed,
                                         Correction::MixedRatio};

}  // namespace

TEST(OperatorStudy, Table21LinearDivergenceFourthPoint) {
  Stopwatch sw;
  for (DerivativeForm form : {DerivativeForm::Difference, DerivativeForm::Standard}) {
    const StudyResult r = runStudy<1>(5, false, Field::Linear, Correction::Mixed, form);
    EXPECT_EQ(r.fallbacks, 0);
    const double rel = std::abs(r.div[3] - 20.0) / 20.0;
    EXPECT_LT(rel, 1e-10);
    const bool diff = form == DerivativeForm::Difference;
    recordValidation({"operator_study_bar1d_N5",
                      std::string("div v2 (2.92b) at point 4, mixed_2.63b, ") +
                          (diff ? "with symmetry terms (2.91b)" : "without symmetry terms (2.91a)"),
                      r.div[3], 20.0, rel, res1D(5, false), sw.seconds(), "rel < 1e-10",
                      "thesis Table 2.1 (sum = 20.0, 1e-14 %)"});
  }
}

TEST(OperatorStudy, Table21PairContributionsReproduced) {
  // The pair contributions of Table 2.1 fix the thesis' geometry: their ratios
  // v_b / (v_b - v_a) = x_b / (x_b - x_a) give points at (i + 0.75) dx, i.e. the 5-point bar of
  // Fig. 2.10 starting at x = 0.25 m (0.35 ... 1.15 m), V = 0.2 m, support 0.56 m. With 2.63b we
  // reproduce every printed contribution (3 decimals), the self pair 4-4 included.
  Stopwatch sw;
  const double dx = 0.2;
  const ParticleBlock b = makeBlock(1, 5, dx, 0.25, 0.0);
  const Kernel k(KernelType::CubicSpline, 1, kKernelH);
  const NeighbourList nl = buildNeighbours(b, k);
  CorrectionBuffer buf;
  const SphGeometry g = makeGeometry(b, nl, k, correct(b, nl, k, Correction::Mixed, buf));
  std::vector<double> u(5);
  for (int i = 0; i < 5; ++i) u[i] = 20.0 * b.x[i];
  // Thesis Table 2.1, point 4 (index 3): pairs 4-2, 4-3, 4-4, 4-5.
  const double thesisDiff[4] = {3.879, 7.572, 0.000, 8.549};
  const double thesisStd[4] = {-5.333, -28.395, 4.569, 49.159};
  for (DerivativeForm form : {DerivativeForm::Difference, DerivativeForm::Standard}) {
    const bool diff = form == DerivativeForm::Difference;
    const auto pairs = divergencePairs<1>(g, form, u.data(), 3);
    double contrib[4] = {0, 0, 0, 0};  // by neighbour 2, 3, 4, 5
    bool seen1 = false;
    for (const auto& p : pairs) {
      if (p.first == 0) seen1 = true;
      if (p.first >= 1) contrib[p.first - 1] += p.second;
    }
    EXPECT_FALSE(seen1);  // point 1 is 0.6 m > 0.56 m away: outside the support, as in the table
    double worst = 0.0;
    for (int q = 0; q < 4; ++q) {
      const double ref = diff ? thesisDiff[q] : thesisStd[q];
      EXPECT_NEAR(contrib[q], ref, 6e-4) << "pair 4-" << q + 2 << (diff ? " (2.91b)" : " (2.91a)");
      worst = std::max(worst, std::abs(contrib[q] - ref));
    }
    recordValidation({"operator_study_bar1d_N5_table2.1",
                      std::string("max |pair contribution - thesis| at point 4, mixed_2.63b, ") +
                          (diff ? "with symmetry terms (2.91b)" : "without symmetry terms (2.91a)"),
                      worst, 0.0, worst, "5 points at 0.35 ... 1.15 m, V = 0.2 m, support 0.56 m",
                      sw.seconds(), "each pair within 6e-4 (3 printed decimals)",
                      "thesis Table 2.1 pair contributions"});
  }
}

TEST(OperatorStudy, Table22QuarticDivergenceFourthPoint) {
  Stopwatch sw;
  const StudyResult d = runStudy<1>(5, false, Field::Quartic, Correction::Mixed,
                                    DerivativeForm::Difference);
  const StudyResult s = runStudy<1>(5, false, Field::Quartic, Correction::Mixed,
                                    DerivativeForm::Standard);
  // Table 2.2: both forms give the same sum with 2.63b.
  EXPECT_NEAR(d.div[3], s.div[3], 1e-9 * std::abs(d.div[3]));
  const double errPercent = 100.0 * std::abs(d.ref[3] - d.div[3]) / std::abs(d.ref[3]);
  std::printf("point 4: SPH %.3f analytical %.3f error %.4f %%\n", d.div[3], d.ref[3], errPercent);
  // Sec. 2.5.1: 2.63b "gives slightly better results for internal points and worse results for
  // boundary points" than the other mixed forms.
  const StudyResult a = runStudy<1>(5, false, Field::Quartic, Correction::Gradient,
                                    DerivativeForm::Difference);
  const double errA = 100.0 * std::abs(a.ref[3] - a.div[3]) / std::abs(a.ref[3]);
  std::printf("point 4 with 2.63a: error %.4f %%; max over the bar 2.63a %.4f %%, 2.63b %.4f %%\n",
              errA, a.maxRelPercent(), d.maxRelPercent());
  EXPECT_LT(errPercent, errA);
  EXPECT_GT(d.maxRelPercent(), a.maxRelPercent());
  constexpr double kThesis = 0.202;  // % (Table 2.2)
  EXPECT_NEAR(errPercent, kThesis, 0.03);
  recordValidation({"operator_study_bar1d_N5",
                    "rel. error [%] (2.93) of div v3 (2.92c) at point 4, mixed_2.63b",
                    errPercent, kThesis, std::abs(errPercent - kThesis) / kThesis,
                    res1D(5, false), sw.seconds(), "|err - 0.202 %| < 0.03 %",
                    "thesis Table 2.2 (0.202 %; its analytical value -496640.962 implies x4 = "
                    "31.64 m, not the 50.7 m of the text)"});
}

TEST(OperatorStudy, Table22PairContributionsOnInferredGeometry) {
  // Table 2.2 is not computed on the bar of the text: its exact value -496640.962 is div v3 at
  // x4 = 31.63594 m, and its ratios v_b / (v_b - v_a) give a uniform bar of spacing 0.12615 m
  // around it. A least-squares fit of (x4, dx) to its seven printed pair values, using the
  // scale-free pair weights V_b grad~W~_ab dx of Table 2.1 (reproduced exactly above), gives
  // dx = 0.12614666 m (done outside this test, from the thesis' numbers only). On that bar
  // (support 2.8 dx, V = dx) our 2.63b gives every printed pair value to ~1e-5 relative (the
  // precision of the fit) and the thesis' sum and error.
  Stopwatch sw;
  const double dx = 0.12614665547, x4 = 31.635940056944946;
  const ParticleBlock b = makeBlock(1, 5, dx, x4 - 3.5 * dx, 0.0);
  const Kernel k(KernelType::CubicSpline, 1, 1.4 * dx);
  const NeighbourList nl = buildNeighbours(b, k);
  CorrectionBuffer buf;
  const SphGeometry g = makeGeometry(b, nl, k, correct(b, nl, k, Correction::Mixed, buf));
  std::vector<double> u(5);
  for (int i = 0; i < 5; ++i) u[i] = quartic(b.x[i]);
  const double thesisDiff[4] = {-95159.963, -186899.604, 0.0, -213580.328};
  const double thesisStd[4] = {2900053.551, 11507941.882, -1485695.206, -13417940.121};
  for (DerivativeForm form : {DerivativeForm::Difference, DerivativeForm::Standard}) {
    const bool diff = form == DerivativeForm::Difference;
    double contrib[4] = {0, 0, 0, 0}, sum = 0.0;
    for (const auto& p : divergencePairs<1>(g, form, u.data(), 3)) {
      if (p.first >= 1) contrib[p.first - 1] += p.second;
      sum += p.second;
    }
    for (int q = 0; q < 4; ++q) {
      const double ref = diff ? thesisDiff[q] : thesisStd[q];
      EXPECT_NEAR(contrib[q], ref, ref == 0.0 ? 1e-6 : 5e-5 * std::abs(ref)) << "pair 4-" << q + 2;
    }
    constexpr double kThesisSum = -495639.894;
    EXPECT_NEAR(sum, kThesisSum, 1e-5 * std::abs(kThesisSum));
    const double err = 100.0 * std::abs(sum - quarticSlope(x4)) / std::abs(quarticSlope(x4));
    EXPECT_NEAR(quarticSlope(x4), -496640.962, 1e-3);
    EXPECT_NEAR(err, 0.202, 0.001);
    recordValidation({"operator_study_bar1d_N5_table2.2",
                      std::string("div v3 at point 4 (sum of pairs), mixed_2.63b, ") +
                          (diff ? "with symmetry terms (2.91b)" : "without symmetry terms (2.91a)"),
                      sum, kThesisSum, std::abs(sum - kThesisSum) / std::abs(kThesisSum),
                      "5 points, dx = 0.126147 m around x4 = 31.636 m (inferred), support 2.8 dx",
                      sw.seconds(), "rel < 1e-5; each pair < 5e-5 rel",
                      "thesis Table 2.2 (sum -495639.894, error 0.202 %)"});
  }
}

TEST(OperatorStudy, ConstantFieldSymmetryTerms) {
  // Fig. 2.11: with symmetry terms (2.91b) the divergence of v1 vanishes for every correction;
  // without (2.91a) only 2.61a and 2.63b give zero.
  Stopwatch sw;
  for (Correction c : {Correction::None, Correction::ShepardGradient, Correction::ShepardRatio,
                       Correction::Gradient, Correction::Mixed, Correction::MixedRatio}) {
    const StudyResult d = runStudy<1>(5, false, Field::Constant, c, DerivativeForm::Difference);
    EXPECT_EQ(d.maxAbs(), 0.0) << correctionName(c);
    const StudyResult s = runStudy<1>(5, false, Field::Constant, c, DerivativeForm::Standard);
    const bool zero = c == Correction::ShepardGradient || c == Correction::Mixed;
    if (zero)
      EXPECT_LT(s.maxAbs(), 1e-10) << correctionName(c);
    else
      EXPECT_GT(s.maxAbs(), 1.0) << correctionName(c);
    recordValidation({"operator_study_bar1d_N5",
                      "max |div v1| (2.92a) without symmetry terms (2.91a), " + correctionName(c),
                      s.maxAbs(), 0.0, s.maxAbs(), res1D(5, false), sw.seconds(),
                      zero ? "< 1e-10 (thesis: zero for 2.61a, 2.63b)"
                           : "> 1 (thesis: not zero, Fig. 2.11b)",
                      "thesis Fig. 2.11b; closed form 0"});
  }
}

TEST(OperatorStudy, LinearFieldExactWithMatrixCorrections1D) {
  // Fig. 2.12: only the corrected gradients (2.63) recover div v2 = 20 with symmetry terms;
  // without them only 2.63b does. Every N, ordered and disordered, every point (free ends).
  for (int n : {5, 50, 500}) {
    for (bool dis : {false, true}) {
      Stopwatch sw;
      double worst = 0.0;
      for (Correction c : kMatrixCorrections) {
        const StudyResult r = runStudy<1>(n, dis, Field::Linear, c, DerivativeForm::Difference);
        EXPECT_EQ(r.fallbacks, 0);
        worst = std::max(worst, r.maxRelPercent() / 100.0);
      }
      const StudyResult s =
          runStudy<1>(n, dis, Field::Linear, Correction::Mixed, DerivativeForm::Standard);
      worst = std::max(worst, s.maxRelPercent() / 100.0);
      EXPECT_LT(worst, 1e-10) << "N " << n << " disordered " << dis;
      // The uncorrected operator is far off at the free ends (the test can fail).
      const StudyResult u =
          runStudy<1>(n, dis, Field::Linear, Correction::None, DerivativeForm::Difference);
      EXPECT_GT(u.maxRelPercent(), 10.0);
      recordValidation({"operator_study_bar1d_N" + std::to_string(n) + (dis ? "_disordered" : ""),
                        "max rel. error of div v2 (2.92b), 2.63a-c with and 2.63b without "
                        "symmetry terms",
                        20.0 * (1.0 + worst), 20.0, worst, res1D(n, dis), sw.seconds(),
                        "rel < 1e-10", "closed form 20; thesis Fig. 2.12 (~1e-14)"});
    }
  }
}

TEST(OperatorStudy, QuarticFieldErrors1D) {
  // Figs. 2.14-2.20: max relative error over the bar with the mixed corrections (2.63a-c, with
  // symmetry terms): thesis ~0.8 % for N = 5, < 1.2 % for N = 50 and 500, ~1 % disordered.
  struct Case {
    int n;
    bool dis;
    double thesis;  // %
    double bound;   // asserted %
    const char* source;
  };
  const Case cases[] = {
      {5, false, 0.8, 1.0, "thesis Fig. 2.14a (max ~0.8 %)"},
      {50, false, 1.2, 1.2, "thesis Fig. 2.16b (< 1.2 %)"},
      {500, false, 1.2, 1.2, "thesis Fig. 2.17b (< 1.2 %)"},
      {5, true, 1.0, 1.5, "thesis Fig. 2.18b (~1 %)"},
      {50, true, 1.0, 1.2, "thesis Fig. 2.19b (< 1.2 %)"},
      {500, true, 1.0, 1.2, "thesis Fig. 2.20b (< 1.2 %)"},
  };
  for (const Case& cs : cases) {
    for (Correction c : kMatrixCorrections) {
      Stopwatch sw;
      const StudyResult r = runStudy<1>(cs.n, cs.dis, Field::Quartic, c, DerivativeForm::Difference);
      EXPECT_EQ(r.fallbacks, 0);
      const double e = r.maxRelPercent();
      std::printf("N %d disordered %d %s: max error %.4f %%\n", cs.n, cs.dis ? 1 : 0,
                  correctionName(c).c_str(), e);
      EXPECT_LT(e, cs.bound) << correctionName(c) << " N " << cs.n;
      EXPECT_GT(e, 0.05);  // a quartic is not reproduced exactly
      recordValidation({"operator_study_bar1d_N" + std::to_string(cs.n) +
                            (cs.dis ? "_disordered" : ""),
                        "max rel. error [%] of div v3 (2.92c) with symmetry terms, " +
                            correctionName(c),
                        e, cs.thesis, std::abs(e - cs.thesis) / cs.thesis, res1D(cs.n, cs.dis),
                        sw.seconds(), "< " + std::to_string(cs.bound).substr(0, 3) + " %",
                        cs.source});
    }
  }
}

namespace {

template <int D>
void study2D3D(const char* name) {
  for (bool dis : {false, true}) {
    const std::string res = std::string("5 per axis (") + (D == 2 ? "25" : "125") +
                            " points), dx = 0.2 m, support 0.56 m" +
                            (dis ? ", disordered +-0.3 dx" : ", ordered");
    for (Correction c : kMatrixCorrections) {
      Stopwatch sw;
      const StudyResult lin = runStudy<D>(5, dis, Field::Linear, c, DerivativeForm::Difference);
      EXPECT_EQ(lin.fallbacks, 0);
      const double el = lin.maxRelPercent() / 100.0;
      EXPECT_LT(el, 1e-10) << name << " " << correctionName(c);
      recordValidation({std::string("operator_study_") + name + (dis ? "_disordered" : ""),
                        "max rel. error of div v2 (2.94), " + correctionName(c),
                        20.0 * D * (1 + el), 20.0 * D, el, res, sw.seconds(), "rel < 1e-10",
                        std::string("closed form; thesis Fig. ") + (D == 2 ? "2.22" : "2.23") +
                            " (~1e-14)"});
      const StudyResult q = runStudy<D>(5, dis, Field::Quartic, c, DerivativeForm::Difference);
      const double eq = q.maxRelPercent();
      std::printf("%s disordered %d %s: linear %.3g, quartic max error %.4f %%\n", name,
                  dis ? 1 : 0, correctionName(c).c_str(), el, eq);
      EXPECT_LT(eq, 1.5) << name << " " << correctionName(c);
      recordValidation({std::string("operator_study_") + name + (dis ? "_disordered" : ""),
                        "max rel. error [%] of div v3 (2.95), " + correctionName(c), eq, 1.0,
                        std::abs(eq - 1.0), res, sw.seconds(), "< 1.5 %",
                        std::string("thesis Fig. ") + (D == 2 ? "2.24" : "2.25") + " (~1 %)"});
    }
  }
}

}  // namespace

TEST(OperatorStudy, TwoAndThreeDimensions) {
  study2D3D<2>("square2d_5x5");
  study2D3D<3>("cube3d_5x5x5");
}
