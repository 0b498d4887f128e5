// `poresph sweep SCENE --set key.path=v1,v2 [--set ...] --out DIR`: a case-by-case study
// (docs/cli.md). Each case is the scene with its overrides written to DIR/<case>/scene.yaml,
// checked by the scene parser (errors name that file, line and key) and run by `poresph run` in
// a child process, so that a case that fails (bad value, blow-up, crash) is reported and the
// others still run. The last timeseries row of each case goes into DIR/summary.csv and
// DIR/summary.md; scripts/plot_timeseries.py draws the chosen columns of every case in
// DIR/summary.png.
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "app/commands.hpp"
#include "libcore/parameters.hpp"
#include "libcore/scene.hpp"

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

std::vector<std::string> splitList(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  int depth = 0;  // commas inside [..] or {..} belong to one value
  for (char c : s) {
    if (c == '[' || c == '{') ++depth;
    if (c == ']' || c == '}') --depth;
    if (c == sep && depth == 0) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

Setting parseSet(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw InputError("--set '" + text + "': expected key.path=v1,v2,... (e.g. --set materials.clay.young_modulus=1e8,2e8)");
  Setting s;
  s.key = text.substr(0, eq);
  s.values = splitList(text.substr(eq + 1), ',');
  for (const auto& v : s.values)
    if (v.empty()) throw InputError("--set '" + text + "': an empty value in the list");
  return s;
}

/// The node at `path` (a.b[2].c; a list element also by its `name`: materials.clay.density),
/// created where a mapping lacks the key (the scene parser then names an unknown one).
YAML::Node locate(YAML::Node root, const std::string& path, const std::string& what) {
  YAML::Node node = root;
  std::string done;
  for (const std::string& partIn : splitList(path, '.')) {
    std::string part = partIn;
    std::vector<long> indices;
    const auto br = part.find('[');
    if (br != std::string::npos) {
      std::string rest = part.substr(br);
      part = part.substr(0, br);
      while (!rest.empty()) {
        const auto close = rest.find(']');
        if (rest[0] != '[' || close == std::string::npos)
          throw InputError(what + ": malformed index in '" + partIn + "'");
        indices.push_back(std::stol(rest.substr(1, close - 1)));
        rest = rest.substr(close + 1);
      }
    }
    if (part.empty() && indices.empty()) throw InputError(what + ": an empty key in '" + path + "'");
    if (!part.empty()) {
      if (node.IsSequence()) {
        // A list element by its name.
        YAML::Node found;
        bool have = false;
        std::string names;
        for (size_t k = 0; k < node.size(); ++k) {
          const YAML::Node n = node[k];
          if (n.IsMap() && n["name"] && n["name"].IsScalar()) {
            names += (names.empty() ? "" : ", ") + n["name"].Scalar();
            if (n["name"].Scalar() == part && !have) {
              found.reset(n);
              have = true;
            }
          }
        }
        if (!have)
          throw InputError(what + ": '" + done + "' is a list with no element named '" + part +
                           "'" + (names.empty() ? std::string() : " (names: " + names + ")") +
                           "; use an index, e.g. " + done + "[0]");
        node.reset(found);
      } else if (node.IsMap() || node.IsNull()) {
        YAML::Node child = node[part];
        node.reset(child);
      } else {
        throw InputError(what + ": '" + done + "' is a value, not a mapping: cannot set '" + part + "' in it");
      }
      done += (done.empty() ? "" : ".") + part;
    }
    for (long i : indices) {
      if (!node.IsSequence() || i < 0 || i >= static_cast<long>(node.size()))
        throw InputError(what + ": '" + done + "' has no element [" + std::to_string(i) + "]" +
                         (node.IsSequence() ? " (" + std::to_string(node.size()) + " elements)" : " (not a list)"));
      YAML::Node child = node[static_cast<size_t>(i)];
      node.reset(child);
      done += "[" + std::to_string(i) + "]";
    }
  }
  return node;
}

std::string caseName(size_t index, const std::vector<std::pair<std::string, std::string>>& chosen) {
  std::string name = "case" + std::string(index < 9 ? "0" : "") + std::to_string(index + 1);
  for (const auto& [k, v] : chosen) {
    std::string last = k.substr(k.find_last_of('.') == std::string::npos ? 0 : k.find_last_of('.') + 1);
    name += "_" + last + "=" + v;
  }
  for (auto& c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '=' || c == '-' || c == '+'))
      c = '-';
  return name.size() > 120 ? name.substr(0, 120) : name;
}

std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string selfExe() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("poresph") : p.string();
}

/// scripts/plot_timeseries.py next to the build (build/poresph -> ../scripts), or "".
std::string plotScript() {
  const fs::path exe = selfExe();
  for (const fs::path& p : {exe.parent_path().parent_path() / "scripts" / "plot_timeseries.py",
                            fs::path("scripts") / "plot_timeseries.py"}) {
    std::error_code ec;
    if (fs::exists(p, ec)) return p.string();
  }
  return "";
}

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
  YAML::Node base;
  try {
    base = YAML::LoadFile(o.scene);
  } catch (const YAML::BadFile&) {
    throw InputError("scene '" + o.scene + "': cannot read the file");
  } catch (const YAML::Exception& e) {
    throw InputError("scene '" + o.scene + "': " + e.what());
  }
  checkDuplicateKeys(base, o.scene);
  if (o.out.empty()) throw InputError("--out: give the study's folder");
  std::error_code ec;
  if (fs::exists(o.out, ec) && !fs::is_empty(o.out, ec) && !o.overwrite)
    throw InputError("--out '" + o.out +
                     "': the folder exists and is not empty; choose a new one, or pass --overwrite "
                     "to replace the cases in it");
  fs::create_directories(o.out, ec);
  if (ec) throw InputError("--out '" + o.out + "': cannot create the folder: " + ec.message());

  // ---- cases: every combination of the values, the first --set varying slowest ----
  size_t total = 1;
  for (const auto& s : sets) total *= s.values.size();
  if (total > 10000) throw InputError("--set: " + std::to_string(total) + " cases, more than 10000");
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
    size_t rem = c;
    for (size_t s = sets.size(); s-- > 0;) {
      k.chosen.insert(k.chosen.begin(), {sets[s].key, sets[s].values[rem % sets[s].values.size()]});
      rem /= sets[s].values.size();
    }
    k.name = caseName(c, k.chosen);
    cases.push_back(k);
  }
  const std::string exe = selfExe();
  std::cerr << "poresph sweep: " << total << " cases of " << o.scene << " in " << o.out << "\n";
  for (Case& k : cases) {
    const fs::path dir = fs::path(o.out) / k.name;
    if (o.overwrite) fs::remove_all(dir, ec);
    fs::create_directories(dir, ec);
    // The case's scene: overrides applied, relative paths (images) resolved from the original.
    YAML::Node scene = YAML::Clone(base);
    try {
      for (const auto& [key, value] : k.chosen) {
        YAML::Node target = locate(scene, key, "--set " + key);
        YAML::Node v = YAML::Load(value);
        target = v;
      }
    } catch (const InputError& e) {
      k.status = std::string("bad setting: ") + e.what();
      std::cerr << "  " << k.name << ": " << k.status << "\n";
      continue;
    }
    if (scene["geometry"] && scene["geometry"].IsSequence())
      for (auto g : scene["geometry"])
        if (g.IsMap() && g["file"] && g["file"].IsScalar() && fs::path(g["file"].Scalar()).is_relative())
          g["file"] = (sceneDir / g["file"].Scalar()).lexically_normal().string();
    const fs::path scenePath = dir / "scene.yaml";
    {
      std::ofstream f(scenePath);
      f << "# " << o.scene << " with";
      for (const auto& [key, value] : k.chosen) f << " " << key << "=" << value;
      f << " (poresph sweep)\n" << YAML::Dump(scene) << "\n";
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
    std::string cmd = shellQuote(exe) + " run " + shellQuote(scenePath.string()) + " --out " +
                      shellQuote((dir / "run").string()) + " --force";
    if (!o.threads.empty()) cmd += " --threads " + shellQuote(o.threads);
    if (o.keepGoing) cmd += " --keep-going";
    cmd += " > " + shellQuote((dir / "log.txt").string()) + " 2>&1";
    std::cerr << "  " << k.name << ": running (log " << (dir / "log.txt").string() << ")\n";
    const int status = std::system(cmd.c_str());
    k.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    k.status = k.code == 0 ? "finished"
               : k.code == 3 ? "numerical failure (exit 3)"
               : k.code == 2 ? "bad input (exit 2)"
                             : "failed (exit " + std::to_string(k.code) + ")";
    if (k.code != 0) {
      std::ifstream log(dir / "log.txt");
      std::string line, lastLine;
      while (std::getline(log, line))
        if (line.find("error") != std::string::npos || line.find("failure") != std::string::npos) lastLine = line;
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
