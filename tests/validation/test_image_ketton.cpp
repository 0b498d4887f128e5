// The shipped Ketton image against counts made independently with scipy 1.10
// (scipy.ndimage.label with generate_binary_structure(3, 1) and (3, 3), and
// scipy.ndimage.distance_transform_edt of the pore mask): 6- and 26-connected clusters, the
// largest cluster's share, percolation, and the exact distance transform (histogram of squared
// distances, their sum and maximum). Reference script: docs/voxel-images.md ("Validation").
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "libcore/image_analysis.hpp"
#include "libcore/voxel_image.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

namespace {
const std::string kSource = "independent count (scipy 1.10 ndimage.label / distance_transform_edt)";
const std::string kRes = "128^3 voxels";
}  // namespace

TEST(ImageValidation, Ketton128ClustersAt26Connectivity) {
  test::Stopwatch clock;
  const VoxelImage img =
      VoxelImage::readRaw(std::string(PORESPH_SOURCE_DIR) + "/data/ketton_128.raw", 128, 128, 128);
  const PoreStatistics s = poreStatistics(img, 0, 26);
  Index count = 0;
  const auto labels = labelPoreClusters(img, 0, &count, 26);
  const auto perc = percolatingClusterCount(img, labels);
  const double wall = clock.seconds();
  test::recordValidation({"ketton_128_image", "26-connected pore clusters", double(s.clusters), 51.0,
                          std::abs(double(s.clusters) - 51.0) / 51.0, kRes, wall, "exact", kSource});
  test::recordValidation({"ketton_128_image", "largest 26-connected cluster / pore voxels",
                          s.largestFraction, 225945.0 / 229429.0,
                          std::abs(s.largestFraction - 225945.0 / 229429.0) / (225945.0 / 229429.0),
                          kRes, wall, "exact (voxel count 225945)", kSource});
  EXPECT_EQ(s.clusters, 51);
  EXPECT_EQ(s.largestCluster, 225945);
  for (int a = 0; a < 3; ++a) {
    EXPECT_TRUE(s.largestPercolates[static_cast<size_t>(a)]);
    EXPECT_EQ(perc[static_cast<size_t>(a)], 1);  // scipy: only the largest spans each axis
  }
}

TEST(ImageValidation, Ketton128DistanceTransformEqualsScipy) {
  test::Stopwatch clock;
  const VoxelImage img =
      VoxelImage::readRaw(std::string(PORESPH_SOURCE_DIR) + "/data/ketton_128.raw", 128, 128, 128);
  const auto d2 = squaredDistanceToSolid(img, 0);
  const PoreSizeDistribution p = poreSizeDistribution(d2, img, 0);
  const double wall = clock.seconds();
  std::int64_t sum = 0;
  std::map<std::uint32_t, std::int64_t> h;
  for (const auto& [k, c] : p.histogram) {
    sum += static_cast<std::int64_t>(k) * c;
    h[k] = c;
  }
  const std::int64_t want[10] = {110411, 38033, 12441, 13556, 16563, 6653, 0, 5909, 6769, 2694};
  for (int k = 1; k <= 10; ++k) EXPECT_EQ(h.count(k) ? h[k] : 0, want[k - 1]) << "d2 = " << k;
  EXPECT_EQ(p.poreVoxels, 229429);
  EXPECT_EQ(sum, 836309);
  EXPECT_EQ(p.histogram.back().first, 85u);
  const double meanRef = 380576.53815896146 / 229429.0;
  EXPECT_NEAR(p.meanRadius, meanRef, 1e-12 * meanRef);
  test::recordValidation({"ketton_128_image", "sum of squared pore distances (EDT)", double(sum),
                          836309.0, std::abs(double(sum) - 836309.0) / 836309.0, kRes, wall,
                          "exact", kSource});
  test::recordValidation({"ketton_128_image", "largest inscribed radius (voxels)", p.maxRadius,
                          std::sqrt(85.0), std::abs(p.maxRadius - std::sqrt(85.0)) / std::sqrt(85.0),
                          kRes, wall, "exact (d2 = 85)", kSource});
  test::recordValidation({"ketton_128_image", "mean pore radius (voxels)", p.meanRadius, meanRef,
                          std::abs(p.meanRadius - meanRef) / meanRef, kRes, wall, "< 1e-12 relative",
                          kSource});
}
