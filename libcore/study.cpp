#include "libcore/study.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cerrno>
#include <cstring>
#include <tuple>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

#include "libcore/parameters.hpp"
#include "libcore/reference.hpp"
#include "libcore/scene.hpp"

namespace fs = std::filesystem;

namespace poresph {

// ================================================================ shared by sweep and study ==

std::vector<std::string> splitTopLevel(const std::string& s, char sep) {
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

YAML::Node locateKey(YAML::Node root, const std::string& path, const std::string& what) {
  YAML::Node node = root;
  std::string done;
  const std::vector<std::string> parts = splitTopLevel(path, '.');
  for (size_t pi = 0; pi < parts.size(); ++pi) {
    const std::string& partIn = parts[pi];
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
        try {
          indices.push_back(std::stol(rest.substr(1, close - 1)));
        } catch (const std::exception&) {
          throw InputError(what + ": malformed index in '" + partIn + "'");
        }
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
        if (!child.IsDefined() && (pi + 1 < parts.size() || !indices.empty())) {
          // A section the scene does not have yet (health: when setting health.max_mach).
          node[part] = YAML::Node(YAML::NodeType::Map);
          child.reset(node[part]);
        }
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

std::vector<std::vector<std::pair<std::string, std::string>>> expandGrid(
    const std::vector<std::pair<std::string, std::vector<std::string>>>& axes, size_t limit) {
  size_t total = 1;
  for (const auto& a : axes) {
    if (a.second.empty()) throw InputError("'" + a.first + "': no values");
    if (total > limit / a.second.size() + 1) total = limit + 1;
    else total *= a.second.size();
  }
  if (total > limit)
    throw InputError("the grid has more than " + std::to_string(limit) + " cases");
  std::vector<std::vector<std::pair<std::string, std::string>>> out;
  for (size_t c = 0; c < total; ++c) {
    std::vector<std::pair<std::string, std::string>> chosen;
    size_t rem = c;
    for (size_t s = axes.size(); s-- > 0;) {
      chosen.insert(chosen.begin(), {axes[s].first, axes[s].second[rem % axes[s].second.size()]});
      rem /= axes[s].second.size();
    }
    out.push_back(chosen);
  }
  return out;
}

std::string caseFolderName(size_t index, const std::vector<std::pair<std::string, std::string>>& chosen) {
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

YAML::Node readSceneYaml(const std::string& path) {
  YAML::Node base;
  try {
    base = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError("scene '" + path + "': cannot read the file");
  } catch (const YAML::Exception& e) {
    throw InputError("scene '" + path + "': " + e.what());
  }
  checkDuplicateKeys(base, path);
  return base;
}

void writeCaseScene(const YAML::Node& base, const std::vector<SceneEdit>& edits,
                    const std::string& sceneDir, const std::string& path, const std::string& header) {
  YAML::Node scene = YAML::Clone(base);
  for (const SceneEdit& e : edits) {
    if (e.remove) {
      const auto dot = e.path.find_last_of('.');
      YAML::Node parent = dot == std::string::npos ? scene : locateKey(scene, e.path.substr(0, dot), e.path);
      if (parent.IsMap()) parent.remove(e.path.substr(dot == std::string::npos ? 0 : dot + 1));
      continue;
    }
    YAML::Node target = locateKey(scene, e.path, e.path);
    YAML::Node v;
    try {
      v = YAML::Load(e.value);
    } catch (const YAML::Exception& x) {
      throw InputError(e.path + "=" + e.value + ": not a YAML value (" + x.msg + ")");
    }
    target = v;
  }
  if (scene["geometry"] && scene["geometry"].IsSequence())
    for (auto g : scene["geometry"])
      if (g.IsMap() && g["file"] && g["file"].IsScalar() && fs::path(g["file"].Scalar()).is_relative())
        g["file"] = (fs::path(sceneDir) / g["file"].Scalar()).lexically_normal().string();
  std::ofstream f(path);
  f << "# " << header << "\n" << YAML::Dump(scene) << "\n";
  if (!f) throw InputError(path + ": cannot write the case's scene");
}

std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string selfExecutable() {
  std::error_code ec;
  std::string p = fs::read_symlink("/proc/self/exe", ec).string();
  // A program rebuilt while it runs (a study while `cmake --build` relinks poresph) reads
  // "PATH (deleted)": the cases run the new file at PATH.
  const std::string deleted = " (deleted)";
  if (p.size() > deleted.size() && p.compare(p.size() - deleted.size(), deleted.size(), deleted) == 0)
    p.resize(p.size() - deleted.size());
  return ec || p.empty() ? std::string("poresph") : p;
}

std::string childExecutable() {
  std::error_code ec;
  if (fs::exists("/proc/self/exe", ec) && access("/proc/self/exe", X_OK) == 0) return "/proc/self/exe";
  return selfExecutable();
}

std::string findScript(const std::string& name) {
  const fs::path exe = selfExecutable();
  for (const fs::path& p : {exe.parent_path().parent_path() / "scripts" / name,
                            fs::path("scripts") / name}) {
    std::error_code ec;
    if (fs::exists(p, ec)) return p.string();
  }
  return "";
}

ChildRun runChild(const std::vector<std::string>& argv, const std::string& logPath) {
  ChildRun r;
  if (argv.empty()) return r;
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid < 0) return r;
  if (pid == 0) {
    const int fd = open(logPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    execv(args[0], args.data());
    const char* msg = "poresph: error: cannot start the case's run\n";
    ssize_t ignored = write(2, msg, std::strlen(msg));
    (void)ignored;
    _exit(127);
  }
  int status = 0;
  struct rusage ru {};
  while (wait4(pid, &status, 0, &ru) < 0 && errno == EINTR) {
  }
  r.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  r.cpuSeconds = static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
                 1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
  r.maxRssKiB = ru.ru_maxrss;
  return r;
}

std::string lastErrorLine(const std::string& logPath) {
  std::ifstream log(logPath);
  std::string line, last;
  while (std::getline(log, line))
    if (line.find("error") != std::string::npos || line.find("failure") != std::string::npos) last = line;
  return last;
}

// ================================================================================== study ==

namespace {

struct VaryName {
  std::string name, keys;
  std::string refusal;  ///< non-empty: the name exists but no scene key is behind it
};

const std::vector<VaryName>& varyTable() {
  static const std::vector<VaryName> t = {
      {"spacing", "spacing (m)", ""},
      {"kernel", "kernel (cubic = cubic_spline, wendland = wendland_c2, quintic = quintic_spline, "
                 "gaussian)", ""},
      {"h_over_dx", "h_over_dx", ""},
      {"cfl", "time_step: {adaptive: true, cfl: V}, time_step.dt removed", ""},
      {"dt", "time_step: {adaptive: false, dt: V}, time_step.cfl removed", ""},
      {"integrator", "integrator", ""},
      {"end_time", "end_time", ""},
      {"precision", "fluid.pair_precision (double, float = single: the fluid-fluid pair "
                    "arithmetic; everything else computes in double)", ""},
      {"correction", "",
       "no scene key selects a kernel or gradient correction (the solid always uses the mixed "
       "correction of Eq. 2.63b, the fluid none; docs/operators.md); it is not varied"},
  };
  return t;
}

std::string kernelAlias(const std::string& v) {
  if (v == "cubic") return "cubic_spline";
  if (v == "wendland" || v == "wendland_c2") return "wendland_c2";
  if (v == "quintic") return "quintic_spline";
  return v;
}

std::string fmtNum(double v, int prec = 4) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream o;
  o.precision(prec);
  o << v;
  return o.str();
}

}  // namespace

const std::vector<std::pair<std::string, std::string>>& studyVaryNames() {
  static std::vector<std::pair<std::string, std::string>> out;
  if (out.empty())
    for (const auto& v : varyTable()) out.emplace_back(v.name, v.refusal.empty() ? v.keys : "(refused) " + v.refusal);
  return out;
}

std::pair<std::string, std::vector<std::string>> parseNamedList(const std::string& text,
                                                                const std::string& option,
                                                                const std::string& example) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw InputError(option + " '" + text + "': expected " + example);
  std::pair<std::string, std::vector<std::string>> out{text.substr(0, eq),
                                                       splitTopLevel(text.substr(eq + 1), ',')};
  for (const auto& v : out.second)
    if (v.empty()) throw InputError(option + " '" + text + "': an empty value in the list");
  return out;
}

VaryAxis parseVary(const std::string& text) {
  VaryAxis a;
  std::tie(a.name, a.values) =
      parseNamedList(text, "--vary", "NAME=v1,v2,... (e.g. --vary spacing=2e-4,1e-4)");
  if (a.name.find('.') != std::string::npos) return a;  // a scene key path
  std::vector<std::string> names;
  for (const auto& v : varyTable()) {
    if (v.name == a.name) {
      if (!v.refusal.empty()) throw InputError("--vary " + a.name + ": " + v.refusal);
      if (a.name == "precision") {
        for (auto& k : a.values) {
          if (k == "single") k = "float";
          if (k != "double" && k != "float")
            throw InputError("--vary precision: unknown precision '" + k +
                             "' (double, or float / single: the fluid module's pair_precision)");
        }
      }
      if (a.name == "kernel") {
        const std::vector<std::string> known = {"cubic_spline", "gaussian", "wendland_c2", "quintic_spline"};
        for (auto& k : a.values) {
          k = kernelAlias(k);
          if (std::find(known.begin(), known.end(), k) == known.end())
            throw InputError("--vary kernel: unknown kernel '" + k +
                             "' (cubic, wendland, quintic, gaussian or their scene names "
                             "cubic_spline, wendland_c2, quintic_spline)");
        }
      }
      return a;
    }
    names.push_back(v.name);
  }
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  const std::string guess = closestMatch(a.name, names);
  throw InputError("--vary " + a.name + ": unknown name (names: " + list +
                   "; or a scene key path with a dot, e.g. materials.gas.density)" +
                   (guess.empty() ? std::string() : "; did you mean '" + guess + "'?"));
}

std::vector<SceneEdit> studyEdits(const std::string& name, const std::string& value) {
  if (name == "kernel") return {{"kernel", kernelAlias(value)}};
  if (name == "precision") return {{"fluid.pair_precision", value == "single" ? "float" : value}};
  if (name == "cfl")
    return {{"time_step.adaptive", "true"}, {"time_step.cfl", value}, {"time_step.dt", "", true}};
  if (name == "dt")
    return {{"time_step.adaptive", "false"}, {"time_step.dt", value}, {"time_step.cfl", "", true}};
  return {{name, value}};  // spacing, h_over_dx, integrator, end_time, or a key path
}

std::vector<size_t> markParetoFront(std::vector<StudyRow>& rows, bool cpu) {
  auto cost = [cpu](const StudyRow& r) { return cpu ? r.cpuSeconds : r.wallSeconds; };
  std::vector<size_t> front;
  for (size_t i = 0; i < rows.size(); ++i) {
    rows[i].pareto = false;
    if (!rows[i].healthy || !rows[i].hasError) continue;
    bool dominated = false;
    for (size_t j = 0; j < rows.size() && !dominated; ++j) {
      if (j == i || !rows[j].healthy || !rows[j].hasError) continue;
      const bool le = cost(rows[j]) <= cost(rows[i]) && rows[j].error <= rows[i].error;
      const bool lt = cost(rows[j]) < cost(rows[i]) || rows[j].error < rows[i].error;
      dominated = le && lt;
    }
    if (!dominated) {
      rows[i].pareto = true;
      front.push_back(i);
    }
  }
  std::sort(front.begin(), front.end(),
            [&](size_t a, size_t b) { return cost(rows[a]) < cost(rows[b]); });
  return front;
}

void assignStudyErrors(std::vector<StudyRow>& rows, bool hasValue, double value) {
  for (auto& r : rows) r.hasError = false;
  if (hasValue) {
    for (auto& r : rows)
      if (r.measured) {
        r.error = referenceError(r.value, value);
        r.hasError = true;
        r.errorAgainst = value != 0.0 ? "closed form (relative)" : "closed form 0 (absolute)";
      }
    return;
  }
  long best = -1;
  for (size_t i = 0; i < rows.size(); ++i)
    if (rows[i].healthy && rows[i].measured &&
        (best < 0 || rows[i].particles > rows[static_cast<size_t>(best)].particles))
      best = static_cast<long>(i);
  if (best < 0) return;
  const double ref = rows[static_cast<size_t>(best)].value;
  for (size_t i = 0; i < rows.size(); ++i) {
    if (!rows[i].measured || static_cast<long>(i) == best) continue;
    rows[i].error = referenceError(rows[i].value, ref);
    rows[i].hasError = true;
    rows[i].errorAgainst = "finest run " + rows[static_cast<size_t>(best)].name;
  }
  rows[static_cast<size_t>(best)].errorAgainst = "the finest run (the reference)";
}

void readRunResults(StudyRow& row, const std::string& runDir) {
  {
    std::ifstream f(fs::path(runDir) / "run.log");
    std::string line;
    while (std::getline(f, line)) {
      if (line.rfind("particles:", 0) == 0) row.particles = std::atoll(line.substr(10).c_str());
      if (line.rfind("steps ", 0) == 0) row.steps = std::atoll(line.substr(6).c_str());
    }
  }
  {
    std::ifstream f(fs::path(runDir) / "reference.yaml");
    if (f) {
      try {
        const YAML::Node n = YAML::Load(std::string(std::istreambuf_iterator<char>(f), {}));
        if (n["ok"] && n["ok"].as<bool>() && n["measured"]) {
          row.measured = true;
          row.value = n["measured"].as<double>();
        }
      } catch (const YAML::Exception&) {
      }
    }
  }
  {
    std::ifstream f(fs::path(runDir) / "timeseries.csv");
    std::string line;
    if (!std::getline(f, line)) return;
    const auto header = splitTopLevel(line, ',');
    auto col = [&](const std::string& c) {
      const auto it = std::find(header.begin(), header.end(), c);
      return it == header.end() ? -1 : static_cast<int>(it - header.begin());
    };
    const int kRho = col("fluid_max_density_variation"), kBal = col("solid_energy_balance"),
              kKe = col("solid_kinetic_energy"), kEl = col("solid_elastic_energy");
    double bal0 = NAN, drift = 0.0, scale = 0.0;
    while (std::getline(f, line)) {
      const auto v = splitTopLevel(line, ',');
      auto at = [&](int k) { return k >= 0 && static_cast<size_t>(k) < v.size() ? std::atof(v[static_cast<size_t>(k)].c_str()) : NAN; };
      if (kRho >= 0) row.densityVariation = std::max(row.densityVariation, at(kRho));
      if (kBal >= 0 && kKe >= 0 && kEl >= 0) {
        const double b = at(kBal);
        if (std::isnan(bal0)) bal0 = b;
        drift = std::max(drift, std::abs(b - bal0));
        scale = std::max(scale, at(kKe) + at(kEl));
      }
    }
    if (kBal >= 0 && scale > 0.0) row.energyDrift = drift / scale;
  }
}

void writeStudyTables(const std::string& dir, const std::string& scene, const std::string& quantity,
                      const std::vector<VaryAxis>& axes, const std::vector<StudyRow>& rows,
                      const std::string& cost) {
  std::ofstream csv(fs::path(dir) / "study.csv"), md(fs::path(dir) / "study.md");
  csv << "case";
  for (const auto& a : axes) csv << "," << a.name;
  csv << ",status,healthy,quantity,measured,error,error_against,pareto,wall_s,cpu_s,peak_rss_mib,"
         "particles,steps,max_density_variation,energy_drift\n";
  md << "# Study of " << scene << "\n\nQuantity: `" << quantity
     << "`; error against " << (rows.empty() ? std::string("-") : [&] {
          for (const auto& r : rows)
            if (r.hasError) return r.errorAgainst;
          return std::string("-");
        }())
     << ". Pareto front (no other healthy run both cheaper in " << (cost == "cpu" ? "CPU" : "wall")
     << " time and more accurate): **bold**.\n\n";
  md << "| case";
  for (const auto& a : axes) md << " | " << a.name;
  md << " | status | measured | error | wall (s) | CPU (s) | peak RSS (MiB) | particles | steps | "
        "max drho/rho | energy drift |\n|---";
  for (size_t k = 0; k < axes.size() + 10; ++k) md << "|---";
  md << "|\n";
  for (const auto& r : rows) {
    std::string status = r.status;
    for (auto& ch : status)
      if (ch == '\n' || ch == '|' || ch == ',' || ch == '"') ch = ' ';
    csv << r.name;
    for (const auto& [k, v] : r.chosen) csv << "," << (v.find(',') != std::string::npos ? "\"" + v + "\"" : v);
    csv << "," << status << "," << (r.healthy ? 1 : 0) << "," << quantity << ","
        << (r.measured ? fmtNum(r.value, 10) : "") << "," << (r.hasError ? fmtNum(r.error, 6) : "")
        << "," << r.errorAgainst << "," << (r.pareto ? 1 : 0) << "," << fmtNum(r.wallSeconds, 6)
        << "," << fmtNum(r.cpuSeconds, 6) << "," << fmtNum(static_cast<double>(r.maxRssKiB) / 1024.0, 5)
        << "," << r.particles << "," << r.steps << ","
        << (r.densityVariation >= 0 ? fmtNum(r.densityVariation, 4) : "") << ","
        << (r.energyDrift >= 0 ? fmtNum(r.energyDrift, 4) : "") << "\n";
    const std::string b = r.pareto ? "**" : "";
    md << "| " << b << r.name << b;
    for (const auto& [k, v] : r.chosen) md << " | " << v;
    md << " | " << status << " | " << (r.measured ? fmtNum(r.value, 6) : "-") << " | "
       << (r.hasError ? b + fmtNum(r.error, 3) + b : "-") << " | " << fmtNum(r.wallSeconds, 3)
       << " | " << fmtNum(r.cpuSeconds, 3) << " | "
       << fmtNum(static_cast<double>(r.maxRssKiB) / 1024.0, 4) << " | " << r.particles << " | "
       << r.steps << " | " << (r.densityVariation >= 0 ? fmtNum(r.densityVariation, 3) : "-")
       << " | " << (r.energyDrift >= 0 ? fmtNum(r.energyDrift, 3) : "-") << " |\n";
  }
}

std::vector<StudyRow> runStudy(const StudyOptions& o) {
  // ---- options and the scene, checked before anything is written ----
  std::vector<VaryAxis> axes;
  for (const auto& v : o.vary) axes.push_back(parseVary(v));
  if (axes.empty()) throw InputError("--vary: give at least one NAME=v1,v2,... to study");
  for (size_t i = 0; i < axes.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (axes[i].name == axes[j].name) throw InputError("--vary " + axes[i].name + ": given twice");
  std::vector<SceneEdit> fixed;
  for (const auto& s : o.sets) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == s.size())
      throw InputError("--set '" + s + "': expected key.path=value (one value for every run)");
    fixed.push_back({s.substr(0, eq), s.substr(eq + 1)});
  }
  const YAML::Node base = readSceneYaml(o.scene);
  if (o.out.empty()) throw InputError("--out: give the study's folder");
  if (o.cost != "wall" && o.cost != "cpu")
    throw InputError("--cost '" + o.cost + "': expected wall or cpu");
  for (const auto& a : axes)  // the precision is the fluid module's key: never add a fluid module
    if (a.name == "precision" && !base["fluid"])
      throw InputError("--vary precision: scene '" + o.scene +
                       "' has no `fluid:` section; the precision varied is the fluid module's "
                       "pair_precision (the solid and the other modules compute in double)");
  // The reference: read from the base scene with the --set edits (so --set reference.value=...
  // works), through the scene parser.
  ReferenceSpec reference;
  {
    const fs::path tmp = fs::temp_directory_path() /
                         ("poresph_study_check_" + std::to_string(getpid()) + ".yaml");
    writeCaseScene(base, fixed, fs::absolute(o.scene).parent_path().string(), tmp.string(),
                   o.scene + " (poresph study: checking the --set edits)");
    try {
      SceneOptions so;
      so.buildParticles = false;
      so.initialise = false;
      so.checkMemory = false;
      reference = loadScene(tmp.string(), so).reference;
    } catch (const InputError& e) {
      fs::remove(tmp);
      std::string msg = e.what();
      const auto at = msg.find(tmp.string());
      if (at != std::string::npos) msg.replace(at, tmp.string().size(), o.scene + " (with --set)");
      throw InputError(msg);
    }
    fs::remove(tmp);
  }
  if (!reference.declared)
    throw InputError("scene '" + o.scene +
                     "': declares no `reference:` quantity for the study to measure; add e.g. "
                     "`reference: {quantity: kinetic_energy, at: end}` (docs/choosing-settings.md) "
                     "or pass --set reference.quantity=COLUMN");
  std::error_code ec;
  if (fs::exists(o.out, ec) && !fs::is_empty(o.out, ec) && !o.overwrite)
    throw InputError("--out '" + o.out +
                     "': the folder exists and is not empty; choose a new one, or pass --overwrite "
                     "to replace the runs in it");
  std::vector<std::pair<std::string, std::vector<std::string>>> grid;
  for (const auto& a : axes) grid.emplace_back(a.name, a.values);
  const auto cases = expandGrid(grid, 1000);
  fs::create_directories(o.out, ec);
  if (ec) throw InputError("--out '" + o.out + "': cannot create the folder: " + ec.message());

  const std::string exe = o.executable.empty() ? childExecutable() : o.executable;
  const std::string sceneDir = fs::absolute(o.scene).parent_path().string();
  std::vector<StudyRow> rows;
  std::cerr << "poresph study: " << cases.size() << " runs of " << o.scene << " in " << o.out
            << " (quantity " << reference.quantity << ")\n";
  for (size_t c = 0; c < cases.size(); ++c) {
    StudyRow row;
    row.chosen = cases[c];
    row.name = caseFolderName(c, row.chosen);
    const fs::path dir = fs::path(o.out) / row.name;
    if (o.overwrite) fs::remove_all(dir, ec);
    fs::create_directories(dir, ec);
    std::vector<SceneEdit> edits = fixed;
    std::string header = o.scene + " with";
    for (const auto& [k, v] : row.chosen) {
      for (const auto& e : studyEdits(k, v)) edits.push_back(e);
      header += " " + k + "=" + v;
    }
    header += " (poresph study)";
    const fs::path scenePath = dir / "scene.yaml";
    try {
      writeCaseScene(base, edits, sceneDir, scenePath.string(), header);
      SceneOptions so;
      so.buildParticles = false;
      so.initialise = false;
      so.checkMemory = false;
      loadScene(scenePath.string(), so);
    } catch (const InputError& e) {
      row.status = std::string("bad scene: ") + e.what();
      std::cerr << "  " << row.name << ": " << row.status << "\n";
      rows.push_back(row);
      continue;
    }
    std::vector<std::string> argv = {exe, "run", scenePath.string(), "--out", (dir / "run").string(), "--force"};
    if (!o.threads.empty()) {
      argv.push_back("--threads");
      argv.push_back(o.threads);
    }
    std::cerr << "  " << row.name << ": running" << std::flush;
    const ChildRun run = runChild(argv, (dir / "log.txt").string());
    row.code = run.code;
    row.wallSeconds = run.wallSeconds;
    row.cpuSeconds = run.cpuSeconds;
    row.maxRssKiB = run.maxRssKiB;
    row.healthy = run.code == 0;
    if (run.code == 0) {
      row.status = "finished";
    } else {
      std::string line = lastErrorLine((dir / "log.txt").string());
      const auto chk = line.find("check '");
      if (run.code == 3 && chk != std::string::npos) {
        const auto endq = line.find('\'', chk + 7);
        row.status = "unstable: " + line.substr(chk + 7, endq - chk - 7);
      } else if (run.code == 3) {
        row.status = "unstable: " + (line.find("NaN") != std::string::npos || line.find("not finite") != std::string::npos
                                         ? std::string("not finite")
                                         : std::string("numerical failure"));
      } else {
        row.status = (run.code == 2 ? "bad input (exit 2)" : "failed (exit " + std::to_string(run.code) + ")");
      }
      if (!line.empty()) {
        if (line.size() > 160) line = line.substr(0, 157) + "...";
        row.status += " - " + line;
      }
    }
    readRunResults(row, (dir / "run").string());
    std::cerr << " -> " << row.status << ", wall " << fmtNum(row.wallSeconds, 3) << " s";
    if (row.measured) std::cerr << ", " << reference.quantity << " = " << fmtNum(row.value, 6);
    std::cerr << "\n";
    rows.push_back(row);
  }
  assignStudyErrors(rows, reference.hasValue, reference.value);
  markParetoFront(rows, o.cost == "cpu");
  writeStudyTables(o.out, o.scene, reference.quantity, axes, rows, o.cost);
  std::cout << "study:        " << (fs::path(o.out) / "study.csv").string() << ", "
            << (fs::path(o.out) / "study.md").string() << "\n";
  if (!o.noPlot) {
    const std::string script = findScript("plot_study.py");
    if (script.empty()) {
      std::cerr << "poresph study: scripts/plot_study.py not found: no plot\n";
    } else {
      const std::vector<std::string> argv = {"/usr/bin/python3", script,
                                             (fs::path(o.out) / "study.csv").string(), "--out",
                                             (fs::path(o.out) / "study.png").string(), "--cost",
                                             o.cost};
      const ChildRun p = runChild(argv, (fs::path(o.out) / "plot.log").string());
      if (p.code == 0)
        std::cout << "plot:         " << (fs::path(o.out) / "study.png").string() << "\n";
      else
        std::cerr << "poresph study: the plot failed (see " << (fs::path(o.out) / "plot.log").string() << ")\n";
    }
  }
  return rows;
}

}  // namespace poresph
