#pragma once
// Contact angle on a wall that moves (issue 14 "Wetting on real walls": "a wall that moves
// (translating plate)"). Scene (2D): a channel periodic along x (length L = boxLength R0), a flat
// lattice-aligned floor of 3 dx of wall particles (contact angle theta) below y = 0 and a lid of
// 3 dx (angle 180: the gas colour, no interface along it) above y = 2.5 R0; the fluid between
// them. The floor translates along x at U; the lid at lidU (default U: the channel translates as a
// whole, so the steady state is the drop carried at U with its equilibrium shape; lidU = 0 adds a
// Couette shear of the gas). The drop starts as a rectangle standing on the floor (width 1.8 R0,
// the area of a half disc of radius R0: not the answer for any angle), at rest (or, with
// fluidStart = U, moving with the plate: the Galilean image of the drop on a wall at rest).
// Two representations of the moving wall:
//   WallMotion::Moving  the wall particles move (motion `prescribed`: the position follows the
//                       imposed velocity U); a translating plate as it is,
//   WallMotion::Mirror  the wall particles stay where they are and carry the velocity U, which
//                       enters the no-slip mirror 2 v_w - <v_f> and the continuity equation (an
//                       infinite plate sliding along itself; the sheared-bubble test's walls).
// Same settings as the flat-wall angle tests (test::kWettingGhostSettings, Oh = 0.036 with
// mu = 0.01 Pa s, quintic h = dx, equal densities, p_b = 100 Pa).
// Readings (in the frame of the drop: t = x - x_c unwrapped about the drop's centroid, s = y):
//  - the circle fit (Kasa) to the liquid-gas pair midpoints more than 2 dx above the wall, cut
//    with the wall's surface s = 0: cos(theta) = -s_c / r (as the flat-wall tests);
//  - per side: a geometric circle fit to the midpoints on the downstream (front, t > t_c of the
//    full fit) and upstream (rear) halves alone, each cut with the wall: the front and rear
//    angles (equal for a cap at rest; with the plate dragging the drop, advancing and receding);
//  - the drop's speed: the mean x velocity of the liquid particles, over U.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"
#include "tests/support/interface_circle.hpp"
#include "tests/support/validation_record.hpp"
#include "tests/support/wetting_case_run.hpp"
#include "tests/validation/fluid_wetting_case.hpp"  // test::kWettingGhostSettings

namespace poresph::test {

enum class WallMotion { Rest, Moving, Mirror };

/// Geometric least-squares circle (orthogonal distances; Gauss-Newton from the Kasa circle). On
/// half a cap the algebraic fit is biased (measured on the 60-degree drop at rest, R0/dx 10: the
/// halves read 63.85 by Kasa, 60.26 geometric, the whole cap 60.86 / 60.57).
inline FittedCircle geometricCircle(const std::vector<Eigen::Vector2d>& pts) {
  FittedCircle c = kasaCircle(pts);
  const int n = static_cast<int>(pts.size());
  Eigen::MatrixXd J(n, 3);
  Eigen::VectorXd res(n);
  for (int it = 0; it < 30; ++it) {
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector2d d = pts[static_cast<size_t>(k)] - c.centre;
      const double dn = std::max(d.norm(), 1e-300);
      res[k] = dn - c.radius;
      J.row(k) << -d.x() / dn, -d.y() / dn, -1.0;
    }
    const Eigen::Vector3d step = J.colPivHouseholderQr().solve(-res);
    c.centre += step.head<2>();
    c.radius += step[2];
    if (step.norm() < 1e-12 * c.radius) break;
  }
  return c;
}

struct MovingSessileParams {
  double theta = 60.0;      // prescribed contact angle (degrees)
  int rOverDx = 10;         // R0 / dx
  double R0 = 1.5e-3;       // radius of the half disc of the drop's area
  double U = 0.01;          // floor velocity along x (m/s)
  double lidU = 0.01;       // lid velocity along x (m/s)
  double fluidStart = 0.0;  // initial x velocity of every fluid particle (m/s)
  WallMotion motion = WallMotion::Moving;
  double boxLength = 5.0;   // period along x / R0
  double mu = 0.01;         // both fluids (Oh = mu / sqrt(rho gamma R0) = 0.036)
  std::string settings;     // fluid module keys (", key: value, ...")
};

struct MovingSessile {
  static constexpr double kPi = 3.14159265358979323846;
  Simulation sim{2};
  FluidModule* fluid = nullptr;
  fluidsetup::Stepper stepper;
  MovingSessileParams p;
  double dx = 0, Lx = 0, Hs = 0, gamma = 0.05, rho = 1000.0, c = 2.0, pb = 100.0;
  double xc = 0;  // drop centroid along x, unwrapped (followed from sample to sample)
  int liquid = 0, gas = 1, floor = 2, lid = 3;

  explicit MovingSessile(const MovingSessileParams& params) : p(params) {
    namespace fs = poresph::fluidsetup;
    dx = p.R0 / p.rOverDx;
    Lx = std::round(p.boxLength * p.R0 / dx) * dx;
    Hs = std::round(2.5 * p.R0 / dx) * dx;
    const double w = 3.0 * dx;
    sim.spacing = dx;
    sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
    sim.domain.lo = {0, -w, 0};
    sim.domain.hi = {Lx, Hs + w, 0};
    sim.domain.periodic = {true, false, false};
    char buf[300];
    std::snprintf(buf, sizeof buf, "{density: %g, sound_speed: %g, viscosity: %g, colour: 1, background_pressure: %g}",
                  rho, c, p.mu, pb);
    liquid = fs::addMaterial(sim, "liquid", "fluid", buf);
    std::snprintf(buf, sizeof buf, "{density: %g, sound_speed: %g, viscosity: %g, colour: -1, background_pressure: %g}",
                  rho, c, p.mu, pb);
    gas = fs::addMaterial(sim, "gas", "fluid", buf);
    const double uf = p.motion == WallMotion::Rest ? 0.0 : p.U, ul = p.motion == WallMotion::Rest ? 0.0 : p.lidU;
    std::snprintf(buf, sizeof buf, "{density: %g, contact_angle: %.17g, velocity: [%.17g, 0]}", rho, p.theta, uf);
    floor = fs::addMaterial(sim, "floor", "wall", buf);
    std::snprintf(buf, sizeof buf, "{density: %g, contact_angle: 180, velocity: [%.17g, 0]}", rho, ul);
    lid = fs::addMaterial(sim, "lid", "wall", buf);
    std::snprintf(buf, sizeof buf, "{surface_tension: %g%s}", gamma, p.settings.c_str());
    fluid = fs::addFluidModule(sim, buf);
    const double a = 0.9 * p.R0, b = 0.5 * kPi * p.R0 * p.R0 / (2.0 * a);  // rectangle of the half disc's area
    const double x0 = 0.5 * Lx;
    auto inDrop = [=](const double* x) { return std::abs(x[0] - x0) < a && x[1] > 0.0 && x[1] < b; };
    fs::addLattice(sim, {0, 0}, {Lx, Hs}, liquid, inDrop);
    fs::addLattice(sim, {0, 0}, {Lx, Hs}, gas, [&](const double* x) { return !inDrop(x); });
    fs::addLattice(sim, {0, -w}, {Lx, 0}, floor);
    fs::addLattice(sim, {0, Hs}, {Lx, Hs + w}, lid);
    if (p.motion == WallMotion::Moving) {
      // the walls translate: motion `prescribed` (as a scene region's `motion: prescribed`; the
      // fluid module keeps it for walls and the position follows the material's velocity)
      std::int32_t* mo = sim.store.data(sim.motion);
      const std::int32_t* mt = sim.store.data(sim.store.material());
      for (Index i = 0; i < sim.store.realCount(); ++i)
        if (mt[i] == floor || mt[i] == lid) mo[i] = kMotionPrescribed;
    }
    fluid->initialise(sim);
    if (p.fluidStart != 0.0) {
      double* v = sim.store.data(sim.store.velocity());
      const std::int32_t* ph = sim.store.data(sim.store.phase());
      for (Index i = 0; i < sim.store.realCount(); ++i)
        if (ph[i] == kPhaseFluid) v[2 * i] = p.fluidStart;
    }
    xc = x0;
  }

  /// Follows the drop's centroid (unwrapped about the last one) and returns the mean x velocity
  /// of the liquid particles.
  double followDrop() {
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const double* v = st.data(st.velocity());
    const std::int32_t* mt = st.data(st.material());
    double sx = 0, sv = 0;
    long long nl = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (mt[i] != liquid) continue;
      sx += unwrap(x[2 * i]);
      sv += v[2 * i];
      ++nl;
    }
    xc = sx / static_cast<double>(nl);
    return sv / static_cast<double>(nl);
  }
  double unwrap(double X) const { return X - Lx * std::round((X - xc) / Lx); }

  struct Angles {
    double full = 0, front = 0, rear = 0, r = 0;
    int points = 0, frontPoints = 0, rearPoints = 0;
  };
  /// The three circle-fit angles (degrees, through the liquid) in the drop's frame.
  Angles angles() {
    followDrop();
    std::vector<Eigen::Vector2d> pts, front, rear;
    for (const auto& mid : liquidGasMidpoints(sim, liquid, gas, dx)) {
      const Eigen::Vector2d q(unwrap(mid.x()) - xc, mid.y());
      if (q.y() > 2.0 * dx) pts.push_back(q);
    }
    Angles A;
    A.points = static_cast<int>(pts.size());
    if (pts.size() < 3) return A;
    const FittedCircle all = kasaCircle(pts);
    auto angle = [](const FittedCircle& f) {
      return std::acos(std::clamp(-f.centre.y() / f.radius, -1.0, 1.0)) * 180.0 / kPi;
    };
    A.full = angle(all);
    A.r = all.radius;
    for (const auto& q : pts) (q.x() > all.centre.x() ? front : rear).push_back(q);
    A.frontPoints = static_cast<int>(front.size());
    A.rearPoints = static_cast<int>(rear.size());
    if (front.size() >= 3) A.front = angle(geometricCircle(front));
    if (rear.size() >= 3) A.rear = angle(geometricCircle(rear));
    return A;
  }

  /// x y material per line (tests/support/wetting_case_run.hpp).
  void dump(const std::string& name) const { dumpParticles(sim, name, [](std::int32_t m) { return m; }); }
};

struct MovingWettingResult {
  double mean = 0, front = 0, rear = 0, lo = 1e300, hi = -1e300, speed = 0, travel = 0, cpu = 0, wall = 0;
  int samples = 0;
  long long steps = 0, particles = 0;
};

/// Runs the drop to tEnd and averages the readings over [tEnd / 2, tEnd] (every `every` seconds):
/// the full, front and rear angles, the drop's speed over U (mean of the liquid's x velocity) and
/// its travel over the window against the plate's, U (t2 - t1).
inline MovingWettingResult runMovingWetting(const MovingSessileParams& p, double tEnd = 0.12, double every = 0.005,
                                            const char* dumpName = nullptr) {
  const RunCost cost;
  MovingSessile s(p);
  MovingWettingResult r;
  const double t1 = 0.5 * tEnd;
  // follow the centroid through the approach (the drop moves < L / 2 between samples)
  for (double t = every; t < t1 * (1 - 1e-9); t += every) {
    s.stepper.runTo(s.sim, t);
    const double vd = s.followDrop();
    if (std::getenv("WETTING_MOVING_SERIES"))
      std::printf("  t %.0f ms: drop speed %.4f U\n", 1e3 * t, vd / (p.U != 0.0 ? p.U : 1.0));
  }
  s.stepper.runTo(s.sim, t1);
  s.followDrop();
  const double x1 = s.xc;
  double vsum = 0;
  const WindowMean w = sampleWindow(
      t1, tEnd, every, [&](double t) { s.stepper.runTo(s.sim, t); },
      [&](double t) {
        const auto A = s.angles();
        r.front += A.front;
        r.rear += A.rear;
        const double vd = s.followDrop();
        vsum += vd;
        if (std::getenv("WETTING_MOVING_SERIES"))
          std::printf("  t %.0f ms: angle %.2f front %.2f rear %.2f, drop speed %.4f U\n", 1e3 * t, A.full, A.front,
                      A.rear, vd / (p.U != 0.0 ? p.U : 1.0));
        return A.full;
      });
  r.mean = w.mean, r.lo = w.lo, r.hi = w.hi, r.samples = w.samples;
  r.front /= r.samples;
  r.rear /= r.samples;
  const double Uref = p.U != 0.0 ? p.U : 1.0;
  r.speed = vsum / r.samples / Uref;
  r.travel = (s.xc - x1) / (Uref * (tEnd - t1));
  cost.finish(s.sim, r);
  const char* mode = p.motion == WallMotion::Rest ? "rest" : p.motion == WallMotion::Moving ? "moving" : "mirror";
  std::printf("moving wall (%s) theta %.0f R0/dx %d U %g lid %g start %g: mean %.2f deg (%.2f to %.2f), front %.2f "
              "rear %.2f over [%.0f, %.0f] ms (%d samples); drop speed %.4f U, travel %.4f U; %lld particles, %lld "
              "steps, %.1f s wall, %.1f s CPU\n",
              mode, p.theta, p.rOverDx, p.U, p.lidU, p.fluidStart, r.mean, r.lo, r.hi, r.front, r.rear, 1e3 * t1,
              1e3 * tEnd, r.samples, r.speed, r.travel, r.particles, r.steps, r.wall, r.cpu);
  std::fflush(stdout);
  if (dumpName) s.dump(dumpName);
  return r;
}

}  // namespace poresph::test
