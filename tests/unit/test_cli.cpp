// The poresph command line, run as a program (the built binary in PORESPH_BINARY_DIR):
// --version, refusing a non-empty output directory, bad input -> exit code 2 with the file and
// key named, and an end-to-end run of a small fluid scene (files written, parameters echoed).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

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
  // The full neighbour list (the default is a half list for fluid-only scenes, whose mean
  // counts each pair of real particles once: tests/unit/test_half_neighbour_list.cpp).
  const fs::path scene = writeScene("info.yaml", std::string(kScene) + "neighbour_list: full\n");
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
  // Two water blocks colliding at 2 x 8 m/s with c = 60 m/s: the water hammer compresses the
  // water by ~U/c = 27 %, far past the weakly compressible range; the density-variation health
  // check stops the run (exit 3) and the last state that passed every check is written. (A
  // sound speed below the collision speed is refused at load; a NaN blow-up is tested in
  // test_cli_runner.cpp.)
  const char* text = R"(dimension: 2
domain: {lo: [0, 0], hi: [0.02, 0.01], periodic: [true, true]}
spacing: 0.001
end_time: 0.01
time_step: {adaptive: true}
output: {every_steps: 100}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 60, viscosity: 1.0e-6}
geometry:
  - {shape: box, lo: [0, 0], hi: [0.01, 0.01], material: water, velocity: [8, 0]}
  - {shape: box, lo: [0.01, 0], hi: [0.02, 0.01], material: water, velocity: [-8, 0]}
)";
  const fs::path scene = writeScene("blowup.yaml", text);
  const fs::path out = tmpDir() / "blowup_out";
  fs::remove_all(out);
  const Result r = runPoresph("run \"" + scene.string() + "\" --out \"" + out.string() + "\" -t 1");
  EXPECT_EQ(r.code, 3) << r.output;
  EXPECT_NE(r.output.find("numerical failure"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("health check 'density_variation'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("last state that passed every check"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(out / "checkpoint.h5"));
  EXPECT_NE(readFile(out / "run.log").find("status: numerical failure"), std::string::npos);
}

// ---- issue 12: every bad input a clear error naming what is wrong, exit code 2 ----

TEST_F(Cli, ThreadsOutOfRangeNameTheOptionValueAndRange) {
  const fs::path scene = writeScene("threads.yaml", kScene);
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const std::string range = "from 1 to " + std::to_string(4 * cores);
  for (const std::string value : {"0", "-1", "10000", "two"}) {
    const Result r = runPoresph("info \"" + scene.string() + "\" --threads " + value);
    EXPECT_EQ(r.code, 2) << value << ": " << r.output;
    EXPECT_NE(r.output.find("--threads"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("got " + value), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(range), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("1797693134862"), std::string::npos) << "309-digit bound: " << r.output;
  }
  const Result r = runPoresph("run \"" + scene.string() + "\" -t 0 --out \"" +
                              (tmpDir() / "threads_out").string() + "\"");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find(range), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(tmpDir() / "threads_out"));
}

TEST_F(Cli, UnknownCommandIsNamedWithTheCommandsAndTheClosest) {
  const fs::path scene = writeScene("command.yaml", kScene);
  Result r = runPoresph("rn \"" + scene.string() + "\"");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("unknown command 'rn'; commands: run, info, image"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("did you mean 'run'?"), std::string::npos) << r.output;
  r = runPoresph("imgae x.raw --shape 1 1 1");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("did you mean 'image'?"), std::string::npos) << r.output;
  r = runPoresph("frobnicate");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("unknown command 'frobnicate'"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("did you mean"), std::string::npos) << r.output;
}

TEST_F(Cli, FilesThatAreNotScenesAreNamed) {
  const fs::path dir = tmpDir() / "scene_dir.yaml";
  fs::create_directories(dir);
  Result r = runPoresph("info \"" + dir.string() + "\"");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find(dir.string() + ": is a directory, not a scene file"), std::string::npos)
      << r.output;
  const std::pair<const char*, std::string> cases[] = {
      {"empty", ""},
      {"mapping", "- 1\n- 2\n"},
      {"mapping", "just some words\n"},
      {"not a text file", std::string("\x7f" "ELF\x02\x01\x01\0\0\0 garbage", 16)},
  };
  int k = 0;
  for (const auto& c : cases) {
    const fs::path p = writeScene("not_a_scene_" + std::to_string(k++) + ".yaml", c.second);
    r = runPoresph("info \"" + p.string() + "\"");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find(p.filename().string()), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(c.first), std::string::npos) << r.output;
  }
}

TEST_F(Cli, DuplicatedKeyIsBadInput) {
  std::string text = kScene;
  text.replace(text.find("  dt: 1.0e-5\n"), 13, "  dt: 1.0e-5\n  dt: 1.0e-3\n");
  const fs::path scene = writeScene("dup.yaml", text);
  const Result r = runPoresph("info \"" + scene.string() + "\"");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("dup.yaml:10: key 'time_step.dt' appears twice (lines 9 and 10)"),
            std::string::npos)
      << r.output;
}

TEST_F(Cli, InfoPrintsTheMemoryEstimateBeforeBuilding) {
  const fs::path small = writeScene("estimate.yaml", kScene);
  Result r = runPoresph("info \"" + small.string() + "\" -t 1");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto estimate = r.output.find("estimate:     a run needs about ");
  EXPECT_NE(estimate, std::string::npos) << r.output;
  EXPECT_LT(estimate, r.output.find("scene:")) << r.output;
  EXPECT_NE(r.output.find("100 particles x "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("particles:    100\n"), std::string::npos) << r.output;
}

TEST_F(Cli, HundredGigabyteSceneIsRefusedBeforeAllocation) {
  // 1 x 1 m at 5e-5 m: 4e8 water particles of ~340 bytes (fields twice + neighbour lists):
  // about 128 GiB.
  std::string text = kScene;
  auto replace = [&text](const std::string& from, const std::string& to) {
    const auto pos = text.find(from);
    ASSERT_NE(pos, std::string::npos) << from;
    text.replace(pos, from.size(), to);
  };
  replace("hi: [0.01, 0.01]\n  periodic: [true, true]", "hi: [1.0, 1.0]\n  periodic: [false, false]");
  replace("spacing: 0.001", "spacing: 5.0e-5");
  replace("    hi: [0.01, 0.01]", "    hi: [1.0, 1.0]");
  const fs::path scene = writeScene("hundred_gb.yaml", text);
  // info: the estimate, and whether it fits, without building anything; exit 0.
  auto t0 = std::chrono::steady_clock::now();
  Result r = runPoresph("info \"" + scene.string() + "\" -t 1");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.0);
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("400000000 particles x "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bytes per particle"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("400000000 (counted; not built)"), std::string::npos) << r.output;
  // run: refused with the numbers, within a second, nothing written.
  std::ifstream meminfo("/proc/meminfo");
  std::string line;
  unsigned long long availableKiB = 0;
  while (std::getline(meminfo, line))
    if (line.rfind("MemAvailable:", 0) == 0) availableKiB = std::stoull(line.substr(13));
  if (availableKiB == 0 || availableKiB > 100ULL * 1024 * 1024)
    GTEST_SKIP() << "MemAvailable unknown or above 100 GiB: the scene would fit here";
  EXPECT_NE(r.output.find("would not fit"), std::string::npos) << r.output;
  const fs::path out = tmpDir() / "hundred_gb_out";
  fs::remove_all(out);
  t0 = std::chrono::steady_clock::now();
  r = runPoresph("run \"" + scene.string() + "\" --out \"" + out.string() + "\" -t 1");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("hundred_gb.yaml:6: key 'spacing' = '5.0e-5'"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("400000000 particles x "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("available "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("does not fit"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--force"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
}
