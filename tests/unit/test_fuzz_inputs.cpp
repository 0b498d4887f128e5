// Fuzz test of the poresph command line (issue 12, "runs that never lie"): broken scenes made
// from the shipped samples (samples/*.yaml) and broken images made from data/ketton_128.raw are
// given to the built binary, each in a child process with a deadline. For every case:
//   - no signal (no crash), no exit code 1 (an unexpected exception: a bug), no hang;
//   - for a fault class that is invalid by construction: exit code 2, stderr names the file
//     (the path exactly as given on the command line) and `run` did not create its --out folder.
// A mutation that may leave the scene valid (a number made negative, a region dropped, ...) may
// run: every scene carries `max_steps: 3` (never a mutation target, and text mutations spare its
// line), so such a run is short; exit code 0 or 3 (a refused numerical blow-up) is then fine.
// The cases are generated deterministically (fixed seed). Per fault class the test prints a
// table (cases, exit 0 / 2 / 3 counts) and writes it to <build>/fuzz_inputs.csv (docs quote it:
// docs/reliability.md, "Fuzz test").
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace {

// ---- the knobs --------------------------------------------------------------------------------
constexpr int kScenesPerClass = 24;   // structural and text mutations of the samples, per class
constexpr int kFileCasesPerClass = 4; // empty / binary file, directory, missing file, options
constexpr int kImagesPerClass = 6;    // image fault classes
constexpr double kTimeoutSeconds = 20.0;  // per case; a case past it is a hang
constexpr std::uint64_t kSeed = 20261123;
constexpr int kParallel = 2;          // child processes at a time
// -------------------------------------------------------------------------------------------------

// PORESPH_FUZZ_BINARY=path runs the cases against another build (e.g. an older commit's).
const fs::path kBinary = std::getenv("PORESPH_FUZZ_BINARY")
                             ? fs::path(std::getenv("PORESPH_FUZZ_BINARY"))
                             : fs::path(PORESPH_BINARY_DIR) / "poresph";
const fs::path kSource = fs::path(PORESPH_SOURCE_DIR);

fs::path workDir() {
  static const fs::path d = [] {
    const fs::path p = fs::path(PORESPH_BINARY_DIR) / ("tmp_fuzz_inputs_" + std::to_string(getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
  }();
  return d;
}

/// splitmix64: the same numbers on every platform and standard library.
struct Rng {
  std::uint64_t s;
  explicit Rng(std::uint64_t seed) : s(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  size_t below(size_t n) { return n == 0 ? 0 : static_cast<size_t>(next() % n); }
  template <class T>
  const T& pick(const std::vector<T>& v) { return v[below(v.size())]; }
};

// ---- a small YAML tree that we emit ourselves (raw scalar text, full control of the output) ----
struct Y {
  enum Kind { Scalar, Seq, Map } kind = Scalar;
  std::string text;                              // Scalar: emitted as is
  std::vector<Y> seq;                            // Seq
  std::vector<std::pair<std::string, Y>> map;    // Map, in file order
  const Y* find(const std::string& k) const {
    for (const auto& [key, v] : map)
      if (key == k) return &v;
    return nullptr;
  }
};

Y fromYaml(const YAML::Node& n) {
  Y y;
  if (n.IsMap()) {
    y.kind = Y::Map;
    for (const auto& kv : n) y.map.emplace_back(kv.first.Scalar(), fromYaml(kv.second));
  } else if (n.IsSequence()) {
    y.kind = Y::Seq;
    for (const auto& e : n) y.seq.push_back(fromYaml(e));
  } else {
    y.text = n.IsNull() ? "null" : n.Scalar();
  }
  return y;
}

std::string flow(const Y& y) {
  if (y.kind == Y::Scalar) return y.text;
  std::string s = y.kind == Y::Seq ? "[" : "{";
  bool first = true;
  if (y.kind == Y::Seq)
    for (const Y& e : y.seq) s += (first ? "" : ", ") + flow(e), first = false;
  else
    for (const auto& [k, v] : y.map) s += (first ? "" : ", ") + k + ": " + flow(v), first = false;
  return s + (y.kind == Y::Seq ? "]" : "}");
}

/// Block style at the top (one key per line, list items one per line), flow style below.
std::string emit(const Y& root) {
  std::string s;
  for (const auto& [k, v] : root.map) {
    if (v.kind == Y::Seq && !v.seq.empty() && v.seq.front().kind == Y::Map) {
      s += k + ":\n";
      for (const Y& e : v.seq) s += "  - " + flow(e) + "\n";
    } else if (v.kind == Y::Map && !v.map.empty()) {
      s += k + ":\n";
      for (const auto& [k2, v2] : v.map) {
        if (v2.kind == Y::Seq && !v2.seq.empty() && v2.seq.front().kind == Y::Map) {
          s += "  " + k2 + ":\n";
          for (const Y& e : v2.seq) s += "    - " + flow(e) + "\n";
        } else {
          s += "  " + k2 + ": " + flow(v2) + "\n";
        }
      }
    } else {
      s += k + ": " + flow(v) + "\n";
    }
  }
  return s;
}

// A node of the tree by path: keys of mappings and indices of sequences.
struct Step {
  bool index = false;
  std::string key;
  size_t i = 0;
};
using Path = std::vector<Step>;

std::string pathText(const Path& p) {
  std::string s;
  for (const Step& st : p) s += st.index ? "[" + std::to_string(st.i) + "]" : (s.empty() ? "" : ".") + st.key;
  return s;
}

Y& at(Y& root, const Path& p) {
  Y* y = &root;
  for (const Step& st : p) {
    if (st.index) {
      y = &y->seq[st.i];
    } else {
      for (auto& kv : y->map)
        if (kv.first == st.key) { y = &kv.second; break; }
    }
  }
  return *y;
}

void collect(const Y& y, Path& p, std::vector<Path>& out) {
  out.push_back(p);
  if (y.kind == Y::Map) {
    for (const auto& [k, v] : y.map) {
      if (p.empty() && k == "max_steps") continue;  // the cap that keeps valid mutations short
      p.push_back(Step{false, k, 0});
      collect(v, p, out);
      p.pop_back();
    }
  } else if (y.kind == Y::Seq) {
    for (size_t i = 0; i < y.seq.size(); ++i) {
      p.push_back(Step{true, "", i});
      collect(y.seq[i], p, out);
      p.pop_back();
    }
  }
}

bool isNumber(const Y& y) {
  if (y.kind != Y::Scalar || y.text.empty()) return false;
  char* end = nullptr;
  std::strtod(y.text.c_str(), &end);
  return end && *end == '\0';
}

/// Keys whose absence makes a scene invalid (docs/scene-format.md, docs/fluid.md, docs/solid.md),
/// given the mapping that holds them and the scene.
bool isRequired(const Y& root, const Path& p) {
  if (p.empty() || p.back().index) return false;
  const std::string& k = p.back().key;
  const std::string parent = pathText(Path(p.begin(), p.end() - 1));
  if (p.size() == 1)
    return k == "dimension" || k == "domain" || k == "spacing" || k == "end_time" ||
           k == "time_step" || k == "output" || k == "materials" || k == "geometry";
  Y& holder = at(const_cast<Y&>(root), Path(p.begin(), p.end() - 1));
  if (parent == "domain") return k == "lo" || k == "hi";
  if (parent == "output") return k == "every_time" || k == "every_steps";
  if (parent == "time_step") {
    const Y* a = holder.find("adaptive");
    return k == "dt" && !(a && a->text == "true");
  }
  if (p.size() == 3 && p[0].key == "materials") {
    if (k == "name" || k == "model" || k == "density") return true;
    const Y* model = holder.find("model");
    const std::string m = model ? model->text : "";
    if (m == "fluid") return k == "sound_speed" || k == "viscosity";
    if (m == "elastic") {
      const Y* dim = root.find("dimension");
      return k == "young_modulus" || (k == "poisson_ratio" && dim && dim->text != "1");
    }
    return false;
  }
  if (p.size() == 3 && p[0].key == "geometry") {
    if (k == "shape" || k == "material") return true;
    const Y* shape = holder.find("shape");
    const std::string s = shape ? shape->text : "";
    return s == "box" ? (k == "lo" || k == "hi") : (k == "centre" || k == "radius");
  }
  if (p.size() >= 4 && p[0].key == "solid" && p[1].key == "boundaries") {
    if (p.size() == 4) {
      const Y* type = holder.find("type");
      const std::string t = type ? type->text : "";
      if (k == "type") return true;
      if (t == "traction") return k == "traction";
      if (t == "pressure") return k == "pressure";
      if (t == "symmetry") return k == "mirror";
      return false;
    }
    if (p.size() == 5) return k == "min" || k == "max" || k == "point" || k == "normal" ||
                              k == "centre" || k == "r_min" || k == "r_max";
  }
  if (p.size() == 3 && p[0].key == "solid" && p[1].key == "initial_velocity")
    return k == "amplitude" || k == "wavevector";
  return false;
}

// ---- running the binary with a deadline ----------------------------------------------------------
struct Outcome {
  int code = -1;        // exit code, -1 if none
  int signal = 0;       // terminating signal, 0 if none
  bool timedOut = false;
  double seconds = 0.0;
  std::string err;      // stderr (and stdout)
};

struct Child {
  pid_t pid = -1;
  fs::path log;
  std::chrono::steady_clock::time_point start;
};

Child spawn(const std::vector<std::string>& args, const fs::path& log) {
  Child c;
  c.log = log;
  c.start = std::chrono::steady_clock::now();
  std::vector<char*> argv;
  std::string bin = kBinary.string();
  argv.push_back(bin.data());
  std::vector<std::string> copy = args;
  for (auto& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  c.pid = fork();
  if (c.pid == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    setenv("OMP_NUM_THREADS", "1", 1);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return c;
}

/// Waits for the child; kills it (SIGKILL) past the deadline.
bool poll(Child& c, Outcome& o, bool block) {
  for (;;) {
    int status = 0;
    const pid_t r = waitpid(c.pid, &status, WNOHANG);
    const double t =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - c.start).count();
    if (r == c.pid) {
      o.seconds = t;
      if (WIFEXITED(status)) o.code = WEXITSTATUS(status);
      if (WIFSIGNALED(status)) o.signal = WTERMSIG(status);
      std::ifstream in(c.log);
      std::ostringstream s;
      s << in.rdbuf();
      o.err += s.str();
      fs::remove(c.log);
      return true;
    }
    if (t > kTimeoutSeconds) {
      kill(c.pid, SIGKILL);
      waitpid(c.pid, &status, 0);
      o.timedOut = true;
      o.seconds = t;
      std::ifstream in(c.log);
      std::ostringstream s;
      s << in.rdbuf();
      o.err += s.str();
      fs::remove(c.log);
      return true;
    }
    if (!block) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

// ---- the cases -------------------------------------------------------------------------------------
struct Case {
  std::string cls;         // fault class
  bool invalid = false;    // invalid by construction
  std::string what;        // what was done (for messages)
  std::vector<std::string> args;
  std::string named;       // the text stderr must contain when invalid (the path as given)
  fs::path outDir;         // `run --out` folder that must not appear when invalid
  Outcome outcome;
};

void writeBytes(const fs::path& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string randomBytes(Rng& rng, size_t n) {
  std::string s(n, '\0');
  for (char& c : s) c = static_cast<char>(rng.below(256));
  return s;
}

class CaseMaker {
 public:
  explicit CaseMaker(Rng& rng) : rng_(rng) {
    for (const auto& e : fs::directory_iterator(kSource / "samples"))
      if (e.path().extension() == ".yaml") samples_.push_back(e.path());
    std::sort(samples_.begin(), samples_.end());
    for (const auto& s : samples_) {
      Y y = fromYaml(YAML::LoadFile(s.string()));
      Y cap;
      cap.text = "3";
      y.map.insert(y.map.begin(), {"max_steps", cap});
      trees_.push_back(y);
      names_.push_back(s.stem().string());
    }
  }

  size_t sampleCount() const { return samples_.size(); }

  /// A scene case: `text` written to a fresh file and run with a fresh --out.
  Case scene(const std::string& cls, bool invalid, const std::string& what, const std::string& text) {
    Case c;
    c.cls = cls;
    c.invalid = invalid;
    c.what = what;
    const std::string id = std::to_string(++count_);
    const fs::path file = workDir() / ("case_" + id + "_" + cls + ".yaml");
    writeBytes(file, text);
    c.outDir = workDir() / ("out_" + id);
    c.args = {"run", file.string(), "--out", c.outDir.string()};
    c.named = file.string();
    return c;
  }

  Case sceneAt(const std::string& cls, bool invalid, const std::string& what, const fs::path& file) {
    Case c;
    c.cls = cls;
    c.invalid = invalid;
    c.what = what;
    c.outDir = workDir() / ("out_" + std::to_string(++count_));
    c.args = {"run", file.string(), "--out", c.outDir.string()};
    c.named = file.string();
    return c;
  }

  /// Applies a structural mutation of class `cls` to a sample; false if the sample has no target.
  bool mutate(const std::string& cls, size_t sample, std::string& text, std::string& what) {
    Y y = trees_[sample];
    std::vector<Path> all;
    Path p;
    collect(y, p, all);
    std::vector<Path> targets;
    for (const Path& q : all) {
      if (q.empty()) {
        if (cls == "unknown_key") targets.push_back(q);
        continue;
      }
      const Y& n = at(y, q);
      const bool scalarList = n.kind == Y::Seq && !n.seq.empty() && n.seq.front().kind == Y::Scalar;
      const bool mapList = n.kind == Y::Seq && !n.seq.empty() && n.seq.front().kind == Y::Map;
      bool ok = false;
      if (cls == "required_key_deleted") ok = isRequired(y, q);
      else if (cls == "unknown_key") ok = n.kind == Y::Map;
      else if (cls == "duplicate_key") ok = n.kind == Y::Map && !n.map.empty();
      else if (cls == "spacing_tiny") ok = q.size() == 1 && q[0].key == "spacing";
      else if (cls == "solid_boundary_selects_nothing")
        ok = q.size() == 3 && q[0].key == "solid" && q[1].key == "boundaries" && n.find("box") &&
             !n.find("shell") && !n.find("material");
      else if (cls == "wrong_type_string" || cls == "wrong_type_bool")
        ok = isNumber(n) || n.kind != Y::Scalar;
      else if (cls == "wrong_type_list") ok = n.kind != Y::Seq;
      else if (cls == "wrong_type_mapping") ok = n.kind != Y::Map;
      else if (cls.rfind("number_", 0) == 0) ok = isNumber(n);
      else if (cls == "vector_length") ok = scalarList;
      else if (cls == "list_length") ok = mapList;
      if (ok) targets.push_back(q);
    }
    if (targets.empty()) return false;
    const Path q = rng_.pick(targets);
    Y& n = at(y, q);
    const std::string where = names_[sample] + ": " + (q.empty() ? "(top level)" : pathText(q));
    if (cls == "required_key_deleted") {
      Y& holder = at(y, Path(q.begin(), q.end() - 1));
      holder.map.erase(std::remove_if(holder.map.begin(), holder.map.end(),
                                      [&](const auto& kv) { return kv.first == q.back().key; }),
                       holder.map.end());
      what = where + " deleted";
    } else if (cls == "unknown_key") {
      Y v;
      v.text = std::to_string(rng_.below(100));
      const std::string key = "fuzz_unknown_" + std::to_string(rng_.below(1000));
      n.map.insert(n.map.begin() + static_cast<long>(rng_.below(n.map.size() + 1)), {key, v});
      what = where + ": key '" + key + "' added";
    } else if (cls == "duplicate_key") {
      // The same key twice, the second with another value: which one counts would be a guess.
      const size_t k = rng_.below(n.map.size());
      auto entry = n.map[k];
      Y v;
      v.text = entry.second.kind == Y::Scalar && entry.second.text != "1" ? "1" : "2";
      n.map.insert(n.map.begin() + static_cast<long>(k + 1 + rng_.below(n.map.size() - k)),
                   {entry.first, v});
      what = where + ": key '" + entry.first + "' repeated with value '" + v.text + "'";
    } else if (cls == "solid_boundary_selects_nothing") {
      // The boundary's box moved far outside the body: it selects no particle.
      for (auto& kv : n.map)
        if (kv.first == "box") {
          for (auto& [k, v] : kv.second.map)
            for (Y& c : v.seq) c.text = k == "min" ? "90" : "91";
          what = where + ": box " + flow(kv.second);
        }
    } else if (cls == "spacing_tiny") {
      // 1e9 (at least 1e11 particles in 1D, far beyond any memory), 1e30 or 1e300 times finer
      // (lattice indices overflow any integer).
      const std::string old = n.text;
      const double factor = std::vector<double>{1e-9, 1e-30, 1e-300}[rng_.below(3)];
      char buf[64];
      std::snprintf(buf, sizeof(buf), "%.6g", std::strtod(old.c_str(), nullptr) * factor);
      n.text = buf;
      what = where + ": '" + old + "' -> '" + n.text + "'";
    } else if (cls.rfind("wrong_type_", 0) == 0) {
      Y v;
      if (cls == "wrong_type_string") v.text = "\"fuzz text\"";
      if (cls == "wrong_type_bool") v.text = rng_.below(2) ? "true" : "false";
      if (cls == "wrong_type_list") v = fromYaml(YAML::Load("[1, 2]"));
      if (cls == "wrong_type_mapping") v = fromYaml(YAML::Load("{fuzz: 1}"));
      what = where + ": '" + flow(n) + "' -> '" + flow(v) + "'";
      n = v;
    } else if (cls.rfind("number_", 0) == 0) {
      const std::string old = n.text;
      if (cls == "number_negative") n.text = old[0] == '-' ? old.substr(1) : "-" + old;
      if (cls == "number_zero") n.text = "0";
      if (cls == "number_huge") n.text = rng_.below(2) ? "1.0e300" : "9223372036854775807";
      if (cls == "number_nan") n.text = ".nan";
      if (cls == "number_inf") n.text = rng_.below(2) ? ".inf" : "-.inf";
      what = where + ": '" + old + "' -> '" + n.text + "'";
    } else if (cls == "vector_length" || cls == "list_length") {
      const size_t k = rng_.below(n.seq.size());
      if (rng_.below(2) || (cls == "list_length" && n.seq.size() == 1)) {
        n.seq.insert(n.seq.begin() + static_cast<long>(k), n.seq[k]);
        what = where + ": item " + std::to_string(k) + " repeated";
      } else {
        n.seq.erase(n.seq.begin() + static_cast<long>(k));
        what = where + ": item " + std::to_string(k) + " removed";
      }
    }
    text = emit(y);
    return true;
  }

  std::string emitted(size_t sample) const { return emit(trees_[sample]); }
  const std::string& name(size_t sample) const { return names_[sample]; }

 private:
  Rng& rng_;
  std::vector<fs::path> samples_;
  std::vector<Y> trees_;
  std::vector<std::string> names_;
  int count_ = 0;
};

std::vector<Case> makeCases() {
  Rng rng(kSeed);
  CaseMaker maker(rng);
  std::vector<Case> cases;
  const size_t nSamples = maker.sampleCount();
  size_t sample = 0;
  auto nextSample = [&] { return (sample++) % nSamples; };

  // Structural mutations (on the parsed tree, emitted again).
  const std::vector<std::pair<std::string, bool>> structural = {
      {"required_key_deleted", true}, {"unknown_key", true},       {"duplicate_key", true},
      {"spacing_tiny", true},         {"solid_boundary_selects_nothing", true},
      {"wrong_type_string", true},
      {"wrong_type_list", true},      {"wrong_type_mapping", true}, {"wrong_type_bool", true},
      {"number_negative", false},     {"number_zero", false},      {"number_huge", false},
      {"number_nan", true},           {"number_inf", true},        {"vector_length", true},
      {"list_length", false}};
  for (const auto& [cls, invalid] : structural) {
    for (int k = 0; k < kScenesPerClass; ++k) {
      std::string text, what;
      size_t s = nextSample();
      for (size_t tries = 0; tries < nSamples && !maker.mutate(cls, s, text, what); ++tries)
        s = nextSample();
      cases.push_back(maker.scene(cls, invalid, what, text));
    }
  }

  // Text mutations of the emitted scene (the first line, `max_steps: 3`, is spared).
  for (int k = 0; k < kScenesPerClass; ++k) {
    const size_t s = nextSample();
    const std::string text = maker.emitted(s);
    const size_t geo = text.find("\ngeometry:");
    const size_t cut = rng.below(geo + 1);
    cases.push_back(maker.scene("truncated_before_geometry", true,
                                maker.name(s) + ": first " + std::to_string(cut) + " bytes",
                                text.substr(0, cut)));
  }
  for (int k = 0; k < kScenesPerClass; ++k) {
    const size_t s = nextSample();
    const std::string text = maker.emitted(s);
    const size_t first = text.find('\n') + 1;
    const size_t cut = first + rng.below(text.size() - first);
    cases.push_back(maker.scene("truncated_anywhere", false,
                                maker.name(s) + ": first " + std::to_string(cut) + " bytes",
                                text.substr(0, cut)));
  }
  for (const std::string cls : {"bytes_inserted", "bytes_replaced"}) {
    for (int k = 0; k < kScenesPerClass; ++k) {
      const size_t s = nextSample();
      std::string text = maker.emitted(s);
      const size_t first = text.find('\n') + 1;
      const size_t n = 1 + rng.below(8);
      const size_t pos = first + rng.below(text.size() - first - n);
      const std::string bytes = randomBytes(rng, n);
      if (cls == "bytes_inserted") text.insert(pos, bytes);
      else text.replace(pos, n, bytes);
      cases.push_back(maker.scene(cls, false,
                                  maker.name(s) + ": " + std::to_string(n) + " bytes at " +
                                      std::to_string(pos),
                                  text));
    }
  }

  // Whole files.
  for (int k = 0; k < kFileCasesPerClass; ++k) {
    cases.push_back(maker.scene("empty_file", true, "0 bytes", ""));
    const size_t n = 1 + rng.below(4096);
    cases.push_back(maker.scene("binary_file", true, std::to_string(n) + " random bytes",
                                randomBytes(rng, n)));
    const fs::path dir = workDir() / ("scene_dir_" + std::to_string(k) + ".yaml");
    fs::create_directories(dir);
    cases.push_back(maker.sceneAt("directory", true, "a directory", dir));
    cases.push_back(maker.sceneAt("missing_file", true, "no such file",
                                  workDir() / ("no_such_scene_" + std::to_string(k) + ".yaml")));
  }

  // Bad options of `run` on a valid scene (the first sample, capped at 3 steps).
  {
    const fs::path good = workDir() / "good_scene.yaml";
    writeBytes(good, maker.emitted(0));
    const std::vector<std::string> threads = {"0", "-1", "abc", "1e9", "2147483648", "100000"};
    for (size_t k = 0; k < threads.size(); ++k) {
      Case c = maker.sceneAt("option_threads", true, "--threads " + threads[k], good);
      c.args.push_back("--threads");
      c.args.push_back(threads[k]);
      c.named = "--threads";
      cases.push_back(c);
    }
    for (int k = 0; k < kFileCasesPerClass; ++k) {
      // --out names an existing file, or a folder below an existing file.
      const fs::path file = workDir() / ("out_is_a_file_" + std::to_string(k));
      writeBytes(file, "precious");
      Case c = maker.sceneAt("option_out_not_a_folder", true, "--out is a file", good);
      c.args[3] = (k % 2 ? file / "below" : file).string();
      c.named = c.args[3];
      c.outDir.clear();
      cases.push_back(c);
    }
    for (int k = 0; k < kFileCasesPerClass; ++k) {
      // --restart from a missing file, an empty one, random bytes, a directory.
      Case c = maker.sceneAt("option_restart_bad_checkpoint", true, "", good);
      fs::path ck = workDir() / ("checkpoint_" + std::to_string(k) + ".h5");
      if (k % 4 == 1) writeBytes(ck, "");
      if (k % 4 == 2) writeBytes(ck, randomBytes(rng, 1 + rng.below(4096)));
      if (k % 4 == 3) fs::create_directories(ck);
      c.what = k % 4 == 0 ? "missing" : k % 4 == 1 ? "empty" : k % 4 == 2 ? "random bytes" : "a directory";
      c.args.push_back("--restart");
      c.args.push_back(ck.string());
      c.named = ck.string();
      cases.push_back(c);
    }
  }

  // Images, from data/ketton_128.raw (128^3 voxels, 8 bit).
  const std::string ketton = readBytes(kSource / "data" / "ketton_128.raw");
  int imageId = 0;
  auto image = [&](const std::string& cls, bool invalid, const std::string& what,
                   const fs::path& file, const std::vector<long>& shape,
                   const std::string& named = "") {
    Case c;
    c.cls = cls;
    c.invalid = invalid;
    c.what = what + ", --shape " + std::to_string(shape[0]) + " " + std::to_string(shape[1]) +
             " " + std::to_string(shape[2]);
    c.args = {"image", file.string(), "--shape", std::to_string(shape[0]),
              std::to_string(shape[1]), std::to_string(shape[2])};
    c.named = named.empty() ? file.string() : named;
    cases.push_back(c);
  };
  auto imageFile = [&](const std::string& bytes) {
    const fs::path f = workDir() / ("image_" + std::to_string(++imageId) + ".raw");
    writeBytes(f, bytes);
    return f;
  };
  const std::vector<long> full = {128, 128, 128};
  for (int k = 0; k < kImagesPerClass; ++k) {
    const size_t cut = rng.below(ketton.size());
    image("image_truncated", true, "ketton cut to " + std::to_string(cut) + " bytes",
          imageFile(ketton.substr(0, cut)), full);
  }
  const fs::path ketton_path = kSource / "data" / "ketton_128.raw";
  for (int k = 0; k < kImagesPerClass; ++k) {
    std::vector<long> shape(3);
    do {
      for (long& n : shape) {
        const size_t r = rng.below(4);
        n = r == 0 ? 2147483647L : r == 1 ? static_cast<long>(1 + rng.below(100000))
                                          : static_cast<long>(1 + rng.below(300));
      }
    } while (static_cast<double>(shape[0]) * static_cast<double>(shape[1]) *
                 static_cast<double>(shape[2]) == 128.0 * 128.0 * 128.0);
    image("image_wrong_shape", true, "ketton", ketton_path, shape);
  }
  const std::vector<std::vector<long>> permuted = {{256, 64, 128}, {64, 256, 128}, {2048, 32, 32},
                                                   {128, 16384, 1}, {1, 1, 2097152}, {512, 512, 8}};
  for (int k = 0; k < kImagesPerClass; ++k)
    image("image_other_shape_same_size", false, "ketton", ketton_path,
          permuted[static_cast<size_t>(k) % permuted.size()]);
  for (int k = 0; k < kImagesPerClass; ++k) {
    const std::vector<long> shape = {static_cast<long>(1 + rng.below(40)),
                                     static_cast<long>(1 + rng.below(40)),
                                     static_cast<long>(1 + rng.below(40))};
    const size_t n = static_cast<size_t>(shape[0] * shape[1] * shape[2]);
    image("image_random_bytes", false, std::to_string(n) + " random bytes",
          imageFile(randomBytes(rng, n)), shape);
  }
  for (int k = 0; k < kImagesPerClass; ++k) {
    const size_t n = 1 + rng.below(100000);
    image("image_random_bytes_wrong_size", true, std::to_string(n) + " random bytes",
          imageFile(randomBytes(rng, n)), {static_cast<long>(1 + rng.below(64)), 64, 64});
  }
  for (int k = 0; k < kFileCasesPerClass; ++k) {
    image("image_empty", true, "0 bytes", imageFile(""), full);
    const fs::path dir = workDir() / ("image_dir_" + std::to_string(k) + ".raw");
    fs::create_directories(dir);
    image("image_directory", true, "a directory", dir, full);
    image("image_missing", true, "no such file",
          workDir() / ("no_such_image_" + std::to_string(k) + ".raw"), full);
  }
  return cases;
}

void runAll(std::vector<Case>& cases) {
  std::vector<std::pair<size_t, Child>> running;
  size_t next = 0;
  while (next < cases.size() || !running.empty()) {
    while (running.size() < static_cast<size_t>(kParallel) && next < cases.size()) {
      const fs::path log = workDir() / ("log_" + std::to_string(next) + ".txt");
      running.emplace_back(next, spawn(cases[next].args, log));
      ++next;
    }
    bool any = false;
    for (size_t r = 0; r < running.size();) {
      if (poll(running[r].second, cases[running[r].first].outcome, false)) {
        Case& c = cases[running[r].first];
        if (!c.outDir.empty()) {
          c.outcome.err += fs::exists(c.outDir) ? "\n[fuzz: --out folder exists]" : "";
          fs::remove_all(c.outDir);
        }
        running.erase(running.begin() + static_cast<long>(r));
        any = true;
      } else {
        ++r;
      }
    }
    if (!any) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

std::string oneLine(std::string s, size_t max = 400) {
  for (char& c : s)
    if (c == '\n') c = ' ';
  if (s.size() > max) s = s.substr(0, max) + "...";
  return s;
}

}  // namespace

TEST(FuzzInputs, BrokenScenesAndImagesAreRefusedCleanly) {
  ASSERT_TRUE(fs::exists(kBinary)) << kBinary << " is not built (ninja poresph)";
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<Case> cases = makeCases();
  runAll(cases);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  struct Count {
    bool invalid = false;
    int cases = 0, exit0 = 0, exit2 = 0, exit3 = 0, other = 0, failed = 0;
    double maxSeconds = 0.0;
  };
  std::vector<std::string> order;
  std::map<std::string, Count> counts;
  for (const Case& c : cases) {
    const Outcome& o = c.outcome;
    if (!counts.count(c.cls)) order.push_back(c.cls);
    Count& n = counts[c.cls];
    n.invalid = c.invalid;
    ++n.cases;
    n.maxSeconds = std::max(n.maxSeconds, o.seconds);
    if (o.code == 0) ++n.exit0;
    else if (o.code == 2) ++n.exit2;
    else if (o.code == 3) ++n.exit3;
    else ++n.other;

    if (std::getenv("PORESPH_FUZZ_VERBOSE"))  // every case: class, exit code, what was done
      std::cout << c.cls << "  exit " << o.code << "  " << c.what << "\n";
    std::string problem;
    if (o.timedOut) problem = "no exit within " + std::to_string(kTimeoutSeconds) + " s (hang)";
    else if (o.signal) problem = "killed by signal " + std::to_string(o.signal);
    else if (o.code == 1) problem = "exit code 1 (unexpected error)";
    else if (o.code == 127 && o.err.empty())
      problem = "exit code 127: the binary could not be started (rebuilt meanwhile?)";
    else if (o.code != 0 && o.code != 2 && o.code != 3) problem = "exit code " + std::to_string(o.code);
    else if (c.invalid && o.code != 2) problem = "exit code " + std::to_string(o.code) + ", expected 2";
    else if (c.invalid && o.err.find(c.named) == std::string::npos)
      problem = "stderr does not name '" + c.named + "'";
    else if (c.invalid && o.err.find("[fuzz: --out folder exists]") != std::string::npos)
      problem = "refused, but the --out folder was created";
    if (!problem.empty()) {
      ++n.failed;
      ADD_FAILURE() << "[" << c.cls << "] " << c.what << "\n  poresph " << c.args[0] << " "
                    << c.args[1] << "\n  " << problem << "\n  output: " << oneLine(o.err);
    }
  }

  std::ostringstream table;
  table << "fault class                     invalid  cases  exit0  exit2  exit3  other  failed  max s\n";
  std::ostringstream csv;
  csv << "class,invalid_by_construction,cases,exit0,exit2,exit3,other,failed,max_seconds\n";
  int total = 0;
  for (const std::string& cls : order) {
    const Count& n = counts[cls];
    total += n.cases;
    char line[256];
    std::snprintf(line, sizeof(line), "%-32s %-6s %6d %6d %6d %6d %6d %7d %6.2f\n", cls.c_str(),
                  n.invalid ? "yes" : "maybe", n.cases, n.exit0, n.exit2, n.exit3, n.other,
                  n.failed, n.maxSeconds);
    table << line;
    csv << cls << "," << (n.invalid ? "yes" : "maybe") << "," << n.cases << "," << n.exit0 << ","
        << n.exit2 << "," << n.exit3 << "," << n.other << "," << n.failed << "," << n.maxSeconds
        << "\n";
  }
  table << total << " cases, " << wall << " s wall (" << kParallel << " at a time)\n";
  std::cout << table.str();
  std::ofstream(fs::path(PORESPH_BINARY_DIR) / "fuzz_inputs.csv") << csv.str();
  fs::remove_all(workDir());
}
