// The fluid module's neighbour loops on a half neighbour list (scene key `neighbour_list: half`
// or `auto`, docs/performance.md "Half neighbour list"): each pair of real particles is stored
// once (NeighbourList::half) and evaluated once, its contribution added to both particles through
// PairScatter (libcore/pair_scatter.hpp: per-thread row blocks and spill buffers, no atomics, no
// allocation once the buffers reached their working size). A pair of a real particle and a
// ghost is in the real particle's row only and adds to it only (its mirror is in the row of the
// ghost's source), as in the gather loops.
//
// The fluid-fluid pair terms are written once for both loops (fluid_pair.hpp), the fluid-wall
// ones once in libcore (fluidBoundaryPair): each side's term is the gather loop's expression with
// r_ba = -r_ab (exact in floating point), so the two lists differ only in the order of the sums
// (round-off; tests/unit/test_half_neighbour_list.cpp).
// Eqs.: continuity 5.1a (or the mass form), pressure 5.2b (or 5.2a, Hu-Adams), viscosity 5.4 with the
// lattice normalisation, artificial viscosity 2.64-2.65, XSPH 2.66, wall extrapolation (Adami et
// al. 2012), density summation (number-density form).
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "libcore/artificial_viscosity.hpp"
#include "libcore/cell_walk.hpp"
#include "libcore/fluid_pair_terms.hpp"
#include "libcore/phases.hpp"
#include "libcore/simulation.hpp"
#include "physics/fluid/fluid_module.hpp"
#include "physics/fluid/fluid_pair.hpp"

namespace poresph {

namespace {

// The vectorised fluid-fluid block of the symmetric force loop (`pair_precision`, docs/fluid.md):
// the fluid-fluid pairs of a row whose both particles receive forces are collected (up to kBlock),
// their neighbour data gathered into small local arrays (structure of arrays, positions and
// velocities relative to particle i, differences taken in double), then one branch-free loop
// computes every pair's terms (the compiler vectorises it: no phase, material or option branch
// inside, kernel type and pressure form fixed at compile time), in Real = double or float; the
// sums of i are taken in double and the terms of j are scattered by a scalar loop.
constexpr int kBlock = 64;

template <class T>
struct FixedKernelType;
template <KernelType K, int D>
struct FixedKernelType<FixedKernel<K, D>> {
  static constexpr KernelType value = K;
};

template <class Real, int D>
struct FluidFluidBlock {
  using real_type = Real;
  int n = 0;
  Index j[kBlock];
  // neighbour data (gathered)
  Real r[D][kBlock], vab[D][kBlock], dist[kBlock];  // dist = |r| (sqrt in the gather: with
  // errno a sqrt is a branch, and the block loop would not vectorise)
  Real rho[kBlock], p[kBlock], pRho2[kBlock], V[kBlock], m[kBlock], c[kBlock], mu[kBlock];
  Real visc[kBlock], drho[kBlock], same[kBlock];
  Real wc[kBlock];  // continuity weight of side a (interfaceContinuityWeight; b's is 2 - wc)
  // terms of the pair for i (A) and j (B)
  Real fA[D][kBlock], fB[D][kBlock], divA[kBlock], divB[kBlock], diffA[kBlock], diffB[kBlock];
  Real momA[kBlock], momB[kBlock];
};

// Per-row constants of particle i and the run's pair options.
struct FluidFluidRow {
  Index i = 0;
  int material = 0;
  double rho = 0.0, p = 0.0, pRho2 = 0.0, V = 0.0, m = 0.0, c = 0.0, mu = 0.0, visc = 1.0;
};
struct FluidFluidRun {
  double kernelScale = 0.0, invH = 0.0, qMax = 0.0;  // F = kernelScale * dOverQ(|r| invH)
  double h = 0.0, alpha = 0.0, pOff = 0.0;
  bool harmonic = true, massForm = false, diffusion = false;
};

// The terms of the block's pairs (Eqs. 5.1a / mass form, 5.2b / 5.2a / Hu-Adams, 5.4, 2.64, density
// diffusion; fluid_pair.hpp) into the block's output arrays. Branch-free: a vectorisable loop
// (the continuity form is a template parameter: a select on a run-wide flag stops GCC 12's
// if-conversion, the diffusion switch is a 0/1 factor).
// On x86-64 with GCC the block is compiled twice, for the baseline (SSE2: float in 4 lanes, double
// not vectorised) and for AVX2 (float in 8 lanes, double in 4), the copy chosen once at load
// time by the processor (ifunc); no FMA in either, so both give the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define PORESPH_BLOCK_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define PORESPH_BLOCK_CLONES
#endif
#if defined(__GNUC__) && !defined(__clang__)
#define PORESPH_FLATTEN __attribute__((flatten))
#else
#define PORESPH_FLATTEN
#endif
template <class Real, int D, KernelType K, FluidPressureForm kForm, bool kMass>
PORESPH_BLOCK_CLONES void fluidFluidBlockTerms(FluidFluidBlock<Real, D>& b, const FluidFluidRow& row,
                          const FluidFluidRun& run) {
  const Real kScale = Real(run.kernelScale), invH = Real(run.invH);
  const Real h = Real(run.h), alpha = Real(run.alpha), pOff = Real(run.pOff);
  const Real fa = Real(row.visc), muA = Real(row.mu), rhoa = Real(row.rho);
  const Real Va = Real(row.V), ma = Real(row.m);
  const FluidPairParticleT<Real> pa{ma, rhoa, Va, Real(row.p), Real(row.pRho2), Real(row.c)};
  const Real harmonicOn = run.harmonic ? Real(1) : Real(0);
  const Real diffusionOn = run.diffusion ? Real(1) : Real(0);
  const double qMax = run.qMax;
  const int n = b.n;
#pragma omp simd
  for (int q = 0; q < n; ++q) {
    Real r2 = 0, vr = 0;
    for (int a = 0; a < D; ++a) {
      r2 += b.r[a][q] * b.r[a][q];
      vr += b.vab[a][q] * b.r[a][q];
    }
    // In double the distance and the density difference are taken here, vectorised (the sqrt
    // without errno: this file is compiled with -fno-math-errno, CMakeLists.txt), from the same
    // doubles the gather computed them from, so with the same bits; in float they come from
    // the gather, in double (the float path's rounding as before).
    constexpr bool kInBlock = std::is_same_v<Real, double>;
    Real dist, drho;
    if constexpr (kInBlock) {
      dist = std::sqrt(r2);
      drho = rhoa - b.rho[q];
    } else {
      dist = b.dist[q];
      drho = b.drho[q];
    }
    const Real F = kScale * KernelShape<K, D>::template dOverQBlend<Real>(dist * invH, qMax);
    const Real vg = F * vr;  // v_ab . grad W
    const Real muB = b.mu[q], muSum = muA + muB;
    // Eq. 5.4's mean: harmonic 4 mu_a mu_b / (mu_a + mu_b) or the sum; 0 for two inviscid fluids
    const Real muSafe = __builtin_isgreater(muSum, Real(0)) ? muSum : Real(1);
    const Real muBar = harmonicOn * (Real(4) * muA * muB / muSafe) + (Real(1) - harmonicOn) * muSum;
    const Real fab = Real(0.5) * (fa + b.visc[q]);
    // V_b = m_b / rho_b: in double here (vectorised, the quotient the gather took), in float
    // from the gather (the double quotient rounded)
    Real Vb;
    if constexpr (kInBlock)
      Vb = b.m[q] / b.rho[q];
    else
      Vb = b.V[q];
    const FluidPairParticleT<Real> pb{b.m[q], b.rho[q], Vb, b.p[q], b.pRho2[q], b.c[q]};
    const FluidFluidCoefficients<Real> c =
        fluidFluidCoefficients<Real, kForm>(F, vr, r2, pa, pb, muBar, fab, pOff, alpha, h);
    for (int a = 0; a < D; ++a) {
      const Real gw = F * b.r[a][q];
      b.fA[a][q] = (c.pressureA * gw + c.viscousA * b.vab[a][q]) + c.artificialA * gw;
      b.fB[a][q] = (c.pressureB * gw + c.viscousB * b.vab[a][q]) + c.artificialB * gw;
    }
    // continuityTerm times the pair's interface weight (1 within one material)
    const Real wA = b.wc[q], wB = Real(2) - b.wc[q];
    if constexpr (kMass) {
      b.divA[q] = wA * ((pb.m / rhoa) * vg);
      b.divB[q] = wB * ((ma / pb.rho) * vg);
    } else {
      b.divA[q] = wA * (pb.V * vg);
      b.divB[q] = wB * (Va * vg);
    }
    const Real dd = diffusionOn * b.same[q];  // densityDiffusionTerm, one material
    b.diffA[q] = dd * (Real(2) * pb.V * drho * F);
    b.diffB[q] = dd * (Real(2) * Va * (-drho) * F);
    b.momA[q] = -(pb.V * r2 * F);
    b.momB[q] = -(Va * r2 * F);
  }
}

// The rows of the symmetric loops: the stored half list (or its Verlet candidates), or the cell
// walk without a list (`neighbour_list: cells`, libcore/cell_walk.hpp). Both call f(j) for the
// same j of row i in the same order, so one loop body serves both (no physics written twice).
struct ListRows {
  const NeighbourList* nl;
  template <class F>
  void operator()(Index i, F&& f) const {
    const std::int64_t k1 = nl->offset[static_cast<size_t>(i) + 1];
    for (auto k = nl->offset[static_cast<size_t>(i)]; k < k1; ++k)
      f(static_cast<Index>(nl->index[static_cast<size_t>(k)]));
  }
};
template <int D>
struct WalkRows {
  CellWalk<D> walk;
  template <class F>
  void operator()(Index i, F&& f) const {
    walk.row(i, f);
  }
};
// Calls body(rows) with the rows of this evaluation: `candidates` asks for the candidates of
// the last search (a superset until the next one; with the walk, the exact pairs).
template <int D, class Body>
void withRows(const Simulation& sim, const double* x, bool candidates, Body&& body) {
  if (sim.cellWalk) {
    const WalkRows<D> rows{CellWalk<D>(sim.search.grid(), x, sim.kernel.support())};
    body(rows);
  } else {
    const ListRows rows{candidates ? &sim.neighbourCandidates() : &sim.neighbours};
    body(rows);
  }
}

}  // namespace

void FluidModule::layoutHalf(Simulation& sim, int width) {
  const Index n = sim.store.realCount();
  if (layoutBuild_ != sim.neighbourBuilds() || layoutCount_ != sim.store.size() ||
      scatter_.rows() != n || scatter_.threads() != std::max(1, omp_get_max_threads())) {
    // Once per neighbour search, before the step's loops: the exact list's rows are subsets of
    // the candidates' rows until the next search. Every buffer of the symmetric loops is sized
    // here for the widest of them, so that the loops themselves never allocate.
    const int maxWidth = halfWidth(sim.dimension());
    if (sim.cellWalk) {  // no list: blocks and spill bounds from the cells
      cellWalkBlocks(sim.search.grid(), sim.dimension(), sim.kernel.support(), n,
                     std::max(1, omp_get_max_threads()), walkBlocks_, walkSpill_, walkScratch_);
      scatter_.layoutBlocks(walkBlocks_, walkSpill_, n, maxWidth);
    } else {
      // Blocks balanced by the entries the loops evaluate (issue 17, docs/performance.md
      // "Serial fraction"): every entry of a fluid row, and of a boundary row only its real fluid
      // neighbours (the others, and every entry of a dry boundary row, are skipped).
      const NeighbourList& cand = sim.neighbourCandidates();
      const std::int32_t* ph = sim.store.data(sim.store.phase());
      const std::int64_t* off = cand.offset.data();
      const std::uint32_t* idx = cand.index.data();
      scatter_.layoutWeighted(cand, n, maxWidth, [=](Index i) -> std::int64_t {
        if (ph[i] == kPhaseFluid) return off[i + 1] - off[i];
        std::int64_t c = 0;
        for (std::int64_t k = off[i]; k < off[i + 1]; ++k) {
          const Index j = static_cast<Index>(idx[k]);
          c += (j < n && ph[j] == kPhaseFluid) ? 1 : 0;
        }
        return c;
      });
    }
    if (pairSum_.size() < static_cast<size_t>(n * maxWidth))
      pairSum_.resize(static_cast<size_t>(n * maxWidth));
    layoutBuild_ = sim.neighbourBuilds();
    layoutCount_ = sim.store.size();
  }
  scatter_.use(width);
}

int FluidModule::halfWidth(int d) const {
  // The wall extrapolation's 2 + D sums (+ D for the no-slip velocity when wall_velocity is
  // held); the force loop's D + 2 (+ 1 for the viscous moment when the factors are held) and
  // the optional XSPH, shifting and transport-velocity vectors; 1 for the density summation
  // and viscous factors.
  const int wall = 2 + d + (wallVelocity.valid() ? d : 0);
  return std::max(wall, forceWidth(d));
}

int FluidModule::forceWidth(int d) const {
  return d + 2 + (factors_ ? 1 : 0) + (xsph_ > 0.0 ? d : 0) + (shifting_ > 0.0 ? d : 0) +
         (transportVelocity_ ? d : 0);
}

// Boundary particles with a fluid neighbour (1) and fluid particles with a boundary neighbour
// (1), from the candidate lists; the gather form flags only the former (it visits only their
// rows), the half form visits the rows of both and skips every other row.
template <int D>
void FluidModule::wetFlagsHalf(Simulation& sim, const Fields& f) {
  const Index n = f.n;
  const Index* ghostSource = sim.store.ghostSources().data();
  unsigned char* wet = wetFlag_.data();
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) wet[i] = 0;
  if (sim.cellWalk) {
    // Without a list only the fluid rows are walked, whole (every neighbour, not only j > i):
    // a boundary particle with a fluid neighbour is a neighbour of that fluid particle (or, for a
    // ghost fluid neighbour, its image is one of the ghost's source; the halo holds every phase).
    // The flags are then the same as the half list's for the fluid particles and a superset for
    // the boundary (a flagged boundary particle without a fluid neighbour gets nothing).
    const CellWalk<D> walk(sim.search.grid(), f.x, sim.kernel.support());
#pragma omp parallel for schedule(dynamic, 512)
    for (Index i = 0; i < n; ++i) {
      if (f.ph[i] != kPhaseFluid) continue;
      walk.template row<false>(i, [&](const Index j) {
        if (f.ph[j] == kPhaseFluid) return;
        const Index b = j < n ? j : ghostSource[j - n];
#pragma omp atomic write
        wet[b] = 1;
#pragma omp atomic write
        wet[i] = 1;
      });
    }
    return;
  }
  withRows<D>(sim, f.x, true, [&](const auto& rows) {
#pragma omp parallel for schedule(dynamic, 512)
    for (Index i = 0; i < n; ++i) {
      const bool fi = f.ph[i] == kPhaseFluid;
      rows(i, [&](const Index j) {
        if ((f.ph[j] == kPhaseFluid) == fi) return;
        const Index b = j < n ? j : ghostSource[j - n];
#pragma omp atomic write
        wet[b] = 1;
#pragma omp atomic write
        wet[i] = 1;
      });
    }
  });
}

template <int D>
void FluidModule::wallExtrapolationHalf(Simulation& sim, const Fields& f) {
  const Index n = f.n;
  const unsigned char* wet = wetFlag_.data();
  Vec<D> g;
  {
    const std::array<double, 3> gNow = gravityAt(sim.time);  // x the gravity_schedule's factor
    for (int a = 0; a < D; ++a) g[a] = gNow[static_cast<size_t>(a)];
  }
  // Per boundary particle: sum W, sum p W, sum rho W r, sum v W (the gather loop's sums; the
  // last only when wall_velocity is held).
  const bool noSlip = f.vw != nullptr;
  const int w = noSlip ? 2 + 2 * D : 2 + D;
  layoutHalf(sim, w);
  double* own = pairSum_.data();
  withRows<D>(sim, f.x, false, [&](const auto& rows) {
  sim.kernel.withFixedType<D>([&](const auto K) {
#pragma omp parallel num_threads(scatter_.threads())
    {
      scatter_.forBlocks([&](int t) {
        scatter_.zero(t, own);
        for (Index i = scatter_.begin(t); i < scatter_.end(t); ++i) {
          if (!wet[i]) continue;  // neither a wet boundary particle nor a fluid one near it
          const bool fi = f.ph[i] == kPhaseFluid;
          double sw = 0.0, sp = 0.0;
          Vec<D> srr = Vec<D>::Zero(), sv = Vec<D>::Zero();
          rows(i, [&](const Index j) {
            const bool fj = f.ph[j] == kPhaseFluid;
            if (fi == fj) return;
            Vec<D> r;
            for (int a = 0; a < D; ++a) r[a] = f.x[i * D + a] - f.x[j * D + a];
            const double wk = K.value(r.norm());
            if (!fi) {  // i boundary, j fluid (real or ghost)
              sw += wk;
              sp += f.p[j] * wk;
              srr += (f.rho[j] * wk) * r;
              if (noSlip)
                for (int a = 0; a < D; ++a) sv[a] += f.v[j * D + a] * wk;
            } else if (j < n && wet[j]) {  // i fluid, j a real boundary particle
              double* tj = scatter_.at(t, own, j);
              const Vec<D> rji = -r;
              tj[0] += wk;
              tj[1] += f.p[i] * wk;
              const Vec<D> s = (f.rho[i] * wk) * rji;
              for (int a = 0; a < D; ++a) tj[2 + a] += s[a];
              if (noSlip)
                for (int a = 0; a < D; ++a) tj[2 + D + a] += f.v[i * D + a] * wk;
            }
          });
          if (!fi) {
            double* ti = own + i * w;
            ti[0] += sw;
            ti[1] += sp;
            for (int a = 0; a < D; ++a) ti[2 + a] += srr[a];
            if (noSlip)
              for (int a = 0; a < D; ++a) ti[2 + D + a] += sv[a];
          }
        }
      });
#pragma omp barrier
      scatter_.forBlocks([&](int t) {
        scatter_.reduce(t, own);
        for (Index i = scatter_.begin(t); i < scatter_.end(t); ++i) {
          if (f.ph[i] == kPhaseFluid) continue;
          const double* ti = own + i * w;
          const double sw = wet[i] ? ti[0] : 0.0;
          if (sw > 0.0) {
            Vec<D> ga = g;  // a moving boundary: g - a_w (Adami et al. 2012, Eq. 27)
            if (f.aw && f.mo[i] != kMotionFixed)
              for (int a = 0; a < D; ++a) ga[a] -= f.aw[i * D + a];
            Vec<D> srr;
            for (int a = 0; a < D; ++a) srr[a] = ti[2 + a];
            f.p[i] = (ti[1] + ga.dot(srr)) / sw;
            if (noSlip)
              for (int a = 0; a < D; ++a) f.vw[i * D + a] = 2.0 * f.v[i * D + a] - ti[2 + D + a] / sw;
          } else {
            f.p[i] = 0.0;
            if (noSlip)
              for (int a = 0; a < D; ++a) f.vw[i * D + a] = f.v[i * D + a];
          }
        }
      });
    }
  });
  });
}

template <int D>
void FluidModule::densitySummationHalf(Simulation& sim, const Fields& f) {
  const Index n = f.n;
  layoutHalf(sim, 1);
  double* own = pairSum_.data();
  const double w0 = sim.kernel.value(0.0);
  withRows<D>(sim, f.x, false, [&](const auto& rows) {
  sim.kernel.withFixedType<D>([&](const auto K) {
#pragma omp parallel num_threads(scatter_.threads())
    {
      scatter_.forBlocks([&](int t) {
        scatter_.zero(t, own);
        for (Index i = scatter_.begin(t); i < scatter_.end(t); ++i) {
          const bool fi = f.ph[i] == kPhaseFluid;
          double s = 0.0;
          rows(i, [&](const Index j) {
            const bool fj = j < n && f.ph[j] == kPhaseFluid;
            if (!fi && !fj) return;
            Vec<D> r;
            for (int a = 0; a < D; ++a) r[a] = f.x[i * D + a] - f.x[j * D + a];
            const double wk = K.value(r.norm());
            s += wk;
            if (fj) *scatter_.at(t, own, j) += wk;
          });
          own[i] += s;
        }
      });
#pragma omp barrier
      scatter_.forBlocks([&](int t) {
        scatter_.reduce(t, own);
        for (Index i = scatter_.begin(t); i < scatter_.end(t); ++i)
          if (f.ph[i] == kPhaseFluid) f.rho[i] = f.m[i] * (w0 + own[i]);
      });
    }
  });
  });
}

template <int D>
void FluidModule::viscousFactorsHalf(Simulation& sim, const Fields& f) {
  const Index n = f.n;
  layoutHalf(sim, 1);
  double* own = pairSum_.data();
  withRows<D>(sim, f.x, false, [&](const auto& rows) {
  sim.kernel.withFixedType<D>([&](const auto K) {
#pragma omp parallel num_threads(scatter_.threads())
    {
      scatter_.forBlocks([&](int t) {
        scatter_.zero(t, own);
        for (Index i = scatter_.begin(t); i < scatter_.end(t); ++i) {
          const bool fi = f.ph[i] == kPhaseFluid;
          double moment = 0.0;  // sum_b V_b |r_ab|^2 (-F_ab), as the gather pass
          rows(i, [&](const Index j) {
            const bool fj = j < n && f.ph[j] == kPhaseFluid;
            if (!fi && !fj) return;
            Vec<D> r;
            for (int a = 0; a < D; ++a) r[a] = f.x[i * D + a] - f.x[j * D + a];
            const double r2 = r.squaredNorm(), F = K.F(r.norm());
            if (fi) moment -= (f.m[j] / f.rho[j]) * r2 * F;
            if (fj) *scatter_.at(t, own, j) -= (f.m[i] / f.rho[i]) * r2 * F;
          });
          own[i] += moment;
        }
      });
#pragma omp barrier
      scatter_.forBlocks([&](int t) {
        scatter_.reduce(t, own);
        for (Index i = scatter_.begin(t); i < scatter_.end(t); ++i)
          f.visc[i] = f.ph[i] == kPhaseFluid && own[i] > 0.5 * D ? D / own[i] : 1.0;
      });
    }
  });
  });
}

template <int D>
void FluidModule::forceLoopHalf(Simulation& sim, const Fields& f, double uShift,
                                const double* wallRho) {
  const Index n = f.n;
  const bool xsphOn = xsph_ > 0.0, shiftOn = shifting_ > 0.0, tvOn = transportVelocity_;
  const double pOff = pressureReference_ ? backgroundPressure_ : 0.0;
  const double tvScale = tvOn ? sim.dt * backgroundPressure_ : 0.0;
  const MaterialData* md = mat_.data();
  const int nm = static_cast<int>(mat_.size());
  const double h = sim.kernel.h();
  const PressureForm pForm = pressureForm_;
  const double alpha = artificialViscosity_, delta = densityDiffusion_;
  const ContinuityForm form = continuityForm_;
  const FluidPairSettings pairSettings = sim.fluidPairSettings;
  const Volumes vol{f.m, f.rho};  // V = m / rho, per pair
  const double* pRho2 = pRho2_.data();
  const FluidFluidOptions ffOptions{pForm, pOff, alpha, h};
  Vec<D> g;
  {
    const std::array<double, 3> gNow = gravityAt(sim.time);  // x the gravity_schedule's factor
    for (int a = 0; a < D; ++a) g[a] = gNow[static_cast<size_t>(a)];
  }

  // Per particle: acceleration (pressure + viscous + artificial), continuity sum, diffusion sum,
  // viscous moment (only with the viscous factors), then the optional XSPH, shifting and
  // transport-velocity sums.
  const bool momOn = f.nextFactor != nullptr;
  const int kDiv = D, kDiff = D + 1, kMom = momOn ? D + 2 : -1;
  int width = momOn ? D + 3 : D + 2;
  const int kX = xsphOn ? width : -1;
  width += xsphOn ? D : 0;
  const int kC = shiftOn ? width : -1;
  width += shiftOn ? D : 0;
  const int kT = tvOn ? width : -1;
  width += tvOn ? D : 0;
  const int w = width;
  layoutHalf(sim, w);
  double* own = pairSum_.data();
  // A particle the loop gives forces to: a moving fluid particle of a fluid material (flags
  // set once per evaluation, read per pair).
  if (receives_.size() < static_cast<size_t>(n)) receives_.resize(static_cast<size_t>(n));
  unsigned char* recvW = receives_.data();
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) {
    const int id = f.mt[i];
    recvW[i] = f.ph[i] == kPhaseFluid && f.mo[i] != kMotionFixed && id >= 0 && id < nm && md[id].fluid;
  }
  const unsigned char* recv = recvW;
  auto receives = [recv](Index i) { return recv[i] != 0; };
  // One fluid material: every receiving particle is of it (the block's material columns are then
  // constants, above).
  int fluidMaterials = 0, theFluid = 0;
  for (int k = 0; k < nm; ++k)
    if (md[k].fluid) {
      ++fluidMaterials;
      theFluid = k;
    }
  const bool oneFluid = fluidMaterials == 1;
  auto valid = [&](int id) { return id >= 0 && id < nm; };
  // Rows of boundary particles without a fluid neighbour (the constitutive stage's flags, a
  // superset until the next search) hold no pair this loop evaluates: skipped whole.
  const unsigned char* wet = wetFlag_.data();
  // The vectorised fluid-fluid block (above) takes the pairs of two receiving fluid particles
  // unless XSPH, shifting or the transport velocity add per-pair vectors (then every pair takes
  // the scalar path below, in double).
  const bool blockOn = !xsphOn && !shiftOn && !tvOn;
  const bool floatPairs = floatPairs_ && blockOn;
  FluidFluidRun run;
  run.invH = 1.0 / h;
  run.h = h;
  run.alpha = alpha;
  run.pOff = pOff;
  run.harmonic = harmonicMean_;
  run.massForm = form == ContinuityForm::Mass;
  run.diffusion = delta > 0.0;

  withRows<D>(sim, f.x, false, [&](const auto& rows) {
  sim.kernel.withFixedType<D>([&](const auto K) {
    constexpr KernelType kType = FixedKernelType<std::decay_t<decltype(K)>>::value;
    FluidFluidRun kr = run;
    kr.kernelScale = K.norm * K.invH * K.invH;
    kr.invH = K.invH;
    kr.qMax = K.qMax;
#pragma omp parallel num_threads(scatter_.threads())
    {
      FluidFluidBlock<double, D> blockD;
      FluidFluidBlock<float, D> blockF;
      // The block's columns that are the same for every pair of the run, filled once per thread
      // instead of per block (issue 17, docs/performance.md "Instruction counts, case A"): the
      // material's sound speed, viscosity and same-material flag with one fluid material, the
      // viscous factor without the factors, the continuity weight without the acoustic interface.
      auto fillConstantColumns = [&](auto& blk) {
        using Real = typename std::decay_t<decltype(blk)>::real_type;
        for (int q = 0; q < kBlock; ++q) {
          if (oneFluid) {
            blk.c[q] = static_cast<Real>(md[theFluid].soundSpeed);
            blk.mu[q] = static_cast<Real>(md[theFluid].viscosity);
            blk.same[q] = Real(1);
          }
          if (!f.visc) blk.visc[q] = Real(1);
          if (!acousticInterface_) blk.wc[q] = Real(1);
        }
      };
      fillConstantColumns(blockD);
      fillConstantColumns(blockF);
      scatter_.forBlocks([&](int t) {
        scatter_.zero(t, own);
        for (Index i = scatter_.begin(t); i < scatter_.end(t); ++i) {
          const bool fluidA = f.ph[i] == kPhaseFluid, wallA = f.ph[i] == kPhaseWall;
          if (!fluidA && !wet[i]) continue;
          const bool recA = receives(i);
          const int ida = f.mt[i];
          const double rhoa = f.rho[i], pa = f.p[i], Va = f.m[i] / rhoa, ma = f.m[i];
          const double fa = f.visc ? f.visc[i] : 1.0;
          const MaterialData* mA = valid(ida) ? &md[ida] : nullptr;
          Vec<D> va;
          for (int a = 0; a < D; ++a) va[a] = f.v[i * D + a];
          Vec<D> accA = Vec<D>::Zero(), dvXA = Vec<D>::Zero(), gradCA = Vec<D>::Zero(),
                 tvA = Vec<D>::Zero();
          double divA = 0.0, diffA = 0.0, momA = 0.0;
          FluidFluidRow row;
          if (recA) {
            row.i = i;
            row.material = ida;
            row.rho = rhoa;
            row.p = pa;
            row.pRho2 = pRho2[i];
            row.V = vol[i];
            row.m = ma;
            row.c = mA->soundSpeed;
            row.mu = mA->viscosity;
            row.visc = fa;
          }
          // Gathers the block's neighbour data, evaluates its pairs and adds their terms to i's
          // sums (double) and to j's rows.
          auto flush = [&](auto& blk) {
            using Real = typename std::decay_t<decltype(blk)>::real_type;
            const int nb = blk.n;
            // (in double the distance and the density difference are the block's own, above)
            constexpr bool kGatherDist = !std::is_same_v<Real, double>;
            for (int q = 0; q < nb; ++q) {
              const Index j = blk.j[q];
              double d2 = 0.0;
              for (int a = 0; a < D; ++a) {
                const double ra = f.x[i * D + a] - f.x[j * D + a];
                if constexpr (kGatherDist) d2 += ra * ra;
                blk.r[a][q] = static_cast<Real>(ra);
                blk.vab[a][q] = static_cast<Real>(va[a] - f.v[j * D + a]);
              }
              if constexpr (kGatherDist) blk.dist[q] = static_cast<Real>(std::sqrt(d2));
              blk.rho[q] = static_cast<Real>(f.rho[j]);
              blk.p[q] = static_cast<Real>(f.p[j]);
              blk.pRho2[q] = static_cast<Real>(pRho2[j]);
              if constexpr (kGatherDist) blk.V[q] = static_cast<Real>(vol[j]);
              blk.m[q] = static_cast<Real>(f.m[j]);
              if constexpr (kGatherDist) blk.drho[q] = static_cast<Real>(rhoa - f.rho[j]);
            }
            // The neighbour's material: with one fluid material every receiving particle has it,
            // so both particles of a block pair are of i's material (the same values as the
            // per-pair lookup): those columns were filled once per thread (fillConstantColumns).
            if (!oneFluid) {
              for (int q = 0; q < nb; ++q) {
                const int mtj = f.mt[blk.j[q]];
                const MaterialData& mB = md[mtj];
                blk.c[q] = static_cast<Real>(mB.soundSpeed);
                blk.mu[q] = static_cast<Real>(mB.viscosity);
                blk.same[q] = mtj == ida ? Real(1) : Real(0);
              }
            }
            // The optional columns in loops of their own, the option tested once per block (the
            // same values as a test per pair; issue 17, docs/performance.md "Instruction counts").
            // (without them the columns hold 1, filled once per thread)
            if (const double* fv = f.visc)
              for (int q = 0; q < nb; ++q) blk.visc[q] = static_cast<Real>(fv[blk.j[q]]);
            if (acousticInterface_)
              for (int q = 0; q < nb; ++q)
                blk.wc[q] = static_cast<Real>(ifaceWeight_[static_cast<size_t>(ida * nm + f.mt[blk.j[q]])]);
            constexpr auto kSym = FluidPressureForm::Symmetric, kHu = FluidPressureForm::HuAdams,
                           kVol = FluidPressureForm::Volume;
            if (pForm == kHu)
              kr.massForm ? fluidFluidBlockTerms<Real, D, kType, kHu, true>(blk, row, kr)
                          : fluidFluidBlockTerms<Real, D, kType, kHu, false>(blk, row, kr);
            else if (pForm == kVol)
              kr.massForm ? fluidFluidBlockTerms<Real, D, kType, kVol, true>(blk, row, kr)
                          : fluidFluidBlockTerms<Real, D, kType, kVol, false>(blk, row, kr);
            else
              kr.massForm ? fluidFluidBlockTerms<Real, D, kType, kSym, true>(blk, row, kr)
                          : fluidFluidBlockTerms<Real, D, kType, kSym, false>(blk, row, kr);
            // The scatter, with the viscous moment's branch taken once per block (two copies of
            // the loop; the same sums in the same order).
            auto scatterBlock = [&](auto withMoment) {
              for (int q = 0; q < nb; ++q) {
                double* tb = scatter_.at(t, own, blk.j[q]);
                for (int a = 0; a < D; ++a) {
                  tb[a] += static_cast<double>(blk.fB[a][q]);
                  accA[a] += static_cast<double>(blk.fA[a][q]);
                }
                tb[kDiv] += static_cast<double>(blk.divB[q]);
                tb[kDiff] += static_cast<double>(blk.diffB[q]);
                if constexpr (decltype(withMoment)::value) tb[kMom] += static_cast<double>(blk.momB[q]);
                divA += static_cast<double>(blk.divA[q]);
                diffA += static_cast<double>(blk.diffA[q]);
                if constexpr (decltype(withMoment)::value) momA += static_cast<double>(blk.momA[q]);
              }
            };
            if (momOn) scatterBlock(std::true_type{});
            else scatterBlock(std::false_type{});
            blk.n = 0;
          };
          auto push = [&](auto& blk, Index j) {
            blk.j[blk.n++] = j;
            if (blk.n == kBlock) flush(blk);
          };
          // The fluid side of i's fluid-wall pairs, the same for each of them.
          FluidPairSide<D> sideA;
          if (recA) {
            sideA.m = ma;
            sideA.rho = rhoa;
            sideA.p = pa;
            sideA.props = mA;
            sideA.v = va;
          }
          // Every pair the block does not take (scalar, double). Flattened: the fluid-wall pair
          // terms (fluidBoundaryPair, which GCC 12 called out of line with its 80-byte result
          // through memory) are inlined here; the same arithmetic (baseline x86-64: no FMA to
          // contract into), so the same bits.
          auto scalarPair = [&](const Index j, const bool recB) PORESPH_FLATTEN {
            Vec<D> r;
            for (int a = 0; a < D; ++a) r[a] = f.x[i * D + a] - f.x[j * D + a];
            const double F = K.F(r.norm());
            if (F == 0.0) return;
            const Vec<D> gradW = F * r;  // grad_a W_ab; grad_b W_ba = -gradW
            Vec<D> vb;
            for (int a = 0; a < D; ++a) vb[a] = f.v[j * D + a];
            double* tb = recB ? scatter_.at(t, own, j) : nullptr;
            const double r2 = r.squaredNorm();
            // Every neighbour: the viscous moment for the next factor, shifting and transport
            // velocity sums (as the gather loop).
            if (momOn) {
              if (recA) momA -= vol[j] * r2 * F;
              if (recB) tb[kMom] -= vol[i] * r2 * F;
            }
            if (shiftOn) {
              if (recA) gradCA += (f.m[j] / f.rho[j]) * gradW;
              if (recB)
                for (int a = 0; a < D; ++a) tb[kC + a] -= (f.m[i] / f.rho[i]) * gradW[a];
            }
            if (tvOn) {
              const double Vb = f.m[j] / f.rho[j];
              if (recA) tvA += (Va * Va + Vb * Vb) * gradW;
              if (recB) {
                const Vec<D> s = (Vb * Vb + Va * Va) * gradW;
                for (int a = 0; a < D; ++a) tb[kT + a] -= s[a];
              }
            }
            const bool fluidB = f.ph[j] == kPhaseFluid, wallB = f.ph[j] == kPhaseWall;
            // Fluid-wall pairs: the shared pair terms, for the fluid side only (walls are fixed).
            if (recA && wallB) {
              const FluidPairResult<D> tr =
                  fluidBoundaryPair<D>(r, F, sideA, wallPairSide<D>(f, j, vol, wallRho, vb), pairSettings);
              accA += tr.pressure;
              accA += fa * tr.viscous;
              accA += tr.artificial;
              divA += tr.divergence;
            }
            if (recB && wallA) {
              const int idb = f.mt[j];
              FluidPairSide<D> sa;
              sa.m = f.m[j];
              sa.rho = f.rho[j];
              sa.p = f.p[j];
              sa.props = &md[idb];
              sa.v = vb;
              const Vec<D> rji = -r;
              const FluidPairResult<D> tr =
                  fluidBoundaryPair<D>(rji, F, sa, wallPairSide<D>(f, i, vol, wallRho, va), pairSettings);
              const double fb = f.visc ? f.visc[j] : 1.0;
              const Vec<D> s = tr.pressure + fb * tr.viscous + tr.artificial;
              for (int a = 0; a < D; ++a) tb[a] += s[a];
              tb[kDiv] += tr.divergence;
            }
            if (!(fluidA && fluidB)) return;  // fluid-solid / fluid-rigid: the coupling's
            // Fluid-fluid pair (Eqs. 5.1a, 5.2b / 5.2a / Hu-Adams, 5.4, 2.64): each side's term as the
            // gather loop writes it for that side.
            const int idb = f.mt[j];
            const MaterialData* mB = valid(idb) ? &md[idb] : nullptr;
            const double rhob = f.rho[j], pb = f.p[j], Vb = vol[j], mb = f.m[j];
            const double muA = mA ? mA->viscosity : (mB ? mB->viscosity : 0.0);
            const double muB = mB ? mB->viscosity : muA;
            const double muBar =
                muA + muB > 0.0 ? (harmonicMean_ ? 4.0 * muA * muB / (muA + muB) : muA + muB)
                                : 0.0;
            const double fab = 0.5 * (fa + (f.visc ? f.visc[j] : 1.0));
            const Vec<D> vab = va - vb;
            const double vabGradW = vab.dot(gradW);  // = v_ba . grad_b W_ba
            if (delta > 0.0 && idb == ida) {  // Molteni-Colagrossi density diffusion
              if (recA) diffA += densityDiffusionTerm(Vb, rhoa, rhob, F);
              if (recB) tb[kDiff] += densityDiffusionTerm(Va, rhob, rhoa, F);
            }
            if (xsphOn && idb == ida) {  // XSPH (2.66) within one material
              const double wk = K.value(r.norm());
              if (recA) dvXA += xsphTerm<D>(mb, rhoa, rhob, wk, vb, va);
              if (recB) {
                const Vec<D> s = xsphTerm<D>(ma, rhob, rhoa, wk, va, vb);
                for (int a = 0; a < D; ++a) tb[kX + a] += s[a];
              }
            }
            // Pressure, viscosity, artificial viscosity of both sides (fluid_pair.hpp).
            const double ca = mA ? mA->soundSpeed : mB->soundSpeed;
            const double cb = mB ? mB->soundSpeed : ca;
            const FluidPairParticle pa_{ma, rhoa, Va, pa, pRho2[i], ca};
            const FluidPairParticle pb_{mb, rhob, Vb, pb, pRho2[j], cb};
            FluidFluidAccel<D> ta, tbAcc;
            fluidFluidPair<D, true>(r, gradW, F, vab, pa_, pb_, muBar, fab, ffOptions, ta, tbAcc);
            const Vec<D> fA = ta.pressure + ta.viscous + ta.artificial;
            const Vec<D> fB = tbAcc.pressure + tbAcc.viscous + tbAcc.artificial;
            // Eq. 5.1a / mass form, times the interface weight between two fluids
            // (interfaceContinuityWeight; 1 within one material)
            const double wcA = acousticInterface_ && valid(ida) && valid(idb)
                                   ? ifaceWeight_[static_cast<size_t>(ida * nm + idb)]
                                   : 1.0;
            if (recA) {
              accA += fA;
              divA += wcA * continuityTerm(form, rhoa, mb, Vb, vabGradW);
            }
            if (recB) {
              for (int a = 0; a < D; ++a) tb[a] += fB[a];
              tb[kDiv] += (2.0 - wcA) * continuityTerm(form, rhob, ma, Va, vabGradW);
            }
          };
          // The row, with the choice of the block (and of its precision) taken once per row
          // instead of per entry (issue 17, docs/performance.md "Instruction counts, case A"):
          // the same pairs in the same order as one loop with the tests inside.
          if (blockOn && recA) {  // fluid-fluid pairs of two receiving particles: the block
            auto blockRow = [&](auto& blk) {
              rows(i, [&](const Index j) {
                if (j < n && receives(j))
                  push(blk, j);
                else
                  scalarPair(j, false);
              });
            };
            if (floatPairs)
              blockRow(blockF);
            else
              blockRow(blockD);
          } else {
            rows(i, [&](const Index j) {
              const bool recB = j < n && receives(j);
              if (!recA && !recB) return;
              scalarPair(j, recB);
            });
          }
          if (blockF.n > 0) flush(blockF);
          if (blockD.n > 0) flush(blockD);
          if (recA) {
            double* ti = own + i * w;
            for (int a = 0; a < D; ++a) ti[a] += accA[a];
            ti[kDiv] += divA;
            ti[kDiff] += diffA;
            if (momOn) ti[kMom] += momA;
            for (int a = 0; a < D; ++a) {
              if (xsphOn) ti[kX + a] += dvXA[a];
              if (shiftOn) ti[kC + a] += gradCA[a];
              if (tvOn) ti[kT + a] += tvA[a];
            }
          }
        }
      });
#pragma omp barrier
      // Every pair is in: the per-particle part, as at the end of the gather loop's row.
      scatter_.forBlocks([&](int t) {
        scatter_.reduce(t, own);
        for (Index i = scatter_.begin(t); i < scatter_.end(t); ++i) {
          if (f.nextFactor) f.nextFactor[i] = 1.0;
          if (!receives(i)) continue;
          const double* ti = own + i * w;
          const MaterialData& ma = md[f.mt[i]];
          if (momOn) f.nextFactor[i] = ti[kMom] > 0.5 * D ? D / ti[kMom] : 1.0;
          Vec<D> ai;
          for (int a = 0; a < D; ++a) ai[a] = ti[a] + g[a];
          addBodyForces<D>(f.x + i * D, ai);
          for (int a = 0; a < D; ++a) f.acc[i * D + a] += ai[a];
          if (f.drho) f.drho[i] += f.rho[i] * ti[kDiv] + delta * h * ma.soundSpeed * ti[kDiff];
          if (f.corrRate) {  // XSPH, transport velocity, shifting: as the gather loop
            Vec<D> dv = Vec<D>::Zero();
            if (xsphOn)
              for (int a = 0; a < D; ++a) dv[a] = xsph_ * ti[kX + a];
            if (tvOn)
              for (int a = 0; a < D; ++a) dv[a] -= (tvScale / f.m[i]) * ti[kT + a];
            if (shiftOn) {
              Vec<D> ds;
              for (int a = 0; a < D; ++a) ds[a] = -shifting_ * h * uShift * ti[kC + a];
              const double cap = 0.5 * uShift, len = ds.norm();
              if (len > cap) ds *= cap / len;
              dv += ds;
            }
            for (int a = 0; a < D; ++a) f.corrRate[i * D + a] += dv[a];
          }
        }
      });
    }
  });
  });
}

std::uint64_t FluidModule::heldBytes() const {
  // The symmetric loops' sums and spills, the cell walk's layout scratch, and the force loop's
  // per-particle scratch ((p - p_ref) / rho^2 or the wall density; flags of wet and receiving
  // particles), which every fluid run holds.
  return static_cast<std::uint64_t>(
      scatter_.bytes() + pairSum_.capacity() * sizeof(double) + walkScratch_.bytes() +
      (walkBlocks_.capacity() + walkSpill_.capacity()) * sizeof(Index) +
      pRho2_.capacity() * sizeof(double) +
      wetFlag_.capacity() + receives_.capacity());
}

double FluidModule::deferredBytesPerParticle(const Simulation& sim, double,
                                             const std::vector<Index>&) const {
  if (!sim.halfNeighbourList) return 0.0;
  // The force loop's sums (acceleration, continuity, diffusion, moment and the optional XSPH,
  // shifting and transport-velocity vectors) for every particle, plus the spills: about a slab
  // of the support's thickness per thread boundary, counted here as 10 % (docs/performance.md).
  return 1.1 * halfWidth(sim.dimension()) * sizeof(double);
}

#define PORESPH_FLUID_HALF(D)                                                                 \
  template void FluidModule::wetFlagsHalf<D>(Simulation&, const Fields&);                     \
  template void FluidModule::wallExtrapolationHalf<D>(Simulation&, const Fields&);            \
  template void FluidModule::densitySummationHalf<D>(Simulation&, const Fields&);             \
  template void FluidModule::viscousFactorsHalf<D>(Simulation&, const Fields&);               \
  template void FluidModule::forceLoopHalf<D>(Simulation&, const Fields&, double, const double*);
PORESPH_FLUID_HALF(1)
PORESPH_FLUID_HALF(2)
PORESPH_FLUID_HALF(3)
#undef PORESPH_FLUID_HALF

}  // namespace poresph
