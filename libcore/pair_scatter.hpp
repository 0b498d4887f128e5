#pragma once
// Race-free symmetric pair evaluation over a half neighbour list (NeighbourList::half, scene key
// `neighbour_list: half`, docs/performance.md "Half neighbour list").
//
// A half list holds each pair of real particles once, in the row of the smaller index, so a
// loop over the rows evaluates the pair once and adds its contribution to both particles: to
// the row's particle i (the thread's own) and to the neighbour j > i, which another thread's
// rows may also reach. PairScatter makes that scatter race-free without atomics or locks:
//  - the rows are split into one contiguous block per thread, balanced by list entries;
//  - a thread adds to a particle j of its own block directly (no other thread writes there:
//    the other threads' rows are either all below the block, and reach it only through their
//    spill buffers, or all above it, and never write below their own rows since j > i);
//  - a particle j beyond its block goes to the thread's spill buffer, which covers the rows
//    from the end of its block to the largest real neighbour index its rows reach;
//  - after a barrier each thread adds the spills of the threads before it into its own rows,
//    in thread order (the result depends on the thread count only through that order).
// With the store in cell order (Simulation::reorderEvery) a spill covers about a slab of the
// support's thickness along the slowest cell axis. Buffers are sized by layout() (once per
// neighbour search, for the widest loop) and grow only there when a layout needs more than they
// hold (counted by allocations()); use(), called by every loop, never allocates.
// A ghost neighbour (index >= nReal) gets nothing: its pair is also in the row of its source.
#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "libcore/neighbour_search.hpp"
#include "libcore/types.hpp"

namespace poresph {

class PairScatter {
 public:
  /// Outside a parallel region: the blocks of omp_get_max_threads() threads over the rows
  /// [0, nReal) of `nl` and the spill of each, for `width` doubles per particle.
  void prepare(const NeighbourList& nl, Index nReal, int width) {
    layout(nl, nReal, width);
    use(width);
  }
  /// The blocks and spill ranges (a scan of the list), and the spill buffers sized for up to
  /// `maxWidth` doubles per particle: the only place that allocates (counted by allocations()).
  /// The layout of a list serves every list whose rows are subsets of its rows (the Verlet
  /// exact lists filtered from candidates until the next search): lay out on the candidates
  /// once per search, then use() per loop, which never allocates.
  void layout(const NeighbourList& nl, Index nReal, int maxWidth) {
    beginLayout(nReal);
    const std::int64_t* off = nl.offset.data();
    const std::int64_t total = nReal > 0 ? off[nReal] : 0;
    block_[0] = 0;
    for (int t = 1; t < nt_; ++t) {
      const std::int64_t target = total * t / nt_;
      block_[static_cast<size_t>(t)] = nReal > 0
          ? static_cast<Index>(std::lower_bound(off, off + nReal + 1, target) - off)
          : 0;
      block_[static_cast<size_t>(t)] = std::max(block_[static_cast<size_t>(t)], block_[static_cast<size_t>(t) - 1]);
    }
    block_[static_cast<size_t>(nt_)] = nReal;
    finishLayout(nl, maxWidth);
  }
  /// layout() with the blocks balanced by a weight per row (rowWeight(i) >= 0, called in
  /// parallel, twice for some rows) instead of the row's list entries: the work the loops do in
  /// the row, e.g. its entries that are evaluated (issue 17: rows of boundary particles without a
  /// fluid neighbour hold entries and no work, which left one thread ~15 % more of the force
  /// loop on the dam breaks). The blocks only change the order in which a particle's sums from
  /// several blocks are added, not the sums.
  template <class RowWeight>
  void layoutWeighted(const NeighbourList& nl, Index nReal, int maxWidth, RowWeight&& rowWeight) {
    beginLayout(nReal);
    // Prefix of the weights over kChunksPerThread chunks of rows per thread, then each block
    // boundary found inside its chunk (no per-row array: no memory per particle).
    const int nc = kChunksPerThread * nt_;
    chunkWeight_.assign(static_cast<size_t>(nc) + 1, 0);
    std::int64_t* cw = chunkWeight_.data();
#pragma omp parallel for schedule(static) num_threads(nt_)
    for (int c = 0; c < nc; ++c) {
      const Index r0 = nReal * c / nc, r1 = nReal * (c + 1) / nc;
      std::int64_t sum = 0;
      for (Index i = r0; i < r1; ++i) sum += rowWeight(i);
      cw[c + 1] = sum;
    }
    for (int c = 0; c < nc; ++c) cw[c + 1] += cw[c];
    const std::int64_t total = cw[nc];
    block_[0] = 0;
    block_[static_cast<size_t>(nt_)] = nReal;
#pragma omp parallel for schedule(static) num_threads(nt_)
    for (int t = 1; t < nt_; ++t) {
      // The first row r with (weight of the rows before r) >= target, as layout()'s lower_bound.
      const std::int64_t target = total * t / nt_;
      const int c = static_cast<int>(std::lower_bound(cw, cw + nc + 1, target) - cw);
      Index r = 0;
      if (c > 0) {
        r = nReal * (c - 1) / nc;
        std::int64_t wsum = cw[c - 1];
        const Index rEnd = nReal * c / nc;
        while (r < rEnd && wsum < target) wsum += rowWeight(r++);
      }
      block_[static_cast<size_t>(t)] = r;
    }
    for (int t = 1; t < nt_; ++t)
      block_[static_cast<size_t>(t)] = std::max(block_[static_cast<size_t>(t)], block_[static_cast<size_t>(t) - 1]);
    finishLayout(nl, maxWidth);
  }
  /// The layout without a list (the cell walk, libcore/cell_walk.hpp cellWalkBlocks): the rows
  /// [blockBegin[t], blockBegin[t+1]) of each of blockBegin.size() - 1 blocks and the spill end
  /// of each (one past the largest real particle its rows add to); buffers as layout().
  void layoutBlocks(const std::vector<Index>& blockBegin, const std::vector<Index>& spillEnd,
                    Index nReal, int maxWidth) {
    if (blockBegin.size() < 2 || spillEnd.size() + 1 != blockBegin.size() ||
        blockBegin.front() != 0 || blockBegin.back() != nReal)
      throw std::logic_error("PairScatter::layoutBlocks: blocks do not cover the rows");
    nt_ = static_cast<int>(spillEnd.size());
    n_ = nReal;
    block_ = blockBegin;
    spillEnd_ = spillEnd;
    for (int t = 0; t < nt_; ++t)
      spillEnd_[static_cast<size_t>(t)] =
          std::max(spillEnd_[static_cast<size_t>(t)], block_[static_cast<size_t>(t) + 1]);
    if (spill_.size() < static_cast<size_t>(nt_)) spill_.resize(static_cast<size_t>(nt_));
    allocate(maxWidth);
  }
  /// One past the largest real particle block t's rows may add to (layout's spill end).
  Index spillEnd(int t) const { return spillEnd_[static_cast<size_t>(t)]; }

 private:
  static constexpr int kChunksPerThread = 64;
  void beginLayout(Index nReal) {
    nt_ = std::max(1, omp_get_max_threads());
    n_ = nReal;
    block_.resize(static_cast<size_t>(nt_) + 1);
    spillEnd_.resize(static_cast<size_t>(nt_));
    if (spill_.size() < static_cast<size_t>(nt_)) spill_.resize(static_cast<size_t>(nt_));
  }
  // The spill end of each block (a scan of its rows' entries) and the buffers.
  void finishLayout(const NeighbourList& nl, int maxWidth) {
    const std::int64_t* off = nl.offset.data();
    const std::uint32_t* idx = nl.index.data();
    const Index n = n_;
#pragma omp parallel for schedule(static, 1) num_threads(nt_)
    for (int t = 0; t < nt_; ++t) {
      const Index b1 = block_[static_cast<size_t>(t) + 1];
      Index hi = b1;
      const std::int64_t k0 = off[block_[static_cast<size_t>(t)]], k1 = off[b1];
      for (std::int64_t k = k0; k < k1; ++k) {
        const Index j = static_cast<Index>(idx[k]);
        hi = (j < n && j >= hi) ? j + 1 : hi;
      }
      spillEnd_[static_cast<size_t>(t)] = hi;
    }
    allocate(maxWidth);
  }
  void allocate(int maxWidth) {
    maxWidth_ = maxWidth;
    const std::int64_t before = allocations_;
    // Room for the widest loop, with half as much again so that the layouts of later searches
    // (the flow spreads, the spill slabs change) mostly fit without growing.
    for (int t = 0; t < nt_; ++t) {
      auto& s = spill_[static_cast<size_t>(t)];
      const std::size_t need = spillRows(t) * static_cast<std::size_t>(maxWidth_);
      if (need > s.capacity()) {
        s.clear();
        s.shrink_to_fit();
        s.reserve(need + need / 2 + 64);
        ++allocations_;
      }
    }
    ++layouts_;
    if (allocations_ > before) ++layoutsThatGrew_;
  }

 public:
  /// The buffers of the layout for a loop of `width` doubles per particle (<= the layout's
  /// maxWidth, else std::logic_error): never allocates.
  void use(int width) {
    if (width > maxWidth_)
      throw std::logic_error("PairScatter::use: width " + std::to_string(width) +
                             " above the layout's " + std::to_string(maxWidth_));
    w_ = width;
    for (int t = 0; t < nt_; ++t)
      spill_[static_cast<size_t>(t)].resize(spillRows(t) * static_cast<std::size_t>(w_));
  }
  /// Threads of the layout: run the loop with `num_threads(threads())`; a team of another size
  /// must take the blocks t = thread, thread + team, ... (forBlocks does).
  int threads() const { return nt_; }
  /// Rows of the layout (nReal of the last layout()).
  Index rows() const { return n_; }
  Index begin(int t) const { return block_[static_cast<size_t>(t)]; }
  Index end(int t) const { return block_[static_cast<size_t>(t) + 1]; }
  /// Calls f(t) for every block t handled by the calling thread of the current team.
  template <class F>
  void forBlocks(F&& f) const {
    const int team = omp_get_num_threads(), me = omp_get_thread_num();
    for (int t = me; t < nt_; t += team) f(t);
  }
  /// Zeroes the rows of block t in `own` (width doubles per particle) and the spill of t.
  void zero(int t, double* own) {
    const Index b0 = begin(t), b1 = end(t);
    if (b1 > b0)
      std::memset(own + b0 * w_, 0, sizeof(double) * static_cast<size_t>((b1 - b0) * w_));
    auto& s = spill_[static_cast<size_t>(t)];
    if (!s.empty()) std::memset(s.data(), 0, sizeof(double) * s.size());
  }
  /// Where block t's rows add to particle j (real, j >= begin(t)): `own` inside the block, the
  /// spill beyond it.
  double* at(int t, double* own, Index j) {
    const Index b1 = block_[static_cast<size_t>(t) + 1];
    return j < b1 ? own + j * w_ : spill_[static_cast<size_t>(t)].data() + (j - b1) * w_;
  }
  /// After a barrier that follows every block's loop: adds the spills of the blocks before t
  /// that reach block t's rows into `own`.
  void reduce(int t, double* own) const {
    const Index b0 = begin(t), b1 = end(t);
    for (int u = 0; u < t; ++u) {
      const Index su = block_[static_cast<size_t>(u) + 1], eu = spillEnd_[static_cast<size_t>(u)];
      const Index lo = std::max(b0, su), hi = std::min(b1, eu);
      if (hi <= lo) continue;
      const double* s = spill_[static_cast<size_t>(u)].data() + (lo - su) * w_;
      double* o = own + lo * w_;
      const std::size_t len = static_cast<std::size_t>((hi - lo) * w_);
      for (std::size_t q = 0; q < len; ++q) o[q] += s[q];
    }
  }
  /// Bytes held by the spill buffers.
  std::size_t bytes() const {
    std::size_t b = (block_.capacity() + spillEnd_.capacity()) * sizeof(Index) +
                    chunkWeight_.capacity() * sizeof(std::int64_t);
    for (const auto& s : spill_) b += s.capacity() * sizeof(double);
    return b;
  }
  /// Number of times a spill buffer grew; only layout() allocates, and a steady layout not.
  std::int64_t allocations() const { return allocations_; }
  /// Layouts made, and how many of them had to grow a buffer (a steady run: the first only).
  std::int64_t layouts() const { return layouts_; }
  std::int64_t layoutsThatGrew() const { return layoutsThatGrew_; }
  /// Largest spill, in particles, of the last layout (diagnostics).
  Index largestSpill() const {
    Index m = 0;
    for (int t = 0; t < nt_; ++t) m = std::max(m, spillEnd_[static_cast<size_t>(t)] - end(t));
    return m;
  }

 private:
  std::size_t spillRows(int t) const {
    return static_cast<std::size_t>(spillEnd_[static_cast<size_t>(t)] -
                                    block_[static_cast<size_t>(t) + 1]);
  }
  int nt_ = 0, w_ = 0, maxWidth_ = 0;
  Index n_ = 0;
  std::vector<Index> block_, spillEnd_;
  std::vector<std::int64_t> chunkWeight_;  // layoutWeighted's prefix over chunks of rows
  std::vector<std::vector<double>> spill_;
  std::int64_t allocations_ = 0, layouts_ = 0, layoutsThatGrew_ = 0;
};

}  // namespace poresph
