#pragma once
// Segmented 3D voxel images (micro-CT) and their pore statistics.
//
// Format: headerless raw, unsigned 8-bit, x fastest, then y, then z (C order of [z][y][x]), as
// the shipped data/ketton_128.raw. A label value marks pore voxels (0 for the Ketton image).
// The statistics (porosity, connected pore clusters, percolation) are what users check an image
// against before they use it, and what the drainage runs will report over time.
//
// Sizes are checked before anything is allocated: the voxel count with overflow-safe 64-bit
// arithmetic, the file size against the shape, and the bytes needed against the memory available
// (docs/voxel-images.md), so that a wrong or too large shape is refused with a message instead of
// a crash.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "libcore/types.hpp"

namespace poresph {

/// Largest voxel count accepted (2^48): beyond it no machine can hold the image (x86-64 user
/// space is 2^47 bytes), and every byte count of the analysis still fits 64-bit arithmetic.
constexpr Index kMaxVoxels = Index{1} << 48;

/// Bytes per voxel that the cluster labelling needs on top of the image (one 32-bit label).
constexpr std::uint64_t kLabelBytesPerVoxel = 4;

class VoxelImage {
 public:
  VoxelImage() = default;
  /// nx, ny, nz voxels; all set to `fill`. Throws InputError for a non-positive size, more than
  /// kMaxVoxels voxels, or more bytes than the memory available.
  VoxelImage(int nx, int ny, int nz, std::uint8_t fill = 0);
  /// Reads a raw file; throws InputError naming the file and the shape when the shape is invalid
  /// or too large, when the file size does not match it, or when the image plus
  /// `extraBytesPerVoxel` per voxel (what the caller will allocate next, e.g. kLabelBytesPerVoxel)
  /// does not fit in the memory available. All checks come before the image is allocated.
  static VoxelImage readRaw(const std::string& path, int nx, int ny, int nz,
                            std::uint64_t extraBytesPerVoxel = 0);

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
  std::uint8_t* data() { return v_.data(); }
  /// Whether the image is a 2D slice (nz == 1).
  bool flat() const { return n_[2] == 1; }

  /// Sub-block [x0, x0+sx) x [y0, y0+sy) x [z0, z0+sz); throws InputError when out of range.
  VoxelImage crop(int x0, int y0, int z0, int sx, int sy, int sz) const;

 private:
  std::array<int, 3> n_{0, 0, 0};
  std::vector<std::uint8_t> v_;
};

/// Neighbour offsets (dx, dy, dz) that connect pore voxels: connectivity 6 (faces), 18 (faces and
/// edges) or 26 (faces, edges and corners), as scipy.ndimage.generate_binary_structure(3, 1|2|3).
/// Throws InputError for any other value.
std::vector<std::array<int, 3>> neighbourOffsets(int connectivity);

struct PoreStatistics {
  int connectivity = 6;          ///< 6, 18 or 26
  Index voxels = 0;
  Index poreVoxels = 0;
  double porosity = 0.0;
  Index clusters = 0;            ///< connected pore clusters
  Index largestCluster = 0;      ///< voxels of the largest cluster
  double largestFraction = 0.0;  ///< largestCluster / poreVoxels
  std::array<bool, 3> largestPercolates{false, false, false};  ///< touches both faces along x, y, z
};

/// Porosity, clusters of voxels equal to `poreLabel` (connected through neighbourOffsets(
/// connectivity)), and percolation of the largest cluster along each axis (no periodicity).
/// Linear in the voxel count; about 4 bytes per voxel on top of the image.
PoreStatistics poreStatistics(const VoxelImage& image, std::uint8_t poreLabel = 0,
                              int connectivity = 6);

/// Cluster id (0..clusters-1, by decreasing size, ties by the first voxel in x-fastest order) of
/// each voxel, -1 for non-pore voxels. Two-pass labelling with a compact equivalence table (one
/// 32-bit entry per provisional cluster), so the labels themselves are the only per-voxel array.
/// Throws InputError when the labels do not fit in the memory available or when there are more
/// than 2^31 - 1 provisional clusters (32-bit labels); images of more than 2^31 voxels are fine.
std::vector<std::int32_t> labelPoreClusters(const VoxelImage& image, std::uint8_t poreLabel,
                                            Index* clusterCount = nullptr, int connectivity = 6,
                                            std::vector<Index>* clusterSizes = nullptr);

}  // namespace poresph
