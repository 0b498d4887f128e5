#pragma once
// Powers of one rate evaluation of a 2D fluid-solid scene, by pair class (the energy studies of
// tests/validation/test_coupling.cpp and test_coupling_rest.cpp): the fluid's stages and then the
// coupling's interfaces are evaluated on their own, and
//   P[0] fluid-fluid kinetic power       sum_fluid m a . v        (the body force's power taken out)
//   P[1] fluid-fluid compression power   sum_fluid m e'(rho) drho  (e' = p / rho^2)
//   P[2] fluid-solid pairs on the fluid  sum_fluid m a . v
//   P[3] fluid-solid pairs on the solid  sum_solid m a . v
//   P[4] fluid-solid compression power   sum_fluid m e'(rho) drho
// The rates and the acceleration are put back afterwards, so the run goes on unchanged.
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "libcore/fluid_properties.hpp"
#include "libcore/module.hpp"
#include "libcore/phases.hpp"
#include "libcore/simulation.hpp"

namespace poresph::test {

/// gravityY: a body force along y on the fluid (m/s^2, negative downwards) whose power is taken
/// out of P[0]; 0 where there is none.
inline std::array<double, 5> pairClassPowers2D(Simulation& sim, Module* fluid, Module* coupling,
                                               double gravityY = 0.0) {
  ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const RealField rateField = st.real("density_rate");
  std::vector<std::vector<double>> saved;
  for (const IntegratedField& f : sim.integrated) {
    const double* r = st.data(f.rate);
    saved.emplace_back(r, r + n * st.components(f.rate.id));
  }
  double* acc = st.data(sim.acceleration);
  const std::vector<double> accSaved(acc, acc + 2 * n);
  double* drho = st.data(rateField);
  const double* v = st.data(st.velocity());
  const double* m = st.data(st.mass());
  const double* rho = st.data(st.density());
  const std::int32_t* ph = st.data(st.phase());
  const std::int32_t* mt = st.data(st.material());
  auto zero = [&] {
    std::fill(acc, acc + 2 * n, 0.0);
    std::fill(drho, drho + n, 0.0);
  };
  auto eprime = [&](Index i) {
    const FluidProperties& fp = sim.materials[static_cast<size_t>(mt[i])].fluid;
    return pressureOf(fp, rho[i]) / (rho[i] * rho[i]);
  };
  std::array<double, 5> P{0, 0, 0, 0, 0};
  zero();
  fluid->kinematics(sim);
  fluid->constitutive(sim);
  fluid->forces(sim);
  for (Index i = 0; i < n; ++i)
    if (ph[i] == kPhaseFluid) {
      P[0] += m[i] * (acc[2 * i] * v[2 * i] + (acc[2 * i + 1] - gravityY) * v[2 * i + 1]);
      P[1] += m[i] * eprime(i) * drho[i];
    }
  zero();
  coupling->interfaces(sim);
  for (Index i = 0; i < n; ++i) {
    const double pw = m[i] * (acc[2 * i] * v[2 * i] + acc[2 * i + 1] * v[2 * i + 1]);
    if (ph[i] == kPhaseFluid) {
      P[2] += pw;
      P[4] += m[i] * eprime(i) * drho[i];
    } else if (ph[i] == kPhaseSolid) {
      P[3] += pw;
    }
  }
  for (size_t k = 0; k < sim.integrated.size(); ++k)
    std::copy(saved[k].begin(), saved[k].end(), st.data(sim.integrated[k].rate));
  std::copy(accSaved.begin(), accSaved.end(), acc);
  return P;
}

}  // namespace poresph::test
