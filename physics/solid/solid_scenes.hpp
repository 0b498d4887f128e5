#pragma once
// Small builders of solid test scenes (used by the solid module's unit, validation and extreme
// tests; also a compact example of building a run in C++ without a scene file).
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "libcore/integrator.hpp"
#include "libcore/simulation.hpp"
#include "physics/solid/elastic_solid.hpp"

namespace poresph::solid {

/// Adds one material to sim.materials from a YAML mapping string (file name "test").
inline const Material& addMaterial(Simulation& sim, const std::string& name,
                                   const std::string& model, const std::string& yaml) {
  return sim.addMaterial(name, model, yaml, "test");
}

/// Creates the "solid" module through the registry, configures it with every "elastic" material
/// of sim and the given section (YAML mapping string, "" for none), adds it to sim and returns it.
inline ElasticSolidModule& addSolidModule(Simulation& sim, const std::string& sectionYaml = "") {
  std::unique_ptr<Module> mod = ModuleRegistry::create("solid");
  std::vector<const Material*> mats;
  for (const auto& m : sim.materials)
    if (m.model == "elastic") mats.push_back(&m);
  if (sectionYaml.empty()) {
    mod->configure(sim, mats, nullptr);
  } else {
    ParameterSet section(YAML::Load(sectionYaml), "test", "solid");
    mod->configure(sim, mats, &section);
  }
  auto* solid = dynamic_cast<ElasticSolidModule*>(mod.get());
  sim.addModule(std::move(mod));
  return *solid;
}

/// 1D bar of n material points on [0, L] at the cell centres (i + 1/2) dx, plus `layersLeft`
/// and `layersRight` extra points beyond each end (for clamped layers), material 0.
inline void buildBar(Simulation& sim, int n, double L, int layersLeft, int layersRight) {
  const double dx = L / n;
  sim.spacing = dx;
  const Index total = n + layersLeft + layersRight;
  sim.store.addParticles(total);
  double* x = sim.store.data(sim.store.position());
  Index k = 0;
  for (int j = layersLeft; j >= 1; --j) x[k++] = -(j - 0.5) * dx;
  for (int i = 0; i < n; ++i) x[k++] = (i + 0.5) * dx;
  for (int j = 1; j <= layersRight; ++j) x[k++] = L + (j - 0.5) * dx;
  sim.domain.lo = {-(layersLeft + 1) * dx, 0, 0};
  sim.domain.hi = {L + (layersRight + 1) * dx, 1, 1};
}

/// Rectangular block of nx x ny (x nz) points at the cell centres of [x0, x0 + nx dx] x ...,
/// material `material`. Returns the index of the first new particle.
template <int D>
Index buildBlock(Simulation& sim, const Vec<D>& origin, const std::array<int, 3>& count, double dx,
                 int material = 0) {
  const Index total = static_cast<Index>(count[0]) * (D > 1 ? count[1] : 1) * (D > 2 ? count[2] : 1);
  const Index first = sim.store.addParticles(total);
  double* x = sim.store.data(sim.store.position());
  std::int32_t* mat = sim.store.data(sim.store.material());
  Index k = first;
  for (int c = 0; c < (D > 2 ? count[2] : 1); ++c)
    for (int b = 0; b < (D > 1 ? count[1] : 1); ++b)
      for (int a = 0; a < count[0]; ++a) {
        const int idx[3] = {a, b, c};
        for (int d = 0; d < D; ++d) x[k * D + d] = origin[d] + (idx[d] + 0.5) * dx;
        mat[k] = material;
        ++k;
      }
  return first;
}

/// Body-fitted particles around a circular hole or bore of radius a centred at the origin (2D):
/// `rings` concentric rings at r_k = a + (k + 1/2) dx, each of N_k = 4 round(2 pi r_k / (4 dx))
/// particles at the angles (m + 1/2) 2 pi / N_k (symmetric about both axes, so that symmetry
/// mirrors x = 0 and y = 0 map particles onto particles), with the volume r_k (2 pi / N_k) dx of
/// their annular cell. The particles' cells tile the annulus a <= r <= a + rings dx exactly, so
/// the surface r = a is represented without a lattice staircase. Full circles: the caller keeps
/// the part it needs. Appends x, y to `xy` and the volume to `volume`.
/// (A scene-level choice: a body imaged from voxels has no such fitted surface.)
inline void appendRings(double a, double dx, int rings, std::vector<double>& xy,
                        std::vector<double>& volume) {
  const double pi = 3.14159265358979323846;
  for (int k = 0; k < rings; ++k) {
    const double r = a + (k + 0.5) * dx;
    const long N = std::max(4L, 4L * std::lround(2.0 * pi * r / (4.0 * dx)));
    const double dth = 2.0 * pi / static_cast<double>(N);
    for (long m = 0; m < N; ++m) {
      const double th = (static_cast<double>(m) + 0.5) * dth;
      xy.push_back(r * std::cos(th));
      xy.push_back(r * std::sin(th));
      volume.push_back(r * dth * dx);
    }
  }
}

/// Spherical shells a + (k + 1/2) dx, k < shells (3D body-fitted layout of a thick sphere):
/// N_k = round(4 pi r^2 / dx^2) points per shell on a Fibonacci (golden-angle) spiral, which
/// spaces them ~dx apart with no pole clustering; each holds the shell's volume / N_k.
inline void appendShells(double a, double dx, int shells, std::vector<double>& xyz,
                         std::vector<double>& volume) {
  const double pi = 3.14159265358979323846;
  const double golden = pi * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < shells; ++k) {
    const double r = a + (k + 0.5) * dx;
    const long N = std::max(8L, std::lround(4.0 * pi * r * r / (dx * dx)));
    const double v = 4.0 * pi * r * r * dx / static_cast<double>(N);
    for (long m = 0; m < N; ++m) {
      const double z = 1.0 - (2.0 * static_cast<double>(m) + 1.0) / static_cast<double>(N);
      const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
      const double phi = golden * static_cast<double>(m);
      xyz.push_back(r * rho * std::cos(phi));
      xyz.push_back(r * rho * std::sin(phi));
      xyz.push_back(r * z);
      volume.push_back(v);
    }
  }
}

/// A water + clay run from point arrays (D coordinates per point, its volume and its material:
/// 0 = the fluid material sim.materials[0], 1 = the elastic sim.materials[1]): creates the fluid,
/// solid and coupling modules (they register their fields first), adds the particles at
/// `density`, checks the pair owners, builds the neighbours and initialises, ready to step.
/// Used by the pressurised-pore tests in 2D (rings) and 3D (shells).
inline void setupWaterInClay(Simulation& sim, const std::vector<double>& coords,
                             const std::vector<double>& volume, const std::vector<int>& material,
                             double density) {
  for (const char* name : {"fluid", "solid", "coupling"}) {
    std::unique_ptr<Module> mod = ModuleRegistry::create(name);
    std::vector<const Material*> mats;
    if (std::string(name) == "fluid") mats = {&sim.materials[0]};
    if (std::string(name) == "solid") mats = {&sim.materials[1]};
    mod->configure(sim, mats, nullptr);
    sim.addModule(std::move(mod));
  }
  const int D = sim.dimension();
  ParticleStore& st = sim.store;
  const Index n = static_cast<Index>(volume.size());
  st.addParticles(n);
  for (Index q = 0; q < n; ++q) {
    const size_t k = static_cast<size_t>(q);
    for (int c = 0; c < D; ++c) st.data(st.position())[D * q + c] = coords[D * k + static_cast<size_t>(c)];
    st.data(st.mass())[q] = density * volume[k];
    st.data(st.density())[q] = density;
    st.data(st.material())[q] = material[k];
    st.data(st.phase())[q] = sim.materials[static_cast<size_t>(material[k])].phase;
  }
  sim.checkPairOwners();
  sim.updateNeighbours();
  for (auto& mod : sim.modules) mod->initialise(sim);
  sim.evaluateRates();
}

/// Zero crossings (linear interpolation) of a sampled signal; returns crossing times.
inline std::vector<double> zeroCrossings(const std::vector<double>& t, const std::vector<double>& y) {
  std::vector<double> out;
  for (size_t k = 1; k < y.size(); ++k)
    if ((y[k - 1] < 0.0) != (y[k] < 0.0)) {
      const double s = y[k - 1] / (y[k - 1] - y[k]);
      out.push_back(t[k - 1] + s * (t[k] - t[k - 1]));
    }
  return out;
}

/// Period from zero crossings: (last - first) / (number of half periods) * 2; 0 if < 3 crossings.
inline double periodFromCrossings(const std::vector<double>& c) {
  if (c.size() < 3) return 0.0;
  return 2.0 * (c.back() - c.front()) / static_cast<double>(c.size() - 1);
}

}  // namespace poresph::solid
