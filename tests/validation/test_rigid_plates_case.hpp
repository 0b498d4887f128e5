#pragma once
// The confined block of issue 15's validation case 4, shared by tests/validation/
// test_rigid_plates.cpp (default) and test_rigid_plates_long.cpp (resolution study): an elastic
// block (2D, plane strain) squeezed by four force-controlled rigid plates, each pushed inward by
// the confining stress s times the face length and free to move along its normal only. Dynamic
// relaxation (solid and plate damping) to the static state; then the stress should be uniform,
// sigma_xx = sigma_yy = -s, and each plate's displacement the elastic closed form
// u = s L / (4 (lambda + mu)) (biaxial plane strain, half the block's shortening per face).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"
#include "physics/rigid/rigid_module.hpp"
#include "tests/support/validation_record.hpp"

namespace poresph::test {

struct PlatesResult {
  double meanErr = 0.0;    // max(|<sxx> + s|, |<syy> + s|) / s
  double worst = 0.0;      // worst interior |sigma_ii + s| / s
  double meanU = 0.0;      // mean plate displacement (m)
  double worstU = 0.0;     // worst |u - u_exact| / u_exact
  double uExact = 0.0;
  double worstForce = 0.0; // worst |plate force + s L| / (s L)
  double seconds = 0.0;
  double faceU = 0.0;          // mean inward displacement of the x face rows (m)
  double interiorStrain = 0.0;  // slope du_x/dX over the interior
  // Against the finite-strain closed form of the model's own law (Saint Venant-Kirchhoff, TL):
  double uSvk = 0.0;          // plate displacement (m)
  double worstUSvk = 0.0;     // worst |u - uSvk| / uSvk
  double worstSvk = 0.0;      // worst interior |sigma_ii + s / stretch| / (s / stretch) (Cauchy)
  double loadArea = 0.0;      // worst |sum n . s_a / area - 1| of the weighted plate bonds
};

/// Stretch of a Saint Venant-Kirchhoff block under an equal nominal compression s along `axes`
/// (2: biaxial plane strain, 3: hydrostatic): P = stretch S, S = (axes lambda + 2 mu) E along
/// each loaded axis with E = (stretch^2 - 1) / 2, so (axes lambda + 2 mu) / 2 stretch (stretch^2
/// - 1) = -s (Newton from the small-strain value). The Cauchy stress is then -s / stretch in
/// plane strain (a face's length shrinks by the stretch) and -s / stretch^2 in 3D.
inline double svkStretch(double s, double lambda, double mu, int axes) {
  const double c = 0.5 * (axes * lambda + 2.0 * mu);
  double l = 1.0 - s / (2.0 * c);
  for (int it = 0; it < 50; ++it) l -= (c * l * (l * l - 1.0) + s) / (c * (3.0 * l * l - 1.0));
  return l;
}

/// The block L = 20 mm across with n particles, plates 2 dx thick.
/// load: "plates" (4 force-controlled plates), "traction" (the solid's traction boundaries on the
/// outer rows: the same face-row point loads without plates) or "pressure" (the solid's pressure
/// boundaries: the consistent nodal load over a support).
inline PlatesResult runPlates(int n, const std::string& formulation, double hourglass,
                       const std::string& load = "plates") {
  test::Stopwatch clock;
  const double L = 0.02, dx = L / n, t = 2 * dx;
  std::ostringstream y;
  y.precision(10);
  y << "dimension: 2\n"
    << "domain: {lo: [-0.01, -0.01], hi: [0.03, 0.03]}\n"
    << "spacing: " << dx << "\n"
    << "kernel: wendland_c2\nend_time: 0.012\ntime_step: {adaptive: true, cfl: 0.5}\n"
    << "output: {every_steps: 100000000}\nmaterials:\n"
    << "  - {name: clay, model: elastic, density: 2000, young_modulus: 1.0e6, poisson_ratio: 0.25, "
       "formulation: " << formulation << ", damping: 3000"
    << (hourglass > 0 ? ", hourglass: " + std::to_string(hourglass) : std::string()) << "}\n";
  const char* names[4] = {"left", "right", "bottom", "top"};
  const char* dirs[4] = {"[1, 0]", "[-1, 0]", "[0, 1]", "[0, -1]"};
  const bool plates = load == "plates" || load == "slip";
  for (int k = 0; k < 4 && plates; ++k)
    y << "  - {name: " << names[k] << ", model: rigid, density: 2000, contact_modulus: 5.0e7, "
      << (load == "slip" ? "bonded: slip, " : "") << "damping: 3000, plate: {direction: " << dirs[k] << ", stress: 1.0e4, area: 0.02}}\n";
  y << "geometry:\n"
    << "  - {shape: box, lo: [0.0, 0.0], hi: [0.02, 0.02], material: clay}\n"
    ;
  if (plates)
    y << "  - {shape: box, lo: [" << -t << ", 0.0], hi: [0.0, 0.02], material: left}\n"
      << "  - {shape: box, lo: [0.02, 0.0], hi: [" << L + t << ", 0.02], material: right}\n"
      << "  - {shape: box, lo: [0.0, " << -t << "], hi: [0.02, 0.0], material: bottom}\n"
      << "  - {shape: box, lo: [0.0, 0.02], hi: [0.02, " << L + t << "], material: top}\n";
  else if (load == "traction")
    y << "solid:\n  boundaries:\n"
      << "    - {name: l, type: traction, box: {min: [-1, -1], max: [" << dx << ", 1]}, traction: [1.0e4, 0]}\n"
      << "    - {name: r, type: traction, box: {min: [" << L - dx << ", -1], max: [1, 1]}, traction: [-1.0e4, 0]}\n"
      << "    - {name: b, type: traction, box: {min: [" << dx << ", -1], max: [" << L - dx << ", " << dx << "]}, traction: [0, 1.0e4]}\n"
      << "    - {name: t, type: traction, box: {min: [" << dx << ", " << L - dx << "], max: [" << L - dx << ", 1]}, traction: [0, -1.0e4]}\n";
  else
    y << "solid:\n  boundaries:\n"
      << "    - {name: p, type: pressure, box: {min: [-1, -1], max: [1, 1]}, pressure: 1.0e4}\n";
  Scene s = loadSceneText(y.str(), "rigid_plates.yaml");
  Simulation& sim = *s.sim;
  auto* rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  EXPECT_NE(rigid, nullptr);
  auto integrator = makeIntegrator("leapfrog");
  while (!s.finished()) integrator->step(sim, s.nextTimeStep());
  const double sigma = 1.0e4, E = 1.0e6, nu = 0.25;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  PlatesResult out;
  out.uExact = sigma * L / (4.0 * (lambda + mu));
  const ParticleStore& st = sim.store;
  const RealField stress = st.real("stress");
  const RealField ref = st.real("reference_position");
  double sxx = 0.0, syy = 0.0;
  int count = 0, interior = 0;
  for (Index i = 0; i < st.realCount(); ++i) {
    if (st.data(st.phase())[i] != kPhaseSolid) continue;
    const Mat<2> S = st.mat<2>(stress, i);
    sxx += S(0, 0);
    syy += S(1, 1);
    ++count;
    const Vec<2> X = st.vec<2>(ref, i);
    const double edge = std::min(std::min(X[0], L - X[0]), std::min(X[1], L - X[1]));
    if (edge < 4 * 0.001) continue;  // 4 mm from the faces at every resolution
    ++interior;
    out.worst = std::max({out.worst, std::abs(S(0, 0) + sigma) / sigma,
                          std::abs(S(1, 1) + sigma) / sigma});
  }
  sxx /= count;
  syy /= count;
  // Interior strain: least-squares slope of u_x against X_x over the particles 4 mm from the
  // faces (exact: -s / (2 (lambda + mu))), and the face rows' extra shortening.
  {
    const RealField pos = st.position();
    double sx = 0, sy = 0, sxx2 = 0, sxy = 0, nn = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (st.data(st.phase())[i] != kPhaseSolid) continue;
      const Vec<2> X = st.vec<2>(ref, i), x = st.vec<2>(pos, i);
      const double edge = std::min(std::min(X[0], L - X[0]), std::min(X[1], L - X[1]));
      if (edge < 4 * 0.001) continue;
      const double u = x[0] - X[0];
      sx += X[0]; sy += u; sxx2 += X[0] * X[0]; sxy += X[0] * u; nn += 1;
    }
    const double slope = (nn * sxy - sx * sy) / (nn * sxx2 - sx * sx);
    out.interiorStrain = slope;
  }
  out.meanErr = std::max(std::abs(sxx + sigma), std::abs(syy + sigma)) / sigma;
  {  // the face rows' mean inward displacement along x (left and right)
    const RealField pos = st.position();
    double sum = 0.0;
    int cnt = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (st.data(st.phase())[i] != kPhaseSolid) continue;
      const Vec<2> X = st.vec<2>(ref, i), x = st.vec<2>(pos, i);
      if (X[0] < dx) { sum += x[0] - X[0]; ++cnt; }
      if (X[0] > L - dx) { sum -= x[0] - X[0]; ++cnt; }
    }
    out.faceU = sum / cnt;
  }
  if (!plates) {
    out.meanU = out.faceU;
    out.worstU = std::abs(out.meanU - out.uExact) / out.uExact;
  }
  for (const auto& [name, value] : sim.diagnostics()) {
    if (name.rfind("plate", 0) != 0) continue;
    if (name.find("_displacement") != std::string::npos) {
      out.worstU = std::max(out.worstU, std::abs(value - out.uExact) / out.uExact);
      out.meanU += value / 4.0;
    } else if (name.find("_force") != std::string::npos) {
      out.worstForce = std::max(out.worstForce, std::abs(value + sigma * L) / (sigma * L));
    }
  }
  {
    const double stretch = svkStretch(sigma, lambda, mu, 2);
    out.uSvk = (1.0 - stretch) * L / 2.0;
    for (const auto& [name, value] : sim.diagnostics())
      if (name.rfind("plate", 0) == 0 && name.find("_displacement") != std::string::npos)
        out.worstUSvk = std::max(out.worstUSvk, std::abs(value - out.uSvk) / out.uSvk);
    if (!plates) out.worstUSvk = std::abs(out.faceU - out.uSvk) / out.uSvk;
    const double cauchy = sigma / stretch;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (st.data(st.phase())[i] != kPhaseSolid) continue;
      const Vec<2> X = st.vec<2>(ref, i);
      if (std::min(std::min(X[0], L - X[0]), std::min(X[1], L - X[1])) < 4 * 0.001) continue;
      const Mat<2> S = st.mat<2>(stress, i);
      out.worstSvk = std::max({out.worstSvk, std::abs(S(0, 0) + cauchy) / cauchy,
                               std::abs(S(1, 1) + cauchy) / cauchy});
    }
    if (rigid)
      for (const auto& P : rigid->plateBonds())
        out.loadArea = std::max(out.loadArea, std::abs(P.loadArea / L - 1.0));
  }
  out.seconds = clock.seconds();
  std::printf("  against the SVK closed form: plate displacement %.5e m, worst %.3f %%; interior "
              "stress worst %.3f %%; weighted bonds' load area %.2e off\n",
              out.uSvk, 100 * out.worstUSvk, 100 * out.worstSvk, out.loadArea);
  std::printf("  %s: %d across, %s, hourglass %g: t = %.4f s (%lld steps): mean stress %.2f %% off, "
              "worst interior %.2f %% (%d particles); plate displacement mean %.5e m, closed form "
              "%.5e m, worst %.2f %%; plate force %.1e; interior strain %.5e (closed form %.5e); x face rows moved %.5e m; %.1f s\n",
              load.c_str(), n, formulation.c_str(), hourglass, sim.time, static_cast<long long>(sim.step),
              100 * out.meanErr, 100 * out.worst, interior, out.meanU, out.uExact,
              100 * out.worstU, out.worstForce, out.interiorStrain, -sigma / (2 * (lambda + mu)), out.faceU, out.seconds);
  return out;
}

/// The 3D case: a cube L = 20 mm across with n particles per edge, squeezed by six `bonded:
/// slip` plates (2 dx thick, one per face) at s = 1e4 Pa; TL clay. Closed forms: hydrostatic
/// small strain u = s L / (2 (3 lambda + 2 mu)), and the SVK stretch of svkStretch(..., 3).
inline PlatesResult runPlates3D(int n, double hourglass) {
  test::Stopwatch clock;
  const double L = 0.02, dx = L / n, t = 2 * dx;
  std::ostringstream y;
  y.precision(10);
  y << "dimension: 3\n"
    << "domain: {lo: [-0.01, -0.01, -0.01], hi: [0.03, 0.03, 0.03]}\n"
    << "spacing: " << dx << "\n"
    << "kernel: wendland_c2\nend_time: 0.012\ntime_step: {adaptive: true, cfl: 0.5}\n"
    << "output: {every_steps: 100000000}\nmaterials:\n"
    << "  - {name: clay, model: elastic, density: 2000, young_modulus: 1.0e6, poisson_ratio: 0.25, "
       "formulation: total_lagrangian, damping: 3000"
    << (hourglass > 0 ? ", hourglass: " + std::to_string(hourglass) : std::string()) << "}\n";
  const char* names[6] = {"xlo", "xhi", "ylo", "yhi", "zlo", "zhi"};
  const char* dirs[6] = {"[1, 0, 0]", "[-1, 0, 0]", "[0, 1, 0]", "[0, -1, 0]", "[0, 0, 1]", "[0, 0, -1]"};
  for (int k = 0; k < 6; ++k)
    y << "  - {name: " << names[k] << ", model: rigid, density: 2000, contact_modulus: 5.0e7, "
      << "bonded: slip, damping: 3000, plate: {direction: " << dirs[k]
      << ", stress: 1.0e4, area: " << L * L << "}}\n";
  y << "geometry:\n  - {shape: box, lo: [0.0, 0.0, 0.0], hi: [0.02, 0.02, 0.02], material: clay}\n";
  for (int k = 0; k < 6; ++k) {
    const int axis = k / 2;
    double lo[3] = {0, 0, 0}, hi[3] = {L, L, L};
    if (k % 2 == 0) { lo[axis] = -t; hi[axis] = 0.0; } else { lo[axis] = L; hi[axis] = L + t; }
    y << "  - {shape: box, lo: [" << lo[0] << ", " << lo[1] << ", " << lo[2] << "], hi: [" << hi[0]
      << ", " << hi[1] << ", " << hi[2] << "], material: " << names[k] << "}\n";
  }
  Scene s = loadSceneText(y.str(), "rigid_plates_3d.yaml");
  Simulation& sim = *s.sim;
  auto* rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  EXPECT_NE(rigid, nullptr);
  auto integrator = makeIntegrator("leapfrog");
  while (!s.finished()) integrator->step(sim, s.nextTimeStep());
  const double sigma = 1.0e4, E = 1.0e6, nu = 0.25;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  PlatesResult out;
  out.uExact = sigma * L / (2.0 * (3.0 * lambda + 2.0 * mu));
  const double stretch = svkStretch(sigma, lambda, mu, 3);
  out.uSvk = (1.0 - stretch) * L / 2.0;
  const double cauchy = sigma / (stretch * stretch);  // the face's area shrinks by stretch^2
  const ParticleStore& st = sim.store;
  const RealField stress = st.real("stress");
  const RealField ref = st.real("reference_position");
  double mean[3] = {0, 0, 0};
  int count = 0, interior = 0;
  for (Index i = 0; i < st.realCount(); ++i) {
    if (st.data(st.phase())[i] != kPhaseSolid) continue;
    const Mat<3> S = st.mat<3>(stress, i);
    for (int a = 0; a < 3; ++a) mean[a] += S(a, a);
    ++count;
    const Vec<3> X = st.vec<3>(ref, i);
    double edge = L;
    for (int a = 0; a < 3; ++a) edge = std::min({edge, X[a], L - X[a]});
    if (edge < 4 * 0.001) continue;
    ++interior;
    for (int a = 0; a < 3; ++a) {
      out.worst = std::max(out.worst, std::abs(S(a, a) + sigma) / sigma);
      out.worstSvk = std::max(out.worstSvk, std::abs(S(a, a) + cauchy) / cauchy);
    }
  }
  for (int a = 0; a < 3; ++a) out.meanErr = std::max(out.meanErr, std::abs(mean[a] / count + sigma) / sigma);
  for (const auto& [name, value] : sim.diagnostics()) {
    if (name.rfind("plate", 0) != 0) continue;
    if (name.find("_displacement") != std::string::npos) {
      out.worstU = std::max(out.worstU, std::abs(value - out.uExact) / out.uExact);
      out.worstUSvk = std::max(out.worstUSvk, std::abs(value - out.uSvk) / out.uSvk);
      out.meanU += value / 6.0;
    } else if (name.find("_force") != std::string::npos) {
      out.worstForce = std::max(out.worstForce, std::abs(value + sigma * L * L) / (sigma * L * L));
    }
  }
  for (const auto& P : rigid->plateBonds())
    out.loadArea = std::max(out.loadArea, std::abs(P.loadArea / (L * L) - 1.0));
  out.seconds = clock.seconds();
  std::printf("  3D slip: %d across, hourglass %g: t = %.4f s (%lld steps): mean stress %.2f %% off, "
              "worst interior %.2f %% (%d particles); plate displacement mean %.5e m, closed form "
              "%.5e m, worst %.2f %%; SVK closed form %.5e m, worst %.3f %%, interior stress vs "
              "SVK worst %.3f %%; plate force %.1e; load area %.2e off; %.1f s\n",
              n, hourglass, sim.time, static_cast<long long>(sim.step), 100 * out.meanErr,
              100 * out.worst, interior, out.meanU, out.uExact, 100 * out.worstU, out.uSvk,
              100 * out.worstUSvk, 100 * out.worstSvk, out.worstForce, out.loadArea, out.seconds);
  return out;
}

/// Probe of the periodic path (docs/rigid.md): the block periodic along x (the clay spans the
/// period), two `bonded: slip` plates on y only: uniaxial strain, sigma_yy = -s exactly (the face
/// does not shrink), plate displacement s L / (2 (lambda + 2 mu)) (small strain) and the SVK
/// stretch of (lambda + 2 mu) / 2 l (l^2 - 1) = -s.
inline PlatesResult runPlatesPeriodic(int n) {
  test::Stopwatch clock;
  const double L = 0.02, dx = L / n, t = 2 * dx;
  std::ostringstream y;
  y.precision(10);
  y << "dimension: 2\n"
    << "domain: {lo: [0.0, -0.01], hi: [0.02, 0.03], periodic: [true, false]}\n"
    << "spacing: " << dx << "\n"
    << "kernel: wendland_c2\nend_time: 0.012\ntime_step: {adaptive: true, cfl: 0.5}\n"
    << "output: {every_steps: 100000000}\nmaterials:\n"
    << "  - {name: clay, model: elastic, density: 2000, young_modulus: 1.0e6, poisson_ratio: 0.25, "
       "formulation: total_lagrangian, damping: 3000}\n";
  y << "  - {name: bottom, model: rigid, density: 2000, contact_modulus: 5.0e7, bonded: slip, damping: 3000, plate: {direction: [0, 1], stress: 1.0e4, area: 0.02}}\n"
    << "  - {name: top, model: rigid, density: 2000, contact_modulus: 5.0e7, bonded: slip, damping: 3000, plate: {direction: [0, -1], stress: 1.0e4, area: 0.02}}\n"
    << "geometry:\n  - {shape: box, lo: [0.0, 0.0], hi: [0.02, 0.02], material: clay}\n"
    << "  - {shape: box, lo: [0.0, " << -t << "], hi: [0.02, 0.0], material: bottom}\n"
    << "  - {shape: box, lo: [0.0, 0.02], hi: [0.02, " << L + t << "], material: top}\n";
  Scene s = loadSceneText(y.str(), "rigid_plates_periodic.yaml");
  Simulation& sim = *s.sim;
  auto* rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  EXPECT_NE(rigid, nullptr);
  auto integrator = makeIntegrator("leapfrog");
  while (!s.finished()) integrator->step(sim, s.nextTimeStep());
  const double sigma = 1.0e4, E = 1.0e6, nu = 0.25;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  PlatesResult out;
  out.uExact = sigma * L / (2.0 * (lambda + 2.0 * mu));
  out.uSvk = (1.0 - svkStretch(sigma, lambda, mu, 1)) * L / 2.0;
  const ParticleStore& st = sim.store;
  const RealField stress = st.real("stress");
  for (Index i = 0; i < st.realCount(); ++i) {
    if (st.data(st.phase())[i] != kPhaseSolid) continue;
    const Mat<2> S = st.mat<2>(stress, i);
    out.worst = std::max(out.worst, std::abs(S(1, 1) + sigma) / sigma);  // every particle
  }
  for (const auto& [name, value] : sim.diagnostics()) {
    if (name.rfind("plate", 0) != 0) continue;
    if (name.find("_displacement") != std::string::npos) {
      out.worstU = std::max(out.worstU, std::abs(value - out.uExact) / out.uExact);
      out.worstUSvk = std::max(out.worstUSvk, std::abs(value - out.uSvk) / out.uSvk);
      out.meanU += value / 2.0;
    } else if (name.find("_force") != std::string::npos) {
      out.worstForce = std::max(out.worstForce, std::abs(value + sigma * L) / (sigma * L));
    }
  }
  for (const auto& P : rigid->plateBonds())
    out.loadArea = std::max(out.loadArea, std::abs(P.loadArea / L - 1.0));
  out.seconds = clock.seconds();
  std::printf("  periodic slip: %d across: plate displacement mean %.5e m, small strain %.5e m "
              "(worst %.3f %%), SVK %.5e m (worst %.3f %%); sigma_yy worst %.4f %% off -s (all "
              "particles); plate force %.1e; load area %.2e off; %.1f s\n",
              n, out.meanU, out.uExact, 100 * out.worstU, out.uSvk, 100 * out.worstUSvk,
              100 * out.worst, out.worstForce, out.loadArea, out.seconds);
  return out;
}

}  // namespace poresph::test

