#pragma once
// Sessile drop in 3D on a flat lattice-aligned wall (issue 14 "Sessile droplet ... in 3D").
// Scene: a cell periodic along x, y and z; a wall slab 3 dx thick (contact angle theta) at the
// bottom, z in [0, 3 dx); fluid above it up to the cell's top (the gas above the drop meets the
// slab's underside through the periodic z boundary: gas only there, no interface). The drop starts
// as a cube of the volume of a hemisphere of radius R0 (side 1.28 R0), standing on the wall at the
// cell's centre: not the answer for any angle (its faces meet the wall at 90 degrees, its edges
// are sharp). Equal densities and viscosities, p_b = 100 Pa, quintic h = dx, the 2D flat-wall
// test's settings (fluid_wetting_case.hpp, test::kWettingGhostSettings).
// Contact angle, two independent readings:
//  - sphere fit (algebraic, Kasa in 3D) to the midpoints of liquid-gas pairs closer than 1.5 dx
//    lying more than 2 dx above the wall's surface z_w = 3 dx (half-way between the wall's top
//    sites and the fluid's lowest: the wall is aligned with the lattice); cos(theta) =
//    -(z_c - z_w) / r;
//  - cap reading from the liquid volume V (N dx^3) and its height H above z_w (highest liquid
//    particle + dx/2): V = pi r^3 (1 - cos q)^2 (2 + cos q) / 3, H = r (1 - cos q), so
//    3 V / (pi H^3) = (2 + cos q) / (1 - cos q) =: y and cos q = (y - 2) / (y + 1).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"
#include "tests/support/validation_record.hpp"
#include "tests/support/wetting_case_run.hpp"

namespace poresph::test {

struct Sessile3D {
  static constexpr double kPi = 3.14159265358979323846;
  Simulation sim{3};
  FluidModule* fluid = nullptr;
  fluidsetup::Stepper stepper;
  double R0, dx, gamma = 0.05, mu = 0.01, rho = 1000.0, c = 2.0, pb = 100.0;
  double zWall = 0.0, Lxy = 0.0, Lz = 0.0;
  int liquid = 0, gas = 1, wall = 2;

  /// radius: R0 (m); rOverDx: R0 / dx; boxHalf: half the cell's side along x and y in R0;
  /// boxHeight: the fluid layer's height in R0.
  Sessile3D(double thetaDeg, double radius, int rOverDx, const std::string& extra, double viscosity = 0.01,
            double boxHalf = 2.0, double boxHeight = 2.0) {
    namespace fs = poresph::fluidsetup;
    R0 = radius;
    mu = viscosity;
    dx = R0 / rOverDx;
    const int nxy = static_cast<int>(std::lround(2.0 * boxHalf * rOverDx));
    const int nz = static_cast<int>(std::lround(boxHeight * rOverDx)) + 3;
    Lxy = nxy * dx;
    Lz = nz * dx;
    zWall = 3.0 * dx;
    sim.spacing = dx;
    sim.kernel = Kernel(KernelType::QuinticSpline, 3, dx);
    sim.domain.lo = {0, 0, 0};
    sim.domain.hi = {Lxy, Lxy, Lz};
    sim.domain.periodic = {true, true, true};
    char buf[300];
    std::snprintf(buf, sizeof buf, "{density: %g, sound_speed: %g, viscosity: %g, colour: 1, background_pressure: %g}",
                  rho, c, mu, pb);
    liquid = fs::addMaterial(sim, "liquid", "fluid", buf);
    std::snprintf(buf, sizeof buf, "{density: %g, sound_speed: %g, viscosity: %g, colour: -1, background_pressure: %g}",
                  rho, c, mu, pb);
    gas = fs::addMaterial(sim, "gas", "fluid", buf);
    std::snprintf(buf, sizeof buf, "{density: %g, contact_angle: %g}", rho, thetaDeg);
    wall = fs::addMaterial(sim, "wall", "wall", buf);
    std::snprintf(buf, sizeof buf, "{surface_tension: %g%s}", gamma, extra.c_str());
    fluid = fs::addFluidModule(sim, buf);
    const double side = std::cbrt(2.0 / 3.0 * kPi) * R0;  // cube of the hemisphere's volume
    const double xc = 0.5 * Lxy, zw = zWall;
    auto inWall = [=](const double* x) { return x[2] < zw; };
    auto inDrop = [=](const double* x) {
      return x[2] >= zw && x[2] < zw + side && std::abs(x[0] - xc) < 0.5 * side && std::abs(x[1] - xc) < 0.5 * side;
    };
    fs::addLattice(sim, {0, 0, 0}, {Lxy, Lxy, Lz}, liquid, inDrop);
    fs::addLattice(sim, {0, 0, 0}, {Lxy, Lxy, Lz}, gas, [=](const double* x) { return !inWall(x) && !inDrop(x); });
    fs::addLattice(sim, {0, 0, 0}, {Lxy, Lxy, Lz}, wall, inWall);
    fluid->initialise(sim);
  }

  /// Contact angle (degrees, through the liquid) from the sphere fitted to the liquid-gas pair
  /// midpoints above 2 dx (rc, zc: the sphere's radius and centre height above the wall).
  double contactAngle(double& rc, double& zc, int& npts) {
    sim.updateNeighbours();
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const std::int32_t* mt = st.data(st.material());
    const auto& nl = sim.neighbours;
    std::vector<Eigen::Vector3d> pts;
    const double half = 0.5 * Lxy;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (mt[i] != liquid) continue;
      for (auto k = nl.offset[static_cast<size_t>(i)]; k < nl.offset[static_cast<size_t>(i) + 1]; ++k) {
        const Index j = nl.index[static_cast<size_t>(k)];
        if (mt[j] != gas) continue;
        Eigen::Vector3d d;
        for (int a = 0; a < 3; ++a) d[a] = x[3 * j + a] - x[3 * i + a];
        for (int a = 0; a < 2; ++a) d[a] -= Lxy * std::round(d[a] / Lxy);  // minimum image (ghost neighbours)
        if (d.norm() > 1.5 * dx) continue;
        Eigen::Vector3d p(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
        p += 0.5 * d;
        // the drop sits at the cell's centre: unwrap to the centred frame
        for (int a = 0; a < 2; ++a) p[a] -= Lxy * std::round((p[a] - half) / Lxy);
        if (p[2] > zWall + 2.0 * dx) pts.push_back(p);
      }
    }
    npts = static_cast<int>(pts.size());
    const int n = npts;
    Eigen::MatrixXd A(n, 4);
    Eigen::VectorXd rhs(n);
    for (int k = 0; k < n; ++k) {
      const auto& p = pts[static_cast<size_t>(k)];
      A.row(k) << p.x(), p.y(), p.z(), 1.0;
      rhs[k] = -p.squaredNorm();
    }
    const Eigen::Vector4d s = A.colPivHouseholderQr().solve(rhs);
    const Eigen::Vector3d ctr(-0.5 * s[0], -0.5 * s[1], -0.5 * s[2]);
    rc = std::sqrt(ctr.squaredNorm() - s[3]);
    zc = ctr.z() - zWall;
    return std::acos(std::clamp(-zc / rc, -1.0, 1.0)) * 180.0 / kPi;
  }

  /// Cap angle (degrees) from the liquid's volume and height (see the header).
  double capAngle(double& height, double& volume) const {
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const std::int32_t* mt = st.data(st.material());
    height = 0.0;
    long long nl = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (mt[i] != liquid) continue;
      ++nl;
      height = std::max(height, x[3 * i + 2] + 0.5 * dx - zWall);
    }
    volume = static_cast<double>(nl) * dx * dx * dx;
    const double y = 3.0 * volume / (kPi * height * height * height);
    return std::acos(std::clamp((y - 2.0) / (y + 1.0), -1.0, 1.0)) * 180.0 / kPi;
  }

  /// Largest fluid speed (the spurious current once the drop has settled).
  double maxSpeed() const {
    const auto& st = sim.store;
    const double* v = st.data(st.velocity());
    const std::int32_t* mt = st.data(st.material());
    double s = 0.0;
    for (Index i = 0; i < st.realCount(); ++i)
      if (mt[i] == liquid || mt[i] == gas) s = std::max(s, std::sqrt(v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]));
    return s;
  }

  /// x y z material (0 liquid, 1 gas, 2 wall) per line.
  void dump(const std::string& name) const {
    dumpParticles(sim, name, [this](std::int32_t m) { return m == liquid ? 0 : m == gas ? 1 : 2; });
  }
};

struct Wetting3DResult {
  double mean = 0, lo = 1e300, hi = -1e300, cap = 0, speed = 0, wall = 0, cpu = 0;
  int samples = 0;
  long long steps = 0, particles = 0;
};

/// Runs the 3D sessile drop to tEnd; the sphere-fit angle sampled every `every` seconds over
/// [tStart, tEnd] and averaged; the cap angle and the largest fluid speed at the end.
inline Wetting3DResult runSessile3D(double thetaDeg, int rdx, double tStart, double tEnd, double viscosity,
                                    const std::string& extra, double every = 0.005, double boxHalf = 2.0,
                                    double boxHeight = 2.0, const std::string& tag = "") {
  const RunCost cost;
  Sessile3D s(thetaDeg, 1.5e-3, rdx, extra, viscosity, boxHalf, boxHeight);
  Wetting3DResult r;
  double rc = 0, zc = 0;
  int np = 0;
  const bool verbose = std::getenv("SESSILE3D_VERBOSE") != nullptr;
  if (verbose)
    for (double t = every; t < tStart - 1e-12; t += every) {
      s.stepper.runTo(s.sim, t);
      const double a = s.contactAngle(rc, zc, np);
      std::printf("  t %.1f ms: sphere fit %.2f deg (r %.2f dx, %d points), max speed %.3g m/s, max var %.3g\n", 1e3 * t,
                  a, rc / s.dx, np, s.maxSpeed(), s.fluid->maxDensityVariation());
      std::fflush(stdout);
    }
  s.stepper.runTo(s.sim, tStart);
  const WindowMean w = sampleWindow(
      tStart, tEnd, every, [&](double t) { s.stepper.runTo(s.sim, t); },
      [&](double t) {
        const double a = s.contactAngle(rc, zc, np);
        if (verbose)
          std::printf("  t %.1f ms: sphere fit %.2f deg (r %.2f dx, %d points), max speed %.3g m/s\n", 1e3 * t, a,
                      rc / s.dx, np, s.maxSpeed());
        return a;
      });
  r.mean = w.mean, r.lo = w.lo, r.hi = w.hi, r.samples = w.samples;
  double H = 0, V = 0;
  r.cap = s.capAngle(H, V);
  r.speed = s.maxSpeed();
  cost.finish(s.sim, r);
  std::printf("3D sessile theta %.0f R0/dx %d mu %g%s: sphere fit mean %.2f deg over [%.0f, %.0f] ms (%d samples, %.2f to "
              "%.2f), cap %.2f at the end (H %.2f dx), max speed %.3g m/s (Ca %.2e), %lld particles, %lld steps, "
              "%.1f s wall, %.1f s CPU\n",
              thetaDeg, rdx, viscosity, tag.c_str(), r.mean, 1e3 * tStart, 1e3 * tEnd, r.samples, r.lo, r.hi, r.cap,
              H / s.dx, r.speed, r.speed * viscosity / s.gamma, r.particles, r.steps, r.wall, r.cpu);
  std::fflush(stdout);
  char name[96];
  std::snprintf(name, sizeof name, "fluid_wetting_3d_theta%.0f_r%d%s.txt", thetaDeg, rdx, tag.c_str());
  s.dump(name);
  return r;
}

}  // namespace poresph::test
