#pragma once
// Runs of a scene over a grid of settings: what `poresph sweep` (a grid of any scene keys, a
// summary of the last timeseries row) and `poresph study` (a grid of numerical settings, each
// run's error, cost and health; docs/choosing-settings.md) share, and the study itself.
//
// Each case is the scene with its edits written to DIR/<case>/scene.yaml, checked by the scene
// parser (errors name that file, line and key), and run by `poresph run` in a child process
// (fork/exec, waited with wait4: exit code, wall time, CPU time and peak resident memory of that
// run alone), so a case that fails (bad value, blow-up, crash) is a row and the others still run.
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace poresph {

// ---------------------------------------------------------------- shared by sweep and study --

/// Splits at `sep`, keeping separators inside [..] and {..} (one YAML value: [0, 1]).
std::vector<std::string> splitTopLevel(const std::string& s, char sep);
/// A command-line list `NAME=v1,v2,...` (the --vary of `poresph study`, the --set of `poresph
/// sweep`): the name and the values (split at top-level commas); InputError naming the option
/// and `example` for a missing name, '=' or value, or an empty value in the list.
std::pair<std::string, std::vector<std::string>> parseNamedList(const std::string& text,
                                                                const std::string& option,
                                                                const std::string& example);
/// The node at `path` (a.b[2].c; a list element also by its `name`: materials.clay.density),
/// created where a mapping lacks the key (the scene parser then names an unknown one). Errors
/// (InputError) start with `what`.
YAML::Node locateKey(YAML::Node root, const std::string& path, const std::string& what);

/// One edit of a case's scene: set `path` to the YAML `value`, or remove the key.
struct SceneEdit {
  std::string path;
  std::string value;
  bool remove = false;
};

/// Every combination of the axes' values, the first axis varying slowest: per case, the
/// (axis name, value) chosen. Throws InputError above `limit` cases.
std::vector<std::vector<std::pair<std::string, std::string>>> expandGrid(
    const std::vector<std::pair<std::string, std::vector<std::string>>>& axes, size_t limit = 10000);
/// "case03_spacing=0.001_kernel=wendland": a folder name (odd characters replaced by '-').
std::string caseFolderName(size_t index, const std::vector<std::pair<std::string, std::string>>& chosen);
/// Applies the edits to a copy of `base`, resolves relative image paths against `sceneDir` and
/// writes it to `path` with the comment `header`. Throws InputError for an edit that cannot apply.
void writeCaseScene(const YAML::Node& base, const std::vector<SceneEdit>& edits,
                    const std::string& sceneDir, const std::string& path, const std::string& header);
/// The scene file read (InputError naming it when unreadable or malformed; duplicate keys refused).
YAML::Node readSceneYaml(const std::string& path);

std::string shellQuote(const std::string& s);
/// This program's path (/proc/self/exe), or "poresph".
std::string selfExecutable();
/// What a child should execute to run this very program: "/proc/self/exe" (the running file,
/// even when `cmake --build` relinks poresph during a study or sweep), else selfExecutable().
std::string childExecutable();
/// scripts/<name> next to the build (build/poresph -> ../scripts) or under ./scripts, or "".
std::string findScript(const std::string& name);

/// A child process's outcome.
struct ChildRun {
  int code = -1;            ///< exit status; 128 + signal when killed
  double wallSeconds = 0.0;
  double cpuSeconds = 0.0;  ///< user + system of the child (all its threads)
  long maxRssKiB = 0;       ///< peak resident memory of the child
};
/// Runs argv[0] with argv (no shell), stdout and stderr to `logPath`, and waits for it (wait4).
ChildRun runChild(const std::vector<std::string>& argv, const std::string& logPath);

/// The last line of a log with "error" or "failure" in it ("" if none).
std::string lastErrorLine(const std::string& logPath);

// --------------------------------------------------------------------------------- study --

/// `--vary NAME=v1,v2,...`: NAME is a study name (studyVaryNames(), mapped to scene keys by
/// studyEdits) or a dotted scene key path (materials.gas.density). Unknown names, names with no
/// scene key behind them (precision, correction) and empty values are InputErrors (exit 2).
struct VaryAxis {
  std::string name;
  std::vector<std::string> values;
};
VaryAxis parseVary(const std::string& text);
/// The study names and the scene keys each sets (docs/choosing-settings.md, docs/cli.md).
const std::vector<std::pair<std::string, std::string>>& studyVaryNames();
/// The scene edits of one axis value (kernel aliases resolved: cubic -> cubic_spline, ...).
std::vector<SceneEdit> studyEdits(const std::string& name, const std::string& value);

/// One run of a study.
struct StudyRow {
  std::string name;                                      ///< folder
  std::vector<std::pair<std::string, std::string>> chosen;
  std::string status = "not run";  ///< finished | unstable: <check> | bad scene: ... | failed ...
  int code = -1;                   ///< exit code of `poresph run` (-1: not run)
  bool healthy = false;            ///< finished with every health check passed
  double wallSeconds = 0.0, cpuSeconds = 0.0;
  long maxRssKiB = 0;
  long long particles = 0, steps = 0;
  double densityVariation = -1.0;  ///< largest fluid_max_density_variation (-1: no fluid)
  double energyDrift = -1.0;       ///< solid energy balance drift / largest solid energy (-1: none)
  bool measured = false;
  double value = 0.0;              ///< the reference quantity measured by the run
  bool hasError = false;
  double error = 0.0;
  std::string errorAgainst;        ///< "closed form", "finest run <name>", ...
  bool pareto = false;
};

/// Marks StudyRow::pareto: the healthy rows with an error that no other healthy row beats in both
/// wall time and error (<= in both, < in one). Returns the indices of the front by wall time.
/// `cpu`: the cost is the CPU time instead of the wall time (a loaded machine).
std::vector<size_t> markParetoFront(std::vector<StudyRow>& rows, bool cpu = false);
/// The errors: against the closed-form `value` when the scene gives one (hasValue), else against
/// the finest healthy run (most particles; the first such run in grid order on a tie).
void assignStudyErrors(std::vector<StudyRow>& rows, bool hasValue, double value);

/// Fills a finished row from its run folder: run.log (particles, steps), reference.yaml (the
/// measured quantity), timeseries.csv (density variation, energy drift).
void readRunResults(StudyRow& row, const std::string& runDir);

struct StudyOptions {
  std::string scene, out, threads;
  std::vector<std::string> vary, sets;
  bool overwrite = false, noPlot = false;
  std::string cost = "wall";  ///< wall | cpu: the cost of the Pareto front and the plot
  std::string executable;  ///< poresph to run the cases with ("": this program)
};
/// The whole study: cases, runs, DIR/study.csv, DIR/study.md, DIR/study.png. Returns the rows.
/// Throws InputError for bad options (before anything is written).
std::vector<StudyRow> runStudy(const StudyOptions& options);
/// study.csv and study.md of `rows`.
void writeStudyTables(const std::string& dir, const std::string& scene, const std::string& quantity,
                      const std::vector<VaryAxis>& axes, const std::vector<StudyRow>& rows,
                      const std::string& cost = "wall");

}  // namespace poresph
