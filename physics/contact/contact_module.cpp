#include "physics/contact/contact_module.hpp"

#include <cmath>

#include "libcore/contact_repulsion.hpp"
#include "libcore/phases.hpp"
#include "libcore/simulation.hpp"

namespace poresph {

void ContactModule::configure(Simulation& sim, const std::vector<const Material*>& materials,
                              const ParameterSet* section) {
  if (section) section->finish();  // no keys yet: an unknown one is an error
}

void ContactModule::initialise(Simulation& sim) {
  bulkModulus_.assign(sim.materials.size(), 0.0);
  for (const Material& m : sim.materials) {
    if (m.phase != kPhaseSolid) continue;
    if (!(m.waveSpeed > 0.0) || !(m.density > 0.0))
      throw InputError("contact: solid material '" + m.name +
                       "' has no density or elastic wave speed (its module did not set one)");
    bulkModulus_[static_cast<size_t>(m.id)] = m.density * m.waveSpeed * m.waveSpeed;  // A.17
  }
}

void ContactModule::interfaces(Simulation& sim) {
  dispatchDimension(sim.dimension(), [&](auto dc) { this->interfacesD<decltype(dc)::value>(sim); });
}

template <int D>
void ContactModule::interfacesD(Simulation& sim) {
  ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const auto& nl = sim.neighbours;
  const double* x = st.data(st.position());
  const double* m = st.data(st.mass());
  const std::int32_t* ph = st.data(st.phase());
  const std::int32_t* mt = st.data(st.material());
  const std::int32_t* mo = st.data(sim.motion);
  double* acc = st.data(sim.acceleration);
  const double dx = sim.spacing;
#pragma omp parallel for schedule(dynamic, 256)
  for (Index i = 0; i < n; ++i) {
    if (ph[i] != kPhaseSolid || mo[i] == kMotionFixed) continue;
    const double k = bulkModulus_[static_cast<size_t>(mt[i])];
    Vec<D> f = Vec<D>::Zero();
    for (auto q = nl.offset[i]; q < nl.offset[i + 1]; ++q) {
      const Index j = nl.index[static_cast<size_t>(q)];
      if (ph[j] != kPhaseWall) continue;
      Vec<D> r;
      for (int c = 0; c < D; ++c) r[c] = x[i * D + c] - x[j * D + c];
      const double d = r.norm();
      if (d >= dx || d == 0.0) continue;
      // Eq. A.18 with B(r) = 2 k_s dx^(D-1) (1 - r/dx) (libcore/contact_repulsion.hpp, shared
      // with the rigid module): pushes the solid particle off the wall.
      const double B = repulsionStrength<D>(d, k, dx);
      f += (m[j] / (m[i] + m[j]) * B / d) * r;
    }
    for (int c = 0; c < D; ++c) acc[i * D + c] += f[c] / m[i];
  }
}

PORESPH_REGISTER_MODULE(ContactModule, "contact")

}  // namespace poresph
