#pragma once
// Cell walk: the pairs of a half neighbour list found on the fly in the cells of the neighbour
// search, without a stored list (scene key `neighbour_list: cells`, docs/performance.md
// "Cell walk without a stored list").
//
// NeighbourSearch::sortCells sorts the particles (ghosts included) into the cells of a search
// of the same radius and keeps their positions in cell order. CellWalk<D>::row(i, f) then calls
// f(j) for every j of row i of the half list that NeighbourSearch::build(..., half = true) would
// store, in the same order: the same rows of cells, pruned against the sphere the same way, the
// same candidates in slot order, kept when |x_i - x_j| < radius (strictly), j != i and j > i
// (every ghost: j >= nReal > i). A symmetric loop fed by row() instead of the stored list
// therefore evaluates the same pairs in the same order, and at one thread gives the same bits
// (tests/unit/test_cell_walk.cpp). The traversal (CellWalk::candidates) is the one
// NeighbourSearch::build appends through: written once.
//
// cellWalkBlocks() gives PairScatter (libcore/pair_scatter.hpp) its blocks without a list:
// rows split by a per-row weight (the particles in the cell's neighbourhood, ~ its candidates)
// and, per block, a bound on the largest real particle its rows can reach (the largest real
// index in the cells within the radius of the rows' cells), so the spill buffers cover every
// particle a pair of the block adds to.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "libcore/neighbour_search.hpp"
#include "libcore/types.hpp"

namespace poresph {

template <int D>
class CellWalk {
 public:
  /// The walk of `grid` (NeighbourSearch::grid() after sortCells or build) for `radius` (the
  /// radius of that search) over positions x (dim D per particle, the positions sorted).
  CellWalk(const NeighbourSearch::Grid& grid, const double* x, double radius)
      : g_(grid), x_(x), radius_(radius), r2max_(radius * radius), cell_(1.0 / grid.invCell) {}

  static constexpr int kMaxSpan = 64;  // rows of cells along y / z (spans are <= 5 in practice)
  /// The block of cells around particle i: rows along z and y and their squared gaps to x_i.
  struct Span {
    int zlo = 0, zhi = 0, ylo = 0, yhi = 0;
    double gy2[kMaxSpan], gz2[kMaxSpan];
  };
  Span span(Index i) const {
    Span sp;
    const double* xi = x_ + i * D;
    if (D > 2) {
      sp.zlo = cellIndex(xi[D - 1] - radius_, D - 1), sp.zhi = cellIndex(xi[D - 1] + radius_, D - 1);
      sp.zhi = std::min(sp.zhi, sp.zlo + kMaxSpan - 1);
      for (int cz = sp.zlo; cz <= sp.zhi; ++cz) {
        const double gz = gap(xi[D - 1], cz, D - 1);
        sp.gz2[cz - sp.zlo] = gz * gz;
      }
    } else {
      sp.gz2[0] = 0.0;
    }
    if (D > 1) {
      sp.ylo = cellIndex(xi[1 % D] - radius_, 1 % D), sp.yhi = cellIndex(xi[1 % D] + radius_, 1 % D);
      sp.yhi = std::min(sp.yhi, sp.ylo + kMaxSpan - 1);
      for (int cy = sp.ylo; cy <= sp.yhi; ++cy) {
        const double gy = gap(xi[1 % D], cy, 1 % D);
        sp.gy2[cy - sp.ylo] = gy * gy;
      }
    } else {
      sp.gy2[0] = 0.0;
    }
    return sp;
  }
  /// Particles in the whole block of cells of `sp`: room for every candidate of its row.
  Index candidateBound(const Span& sp) const {
    const int dimsX = g_.dims[0], dimsY = g_.dims[1];
    const Index first = static_cast<Index>(g_.cellStart[(static_cast<Index>(sp.zlo) * dimsY + sp.ylo) * dimsX]);
    const Index last = static_cast<Index>(g_.cellStart[(static_cast<Index>(sp.zhi) * dimsY + sp.yhi) * dimsX + dimsX]);
    return last - first;
  }
  /// visit(j, r2) for every candidate j of particle i in slot order: the rows of cells of `sp`
  /// within the radius, each cut along x to the cells within sqrt(r^2 - gap^2) of x_i (the
  /// traversal of NeighbourSearch::build, which appends through it, and of row()).
  /// kSkipLower (a half list, where a candidate j <= i is never kept): the cells at the start of
  /// a row's range whose particles all have an index <= i are passed over (the counting sort is
  /// stable, so the last slot of a cell holds its largest index). Only candidates a half list
  /// rejects are left out, the others in the same order (tests/unit/test_cell_walk.cpp); with the
  /// store in cell order (Simulation::reorderEvery) the rows below particle i are mostly such
  /// cells (the 2D box at rest: -19 % of the search's instructions).
  template <bool kSkipLower = false, class V>
  void candidates(Index i, const Span& sp, V&& visit) const {
    const double* xi = x_ + i * D;
    const double* xs = g_.xs;
    const NeighbourSearch::CellIndex* sorted = g_.sorted;
    const NeighbourSearch::CellIndex* cellStart = g_.cellStart;
    const double r2max = r2max_;
    const int dimsX = g_.dims[0], dimsY = g_.dims[1];
    const double ox = g_.origin[0], invCell = g_.invCell, margin = g_.margin;
    const double xi0 = xi[0];
    for (int cz = sp.zlo; cz <= sp.zhi; ++cz) {
      const double gzz = sp.gz2[cz - sp.zlo];
      if (gzz >= r2max) continue;
      for (int cy = sp.ylo; cy <= sp.yhi; ++cy) {
        const double g2 = gzz + sp.gy2[cy - sp.ylo];
        if (g2 >= r2max) continue;
        const double ext = std::sqrt(r2max - g2) * (1.0 + 1e-12) + margin;
        const double flo = (xi0 - ext - ox) * invCell, fhi = (xi0 + ext - ox) * invCell;
        const int xlo = flo <= 0.0 ? 0 : static_cast<int>(flo);
        const int xhi = fhi >= dimsX - 1 ? dimsX - 1 : static_cast<int>(fhi);
        // Cells xlo..xhi of a row are contiguous in the sorted order: one range per row.
        const Index rowBase = (static_cast<Index>(cz) * dimsY + cy) * dimsX;
        Index c = rowBase + xlo;
        const Index je = static_cast<Index>(cellStart[rowBase + xhi + 1]);
        if constexpr (kSkipLower) {
          const Index cEnd = rowBase + xhi + 1;
          while (c < cEnd) {
            const Index e = static_cast<Index>(cellStart[c + 1]);
            if (e > static_cast<Index>(cellStart[c]) && static_cast<Index>(sorted[e - 1]) > i) break;
            ++c;
          }
        }
        const Index jb = static_cast<Index>(cellStart[c]);
        for (Index s = jb; s < je; ++s) {
          double r2 = 0.0;
          for (int a = 0; a < D; ++a) {
            const double dx = xi[a] - xs[s * D + a];
            r2 += dx * dx;
          }
          visit(static_cast<Index>(sorted[s]), r2);
        }
      }
    }
  }

  /// Calls f(j) for every j of row i of the half list, in the half list's order (kHalf), or of
  /// the full list (every j != i within the radius: kHalf = false).
  template <bool kHalf = true, class F>
  void row(Index i, F&& f) const {
    const double r2max = r2max_;
    candidates(i, span(i), [&](Index j, double r2) {
      if (r2 < r2max && (kHalf ? j > i : j != i)) f(j);
    });
  }

 private:
  int cellIndex(double v, int a) const {
    const double fr = (v - g_.origin[a]) * g_.invCell;
    if (!(fr >= 0.0)) return 0;  // also catches -inf
    if (fr >= static_cast<double>(g_.dims[a] - 1)) return g_.dims[a] - 1;
    return static_cast<int>(fr);
  }
  // Distance from v to cell c along axis a (zero inside), lowered by the round-off guard.
  double gap(double v, int c, int a) const {
    const double lo = g_.origin[a] + c * cell_, hi = lo + cell_;
    const double gg = v < lo ? lo - v : (v > hi ? v - hi : 0.0);
    return std::max(0.0, gg - g_.margin);
  }
  NeighbourSearch::Grid g_;
  const double* x_;
  double radius_, r2max_, cell_;
};

/// Per-cell scratch of cellWalkBlocks (kept between calls; bytes() for the memory report).
struct CellWalkScratch {
  std::vector<std::int64_t> weight;  // particles in the cells within the radius of each cell
  std::vector<Index> reach;          // largest real particle in those cells (-1: none)
  std::vector<std::int64_t> lineW;
  std::vector<Index> lineR;
  std::size_t bytes() const {
    return (weight.capacity() + lineW.capacity()) * sizeof(std::int64_t) +
           (reach.capacity() + lineR.capacity()) * sizeof(Index);
  }
};

/// Blocks of the rows [0, nReal) for `threads` threads and the spill end of each (one past the
/// largest real particle a pair of the block's rows can reach, at least the block's end), from
/// the cell grid of a search of `radius`: blockBegin gets threads + 1 entries, spillEnd threads.
/// One thread: one block, no spill (nothing per cell is computed).
inline void cellWalkBlocks(const NeighbourSearch::Grid& g, int dim, double radius, Index nReal,
                           int threads, std::vector<Index>& blockBegin,
                           std::vector<Index>& spillEnd, CellWalkScratch& s) {
  threads = std::max(1, threads);
  blockBegin.assign(static_cast<size_t>(threads) + 1, nReal);
  blockBegin[0] = 0;
  spillEnd.assign(static_cast<size_t>(threads), nReal);
  if (threads == 1 || nReal == 0) return;
  const Index nc = g.cells;
  s.weight.assign(static_cast<size_t>(nc), 0);
  s.reach.assign(static_cast<size_t>(nc), -1);
  for (Index c = 0; c < nc; ++c) {
    const Index b = static_cast<Index>(g.cellStart[c]), e = static_cast<Index>(g.cellStart[c + 1]);
    s.weight[static_cast<size_t>(c)] = e - b;
    Index m = -1;
    for (Index q = b; q < e; ++q)
      if (static_cast<Index>(g.sorted[q]) < nReal) m = std::max(m, static_cast<Index>(g.sorted[q]));
    s.reach[static_cast<size_t>(c)] = m;
  }
  // A particle of cell k reaches the cells k - K .. k + K along each axis (K cells cover the
  // radius from anywhere in its cell): sum and max over that box, one axis at a time.
  const int K = std::max(1, static_cast<int>(std::ceil(radius * g.invCell * (1.0 + 1e-12))));
  Index stride = 1;
  for (int a = 0; a < dim; ++a) {
    const Index len = g.dims[a];
    s.lineW.resize(static_cast<size_t>(len));
    s.lineR.resize(static_cast<size_t>(len));
    for (Index c0 = 0; c0 < nc; ++c0) {
      if ((c0 / stride) % len != 0) continue;  // the first cell of each line along axis a
      for (Index k = 0; k < len; ++k) {
        s.lineW[static_cast<size_t>(k)] = s.weight[static_cast<size_t>(c0 + k * stride)];
        s.lineR[static_cast<size_t>(k)] = s.reach[static_cast<size_t>(c0 + k * stride)];
      }
      for (Index k = 0; k < len; ++k) {
        std::int64_t w = 0;
        Index r = -1;
        for (Index q = std::max<Index>(0, k - K); q <= std::min<Index>(len - 1, k + K); ++q) {
          w += s.lineW[static_cast<size_t>(q)];
          r = std::max(r, s.lineR[static_cast<size_t>(q)]);
        }
        s.weight[static_cast<size_t>(c0 + k * stride)] = w;
        s.reach[static_cast<size_t>(c0 + k * stride)] = r;
      }
    }
    stride *= len;
  }
  // Blocks balanced by the rows' weights (half of a row's candidates are above it on average).
  std::int64_t total = 0;
  for (Index i = 0; i < nReal; ++i) total += s.weight[static_cast<size_t>(g.cellOf[i])];
  std::int64_t acc = 0;
  int t = 1;
  for (Index i = 0; i < nReal && t < threads; ++i) {
    acc += s.weight[static_cast<size_t>(g.cellOf[i])];
    while (t < threads && acc >= total * t / threads) blockBegin[static_cast<size_t>(t++)] = i + 1;
  }
  for (int u = 0; u < threads; ++u) {
    const Index b0 = blockBegin[static_cast<size_t>(u)], b1 = blockBegin[static_cast<size_t>(u) + 1];
    Index hi = b1;
    for (Index i = b0; i < b1; ++i) hi = std::max(hi, s.reach[static_cast<size_t>(g.cellOf[i])] + 1);
    spillEnd[static_cast<size_t>(u)] = std::min(hi, nReal);
  }
}

}  // namespace poresph
