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

namespace {

// Third derivative of v3 (2.92c); its fourth is -96 and its fifth 0.
double quarticThird(double x) { return -96 * x + 18; }

// div v3 at point 4 of a 5-point bar (spacing dx, point 4 at x4, V = dx, support 2.8 dx), 2.63b:
// the pair contributions by neighbour 2, 3, 4 (self), 5 and their sum.
struct Table22Pairs {
  double pair[4] = {0, 0, 0, 0};
  double sum = 0.0;
};
Table22Pairs table22Pairs(double dx, double x4, DerivativeForm form) {
  const ParticleBlock b = makeBlock(1, 5, dx, x4 - 3.5 * dx, 0.0);
  const Kernel k(KernelType::CubicSpline, 1, 1.4 * dx);
  const NeighbourList nl = buildNeighbours(b, k);
  CorrectionBuffer buf;
  const SphGeometry g = makeGeometry(b, nl, k, correct(b, nl, k, Correction::Mixed, buf));
  std::vector<double> u(5);
  for (int i = 0; i < 5; ++i) u[i] = quartic(b.x[i]);
  Table22Pairs t;
  for (const auto& p : divergencePairs<1>(g, form, u.data(), 3)) {
    if (p.first >= 1) t.pair[p.first - 1] += p.second;
    t.sum += p.second;
  }
  return t;
}

}  // namespace

TEST(OperatorStudy, QuarticErrorIsTheClosedFormTruncationTermAtInteriorPoints) {
  // What the matrix corrections guarantee for a non-linear field, checked against a closed form.
  // At a point whose support is complete and symmetric (uniform spacing dx, support 2.8 dx: the
  // neighbours at +-dx and +-2dx) the Shepard sum is even and G_a = 0, so 2.61a reduces to
  // grad W / S_a and every matrix correction (2.63a-c) gives the weight
  // grad~W~_ab = -d F(|d|) / sum_c V_c d_c^2 F(|d_c|), d = x_b - x_a. With the Taylor series of
  // v_b - v_a (exact for the quartic v3, whose fifth derivative is 0) the even powers of d vanish
  // and
  //   div v - v'(x_a) = v3'''(x_a) / 6 * sum_j j^4 F(j dx) / sum_j j^2 F(j dx) * dx^2  (j = 1, 2),
  // i.e. the error is exactly second order in dx at fixed h/dx, proportional to v3'''. We compute
  // the constant from the kernel alone (no correction code) and compare at every interior point
  // of bars with N = 5 (the thesis' bar: its point 3), 10, 20, 40, h = 1.4 dx (support 2.8 dx as
  // in Sec. 2.5), 2.63a-c with symmetry terms and 2.63b without. The error itself is 3e-3 %
  // (N = 5) to 5e-5 % (N = 40) of div v; the tolerance is 1e-6 of the error (the round-off of
  // v3 ~ -2.6e7 at x = 50 m in the differences v_b - v_a reaches 2e-7 of it at N = 40).
  Stopwatch sw;
  const Kernel unit(KernelType::CubicSpline, 1, 1.4);  // dx = 1: F(j) of the same h/dx
  const double num = unit.F(1.0) + 16.0 * unit.F(2.0), den = unit.F(1.0) + 4.0 * unit.F(2.0);
  ASSERT_EQ(unit.value(3.0), 0.0);  // no neighbour at 3 dx
  const double c = num / den;       // dimensionless
  double worst = 0.0, errN5Point3 = 0.0, closedN5Point3 = 0.0;
  int checked = 0;
  for (int n : {5, 10, 20, 40}) {
    const double dx = 1.0 / n;
    const ParticleBlock b = makeBlock(1, n, dx, kOrigin, 0.0);
    const Kernel k(KernelType::CubicSpline, 1, 1.4 * dx);
    const NeighbourList nl = buildNeighbours(b, k);
    std::vector<double> u(static_cast<size_t>(n)), div(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) u[i] = quartic(b.x[i]);
    for (Correction corr : kMatrixCorrections) {
      CorrectionBuffer buf;
      CorrectionStats st;
      const SphGeometry g = makeGeometry(b, nl, k, correct(b, nl, k, corr, buf, &st));
      EXPECT_EQ(st.fallbacks, 0);
      for (DerivativeForm form : {DerivativeForm::Difference, DerivativeForm::Standard}) {
        if (form == DerivativeForm::Standard && corr != Correction::Mixed) continue;  // 2.91a: 2.63b only
        divergence<1>(g, form, u.data(), div.data());
        for (int i = 2; i + 2 < n; ++i) {  // complete, symmetric supports
          const double x = b.x[i];
          const double closed = quarticThird(x) / 6.0 * c * dx * dx;
          const double err = div[i] - quarticSlope(x);
          EXPECT_NEAR(err, closed, 1e-6 * std::abs(closed))
              << "N " << n << " point " << i + 1 << " " << correctionName(corr);
          worst = std::max(worst, std::abs(err - closed) / std::abs(closed));
          ++checked;
          if (n == 5 && corr == Correction::Mixed && form == DerivativeForm::Difference) {
            errN5Point3 = 100.0 * std::abs(err / quarticSlope(x));
            closedN5Point3 = 100.0 * std::abs(closed / quarticSlope(x));
          }
        }
      }
    }
  }
  EXPECT_EQ(checked, (1 + 6 + 16 + 36) * 4);
  std::printf("interior closed form: c = %.6f, worst relative deviation %.3g over %d points; "
              "N = 5 point 3: %.5f %% (closed form %.5f %%)\n",
              c, worst, checked, errN5Point3, closedN5Point3);
  recordValidation({"operator_study_bar1d_interior",
                    "rel. error [%] (2.93) of div v3 at point 3 of N = 5 (interior), mixed_2.63b",
                    errN5Point3, closedN5Point3,
                    std::abs(errN5Point3 - closedN5Point3) / closedN5Point3, res1D(5, false),
                    sw.seconds(), "rel < 1e-6",
                    "closed form v3'''/6 sum j^4 F / sum j^2 F dx^2 (Taylor with 2.57)"});
  recordValidation({"operator_study_bar1d_interior",
                    "max rel. deviation of div v3 - v3' from the closed-form dx^2 term, 2.63a-c, "
                    "N = 5, 10, 20, 40, every interior point",
                    worst, 0.0, worst, "N = 5 ... 40 on [50, 51] m, h = 1.4 dx (support 2.8 dx)",
                    sw.seconds(), "< 1e-6",
                    "closed form v3'''/6 sum j^4 F / sum j^2 F dx^2 (Taylor with 2.57)"});
}

TEST(OperatorStudy, QuarticFourthPointMixedFormsCompared) {
  // Point 4 of the bar of the text (50.7 m) has no neighbour at +2 dx: only linear exactness is
  // guaranteed there (Table21LinearDivergenceFourthPoint). Checked here are the statements of
  // Sec. 2.5.1 and Table 2.2 that hold on any bar: both forms give the same sum with 2.63b (its
  // base 2.61a has sum_b V_b grad~W~_ab = 0, self included), and 2.63b is better than 2.63a at
  // this inner point but worse over the bar (the free ends). Our error, 0.199 %, is reported, not
  // compared with the thesis' 0.202 %: Table 2.2 is computed on another bar (x4 = 31.64 m, see
  // Table22ReproducedOnFittedGeometry), so the closeness of the two numbers is a coincidence.
  Stopwatch sw;
  const StudyResult d = runStudy<1>(5, false, Field::Quartic, Correction::Mixed,
                                    DerivativeForm::Difference);
  const StudyResult s = runStudy<1>(5, false, Field::Quartic, Correction::Mixed,
                                    DerivativeForm::Standard);
  EXPECT_NEAR(d.div[3], s.div[3], 1e-9 * std::abs(d.div[3]));
  const double errPercent = 100.0 * std::abs(d.ref[3] - d.div[3]) / std::abs(d.ref[3]);
  const StudyResult a = runStudy<1>(5, false, Field::Quartic, Correction::Gradient,
                                    DerivativeForm::Difference);
  const double errA = 100.0 * std::abs(a.ref[3] - a.div[3]) / std::abs(a.ref[3]);
  std::printf("point 4: SPH %.3f analytical %.3f error 2.63b %.4f %%, 2.63a %.4f %%; max over "
              "the bar 2.63a %.4f %%, 2.63b %.4f %%\n",
              d.div[3], d.ref[3], errPercent, errA, a.maxRelPercent(), d.maxRelPercent());
  EXPECT_LT(errPercent, errA);
  EXPECT_GT(d.maxRelPercent(), a.maxRelPercent());
  char tol[160];
  std::snprintf(tol, sizeof tol,
                "reported; asserted: below 2.63a's %.3f %% at point 4, forms equal to 1e-9", errA);
  recordValidation({"operator_study_bar1d_N5",
                    "rel. error [%] (2.93) of div v3 (2.92c) at point 4, mixed_2.63b",
                    errPercent, std::nan(""), 0.0, res1D(5, false), sw.seconds(), tol,
                    "none on this bar (thesis Table 2.2's 0.202 % is for another bar, x4 = 31.64 m)"});
}

TEST(OperatorStudy, Table22ReproducedOnFittedGeometry) {
  // A reproduction of Table 2.2 on an inferred geometry, not a validation on the thesis' set-up
  // (which the table does not use). Its exact value -496640.962 is div v3 at x4 = 31.63594 m
  // (solved for below: an inversion, no fit). The spacing is fitted to ONE printed value, the
  // standard-form pair 4-5 (2.91a; these pairs scale as 1/dx and pin it). Everything else is held
  // out and checked: the other three standard-form pairs, the self pair 4-4 included
  // (grad~W~_aa != 0 of the 2.61a quotient rule, 3x the sum: a missing self term or a plain
  // base gradient would miss it entirely), the three difference-form pairs (2.91b), their sum and
  // the error 0.202 %. The difference-form pairs are nearly scale-free (V_b grad~W~_ab dx does
  // not depend on dx), so they test the correction's weights rather than the fit.
  Stopwatch sw;
  constexpr double kExact = -496640.962, kThesisSum = -495639.894, kThesisError = 0.202;
  double x4 = 31.6;  // Newton on v3'(x) = kExact
  for (int it = 0; it < 50; ++it)
    x4 -= (quarticSlope(x4) - kExact) / (-48 * x4 * x4 + 18 * x4 + 30);
  EXPECT_NEAR(quarticSlope(x4), kExact, 1e-6);
  const double thesisDiff[4] = {-95159.963, -186899.604, 0.0, -213580.328};
  const double thesisStd[4] = {2900053.551, 11507941.882, -1485695.206, -13417940.121};
  auto misfit = [&](double dx) {
    return std::abs(table22Pairs(dx, x4, DerivativeForm::Standard).pair[3] / thesisStd[3] - 1.0);
  };
  // Golden-section search for dx on [0.11, 0.14] m (one minimum there).
  double lo = 0.11, hi = 0.14;
  const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int it = 0; it < 80; ++it) {
    const double m1 = hi - phi * (hi - lo), m2 = lo + phi * (hi - lo);
    if (misfit(m1) < misfit(m2)) hi = m2;
    else lo = m1;
  }
  const double dx = 0.5 * (lo + hi);
  EXPECT_LT(misfit(dx), 1e-9);
  const Table22Pairs dif = table22Pairs(dx, x4, DerivativeForm::Difference);
  const Table22Pairs std_ = table22Pairs(dx, x4, DerivativeForm::Standard);
  EXPECT_EQ(dif.pair[2], 0.0);  // the difference form has no self pair
  double heldOut = 0.0;
  for (int q = 0; q < 4; ++q) {
    for (bool diff : {true, false}) {
      if (q == 2 && diff) continue;
      if (q == 3 && !diff) continue;  // the fitted value
      const double ours = diff ? dif.pair[q] : std_.pair[q];
      const double ref = diff ? thesisDiff[q] : thesisStd[q];
      const double rel = std::abs(ours / ref - 1.0);
      heldOut = std::max(heldOut, rel);
      EXPECT_LT(rel, 5e-5) << "held-out pair 4-" << q + 2 << (diff ? " (2.91b): " : " (2.91a): ")
                           << ours << " vs thesis " << ref;
    }
  }
  EXPECT_NEAR(dif.sum, std_.sum, 1e-9 * std::abs(dif.sum));
  const double sumRel = std::abs(dif.sum / kThesisSum - 1.0);
  EXPECT_LT(sumRel, 5e-5);
  const double err = 100.0 * std::abs(dif.sum - kExact) / std::abs(kExact);
  EXPECT_NEAR(err, kThesisError, 5e-4);  // the thesis prints 3 decimals
  std::printf("Table 2.2: x4 = %.9f m, dx = %.9f m (fitted to pair 4-5, 2.91a); held out: "
              "2.91a %.3f %.3f %.3f, 2.91b %.3f %.3f %.3f, sum %.3f, error %.4f %% (max rel. "
              "deviation of the pairs %.2g)\n",
              x4, dx, std_.pair[0], std_.pair[1], std_.pair[2], dif.pair[0], dif.pair[1],
              dif.pair[3], dif.sum, err, heldOut);
  char res[160];
  std::snprintf(res, sizeof res,
                "5 points, dx = %.6f m (fitted to pair 4-5), x4 = %.3f m (from the exact value), "
                "support 2.8 dx", dx, x4);
  const std::string source =
      "thesis Table 2.2 (reproduction on an inferred geometry, not the bar of the text)";
  recordValidation({"operator_study_bar1d_N5_table2.2_reproduction",
                    "max rel. deviation of the 6 held-out pair values at point 4 from the thesis, "
                    "mixed_2.63b (dx fitted to pair 4-5 without symmetry terms)",
                    heldOut, 0.0, heldOut, res, sw.seconds(), "each < 5e-5", source});
  recordValidation({"operator_study_bar1d_N5_table2.2_reproduction",
                    "div v3 at point 4 (sum of pairs, held out), mixed_2.63b", dif.sum, kThesisSum,
                    sumRel, res, sw.seconds(), "rel < 5e-5", source});
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
