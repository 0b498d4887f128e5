// Image readers (raw, mhd, nhdr, tiff, vti, hdf5) and label operations: round trips of every
// format and voxel type, the refusals (size mismatch, truncated file, unknown label, empty phase,
// bad header) with their numbers, a fuzz of every format (random truncations and byte flips:
// InputError or a correct read, never a crash), coarsening, slices, the exact distance
// transform against brute force, and the seeded synthetic image.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "libcore/image_analysis.hpp"
#include "libcore/image_io.hpp"

using namespace poresph;
namespace fs = std::filesystem;

namespace {

std::string scratch(const std::string& name) {
  const fs::path d = fs::path(PORESPH_BINARY_DIR) / "tmp_test_image_io" / std::to_string(getpid());
  fs::create_directories(d);
  return (d / name).string();
}

RawVolume makeVolume(VoxelType t, std::array<int, 3> n, unsigned seed) {
  RawVolume v;
  v.n = n;
  v.type = t;
  const Index count = v.voxelCount();
  v.bytes.resize(static_cast<size_t>(count) * voxelTypeBytes(t));
  std::mt19937 rng(seed);
  for (Index i = 0; i < count; ++i) {
    unsigned char* p = v.bytes.data() + i * voxelTypeBytes(t);
    const int r = static_cast<int>(rng() % 3);
    switch (t) {
      case VoxelType::UInt8: { std::uint8_t x = static_cast<std::uint8_t>(r * 100); std::memcpy(p, &x, 1); break; }
      case VoxelType::UInt16: { std::uint16_t x = static_cast<std::uint16_t>(r * 30000); std::memcpy(p, &x, 2); break; }
      case VoxelType::Int32: { std::int32_t x = r * 100000 - 5; std::memcpy(p, &x, 4); break; }
      case VoxelType::Float32: { float x = 0.25f * r + 0.1f; std::memcpy(p, &x, 4); break; }
    }
  }
  return v;
}

std::string message(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

const std::vector<VoxelType> kTypes = {VoxelType::UInt8, VoxelType::UInt16, VoxelType::Int32,
                                       VoxelType::Float32};

}  // namespace

TEST(ImageIo, EveryFormatAndTypeRoundTrips) {
  for (const std::string fmt : {"raw", "mhd", "nhdr", "tiff", "vti", "hdf5"})
    for (VoxelType t : kTypes) {
      const RawVolume v = makeVolume(t, {7, 5, 3}, 11);
      const std::string ext = fmt == "tiff" ? "tif" : fmt == "hdf5" ? "h5" : fmt;
      const std::string path = scratch("round_" + voxelTypeName(t) + "." + ext);
      writeVolume(v, path, fmt);
      ImageFileSpec spec;
      spec.path = path;
      if (fmt == "raw") {
        spec.shape = v.n;
        spec.type = t;
      }
      const RawVolume r = readVolume(spec);
      SCOPED_TRACE(fmt + " " + voxelTypeName(t));
      EXPECT_EQ(r.n, v.n);
      EXPECT_EQ(r.type, t);
      ASSERT_EQ(r.bytes.size(), v.bytes.size());
      EXPECT_TRUE(r.bytes == v.bytes);
    }
}

TEST(ImageIo, RawByteOrderAndHeaderBytes) {
  const std::string path = scratch("be.raw");
  {
    std::ofstream f(path, std::ios::binary);
    const unsigned char bytes[] = {9, 9, 9, 0x01, 0x02, 0x00, 0x07};  // 3 header bytes
    f.write(reinterpret_cast<const char*>(bytes), sizeof(bytes));
  }
  ImageFileSpec s;
  s.path = path;
  s.shape = {2, 1, 1};
  s.type = VoxelType::UInt16;
  s.bigEndian = true;
  s.headerBytes = 3;
  const RawVolume v = readVolume(s);
  EXPECT_EQ(v.value(0), 0x0102);
  EXPECT_EQ(v.value(1), 0x0007);
  s.bigEndian = false;
  EXPECT_EQ(readVolume(s).value(0), 0x0201);
}

TEST(ImageIo, RefusalsNameTheFileAndTheNumbers) {
  const RawVolume v = makeVolume(VoxelType::UInt16, {4, 4, 4}, 3);
  const std::string raw = scratch("r.raw");
  writeVolume(v, raw, "raw");
  ImageFileSpec s;
  s.path = raw;
  s.shape = {4, 4, 5};
  s.type = VoxelType::UInt16;
  std::string m = message([&] { readVolume(s); });
  EXPECT_NE(m.find("r.raw"), std::string::npos) << m;
  EXPECT_NE(m.find("size 128 bytes does not match the shape 4 x 4 x 5"), std::string::npos) << m;
  EXPECT_NE(m.find("160 bytes"), std::string::npos) << m;
  s.shape = {4, 4, 4};
  s.path = scratch("missing.raw");
  EXPECT_NE(message([&] { readVolume(s); }).find("no such file"), std::string::npos);
  // A truncated mhd data file.
  const std::string mhd = scratch("t.mhd");
  writeVolume(v, mhd, "mhd");
  fs::resize_file(scratch("t.raw"), 100);
  m = message([&] { ImageFileSpec q; q.path = mhd; readVolume(q); });
  EXPECT_NE(m.find("t.raw"), std::string::npos) << m;
  EXPECT_NE(m.find("size 100 bytes"), std::string::npos) << m;
  // A truncated TIFF.
  const std::string tif = scratch("t.tif");
  writeVolume(v, tif, "tiff");
  fs::resize_file(tif, fs::file_size(tif) - 10);
  m = message([&] { ImageFileSpec q; q.path = tif; readVolume(q); });
  EXPECT_NE(m.find("truncated"), std::string::npos) << m;
  EXPECT_NE(m.find("t.tif"), std::string::npos) << m;
  // An unknown extension, a .gz.
  EXPECT_NE(message([&] { detectImageFormat("a.png"); }).find("'.png'"), std::string::npos);
  EXPECT_NE(message([&] { detectImageFormat("a.raw.gz"); }).find("gunzip"), std::string::npos);
  // An unknown voxel type name.
  EXPECT_NE(message([&] { parseVoxelType("uint64", "type"); }).find("uint8, uint16, int32, float32"),
            std::string::npos);
  // mhd with an unsupported element type names the line.
  const std::string bad = scratch("bad.mhd");
  std::ofstream(bad) << "NDims = 3\nDimSize = 4 4 4\nElementType = MET_DOUBLE\nElementDataFile = t.raw\n";
  m = message([&] { ImageFileSpec q; q.path = bad; readVolume(q); });
  EXPECT_NE(m.find("bad.mhd':3: ElementType = 'MET_DOUBLE'"), std::string::npos) << m;
  // HDF5: two datasets and none named.
  const std::string h5 = scratch("two.h5");
  writeVolume(v, h5, "hdf5", "a");
  m = message([&] { ImageFileSpec q; q.path = h5; q.dataset = "b"; readVolume(q); });
  EXPECT_NE(m.find("no dataset 'b'"), std::string::npos) << m;
}

TEST(ImageIo, LabelsThresholdUnknownValueEmptyPhase) {
  RawVolume v = makeVolume(VoxelType::UInt16, {5, 4, 3}, 5);  // values 0, 30000, 60000
  LabelRule rule;
  rule.map = {{0, 0}, {30000, 1}, {60000, 2}};
  const VoxelImage img = applyLabels(v, rule);
  for (Index i = 0; i < v.voxelCount(); ++i)
    EXPECT_EQ(img.values()[static_cast<size_t>(i)], static_cast<int>(v.value(i) / 30000));
  // Any value may be the pore label: swap 0 and 2.
  rule.map = {{0, 2}, {30000, 1}, {60000, 0}};
  const VoxelImage swapped = applyLabels(v, rule);
  EXPECT_EQ(swapped.values()[0], 2 - img.values()[0]);
  // A value without an entry: named with its count and first voxel.
  rule.map = {{0, 0}, {30000, 1}};
  Index n60000 = 0;
  for (Index i = 0; i < v.voxelCount(); ++i) n60000 += v.value(i) == 60000;
  std::string m = message([&] { applyLabels(v, rule); });
  EXPECT_NE(m.find("value 60000 (" + std::to_string(n60000) + " voxels"), std::string::npos) << m;
  EXPECT_NE(m.find("values mapped: 0, 30000"), std::string::npos) << m;
  // An empty phase.
  rule.map = {{0, 0}, {30000, 1}, {60000, 2}, {7, 3}};
  m = message([&] { applyLabels(v, rule); });
  EXPECT_NE(m.find("value 7 (label 3) has no voxel"), std::string::npos) << m;
  rule.requireEveryLabel = false;
  EXPECT_NO_THROW(applyLabels(v, rule));
  // Without a rule, values above 255 are refused.
  m = message([&] { applyLabels(v, LabelRule{}); });
  EXPECT_NE(m.find("is not a label 0..255"), std::string::npos) << m;
  // Threshold of a float image: 0.1, 0.35, 0.6 -> below 0.5 -> 0.
  const RawVolume f = makeVolume(VoxelType::Float32, {6, 6, 2}, 9);
  LabelRule t;
  t.threshold = true;
  t.level = 0.5;
  t.below = 1;
  t.above = 0;
  const VoxelImage ti = applyLabels(f, t);
  for (Index i = 0; i < f.voxelCount(); ++i)
    EXPECT_EQ(ti.values()[static_cast<size_t>(i)], f.value(i) < 0.5 ? 1 : 0);
  t.level = 10.0;
  m = message([&] { applyLabels(f, t); });
  EXPECT_NE(m.find("no value lies at or above the threshold 10"), std::string::npos) << m;
}

TEST(ImageIo, FuzzedFilesGiveErrorsNotCrashes) {
  std::mt19937 rng(2024);
  int refused = 0, read = 0;
  for (const std::string fmt : {"mhd", "nhdr", "tiff", "vti", "hdf5", "raw"}) {
    const RawVolume v = makeVolume(VoxelType::UInt16, {6, 5, 4}, 1);
    const std::string ext = fmt == "tiff" ? "tif" : fmt == "hdf5" ? "h5" : fmt;
    const std::string path = scratch("fuzz." + ext);
    const std::string data = fmt == "mhd" || fmt == "nhdr" ? scratch("fuzz.raw") : path;
    for (int trial = 0; trial < 40; ++trial) {
      writeVolume(v, path, fmt);
      // Truncate or corrupt the header / data file at random.
      const std::string target = trial % 2 || data == path ? path : data;
      std::string bytes;
      {
        std::ifstream in(target, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
      }
      if (trial % 3 == 0) {
        bytes.resize(rng() % (bytes.size() + 1));
      } else {
        for (int k = 0; k < 1 + trial % 5; ++k)
          bytes[rng() % bytes.size()] = static_cast<char>(rng() & 255);
      }
      std::ofstream(target, std::ios::binary | std::ios::trunc) << bytes;
      ImageFileSpec s;
      s.path = path;
      if (fmt == "raw") {
        s.shape = v.n;
        s.type = VoxelType::UInt16;
      }
      try {
        const RawVolume r = readVolume(s);
        // What is read must be self-consistent.
        EXPECT_EQ(static_cast<Index>(r.bytes.size()), r.voxelCount() * voxelTypeBytes(r.type));
        ++read;
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("tmp_test_image_io"), std::string::npos) << e.what();
        ++refused;
      }
    }
  }
  EXPECT_GT(refused, 60);
  EXPECT_GT(read, 10);
}

TEST(ImageIo, TiffFolderStack) {
  const RawVolume v = makeVolume(VoxelType::UInt8, {5, 3, 4}, 2);
  const std::string dir = scratch("stack");
  fs::create_directories(dir);
  for (int z = 0; z < 4; ++z) {
    RawVolume page;
    page.n = {5, 3, 1};
    page.type = VoxelType::UInt8;
    page.bytes.assign(v.bytes.begin() + z * 15, v.bytes.begin() + (z + 1) * 15);
    writeVolume(page, dir + "/slice_00" + std::to_string(z) + ".tif", "tiff");
  }
  ImageFileSpec s;
  s.path = dir;
  const RawVolume r = readVolume(s);
  EXPECT_EQ(r.n, v.n);
  EXPECT_TRUE(r.bytes == v.bytes);
}

TEST(ImageOps, CoarsenMajorityAndSlices) {
  VoxelImage img(4, 4, 2, 1);
  // Block (0,0): five 0s, three 1s -> 0. Block (1,0): four 2s and four 1s -> tie -> 1.
  for (int k = 0; k < 5; ++k) img.at(k % 2, (k / 2) % 2, k / 4) = 0;
  for (int k = 0; k < 4; ++k) img.at(2 + k % 2, k / 2, 0) = 2;
  const VoxelImage c = coarsenImage(img, 2);
  EXPECT_EQ(c.nx(), 2);
  EXPECT_EQ(c.nz(), 1);
  EXPECT_EQ(c.at(0, 0, 0), 0);
  EXPECT_EQ(c.at(1, 0, 0), 1);
  EXPECT_NE(message([&] { coarsenImage(img, 3); }).find("crop it to a multiple of 3"), std::string::npos);
  // Slices.
  VoxelImage g(3, 4, 5);
  for (int z = 0; z < 5; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 3; ++x) g.at(x, y, z) = static_cast<std::uint8_t>(x + 10 * y + 50 * z);
  const VoxelImage sx = sliceImage(g, 0, 2), sy = sliceImage(g, 1, 1), sz = sliceImage(g, 2, 4);
  EXPECT_EQ(sx.nx(), 4);
  EXPECT_EQ(sx.ny(), 5);
  EXPECT_EQ(sx.at(3, 4, 0), 2 + 30 + 200);
  EXPECT_EQ(sy.nx(), 3);
  EXPECT_EQ(sy.ny(), 5);
  EXPECT_EQ(sy.at(2, 3, 0), 2 + 10 + 150);
  EXPECT_EQ(sz.at(1, 2, 0), 1 + 20 + 200);
  EXPECT_NE(message([&] { sliceImage(g, 2, 5); }).find("outside the image"), std::string::npos);
  // A 2D image coarsens in x and y only.
  EXPECT_EQ(coarsenImage(sliceImage(g, 2, 0), 1).nz(), 1);
}

TEST(ImageOps, DistanceTransformEqualsBruteForce) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 12; ++trial) {
    const int nx = 3 + static_cast<int>(rng() % 12), ny = 1 + static_cast<int>(rng() % 10),
              nz = 1 + static_cast<int>(rng() % 8);
    VoxelImage img(nx, ny, nz);
    const double solid = trial % 3 == 0 ? 0.02 : 0.3;
    for (Index i = 0; i < img.voxelCount(); ++i)
      img.data()[i] = (rng() % 1000) < solid * 1000 ? 1 : 0;
    const auto d2 = squaredDistanceToSolid(img, 0);
    for (int z = 0; z < nz; ++z)
      for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x) {
          std::int64_t best = -1;
          for (int c = 0; c < nz; ++c)
            for (int b = 0; b < ny; ++b)
              for (int a = 0; a < nx; ++a)
                if (img.at(a, b, c) != 0) {
                  const std::int64_t d = (a - x) * (a - x) + (b - y) * (b - y) + (c - z) * (c - z);
                  if (best < 0 || d < best) best = d;
                }
          const std::uint32_t want = best < 0 ? kNoSolid : static_cast<std::uint32_t>(best);
          ASSERT_EQ(d2[static_cast<size_t>(img.linear(x, y, z))], want)
              << "trial " << trial << " at " << x << "," << y << "," << z;
        }
  }
}

TEST(ImageOps, SyntheticClayIsSeededAndHitsItsFractions) {
  SynthClayOptions o;
  o.n = {24, 20, 16};
  o.porosity = 0.2;
  o.inclusionFraction = 0.1;
  const VoxelImage a = synthClay(o), b = synthClay(o);
  EXPECT_TRUE(a.values() == b.values());
  Index count[3] = {0, 0, 0};
  for (auto v : a.values()) ++count[v];
  const double n = static_cast<double>(a.voxelCount());
  EXPECT_EQ(count[0], std::llround(0.2 * n));
  EXPECT_EQ(count[2], std::llround(0.1 * n));
  o.seed = 2;
  EXPECT_FALSE(synthClay(o).values() == a.values());
  o.porosity = 0.95;
  EXPECT_NE(message([&] { synthClay(o); }).find("sum below 1"), std::string::npos);
}

TEST(ImageOps, LabelledVtiHoldsLabelsClustersAndRadii) {
  VoxelImage img(6, 5, 4, 1);
  for (int z = 0; z < 4; ++z)
    for (int x = 1; x < 5; ++x) img.at(x, 2, z) = 0;  // a pore channel
  img.at(0, 0, 0) = 0;                                // an isolated pore voxel
  Index count = 0;
  const auto labels = labelPoreClusters(img, 0, &count, 6);
  std::vector<float> radius(labels.size(), 0.5f);
  const std::string path = scratch("labelled.vti");
  writeLabelledVti(path, img, 1e-6, {{"cluster_6", &labels, nullptr}, {"pore_radius", nullptr, &radius}});
  for (const std::string name : {"label", "cluster_6", "pore_radius"}) {
    ImageFileSpec s;
    s.path = path;
    s.dataset = name;
    const RawVolume v = readVolume(s);
    ASSERT_EQ(v.n, (std::array<int, 3>{6, 5, 4})) << name;
    EXPECT_NEAR(v.spacing[0], 1e-6, 1e-18);
    for (Index i = 0; i < v.voxelCount(); ++i) {
      const double want = name == "label" ? img.values()[static_cast<size_t>(i)]
                          : name == "cluster_6" ? labels[static_cast<size_t>(i)] : 0.5;
      ASSERT_EQ(v.value(i), want) << name << " voxel " << i;
    }
  }
  EXPECT_EQ(count, 2);
  // Without a name the three arrays are ambiguous: the message lists them.
  ImageFileSpec s;
  s.path = path;
  EXPECT_NE(message([&] { readVolume(s); }).find("holds several arrays (label (cells), cluster_6 (cells), pore_radius (cells))"),
            std::string::npos);
}
