// Extreme (issue 5): a gas bubble sheared in water at density ratio 1000 and viscosity ratio 100
// (the thesis' mobility 1e-2). Plane Couette flow between two walls moving at +-U along a
// periodic x axis (walls: material model "wall" with a tangential `velocity`), a bubble of
// radius R at the centre, CSF surface tension (Eqs. 5.6-5.8, 1.9), `pressure_gradient: hu_adams`.
// The run lasts many capillary relaxation times mu_l R / gamma; it must stay finite, no particle
// may leave the channel through a wall, the bubble must stay one piece (no gas particle far from
// it, no liquid particle inside it) and it must deform but not break up at Ca = 0.2.
// The measured Taylor deformation D = (L - B) / (L + B) and the density variation are printed.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"

using namespace poresph;
namespace fs = poresph::fluidsetup;

TEST(FluidExtreme, ShearedBubbleDensityRatio1000) {
  Simulation sim(2);
  const double R = 1.5e-3, dx = R / 10, Lx = 6 * R, Ly = 4 * R, gamma = 0.05;
  const double muL = 0.1;  // gas 1e-3: viscosity ratio 100
  const double Ca = 0.2;   // mu_l G R / gamma
  const double G = Ca * gamma / (muL * R), U = 0.5 * G * Ly;
  const double tRelax = muL * R / gamma;  // capillary relaxation time, 3 ms
  const double t = 3 * dx;                // wall thickness (support of the quintic, h = dx)
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
  sim.domain.lo = {0, -t - dx, 0};
  sim.domain.hi = {Lx, Ly + t + dx, 0};
  sim.domain.periodic = {true, false, false};
  const int liq = fs::addMaterial(sim, "water", "fluid",
                                  "{density: 1000, sound_speed: 4, viscosity: 0.1, colour: 1, background_pressure: 100}");
  const int gas = fs::addMaterial(sim, "gas", "fluid",
                                  "{density: 1, sound_speed: 50, viscosity: 1.0e-3, colour: -1, background_pressure: 100}");
  char buf[200];
  std::snprintf(buf, sizeof buf, "{density: 1000, velocity: [%.17g, 0]}", -U);
  const int bottom = fs::addMaterial(sim, "bottom", "wall", buf);
  std::snprintf(buf, sizeof buf, "{density: 1000, velocity: [%.17g, 0]}", U);
  const int top = fs::addMaterial(sim, "top", "wall", buf);
  FluidModule* fluid = fs::addFluidModule(
      sim, "{surface_tension: 0.05, pressure_gradient: hu_adams, wall_wetting: false}");
  const double cx0 = 0.5 * Lx, cy0 = 0.5 * Ly;
  auto inBubble = [&](const double* x) { return std::hypot(x[0] - cx0, x[1] - cy0) < R; };
  fs::addLattice(sim, {0, 0}, {Lx, Ly}, gas, inBubble);
  fs::addLattice(sim, {0, 0}, {Lx, Ly}, liq, [&](const double* x) { return !inBubble(x); });
  fs::addLattice(sim, {0, -t}, {Lx, 0}, bottom);
  fs::addLattice(sim, {0, Ly}, {Lx, Ly + t}, top);
  fluid->initialise(sim);
  {  // start from the undisturbed Couette profile u = G (y - Ly/2) (the bubble then adapts)
    auto& st = sim.store;
    const double* x = st.data(st.position());
    double* v = st.data(st.velocity());
    const std::int32_t* ph = st.data(st.phase());
    for (Index i = 0; i < st.realCount(); ++i)
      if (ph[i] == kPhaseFluid) v[2 * i] = G * (x[2 * i + 1] - cy0), v[2 * i + 1] = 0.0;
  }
  fs::Stepper stepper;
  const double tEnd = 5.0 * tRelax;  // 15 ms: 5 relaxation times, G t = 1.0 (8 until 2026-11-27)
  double worstVar = 0.0;
  while (sim.time < tEnd * (1 - 1e-12)) {
    stepper.step(sim, tEnd - sim.time);
    worstVar = std::max(worstVar, fluid->maxDensityVariation());
    if (std::getenv("FLUID_DEBUG") && sim.step % 1000 == 0)
      std::printf("t %.4e  variation %.3g %%\n", sim.time, 100 * fluid->maxDensityVariation());
  }
  sim.checkFinite();
  const auto& st = sim.store;
  const double* x = st.data(st.position());
  const double* col = st.data(fluid->colour);
  const std::int32_t* ph = st.data(st.phase());
  // bubble centroid (the bubble sits at y = Ly/2, where the Couette velocity is 0; periodic
  // unwrapping about cx0 is enough since it moves by much less than Lx/2)
  auto unwrap = [&](double X) { return X - Lx * std::round((X - cx0) / Lx); };
  double cx = 0, cy = 0, ng = 0;
  int outside = 0;
  for (Index i = 0; i < st.realCount(); ++i) {
    if (ph[i] != kPhaseFluid) continue;
    if (x[2 * i + 1] < 0 || x[2 * i + 1] > Ly) ++outside;
    if (col[i] < 0) cx += unwrap(x[2 * i]), cy += x[2 * i + 1], ng += 1;
  }
  cx /= ng;
  cy /= ng;
  // second moments of the gas -> principal axes of the equivalent ellipse
  Eigen::Matrix2d M = Eigen::Matrix2d::Zero();
  double farthestGas = 0.0, nearestLiquid = 1e9;
  for (Index i = 0; i < st.realCount(); ++i) {
    if (ph[i] != kPhaseFluid) continue;
    const Eigen::Vector2d r(unwrap(x[2 * i]) - cx, x[2 * i + 1] - cy);
    if (col[i] < 0) {
      M += r * r.transpose();
      farthestGas = std::max(farthestGas, r.norm());
    } else {
      nearestLiquid = std::min(nearestLiquid, r.norm());
    }
  }
  M /= ng;
  {  // x, y, colour, speed for a picture (scripts/render_points.py or any plotting tool)
    std::ofstream f(std::string(PORESPH_BINARY_DIR) + "/fluid_sheared_bubble.txt");
    const double* v = st.data(st.velocity());
    for (Index i = 0; i < st.realCount(); ++i)
      f << x[2 * i] << " " << x[2 * i + 1] << " " << (ph[i] == kPhaseFluid ? col[i] : 0.0) << " "
        << std::hypot(v[2 * i], v[2 * i + 1]) << "\n";
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(M);
  const double B = 2.0 * std::sqrt(es.eigenvalues()(0)), L = 2.0 * std::sqrt(es.eigenvalues()(1));
  const double D = (L - B) / (L + B);
  const Eigen::Vector2d axis = es.eigenvectors().col(1);
  const double angle = std::atan2(std::abs(axis(1)), std::abs(axis(0))) * 180.0 / 3.14159265358979;
  std::printf("sheared bubble, density ratio 1000, Ca %.2f: %lld steps to %.1f relaxation times, "
              "max density variation %.3g %%, D = %.3f at %.1f degrees, farthest gas %.2f R, "
              "nearest liquid %.2f R, %d outside\n",
              Ca, static_cast<long long>(sim.step), sim.time / tRelax, 100 * worstVar, D, angle,
              farthestGas / R, nearestLiquid / R, outside);
  EXPECT_EQ(outside, 0);                 // no particle crosses a wall
  EXPECT_LT(farthestGas, 2.0 * R);       // the bubble did not break up or shed gas
  EXPECT_GT(nearestLiquid, 0.3 * R);     // no liquid particle inside the bubble
  EXPECT_GT(D, 0.02);                    // the shear deforms it ...
  EXPECT_LT(D, 0.5);                     // ... but it stays a bubble
  EXPECT_LT(std::abs(cy - cy0), 0.2 * R);  // it stays on the centre line (symmetry)
  EXPECT_LT(worstVar, 0.10);
}
