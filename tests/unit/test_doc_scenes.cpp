// Every complete scene shown in docs/*.md runs: `poresph run` into a fresh folder, exit code 0,
// and the expectation its marker states holds at the end (issue 12, "runs that never lie").
//
// The rule (docs/reliability.md, "Scenes in the docs"): a ```yaml block whose first line is
//   # scene: NAME [expect: COLUMN < VALUE]
// is a complete scene. The test runs it to its end_time with the built binary and, when an
// expectation is given, reads the last row of timeseries.csv (docs/output.md) and checks
// COLUMN < VALUE there. A ```yaml block with a top-level `dimension:` key but no marker is an
// error, so that no complete scene in the docs escapes the test; fragments (a materials list, a
// module section) need no marker.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path kBinary = fs::path(PORESPH_BINARY_DIR) / "poresph";
constexpr double kTimeoutSeconds = 60.0;  // per scene; the docs' scenes take seconds

struct DocScene {
  std::string doc;      // docs/<page>.md
  int line = 0;         // line of the ```yaml fence
  std::string name;
  std::string column;   // expectation: last row's COLUMN < bound (empty: none)
  double bound = 0.0;
  std::string text;
};

std::vector<DocScene> docScenes(std::vector<std::string>& unmarked) {
  std::vector<fs::path> pages;
  for (const auto& e : fs::directory_iterator(fs::path(PORESPH_SOURCE_DIR) / "docs"))
    if (e.path().extension() == ".md") pages.push_back(e.path());
  std::sort(pages.begin(), pages.end());
  const std::regex marker(R"(^#\s*scene:\s*([A-Za-z0-9_.-]+)(\s+expect:\s*([A-Za-z0-9_]+)\s*<\s*(\S+))?\s*$)");
  std::vector<DocScene> scenes;
  for (const fs::path& page : pages) {
    std::ifstream in(page);
    std::string line;
    int n = 0, fence = 0;
    bool inYaml = false;
    std::string block;
    while (std::getline(in, line)) {
      ++n;
      if (!inYaml && line.rfind("```yaml", 0) == 0) {
        inYaml = true;
        fence = n;
        block.clear();
      } else if (inYaml && line.rfind("```", 0) == 0) {
        inYaml = false;
        const std::string first = block.substr(0, block.find('\n'));
        std::smatch m;
        const std::string where = "docs/" + page.filename().string() + ":" + std::to_string(fence);
        if (std::regex_match(first, m, marker)) {
          DocScene s;
          s.doc = where;
          s.line = fence;
          s.name = m[1];
          if (m[2].matched) {
            s.column = m[3];
            s.bound = std::strtod(m[4].str().c_str(), nullptr);
          }
          s.text = block;
          scenes.push_back(s);
        } else if (std::regex_search(block, std::regex(R"((^|\n)dimension:)"))) {
          unmarked.push_back(where);
        }
      } else if (inYaml) {
        block += line + "\n";
      }
    }
  }
  return scenes;
}

struct RunResult {
  int code = -1;
  bool timedOut = false;
  double seconds = 0.0;
  std::string output;
};

RunResult runBinary(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> all = {kBinary.string()};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    execv(argv[0], argv.data());
    _exit(127);
  }
  RunResult r;
  int status = 0;
  for (;;) {
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (waitpid(pid, &status, WNOHANG) == pid) break;
    if (r.seconds > kTimeoutSeconds) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      r.timedOut = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (!r.timedOut && WIFEXITED(status)) r.code = WEXITSTATUS(status);
  std::ifstream in(log);
  std::ostringstream s;
  s << in.rdbuf();
  r.output = s.str();
  return r;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream s(line);
  std::string cell;
  while (std::getline(s, cell, ',')) out.push_back(cell);
  return out;
}

}  // namespace

TEST(DocScenes, EveryCompleteSceneInTheDocsRunsAndMeetsItsExpectation) {
  ASSERT_TRUE(fs::exists(kBinary)) << kBinary << " is not built (ninja poresph)";
  std::vector<std::string> unmarked;
  const std::vector<DocScene> scenes = docScenes(unmarked);
  for (const std::string& where : unmarked)
    ADD_FAILURE() << where << ": a ```yaml block with a top-level 'dimension:' key has no "
                  << "'# scene: NAME' marker on its first line (docs/reliability.md)";
  ASSERT_GE(scenes.size(), 1u) << "docs/scene-format.md shows at least one complete scene";

  const fs::path work = fs::path(PORESPH_BINARY_DIR) / ("tmp_doc_scenes_" + std::to_string(getpid()));
  fs::remove_all(work);
  fs::create_directories(work);
  setenv("OMP_NUM_THREADS", "1", 0);
  for (const DocScene& s : scenes) {
    SCOPED_TRACE(s.doc + " (scene " + s.name + ")");
    const fs::path file = work / (s.name + ".yaml");
    std::ofstream(file) << s.text;
    const fs::path out = work / (s.name + "_out");  // fresh: never created before
    const RunResult r = runBinary({"run", file.string(), "--out", out.string()}, work / (s.name + ".log"));
    std::cout << s.doc << "  scene " << s.name << ": exit " << r.code << ", " << r.seconds << " s\n";
    ASSERT_FALSE(r.timedOut) << "no exit within " << kTimeoutSeconds << " s";
    ASSERT_EQ(r.code, 0) << r.output;
    if (s.column.empty()) continue;
    std::ifstream csv(out / "timeseries.csv");
    std::string header, line, last;
    ASSERT_TRUE(std::getline(csv, header)) << "no timeseries.csv in " << out;
    while (std::getline(csv, line))
      if (!line.empty()) last = line;
    const auto names = split(header), values = split(last);
    const auto it = std::find(names.begin(), names.end(), s.column);
    ASSERT_NE(it, names.end()) << "timeseries.csv has no column '" << s.column << "': " << header;
    const size_t k = static_cast<size_t>(it - names.begin());
    ASSERT_LT(k, values.size()) << last;
    const double v = std::strtod(values[k].c_str(), nullptr);
    std::cout << "  last row: time " << values[0] << " s, " << s.column << " = " << v
              << " (bound " << s.bound << ")\n";
    EXPECT_LT(v, s.bound) << s.column << " at the end (t = " << values[0] << " s)";
  }
  fs::remove_all(work);
}
