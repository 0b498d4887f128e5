#pragma once
// Capillary entry into a slit between elastic walls (issue 11 item 5), shared by
// test_coupling_slit_entry.cpp (the blocks alone under a uniform pressure, default) and
// test_coupling_slit_entry_long.cpp (the gas entry, validation_long).
//
// samples/coupling_elastic_slit_entry.yaml: the capillary entry of
// tests/validation/test_fluid_capillary_entry.cpp (periodic channel H = 3 mm, slit w = 1 mm and
// Ls = 3 mm long from xs = 4 mm, theta = 60 deg, gamma = 0.05 N/m, body force f along x) whose
// two slit blocks are clay (E = 12 kPa, nu = 0.25, t = 1 mm thick) standing on a frictionless
// roller (symmetry mirror layer at the channel wall) and held in x by one column of particles
// (x = 5.45 mm, kept 0.35 mm from the wet face). Pressures p_y on the wet face and p_x on the two
// ends give the exact uniform plane-strain state sigma_yy = -p_y, sigma_xx = -p_x,
// sigma_zz = nu (sigma_xx + sigma_yy), eps_yy uniform, so a point at distance y from the roller
// moves towards it by
//   u(y) = y (1 + nu) ((1 - nu) p_y - nu p_x) / E   (p_x = p_y = p: p y (1 + nu)(1 - 2 nu) / E);
// the wet face (y = t) by u(t), the wet row of particles (y = t - dx/2, where the opening is
// read) by u(t - dx/2) = 0.95 u(t) at dx = 0.1 mm. For loads that are not uniform, Betti's
// reciprocal theorem with the uniform state of a unit load on the wet face alone (sigma_yy = -1,
// sigma_xx = 0: u_y = eps_yy y, u_x = eps_xx (x - x_pin), no work at the roller and the pin)
// gives the mean displacement of the wet face exactly from the mean face pressure p_y and the
// ends' mean pressures weighted by their distance from the pin column:
//   p_x = ((x_pin - xs) p_left + (xs + Ls - x_pin) p_right) / Ls.
// The Young-Laplace entry threshold of the fixed slit (Eq. 1.10 with the contact angle):
//   rho f* Lx = 2 gamma cos(theta) (1/w - 1/H);
// a slit opened by delta has w -> w + delta, f*_el / f* = (1/(w + delta) - 1/H) / (1/w - 1/H).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"

namespace poresph::slitentry {

constexpr double kPi = 3.14159265358979323846;
constexpr double kE = 12000.0, kNu = 0.25, kT = 1e-3;               // clay, block thickness
constexpr double kW = 1e-3, kH = 3e-3, kLx = 8e-3, kXs = 4e-3, kLs = 3e-3;
constexpr double kPinX = 5.45e-3;  // the pin column of the sample
constexpr double kGamma = 0.05, kRho = 1000.0, kTheta = 60.0;

inline double threshold() {  // f*, m/s^2
  return 2.0 * kGamma * std::cos(kTheta * kPi / 180.0) * (1.0 / kW - 1.0 / kH) / (kRho * kLx);
}
/// Displacement towards the roller of a block's point at distance y from it, under p_y (wet
/// face) and p_x (ends); y = kT: the wet face.
inline double faceDisplacement(double py, double px, double y = kT) {
  return y * (1.0 + kNu) * ((1.0 - kNu) * py - kNu * px) / kE;
}
/// f*_el / f* for the slit opened by delta.
inline double thresholdRatio(double delta) {
  return (1.0 / (kW + delta) - 1.0 / kH) / (1.0 / kW - 1.0 / kH);
}

inline std::string sampleText() {
  const std::string path = std::string(PORESPH_SOURCE_DIR) + "/samples/coupling_elastic_slit_entry.yaml";
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot read " + path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

inline void replaceOnce(std::string& t, const std::string& from, const std::string& to) {
  const auto at = t.find(from);
  if (at == std::string::npos) throw std::runtime_error("sample text has no '" + from + "'");
  t.replace(at, from.size(), to);
}

inline void dropLinesWith(std::string& t, const std::string& key) {
  std::string out;
  std::istringstream in(t);
  for (std::string line; std::getline(in, line);)
    if (line.find(key) == std::string::npos) out += line + "\n";
  t = out;
}

/// The sample at body force ratio x f*; fixedWalls: the blocks (and their roller layers) made of
/// the fixed wall material, no solid, as in the fixed-wall test; model: the fluid-solid model.
inline std::string entryScene(double ratio, bool fixedWalls, const std::string& model = "extrapolated") {
  std::string t = sampleText();
  char g[64];
  std::snprintf(g, sizeof g, "gravity: [%.12g, 0]", ratio * threshold());
  replaceOnce(t, "gravity: [4.583333333333333, 0]", g);
  replaceOnce(t, "fluid_solid: extrapolated", "fluid_solid: " + model);
  if (const char* gm = std::getenv("SLIT_ENTRY_GAMMA"))  // study hook: the surface tension
    replaceOnce(t, "surface_tension: 0.05", std::string("surface_tension: ") + gm);
  if (const char* hg = std::getenv("SLIT_ENTRY_HOURGLASS"))  // study hook: the clay's hourglass
    replaceOnce(t, "hourglass: 1,", std::string("hourglass: ") + hg + ",");
  if (fixedWalls) {
    t = t.substr(0, t.find("\nsolid:")) + "\n";
    dropLinesWith(t, "coupling:");
    dropLinesWith(t, "{name: clay");
    for (auto at = t.find("material: clay"); at != std::string::npos; at = t.find("material: clay"))
      t.replace(at, 14, "material: wall");
  }
  return t;
}

/// The two blocks alone (no fluid), the roller and pin of the sample, pressure p on every wet
/// face (solid boundary `pressure`, the consistent nodal load of the uniform stress -p).
inline std::string blocksAloneScene(double p, double endTime) {
  std::string t = sampleText();
  dropLinesWith(t, "coupling:");
  dropLinesWith(t, "{name: water");
  dropLinesWith(t, "{name: gas");
  dropLinesWith(t, "{name: wall");
  dropLinesWith(t, "material: water");
  dropLinesWith(t, "material: gas");
  dropLinesWith(t, "material: wall");
  const auto f = t.find("\nfluid:"), s = t.find("\nsolid:");
  t.erase(f, s - f);
  char e[64];
  std::snprintf(e, sizeof e, "end_time: %g", endTime);
  replaceOnce(t, "end_time: 0.08", e);
  replaceOnce(t, "cfl: 1.0", "cfl: 0.5");
  char load[240];
  std::snprintf(load, sizeof load,
                "  boundaries:\n"
                "    - {name: load, type: pressure, pressure: %.12g, box: {min: [-1, -1], max: [1, 1]}}\n",
                p);
  replaceOnce(t, "  boundaries:\n", load);
  return t;
}

/// Opening and face pressures, read in the reference frame of the blocks.
struct SlitState {
  double uLow = 0, uHigh = 0;   ///< mean u_y of the wet rows (lower block's top, upper's bottom)
  double yLow = 0, yHigh = 0;   ///< their mean reference distance from the rollers (t - dx/2)
  double pFaceLow = 0, pFaceHigh = 0;  ///< fluid pressure within 1.5 dx of the wet faces
  double pEndsLow = 0, pEndsHigh = 0;  ///< same at the two ends, weighted (Betti, above)
  double pLeft = 0, pRight = 0;        ///< the ends' mean pressures (both blocks)
  double opening() const { return uHigh - uLow; }
  /// The elastic estimate of opening() (the wet rows) at these pressures (both blocks).
  double estimate() const {
    return faceDisplacement(pFaceLow, pEndsLow, yLow) + faceDisplacement(pFaceHigh, pEndsHigh, yHigh);
  }
  /// The opening of the slit between the wet faces: the rows' opening with the uniform strain
  /// carried on to the faces (x t / (t - dx/2)).
  double faceOpening() const {
    return yLow > 0.0 && yHigh > 0.0 ? (uHigh - uLow) * kT / (0.5 * (yLow + yHigh)) : 0.0;
  }
};

inline SlitState readSlit(const Simulation& sim) {
  const ParticleStore& st = sim.store;
  const double dx = sim.spacing;
  const double y0 = 0.5 * (kH - kW), y1 = 0.5 * (kH + kW);  // wet faces (1 mm, 2 mm)
  const bool fluid = st.has("pressure");
  const double* pres = fluid ? st.data(st.real("pressure")) : nullptr;
  const bool solid = st.has("reference_position");
  const double* x = st.data(st.position());
  const std::int32_t* ph = st.data(st.phase());
  const double* X = solid ? st.data(st.real("reference_position")) : nullptr;
  double s[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  long n[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  auto add = [&](int k, double v) { s[k] += v, ++n[k]; };
  const double band = 1.5 * dx;
  for (Index i = 0; i < st.realCount(); ++i) {
    const double px = x[2 * i], py = x[2 * i + 1];
    if (pres && ph[i] == kPhaseFluid) {
      const double p = pres[i];
      const bool inX = px > kXs && px < kXs + kLs;
      const bool left = px > kXs - band && px < kXs, right = px > kXs + kLs && px < kXs + kLs + band;
      if (inX && py > y0 && py < y0 + band) add(2, p);
      if (inX && py < y1 && py > y1 - band) add(3, p);
      if (py > 0.0 && py < y0) {
        if (left) add(4, p);
        if (right) add(8, p);
      }
      if (py > y1 && py < kH) {
        if (left) add(5, p);
        if (right) add(9, p);
      }
    } else if (X && ph[i] == kPhaseSolid) {
      const double Y = X[2 * i + 1], Xx = X[2 * i];
      if (Xx < kXs || Xx > kXs + kLs) continue;
      if (Y < y0 && Y > y0 - dx) add(0, py - Y), s[6] += Y;
      if (Y > y1 && Y < y1 + dx) add(1, py - Y), s[7] += kH - Y;
    }
  }
  SlitState r;
  auto mean = [&](int k) { return n[k] > 0 ? s[k] / n[k] : 0.0; };
  r.uLow = mean(0), r.uHigh = mean(1);
  r.yLow = n[0] > 0 ? s[6] / n[0] : 0.0, r.yHigh = n[1] > 0 ? s[7] / n[1] : 0.0;
  r.pFaceLow = mean(2), r.pFaceHigh = mean(3);
  const double wl = (kPinX - kXs) / kLs, wr = (kXs + kLs - kPinX) / kLs;
  r.pEndsLow = wl * mean(4) + wr * mean(8), r.pEndsHigh = wl * mean(5) + wr * mean(9);
  r.pLeft = 0.5 * (mean(4) + mean(5)), r.pRight = 0.5 * (mean(8) + mean(9));
  return r;
}

/// Largest x of a gas particle past the slit entrance (as test_fluid_capillary_entry.cpp).
inline double gasFront(const Simulation& sim, int gas) {
  const ParticleStore& st = sim.store;
  const double* x = st.data(st.position());
  const std::int32_t* mt = st.data(st.material());
  double f = -1e300;
  for (Index i = 0; i < st.realCount(); ++i)
    if (mt[i] == gas && x[2 * i] < kXs + kLs + 1e-3) f = std::max(f, x[2 * i] - kXs);
  return f;
}

inline int materialId(const Simulation& sim, const std::string& name) {
  for (const auto& m : sim.materials)
    if (m.name == name) return m.id;
  throw std::runtime_error("no material " + name);
}

}  // namespace poresph::slitentry
