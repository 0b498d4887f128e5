#include "physics/coupling/coupling_module.hpp"

#include <cmath>

#include "libcore/fluid_pair_terms.hpp"
#include "libcore/phases.hpp"
#include "libcore/simulation.hpp"

namespace poresph {

void CouplingModule::configure(Simulation& sim, const std::vector<const Material*>& materials,
                               const ParameterSet* section) {
  model_ = BoundaryModel::Mirror;
  if (section) {
    model_ = section->choice("fluid_solid", "mirror", {"mirror", "extrapolated"}) == "extrapolated"
                 ? BoundaryModel::Extrapolated
                 : BoundaryModel::Mirror;
    section->finish();
  }
  sim.published.fluidSolidModel = model_;  // read by the rigid module's initialise()
}

void CouplingModule::initialise(Simulation& sim) {
  const ParticleStore& st = sim.store;
  if (!st.has("pressure") || !st.has("wall_velocity"))
    throw InputError("coupling: fluid-solid pairs need the fluid module's extrapolated boundary "
                     "pressure and velocity (fields 'pressure', 'wall_velocity'), which are "
                     "missing: the scene has solid particles but no fluid material");
  pressure_ = st.real("pressure");
  wallVelocity_ = st.real("wall_velocity");
  viscousFactor_ = st.has("viscous_factor") ? st.real("viscous_factor") : RealField{};
  densityRate_ = st.has("density_rate") ? st.real("density_rate") : RealField{};
}

void CouplingModule::interfaces(Simulation& sim) {
  dispatchDimension(sim.dimension(), [&](auto dc) { this->interfacesD<decltype(dc)::value>(sim); });
}

template <int D>
void CouplingModule::interfacesD(Simulation& sim) {
  ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const auto& nl = sim.neighbours;
  const Kernel& W = sim.kernel;
  const double* x = st.data(st.position());
  const double* v = st.data(st.velocity());
  const double* m = st.data(st.mass());
  const double* rho = st.data(st.density());
  const double* p = st.data(pressure_);
  const double* vw = st.data(wallVelocity_);
  const double* visc = viscousFactor_.valid() ? st.data(viscousFactor_) : nullptr;
  double* drho = densityRate_.valid() ? st.data(densityRate_) : nullptr;
  const std::int32_t* ph = st.data(st.phase());
  const std::int32_t* mt = st.data(st.material());
  const std::int32_t* mo = st.data(sim.motion);
  double* acc = st.data(sim.acceleration);
  const FluidPairSettings settings = sim.fluidPairSettings;
  const BoundaryModel model = model_;
  const std::vector<Material>& mats = sim.materials;

  // The force of solid particle b on fluid particle a (libcore FluidBoundaryForce). Both
  // sides call it with the fluid particle first, so the two evaluations are identical and the
  // forces cancel to round-off.
  const FluidBoundaryForce<D> pairForce{x, v, m, rho, p, vw, visc,
                                      mt, mats.data(), &W, settings, model};
  auto isFluid = [&](Index i) {
    return ph[i] == kPhaseFluid && mats[static_cast<size_t>(mt[i])].fluid.valid();
  };

  double fx = 0.0, fy = 0.0, fz = 0.0;  // force of the fluid on the solid
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : fx, fy, fz)
  for (Index i = 0; i < n; ++i) {
    if (isFluid(i)) {
      if (mo[i] == kMotionFixed) continue;
      double divv = 0.0;
      const Vec<D> f = pairForce.onFluid(i, nl, ph, kPhaseSolid, divv);
      for (int c = 0; c < D; ++c) acc[i * D + c] += f[c] / m[i];
      if (drho) drho[i] += rho[i] * divv;  // Eq. 5.1a over the solid neighbours
    } else if (ph[i] == kPhaseSolid) {  // fixed ones too: their load is in the total force
      Vec<D> f = Vec<D>::Zero();
      for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
        const Index j = nl.index[static_cast<size_t>(k)];
        if (!isFluid(j)) continue;
        double div = 0.0;
        f -= pairForce.reaction(j, i, div);  // reaction: minus the force of i on the fluid particle j
                                             // (with the solid's pressure offset: solid_gauge)
      }
      for (int c = 0; c < D; ++c) acc[i * D + c] += f[c] / m[i];
      fx += f[0];
      if (D > 1) fy += f[1 % D];
      if (D > 2) fz += f[2 % D];
    }
  }
  forceOnSolid_ = {fx, fy, fz};
}

void CouplingModule::diagnostics(const Simulation& sim,
                                 std::vector<std::pair<std::string, double>>& columns) const {
  const char* axis[3] = {"x", "y", "z"};
  for (int c = 0; c < sim.dimension(); ++c)
    columns.emplace_back(std::string("fluid_solid_force_") + axis[c],
                         forceOnSolid_[static_cast<size_t>(c)]);
}

PORESPH_REGISTER_MODULE(CouplingModule, "coupling")

}  // namespace poresph
