// The 2D channel of the capillary tests (issue 14: capillary entry, parallel throats, Pc-S
// staircase, pore network): periodic along x over [0, Lx], fixed walls 3 dx thick below y = 0 and
// above y = H, quintic spline with h = dx, water (colour +1) and gas (colour -1) at one background
// pressure, and a wall material carrying the contact angle. Each test then places its own
// particles and fluid module.
#pragma once

#include <cstdio>

#include "libcore/kernel.hpp"
#include "libcore/simulation.hpp"
#include "physics/fluid/fluid_setup.hpp"

namespace poresph::test {

struct ChannelFluid {
  double density, soundSpeed, viscosity;
};

struct ChannelMaterials {
  int water, gas, wall;
};

inline ChannelMaterials setUpChannel2D(Simulation& sim, double dx, double Lx, double H,
                                       const ChannelFluid& water, const ChannelFluid& gas,
                                       double backgroundPressure, double contactAngleDeg) {
  namespace fs = poresph::fluidsetup;
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
  const double t = 3 * dx;
  sim.domain.lo = {0, -t, 0};
  sim.domain.hi = {Lx, H + t, 0};
  sim.domain.periodic = {true, false, false};
  char buf[300];
  ChannelMaterials ids{};
  std::snprintf(buf, sizeof buf,
                "{density: %.9g, sound_speed: %.9g, viscosity: %.9g, colour: 1, background_pressure: %.9g}",
                water.density, water.soundSpeed, water.viscosity, backgroundPressure);
  ids.water = fs::addMaterial(sim, "water", "fluid", buf);
  std::snprintf(buf, sizeof buf,
                "{density: %.9g, sound_speed: %.9g, viscosity: %.9g, colour: -1, background_pressure: %.9g}",
                gas.density, gas.soundSpeed, gas.viscosity, backgroundPressure);
  ids.gas = fs::addMaterial(sim, "gas", "fluid", buf);
  std::snprintf(buf, sizeof buf, "{density: 1000, contact_angle: %.9g}", contactAngleDeg);
  ids.wall = fs::addMaterial(sim, "wall", "wall", buf);
  return ids;
}

}  // namespace poresph::test
