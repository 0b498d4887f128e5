#pragma once
// Shared helpers of the operator and correction tests: particle blocks (ordered or randomly
// perturbed, with free boundaries: no ghosts, so the support is truncated at the block's faces),
// neighbour lists and geometries.
#include <cstdint>
#include <random>
#include <vector>

#include "libcore/corrections.hpp"
#include "libcore/kernel.hpp"
#include "libcore/neighbour_search.hpp"
#include "libcore/sph_operators.hpp"

namespace poresph::test {

/// Uniform double in [0, 1) from mt19937 bits (portable across standard libraries, unlike
/// std::uniform_real_distribution).
inline double uniform01(std::mt19937& gen) { return gen() / 4294967296.0; }

/// A block of n^D particles (n per axis) of spacing dx, cell centres from `origin`:
/// x = origin + (i + 0.5) dx per axis. `jitter` perturbs each coordinate by a uniform amount in
/// [-jitter, jitter] dx (fixed seed).
struct ParticleBlock {
  int dim = 1;
  double dx = 1.0;
  std::vector<double> x;       ///< dim per particle
  std::vector<double> volume;  ///< dx^dim each
  Index count() const { return static_cast<Index>(volume.size()); }
};

inline ParticleBlock makeBlock(int dim, int n, double dx, double origin, double jitter,
                               std::uint32_t seed = 12345u) {
  ParticleBlock b;
  b.dim = dim;
  b.dx = dx;
  std::mt19937 gen(seed);
  const int nz = dim > 2 ? n : 1, ny = dim > 1 ? n : 1;
  double vol = 1.0;
  for (int d = 0; d < dim; ++d) vol *= dx;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < n; ++i) {
        const int idx[3] = {i, j, k};
        for (int d = 0; d < dim; ++d) {
          const double shift = jitter > 0.0 ? (2.0 * uniform01(gen) - 1.0) * jitter * dx : 0.0;
          b.x.push_back(origin + (idx[d] + 0.5) * dx + shift);
        }
        b.volume.push_back(vol);
      }
  return b;
}

/// Neighbour lists of every particle of the block within the kernel support.
inline NeighbourList buildNeighbours(const ParticleBlock& b, const Kernel& k) {
  NeighbourList nl;
  NeighbourSearch search;
  search.build(b.x.data(), b.dim, b.count(), b.count(), k.support(), nl);
  return nl;
}

/// Geometry of the block with a correction view (None by default).
inline SphGeometry makeGeometry(const ParticleBlock& b, const NeighbourList& nl, const Kernel& k,
                                CorrectionView view = {}) {
  SphGeometry g;
  g.dim = b.dim;
  g.nReal = b.count();
  g.x = b.x.data();
  g.volume = b.volume.data();
  g.neighbours = &nl;
  g.kernel = &k;
  g.correction = view;
  return g;
}

/// Computes a correction of the block into `buf` and returns its view.
inline CorrectionView correct(const ParticleBlock& b, const NeighbourList& nl, const Kernel& k,
                              Correction c, CorrectionBuffer& buf,
                              CorrectionStats* stats = nullptr) {
  buf.resize(b.dim, b.count());
  const CorrectionStats s = computeCorrection(b.dim, c, k, b.x.data(), b.volume.data(),
                                              b.count(), nl, buf.arrays());
  if (stats) *stats = s;
  return buf.view(c, k);
}

}  // namespace poresph::test
