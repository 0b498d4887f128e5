// `poresph sweep` run as a program: one folder per case, a failing case reported while the others
// run, the summary table, the refusal to overwrite a study, and the post-processing scripts
// (scripts/plot_timeseries.py, scripts/render_views.py, scripts/profile_along_axis.py) on the study's output: their PNGs exist
// and are not blank. The scripts need /usr/bin/python3 with vtk and matplotlib
// (scripts/install-deps.sh); without them that part is skipped with a message.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace std::string_literals;
namespace fs = std::filesystem;

namespace {

struct Result {
  int code = -1;
  std::string output;
};

Result shell(const std::string& cmd) {
  const fs::path log = fs::path(PORESPH_BINARY_DIR) / ("tmp_test_sweep_" + std::to_string(getpid()) + ".log");
  const int status = std::system((cmd + " > \"" + log.string() + "\" 2>&1").c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ostringstream s;
  s << std::ifstream(log).rdbuf();
  r.output = s.str();
  fs::remove(log);
  return r;
}

std::string slurp(const fs::path& p) {
  std::ostringstream s;
  s << std::ifstream(p).rdbuf();
  return s.str();
}

const std::string kBinary = "\""s + PORESPH_BINARY_DIR + "/poresph\"";
const std::string kScene = "\""s + PORESPH_SOURCE_DIR + "/samples/image_synth_clay_2d.yaml\"";

/// Whether every PNG of `paths` exists and is not blank (standard deviation of its pixels > 0.02,
/// read with matplotlib); the output names the blank or missing ones.
Result notBlank(const std::vector<fs::path>& paths) {
  std::string cmd = "/usr/bin/python3 -c \"import matplotlib.image as m, sys, os\n"
                    "bad = [p for p in sys.argv[1:] if not os.path.exists(p) or m.imread(p)[..., :3].std() <= 0.02]\n"
                    "print('blank or missing:', bad)\nsys.exit(1 if bad else 0)\"";
  for (const auto& p : paths) cmd += " \"" + p.string() + "\"";
  return shell(cmd);
}

}  // namespace

TEST(Sweep, CasesSummaryFailuresAndScripts) {
  const fs::path out = fs::path(PORESPH_BINARY_DIR) / ("tmp_test_sweep_" + std::to_string(getpid()));
  fs::remove_all(out);
  const std::string cmd = kBinary + " sweep " + kScene +
                          " --set materials.clay.poisson_ratio=0.3,0.7 --set end_time=2e-7 --threads 1 --out \"" +
                          out.string() + "\"";
  Result r = shell(cmd);
  // One case fails (poisson_ratio 0.7 is refused by the scene parser, naming the key); the other runs.
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("1 finished, 1 failed"), std::string::npos) << r.output;
  const std::string good = "case01_poisson_ratio=0.3_end_time=2e-7", bad = "case02_poisson_ratio=0.7_end_time=2e-7";
  EXPECT_TRUE(fs::exists(out / good / "run" / "timeseries.csv")) << r.output;
  EXPECT_TRUE(fs::exists(out / good / "scene.yaml"));
  EXPECT_FALSE(fs::exists(out / bad / "run" / "timeseries.csv"));
  const std::string csv = slurp(out / "summary.csv");
  EXPECT_NE(csv.find("case,materials.clay.poisson_ratio,end_time,status,time,step,kinetic_energy"), std::string::npos) << csv;
  EXPECT_NE(csv.find(good + ",0.3,2e-7,finished,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(bad + ",0.7,2e-7,bad scene:"), std::string::npos) << csv;
  EXPECT_NE(csv.find("materials[1].poisson_ratio"), std::string::npos) << csv;  // the key is named
  EXPECT_NE(slurp(out / "summary.md").find("| " + good + " | 0.3 | 2e-7 | finished |"), std::string::npos);

  // A study folder is never overwritten without --overwrite.
  r = shell(cmd);
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("pass --overwrite"), std::string::npos) << r.output;
  // A key path that does not exist in a list is named.
  r = shell(kBinary + " sweep " + kScene + " --set materials.sand.density=1,2 --out \"" + out.string() + "_b\"");
  EXPECT_NE(r.output.find("no element named 'sand' (names: water, clay, inclusion)"), std::string::npos) << r.output;
  fs::remove_all(out.string() + "_b");

  // ---- the post-processing scripts on the study's output ----
  if (shell("/usr/bin/python3 -c \"import vtk, matplotlib\"").code != 0) {
    GTEST_SKIP() << "/usr/bin/python3 lacks vtk or matplotlib (scripts/install-deps.sh installs "
                    "python3-vtk9 and python3-matplotlib): the scripts were not run";
  }
  const std::string scripts = "\""s + PORESPH_SOURCE_DIR + "/scripts/";
  r = shell("/usr/bin/python3 " + scripts + "plot_timeseries.py\" \"" + (out / good / "run" / "timeseries.csv").string() +
            "\" --columns kinetic_energy,solid_elastic_energy --out \"" + (out / "ts.png").string() + "\"");
  EXPECT_EQ(r.code, 0) << r.output;
  r = shell("/usr/bin/python3 " + scripts + "plot_timeseries.py\" \"" + (out / good / "run" / "timeseries.csv").string() +
            "\" --columns no_such_column --out \"" + (out / "x.png").string() + "\"");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("no_such_column"), std::string::npos) << r.output;
  r = shell("/usr/bin/python3 " + scripts + "render_views.py\" \"" + (out / good / "run").string() +
            "\" --fields phase,pressure,max_principal_stress --out \"" + (out / "views").string() + "\"");
  EXPECT_EQ(r.code, 0) << r.output;
  // scripts/profile_along_axis.py: per-layer fluid counts (the layer from run.yaml's spacing); the
  // CSV's counts of the first snapshot add up to the fluid particles inside the solid's range.
  r = shell("/usr/bin/python3 " + scripts + "profile_along_axis.py\" \"" + (out / good / "run").string() +
            "\" --axis y --csv \"" + (out / "profile.csv").string() + "\"");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("layers 48 from y = 0"), std::string::npos) << r.output;
  {
    std::istringstream csv(slurp(out / "profile.csv"));
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line, "snapshot,quantity,layer,count");
    long total = 0;
    int rows = 0;
    while (std::getline(csv, line)) {
      if (line.rfind("step_00000000.vtu,material", 0) != 0) continue;
      total += std::stol(line.substr(line.rfind(',') + 1));
      ++rows;
    }
    EXPECT_EQ(rows, 48);
    EXPECT_GT(total, 300);
  }
  r = shell("/usr/bin/python3 " + scripts + "profile_along_axis.py\" \"" + out.string() + "\"");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("no snapshots"), std::string::npos) << r.output;
  std::vector<fs::path> pngs = {out / "summary.png", out / "ts.png"};
  for (const char* png : {"phases.png", "phase_xy.png", "pressure_xy.png", "max_principal_stress_xy.png"})
    pngs.push_back(out / "views" / png);
  r = notBlank(pngs);
  EXPECT_EQ(r.code, 0) << r.output;
  fs::remove_all(out);
}

// Linked keys (`--set a+b=v1,v2`): each case writes its one value to every key joined by '+', as a
// drainage sweep sets both confining plates; an empty key in the link is refused before any run.
TEST(Sweep, LinkedKeysTakeOneValuePerCase) {
  const fs::path out = fs::path(PORESPH_BINARY_DIR) / ("tmp_test_sweep_linked_" + std::to_string(getpid()));
  fs::remove_all(out);
  Result r = shell(kBinary + " sweep " + kScene +
                   " --set materials.clay.density+materials.inclusion.density=2100,2200 --set end_time=2e-7"
                   " --threads 1 --no-plot --out \"" + out.string() + "\"");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("2 finished, 0 failed"), std::string::npos) << r.output;
  for (const std::string v : {"2100", "2200"}) {
    const fs::path scene = out / ("case0"s + (v == "2100" ? "1" : "2") + "_density=" + v + "_end_time=2e-7") / "scene.yaml";
    const std::string text = slurp(scene);
    size_t n = 0;
    for (size_t at = text.find("density: " + v); at != std::string::npos; at = text.find("density: " + v, at + 1)) ++n;
    EXPECT_EQ(n, 2u) << scene << ":\n" << text;  // clay and inclusion, nothing else
    EXPECT_EQ(text.find("density: 2000"), std::string::npos) << text;
    EXPECT_EQ(text.find("density: 2650"), std::string::npos) << text;
  }
  EXPECT_NE(slurp(out / "summary.csv").find("case,materials.clay.density+materials.inclusion.density,end_time,status"),
            std::string::npos);
  r = shell(kBinary + " sweep " + kScene + " --set materials.clay.density+=1,2 --out \"" + out.string() + "_c\"");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("an empty key path"), std::string::npos) << r.output;
  fs::remove_all(out);
  fs::remove_all(out.string() + "_c");
}
