// Voxel images: reading (size, overflow and memory checks before allocating), cropping, and pore
// statistics on images whose answer is known by construction or by a brute-force flood fill; the
// `poresph image` command's refusals, run as a program.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include "libcore/memory.hpp"
#include "libcore/voxel_image.hpp"

using namespace poresph;
namespace fs = std::filesystem;

namespace {

/// A scratch file name of this process (ctest runs the tests of a file in parallel processes).
std::string scratch(const std::string& name) {
  const fs::path d = fs::path(PORESPH_BINARY_DIR) / "tmp_test_voxel_image";
  fs::create_directories(d);
  return (d / (std::to_string(getpid()) + "_" + name)).string();
}

std::string emptyFile() {
  const std::string path = scratch("empty.raw");
  std::ofstream(path, std::ios::binary);
  return path;
}

/// A sparse file of `bytes` (no disk used), or "" where the file system cannot make one.
std::string sparseFile(std::uintmax_t bytes) {
  const std::string path = scratch("sparse.raw");
  std::ofstream(path, std::ios::binary);
  std::error_code ec;
  fs::resize_file(path, bytes, ec);
  if (ec) {
    fs::remove(path);
    return "";
  }
  return path;
}

std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

/// Brute-force reference: flood fill from each unvisited pore voxel in x-fastest order, with
/// neighbours written out independently of neighbourOffsets (at most `maxNonZero` of dx, dy, dz
/// non-zero), then ids by decreasing size, ties by first voxel.
std::vector<std::int32_t> floodFillLabels(const VoxelImage& img, std::uint8_t pore, int maxNonZero) {
  const Index n = img.voxelCount();
  std::vector<std::int32_t> comp(static_cast<size_t>(n), -1);
  std::vector<Index> size;
  std::int32_t next = 0;
  for (int z = 0; z < img.nz(); ++z)
    for (int y = 0; y < img.ny(); ++y)
      for (int x = 0; x < img.nx(); ++x) {
        if (img.at(x, y, z) != pore || comp[static_cast<size_t>(img.linear(x, y, z))] >= 0) continue;
        std::vector<std::array<int, 3>> stack{{x, y, z}};
        comp[static_cast<size_t>(img.linear(x, y, z))] = next;
        Index count = 0;
        while (!stack.empty()) {
          const auto c = stack.back();
          stack.pop_back();
          ++count;
          for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                const int nz = (dx != 0) + (dy != 0) + (dz != 0);
                if (nz == 0 || nz > maxNonZero) continue;
                const int a = c[0] + dx, b = c[1] + dy, d = c[2] + dz;
                if (a < 0 || b < 0 || d < 0 || a >= img.nx() || b >= img.ny() || d >= img.nz()) continue;
                auto& l = comp[static_cast<size_t>(img.linear(a, b, d))];
                if (img.at(a, b, d) != pore || l >= 0) continue;
                l = next;
                stack.push_back({a, b, d});
              }
        }
        size.push_back(count);
        ++next;
      }
  std::vector<std::int32_t> order(static_cast<size_t>(next)), rank(static_cast<size_t>(next));
  for (std::int32_t c = 0; c < next; ++c) order[static_cast<size_t>(c)] = c;
  std::stable_sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    return size[static_cast<size_t>(a)] > size[static_cast<size_t>(b)];
  });
  for (std::int32_t k = 0; k < next; ++k) rank[static_cast<size_t>(order[static_cast<size_t>(k)])] = k;
  for (auto& l : comp)
    if (l >= 0) l = rank[static_cast<size_t>(l)];
  return comp;
}

}  // namespace

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

TEST(VoxelImage, EqualSizesNumberedByFirstVoxel) {
  VoxelImage img(7, 1, 1, 255);
  img.at(4, 0, 0) = img.at(5, 0, 0) = 0;  // later pair
  img.at(0, 0, 0) = img.at(1, 0, 0) = 0;  // earlier pair
  img.at(3, 0, 0) = 255;
  const auto label = labelPoreClusters(img, 0);
  EXPECT_EQ(label[0], 0);
  EXPECT_EQ(label[4], 1);
}

// The old code multiplied the three sizes in 64-bit without a check: 2^66 voxels wrapped around
// and the program crashed. Now the count is refused, naming the file, the shape and the limit.
TEST(VoxelImage, OverflowingShapeRefusedNamingFileShapeAndLimit) {
  const std::string path = emptyFile();
  const std::string m = messageOf([&] { VoxelImage::readRaw(path, 4194304, 4194304, 4194304); });
  EXPECT_NE(m.find(path), std::string::npos) << m;
  EXPECT_NE(m.find("4194304 x 4194304 x 4194304"), std::string::npos) << m;
  EXPECT_NE(m.find("2^48"), std::string::npos) << m;
  const std::string c = messageOf([&] { VoxelImage(2147483647, 2147483647, 2147483647); });
  EXPECT_NE(c.find("2147483647 x 2147483647 x 2147483647"), std::string::npos) << c;
  EXPECT_NE(messageOf([&] { VoxelImage(0, 5, 5); }).find("positive"), std::string::npos);
  fs::remove(path);
}

// 2^48 voxels is within the count limit but far beyond memory: the old reader allocated the
// image before looking at the file; now the file size is checked first.
TEST(VoxelImage, FileSizeCheckedBeforeAllocating) {
  const std::string path = emptyFile();
  const std::string m = messageOf([&] { VoxelImage::readRaw(path, 65536, 65536, 65536); });
  EXPECT_NE(m.find("size 0 bytes does not match the shape 65536 x 65536 x 65536"), std::string::npos)
      << m;
  fs::remove(path);
}

// A file that matches its shape but cannot fit in memory (a 4 TiB sparse file) is refused
// before anything is allocated, with the bytes needed and available.
TEST(VoxelImage, ImageLargerThanMemoryRefusedWithTheNumbers) {
  const std::uint64_t available = availableMemoryBytes();
  if (available == 0) GTEST_SKIP() << "MemAvailable unknown on this system";
  const std::string path = sparseFile(std::uintmax_t{65536} * 65536 * 1024);
  if (path.empty()) GTEST_SKIP() << "no sparse files on this file system";
  const std::string m = messageOf([&] { VoxelImage::readRaw(path, 65536, 65536, 1024); });
  EXPECT_NE(m.find(path), std::string::npos) << m;
  EXPECT_NE(m.find("needs 4.00 TiB"), std::string::npos) << m;
  EXPECT_NE(m.find("is available"), std::string::npos) << m;
  fs::remove(path);
  // The caller's own bytes per voxel count too: a small image with a huge analysis is refused.
  const std::string small = scratch("small.raw");
  std::ofstream(small, std::ios::binary) << std::string(8, '\0');
  const std::string a = messageOf([&] { VoxelImage::readRaw(small, 2, 2, 2, std::uint64_t{1} << 60); });
  EXPECT_NE(a.find("needs"), std::string::npos) << a;
  EXPECT_NE(a.find("is available"), std::string::npos) << a;
  EXPECT_EQ(VoxelImage::readRaw(small, 2, 2, 2, kLabelBytesPerVoxel).voxelCount(), 8);
  fs::remove(small);
}

TEST(VoxelImage, FormatBytesAndAvailableMemory) {
  EXPECT_EQ(formatBytes(0), "0 B");
  EXPECT_EQ(formatBytes(1023), "1023 B");
  EXPECT_EQ(formatBytes(1536), "1.50 KiB");
  EXPECT_EQ(formatBytes(std::uint64_t{5} << 40), "5.00 TiB");
  EXPECT_EQ(formatBytes(~std::uint64_t{0}), "16.0 EiB");
#ifdef __linux__
  EXPECT_GT(availableMemoryBytes(), 0u);
#endif
}

TEST(VoxelImage, NeighbourOffsetsCounts) {
  EXPECT_EQ(neighbourOffsets(6).size(), 6u);
  EXPECT_EQ(neighbourOffsets(18).size(), 18u);
  EXPECT_EQ(neighbourOffsets(26).size(), 26u);
  EXPECT_NE(messageOf([] { neighbourOffsets(8); }).find("6, 18 or 26, got 8"), std::string::npos);
}

TEST(VoxelImage, DiagonalVoxelsJoinWith18And26Connectivity) {
  VoxelImage img(3, 3, 3, 255);
  img.at(0, 0, 0) = 0;
  img.at(1, 1, 0) = 0;  // edge neighbour of the first
  img.at(2, 2, 1) = 0;  // corner neighbour of the second
  EXPECT_EQ(poreStatistics(img, 0, 6).clusters, 3);
  EXPECT_EQ(poreStatistics(img, 0, 18).clusters, 2);
  const PoreStatistics s = poreStatistics(img, 0, 26);
  EXPECT_EQ(s.clusters, 1);
  EXPECT_EQ(s.connectivity, 26);
  EXPECT_TRUE(s.largestPercolates[0]);
  EXPECT_FALSE(s.largestPercolates[2]);
}

// The labelling (two passes, equivalence table) against a flood fill, voxel by voxel, ids
// included, on random images around and below the percolation thresholds (many merges) and
// with thin axes (rows and planes, where the bounds checks matter).
TEST(VoxelImage, LabelsEqualBruteForceFloodFill) {
  std::mt19937 rng(12);
  const std::array<std::array<int, 3>, 6> shapes{{{9, 7, 5}, {1, 13, 11}, {16, 1, 9}, {12, 10, 1},
                                                  {20, 1, 1}, {17, 15, 13}}};
  int cases = 0;
  for (const auto& sh : shapes)
    for (const double p : {0.1, 0.25, 0.35, 0.6})
      for (const int conn : {6, 18, 26}) {
        VoxelImage img(sh[0], sh[1], sh[2], 255);
        std::bernoulli_distribution pore(p);
        for (int z = 0; z < sh[2]; ++z)
          for (int y = 0; y < sh[1]; ++y)
            for (int x = 0; x < sh[0]; ++x)
              if (pore(rng)) img.at(x, y, z) = 7;
        Index count = -1;
        const auto label = labelPoreClusters(img, 7, &count, conn);
        const auto expected = floodFillLabels(img, 7, conn == 6 ? 1 : conn == 18 ? 2 : 3);
        const Index expectedCount =
            expected.empty() ? 0 : *std::max_element(expected.begin(), expected.end()) + 1;
        ASSERT_EQ(count, expectedCount) << sh[0] << "x" << sh[1] << "x" << sh[2] << " p " << p
                                        << " connectivity " << conn;
        ASSERT_EQ(label, expected) << sh[0] << "x" << sh[1] << "x" << sh[2] << " p " << p
                                   << " connectivity " << conn;
        ++cases;
      }
  EXPECT_EQ(cases, 72);
}

// ---- the `poresph image` command, run as a program (the built binary, as in test_cli.cpp) ----
namespace {

struct CommandResult {
  int code = -1;
  std::string output;  // stdout and stderr together
};

CommandResult runImage(const std::string& args) {
  const fs::path binary = fs::path(PORESPH_BINARY_DIR) / "poresph";
  const std::string log = scratch("image_output.txt");
  const std::string cmd =
      "\"" + binary.string() + "\" image " + args + " > \"" + log + "\" 2>&1";
  const int status = std::system(cmd.c_str());
  CommandResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;  // -1: killed (a crash)
  std::ostringstream s;
  s << std::ifstream(log).rdbuf();
  r.output = s.str();
  fs::remove(log);
  return r;
}

}  // namespace

TEST(VoxelImageCommand, RefusalsExitWithCode2AndNameTheValue) {
  ASSERT_TRUE(fs::exists(fs::path(PORESPH_BINARY_DIR) / "poresph")) << "poresph is not built";
  const std::string path = emptyFile();
  CommandResult r = runImage("\"" + path + "\" --shape 4194304 4194304 4194304");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find(path), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("4194304 x 4194304 x 4194304"), std::string::npos) << r.output;

  // CLI11's PositiveNumber printed a 309-digit bound here.
  r = runImage("\"" + path + "\" --shape 0 4 4");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--shape: every size must be a positive whole number"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("got 0"), std::string::npos) << r.output;
  EXPECT_LT(r.output.size(), 200u) << r.output;

  r = runImage("\"" + path + "\" --shape 4 4 4 --pore-label 256");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--pore-label: must be a whole number from 0 to 255, got 256"),
            std::string::npos)
      << r.output;
  r = runImage("\"" + path + "\" --shape 4 4 4 --connectivity 8");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--connectivity: must be 6, 18 or 26, got 8"), std::string::npos)
      << r.output;
  fs::remove(path);

  if (availableMemoryBytes() == 0) return;
  const std::string huge = sparseFile(std::uintmax_t{65536} * 65536 * 1024);
  if (huge.empty()) return;
  r = runImage("\"" + huge + "\" --shape 65536 65536 1024");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("needs 20.0 TiB"), std::string::npos) << r.output;  // image + labels
  EXPECT_NE(r.output.find("is available"), std::string::npos) << r.output;
  fs::remove(huge);
}

TEST(VoxelImageCommand, KettonWith26Connectivity) {
  ASSERT_TRUE(fs::exists(fs::path(PORESPH_BINARY_DIR) / "poresph")) << "poresph is not built";
  const CommandResult r = runImage("\"" + std::string(PORESPH_SOURCE_DIR) +
                         "/data/ketton_128.raw\" --shape 128 128 128 --connectivity 26");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("(26-connected)"), std::string::npos) << r.output;
}
