#pragma once
// Geometry builders: regions of a scene (boxes, spheres / discs / segments, cylinders) filled
// with a Cartesian lattice of spacing dx.
//
// One global lattice serves every region: its sites are lo + (i + 1/2) dx along each axis (lo =
// the domain's lower corner, i any integer), so that a box [lo, hi] whose faces lie on multiples
// of dx gets exactly (hi - lo)/dx sites per axis, regions that touch share no site, and regions
// outside the domain (wall layers on non-periodic axes) line up with the particles inside.
// Along a periodic axis only sites inside [lo, hi) exist (the images come from the halo), and
// the domain length must be a whole number of spacings.
//
// Regions are applied in order; a later region overrides earlier ones where they overlap. A
// region with no material (material: none in the scene) subtracts: its sites hold no particle.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "libcore/domain.hpp"
#include "libcore/types.hpp"

namespace poresph {

/// A label image placed on the lattice (geometry shape `image`, libcore/image_scene.hpp): voxel
/// (i, j, k) is the lattice site at origin + (i + 1/2, j + 1/2, k + 1/2) voxel, voxel = spacing.
/// Each voxel names the member of the image's region group that owns it (one region per material
/// of the label map), or kNoMember for no particle.
struct ImageGrid {
  static constexpr std::uint8_t kNoMember = 255;
  std::array<int, 3> n{1, 1, 1};                ///< voxels along x, y, z (z = 1 for a 2D image)
  double voxel = 0.0;                           ///< edge length (m), equal to the spacing
  std::array<double, 3> origin{0.0, 0.0, 0.0};  ///< lower corner of voxel (0, 0, 0)
  std::vector<std::uint8_t> member;             ///< per voxel, x fastest
  int members = 0;
  /// Member of the voxel holding point x (dim components), or kNoMember outside the image.
  std::uint8_t memberAt(const double* x, int dim) const;
};

struct Region {
  enum class Shape { Box, Sphere, Cylinder, Image };
  Shape shape = Shape::Box;
  std::array<double, 3> lo{0.0, 0.0, 0.0};      ///< box: lower corner
  std::array<double, 3> hi{0.0, 0.0, 0.0};      ///< box: upper corner
  std::array<double, 3> centre{0.0, 0.0, 0.0};  ///< sphere, cylinder: centre
  double radius = 0.0;                          ///< sphere: radius (disc in 2D, segment in 1D);
                                                ///< cylinder: radius about its axis
  std::array<double, 3> axis{0.0, 0.0, 1.0};    ///< cylinder: unit axis (in the plane in 2D,
                                                ///< where the cylinder is a tilted rectangle)
  double length = 0.0;                          ///< cylinder: length along the axis
  int material = -1;                            ///< material id; -1 subtracts
  std::int32_t motion = 0;                      ///< Motion (libcore/simulation.hpp)
  std::array<double, 3> velocity{0.0, 0.0, 0.0};///< initial (or imposed) velocity, m/s
  std::string where;                            ///< "file:line: geometry[k]" for messages
  /// Image: the grid shared by the group's regions, and which member this region is. The group
  /// is consecutive regions (members 0 .. members-1); lo / hi are the image's box.
  std::shared_ptr<const ImageGrid> image;
  int imageMember = 0;

  bool subtracts() const { return material < 0; }
  /// Whether point x (dim components) lies in the region, with a tolerance tol on the boundary.
  bool contains(const double* x, int dim, double tol) const;
  /// Axis-aligned bounding box.
  void bounds(int dim, std::array<double, 3>& blo, std::array<double, 3>& bhi) const;
  /// The interval [x0, x1] along x that a convex region (box, sphere, cylinder) covers on the
  /// line through x (its components 1 .. dim-1; x[0] is ignored), grown by tol; false when the
  /// line misses it. The lattice fill refines the ends with contains().
  bool rowSpan(const double* x, int dim, double tol, double& x0, double& x1) const;
};

/// Lattice sites that hold a particle, with the region that owns each (the last region that
/// contains the site), ordered x fastest, then y, then z.
struct LatticeFill {
  int dimension = 3;
  std::vector<double> position;  ///< dimension components per site
  std::vector<int> region;       ///< owning region of each site (never a subtracting one)
  Index count() const { return static_cast<Index>(region.size()); }
};

/// The most particles a scene may hold: particle ids are 32-bit (ParticleStore).
constexpr std::uint64_t kMaxLatticeParticles = 2147483647ULL;

/// Thrown when the spacing is too small for the geometry: the lattice cannot be indexed, counted
/// or held (the message gives the spacing and the count it implies; the scene adds the key).
class LatticeTooLarge : public InputError {
 public:
  using InputError::InputError;
};

/// Result of the counting pass: what fillLattice would produce, found row by row (x rows of the
/// bounding lattice of the regions) with a few small buffers, without allocating per site.
struct LatticeCount {
  std::uint64_t sites = 0;                ///< lattice sites that hold a particle
  std::vector<std::uint64_t> perRegion;   ///< sites owned by each region (0 for subtracting ones)
  double boundingSites = 0.0;             ///< sites of the bounding lattice (may be huge)
};

/// Counts the sites that fillLattice would fill, with 64-bit overflow-safe arithmetic and in
/// O(rows x regions^2) time (rows = lattice rows along x of the regions' bounding box). Throws
/// LatticeTooLarge when the lattice indices would overflow, when the bounding box has more than
/// 2^28 rows, or when the count exceeds kMaxLatticeParticles; InputError when a periodic length
/// is not a whole number of spacings.
LatticeCount countLattice(const std::vector<Region>& regions, const Domain& domain, double dx);

/// Fills `regions` on the lattice of spacing dx anchored at domain.lo (see the file comment).
/// Runs the counting pass first (same errors as countLattice) and allocates exactly the sites
/// counted; no array over the bounding lattice is made.
LatticeFill fillLattice(const std::vector<Region>& regions, const Domain& domain, double dx);

}  // namespace poresph
