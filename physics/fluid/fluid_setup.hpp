#pragma once
// Small helpers to build fluid scenes directly in C++ (tests, benchmarks): materials from YAML
// text, lattice filling of boxes and discs, and a one-evaluation symplectic-Euler stepper
//   v^{n+1} = v^n + dt a^n,  x^{n+1} = x^n + dt v^{n+1},  rho^{n+1} = rho^n + dt drho^n,
// which respects the motion field like libcore's integrators do.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "libcore/integrator.hpp"
#include "libcore/simulation.hpp"
#include "physics/fluid/fluid_module.hpp"

namespace poresph::fluidsetup {

/// Adds a material to sim.materials (id = its index) from a YAML mapping text.
inline int addMaterial(Simulation& sim, const std::string& name, const std::string& model,
                       const std::string& yaml) {
  return sim.addMaterial(name, model, yaml, "<test>").id;
}

/// Creates, configures and adds the fluid module for every material of sim (section: YAML text).
inline FluidModule* addFluidModule(Simulation& sim, const std::string& sectionYaml) {
  auto mod = std::make_unique<FluidModule>();
  std::vector<const Material*> mats;
  for (const auto& m : sim.materials) mats.push_back(&m);
  if (sectionYaml.empty()) {
    mod->configure(sim, mats, nullptr);
  } else {
    ParameterSet s(YAML::Load(sectionYaml), "<test>", "fluid");
    mod->configure(sim, mats, &s);
  }
  FluidModule* raw = mod.get();
  sim.addModule(std::move(mod));
  return raw;
}

/// Adds particles on the lattice x = lo + (k + 1/2) dx (every axis) inside [lo, hi) for which
/// select(x) is true, with material `mat`. Returns the number added.
inline Index addLattice(Simulation& sim, const std::vector<double>& lo, const std::vector<double>& hi,
                        int mat, const std::function<bool(const double*)>& select = nullptr) {
  const int d = sim.dimension();
  const double dx = sim.spacing;
  std::vector<long> cnt(3, 1);
  for (int a = 0; a < d; ++a)
    cnt[static_cast<size_t>(a)] = std::lround(std::floor((hi[static_cast<size_t>(a)] - lo[static_cast<size_t>(a)]) / dx + 1e-9));
  std::vector<double> pts;
  double xx[3];
  for (long k2 = 0; k2 < cnt[2]; ++k2)
    for (long k1 = 0; k1 < cnt[1]; ++k1)
      for (long k0 = 0; k0 < cnt[0]; ++k0) {
        const long k[3] = {k0, k1, k2};
        for (int a = 0; a < d; ++a) xx[a] = lo[static_cast<size_t>(a)] + (static_cast<double>(k[a]) + 0.5) * dx;
        if (select && !select(xx)) continue;
        for (int a = 0; a < d; ++a) pts.push_back(xx[a]);
      }
  const Index n = static_cast<Index>(pts.size()) / d;
  if (n == 0) return 0;
  const Index first = sim.store.addParticles(n);
  double* x = sim.store.data(sim.store.position());
  std::int32_t* mt = sim.store.data(sim.store.material());
  for (Index i = 0; i < n; ++i) {
    for (int a = 0; a < d; ++a) x[(first + i) * d + a] = pts[static_cast<size_t>(i * d + a)];
    mt[first + i] = mat;
  }
  return n;
}

/// Steps with one of libcore's integrators (default "leapfrog", Eq. 2.48) at
/// dt = min(dtMax, sim.stableTimeStep()); throws NumericalError when the state is not finite.
class Stepper {
 public:
  explicit Stepper(const std::string& scheme = "leapfrog") : integrator_(makeIntegrator(scheme)) {}
  double step(Simulation& sim, double dtMax = 1e300) {
    const double dt = std::min(dtMax, sim.stableTimeStep());
    if (!(dt > 0.0) || !std::isfinite(dt))
      throw NumericalError("fluid stepper: time step " + std::to_string(dt) + " at step " +
                           std::to_string(sim.step));
    integrator_->step(sim, dt);
    if (sim.step % 100 == 0) sim.checkFinite();
    return dt;
  }
  /// Steps until sim.time reaches tEnd (the last step is shortened to land on it).
  void runTo(Simulation& sim, double tEnd) {
    while (sim.time < tEnd * (1.0 - 1e-12)) step(sim, tEnd - sim.time);
  }
  Integrator& integrator() { return *integrator_; }

 private:
  std::unique_ptr<Integrator> integrator_;
};

}  // namespace poresph::fluidsetup
