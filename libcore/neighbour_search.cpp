#include "libcore/neighbour_search.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace poresph {

template <int D>
void NeighbourSearch::sortIntoCells(const double* x, Index n, double cellSize) {
  // Bounding box of all particles (ghosts included).
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (int a = 0; a < D; ++a) {
    double mn = std::numeric_limits<double>::max(), mx = -std::numeric_limits<double>::max();
#pragma omp parallel for reduction(min : mn) reduction(max : mx) schedule(static)
    for (Index i = 0; i < n; ++i) {
      mn = std::min(mn, x[i * D + a]);
      mx = std::max(mx, x[i * D + a]);
    }
    if (n == 0) mn = mx = 0.0;
    if (!std::isfinite(mn) || !std::isfinite(mx))
      throw NumericalError("neighbour search: a particle position is not finite");
    lo[a] = mn;
    hi[a] = mx;
  }
  // Cell size = support radius, enlarged when the cell count would exceed ~2 cells per particle
  // (tiny h in a large box): larger cells only add candidates, never lose a pair.
  double cell = cellSize;
  for (int iter = 0; iter < 64; ++iter) {
    double cells = 1.0;
    for (int a = 0; a < D; ++a) cells *= std::floor((hi[a] - lo[a]) / cell) + 1.0;
    if (cells <= 2.0 * static_cast<double>(n) + 64.0) break;
    cell *= 1.25;
  }
  invCell_ = 1.0 / cell;
  nCells_ = 1;
  for (int a = 0; a < 3; ++a) dims_[a] = 1;
  for (int a = 0; a < D; ++a) {
    origin_[a] = lo[a];
    dims_[a] = static_cast<int>(std::floor((hi[a] - lo[a]) * invCell_)) + 1;
    nCells_ *= dims_[a];
  }
  cellOf_.resize(static_cast<size_t>(n));
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) {
    Index c = 0;
    for (int a = D - 1; a >= 0; --a) {
      int k = static_cast<int>((x[i * D + a] - origin_[a]) * invCell_);
      k = std::min(std::max(k, 0), dims_[a] - 1);
      c = c * dims_[a] + k;
    }
    cellOf_[static_cast<size_t>(i)] = c;
  }
  // Counting sort (stable: particles keep their order within a cell).
  cellStart_.assign(static_cast<size_t>(nCells_) + 1, 0);
  for (Index i = 0; i < n; ++i) ++cellStart_[static_cast<size_t>(cellOf_[static_cast<size_t>(i)]) + 1];
  for (Index c = 0; c < nCells_; ++c) cellStart_[static_cast<size_t>(c) + 1] += cellStart_[static_cast<size_t>(c)];
  sorted_.resize(static_cast<size_t>(n));
  cursor_.assign(cellStart_.begin(), cellStart_.end() - 1);
  for (Index i = 0; i < n; ++i) {
    const Index c = cellOf_[static_cast<size_t>(i)];
    sorted_[static_cast<size_t>(cursor_[static_cast<size_t>(c)]++)] = i;
  }
}

template <int D>
void NeighbourSearch::buildDim(const double* x, Index nReal, Index nTotal, double radius,
                               NeighbourList& out) {
  sortIntoCells<D>(x, nTotal, radius);
  const double r2max = radius * radius;
  const int nThreads = omp_get_max_threads();
  if (static_cast<int>(threadIndex_.size()) < nThreads) {
    threadIndex_.resize(static_cast<size_t>(nThreads));
    threadCount_.resize(static_cast<size_t>(nThreads));
  }
  out.offset.resize(static_cast<size_t>(nReal) + 1);
  std::vector<std::int64_t>& chunkBegin = chunkBegin_;
  chunkBegin.assign(static_cast<size_t>(nThreads) + 1, 0);
  // Visiting order of the neighbour cells: enough layers to cover `radius` (one layer unless
  // cells were enlarged beyond the radius, which only makes one layer more than enough).
  const int layer = 1;
#pragma omp parallel num_threads(nThreads)
  {
    const int t = omp_get_thread_num();
    const int nt = omp_get_num_threads();
    const Index i0 = nReal * t / nt, i1 = nReal * (t + 1) / nt;
    auto& idx = threadIndex_[static_cast<size_t>(t)];
    auto& cnt = threadCount_[static_cast<size_t>(t)];
    idx.clear();
    cnt.clear();
    for (Index i = i0; i < i1; ++i) {
      const double* xi = x + i * D;
      int ci[3] = {0, 0, 0};
      for (int a = 0; a < D; ++a) {
        int k = static_cast<int>((xi[a] - origin_[a]) * invCell_);
        ci[a] = std::min(std::max(k, 0), dims_[a] - 1);
      }
      const std::size_t before = idx.size();
      const int zlo = D > 2 ? std::max(ci[2] - layer, 0) : 0, zhi = D > 2 ? std::min(ci[2] + layer, dims_[2] - 1) : 0;
      const int ylo = D > 1 ? std::max(ci[1] - layer, 0) : 0, yhi = D > 1 ? std::min(ci[1] + layer, dims_[1] - 1) : 0;
      const int xlo = std::max(ci[0] - layer, 0), xhi = std::min(ci[0] + layer, dims_[0] - 1);
      for (int cz = zlo; cz <= zhi; ++cz)
        for (int cy = ylo; cy <= yhi; ++cy) {
          // Cells xlo..xhi are contiguous in the sorted array: one range per row.
          const Index rowBase = (static_cast<Index>(cz) * dims_[1] + cy) * dims_[0];
          const Index jb = cellStart_[static_cast<size_t>(rowBase + xlo)];
          const Index je = cellStart_[static_cast<size_t>(rowBase + xhi) + 1];
          for (Index s = jb; s < je; ++s) {
            const Index j = sorted_[static_cast<size_t>(s)];
            if (j == i) continue;
            double r2 = 0.0;
            for (int a = 0; a < D; ++a) {
              const double dx = xi[a] - x[j * D + a];
              r2 += dx * dx;
            }
            if (r2 < r2max) idx.push_back(static_cast<std::uint32_t>(j));
          }
        }
      cnt.push_back(static_cast<std::int64_t>(idx.size() - before));
    }
    chunkBegin[static_cast<size_t>(t) + 1] = static_cast<std::int64_t>(idx.size());
#pragma omp barrier
#pragma omp single
    {
      for (int k = 0; k < nt; ++k) chunkBegin[static_cast<size_t>(k) + 1] += chunkBegin[static_cast<size_t>(k)];
      out.index.resize(static_cast<size_t>(chunkBegin[static_cast<size_t>(nt)]));
    }
    std::int64_t o = chunkBegin[static_cast<size_t>(t)];
    for (Index i = i0; i < i1; ++i) {
      out.offset[static_cast<size_t>(i)] = o;
      o += cnt[static_cast<size_t>(i - i0)];
    }
    std::copy(idx.begin(), idx.end(), out.index.begin() + chunkBegin[static_cast<size_t>(t)]);
  }
  out.offset[static_cast<size_t>(nReal)] = static_cast<std::int64_t>(out.index.size());
}

void NeighbourSearch::build(const double* x, int dim, Index nReal, Index nTotal, double radius,
                            NeighbourList& out) {
  if (!(radius > 0.0)) throw std::logic_error("neighbour search: radius must be positive");
  if (nTotal > static_cast<Index>(std::numeric_limits<std::uint32_t>::max()))
    throw std::logic_error("neighbour search: more than 2^32 particles in one store");
  dispatchDimension(dim, [&](auto d) { buildDim<decltype(d)::value>(x, nReal, nTotal, radius, out); });
}

void NeighbourSearch::cellOrder(const double* x, int dim, Index n, double cellSize,
                                std::vector<Index>& newToOld) {
  dispatchDimension(dim, [&](auto d) { sortIntoCells<decltype(d)::value>(x, n, cellSize); });
  newToOld.assign(sorted_.begin(), sorted_.end());
}

}  // namespace poresph
