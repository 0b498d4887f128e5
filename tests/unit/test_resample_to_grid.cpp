// scripts/resample_to_grid.py (issue 16 "Outputs": phase and damage resampled on the image grid
// for volume rendering): the README's main job scene after one step, resampled by reference
// position at the image's voxel size, must give back the image: one particle per cell, and the
// solid cells exactly the clay voxels of the crop of data/ketton_128.raw (counted here from the
// raw file, independently of the scene code). A missing --spacing is refused.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "libcore/runner.hpp"
#include "libcore/scene.hpp"

using namespace poresph;
namespace fs = std::filesystem;

namespace {
int shell(const std::string& cmd, std::string* out = nullptr) {
  const fs::path log = fs::path(PORESPH_BINARY_DIR) / ("tmp_resample_" + std::to_string(getpid()) + ".log");
  const int status = std::system((cmd + " > \"" + log.string() + "\" 2>&1").c_str());
  if (out) {
    std::ostringstream s;
    s << std::ifstream(log).rdbuf();
    *out = s.str();
  }
  fs::remove(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
}  // namespace

TEST(ResampleToGrid, ReferenceGridOfTheMainJobIsItsImage) {
  if (shell("/usr/bin/python3 -c \"import vtk, numpy\"") != 0)
    GTEST_SKIP() << "/usr/bin/python3 lacks vtk or numpy (scripts/install-deps.sh installs them)";
  const std::string src = PORESPH_SOURCE_DIR;
  std::ifstream in(src + "/samples/drainage_ketton_3d.yaml");
  std::stringstream buf;
  buf << in.rdbuf();
  std::string text = buf.str();
  const size_t e = text.find("end_time: 0.0095");
  ASSERT_NE(e, std::string::npos);
  text.replace(e, 16, "end_time: 0.0095\nmax_steps: 1");
  const fs::path dir = fs::path(PORESPH_BINARY_DIR) / "test-resample";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // The scene's image path is relative to the scene file: keep the file in samples/'s place.
  Scene scene = loadSceneText(text, src + "/samples/resample_test.yaml");
  RunOptions o;
  o.handleSignals = false;
  o.outDir = (dir / "run").string();
  ASSERT_EQ(runScene(scene, o).status, RunStatus::Finished);
  std::string snapshot;
  for (const auto& f : fs::directory_iterator(dir / "run" / "snapshots"))
    if (f.path().extension() == ".vtu") snapshot = std::max(snapshot, f.path().string());
  ASSERT_FALSE(snapshot.empty());
  const std::string vti = (dir / "grid.vti").string();
  std::string out;
  ASSERT_EQ(shell("/usr/bin/python3 \"" + src + "/scripts/resample_to_grid.py\" \"" + snapshot +
                      "\" \"" + vti + "\" --spacing 1e-4 --by reference", &out),
            0)
      << out;
  // Count in the grid, and count the clay voxels (255) of the crop in the raw image.
  const std::string check =
      "import vtk, numpy as np\n"
      "from vtk.util.numpy_support import vtk_to_numpy\n"
      "r = vtk.vtkXMLImageDataReader(); r.SetFileName('" + vti + "'); r.Update(); g = r.GetOutput()\n"
      "ph = vtk_to_numpy(g.GetCellData().GetArray('phase'))\n"
      "occ = vtk_to_numpy(g.GetCellData().GetArray('particles_in_cell'))\n"
      "img = np.fromfile('" + src + "/data/ketton_128.raw', dtype=np.uint8).reshape(128, 128, 128)\n"
      "crop = img[48:64, 76:92, 112:128]\n"  // z, y, x order of the raw file (x fastest)
      "print(int(occ.max()), int((ph == 2).sum()), int((crop == 255).sum()))\n";
  std::ofstream(dir / "check.py") << check;
  ASSERT_EQ(shell("/usr/bin/python3 \"" + (dir / "check.py").string() + "\"", &out), 0) << out;
  int maxPerCell = 0, solidCells = 0, clayVoxels = 0;
  std::istringstream(out) >> maxPerCell >> solidCells >> clayVoxels;
  EXPECT_EQ(maxPerCell, 1) << out;
  EXPECT_GT(clayVoxels, 3000);
  EXPECT_EQ(solidCells, clayVoxels) << out;

  EXPECT_NE(shell("/usr/bin/python3 \"" + src + "/scripts/resample_to_grid.py\" \"" + snapshot +
                  "\" \"" + vti + "\""),
            0);
}
