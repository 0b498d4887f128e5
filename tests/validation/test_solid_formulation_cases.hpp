#pragma once
// Lame and Kirsch convergence cases of the total-Lagrangian solid in 2D (plane strain) and 3D
// (slab periodic along z), shared by test_solid_formulation.cpp (default suite) and
// test_solid_formulation_long.cpp (3D and the finest 2D Kirsch). See test_solid_formulation.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "physics/solid/solid_scenes.hpp"
#include "tests/support/validation_record.hpp"

namespace poresph::solid::formulation_cases {

constexpr double kPi = 3.14159265358979323846;
/// Layers of the 3D slab along z (periodic): the period must hold two kernel supports (2 x 2.6 dx).
constexpr int kSlabLayers = 6;

struct Particles {
  std::vector<double> xy, volume;  // 2D positions and areas of the plane section
  std::vector<int> material;       // 0: body, 1: loaded zone (pressure selection)
};

/// Puts the plane section into the simulation: in 2D as is; in 3D extruded over kSlabLayers
/// layers z = (k + 1/2) dx of a domain periodic along z.
template <int D>
void place(Simulation& sim, const Particles& p, double dx, double rho0,
           const std::array<double, 2>& lo, const std::array<double, 2>& hi) {
  const Index n2 = static_cast<Index>(p.volume.size());
  const int layers = D == 3 ? kSlabLayers : 1;
  const Index first = sim.store.addParticles(n2 * layers);
  double* x = sim.store.data(sim.store.position());
  double* m = sim.store.data(sim.store.mass());
  std::int32_t* mat = sim.store.data(sim.store.material());
  for (int k = 0; k < layers; ++k)
    for (Index q = 0; q < n2; ++q) {
      const Index i = first + k * n2 + q;
      x[i * D] = p.xy[static_cast<size_t>(2 * q)];
      x[i * D + 1] = p.xy[static_cast<size_t>(2 * q + 1)];
      if (D == 3) x[i * D + 2] = (k + 0.5) * dx;
      m[i] = rho0 * p.volume[static_cast<size_t>(q)] * (D == 3 ? dx : 1.0);
      mat[i] = p.material[static_cast<size_t>(q)];
    }
  sim.domain.lo = {lo[0], lo[1], 0.0};
  sim.domain.hi = {hi[0], hi[1], D == 3 ? kSlabLayers * dx : 1.0};
  if (D == 3) sim.domain.periodic = {false, false, true};
}

/// Symmetry mirrors on x = 0 and y = 0 (quarter model), YAML entries.
template <int D>
std::string symmetryPlanes() {
  const std::string z = D == 3 ? ", -1" : "", z1 = D == 3 ? ", 1" : "", z0 = D == 3 ? ", 0" : "";
  return "{name: symmetry_x, type: symmetry, box: {min: [-1, -1" + z + "], max: [0, 1" + z1 +
         "]}, mirror: {point: [0, 0" + z0 + "], normal: [1, 0" + z0 + "]}},"
         "{name: symmetry_y, type: symmetry, box: {min: [-1, -1" + z + "], max: [1, 0" + z1 +
         "]}, mirror: {point: [0, 0" + z0 + "], normal: [0, 1" + z0 + "]}}";
}

inline std::string materialYaml(double E, double nu, double damping) {
  return "{density: 2000, young_modulus: " + std::to_string(E) + ", poisson_ratio: " +
         std::to_string(nu) + ", formulation: total_lagrangian, damping: " + std::to_string(damping) + "}";
}

inline std::string label(int D, double nu) {
  char s[64];
  std::snprintf(s, sizeof s, "%s_nu%03d", D == 2 ? "2d" : "3d", static_cast<int>(std::lround(nu * 100)));
  return s;
}

// ------------------------------------------------------------------------------------------------
// Lame: thick-walled cylinder under internal pressure (plane strain)
// ------------------------------------------------------------------------------------------------
struct LameResult {
  double radial = 0, hoop = 0, bore = 0, wall = 0;  // errors: / p, / p, relative
  Index particles = 0;
};

template <int D>
LameResult runLame(double nu, int across) {
  test::Stopwatch clock;
  const double a = 0.01, b = 0.02, p = 1.0e5, E = 1.0e8;
  const double dx = (b - a) / across;
  Simulation sim(D);
  addMaterial(sim, "clay", "elastic", materialYaml(E, nu, 2.0e4));
  addMaterial(sim, "clay_bore", "elastic", materialYaml(E, nu, 2.0e4));
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::CubicSpline, D, 1.3 * dx);
  const double depth = 2.0 * sim.kernel.support() + dx;  // mirror layers: two supports
  const double loaded = a + 2.0 * sim.kernel.support();  // consistent load: two supports deep
  Particles P;
  std::vector<double> all, allV;
  appendRings(a, dx, across, all, allV);
  for (size_t k = 0; k < allV.size(); ++k)
    if (all[2 * k] > -depth && all[2 * k + 1] > -depth) {
      P.xy.push_back(all[2 * k]);
      P.xy.push_back(all[2 * k + 1]);
      P.volume.push_back(allV[k]);
      P.material.push_back(std::hypot(all[2 * k], all[2 * k + 1]) <= loaded ? 1 : 0);
    }
  place<D>(sim, P, dx, 2000.0, {-b - depth, -b - depth}, {b + depth, b + depth});
  ElasticSolidModule& solid = addSolidModule(
      sim, "{boundaries: [{name: bore, type: pressure, material: clay_bore, pressure: " +
               std::to_string(p) + ", ramp_time: 1.0e-3}," + symmetryPlanes<D>() + "]}");
  solid.initialise(sim);
  auto integrator = makeIntegrator("leapfrog");
  const double dt = 0.5 * solid.elasticTimeStepLimit(sim);
  const long steps = static_cast<long>(4.0e-3 / dt);
  for (long k = 0; k < steps; ++k) integrator->step(sim, dt);

  // Lame: sigma_r = A - B / r^2, sigma_t = A + B / r^2; plane strain
  // u_r = (1 + nu) / E * A * ((1 - 2 nu) r + b^2 / r)
  const double A = p * a * a / (b * b - a * a), B = A * b * b;
  const int bins = 8;
  std::vector<double> sr(bins, 0.0), st(bins, 0.0), rs(bins, 0.0);
  std::vector<int> cnt(bins, 0);
  double ur = 0.0;
  int nur = 0;
  ParticleStore& s = sim.store;
  const RealField X = s.real("reference_position"), sigma = s.real("stress"), u = s.real("displacement");
  for (Index i = 0; i < s.realCount(); ++i) {
    const Vec<D> Xi = s.vec<D>(X, i);
    if (Xi[0] < 0.0 || Xi[1] < 0.0) continue;  // mirror layers
    const double r = std::hypot(Xi[0], Xi[1]);
    Vec<D> er = Vec<D>::Zero(), et = Vec<D>::Zero();
    er[0] = Xi[0] / r;
    er[1] = Xi[1] / r;
    et[0] = -er[1];
    et[1] = er[0];
    const Mat<D> S = s.mat<D>(sigma, i);
    const int k = std::min(bins - 1, static_cast<int>((r - a) / (b - a) * bins));
    sr[static_cast<size_t>(k)] += er.dot(S * er);
    st[static_cast<size_t>(k)] += et.dot(S * et);
    rs[static_cast<size_t>(k)] += r;
    ++cnt[static_cast<size_t>(k)];
    if (r < a + dx) {  // first ring
      ur += er.dot(s.vec<D>(u, i));
      ++nur;
    }
  }
  LameResult res;
  for (int k = 0; k < bins; ++k) {
    const double r = rs[static_cast<size_t>(k)] / cnt[static_cast<size_t>(k)];
    res.radial = std::max(res.radial, std::abs(sr[static_cast<size_t>(k)] / cnt[static_cast<size_t>(k)] - (A - B / (r * r))) / p);
    res.hoop = std::max(res.hoop, std::abs(st[static_cast<size_t>(k)] / cnt[static_cast<size_t>(k)] - (A + B / (r * r))) / p);
  }
  const double r1 = a + 0.5 * dx;
  const double urExact = (1 + nu) / E * A * ((1 - 2 * nu) * r1 + b * b / r1);
  res.bore = std::abs(ur / nur - urExact) / urExact;
  res.wall = clock.seconds();
  res.particles = s.realCount();
  return res;
}

/// Observed order between two resolutions n1 < n2 (particles across) of errors e1, e2.
inline double order(double e1, double e2, int n1, int n2) {
  return std::log(e1 / e2) / std::log(static_cast<double>(n2) / n1);
}

/// Runs Lame at three resolutions; asserts the finest errors (hoop, radial < 5 % of p, bore
/// displacement < 2 %) and that each error falls from the coarsest to the finest resolution with
/// an observed order above `minOrder` (set from the measurement, docs/solid.md).
template <int D>
void checkLame(double nu, const std::vector<int>& across, double minOrder = 1.2) {
  std::vector<LameResult> r;
  for (int n : across) {
    r.push_back(runLame<D>(nu, n));
    std::printf("Lame %dD nu = %.2f, %d across: radial %.2f %% p, hoop %.2f %% p, bore u_r %.2f %%, %lld particles, %.1f s\n",
                D, nu, n, 100 * r.back().radial, 100 * r.back().hoop, 100 * r.back().bore,
                static_cast<long long>(r.back().particles), r.back().wall);
  }
  const size_t f = r.size() - 1;
  const double oR = order(r[0].radial, r[f].radial, across[0], across[f]);
  const double oT = order(r[0].hoop, r[f].hoop, across[0], across[f]);
  const double oU = order(r[0].bore, r[f].bore, across[0], across[f]);
  std::printf("  observed order %d -> %d across: radial %.2f, hoop %.2f, bore %.2f\n", across[0], across[f], oR, oT, oU);
  const std::string ref = "Lame closed form (thick-walled cylinder, plane strain)";
  for (size_t k = 0; k < r.size(); ++k) {
    const std::string res = std::to_string(across[k]) + " body-fitted rings across the wall (a = 10 mm, b = 20 mm), h = 1.3 dx, " +
                            (D == 2 ? "2D quarter + mirrors" : "3D slab of 6 layers periodic along z, quarter + mirrors");
    const std::string tol = k == f ? "< 5 % p (stress), < 2 % (u_r); falling with resolution" : "falling with resolution";
    const std::string c = "solid_tl_lame_" + label(D, nu) + "_" + std::to_string(across[k]);
    test::recordValidation({c, "max radial-stress error over 8 bins / p", r[k].radial, 0.0, r[k].radial, res, r[k].wall, tol, ref});
    test::recordValidation({c, "max hoop-stress error over 8 bins / p", r[k].hoop, 0.0, r[k].hoop, res, r[k].wall, tol, ref});
    test::recordValidation({c, "bore displacement u_r(a + dx/2), relative error", r[k].bore, 0.0, r[k].bore, res, r[k].wall, tol, ref});
  }
  EXPECT_LT(r[f].radial, 0.05) << D << "D nu = " << nu;
  EXPECT_LT(r[f].hoop, 0.05) << D << "D nu = " << nu;
  EXPECT_LT(r[f].bore, 0.02) << D << "D nu = " << nu;
  EXPECT_GT(oR, minOrder) << "radial " << D << "D nu = " << nu;
  EXPECT_GT(oT, minOrder) << "hoop " << D << "D nu = " << nu;
  EXPECT_GT(oU, minOrder) << "bore " << D << "D nu = " << nu;
}

// ------------------------------------------------------------------------------------------------
// Kirsch: plate with a circular hole under remote tension (plane strain)
// ------------------------------------------------------------------------------------------------
struct KirschResult {
  double kt = 0, wall = 0;
  Index particles = 0;
};

template <int D>
KirschResult runKirsch(double nu, int perRadius) {
  test::Stopwatch clock;
  const double a = 0.01, W = 8.0 * a, sigma0 = 1.0e5;
  const double dx = a / perRadius;
  Simulation sim(D);
  addMaterial(sim, "plate", "elastic", materialYaml(1.0e9, nu, 2.0e4));
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::CubicSpline, D, 1.3 * dx);
  const double depth = 2.0 * sim.kernel.support() + dx;
  const int n = static_cast<int>(std::lround(W / dx)), m = static_cast<int>(std::ceil(depth / dx));
  const double lattice = a + perRadius * dx;  // rings to 2 a, the Cartesian lattice beyond
  Particles P;
  std::vector<double> all, allV;
  appendRings(a, dx, perRadius, all, allV);
  for (int j = -m; j < n; ++j)
    for (int i = -m; i < n; ++i) {
      const double x = (i + 0.5) * dx, y = (j + 0.5) * dx;
      if (std::hypot(x, y) < lattice) continue;
      all.push_back(x);
      all.push_back(y);
      allV.push_back(dx * dx);
    }
  for (size_t k = 0; k < allV.size(); ++k)
    if (all[2 * k] > -depth && all[2 * k + 1] > -depth) {
      P.xy.push_back(all[2 * k]);
      P.xy.push_back(all[2 * k + 1]);
      P.volume.push_back(allV[k]);
      P.material.push_back(0);
    }
  place<D>(sim, P, dx, 2000.0, {-depth - dx, -depth - dx}, {W + dx, W + dx});
  const std::string edge = std::to_string(W - dx), z = D == 3 ? ", -1" : "", z1 = D == 3 ? ", 1" : "",
                    z0 = D == 3 ? ", 0" : "";
  ElasticSolidModule& solid = addSolidModule(
      sim, "{boundaries: [{name: pull, type: traction, box: {min: [" + edge + ", 0" + z + "], max: [1, 1" + z1 +
               "]}, traction: [" + std::to_string(sigma0) + ", 0" + z0 + "], ramp_time: 1.5e-3}," +
               symmetryPlanes<D>() + "]}");
  solid.initialise(sim);
  auto integrator = makeIntegrator("leapfrog");
  const double dt = 0.9 * solid.elasticTimeStepLimit(sim);
  const long steps = static_cast<long>(5.0e-3 / dt);
  for (long k = 0; k < steps; ++k) integrator->step(sim, dt);
  // hoop stress at 90 deg of the first three rings: the two particles of each ring nearest to
  // 90 deg (at 90 - dth/2 and 90 - 3 dth/2; sigma_tt even about 90 deg: (9 f1 - f2) / 8),
  // averaged over the slab's layers in 3D; quadratic extrapolation to r = a
  ParticleStore& s = sim.store;
  const RealField X = s.real("reference_position"), sig = s.real("stress");
  std::vector<double> rr, ff;
  for (int k = 0; k < 3; ++k) {
    const double r = a + (k + 0.5) * dx;
    const long N = std::max(4L, 4L * std::lround(2.0 * kPi * r / (4.0 * dx)));
    const double dth = 2.0 * kPi / static_cast<double>(N);
    double f[2] = {0, 0};
    int c[2] = {0, 0};
    for (Index i = 0; i < s.realCount(); ++i) {
      const Vec<D> Xi = s.vec<D>(X, i);
      if (std::abs(std::hypot(Xi[0], Xi[1]) - r) > 1e-3 * dx || Xi[0] < 0.0 || Xi[1] < 0.0) continue;
      const double t = std::atan2(Xi[1], Xi[0]);
      const int which = std::abs(t - (0.5 * kPi - 0.5 * dth)) < 0.1 * dth ? 0
                        : std::abs(t - (0.5 * kPi - 1.5 * dth)) < 0.1 * dth ? 1 : -1;
      if (which < 0) continue;
      Vec<D> e = Vec<D>::Zero();
      e[0] = -std::sin(t);
      e[1] = std::cos(t);
      f[which] += e.dot(s.mat<D>(sig, i) * e) / sigma0;
      ++c[which];
    }
    rr.push_back(r);
    ff.push_back((9.0 * f[0] / c[0] - f[1] / c[1]) / 8.0);
  }
  KirschResult res;
  const double x = a;
  res.kt = ff[0] * (x - rr[1]) * (x - rr[2]) / ((rr[0] - rr[1]) * (rr[0] - rr[2])) +
           ff[1] * (x - rr[0]) * (x - rr[2]) / ((rr[1] - rr[0]) * (rr[1] - rr[2])) +
           ff[2] * (x - rr[0]) * (x - rr[1]) / ((rr[2] - rr[0]) * (rr[2] - rr[1]));
  res.wall = clock.seconds();
  res.particles = s.realCount();
  return res;
}

/// Observed order of the K_t increments of three resolutions (Richardson: d2 / d1 = (h1^p -
/// h2^p) / (h0^p - h1^p), h = 1 / perRadius; 0 when the increments do not shrink) and the limit
/// it extrapolates to.
struct KirschOrder {
  double order = 0.0, limit = 0.0;
};
inline KirschOrder kirschOrder(const std::vector<int>& perRadius, const std::vector<KirschResult>& r) {
  const double d1 = r[1].kt - r[0].kt, d2 = r[2].kt - r[1].kt;
  // observed order of the K_t increments (Richardson): d2 / d1 = (q^-p - 1) ... for n_k in a
  // geometric-like sequence; written for the actual resolutions with p from the three values
  const auto model = [&](double p) {
    const double h0 = 1.0 / perRadius[0], h1 = 1.0 / perRadius[1], h2 = 1.0 / perRadius[2];
    return (std::pow(h1, p) - std::pow(h2, p)) / (std::pow(h0, p) - std::pow(h1, p));
  };
  double lo = 0.01, hi = 10.0;  // model(p) falls with p: solve model(p) = d2 / d1 by bisection
  const double ratio = d1 != 0.0 ? d2 / d1 : 1.0;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (model(mid) > ratio ? lo : hi) = mid;
  }
  const double o = ratio > 0.0 && ratio < model(0.01) ? 0.5 * (lo + hi) : 0.0;
  const double limit = r[2].kt + d2 * std::pow(1.0 / perRadius[2], o) /
                                      (std::pow(1.0 / perRadius[1], o) - std::pow(1.0 / perRadius[2], o) + 1e-300);
  return {o, limit};
}

/// Runs Kirsch at three resolutions (returned); asserts |K_t - 3| / 3 < tol at the finest and that K_t
/// converges: it rises with resolution and its last change is smaller than the first by the
/// factor the observed order `minOrder` implies (K_t tends to a limit about 3 % below Kirsch's 3
/// with the quadratic extrapolation from the first three rings: docs/solid.md).
template <int D>
std::vector<KirschResult> checkKirsch(double nu, const std::vector<int>& perRadius, double tol,
                                      double minOrder = 1.0) {
  std::vector<KirschResult> r;
  std::vector<double> err;
  for (int n : perRadius) {
    r.push_back(runKirsch<D>(nu, n));
    err.push_back(std::abs(r.back().kt - 3.0) / 3.0);
    std::printf("Kirsch %dD nu = %.2f, %d per radius: K_t = %.3f (%.1f %%), %lld particles, %.1f s\n", D, nu, n,
                r.back().kt, 100 * err.back(), static_cast<long long>(r.back().particles), r.back().wall);
  }
  const KirschOrder ko = kirschOrder(perRadius, r);
  const double d1 = r[1].kt - r[0].kt, d2 = r[2].kt - r[1].kt, o = ko.order, limit = ko.limit;
  std::printf("  K_t increments %.4f, %.4f: observed order %.2f, Richardson limit %.3f\n", d1, d2, o, limit);
  const size_t f = r.size() - 1;
  for (size_t k = 0; k < r.size(); ++k) {
    const std::string res = "hole radius " + std::to_string(perRadius[k]) + " dx, rings to 2 a, lattice beyond, W = 8 a, h = 1.3 dx, " +
                            (D == 2 ? "2D plane strain" : "3D slab of 6 layers periodic along z");
    char tol_s[128];
    std::snprintf(tol_s, sizeof tol_s, k == f ? "< %.0f %%; K_t converging (order > %.1f)" : "K_t converging (order > %.1f)",
                  k == f ? 100 * tol : minOrder, minOrder);
    test::recordValidation({"solid_tl_kirsch_" + label(D, nu) + "_" + std::to_string(perRadius[k]),
                            "K_t: sigma_tt(r, 90 deg) of the first 3 rings extrapolated to r = a", r[k].kt, 3.0,
                            err[k], res, r[k].wall, tol_s, "Kirsch (infinite plate)"});
  }
  EXPECT_LT(err[f], tol) << D << "D nu = " << nu;
  EXPECT_GT(d1, 0.0) << D << "D nu = " << nu;
  EXPECT_GT(d2, 0.0) << D << "D nu = " << nu;
  EXPECT_GT(o, minOrder) << D << "D nu = " << nu;
  return r;
}

}  // namespace poresph::solid::formulation_cases
