#pragma once
// A static droplet scene in 2D or 3D for the CSF surface-tension tests (Eqs. 5.6-5.8, 1.9):
// a periodic box [0, B)^D of gas with a liquid disc / sphere of radius R at the centre, on the
// lattice of spacing dx = R / (R/dx), quintic spline with h = dx, colours +1 / -1. Densities and
// viscosities of both phases are parameters (default equal: the thesis' static droplet).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"

namespace poresph::test {

struct FluidDrop {
  struct Params {
    int dim = 2;
    double R = 1.5e-3;
    double rOverDx = 15;
    double boxOverR = 3.0;      ///< B / R
    double hOverDx = 1.0;       ///< smoothing length of the quintic spline / dx
    double gamma = 0.05;
    double rhoLiquid = 1000.0, rhoGas = 1000.0;
    double muLiquid = 0.3, muGas = 0.3;
    double cLiquid = 2.0, cGas = 2.0;
    double backgroundPressure = 0.0;
    std::string extra;          ///< extra keys of the fluid section, starting with ", "
    bool square = false;        ///< a square / cube of the same area / volume instead
  };

  Simulation sim;
  FluidModule* fluid = nullptr;
  fluidsetup::Stepper stepper;
  Params prm;
  double dx, R, B;

  explicit FluidDrop(const Params& p) : sim(p.dim), prm(p) {
    namespace fs = poresph::fluidsetup;
    const int d = p.dim;
    R = p.R;
    dx = R / p.rOverDx;
    // the box holds an integer number of lattice cells (periodic lattice without a seam)
    B = std::round(p.boxOverR * p.rOverDx) * dx;
    sim.spacing = dx;
    sim.kernel = Kernel(KernelType::QuinticSpline, d, p.hOverDx * dx);
    sim.domain.lo = {0, 0, 0};
    sim.domain.hi = {B, B, d == 3 ? B : 0.0};
    sim.domain.periodic = {true, true, d == 3};
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "{density: %g, sound_speed: %g, viscosity: %g, colour: 1, background_pressure: %g}",
                  p.rhoLiquid, p.cLiquid, p.muLiquid, p.backgroundPressure);
    const int liq = fs::addMaterial(sim, "liquid", "fluid", buf);
    std::snprintf(buf, sizeof buf,
                  "{density: %g, sound_speed: %g, viscosity: %g, colour: -1, background_pressure: %g}",
                  p.rhoGas, p.cGas, p.muGas, p.backgroundPressure);
    const int gas = fs::addMaterial(sim, "gas", "fluid", buf);
    std::snprintf(buf, sizeof buf, "{surface_tension: %g%s}", p.gamma, p.extra.c_str());
    fluid = fs::addFluidModule(sim, buf);
    const double c = 0.5 * B, RR = R;
    // side of the square (cube) of the disc's area (sphere's volume)
    const double side = d == 2 ? std::sqrt(3.14159265358979323846) * R
                               : std::cbrt(4.0 * 3.14159265358979323846 / 3.0) * R;
    const bool square = p.square;
    auto inside = [=](const double* x) {
      double r2 = 0, m = 0;
      for (int a = 0; a < d; ++a) r2 += (x[a] - c) * (x[a] - c), m = std::max(m, std::abs(x[a] - c));
      return square ? m < 0.5 * side : r2 < RR * RR;
    };
    const std::vector<double> lo(static_cast<size_t>(d), 0.0), hi(static_cast<size_t>(d), B);
    fs::addLattice(sim, lo, hi, liq, inside);
    fs::addLattice(sim, lo, hi, gas, [&](const double* x) { return !inside(x); });
    fluid->initialise(sim);
  }

  Index count() const { return sim.store.realCount(); }

  double radiusOf(const double* x) const {
    double r2 = 0;
    for (int a = 0; a < prm.dim; ++a) r2 += (x[a] - 0.5 * B) * (x[a] - 0.5 * B);
    return std::sqrt(r2);
  }

  /// Mean pressure inside r < r1 and outside r > r2 (distance from the box centre).
  void pressures(double r1, double r2, double& pin, double& pout) const {
    const auto& st = sim.store;
    const int d = prm.dim;
    const double* x = st.data(st.position());
    const double* p = st.data(fluid->pressure);
    double si = 0, ni = 0, so = 0, no = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      const double r = radiusOf(x + i * d);
      if (r < r1) si += p[i], ni += 1;
      if (r > r2) so += p[i], no += 1;
    }
    pin = si / ni;
    pout = so / no;
  }

  /// Pressure jump with the default averaging regions (r < R - 3h inside, r > R + 3h outside).
  double jump() const {
    const double h = sim.kernel.h();
    double pin, pout;
    pressures(R - 3 * h, R + 3 * h, pin, pout);
    return pin - pout;
  }

  /// Root-mean-square particle speed (all particles; equal masses in the tests that use it).
  double rmsSpeed() const {
    const auto& st = sim.store;
    const int d = prm.dim;
    const double* v = st.data(st.velocity());
    double s = 0;
    for (Index i = 0; i < st.realCount() * d; ++i) s += v[i] * v[i];
    return std::sqrt(s / static_cast<double>(st.realCount()));
  }

  double maxSpeed() const {
    const auto& st = sim.store;
    const int d = prm.dim;
    const double* v = st.data(st.velocity());
    double m = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      double v2 = 0;
      for (int a = 0; a < d; ++a) v2 += v[i * d + a] * v[i * d + a];
      m = std::max(m, v2);
    }
    return std::sqrt(m);
  }

  /// Liquid extent: largest distance of a liquid particle and smallest distance of a gas
  /// particle from the liquid's centroid (the drop stays intact when rmaxLiquid < R + 2 dx and
  /// rminGas > R - 2 dx).
  void extent(double& rmaxLiquid, double& rminGas) const {
    const auto& st = sim.store;
    const int d = prm.dim;
    const double* x = st.data(st.position());
    const double* col = st.data(fluid->colour);
    double cen[3] = {0, 0, 0}, n = 0;
    for (Index i = 0; i < st.realCount(); ++i)
      if (col[i] > 0) {
        for (int a = 0; a < d; ++a) cen[a] += x[i * d + a];
        n += 1;
      }
    for (int a = 0; a < d; ++a) cen[a] /= n;
    rmaxLiquid = 0;
    rminGas = 1e300;
    for (Index i = 0; i < st.realCount(); ++i) {
      double r2 = 0;
      for (int a = 0; a < d; ++a) r2 += (x[i * d + a] - cen[a]) * (x[i * d + a] - cen[a]);
      const double r = std::sqrt(r2);
      if (col[i] > 0) rmaxLiquid = std::max(rmaxLiquid, r);
      else rminGas = std::min(rminGas, r);
    }
  }

  /// Dynamic relaxation: multiplies the velocities (and the leapfrog's half-step velocities, its
  /// state) by `factor`. Used only to remove the acoustic transient of the start from rest; the
  /// equilibrium it leads to is the undamped one (the measurement follows an undamped phase).
  void scaleVelocities(double factor) {
    auto& st = sim.store;
    const Index n = st.realCount() * prm.dim;
    double* v = st.data(st.velocity());
    for (Index i = 0; i < n; ++i) v[i] *= factor;
    if (st.has("integrator_velocity")) {
      double* w = st.data(st.real("integrator_velocity"));
      for (Index i = 0; i < n; ++i) w[i] *= factor;
    }
  }

  /// Angular frequency of the box's lowest acoustic mode, 2 pi c / B.
  double acousticOmega() const { return 2.0 * 3.14159265358979323846 * prm.cLiquid / B; }

  struct Measurement {
    double dpMean = 0, dpMin = 1e300, dpMax = -1e300;  ///< jump over the measuring window
    double speedEnd = 0, speedMean = 0;                ///< largest particle speed: at the end, window mean
    double rmsMean = 0;                                ///< rms particle speed, window mean
    long steps = 0, stepsWindow = 0;
  };

  /// Start at rest; damped phase t < tRelax (velocities scaled by exp(-lambda dt) after each
  /// step, lambda = 2 zeta omega with the box's acoustic omega, zeta = 0.6: near-critical damping
  /// of the start's compression wave), then undamped to tEnd; the jump and the largest speed are
  /// sampled after every step of the last tWindow and averaged over time.
  Measurement settleAndMeasure(double tRelax, double tEnd, double tWindow, double zeta = 0.6) {
    Measurement m;
    const double lambda = 2.0 * zeta * acousticOmega();
    double sdp = 0, ssp = 0, srms = 0, st = 0;
    while (sim.time < tEnd * (1.0 - 1e-12)) {
      const double dt = stepper.step(sim, tEnd - sim.time);
      if (sim.time <= tRelax) scaleVelocities(std::exp(-lambda * dt));
      if (sim.time >= tEnd - tWindow * (1.0 + 1e-9)) {
        const double dp = jump(), sp = maxSpeed();
        sdp += dp * dt;
        ssp += sp * dt;
        srms += rmsSpeed() * dt;
        st += dt;
        m.dpMin = std::min(m.dpMin, dp);
        m.dpMax = std::max(m.dpMax, dp);
        ++m.stepsWindow;
      }
    }
    m.dpMean = sdp / st;
    m.speedMean = ssp / st;
    m.rmsMean = srms / st;
    m.speedEnd = maxSpeed();
    m.steps = static_cast<long>(sim.step);
    return m;
  }

  /// Writes x, y[, z], colour, pressure, curvature, |v| of the particles (3D: those within dx/2
  /// of the lattice plane nearest z = B/2) to <build>/name.
  void dumpSlice(const std::string& name) const {
    const auto& st = sim.store;
    const int d = prm.dim;
    std::ofstream f(std::string(PORESPH_BINARY_DIR) + "/" + name);
    const double* x = st.data(st.position());
    const double* col = st.data(fluid->colour);
    const double* p = st.data(fluid->pressure);
    const double* k = st.data(fluid->curvature);
    const double* v = st.data(st.velocity());
    const double zc = (std::floor(0.5 * B / dx + 1e-9) + 0.5) * dx;  // lattice plane nearest B/2
    for (Index i = 0; i < st.realCount(); ++i) {
      if (d == 3 && std::abs(x[i * d + 2] - zc) >= 0.5 * dx) continue;
      double v2 = 0;
      for (int a = 0; a < d; ++a) v2 += v[i * d + a] * v[i * d + a];
      for (int a = 0; a < d; ++a) f << x[i * d + a] << " ";
      f << col[i] << " " << p[i] << " " << k[i] << " " << std::sqrt(v2) << "\n";
    }
  }
};

}  // namespace poresph::test
