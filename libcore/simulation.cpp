#include "libcore/simulation.hpp"

#include <cmath>
#include <cstring>

#include "libcore/phases.hpp"
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

namespace poresph {

Simulation::Simulation(int dimension) : store(dimension) {
  domain.dimension = dimension;
  acceleration = store.addReal("acceleration", dimension, kFieldOutput | kFieldRollbackSingle, "core");
  motion = store.addInt("motion", 1, kFieldDefault, "core");
}

void Simulation::addModule(std::unique_ptr<Module> m) { modules.push_back(std::move(m)); }

Module* Simulation::module(const std::string& name) const {
  for (const auto& m : modules)
    if (m->name() == name) return m.get();
  return nullptr;
}

const Material& Simulation::addMaterial(const std::string& name, const std::string& model,
                                       const std::string& yamlMapping, const std::string& origin) {
  Material m;
  m.id = static_cast<int>(materials.size());
  m.name = name;
  m.model = model;
  m.parameters = ParameterSet(YAML::Load(yamlMapping), origin, "materials[" + std::to_string(m.id) + "]");
  // The owning module range-checks it in configure() (with the file and key in its message).
  if (m.parameters.has("density")) m.density = m.parameters.real("density", Range::any());
  materials.push_back(m);
  return materials.back();
}

void Simulation::addIntegrated(RealField value, RealField rate, bool freeOnly) {
  for (const auto& f : integrated) {
    if (f.value.id != value.id) continue;
    if (f.rate.id == rate.id && f.freeOnly == freeOnly) return;
    if (f.rate.id == rate.id)
      throw std::logic_error("field '" + store.spec(value.id).name + "' is already integrated " +
                             (f.freeOnly ? "for free particles only" : "for every particle") +
                             "; a module asked for it " +
                             (freeOnly ? "for free particles only" : "for every particle"));
    // One rate per integrated field: the integrators keep one scratch copy per field, so a
    // second rate (e.g. two modules' XSPH corrections of the positions) would be lost silently.
    throw std::logic_error("field '" + store.spec(value.id).name + "' already has the rate '" +
                           store.spec(f.rate.id).name + "'; a second rate '" +
                           store.spec(rate.id).name + "' cannot be integrated into it");
  }
  integrated.push_back(IntegratedField{value, rate, freeOnly});
}

std::vector<Index> Simulation::phaseCounts() const {
  std::vector<Index> count(kPhaseCount + 1, 0);  // last entry: unset or unknown
  const std::int32_t* ph = store.data(store.phase());
  for (Index i = 0; i < store.realCount(); ++i)
    ++count[ph[i] >= 0 && ph[i] < kPhaseCount ? static_cast<size_t>(ph[i]) : kPhaseCount];
  return count;
}

void Simulation::checkPairOwners() const {
  const std::vector<Index> count = phaseCounts();
  if (count[kPhaseCount] > 0) {
    const std::int32_t* ph = store.data(store.phase());
    const std::int32_t* mt = store.data(store.material());
    Index i = 0;
    while (ph[i] >= 0 && ph[i] < kPhaseCount) ++i;
    const int id = mt[i];
    throw InputError("particle " + std::to_string(i) + " of material " +
                     (id >= 0 && id < static_cast<int>(materials.size())
                          ? "'" + materials[static_cast<size_t>(id)].name + "' (model " +
                                materials[static_cast<size_t>(id)].model + ")"
                          : std::to_string(id)) +
                     " has no phase: its module declared none (a bug of that module)");
  }
  for (std::int32_t p = 0; p < kPhaseCount; ++p)
    for (std::int32_t q = p; q < kPhaseCount; ++q) {
      if (count[static_cast<size_t>(p)] == 0 || count[static_cast<size_t>(q)] == 0) continue;
      if (p == kPhaseWall && q == kPhaseWall) continue;  // walls never move
      if (p == q && count[static_cast<size_t>(p)] < 2) continue;
      const PairClass c(p, q);
      std::vector<std::string> owners;
      for (const auto& m : modules)
        for (const PairClass& o : m->ownedPairs())
          if (o == c) owners.push_back(m->name());
      if (owners.size() == 1) continue;
      std::string names;
      for (const auto& n : owners) names += (names.empty() ? "'" : ", '") + n + "'";
      if (owners.empty())
        throw InputError("the scene has " + std::string(phaseName(p)) + " and " + phaseName(q) +
                         " particles but no module applies the " + c.name() +
                         " pair forces (they would pass through each other); see "
                         "docs/coupling.md for the pair classes each module owns");
      throw InputError("the " + c.name() + " pair forces are claimed by several modules (" +
                       names + "): exactly one may own a pair class (docs/coupling.md)");
    }
}

RealField Simulation::previousAcceleration() {
  if (!previousAcceleration_.valid())
    previousAcceleration_ = store.addReal("previous_acceleration", dimension(), kFieldNone, "core");
  return previousAcceleration_;
}

RealField Simulation::positionCorrection() {
  if (!positionCorrection_.valid()) {
    positionCorrection_ = store.addReal("position_correction", dimension(), kFieldNone, "core");
    addIntegrated(store.position(), positionCorrection_, true);
  }
  return positionCorrection_;
}

void Simulation::updateNeighbours() {
  const double support = kernel.support();
  // Verlet skin. With periodic axes the halo is built with the width support + skin and kept
  // between two searches: the real particles are not wrapped then (one may stand up to skin / 2
  // outside the box), and the ghosts follow their sources (PeriodicHalo::refresh). A particle
  // within support of a periodic face at any step between the searches was within support +
  // skin / 2 of it at the search, so its image exists; two images closer than support now were
  // closer than support + skin then, so the pair is among the candidates.
  verletActive_ = neighbourSkin > 0.0;
  // The pair classes the lists keep (the phase pointer taken at each search: the halo may
  // reallocate the store).
  const PairMask pairMask = neighbourPairMask();
  auto keep = [&] { return PairFilter{store.data(store.phase()), pairMask}; };
  if (verletActive_ &&
      (verlet.candidates().half != halfNeighbourList || verlet.pairMask() != keep().kept()))
    verlet.invalidate();
  if (verletActive_ && verlet.valid(store.data(store.position()), dimension(), store.realCount(),
                                    store.size(), support, neighbourSkin)) {
    halo.refresh(store);
    verlet.filter(store.data(store.position()), dimension(), support, neighbours);
    return;
  }
  if (reorderEvery > 0 && neighbourBuilds_ % reorderEvery == 0) {
    store.clearGhosts();
    halo.wrap(store, domain);
    search.cellOrder(store.data(store.position()), dimension(), store.realCount(), support, order_);
    store.permute(order_);
  }
  ++neighbourBuilds_;
  halo.build(store, domain, verletActive_ ? support + neighbourSkin : support);
  if (cellWalk) {
    // No stored list (`neighbour_list: cells`): the cells of the search, walked by the
    // symmetric loops (libcore/cell_walk.hpp); `neighbours` is an empty half list.
    search.sortCells(store.data(store.position()), dimension(), store.size(), support);
    neighbours.half = true;
    if (neighbours.offset.capacity() > 0 || neighbours.index.capacity() > 0) {
      std::vector<std::int64_t>().swap(neighbours.offset);
      NeighbourList::IndexVector().swap(neighbours.index);
    }
    return;
  }
  if (verletActive_) {
    verlet.rebuild(search, store.data(store.position()), dimension(), store.realCount(),
                   store.size(), support, neighbourSkin, halfNeighbourList, keep());
    verlet.filter(store.data(store.position()), dimension(), support, neighbours);
    return;
  }
  search.build(store.data(store.position()), dimension(), store.realCount(), store.size(), support,
               neighbours, halfNeighbourList, keep());
}

PairMask Simulation::neighbourPairMask() const {
  if (modules.empty()) return kAllPairClasses;
  PairMask m = extraNeighbourPairs;
  for (const auto& mod : modules) m |= mod->neighbourPairsRead();
  return m & kAllPairClasses;
}

void Simulation::chooseNeighbourList() {
  halfNeighbourList = false;
  cellWalk = false;
  if (neighbourListChoice == NeighbourListChoice::Full) return;
  const bool cells = neighbourListChoice == NeighbourListChoice::Cells;
  for (const auto& m : modules) {
    if (m->supportsHalfNeighbourList()) continue;
    if (neighbourListChoice == NeighbourListChoice::Auto) return;
    throw InputError(std::string("neighbour_list: ") + (cells ? "cells" : "half") + ": module '" +
                     m->name() +
                     "' needs the full neighbour list as configured (a half list or cell walk "
                     "serves only the modules whose pair loops are symmetric: "
                     "docs/performance.md); use neighbour_list: full or auto");
  }
  if (cells && neighbourSkin > 0.0)
    throw InputError("neighbour_list: cells walks the cells at every step and keeps no list: "
                     "it takes no neighbour_skin (remove it or use neighbour_list: half)");
  halfNeighbourList = true;
  cellWalk = cells;
  if (cellWalk) neighbours.half = true;  // empty: the loops walk the cells
}

void Simulation::evaluateRates() {
  updateNeighbours();
  evaluateRatesOnTheList();
}

void Simulation::evaluateRatesOnTheList() {
  const Index n = store.size();
  // The copy and the zeroing in one parallel region (issue 17: as memcpy / memset they were the
  // serial part of the step that grows with N, ~1 % of case A's instructions, and memory-bound).
  const Index na = n * dimension();
  double* acc = store.data(acceleration);
  double* prev = previousAcceleration_.valid() ? store.data(previousAcceleration_) : nullptr;
#pragma omp parallel
  {
    if (prev) {
#pragma omp for simd schedule(static) nowait
      for (Index k = 0; k < na; ++k) prev[k] = acc[k];
    }
    // (the same static partition: each thread zeroes the values it copied)
#pragma omp for simd schedule(static) nowait
    for (Index k = 0; k < na; ++k) acc[k] = 0.0;
    for (const auto& f : integrated) {
      double* p = store.data(f.rate);
      const Index len = n * store.components(f.rate.id);
#pragma omp for simd schedule(static) nowait
      for (Index k = 0; k < len; ++k) p[k] = 0.0;
    }
  }
  for (auto& m : modules) m->kinematics(*this);
  for (auto& m : modules) m->constitutive(*this);
  for (auto& m : modules) m->forces(*this);
  for (auto& m : modules) m->interfaces(*this);
  for (auto& m : modules) m->constraints(*this);
}

double Simulation::stableTimeStep() const {
  double dtMax = std::numeric_limits<double>::infinity();
  for (const auto& m : modules) dtMax = std::min(dtMax, m->timeStepLimit(*this));
  return dtMax;
}

double Simulation::kineticEnergy() const {
  const double* v = store.data(store.velocity());
  const double* m = store.data(store.mass());
  const std::int32_t* mo = store.data(motion);
  const int d = dimension();
  double e = 0.0;
#pragma omp parallel for reduction(+ : e) schedule(static)
  for (Index i = 0; i < store.realCount(); ++i) {
    if (mo[i] == kMotionFixed) continue;
    double v2 = 0.0;
    for (int a = 0; a < d; ++a) v2 += v[i * d + a] * v[i * d + a];
    e += 0.5 * m[i] * v2;
  }
  return e;
}

std::vector<std::pair<std::string, double>> Simulation::diagnostics() const {
  std::vector<std::pair<std::string, double>> c;
  c.emplace_back("time", time);
  c.emplace_back("step", static_cast<double>(step));
  c.emplace_back("dt", dt);
  c.emplace_back("kinetic_energy", kineticEnergy());
  for (const auto& m : modules) m->diagnostics(*this, c);
  return c;
}

void Simulation::checkFinite() const {
  const Index n = store.realCount();
  for (const auto& s : store.fields()) {
    // Constant fields (set at initialise, e.g. the TL family's corrected gradients: 2 D x ~106
    // numbers per particle in 3D) cannot turn non-finite during a step: scanning them was 7 % of
    // the 3D drainage step.
    if (s.type != FieldType::Real || (s.flags & kFieldConstant)) continue;
    const int id = static_cast<int>(&s - store.fields().data());
    const double* d = store.data(RealField{id});
    const Index c = s.components;
    // Fast test first: x - x is +0 for every finite x and NaN for an infinity or a NaN, so the
    // sum over the field is 0 exactly when every value is finite (a branch-free loop the compiler
    // vectorises: ~1 instruction per value against ~10 for a test and a branch per value). Only
    // a field that fails it is scanned for its first particle that is not finite.
    const Index count = n * c;
    double probe = 0.0;
    // Below 4096 values on the calling thread, outside any OpenMP region (issue 11 speed: a
    // region costs ~1,500-2,500 instructions even with one thread, more than the pass over the
    // 676 particles of the 2D box; 12 fields a step there). The probe is 0 or NaN either way.
    if (count < 4096) {
#pragma omp simd reduction(+ : probe)
      for (Index k = 0; k < count; ++k) probe += d[k] - d[k];
    } else {
#pragma omp parallel for simd reduction(+ : probe) schedule(static)
      for (Index k = 0; k < count; ++k) probe += d[k] - d[k];
    }
    if (probe == 0.0) continue;
    Index bad = n;
#pragma omp parallel for reduction(min : bad) schedule(static)
    for (Index i = 0; i < n; ++i)
      for (Index q = 0; q < c; ++q)
        if (!std::isfinite(d[i * c + q])) bad = std::min(bad, i);
    if (bad < n) {
      std::ostringstream m;
      m << "field '" << s.name << "' of particle " << bad << " (id "
        << store.data(store.id())[bad] << ", material " << store.data(store.material())[bad]
        << ") is not finite at step " << step << ", time " << time << " s";
      throw NumericalError(m.str());
    }
  }
}

}  // namespace poresph
