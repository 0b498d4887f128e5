// poresph: the command line (docs/cli.md).
//
//   poresph run SCENE [--out DIR] [--threads N] [--force] [--restart CHECKPOINT]
//   poresph info SCENE [--threads N]
//   poresph image FILE [--shape NX NY NZ] [--pore-label L] [--connectivity C] ... (app/image_command.cpp)
//   poresph synth OUT [--shape NX NY NZ] [--porosity P] ...                      (app/image_command.cpp)
//   poresph sweep SCENE --set key=v1,v2 [--set ...] --out DIR [--summary cols]  (app/sweep_command.cpp)
//   poresph study SCENE --vary name=v1,v2 [--vary ...] --out DIR              (app/study_command.cpp)
//   poresph --help | --version
//
// Exit codes: 0 done, 2 bad input (scene, options, output directory), 3 numerical blow-up,
// 130 / 143 stopped by SIGINT / SIGTERM (a checkpoint was written), 1 anything else.
#include <omp.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <csignal>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <thread>

#include "libcore/health.hpp"
#include "libcore/memory.hpp"
#include "libcore/parameters.hpp"
#include "libcore/reference.hpp"
#include "libcore/runner.hpp"
#include "libcore/scene.hpp"
#include "app/commands.hpp"

namespace fs = std::filesystem;
using namespace poresph;

namespace {

constexpr int kExitInput = 2;
constexpr int kExitNumerical = 3;

void setThreads(int threads) {
  if (threads > 0) omp_set_num_threads(threads);
}

/// Refuses a non-empty output directory unless `force`; creates it.
void prepareOutputDirectory(const std::string& dir, bool force) {
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec))
      throw InputError("--out '" + dir + "': exists and is not a directory");
    if (!fs::is_empty(dir, ec) && !force)
      throw InputError("--out '" + dir +
                       "': the output directory is not empty; choose a new one, or pass --force "
                       "to write into it (files of an earlier run are overwritten)");
  }
  fs::create_directories(dir, ec);
  if (ec) throw InputError("--out '" + dir + "': cannot create the directory: " + ec.message());
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  if (!f) throw InputError(path + ": cannot write the file");
}

int commandInfo(const std::string& scenePath, long estimateSteps) {
  // Two phases: read, configure and count (nothing per particle allocated), print the memory
  // estimate, and only then build the particles, if they fit.
  SceneOptions opt;
  opt.initialise = false;
  opt.buildParticles = false;
  opt.checkMemory = false;
  Scene scene = loadScene(scenePath, opt);
  std::cout << "estimate:     a run needs " << scene.memory.describe() << "\n" << std::flush;
  if (!scene.memory.fits()) {
    std::cout << describeScene(scene) << "threads:      " << omp_get_max_threads() << "\n"
              << "poresph: the scene would not fit in the available memory: particles not built; "
                 "`poresph run` refuses it unless --force\n";
    return 0;
  }
  buildParticles(scene);
  // Build the neighbour lists once so that the summary shows measured counts.
  scene.sim->updateNeighbours();
  std::cout << describeScene(scene) << "threads:      " << omp_get_max_threads() << "\n";
  if (estimateSteps > 0) {
    // Each module's stable step and the run time from a few timed steps (libcore/runner.hpp).
    std::cout << std::flush;
    initialiseScene(scene);
    const RunEstimate estimate = estimateRun(scene, estimateSteps, 30.0);
    std::cout << describeEstimate(scene, estimate);
    std::cout << describeMemory(memoryReport(*scene.sim, 0, 0.0));
    // The run loop's rollback copy (libcore/health.hpp), CPU time of one copy. (A comparison with
    // a copy of every field used to be printed here; it held a second copy of the whole store and
    // made the peak memory of `info` ~1.8x that of the run it describes.)
    const double checkpointCopy = [&] {
      RollbackState copy(1, false);
      copy.capture(*scene.sim);  // sizes the buffers
      const int repeats = 5;
      const std::clock_t c0 = std::clock();
      for (int k = 0; k < repeats; ++k) copy.capture(*scene.sim);
      return static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC / repeats;
    }();
    std::cout << "rollback:     one copy " << checkpointCopy * 1e3
              << " ms CPU (checkpoint and output fields)";
    if (estimate.secondsPerStep > 0.0)
      std::cout << ", a step " << estimate.secondsPerStep * 1e3 << " ms wall";
    std::cout << ", copied every " << scene.health.rollbackEvery << " step(s)\n";
  } else {
    std::cout << describeMemory(memoryReport(
        *scene.sim, 0, static_cast<double>(latticeNeighbourCount(
                           scene.sim->dimension(),
                           scene.sim->kernel.support() / scene.sim->spacing))));
  }
  return 0;
}

/// An unknown first word is named with the commands and the closest one ("rn" -> run), instead
/// of CLI11's "The following arguments were not expected".
void checkCommand(int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return;
  const std::vector<std::string> commands = {"run", "info", "image", "synth", "sweep", "study"};
  const std::string word = argv[1];
  if (std::find(commands.begin(), commands.end(), word) != commands.end()) return;
  const std::string guess = closestMatch(word, commands);
  throw InputError("unknown command '" + word + "'; commands: run, info, image, synth, sweep, study" +
                   (guess.empty() ? std::string() : " (did you mean '" + guess + "'?)") +
                   "; see poresph --help");
}

/// A whole number in [lo, hi] from an option's text; the message names the option, the rule and
/// the value as given (CLI11's PositiveNumber check printed its bound as a 309-digit number).
long long wholeNumberOption(const std::string& option, const std::string& text, long long lo,
                            long long hi, const std::string& rule) {
  std::size_t used = 0;
  long long value = 0;
  try {
    value = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || value < lo || value > hi)
    throw InputError(option + ": " + rule + ", got " + (text.empty() ? "an empty value" : text));
  return value;
}

/// --threads: 1 .. 4 x the cores of this machine (0, negative or absurd counts are refused).
int threadsOption(const std::string& text) {
  const long long cores = std::max(1u, std::thread::hardware_concurrency());
  return static_cast<int>(wholeNumberOption(
      "--threads", text, 1, 4 * cores,
      "the thread count must be a whole number from 1 to " + std::to_string(4 * cores) +
          " (1 .. 4 x the " + std::to_string(cores) + " cores of this machine)"));
}

/// runs/<scene name>-<UTC date>-<time>: a new folder per run when --out is not given.
std::string defaultOutputDirectory(const std::string& scenePath) {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%Y%m%d-%H%M%S", &utc);
  return "runs/" + fs::path(scenePath).stem().string() + "-" + stamp;
}

int commandRun(const std::string& scenePath, std::string outDir, bool force,
               const std::string& restart, bool keepGoing) {
  // Check the scene before touching the output directory. The memory estimate is checked before
  // any particle is allocated; --force runs a scene that does not fit anyway.
  SceneOptions sceneOptions;
  sceneOptions.checkMemory = !force;
  Scene scene = loadScene(scenePath, sceneOptions);
  if (restart.empty() && !keepGoing && !scene.health.keepGoing)
    checkInitialHealth(scene, scenePath);
  // Refused before --out is touched; the warnings are printed by the run's own restore (once).
  if (!restart.empty()) restoreCheckpoint(scene, restart, nullptr, /*printWarnings=*/false);
  // A restart continues the run in the checkpoint's own directory unless --out says otherwise:
  // that directory is not empty, and continuing it (timeseries rows and snapshots after the
  // checkpoint's time replaced, earlier ones kept) is what was asked for.
  std::error_code sameEc;
  const std::string restartDir =
      restart.empty() ? std::string() : fs::path(restart).parent_path().string();
  if (outDir.empty() && !restart.empty()) outDir = restartDir.empty() ? "." : restartDir;
  if (outDir.empty()) outDir = defaultOutputDirectory(scenePath);
  const bool continuing =
      !restart.empty() && fs::exists(outDir, sameEc) &&
      fs::equivalent(outDir, restartDir.empty() ? "." : restartDir, sameEc);
  prepareOutputDirectory(outDir, force || continuing);
  const fs::path sceneCopy = fs::path(outDir) / fs::path(scenePath).filename();
  std::error_code ec;
  if (fs::absolute(sceneCopy, ec) != fs::absolute(scenePath, ec))
    fs::copy_file(scenePath, sceneCopy, fs::copy_options::overwrite_existing, ec);
  if (ec) throw InputError(sceneCopy.string() + ": cannot copy the scene: " + ec.message());
  writeFile((fs::path(outDir) / "run.yaml").string(), resolvedSceneYaml(scene));
  std::ostringstream summary;
  summary << "PoreSPH " << PORESPH_VERSION << "\n" << describeScene(scene)
          << "threads:      " << omp_get_max_threads() << "\n";
  std::cerr << summary.str();
  std::cerr << "poresph: writing to " << outDir << " (parameters used: " << outDir
            << "/run.yaml)\n";

  RunOptions opt;
  opt.outDir = outDir;
  opt.progress = &std::cerr;
  opt.restartFrom = restart;
  opt.keepGoing = keepGoing;
  const RunResult r = runScene(scene, opt);

  std::ostringstream end;
  if (scene.reference.declared) {
    // The scene's reference quantity on the final state (libcore/reference.hpp): DIR/reference.yaml.
    const ReferenceResult ref =
        evaluateReference(scene, (fs::path(outDir) / "timeseries.csv").string());
    writeFile((fs::path(outDir) / "reference.yaml").string(), referenceYaml(scene.reference, ref));
    end << "reference: " << scene.reference.quantity << " = ";
    if (ref.ok) end << ref.measured;
    else end << "not measured (" << ref.note << ")";
    if (ref.ok && ref.hasValue)
      end << " (value " << ref.value << ", error " << ref.error << (ref.relative ? "" : " absolute")
          << ")";
    end << "\n";
  }
  end << "steps " << r.steps << ", time " << r.time << " s, wall " << r.wallSeconds << " s, "
      << r.snapshots << " snapshots, checkpoint " << r.checkpoint << "\n";
  switch (r.status) {
    case RunStatus::Finished: {
      const std::string reason = scene.endConditionMet();
      end << "status: finished" << (reason.empty() ? "" : " (" + reason + ")") << "\n";
      break;
    }
    case RunStatus::Interrupted: end << "status: interrupted by signal " << r.signal << "\n"; break;
    case RunStatus::Failed: end << "status: numerical failure: " << r.message << "\n"; break;
  }
  writeFile((fs::path(outDir) / "run.log").string(), summary.str() + end.str());
  std::cerr << "poresph: " << end.str();
  if (r.status == RunStatus::Failed) return kExitNumerical;
  if (r.status == RunStatus::Interrupted) return 128 + r.signal;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"PoreSPH " PORESPH_VERSION
               ": SPH simulation of pore-scale drainage with damage (docs/cli.md)"};
  app.set_version_flag("--version", std::string("poresph ") + PORESPH_VERSION);
  app.require_subcommand(1);

  std::string scenePath, outDir, restart;
  bool force = false;
  std::string threadsText;  // checked by threadsOption (1 .. 4 x cores)

  CLI::App* run = app.add_subcommand("run", "Run a scene to its end_time");
  run->add_option("scene", scenePath, "Scene file (YAML, docs/scene-format.md)")->required();
  run->add_option("--out,-o", outDir,
                  "Output directory (refused if not empty, unless --force; default "
                  "runs/<scene>-<UTC date-time>)");
  run->add_option("--threads,-t", threadsText,
                  "OpenMP threads, 1 .. 4 x cores (default: OMP_NUM_THREADS or all)");
  run->add_flag("--force,-f", force,
                "Write into a non-empty output directory; run a scene whose memory estimate "
                "exceeds the available memory");
  run->add_option("--restart", restart,
                  "Resume from a checkpoint written by an earlier run of the same scene (the "
                  "run continues in the checkpoint's directory unless --out is given)");
  bool keepGoing = false;
  run->add_flag("--keep-going", keepGoing,
                "Health checks warn (once per check) instead of stopping the run "
                "(docs/reliability.md)");

  CLI::App* info = app.add_subcommand("info", "Describe a scene without running it");
  info->add_option("scene", scenePath, "Scene file (YAML)")->required();
  info->add_option("--threads,-t", threadsText, "OpenMP threads, 1 .. 4 x cores");
  std::string estimateText = "10";
  info->add_option("--estimate-steps", estimateText,
                   "steps to time for the run-time estimate (at most 30 s; 0: none)");

  // Commands in their own files (app/commands.hpp); their values are checked when they run.
  const std::vector<app::Command> commands = {app::addImageCommand(app), app::addSynthCommand(app),
                                                app::addSweepCommand(app), app::addStudyCommand(app)};

  try {
    checkCommand(argc, argv);
  } catch (const InputError& e) {
    std::cerr << "poresph: error: " << e.what() << "\n";
    return kExitInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help/version (code 0) or the error
    return code == 0 ? 0 : kExitInput;
  }

  try {
    if (!threadsText.empty()) setThreads(threadsOption(threadsText));
    if (info->parsed())
      return commandInfo(scenePath, wholeNumberOption("--estimate-steps", estimateText, 0, 1000000,
                                                      "a whole number of steps from 0 to 1000000"));
    for (const auto& c : commands)
      if (c.sub->parsed()) return c.run();
    if (run->parsed()) return commandRun(scenePath, outDir, force, restart, keepGoing);
  } catch (const InputError& e) {
    std::cerr << "poresph: error: " << e.what() << "\n";
    return kExitInput;
  } catch (const NumericalError& e) {
    std::cerr << "poresph: numerical failure: " << e.what() << "\n";
    return kExitNumerical;
  } catch (const std::exception& e) {
    std::cerr << "poresph: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
