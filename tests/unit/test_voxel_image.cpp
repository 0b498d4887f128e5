// Voxel images: reading (size checks), cropping and pore statistics on images whose answer is
// known by construction.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "libcore/voxel_image.hpp"

using namespace poresph;

TEST(VoxelImage, TwoSeparateTubesAndAnIsolatedVoxel) {
  VoxelImage img(8, 6, 5, 255);
  for (int x = 0; x < 8; ++x) img.at(x, 1, 1) = 0;  // tube along x: percolates in x
  for (int z = 0; z < 5; ++z) img.at(5, 4, z) = 0;  // tube along z: 5 voxels
  img.at(2, 4, 3) = 0;                              // isolated voxel
  img.at(1, 2, 1) = 0;                              // diagonal to nothing, face-touches the x tube
  const PoreStatistics s = poreStatistics(img, 0);
  EXPECT_EQ(s.voxels, 8 * 6 * 5);
  EXPECT_EQ(s.poreVoxels, 8 + 5 + 1 + 1);
  EXPECT_EQ(s.clusters, 3);
  EXPECT_EQ(s.largestCluster, 9);
  EXPECT_DOUBLE_EQ(s.largestFraction, 9.0 / 15.0);
  EXPECT_TRUE(s.largestPercolates[0]);
  EXPECT_FALSE(s.largestPercolates[1]);
  EXPECT_FALSE(s.largestPercolates[2]);
}

TEST(VoxelImage, DiagonalVoxelsAreSeparateClusters) {
  VoxelImage img(3, 3, 3, 255);
  img.at(0, 0, 0) = 0;
  img.at(1, 1, 0) = 0;  // edge neighbour only: not 6-connected
  img.at(2, 2, 2) = 0;  // corner neighbour only
  EXPECT_EQ(poreStatistics(img, 0).clusters, 3);
}

TEST(VoxelImage, LabelsOrderedBySize) {
  VoxelImage img(6, 1, 1, 255);
  img.at(0, 0, 0) = 0;
  img.at(2, 0, 0) = 0;
  img.at(3, 0, 0) = 0;
  img.at(4, 0, 0) = 0;
  Index count = 0;
  const auto label = labelPoreClusters(img, 0, &count);
  EXPECT_EQ(count, 2);
  EXPECT_EQ(label[0], 1);
  EXPECT_EQ(label[1], -1);
  EXPECT_EQ(label[2], 0);
}

TEST(VoxelImage, CropKeepsValuesAndChecksBounds) {
  VoxelImage img(4, 4, 4, 255);
  img.at(3, 2, 1) = 0;
  const VoxelImage c = img.crop(2, 2, 1, 2, 2, 2);
  EXPECT_EQ(c.at(1, 0, 0), 0);
  EXPECT_THROW(img.crop(3, 0, 0, 2, 1, 1), InputError);
}

TEST(VoxelImage, SizeMismatchNamesFileAndSizes) {
  const std::string path = std::string(PORESPH_BINARY_DIR) + "/voxel_size_mismatch.raw";
  {
    std::ofstream out(path, std::ios::binary);
    for (int i = 0; i < 10; ++i) out.put(0);
  }
  try {
    VoxelImage::readRaw(path, 2, 2, 2);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find("10 bytes"), std::string::npos) << m;
    EXPECT_NE(m.find("2 x 2 x 2"), std::string::npos) << m;
  }
  std::remove(path.c_str());
  EXPECT_THROW(VoxelImage::readRaw(path + ".missing", 2, 2, 2), InputError);
}
