// `poresph sweep SCENE --set key.path=v1,v2 [--set ...] --out DIR`: a case-by-case study
// (docs/cli.md). Each case is the scene with its overrides written to DIR/<case>/scene.yaml,
// checked by the scene parser (errors name that file, line and key) and run by `poresph run` in
// a child process, so that a case that fails (bad value, blow-up, crash) is reported and the
// others still run. The last timeseries row of each case goes into DIR/summary.csv and
// DIR/summary.md; scripts/plot_timeseries.py draws the chosen columns of every case in
// DIR/summary.png. Linked keys, `--set a.b+c.d=v1,v2`, give each case's value to every key joined
// by '+' (both confining plates of a drainage scene in one sweep).
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <tuple>

#include <yaml-cpp/yaml.h>

#include "app/commands.hpp"
#include "libcore/parameters.hpp"
#include "libcore/scene.hpp"
#include "libcore/study.hpp"

namespace fs = std::filesystem;

namespace poresph::app {

namespace {

struct SweepOptions {
  std::string scene, out, summary, threads;
  std::vector<std::string> sets;
  bool overwrite = false, keepGoing = false, noPlot = false;
};

struct Setting {
  std::string key;
  std::vector<std::string> values;
};

std::vector<std::string> splitList(const std::string& s, char sep) { return splitTopLevel(s, sep); }

Setting parseSet(const std::string& text) {
  Setting s;
  std::tie(s.key, s.values) = parseNamedList(
      text, "--set", "key.path=v1,v2,... (e.g. --set materials.clay.young_modulus=1e8,2e8)");
  for (const auto& k : splitList(s.key, '+'))
    if (k.empty())
      throw InputError("--set '" + text + "': an empty key path in '" + s.key +
                       "' (linked keys: key.a+key.b=v1,v2 gives each case's value to both)");
  return s;
}

std::string plotScript() { return findScript("plot_timeseries.py"); }

/// Header and last row of a timeseries.csv.
bool lastRow(const fs::path& csv, std::vector<std::string>& header, std::vector<std::string>& row) {
  std::ifstream f(csv);
  std::string line, last;
  if (!std::getline(f, line)) return false;
  header = splitList(line, ',');
  while (std::getline(f, line))
    if (!line.empty()) last = line;
  if (last.empty()) return false;
  row = splitList(last, ',');
  return true;
}

int runSweep(const SweepOptions& o) {
  // ---- the settings and the scene, checked before anything is written ----
  std::vector<Setting> sets;
  for (const auto& s : o.sets) sets.push_back(parseSet(s));
  if (sets.empty()) throw InputError("--set: give at least one key.path=v1,v2,... to sweep");
  const YAML::Node base = readSceneYaml(o.scene);
  if (o.out.empty()) throw InputError("--out: give the study's folder");
  std::error_code ec;
  if (fs::exists(o.out, ec) && !fs::is_empty(o.out, ec) && !o.overwrite)
    throw InputError("--out '" + o.out +
                     "': the folder exists and is not empty; choose a new one, or pass --overwrite "
                     "to replace the cases in it");
  fs::create_directories(o.out, ec);
  if (ec) throw InputError("--out '" + o.out + "': cannot create the folder: " + ec.message());

  // ---- cases: every combination of the values, the first --set varying slowest ----
  std::vector<std::pair<std::string, std::vector<std::string>>> grid;
  for (const auto& s : sets) grid.emplace_back(s.key, s.values);
  std::vector<std::vector<std::pair<std::string, std::string>>> chosen;
  try {
    chosen = expandGrid(grid, 10000);
  } catch (const InputError& e) {
    throw InputError(std::string("--set: ") + e.what());
  }
  const size_t total = chosen.size();
  const fs::path sceneDir = fs::absolute(fs::path(o.scene)).parent_path();
  struct Case {
    std::string name;
    std::vector<std::pair<std::string, std::string>> chosen;
    std::string status = "not run";
    int code = -1;
  };
  std::vector<Case> cases;
  for (size_t c = 0; c < total; ++c) {
    Case k;
    k.chosen = chosen[c];
    k.name = caseFolderName(c, k.chosen);
    cases.push_back(k);
  }
  const std::string exe = childExecutable();
  std::cerr << "poresph sweep: " << total << " cases of " << o.scene << " in " << o.out << "\n";
  for (Case& k : cases) {
    const fs::path dir = fs::path(o.out) / k.name;
    if (o.overwrite) fs::remove_all(dir, ec);
    fs::create_directories(dir, ec);
    // The case's scene: overrides applied, relative paths (images) resolved from the original.
    const fs::path scenePath = dir / "scene.yaml";
    try {
      std::vector<SceneEdit> edits;
      std::string header = o.scene + " with";
      for (const auto& [key, value] : k.chosen) {
        // Linked keys `a+b=v1,v2`: one value per case, written to each key (e.g. both plates).
        for (const auto& one : splitList(key, '+')) edits.push_back({one, value});
        header += " " + key + "=" + value;
      }
      writeCaseScene(base, edits, sceneDir.string(), scenePath.string(), header + " (poresph sweep)");
    } catch (const InputError& e) {
      k.status = std::string("bad setting: ") + e.what();
      std::cerr << "  " << k.name << ": " << k.status << "\n";
      continue;
    }
    // The parser checks the case before it runs: its errors name this file, line and key.
    try {
      SceneOptions so;
      so.buildParticles = false;
      so.initialise = false;
      so.checkMemory = false;
      loadScene(scenePath.string(), so);
    } catch (const InputError& e) {
      k.status = std::string("bad scene: ") + e.what();
      std::cerr << "  " << k.name << ": " << k.status << "\n";
      continue;
    }
    std::vector<std::string> argv = {exe, "run", scenePath.string(), "--out", (dir / "run").string(), "--force"};
    if (!o.threads.empty()) {
      argv.push_back("--threads");
      argv.push_back(o.threads);
    }
    if (o.keepGoing) argv.push_back("--keep-going");
    std::cerr << "  " << k.name << ": running (log " << (dir / "log.txt").string() << ")\n";
    k.code = runChild(argv, (dir / "log.txt").string()).code;
    k.status = k.code == 0 ? "finished"
               : k.code == 3 ? "numerical failure (exit 3)"
               : k.code == 2 ? "bad input (exit 2)"
                             : "failed (exit " + std::to_string(k.code) + ")";
    if (k.code != 0) {
      const std::string lastLine = lastErrorLine((dir / "log.txt").string());
      if (!lastLine.empty()) k.status += ": " + lastLine;
    }
    std::cerr << "  " << k.name << ": " << k.status << "\n";
  }

  // ---- summary: the chosen columns of each case's last timeseries row ----
  std::vector<std::string> columns;
  if (!o.summary.empty()) columns = splitList(o.summary, ',');
  if (columns.empty()) {
    // Generic defaults that exist in the runs' timeseries (drainage columns first).
    const std::vector<std::string> preferred = {
        "drainage_percolation_time", "drainage_porosity", "drainage_gas_saturation",
        "drainage_damaged_fraction", "time", "step", "kinetic_energy"};
    std::vector<std::string> header, row;
    for (const Case& k : cases)
      if (lastRow(fs::path(o.out) / k.name / "run" / "timeseries.csv", header, row)) break;
    for (const auto& p : preferred)
      if (std::find(header.begin(), header.end(), p) != header.end()) columns.push_back(p);
    if (columns.empty()) columns = {"time", "step"};
  }
  std::ofstream csv(fs::path(o.out) / "summary.csv"), md(fs::path(o.out) / "summary.md");
  csv << "case";
  md << "| case";
  for (const auto& s : sets) {
    csv << "," << s.key;
    md << " | " << s.key;
  }
  csv << ",status";
  md << " | status";
  for (const auto& c : columns) {
    csv << "," << c;
    md << " | " << c;
  }
  csv << "\n";
  md << " |\n|" << std::string("---|") ;
  for (size_t k = 0; k < sets.size() + 1 + columns.size(); ++k) md << "---|";
  md << "\n";
  int failed = 0;
  std::vector<std::string> missing;
  std::vector<std::string> plotted;
  for (const Case& k : cases) {
    std::vector<std::string> header, row;
    const fs::path ts = fs::path(o.out) / k.name / "run" / "timeseries.csv";
    const bool have = lastRow(ts, header, row);
    if (have) plotted.push_back(ts.string());
    failed += k.code != 0;
    std::string status = k.status;
    for (auto& ch : status)
      if (ch == '\n' || ch == '|' || ch == ',') ch = ' ';
    csv << k.name;
    md << "| " << k.name;
    for (const auto& [key, value] : k.chosen) {
      csv << "," << (value.find(',') != std::string::npos ? "\"" + value + "\"" : value);
      md << " | " << value;
    }
    csv << "," << status;
    md << " | " << status;
    for (const auto& c : columns) {
      std::string v;
      if (have) {
        const auto it = std::find(header.begin(), header.end(), c);
        if (it != header.end() && static_cast<size_t>(it - header.begin()) < row.size())
          v = row[static_cast<size_t>(it - header.begin())];
        else if (std::find(missing.begin(), missing.end(), c) == missing.end())
          missing.push_back(c);
      }
      csv << "," << v;
      md << " | " << (v.empty() ? "-" : v);
    }
    csv << "\n";
    md << " |\n";
  }
  for (const auto& c : missing)
    std::cerr << "poresph sweep: --summary column '" << c << "' is not in the timeseries of some cases\n";
  std::cout << "summary:      " << (fs::path(o.out) / "summary.csv").string() << ", "
            << (fs::path(o.out) / "summary.md").string() << "\n";
  // ---- plot: the summary columns of every case against time ----
  const std::string script = plotScript();
  std::vector<std::string> timeColumns;
  for (const auto& c : columns)
    if (c != "time" && c != "step") timeColumns.push_back(c);
  if (o.noPlot || plotted.empty() || timeColumns.empty()) {
  } else if (script.empty()) {
    std::cerr << "poresph sweep: scripts/plot_timeseries.py not found: no plot\n";
  } else {
    std::string cols;
    for (const auto& c : timeColumns) cols += (cols.empty() ? "" : ",") + c;
    std::string cmd = "/usr/bin/python3 " + shellQuote(script);
    for (const auto& p : plotted) cmd += " " + shellQuote(p);
    cmd += " --columns " + shellQuote(cols) + " --out " + shellQuote((fs::path(o.out) / "summary.png").string());
    std::string labels;
    for (const Case& k : cases)
      if (fs::exists(fs::path(o.out) / k.name / "run" / "timeseries.csv", ec))
        labels += (labels.empty() ? "" : ",") + k.name;
    cmd += " --labels " + shellQuote(labels) + " > " + shellQuote((fs::path(o.out) / "plot.log").string()) + " 2>&1";
    if (std::system(cmd.c_str()) == 0)
      std::cout << "plot:         " << (fs::path(o.out) / "summary.png").string() << "\n";
    else
      std::cerr << "poresph sweep: the plot failed (see " << (fs::path(o.out) / "plot.log").string() << ")\n";
  }
  std::cout << "cases:        " << cases.size() - failed << " finished, " << failed << " failed\n";
  return failed ? 1 : 0;
}

}  // namespace

Command addSweepCommand(CLI::App& app) {
  auto o = std::make_shared<SweepOptions>();
  CLI::App* c = app.add_subcommand("sweep", "Run a scene for each combination of values (a study)");
  c->add_option("scene", o->scene, "Scene file (YAML)")->required();
  c->add_option("--set", o->sets, "key.path=v1,v2,... (repeatable; lists by index [k] or by name)")->required();
  c->add_option("--out,-o", o->out, "Study folder: one sub-folder per case, summary.csv/.md/.png")->required();
  c->add_option("--summary", o->summary, "Timeseries columns for the summary (comma-separated)");
  c->add_option("--threads,-t", o->threads, "OpenMP threads for each case");
  c->add_flag("--overwrite", o->overwrite, "Replace the cases of an existing, non-empty study folder");
  c->add_flag("--keep-going", o->keepGoing, "Pass --keep-going to each run (health checks warn)");
  c->add_flag("--no-plot", o->noPlot, "Do not draw summary.png");
  return {c, [o] { return runSweep(*o); }};
}

}  // namespace poresph::app
