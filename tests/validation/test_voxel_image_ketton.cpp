// The shipped Ketton image: porosity, 6-connected clusters and percolation against the counts
// made independently with numpy + scipy.ndimage.label (data/README.md).
#include <gtest/gtest.h>

#include <cmath>

#include "libcore/voxel_image.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

TEST(VoxelImageValidation, Ketton128MatchesIndependentCounts) {
  test::Stopwatch clock;
  const VoxelImage img =
      VoxelImage::readRaw(std::string(PORESPH_SOURCE_DIR) + "/data/ketton_128.raw", 128, 128, 128);
  const PoreStatistics s = poreStatistics(img, 0);
  const double wall = clock.seconds();
  const std::string res = "128^3 voxels";
  const std::string src = "independent count (numpy + scipy.ndimage.label), data/README.md";
  test::recordValidation({"ketton_128_image", "porosity", s.porosity, 0.109400,
                          std::abs(s.porosity - 0.109400) / 0.109400, res, wall, "< 1e-5 relative", src});
  test::recordValidation({"ketton_128_image", "6-connected pore clusters", double(s.clusters), 480.0,
                          std::abs(double(s.clusters) - 480.0) / 480.0, res, wall, "exact", src});
  test::recordValidation({"ketton_128_image", "largest cluster / pore voxels", s.largestFraction,
                          0.976023, std::abs(s.largestFraction - 0.976023) / 0.976023, res, wall,
                          "< 1e-5 relative", src});
  EXPECT_EQ(s.poreVoxels, 229429);
  EXPECT_NEAR(s.porosity, 0.109400, 1e-6);
  EXPECT_EQ(s.clusters, 480);
  EXPECT_NEAR(s.largestFraction, 0.976023, 1e-6);
  EXPECT_TRUE(s.largestPercolates[0]);
  EXPECT_TRUE(s.largestPercolates[1]);
  EXPECT_TRUE(s.largestPercolates[2]);
}
