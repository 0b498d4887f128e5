// Scenes from images (geometry shape `image`): one particle per (coarsened) voxel at the voxel's
// centre with the material its label maps to, for 2D slices and 3D crops; the refusals (a value
// without a label, a voxel size that disagrees with the spacing, a 3D image in a 2D scene, an
// origin off the lattice, an empty phase).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>

#include "libcore/image_io.hpp"
#include "libcore/scene.hpp"

using namespace poresph;
namespace fs = std::filesystem;

namespace {

std::string dir() {
  const fs::path d = fs::path(PORESPH_BINARY_DIR) / "tmp_test_image_scene" / std::to_string(getpid());
  fs::create_directories(d);
  return d.string();
}

/// A 6 x 5 x 4 uint16 image with values 7 (pore), 300 (clay), 9000 (inclusion) at random.
RawVolume image(unsigned seed = 3) {
  RawVolume v;
  v.n = {6, 5, 4};
  v.type = VoxelType::UInt16;
  v.bytes.resize(120 * 2);
  std::mt19937 rng(seed);
  const std::uint16_t values[3] = {7, 300, 9000};
  for (int i = 0; i < 120; ++i) {
    const std::uint16_t x = values[rng() % 3];
    std::memcpy(&v.bytes[static_cast<size_t>(i) * 2], &x, 2);
  }
  return v;
}

const char* kMaterials = R"(
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 10, viscosity: 1.0e-3}
  - {name: clay, model: elastic, density: 2000, young_modulus: 1.0e6, poisson_ratio: 0.25}
  - {name: grain, model: elastic, density: 2500, young_modulus: 1.0e7, poisson_ratio: 0.25}
)";

std::string scene(int dim, const std::string& geometry, double spacing = 0.1) {
  std::ostringstream s;
  s << "dimension: " << dim << "\n";
  if (dim == 3) s << "domain: {lo: [0, 0, 0], hi: [1, 1, 1]}\n";
  else s << "domain: {lo: [0, 0], hi: [1, 1]}\n";
  s << "spacing: " << spacing << "\nend_time: 1.0e-6\ntime_step: {adaptive: true}\noutput: {every_steps: 1}\n"
    << kMaterials << "geometry:\n" << geometry;
  return s.str();
}

Scene load(const std::string& text) {
  SceneOptions o;
  o.initialise = false;
  return loadSceneText(text, dir() + "/scene.yaml", o);
}

std::string error(const std::string& text) {
  try {
    load(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(ImageScene, OneParticlePerVoxelWithItsMaterial3D) {
  const RawVolume v = image();
  writeVolume(v, dir() + "/img.tif", "tiff");
  const Scene s = load(scene(3, R"(
  - {shape: box, lo: [0, 0, 0], hi: [1, 1, 1], material: water}
  - shape: image
    file: img.tif
    labels: {7: none, 300: clay, 9000: grain}
    crop: {lo: [1, 0, 0], size: [4, 5, 4]}
    origin: [0.2, 0.3, 0.1]
    voxel_size: 0.1
)"));
  const ParticleStore& st = s.sim->store;
  const double* x = st.data(st.position());
  const std::int32_t* mat = st.data(st.material());
  // Every particle inside the image box is a clay or grain voxel; pores (none) are empty; the
  // water box remains outside the image box only.
  std::map<std::array<long, 3>, int> at;
  for (Index i = 0; i < st.realCount(); ++i) {
    std::array<long, 3> k;
    for (int a = 0; a < 3; ++a) k[static_cast<size_t>(a)] = std::lround(x[i * 3 + a] / 0.1 - 0.5);
    at[k] = mat[i];
  }
  Index clay = 0, grain = 0;
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 5; ++y)
      for (int xx = 0; xx < 4; ++xx) {
        const double value = v.value((z * 5 + y) * 6 + xx + 1);
        const std::array<long, 3> k{xx + 2, y + 3, z + 1};
        if (value == 7) {
          EXPECT_EQ(at.count(k), 0u);
        } else {
          ASSERT_EQ(at.count(k), 1u);
          EXPECT_EQ(at[k], value == 300 ? 1 : 2);
          (value == 300 ? clay : grain)++;
        }
      }
  EXPECT_EQ(s.particlesPerMaterial[1], clay);
  EXPECT_EQ(s.particlesPerMaterial[2], grain);
  EXPECT_EQ(s.particlesPerMaterial[0], 1000 - 4 * 5 * 4);
}

TEST(ImageScene, SliceAndCoarsenIn2D) {
  RawVolume v = image(5);
  writeVolume(v, dir() + "/img.h5", "hdf5", "phases");
  const Scene s = load(scene(2, R"(
  - shape: image
    file: img.h5
    dataset: phases
    labels: {7: water, 300: clay, 9000: clay}
    slice: {axis: x, index: 2}
    allow_empty_labels: true
)", 0.1));
  // Slice normal to x: (y, z) = 5 x 4 voxels, all particles.
  EXPECT_EQ(s.sim->store.realCount(), 20);
  Index water = 0;
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 5; ++y) water += v.value((z * 5 + y) * 6 + 2) == 7;
  EXPECT_EQ(s.particlesPerMaterial[0], water);
  // 2 x coarsening of a 4 x 4 crop: 2 x 2 particles at spacing 0.2.
  const Scene c = load(scene(2, R"(
  - shape: image
    file: img.h5
    labels: {7: water, 300: clay, 9000: grain}
    allow_empty_labels: true
    crop: {lo: [0, 0, 0], size: [4, 4, 1]}
    coarsen: 2
    voxel_size: 0.1
)", 0.2));
  EXPECT_EQ(c.sim->store.realCount(), 4);
}

TEST(ImageScene, Refusals) {
  writeVolume(image(), dir() + "/img.raw", "raw");
  const std::string raw = "  - shape: image\n    file: img.raw\n    size: [6, 5, 4]\n    voxel_type: uint16\n";
  std::string m = error(scene(3, raw + "    labels: {7: water, 300: clay}\n"));
  EXPECT_NE(m.find("scene.yaml:"), std::string::npos) << m;
  EXPECT_NE(m.find("value 9000 ("), std::string::npos) << m;
  EXPECT_NE(m.find("has no entry in the label map"), std::string::npos) << m;
  m = error(scene(3, raw + "    labels: {7: water, 300: clay, 9000: grain}\n    voxel_size: 0.05\n"));
  EXPECT_NE(m.find("voxel_size"), std::string::npos) << m;
  EXPECT_NE(m.find("must equal the scene's spacing 0.1"), std::string::npos) << m;
  m = error(scene(2, raw + "    labels: {7: water, 300: clay, 9000: grain}\n"));
  EXPECT_NE(m.find("a 2D scene needs a 2D image"), std::string::npos) << m;
  m = error(scene(3, raw + "    labels: {7: water, 300: clay, 9000: grain}\n    origin: [0.05, 0, 0]\n"));
  EXPECT_NE(m.find("must lie on the lattice"), std::string::npos) << m;
  m = error(scene(3, raw + "    labels: {7: water, 300: clay, 9000: grain, 5: clay}\n"));
  EXPECT_NE(m.find("value 5 (label"), std::string::npos) << m;
  m = error(scene(3, raw + "    labels: {7: water, 300: clay, 9000: sand}\n"));
  EXPECT_NE(m.find("no material named 'sand'"), std::string::npos) << m;
  m = error(scene(3, "  - shape: image\n    file: img.raw\n    size: [6, 5, 5]\n    voxel_type: uint16\n"
                      "    labels: {7: water, 300: clay, 9000: grain}\n"));
  EXPECT_NE(m.find("size 240 bytes does not match the shape 6 x 5 x 5"), std::string::npos) << m;
  m = error(scene(3, raw + "    labels: {7: water, 300: clay, 9000: grain}\n    coarsen: 4\n"));
  EXPECT_NE(m.find("crop it to a multiple of 4"), std::string::npos) << m;
  m = error(scene(3, raw + "    threshold: {level: 100, below: water, above: clay}\n    labels: {7: water}\n"));
  EXPECT_NE(m.find("not both"), std::string::npos) << m;
}

TEST(ImageScene, ShippedKettonSlice) {
  // The shipped sample: its particle counts equal numpy's count of the same slice and 2 x 2
  // majority with ties to the pore (395 pore blocks of 4096).
  SceneOptions o;
  o.initialise = false;
  const Scene s =
      loadScene(std::string(PORESPH_SOURCE_DIR) + "/samples/image_ketton_2d.yaml", o);
  EXPECT_EQ(s.particlesPerMaterial[0], 395);
  EXPECT_EQ(s.particlesPerMaterial[1], 3701);
}
