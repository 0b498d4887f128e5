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
//
// Half lists (`half` = true, scene key `neighbour_list: half`, docs/performance.md): each pair
// of real particles is stored once, in the row of the smaller index (j > i), for loops that
// evaluate a pair once and update both particles (symmetric evaluation, libcore/pair_scatter.hpp);
// a pair of a real particle and a ghost stays in the real particle's row as in the full list
// (ghosts have no row; the mirrored pair sits in the row of the ghost's source).
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "libcore/phases.hpp"
#include "libcore/types.hpp"

namespace poresph {

/// std::allocator whose resize leaves the added elements uninitialised (default-initialised)
/// instead of zeroing them: the list arrays are always written before they are read, and the
/// Verlet filter grows the exact list back to the candidates' size every step (issue 17: that
/// zero-fill was the largest serial part of the step, docs/performance.md).
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() noexcept = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

struct NeighbourList {
  using IndexVector = std::vector<std::uint32_t, DefaultInitAllocator<std::uint32_t>>;
  std::vector<std::int64_t> offset;   ///< size nReal + 1
  IndexVector index;                  ///< neighbours of i: index[offset[i] .. offset[i+1])
  bool half = false;  ///< only j > i in row i (real-real pairs once; see above)
  Index realCount() const { return offset.empty() ? 0 : static_cast<Index>(offset.size()) - 1; }
  std::int64_t pairCount() const { return offset.empty() ? 0 : offset.back(); }
  std::size_t bytes() const {
    return offset.capacity() * sizeof(std::int64_t) + index.capacity() * sizeof(std::uint32_t);
  }
};

/// Which pairs a search keeps, by the phases of the two particles (Simulation::neighbourPairMask):
/// with `phase` set, the pair of row i and neighbour j is kept when bit phase[i] * kPhaseCount +
/// phase[j] of `mask` is set (a class sets both of its bits, so the list stays symmetric); a row
/// whose phase keeps no class is left empty without being searched. When a particle of
/// [0, nTotal) has a phase outside [0, kPhaseCount) every pair is kept. The rows that remain
/// hold their pairs in the order of the unfiltered list.
struct PairFilter {
  const std::int32_t* phase = nullptr;  ///< of particles [0, nTotal) (a ghost: its source's)
  PairMask mask = kAllPairClasses;
  bool active() const { return phase != nullptr && (mask & kAllPairClasses) != kAllPairClasses; }
  /// The classes a list built with this filter holds (kAllPairClasses when inactive).
  PairMask kept() const { return active() ? (mask & kAllPairClasses) : kAllPairClasses; }
};

class NeighbourSearch {
 public:
  /// Cells, slots and particles of the cell arrays: 32 bits (a store holds < 2^32 particles and
  /// the cells are capped at ~2 per particle, checked), half the memory of Index; the values
  /// are the same, so lists and walks are unchanged (docs/performance.md "Memory levers").
  using CellIndex = std::uint32_t;
  /// Neighbours within `radius` (strictly closer) of each real particle.
  /// x: positions, dim components per particle. `half`: keep only j > i (a half list).
  /// `keep`: only the pairs of these phase classes (PairFilter; default every pair).
  void build(const double* x, int dim, Index nReal, Index nTotal, double radius,
             NeighbourList& out, bool half = false, const PairFilter& keep = PairFilter());
  /// Permutation that sorts particles [0, n) by cell (cell size `cellSize`), x fastest: feed it
  /// to ParticleStore::permute for cache locality.
  void cellOrder(const double* x, int dim, Index n, double cellSize, std::vector<Index>& newToOld);

  /// Sorts particles [0, nTotal) into the cells of a search of `radius` and keeps their
  /// positions in cell order, as build() does, without building a list: the grid that a cell
  /// walk reads (libcore/cell_walk.hpp, scene key `neighbour_list: cells`).
  void sortCells(const double* x, int dim, Index nTotal, double radius);
  /// The cell grid of the last build() or sortCells() (views into the search's arrays, valid
  /// until its next build, sortCells or cellOrder).
  struct Grid {
    int dims[3] = {1, 1, 1};
    double origin[3] = {0, 0, 0};
    double invCell = 1.0, margin = 0.0;
    Index cells = 0, count = 0;            ///< cells, particles sorted
    const CellIndex* cellStart = nullptr;  ///< cell c holds the slots cellStart[c] .. cellStart[c+1]
    const CellIndex* sorted = nullptr;     ///< particle of each slot (cell order)
    const CellIndex* cellOf = nullptr;     ///< cell of each particle
    const double* xs = nullptr;            ///< positions by slot (dim per slot)
  };
  Grid grid() const;

  /// Number of cells of the last build (for diagnostics and tests).
  Index cellCount() const { return nCells_; }
  /// Cell edge of the last build (radius / 2 unless enlarged to cap the cell count).
  double cellSize() const { return 1.0 / invCell_; }
  /// Bytes held by the search itself (cells, sorted copy of positions, per-thread buffers).
  std::size_t bytes() const;

 private:
  template <int D>
  void buildDim(const double* x, Index nReal, Index nTotal, double radius, NeighbourList& out,
                bool half, const PairFilter& keep);
  template <int D>
  void sortIntoCells(const double* x, Index n, double cellSize);
  template <int D>
  void copySortedPositions(const double* x, Index n);
  Index gridCount_ = 0;  // particles sorted by the last build or sortCells (0 after cellOrder)

  Index nCells_ = 0;
  int dims_[3] = {1, 1, 1};
  double origin_[3] = {0, 0, 0};
  double invCell_ = 1.0;
  std::vector<CellIndex> cellOf_;
  std::vector<CellIndex> cellStart_;  // nCells_ + 1 (also the counting sort's cursor)
  std::vector<CellIndex> sorted_;
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

/// Verlet (skin) list: the candidates within radius + skin of each real particle, built by a
/// NeighbourSearch, and the exact list (pairs closer than the radius, in candidate order)
/// filtered from them every step. The candidates hold every pair closer than the radius as long
/// as no particle has moved by skin/2 or more since they were built: two particles that were at
/// least radius + skin apart can then have approached by less than skin, i.e. they are still at
/// least the radius apart. `valid` checks exactly that (and the particle counts), so the filtered
/// list always equals a fresh search's list as a set of pairs (tests/unit/test_neighbour_verlet).
/// Only for stores without ghosts (a periodic halo is rebuilt every step, its ghost indices
/// change): Simulation::updateNeighbours uses it when no axis is periodic.
class VerletNeighbours {
 public:
  /// True when the candidates of the last rebuild (same radius and skin, same particle counts)
  /// still hold every pair closer than `radius`: the largest displacement since the rebuild is
  /// below skin/2.
  bool valid(const double* x, int dim, Index nReal, Index nTotal, double radius,
             double skin) const;
  /// Rebuilds the candidates with `search` (radius + skin) and remembers the positions; `half`:
  /// half candidates (j > i), whose filtered list is then a half list too; `keep`: candidates of
  /// these phase classes only (PairFilter), and so the filtered lists too.
  void rebuild(NeighbourSearch& search, const double* x, int dim, Index nReal, Index nTotal,
               double radius, double skin, bool half = false,
               const PairFilter& keep = PairFilter());
  /// The phase classes the candidates hold (PairFilter::kept of the last rebuild).
  PairMask pairMask() const { return mask_; }
  /// The exact list: the candidates closer than `radius` (strictly), in candidate order (a
  /// half list when the candidates are).
  void filter(const double* x, int dim, double radius, NeighbourList& out);
  /// Largest displacement of a real particle since the last rebuild (infinite before the first).
  double maxDisplacement(const double* x, int dim, Index nReal) const;
  /// Forget the candidates (the next `valid` is false).
  void invalidate() { nReal_ = -1; }
  const NeighbourList& candidates() const { return cand_; }
  std::int64_t rebuildCount() const { return rebuilds_; }
  std::size_t bytes() const {
    return cand_.bytes() + x0_.capacity() * sizeof(double) +
           (threadBegin_.capacity() + threadUsed_.capacity()) * sizeof(std::int64_t);
  }

 private:
  template <int D>
  void filterDim(const double* x, double radius, NeighbourList& out);
  NeighbourList cand_;
  std::vector<double> x0_;  // positions of the real particles at the rebuild
  Index nReal_ = -1, nTotal_ = -1;
  int dim_ = 0;
  double radius_ = 0.0, skin_ = 0.0;
  PairMask mask_ = kAllPairClasses;
  std::int64_t rebuilds_ = 0;
  std::vector<std::int64_t> threadBegin_, threadUsed_;
};

}  // namespace poresph
