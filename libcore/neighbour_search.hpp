#pragma once
// Cell-linked-list neighbour search. Cells are half the radius (enlarged when the cell count
// would exceed ~2 per particle); for each particle the rows of cells within the radius are
// pruned against the sphere, so that few candidates beyond the radius are tested.
//
// Lists are built for the real particles [0, nReal) over all particles [0, nTotal), ghosts
// included, so periodicity comes from the halo (PeriodicHalo) and not from the search itself:
// the same search will serve MPI halos. Lists are stored in compressed rows (offset, index),
// self excluded, and are ordered the same whatever the thread count. Memory is kept between
// builds, so that a time loop does not allocate once the lists reached their working size.
#include <cstdint>
#include <vector>

#include "libcore/types.hpp"

namespace poresph {

struct NeighbourList {
  std::vector<std::int64_t> offset;   ///< size nReal + 1
  std::vector<std::uint32_t> index;   ///< neighbours of i: index[offset[i] .. offset[i+1])
  Index realCount() const { return offset.empty() ? 0 : static_cast<Index>(offset.size()) - 1; }
  std::int64_t pairCount() const { return offset.empty() ? 0 : offset.back(); }
  std::size_t bytes() const {
    return offset.capacity() * sizeof(std::int64_t) + index.capacity() * sizeof(std::uint32_t);
  }
};

class NeighbourSearch {
 public:
  /// Neighbours within `radius` (strictly closer) of each real particle.
  /// x: positions, dim components per particle.
  void build(const double* x, int dim, Index nReal, Index nTotal, double radius,
             NeighbourList& out);
  /// Permutation that sorts particles [0, n) by cell (cell size `cellSize`), x fastest: feed it
  /// to ParticleStore::permute for cache locality.
  void cellOrder(const double* x, int dim, Index n, double cellSize, std::vector<Index>& newToOld);

  /// Number of cells of the last build (for diagnostics and tests).
  Index cellCount() const { return nCells_; }
  /// Cell edge of the last build (radius / 2 unless enlarged to cap the cell count).
  double cellSize() const { return 1.0 / invCell_; }
  /// Bytes held by the search itself (cells, sorted copy of positions, per-thread buffers).
  std::size_t bytes() const;

 private:
  template <int D>
  void buildDim(const double* x, Index nReal, Index nTotal, double radius, NeighbourList& out);
  template <int D>
  void sortIntoCells(const double* x, Index n, double cellSize);

  Index nCells_ = 0;
  int dims_[3] = {1, 1, 1};
  double origin_[3] = {0, 0, 0};
  double invCell_ = 1.0;
  std::vector<Index> cellOf_;
  std::vector<Index> cellStart_;
  std::vector<Index> sorted_;
  std::vector<Index> cursor_;
  std::vector<double> xs_;  // positions in cell order (contiguous candidates)
  double margin_ = 0.0;     // round-off guard of the row pruning (absolute, metres)
  std::vector<std::int64_t> chunkBegin_;
  // In-place CSR fill: each thread writes into its own region of the output, sized from its
  // chunk length in the previous build (+1/8); a thread that overflows continues in its
  // threadIndex_ buffer, which is released after the build (only a growing list allocates).
  std::vector<std::int64_t> regionBegin_;
  std::vector<std::int64_t> regionUsed_;
  std::vector<std::int64_t> prevChunk_;
  int prevThreads_ = 0;
  std::vector<std::vector<std::uint32_t>> threadIndex_;
  std::vector<std::vector<std::int64_t>> threadCount_;
};

}  // namespace poresph
