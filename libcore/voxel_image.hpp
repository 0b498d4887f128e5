#pragma once
// Segmented 3D voxel images (micro-CT) and their pore statistics.
//
// Format: headerless raw, unsigned 8-bit, x fastest, then y, then z (C order of [z][y][x]), as
// the shipped data/ketton_128.raw. A label value marks pore voxels (0 for the Ketton image).
// The statistics (porosity, 6-connected pore clusters, percolation) are what users check a scene
// against before they run it, and what the drainage runs report over time.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "libcore/types.hpp"

namespace poresph {

class VoxelImage {
 public:
  VoxelImage() = default;
  /// nx, ny, nz voxels; all set to `fill`.
  VoxelImage(int nx, int ny, int nz, std::uint8_t fill = 0);
  /// Reads a raw file; throws InputError naming the file, the expected and the actual size.
  static VoxelImage readRaw(const std::string& path, int nx, int ny, int nz);

  int nx() const { return n_[0]; }
  int ny() const { return n_[1]; }
  int nz() const { return n_[2]; }
  Index voxelCount() const { return static_cast<Index>(n_[0]) * n_[1] * n_[2]; }
  Index linear(int x, int y, int z) const {
    return (static_cast<Index>(z) * n_[1] + y) * n_[0] + x;
  }
  std::uint8_t at(int x, int y, int z) const { return v_[static_cast<size_t>(linear(x, y, z))]; }
  std::uint8_t& at(int x, int y, int z) { return v_[static_cast<size_t>(linear(x, y, z))]; }
  const std::vector<std::uint8_t>& values() const { return v_; }

  /// Sub-block [x0, x0+sx) x [y0, y0+sy) x [z0, z0+sz); throws InputError when out of range.
  VoxelImage crop(int x0, int y0, int z0, int sx, int sy, int sz) const;

 private:
  std::array<int, 3> n_{0, 0, 0};
  std::vector<std::uint8_t> v_;
};

struct PoreStatistics {
  Index voxels = 0;
  Index poreVoxels = 0;
  double porosity = 0.0;
  Index clusters = 0;            ///< 6-connected pore clusters
  Index largestCluster = 0;      ///< voxels of the largest cluster
  double largestFraction = 0.0;  ///< largestCluster / poreVoxels
  std::array<bool, 3> largestPercolates{false, false, false};  ///< touches both faces along x, y, z
};

/// Porosity, 6-connected clusters of voxels equal to `poreLabel`, and percolation of the largest
/// cluster along each axis (no periodicity). Union-find; linear in the voxel count.
PoreStatistics poreStatistics(const VoxelImage& image, std::uint8_t poreLabel = 0);

/// Cluster id (0..clusters-1, by decreasing size) of each voxel, -1 for non-pore voxels.
std::vector<std::int32_t> labelPoreClusters(const VoxelImage& image, std::uint8_t poreLabel,
                                            Index* clusterCount = nullptr);

}  // namespace poresph
