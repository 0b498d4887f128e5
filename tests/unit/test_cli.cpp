// The poresph command line, run as a program (the built binary in PORESPH_BINARY_DIR):
// --version, refusing a non-empty output directory, bad input -> exit code 2 with the file and
// key named, and an end-to-end run of a small fluid scene (files written, parameters echoed).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace {

const fs::path kBinary = fs::path(PORESPH_BINARY_DIR) / "poresph";

fs::path tmpDir() {
  const fs::path d = fs::path(PORESPH_BINARY_DIR) / "tmp_test_cli";
  fs::create_directories(d);
  return d;
}

struct Result {
  int code = -1;
  std::string output;  // stdout and stderr together
};

Result runPoresph(const std::string& args) {
  // One log per process and call: ctest runs the tests of this file in parallel processes.
  static int calls = 0;
  const fs::path log =
      tmpDir() / ("output_" + std::to_string(getpid()) + "_" + std::to_string(++calls) + ".txt");
  const std::string cmd = "\"" + kBinary.string() + "\" " + args + " > \"" + log.string() + "\" 2>&1";
  const int status = std::system(cmd.c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(log);
  std::ostringstream s;
  s << in.rdbuf();
  r.output = s.str();
  fs::remove(log);
  return r;
}

std::string readFile(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A 2D box of water at rest, 10 x 10 particles in a periodic box, 20 steps.
const char* kScene = R"(dimension: 2
domain:
  lo: [0, 0]
  hi: [0.01, 0.01]
  periodic: [true, true]
spacing: 0.001
end_time: 2.0e-4
time_step:
  dt: 1.0e-5
output:
  every_steps: 10
materials:
  - name: water
    model: fluid
    density: 1000
    sound_speed: 10
    viscosity: 1.0e-3
geometry:
  - shape: box
    lo: [0, 0]
    hi: [0.01, 0.01]
    material: water
)";

fs::path writeScene(const std::string& name, const std::string& text) {
  const fs::path p = tmpDir() / name;
  std::ofstream(p) << text;
  return p;
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(kBinary)) << kBinary << " is not built (ninja poresph)";
  }
};

}  // namespace

TEST_F(Cli, VersionAndHelp) {
  Result r = runPoresph("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.output.find(PORESPH_VERSION), std::string::npos) << r.output;
  r = runPoresph("--help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.output.find("run"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("info"), std::string::npos) << r.output;
  r = runPoresph("--no-such-option");
  EXPECT_EQ(r.code, 2) << r.output;
}

TEST_F(Cli, RefusesNonEmptyOutputDirectory) {
  const fs::path scene = writeScene("refuse.yaml", kScene);
  const fs::path out = tmpDir() / "refuse_out";
  fs::remove_all(out);
  fs::create_directories(out);
  std::ofstream(out / "precious.txt") << "keep me";
  const Result r = runPoresph("run \"" + scene.string() + "\" --out \"" + out.string() + "\" -t 1");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("not empty"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(out.string()), std::string::npos) << r.output;
  // Nothing was written into it.
  long n = 0;
  for (const auto& e : fs::directory_iterator(out)) n += e.is_regular_file() || e.is_directory();
  EXPECT_EQ(n, 1);
  EXPECT_EQ(readFile(out / "precious.txt"), "keep me");
}

TEST_F(Cli, BadSceneExitsWithCode2NamingFileKeyAndValue) {
  std::string text = kScene;
  text.replace(text.find("sound_speed: 10"), 15, "sound_speed: -10");
  const fs::path scene = writeScene("bad_sound_speed.yaml", text);
  Result r = runPoresph("info \"" + scene.string() + "\"");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("bad_sound_speed.yaml:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("sound_speed"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("-10"), std::string::npos) << r.output;

  const fs::path missing = tmpDir() / "no_such_scene.yaml";
  const fs::path out = tmpDir() / "missing_out";
  fs::remove_all(out);
  r = runPoresph("run \"" + missing.string() + "\" --out \"" + out.string() + "\"");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find(missing.string()), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out)) << "a bad scene must not create the output directory";
}

TEST_F(Cli, InfoDescribesTheScene) {
  const fs::path scene = writeScene("info.yaml", kScene);
  const Result r = runPoresph("info \"" + scene.string() + "\" --threads 1");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("dimension:    2"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("particles:    100"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("water"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("fluid"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bytes/particle"), std::string::npos) << r.output;
  // Cubic spline, h = 1.3 dx: 20 lattice neighbours; a full periodic lattice measures 20 too.
  EXPECT_NE(r.output.find("~20 per interior particle"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("measured mean 20"), std::string::npos) << r.output;
}

TEST_F(Cli, RunsASceneEndToEnd) {
  const fs::path scene = writeScene("box_at_rest.yaml", kScene);
  const fs::path out = tmpDir() / "run_out";
  fs::remove_all(out);
  Result r = runPoresph("run \"" + scene.string() + "\" --out \"" + out.string() + "\" --threads 1");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "box_at_rest.yaml"));
  EXPECT_TRUE(fs::exists(out / "results.pvd"));
  EXPECT_TRUE(fs::exists(out / "timeseries.csv"));
  EXPECT_TRUE(fs::exists(out / "checkpoint.h5"));
  EXPECT_TRUE(fs::exists(out / "snapshots" / "step_00000000.vtu"));
  EXPECT_TRUE(fs::exists(out / "snapshots" / "step_00000010.vtu"));
  EXPECT_TRUE(fs::exists(out / "snapshots" / "step_00000020.vtu"));
  EXPECT_FALSE(fs::exists(out / "snapshots" / "step_00000021.vtu"));
  // Every value used, defaults included, is echoed.
  const std::string echo = readFile(out / "run.yaml");
  EXPECT_NE(echo.find("h_over_dx: 1.3"), std::string::npos) << echo;
  EXPECT_NE(echo.find("integrator: leapfrog"), std::string::npos) << echo;
  EXPECT_NE(echo.find("sound_speed: 10"), std::string::npos) << echo;
  // timeseries: header + rows at steps 0, 10, 20.
  std::ifstream ts(out / "timeseries.csv");
  std::string line;
  long rows = 0;
  while (std::getline(ts, line))
    if (!line.empty()) ++rows;
  EXPECT_EQ(rows, 4);
  EXPECT_NE(readFile(out / "run.log").find("status: finished"), std::string::npos);

  // A second run into the same directory is refused, then accepted with --force.
  r = runPoresph("run \"" + scene.string() + "\" --out \"" + out.string() + "\" -t 1");
  EXPECT_EQ(r.code, 2) << r.output;
  r = runPoresph("run \"" + scene.string() + "\" --out \"" + out.string() + "\" --force -t 1");
  EXPECT_EQ(r.code, 0) << r.output;
}

TEST_F(Cli, WithoutOutWritesANewFolderUnderRuns) {
  const fs::path dir = tmpDir() / "default_out";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scene = writeScene("default_out/short.yaml",
                                    std::string(kScene) + "max_steps: 2\n");
  const std::string cmd = "cd \"" + dir.string() + "\" && \"" + kBinary.string() +
                          "\" run short.yaml -t 1 > log.txt 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << readFile(dir / "log.txt");
  long runs = 0;
  for (const auto& e : fs::directory_iterator(dir / "runs")) {
    ++runs;
    EXPECT_EQ(e.path().filename().string().rfind("short-", 0), 0u) << e.path();
    EXPECT_TRUE(fs::exists(e.path() / "checkpoint.h5"));
    EXPECT_TRUE(fs::exists(e.path() / "snapshots" / "step_00000002.vtu"));
  }
  EXPECT_EQ(runs, 1);
}

TEST_F(Cli, NumericalBlowUpExitsWithCode3AndWritesTheLastGoodState) {
  // Two water blocks colliding at 5 times the sound speed (Mach 5 in a weakly compressible
  // model, far outside its validity): the density becomes non-finite within a few hundred steps.
  const char* text = R"(dimension: 2
domain: {lo: [0, 0], hi: [0.02, 0.01], periodic: [true, true]}
spacing: 0.001
end_time: 0.01
time_step: {dt: 5.0e-6}
output: {every_steps: 100}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 10, viscosity: 1.0e-6}
geometry:
  - {shape: box, lo: [0, 0], hi: [0.01, 0.01], material: water, velocity: [50, 0]}
  - {shape: box, lo: [0.01, 0], hi: [0.02, 0.01], material: water, velocity: [-50, 0]}
)";
  const fs::path scene = writeScene("blowup.yaml", text);
  const fs::path out = tmpDir() / "blowup_out";
  fs::remove_all(out);
  const Result r = runPoresph("run \"" + scene.string() + "\" --out \"" + out.string() + "\" -t 1");
  EXPECT_EQ(r.code, 3) << r.output;
  EXPECT_NE(r.output.find("numerical failure"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("is not finite"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("last good state"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(out / "checkpoint.h5"));
  EXPECT_NE(readFile(out / "run.log").find("status: numerical failure"), std::string::npos);
}
