#include "libcore/neighbour_search.hpp"

#include "libcore/cell_walk.hpp"

#include <omp.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>

namespace poresph {

#ifndef PORESPH_CELL_FRACTION
#define PORESPH_CELL_FRACTION 0.5
#endif
// Cell edge / radius of the search (0.5: measured fastest, docs/performance.md).
constexpr double kCellFraction = PORESPH_CELL_FRACTION;
// Below this many particles the passes of a search run without an OpenMP region (a region costs
// ~2k instructions even at one thread; the box at rest, 676 particles, rebuilds every step).
// The results do not depend on it: min/max reductions and per-particle writes are exact.
constexpr Index kSerialBelow = 4096;


template <int D>
void NeighbourSearch::sortIntoCells(const double* x, Index n, double cellSize) {
  // Bounding box of all particles (ghosts included). A NaN or Inf position is an error: it would
  // otherwise be silently binned into cell 0 (min/max ignore NaN).
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  double maxAbs = 0.0;
  for (int a = 0; a < D; ++a) {
    double mn = std::numeric_limits<double>::max(), mx = -std::numeric_limits<double>::max();
    int bad = 0;
    const auto scan = [&](Index i, double& lo_, double& hi_, int& bad_) {
      const double v = x[i * D + a];
      if (!std::isfinite(v)) bad_ = 1;
      lo_ = std::min(lo_, v);
      hi_ = std::max(hi_, v);
    };
    if (n < kSerialBelow) {
      for (Index i = 0; i < n; ++i) scan(i, mn, mx, bad);
    } else {
#pragma omp parallel for reduction(min : mn) reduction(max : mx, bad) schedule(static)
      for (Index i = 0; i < n; ++i) scan(i, mn, mx, bad);
    }
    if (bad) {
      Index first = 0;
      while (first < n && std::isfinite(x[first * D + a])) ++first;
      throw NumericalError("neighbour search: position of particle " + std::to_string(first) +
                           " is not finite (axis " + std::to_string(a) + ")");
    }
    if (n == 0) mn = mx = 0.0;
    if (!std::isfinite(mx - mn))
      throw NumericalError("neighbour search: particle positions span more than the largest double");
    lo[a] = mn;
    hi[a] = mx;
    maxAbs = std::max({maxAbs, std::abs(mn), std::abs(mx)});
  }
  // Cell size as asked, enlarged when the cell count would exceed ~2 cells per particle (tiny h
  // in a large box): larger cells only add candidates, never lose a pair. The smallest cell that
  // meets the cap is found by bisection, so the count stays bounded whatever the box/h ratio.
  const double target = 2.0 * static_cast<double>(n) + 64.0;
  auto cellsFor = [&](double c) {
    double cells = 1.0;
    for (int a = 0; a < D; ++a) cells *= std::floor((hi[a] - lo[a]) / c) + 1.0;
    return cells;
  };
  double cell = cellSize;
  if (cellsFor(cell) > target) {
    double small = cell, large = cell;
    for (int a = 0; a < D; ++a) large = std::max(large, 2.0 * (hi[a] - lo[a]));  // one cell
    for (int iter = 0; iter < 200 && large > small * (1.0 + 1e-6); ++iter) {
      const double mid = std::sqrt(small) * std::sqrt(large);  // geometric: ratios can be 1e300
      if (cellsFor(mid) > target) small = mid; else large = mid;
    }
    cell = large;
  }
  invCell_ = 1.0 / cell;
  // Round-off guard of the row pruning in buildDim: cell bounds computed as origin + c * cell
  // may differ from the binning (x - origin) * invCell by a few ulps of the coordinates.
  margin_ = 1e-9 * cell + 16.0 * DBL_EPSILON * maxAbs;
  nCells_ = 1;
  for (int a = 0; a < 3; ++a) dims_[a] = 1;
  for (int a = 0; a < D; ++a) {
    origin_[a] = lo[a];
    dims_[a] = static_cast<int>(std::floor((hi[a] - lo[a]) * invCell_)) + 1;
    nCells_ *= dims_[a];
  }
  if (static_cast<double>(nCells_) >= static_cast<double>(std::numeric_limits<CellIndex>::max()))
    throw std::logic_error("neighbour search: " + std::to_string(nCells_) +
                           " cells exceed the 32-bit cell index");
  cellOf_.resize(static_cast<size_t>(n));
  const auto bin = [&](Index i) {
    Index c = 0;
    for (int a = D - 1; a >= 0; --a) {
      int k = static_cast<int>((x[i * D + a] - origin_[a]) * invCell_);
      k = std::min(std::max(k, 0), dims_[a] - 1);
      c = c * dims_[a] + k;
    }
    cellOf_[static_cast<size_t>(i)] = static_cast<CellIndex>(c);
  };
  if (n < kSerialBelow) {
    for (Index i = 0; i < n; ++i) bin(i);
  } else {
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) bin(i);
  }
  // Counting sort (stable: particles keep their order within a cell). cellStart_[c] serves as
  // the cursor of cell c while filling (it then holds the end of c, the start of c + 1) and is
  // shifted back afterwards: no separate cursor array.
  cellStart_.assign(static_cast<size_t>(nCells_) + 1, 0);
  for (Index i = 0; i < n; ++i) ++cellStart_[static_cast<size_t>(cellOf_[static_cast<size_t>(i)]) + 1];
  for (Index c = 0; c < nCells_; ++c) cellStart_[static_cast<size_t>(c) + 1] += cellStart_[static_cast<size_t>(c)];
  sorted_.resize(static_cast<size_t>(n));
  for (Index i = 0; i < n; ++i) {
    const CellIndex c = cellOf_[static_cast<size_t>(i)];
    sorted_[static_cast<size_t>(cellStart_[c]++)] = static_cast<CellIndex>(i);
  }
  for (Index c = nCells_; c > 0; --c) cellStart_[static_cast<size_t>(c)] = cellStart_[static_cast<size_t>(c) - 1];
  cellStart_[0] = 0;
}

template <int D>
void NeighbourSearch::copySortedPositions(const double* x, Index n) {
  // Positions in cell order: the candidates of a row of cells are contiguous in memory.
  xs_.resize(static_cast<size_t>(n) * D);
  const auto copy = [&](Index s) {
    for (int a = 0; a < D; ++a) xs_[static_cast<size_t>(s * D + a)] = x[sorted_[static_cast<size_t>(s)] * D + a];
  };
  if (n < kSerialBelow) {
    for (Index s = 0; s < n; ++s) copy(s);
  } else {
#pragma omp parallel for schedule(static)
    for (Index s = 0; s < n; ++s) copy(s);
  }
  gridCount_ = n;
}

template <int D>
void NeighbourSearch::buildDim(const double* x, Index nReal, Index nTotal, double radius,
                               NeighbourList& out, bool half, const PairFilter& keep) {
  out.half = half;
  // Cells of half the radius: the candidates of a particle fill a box of (radius + cell) half
  // width instead of (2 radius) for cells of one radius; rows are then pruned to the sphere.
  sortIntoCells<D>(x, nTotal, kCellFraction * radius);
  const double r2max = radius * radius;
  copySortedPositions<D>(x, nTotal);

  const int nThreads = omp_get_max_threads();
  if (static_cast<int>(threadIndex_.size()) < nThreads) {
    threadIndex_.resize(static_cast<size_t>(nThreads));
    threadCount_.resize(static_cast<size_t>(nThreads));
  }
  out.offset.resize(static_cast<size_t>(nReal) + 1);
  std::vector<std::int64_t>& chunkBegin = chunkBegin_;
  chunkBegin.assign(static_cast<size_t>(nThreads) + 1, 0);
  regionBegin_.assign(static_cast<size_t>(nThreads) + 1, 0);
  regionUsed_.assign(static_cast<size_t>(nThreads), 0);
  if (prevChunk_.size() < static_cast<size_t>(nThreads)) prevChunk_.resize(static_cast<size_t>(nThreads), 0);
  bool anyOverflow = false;
  // Pair classes (PairFilter): off when every class is kept or a particle has a phase outside
  // [0, kPhaseCount) (then every pair is kept, as documented).
  bool filterOn = keep.active();
  if (filterOn) {
    int bad = 0;
    const std::int32_t* ph = keep.phase;
    const auto check = [&](Index i, int& bad_) {
      bad_ = std::max(bad_, static_cast<int>(static_cast<std::uint32_t>(ph[i]) >=
                                             static_cast<std::uint32_t>(kPhaseCount)));
    };
    if (nTotal < kSerialBelow) {
      for (Index i = 0; i < nTotal; ++i) check(i, bad);
    } else {
#pragma omp parallel for schedule(static) reduction(max : bad)
      for (Index i = 0; i < nTotal; ++i) check(i, bad);
    }
    filterOn = bad == 0;
  }
  const std::int32_t* phase = keep.phase;
  const PairMask mask = keep.mask;
  // The traversal is the cell walk's (libcore/cell_walk.hpp): the same rows of cells, pruned
  // to the sphere, in slot order; here every candidate is appended and kept when inside.
  const NeighbourSearch::Grid g = grid();
  const CellWalk<D> walk(g, x, radius);
  // One thread, or few particles: the region's body runs on the calling thread, without an
  // OpenMP region (its single/barrier constructs then bind to a team of one).
  const bool serial = nThreads == 1 || nTotal < kSerialBelow;
  const auto region = [&](const int t, const int nt) {
    const Index i0 = nReal * t / nt, i1 = nReal * (t + 1) / nt;
    auto& idx = threadIndex_[static_cast<size_t>(t)];
    auto& cnt = threadCount_[static_cast<size_t>(t)];
    cnt.clear();
#pragma omp single
    {
      // Regions of the output, one per thread, from the chunk lengths of the previous build.
      std::int64_t prevTotal = 0;
      for (int k = 0; k < prevThreads_; ++k) prevTotal += prevChunk_[static_cast<size_t>(k)];
      for (int k = 0; k < nt; ++k) {
        const std::int64_t est =
            prevThreads_ == nt ? prevChunk_[static_cast<size_t>(k)] : prevTotal / nt;
        regionBegin_[static_cast<size_t>(k) + 1] = regionBegin_[static_cast<size_t>(k)] + est + est / 8 + 1024;
      }
      const std::size_t want = static_cast<std::size_t>(regionBegin_[static_cast<size_t>(nt)]);
      // Explicit reserve: a plain resize beyond the capacity would double it.
      if (want > out.index.capacity()) out.index.reserve(want + want / 16);
      out.index.resize(want);
    }  // implicit barrier
    std::uint32_t* dst = out.index.data() + regionBegin_[static_cast<size_t>(t)];
    std::size_t cap = static_cast<std::size_t>(regionBegin_[static_cast<size_t>(t) + 1] -
                                               regionBegin_[static_cast<size_t>(t)]);
    bool inRegion = true;
    std::size_t regionUsed = 0;
    std::size_t used = 0;  // entries written at dst (region first, then the overflow buffer)
    std::size_t total = 0; // entries of this thread so far, region + overflow
    for (Index i = i0; i < i1; ++i) {
      // Smallest index kept, minus one: j > i for a half list, every j != i otherwise.
      const Index jFloor = half ? i : Index(-1);
      // The neighbour phases row i keeps (bit q: phase q), with the pair-class filter.
      constexpr std::uint32_t kEvery = (1u << kPhaseCount) - 1;
      const std::uint32_t rowKeep =
          filterOn ? (mask >> (static_cast<std::uint32_t>(phase[i]) * kPhaseCount)) & kEvery : kEvery;
      if (rowKeep == 0) {  // no class of this row's phase is read: an empty row, not searched
        cnt.push_back(0);
        continue;
      }
      const typename CellWalk<D>::Span sp = walk.span(i);
      // Room for every candidate of this particle: all particles of the block of cells.
      {
        const std::size_t need = static_cast<std::size_t>(walk.candidateBound(sp));
        if (inRegion && used + need > cap) {  // region full: continue in the overflow buffer
          inRegion = false;
          regionUsed = used;
          used = 0;
          cap = 0;
        }
        if (!inRegion && cap < used + need) {
          // Grow by a quarter (not doubling): slack costs real memory at 1e6+ particles.
          idx.resize(std::max(idx.size() + idx.size() / 4, used + need + 4096));
          cap = idx.size();
        }
        if (!inRegion) dst = idx.data();
      }
      const std::size_t start = used;
      // Branch-free append: write every candidate, keep it when inside the radius (and, with
      // the pair-class filter, when row i keeps the neighbour's phase).
      const auto walkRow = [&](auto&& visit) {
        if (half)
          walk.template candidates<true>(i, sp, visit);  // skips cells of indices <= i
        else
          walk.candidates(i, sp, visit);
      };
      if (filterOn && rowKeep != kEvery) {
        walkRow([&](Index j, double r2) {
          dst[used] = static_cast<std::uint32_t>(j);
          const std::uint32_t pj = static_cast<std::uint32_t>(phase[j]);
          used += static_cast<std::size_t>((r2 < r2max) & (j != i) & (j > jFloor) &
                                           ((rowKeep >> pj) & 1u));
        });
      } else {
        walkRow([&](Index j, double r2) {
          dst[used] = static_cast<std::uint32_t>(j);
          used += static_cast<std::size_t>((r2 < r2max) & (j != i) & (j > jFloor));
        });
      }
      cnt.push_back(static_cast<std::int64_t>(used - start));
      total += used - start;
    }
    if (inRegion) regionUsed = used;
    regionUsed_[static_cast<size_t>(t)] = static_cast<std::int64_t>(regionUsed);
    chunkBegin[static_cast<size_t>(t) + 1] = static_cast<std::int64_t>(total);
    prevChunk_[static_cast<size_t>(t)] = static_cast<std::int64_t>(total);
    if (!inRegion) {
#pragma omp atomic write
      anyOverflow = true;
    }
#pragma omp barrier
#pragma omp single
    {
      for (int k = 0; k < nt; ++k) chunkBegin[static_cast<size_t>(k) + 1] += chunkBegin[static_cast<size_t>(k)];
      const std::size_t n = static_cast<std::size_t>(chunkBegin[static_cast<size_t>(nt)]);
      if (!anyOverflow) {
        // Every chunk fits its region, so chunk k moves left (or stays): in increasing k the
        // moves never overwrite data not yet moved.
        std::uint32_t* base = out.index.data();
        for (int k = 1; k < nt; ++k)
          std::memmove(base + chunkBegin[static_cast<size_t>(k)], base + regionBegin_[static_cast<size_t>(k)],
                       sizeof(std::uint32_t) * static_cast<std::size_t>(regionUsed_[static_cast<size_t>(k)]));
        out.index.resize(n);
      } else {
        // The list grew: assemble it in a new array (allocates; only when the list grows).
        NeighbourList::IndexVector fresh;
        // Room for the regions of the next build (chunk + 1/8 + 1024 each), so that a steady
        // list does not reallocate again.
        fresh.reserve(n + n / 8 + 1024 * static_cast<std::size_t>(nt));
        fresh.resize(n);
        for (int k = 0; k < nt; ++k) {
          const std::uint32_t* region = out.index.data() + regionBegin_[static_cast<size_t>(k)];
          const std::size_t ru = static_cast<std::size_t>(regionUsed_[static_cast<size_t>(k)]);
          const std::size_t len = static_cast<std::size_t>(chunkBegin[static_cast<size_t>(k) + 1] -
                                                           chunkBegin[static_cast<size_t>(k)]);
          std::uint32_t* to = fresh.data() + chunkBegin[static_cast<size_t>(k)];
          std::copy(region, region + ru, to);
          const auto& over = threadIndex_[static_cast<size_t>(k)];
          std::copy(over.begin(), over.begin() + static_cast<std::ptrdiff_t>(len - ru), to + ru);
        }
        out.index.swap(fresh);
        for (int k = 0; k < nt; ++k) std::vector<std::uint32_t>().swap(threadIndex_[static_cast<size_t>(k)]);
      }
      prevThreads_ = nt;
    }
    std::int64_t o = chunkBegin[static_cast<size_t>(t)];
    for (Index i = i0; i < i1; ++i) {
      out.offset[static_cast<size_t>(i)] = o;
      o += cnt[static_cast<size_t>(i - i0)];
    }
  };
  if (serial) {
    region(0, 1);
  } else {
#pragma omp parallel num_threads(nThreads)
    region(omp_get_thread_num(), omp_get_num_threads());
  }
  out.offset[static_cast<size_t>(nReal)] = static_cast<std::int64_t>(out.index.size());
}

void NeighbourSearch::build(const double* x, int dim, Index nReal, Index nTotal, double radius,
                            NeighbourList& out, bool half, const PairFilter& keep) {
  if (!(radius > 0.0) || !(radius * radius > 0.0) || !std::isfinite(radius * radius))
    throw std::logic_error("neighbour search: radius must be positive and finite (and its square "
                           "a normal double), got " + std::to_string(radius));
  if (nReal < 0 || nReal > nTotal)
    throw std::logic_error("neighbour search: need 0 <= nReal <= nTotal");
  if (nTotal > static_cast<Index>(std::numeric_limits<std::uint32_t>::max()))
    throw std::logic_error("neighbour search: more than 2^32 particles in one store");
  dispatchDimension(dim, [&](auto d) {
    buildDim<decltype(d)::value>(x, nReal, nTotal, radius, out, half, keep);
  });
}

void NeighbourSearch::sortCells(const double* x, int dim, Index nTotal, double radius) {
  if (!(radius > 0.0) || !(radius * radius > 0.0) || !std::isfinite(radius * radius))
    throw std::logic_error("neighbour search: radius must be positive and finite (and its square "
                           "a normal double), got " + std::to_string(radius));
  if (nTotal < 0 || nTotal > static_cast<Index>(std::numeric_limits<std::uint32_t>::max()))
    throw std::logic_error("neighbour search: need 0 <= particles < 2^32 in one store");
  // The same cells as build() (kCellFraction of the radius, enlarged by the same cap), so that
  // a walk of them visits the candidates of build() in the same order.
  dispatchDimension(dim, [&](auto d) {
    constexpr int D = decltype(d)::value;
    sortIntoCells<D>(x, nTotal, kCellFraction * radius);
    copySortedPositions<D>(x, nTotal);
  });
}

NeighbourSearch::Grid NeighbourSearch::grid() const {
  Grid g;
  for (int a = 0; a < 3; ++a) {
    g.dims[a] = dims_[a];
    g.origin[a] = origin_[a];
  }
  g.invCell = invCell_;
  g.margin = margin_;
  g.cells = gridCount_ > 0 ? nCells_ : 0;
  g.count = gridCount_;
  g.cellStart = cellStart_.data();
  g.sorted = sorted_.data();
  g.cellOf = cellOf_.data();
  g.xs = xs_.data();
  return g;
}

void NeighbourSearch::cellOrder(const double* x, int dim, Index n, double cellSize,
                                std::vector<Index>& newToOld) {
  if (!(cellSize > 0.0) || !std::isfinite(cellSize))
    throw std::logic_error("neighbour search: cell size must be positive and finite, got " +
                           std::to_string(cellSize));
  gridCount_ = 0;  // the cells of the reorder, not of a search: no grid for a walk
  dispatchDimension(dim, [&](auto d) { sortIntoCells<decltype(d)::value>(x, n, cellSize); });
  newToOld.assign(sorted_.begin(), sorted_.end());
}

// ---- Verlet list ------------------------------------------------------------------------------

double VerletNeighbours::maxDisplacement(const double* x, int dim, Index nReal) const {
  if (nReal_ < 0 || nReal != nReal_ || dim != dim_) return std::numeric_limits<double>::infinity();
  const double* x0 = x0_.data();
  double d2max = 0.0;
  // Squared displacement per particle; a NaN position gives NaN, which max ignores: caught by
  // the comparison below (a NaN makes `valid` false through the finiteness of the sum).
  int bad = 0;
#pragma omp parallel for schedule(static) reduction(max : d2max, bad)
  for (Index i = 0; i < nReal; ++i) {
    double d2 = 0.0;
    for (int a = 0; a < dim; ++a) {
      const double d = x[i * dim + a] - x0[i * dim + a];
      d2 += d * d;
    }
    if (!(d2 <= 1e300)) bad = 1;
    d2max = std::max(d2max, d2);
  }
  return bad ? std::numeric_limits<double>::infinity() : std::sqrt(d2max);
}

bool VerletNeighbours::valid(const double* x, int dim, Index nReal, Index nTotal, double radius,
                             double skin) const {
  if (nReal_ < 0 || nReal != nReal_ || nTotal != nTotal_ || dim != dim_ || radius != radius_ ||
      skin != skin_)
    return false;
  // Strictly below skin/2, with a relative guard of 1e-9 for the round-off of the differences.
  return maxDisplacement(x, dim, nReal) < 0.5 * skin * (1.0 - 1e-9);
}

void VerletNeighbours::rebuild(NeighbourSearch& search, const double* x, int dim, Index nReal,
                               Index nTotal, double radius, double skin, bool half,
                               const PairFilter& keep) {
  if (!(skin >= 0.0) || !std::isfinite(skin))
    throw std::logic_error("Verlet list: skin must be >= 0 and finite, got " + std::to_string(skin));
  search.build(x, dim, nReal, nTotal, radius + skin, cand_, half, keep);
  mask_ = keep.kept();
  x0_.assign(x, x + static_cast<size_t>(nReal) * static_cast<size_t>(dim));
  nReal_ = nReal;
  nTotal_ = nTotal;
  dim_ = dim;
  radius_ = radius;
  skin_ = skin;
  ++rebuilds_;
}

template <int D>
void VerletNeighbours::filterDim(const double* x, double radius, NeighbourList& out) {
  const Index n = cand_.realCount();
  const double r2max = radius * radius;
  const std::size_t total = cand_.index.size();
  out.half = cand_.half;
  // The exact list is a subset of the candidates: room for all of them (reserved once).
  if (out.index.capacity() < total) out.index.reserve(total + total / 16);
  out.index.resize(total);
  out.offset.resize(static_cast<size_t>(n) + 1);
  const std::int64_t* co = cand_.offset.data();
  const std::uint32_t* ci = cand_.index.data();
  std::uint32_t* oi = out.index.data();
  std::int64_t* oo = out.offset.data();
  const int maxThreads = omp_get_max_threads();
  threadBegin_.assign(static_cast<size_t>(maxThreads) + 1, 0);
  threadUsed_.assign(static_cast<size_t>(maxThreads), 0);
#pragma omp parallel num_threads(maxThreads)
  {
    const int t = omp_get_thread_num();
    const int nt = omp_get_num_threads();
    const Index i0 = n * t / nt, i1 = n * (t + 1) / nt;
    // Each thread filters its particles into the candidates' own range of the output (the
    // filtered rows never outgrow it), then the ranges are closed up.
    std::int64_t w = co[i0];
    for (Index i = i0; i < i1; ++i) {
      oo[i] = w;
      double xi[D];
      for (int a = 0; a < D; ++a) xi[a] = x[i * D + a];
      for (std::int64_t k = co[i]; k < co[i + 1]; ++k) {
        const std::uint32_t j = ci[k];
        double r2 = 0.0;
        for (int a = 0; a < D; ++a) {
          const double d = xi[a] - x[static_cast<Index>(j) * D + a];
          r2 += d * d;
        }
        oi[w] = j;  // branch-free append
        w += static_cast<std::int64_t>(r2 < r2max);
      }
    }
    threadUsed_[static_cast<size_t>(t)] = w - co[i0];
#pragma omp barrier
#pragma omp single
    {
      for (int k = 0; k < nt; ++k)
        threadBegin_[static_cast<size_t>(k) + 1] =
            threadBegin_[static_cast<size_t>(k)] + threadUsed_[static_cast<size_t>(k)];
      // Range k moves left (or stays): in increasing k no move overwrites data not yet moved.
      for (int k = 1; k < nt; ++k) {
        const Index b = n * k / nt;
        std::memmove(oi + threadBegin_[static_cast<size_t>(k)], oi + co[b],
                     sizeof(std::uint32_t) * static_cast<size_t>(threadUsed_[static_cast<size_t>(k)]));
      }
    }
    const std::int64_t shift = co[i0] - threadBegin_[static_cast<size_t>(t)];
    for (Index i = i0; i < i1; ++i) oo[i] -= shift;
#pragma omp single
    out.offset[static_cast<size_t>(n)] = threadBegin_[static_cast<size_t>(nt)];
  }
  out.index.resize(static_cast<size_t>(out.offset[static_cast<size_t>(n)]));
}

void VerletNeighbours::filter(const double* x, int dim, double radius, NeighbourList& out) {
  if (dim != dim_ || cand_.offset.empty())
    throw std::logic_error("Verlet list: filter called before a rebuild");
  dispatchDimension(dim, [&](auto d) { filterDim<decltype(d)::value>(x, radius, out); });
}

std::size_t NeighbourSearch::bytes() const {
  std::size_t b = (cellOf_.capacity() + cellStart_.capacity() + sorted_.capacity()) *
                      sizeof(CellIndex) +
                  xs_.capacity() * sizeof(double) +
                  (chunkBegin_.capacity() + regionBegin_.capacity() + regionUsed_.capacity() +
                   prevChunk_.capacity()) * sizeof(std::int64_t);
  for (const auto& v : threadIndex_) b += v.capacity() * sizeof(std::uint32_t);
  for (const auto& v : threadCount_) b += v.capacity() * sizeof(std::int64_t);
  return b;
}

}  // namespace poresph
