#include "libcore/reference.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "libcore/parameters.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"

namespace poresph {

namespace {

std::array<double, 3> toArray3(const std::vector<double>& v) {
  std::array<double, 3> a{0, 0, 0};
  for (size_t k = 0; k < v.size() && k < 3; ++k) a[k] = v[k];
  return a;
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == ',') {
      out.push_back(cur);
      cur.clear();
    } else if (c != '\r') {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

/// time and `column` of every row of a timeseries.csv; false (with `why`) when absent.
bool readColumn(const std::string& path, const std::string& column, std::vector<double>& t,
                std::vector<double>& y, std::string& why) {
  std::ifstream f(path);
  std::string line;
  if (!f || !std::getline(f, line)) {
    why = "no timeseries (" + path + ")";
    return false;
  }
  const auto header = splitCsv(line);
  const auto it = std::find(header.begin(), header.end(), column);
  const auto itT = std::find(header.begin(), header.end(), "time");
  if (it == header.end()) {
    std::string cols;
    for (const auto& h : header) cols += (cols.empty() ? "" : ", ") + h;
    why = "the timeseries has no column '" + column + "' (columns: " + cols + ")";
    return false;
  }
  const size_t k = static_cast<size_t>(it - header.begin());
  const size_t kt = static_cast<size_t>(itT - header.begin());
  while (std::getline(f, line)) {
    if (line.empty()) continue;
    const auto row = splitCsv(line);
    if (row.size() <= std::max(k, kt)) continue;
    try {
      t.push_back(itT == header.end() ? static_cast<double>(t.size()) : std::stod(row[kt]));
      y.push_back(std::stod(row[k]));
    } catch (const std::exception&) {
      t.resize(y.size());
    }
  }
  if (y.empty()) {
    why = "the timeseries has no rows";
    return false;
  }
  return true;
}

double periodOf(const std::vector<double>& t, const std::vector<double>& y) {
  double mean = 0.0;
  for (double v : y) mean += v;
  mean /= static_cast<double>(y.size());
  std::vector<double> crossings;
  for (size_t k = 1; k < y.size(); ++k) {
    const double a = y[k - 1] - mean, b = y[k] - mean;
    if ((a < 0.0 && b >= 0.0) || (a > 0.0 && b <= 0.0))
      crossings.push_back(t[k - 1] + (t[k] - t[k - 1]) * a / (a - b));
  }
  if (crossings.size() < 3) return NAN;
  // Two crossings per period: twice the least-squares slope of crossing time against its index
  // (less biased by the ends of a short series than first-to-last: 0.04 % against 0.1 % for the
  // bar over three periods).
  const double nc = static_cast<double>(crossings.size());
  double mk = 0.0, mt = 0.0;
  for (size_t k = 0; k < crossings.size(); ++k) mk += static_cast<double>(k) / nc, mt += crossings[k] / nc;
  double sxy = 0.0, sxx = 0.0;
  for (size_t k = 0; k < crossings.size(); ++k) {
    sxy += (static_cast<double>(k) - mk) * (crossings[k] - mt);
    sxx += (static_cast<double>(k) - mk) * (static_cast<double>(k) - mk);
  }
  return 2.0 * sxy / sxx;
}

/// `at: first COLUMN [OP VALUE]` (the text after "first "): the event column and, with a
/// threshold, the comparison (`>=` or `<=`) and its value. False when the text is not of that form.
bool parseFirst(const std::string& at, std::string& column, std::string& op, double& threshold) {
  std::istringstream in(at.substr(6));
  std::string extra, value;
  if (!(in >> column)) return false;
  op.clear();
  if (!(in >> op)) return true;  // `first COLUMN`: the first nonzero row
  if (op != ">=" && op != "<=") return false;
  if (!(in >> value) || (in >> extra)) return false;
  std::size_t used = 0;
  try {
    threshold = std::stod(value, &used);
  } catch (const std::exception&) {
    return false;
  }
  return used == value.size() && std::isfinite(threshold);
}

}  // namespace

const std::vector<std::string>& referenceQuantityNames() {
  static const std::vector<std::string> names = {
      "laplace_jump", "spurious_capillary_number", "hoop_stress", "radial_stress", "period",
      "material_volume"};
  return names;
}

bool ReferenceSpec::isStateQuantity() const {
  return quantity != "period" &&
         std::find(referenceQuantityNames().begin(), referenceQuantityNames().end(), quantity) !=
             referenceQuantityNames().end();
}

double referenceError(double measured, double value, bool* relative) {
  const bool rel = value != 0.0;
  if (relative) *relative = rel;
  return rel ? std::abs(measured - value) / std::abs(value) : std::abs(measured - value);
}

ReferenceSpec readReference(const ParameterSet& s, int dim) {
  ReferenceSpec r;
  r.declared = true;
  r.quantity = s.string("quantity");
  if (r.quantity.empty()) s.fail("quantity", "give a named quantity or a timeseries column");
  const size_t D = static_cast<size_t>(dim);
  if (s.has("value")) {
    r.hasValue = true;
    r.value = s.real("value");
  }
  r.at = s.string("at", "end");
  if (r.at.rfind("first ", 0) == 0) {
    // `at: first COLUMN`: the time of the first row where timeseries COLUMN is nonzero (an event
    // such as drainage_percolated); `at: first COLUMN >= VALUE` (or <=): the time at which COLUMN
    // first reaches VALUE (e.g. 'first solid_damage_max >= 0.1'); checked against the timeseries
    // when the run ends.
    std::string col, op;
    double thr = 0.0;
    if (!parseFirst(r.at, col, op, thr))
      s.fail("at", "'first' takes one timeseries column, optionally with a threshold: "
                   "'first drainage_percolated' or 'first solid_damage_max >= 0.1'");
  } else if (r.at != "end" && r.at != "max" && r.at != "min") {
    double t = 0.0;
    std::size_t used = 0;
    try {
      t = std::stod(r.at, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != r.at.size() || !(t >= 0.0))
      s.fail("at", "expected end, max, min, first COLUMN or a time in seconds (>= 0)");
    r.atTime = t;
  }
  const std::string& q = r.quantity;
  if (q == "laplace_jump") {
    r.centre = toArray3(s.reals("centre", D));
    r.radius = s.real("radius", Range::positive());
  } else if (q == "spurious_capillary_number") {
    r.surfaceTension = s.real("surface_tension", 0.0, Range::positive());
  } else if (q == "hoop_stress" || q == "radial_stress") {
    if (dim < 2) s.fail("quantity", "needs a 2D or 3D scene (a stress about a centre)");
    r.centre = toArray3(s.reals("centre", D));
    r.point = toArray3(s.reals("point", D));
    double d2 = 0.0;
    for (size_t a = 0; a < D; ++a) d2 += (r.point[a] - r.centre[a]) * (r.point[a] - r.centre[a]);
    if (!(d2 > 0.0)) s.fail("point", "must differ from centre (the directions are about it)");
  } else if (q == "period") {
    r.column = s.string("column");
    r.factor = s.real("factor", 1.0, Range::positive());
  } else if (q == "material_volume") {
    r.material = s.string("material");
    const ParameterSet b = s.section("box");
    r.boxMin = toArray3(b.reals("min", D));
    r.boxMax = toArray3(b.reals("max", D));
    b.finish();
    r.scale = s.real("scale", 1.0, Range::positive());
  }
  if (r.isStateQuantity() && r.at != "end")
    s.fail("at", "'" + q + "' is computed from the final state: only at: end");
  if (q == "period" && r.at != "end")
    s.fail("at", "'period' is computed over the whole timeseries: only at: end");
  s.finish();
  // The echo: the section as read.
  r.echo["quantity"] = r.quantity;
  r.echo["at"] = r.at;
  if (r.hasValue) r.echo["value"] = r.value;
  return r;
}

ReferenceResult evaluateReference(const Scene& scene, const std::string& timeseries) {
  const ReferenceSpec& ref = scene.reference;
  ReferenceResult out;
  out.hasValue = ref.hasValue;
  out.value = ref.value;
  if (!ref.declared) {
    out.note = "the scene declares no reference";
    return out;
  }
  const Simulation& sim = *scene.sim;
  const ParticleStore& st = sim.store;
  const int d = sim.dimension();
  const Index n = st.realCount();
  const double* x = st.data(st.position());
  const double* v = st.data(st.velocity());
  const std::int32_t* phase = st.data(st.phase());
  auto dist = [&](Index i, const std::array<double, 3>& c) {
    double r2 = 0.0;
    for (int a = 0; a < d; ++a) r2 += (x[i * d + a] - c[static_cast<size_t>(a)]) * (x[i * d + a] - c[static_cast<size_t>(a)]);
    return std::sqrt(r2);
  };
  const std::string& q = ref.quantity;
  double m = NAN;
  if (q == "laplace_jump") {
    if (!st.has("pressure") || !st.has("colour")) {
      out.note = "laplace_jump needs the fluid's pressure and colour fields (surface tension)";
      return out;
    }
    const double* p = st.data(st.real("pressure"));
    const double* col = st.data(st.real("colour"));
    const double h = sim.kernel.h();
    double si = 0, ni = 0, so = 0, no = 0;
    for (Index i = 0; i < n; ++i) {
      if (phase[i] != kPhaseFluid) continue;
      const double r = dist(i, ref.centre);
      if (r < ref.radius - 3 * h && col[i] > 0.0) si += p[i], ni += 1;
      if (r > ref.radius + 3 * h) so += p[i], no += 1;
    }
    if (ni == 0 || no == 0) {
      out.note = "laplace_jump: no fluid particle within R - 3h of the centre or beyond R + 3h";
      return out;
    }
    m = si / ni - so / no;
  } else if (q == "spurious_capillary_number") {
    double gamma = ref.surfaceTension;
    if (!(gamma > 0.0)) {
      const YAML::Node f = scene.source["fluid"];
      if (f && f.IsMap() && f["surface_tension"]) gamma = f["surface_tension"].as<double>(0.0);
    }
    double mu = 0.0;
    for (const auto& mat : sim.materials)
      if (mat.phase == kPhaseFluid) mu = std::max(mu, mat.fluid.viscosity);
    if (!(gamma > 0.0) || !(mu > 0.0)) {
      out.note = "spurious_capillary_number needs a surface tension and a fluid viscosity";
      return out;
    }
    double vmax2 = 0.0;
    for (Index i = 0; i < n; ++i) {
      if (phase[i] != kPhaseFluid) continue;
      double v2 = 0.0;
      for (int a = 0; a < d; ++a) v2 += v[i * d + a] * v[i * d + a];
      vmax2 = std::max(vmax2, v2);
    }
    m = mu * std::sqrt(vmax2) / gamma;
  } else if (q == "hoop_stress" || q == "radial_stress") {
    if (!st.has("stress")) {
      out.note = q + " needs a solid (the stress field)";
      return out;
    }
    const double* sig = st.data(st.real("stress"));
    const double* mass = st.data(st.mass());
    const double* rho = st.data(st.density());
    // Directions at the point: radial e_r from the centre in the xy plane, hoop e_t = e_z x e_r
    // (in 3D: about the z axis through the centre).
    std::array<double, 3> er{0, 0, 0}, et{0, 0, 0};
    double len = 0.0;
    for (int a = 0; a < std::min(d, 2); ++a) {
      er[static_cast<size_t>(a)] = ref.point[static_cast<size_t>(a)] - ref.centre[static_cast<size_t>(a)];
      len += er[static_cast<size_t>(a)] * er[static_cast<size_t>(a)];
    }
    len = std::sqrt(len);
    for (auto& c : er) c /= len;
    et = {-er[1], er[0], 0.0};
    const std::array<double, 3>& e = q == "hoop_stress" ? et : er;
    double sw = 0.0, s = 0.0;
    for (Index i = 0; i < n; ++i) {
      if (phase[i] != kPhaseSolid) continue;
      const double r = dist(i, ref.point);
      if (r >= sim.kernel.support()) continue;
      const double w = sim.kernel.value(r) * mass[i] / rho[i];
      double proj = 0.0;  // e . sigma . e (column-major D x D)
      for (int a = 0; a < d; ++a)
        for (int b = 0; b < d; ++b)
          proj += e[static_cast<size_t>(a)] * sig[i * d * d + b * d + a] * e[static_cast<size_t>(b)];
      sw += w;
      s += w * proj;
    }
    if (!(sw > 0.0)) {
      out.note = q + ": no solid particle within the kernel support of the point";
      return out;
    }
    m = s / sw;
  } else if (q == "material_volume") {
    int id = -1;
    for (const auto& mat : sim.materials)
      if (mat.name == ref.material) id = mat.id;
    if (id < 0) {
      out.note = "material_volume: the scene has no material '" + ref.material + "'";
      return out;
    }
    const std::int32_t* matId = st.data(st.material());
    const double* mass = st.data(st.mass());
    const double* rho = st.data(st.density());
    double vol = 0.0;
    for (Index i = 0; i < n; ++i) {
      if (matId[i] != id) continue;
      bool in = true;
      for (int a = 0; a < d; ++a)
        in = in && x[i * d + a] >= ref.boxMin[static_cast<size_t>(a)] &&
             x[i * d + a] <= ref.boxMax[static_cast<size_t>(a)];
      if (in) vol += mass[i] / rho[i];
    }
    m = vol * ref.scale;
  } else {
    // A timeseries column, or the period of one.
    std::vector<double> t, y;
    std::string why;
    const std::string col = q == "period" ? ref.column : q;
    if (timeseries.empty() || !readColumn(timeseries, col, t, y, why)) {
      out.note = why.empty() ? "no timeseries" : why;
      return out;
    }
    if (q == "period") {
      m = periodOf(t, y) * ref.factor;
      if (!std::isfinite(m)) {
        out.note = "period: fewer than three crossings of the mean of '" + col + "'";
        return out;
      }
    } else if (ref.at == "end") {
      m = y.back();
    } else if (ref.at == "max") {
      m = *std::max_element(y.begin(), y.end());
    } else if (ref.at == "min") {
      m = *std::min_element(y.begin(), y.end());
    } else {
      double atTime = ref.atTime;
      if (ref.at.rfind("first ", 0) == 0) {
        // The time of the event: the first row where the event column is nonzero, or, with a
        // threshold, where it first reaches the threshold, interpolated linearly between that
        // row and the one before (a continuous column such as solid_damage_max is then read
        // finer than the output interval).
        std::string event, op;
        double thr = 0.0;
        parseFirst(ref.at, event, op, thr);  // checked by readReference
        std::vector<double> te, ye;
        if (!readColumn(timeseries, event, te, ye, why)) {
          out.note = why;
          return out;
        }
        auto reached = [&](double v) {
          if (!std::isfinite(v)) return false;
          if (op.empty()) return v != 0.0;
          return op == ">=" ? v >= thr : v <= thr;
        };
        atTime = -1.0;
        for (size_t k = 0; k < ye.size(); ++k)
          if (reached(ye[k])) {
            atTime = te[k];
            if (!op.empty() && k > 0 && std::isfinite(ye[k - 1]) && ye[k] != ye[k - 1])
              atTime = te[k - 1] + (thr - ye[k - 1]) / (ye[k] - ye[k - 1]) * (te[k] - te[k - 1]);
            break;
          }
        if (atTime < 0.0) {
          out.note = "at: " + ref.at + ": '" + event +
                     (op.empty() ? "' is 0 in every row" : "' is never " + op + " " + ref.at.substr(ref.at.rfind(' ') + 1)) +
                     " (the event did not happen by the end of the run)";
          return out;
        }
      }
      if (atTime < t.front() - 1e-12 || atTime > t.back() + 1e-12 * std::max(1.0, t.back())) {
        std::ostringstream o;
        o << "at: " << ref.at << " s lies outside the timeseries (" << t.front() << " .. "
          << t.back() << " s)";
        out.note = o.str();
        return out;
      }
      m = y.back();
      for (size_t k = 1; k < t.size(); ++k)
        if (t[k] >= atTime) {
          const double f = t[k] > t[k - 1] ? (atTime - t[k - 1]) / (t[k] - t[k - 1]) : 1.0;
          m = y[k - 1] + f * (y[k] - y[k - 1]);
          break;
        }
    }
  }
  if (!std::isfinite(m)) {
    out.note = q + " is not finite";
    return out;
  }
  out.ok = true;
  out.measured = m;
  if (ref.hasValue) out.error = referenceError(m, ref.value, &out.relative);
  return out;
}

std::string referenceYaml(const ReferenceSpec& spec, const ReferenceResult& r) {
  std::ostringstream o;
  o.precision(12);
  o << "# the scene's reference quantity evaluated at the end of the run (libcore/reference.hpp)\n";
  o << "quantity: " << spec.quantity << "\n";
  o << "at: " << spec.at << "\n";
  o << "ok: " << (r.ok ? "true" : "false") << "\n";
  if (r.ok) o << "measured: " << r.measured << "\n";
  if (r.hasValue) o << "value: " << r.value << "\n";
  if (r.ok && r.hasValue) {
    o << "error: " << r.error << "\n";
    o << "relative: " << (r.relative ? "true" : "false") << "\n";
  }
  if (!r.note.empty()) {
    YAML::Emitter e;
    e << YAML::DoubleQuoted << r.note;
    o << "note: " << e.c_str() << "\n";
  }
  return o.str();
}

}  // namespace poresph
