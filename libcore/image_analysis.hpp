#pragma once
// Operations on label images (docs/voxel-images.md): coarsening by majority vote, 2D slices, the
// exact Euclidean distance transform and the pore-size distribution derived from it, percolation
// per axis, the labelled .vti for ParaView, and the seeded synthetic clay-like image of data/.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "libcore/voxel_image.hpp"

namespace poresph {

/// Blocks of f x f x f voxels (f x f x 1 for a 2D image) -> one voxel holding the label most
/// voxels of the block hold; a tie goes to the smallest label. Every size must be a multiple of
/// f (InputError naming the shape and f otherwise: crop first).
VoxelImage coarsenImage(const VoxelImage& img, int factor);

/// The 2D image (nz = 1) of the plane normal to `axis` (0 x, 1 y, 2 z) at `index`: normal to z
/// -> (x, y); normal to y -> (x, z); normal to x -> (y, z). InputError when out of range.
VoxelImage sliceImage(const VoxelImage& img, int axis, int index);

/// Squared Euclidean distance (in voxel units) from each voxel whose label is `poreLabel` to the
/// centre of the nearest voxel with another label; 0 for those voxels. Exact: separable
/// lower-envelope passes of Felzenszwalb & Huttenlocher (Theory of Computing 8, 2012), one per
/// axis, O(voxels). Voxels outside the image do not count (as scipy.ndimage.distance_transform_edt).
/// kNoSolid where the image has no other label at all. 4 bytes per voxel.
constexpr std::uint32_t kNoSolid = 0xffffffffu;
std::vector<std::uint32_t> squaredDistanceToSolid(const VoxelImage& img, std::uint8_t poreLabel);

/// Pore-size distribution from the distance transform: how many pore voxels lie at each squared
/// distance d2 from the solid (radius sqrt(d2) voxels). The largest d2 is the radius of the
/// largest sphere inscribed in the pore space (at a voxel centre).
struct PoreSizeDistribution {
  std::vector<std::pair<std::uint32_t, std::int64_t>> histogram;  ///< (d2, voxels), d2 ascending
  std::int64_t poreVoxels = 0;
  double meanRadius = 0.0;    ///< voxels: mean of sqrt(d2) over the pore voxels
  double maxRadius = 0.0;     ///< voxels
  double medianRadius = 0.0;  ///< voxels
};
PoreSizeDistribution poreSizeDistribution(const std::vector<std::uint32_t>& d2,
                                          const VoxelImage& img, std::uint8_t poreLabel);

/// Per axis (x, y, z): how many clusters of `labels` (labelPoreClusters) touch both faces normal
/// to the axis (no periodicity).
std::array<Index, 3> percolatingClusterCount(const VoxelImage& img,
                                             const std::vector<std::int32_t>& labels);

/// Writes a .vti (VTK XML image data, zlib-compressed, cell data: one value per voxel) with the
/// label image as "label", and each of `extra` (name, values per voxel) beside it.
struct VoxelField {
  std::string name;
  const std::vector<std::int32_t>* ints = nullptr;  ///< one of the two
  const std::vector<float>* reals = nullptr;
};
void writeLabelledVti(const std::string& path, const VoxelImage& img, double voxelSize,
                      const std::vector<VoxelField>& extra);

/// A seeded synthetic clay-like image (labels 0 pore, 1 clay, 2 inclusion): inclusions are
/// spheres (discs in 2D) of radius `inclusionRadius` voxels placed at random until their volume
/// fraction reaches `inclusionFraction`; pores are spheres of radius `poreRadius` placed at
/// random (in the clay only) until the porosity reaches `porosity`. The random numbers are a
/// splitmix64 sequence from `seed` (the same image on every machine and compiler).
struct SynthClayOptions {
  std::array<int, 3> n{48, 48, 48};
  double porosity = 0.15;
  double poreRadius = 2.5;
  double inclusionFraction = 0.10;
  double inclusionRadius = 4.0;
  std::uint64_t seed = 1;
};
VoxelImage synthClay(const SynthClayOptions& opt);

}  // namespace poresph
