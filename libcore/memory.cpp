#include "libcore/memory.hpp"

#include <cmath>

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

#include "libcore/health.hpp"
#include "libcore/module.hpp"
#include "libcore/simulation.hpp"

namespace poresph {

std::uint64_t availableMemoryBytes() {
  std::ifstream in("/proc/meminfo");
  std::string line;
  while (std::getline(in, line)) {
    // "MemAvailable:   12345678 kB"
    if (line.rfind("MemAvailable:", 0) != 0) continue;
    std::istringstream s(line.substr(13));
    std::uint64_t kib = 0;
    std::string unit;
    if (!(s >> kib)) return 0;
    s >> unit;
    return unit == "kB" ? kib * 1024 : kib;
  }
  return 0;
}

std::string formatBytes(std::uint64_t bytes) {
  static const char* const units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  if (bytes < 1024) return std::to_string(bytes) + " B";
  double v = static_cast<double>(bytes);
  int u = 0;
  while (v >= 1024.0 && u < 6) v /= 1024.0, ++u;
  char buf[32];
  std::snprintf(buf, sizeof(buf), v < 10.0 ? "%.2f %s" : (v < 100.0 ? "%.1f %s" : "%.0f %s"), v,
                units[u]);
  return buf;
}

}  // namespace poresph

// ---- what a run holds per particle ----
namespace poresph {

MemoryReport memoryReport(const Simulation& sim, std::uint64_t particles,
                          double neighboursPerParticle) {
  MemoryReport r;
  const ParticleStore& st = sim.store;
  const Index nReal = st.realCount();
  r.particles = particles > 0 ? particles : static_cast<std::uint64_t>(nReal);
  const int d = sim.dimension();

  // Particles per owning module (by material), to tell the bytes held for particles of other
  // modules' materials (e.g. solid fields of fluid particles).
  std::map<std::string, Index> ownParticles;
  if (nReal > 0) {
    std::vector<Index> perMaterial(sim.materials.size(), 0);
    const std::int32_t* mt = st.data(st.material());
    for (Index i = 0; i < nReal; ++i)
      if (mt[i] >= 0 && static_cast<size_t>(mt[i]) < perMaterial.size())
        ++perMaterial[static_cast<size_t>(mt[i])];
    for (const auto& m : sim.materials)
      ownParticles[ModuleRegistry::moduleForModel(m.model)] +=
          perMaterial[static_cast<size_t>(m.id)];
  }

  std::map<std::string, std::pair<double, double>> byOwner;  // owner -> (bytes, foreign bytes)
  std::vector<std::string> order;
  bool integratorBound = false;
  for (const auto& s : st.fields()) {
    const double b = static_cast<double>(s.components) *
                     (s.type == FieldType::Real ? sizeof(double) : sizeof(std::int32_t));
    if (!byOwner.count(s.owner)) order.push_back(s.owner);
    auto& e = byOwner[s.owner];
    e.first += b;
    auto own = ownParticles.find(s.owner);
    if (own != ownParticles.end() && nReal > 0)
      e.second += b * static_cast<double>(nReal - own->second) / static_cast<double>(nReal);
    if (s.owner == "integrator") integratorBound = true;
  }
  for (const auto& owner : order) {
    MemoryLine l;
    l.what = "fields: " + owner;
    l.bytesPerParticle = byOwner[owner].first;
    l.foreignBytesPerParticle = byOwner[owner].second;
    if (l.foreignBytesPerParticle > 0)
      l.note = "of which held for other modules' particles";
    r.lines.push_back(l);
  }
  // What modules hold outside the store (the TL reference family in compressed rows).
  if (nReal > 0)
    for (const auto& m : sim.modules)
      if (const std::uint64_t held = m->heldBytes(); held > 0)
        r.lines.push_back({"held: " + m->name(),
                           static_cast<double>(held) / static_cast<double>(nReal), 0.0,
                           "outside the store, for its own particles"});
  if (!integratorBound) {
    // Integrator::bindScratch registers these at the first step: a velocity copy (and a position
    // copy, predictor_corrector only: counted here, so an upper bound for verlet and leapfrog)
    // plus one copy of every integrated field.
    double b = 2.0 * d * sizeof(double);
    for (const auto& f : sim.integrated) b += st.components(f.value.id) * sizeof(double);
    r.lines.push_back({"fields: integrator", b, 0.0, "registered at the first step"});
  }
  const double fieldBytes = static_cast<double>(st.bytesPerParticle()) +
                            (integratorBound ? 0.0 : r.lines.back().bytesPerParticle);
  if (st.ghostCount() > 0 && nReal > 0) {
    r.lines.push_back({"periodic ghosts", fieldBytes * static_cast<double>(st.ghostCount()) /
                                              static_cast<double>(nReal),
                       0.0, std::to_string(st.ghostCount()) + " ghosts, every field"});
  } else if (sim.neighbours.realCount() == 0) {
    // Before the halo exists: an image of every particle within the support of each periodic
    // face (PeriodicHalo::build), edges and corners included, for particles filling the box.
    double images = 1.0;
    bool any = false;
    for (int a = 0; a < d; ++a)
      if (sim.domain.periodic[static_cast<size_t>(a)] && sim.domain.length(a) > 0.0) {
        images *= 1.0 + 2.0 * sim.kernel.support() / sim.domain.length(a);
        any = true;
      }
    if (any)
      r.lines.push_back({"periodic ghosts", fieldBytes * (images - 1.0), 0.0,
                         "estimate: support / periodic length, every field"});
  }
  r.lines.push_back({"rollback copy", static_cast<double>(RollbackState::bytesPerParticle(st)),
                     0.0, "checkpoint and output fields; velocity, density, acceleration, pressure in "
                     "single precision, few-valued fields as bytes (health: rollback_every)"});
  const std::string listKind = sim.halfNeighbourList ? " (half: each pair once)" : "";
  if (sim.cellWalk) {
    // neighbour_list: cells: no list; the search holds the cells and the sorted positions
    // (measured once a step sorted them), the fluid's per-cell layout scratch is in its line.
    r.lines.push_back({"neighbour list", 0.0, 0.0,
                       "none: the symmetric loops walk the cells (neighbour_list: cells)"});
    const Index sorted = sim.search.grid().count;
    if (sorted > 0 && nReal > 0)
      r.lines.push_back({"neighbour search",
                         static_cast<double>(sim.search.bytes()) / static_cast<double>(nReal), 0.0,
                         "measured: cells, sorted positions"});
    else
      r.lines.push_back({"neighbour search", 8.0 + 8.0 * d, 0.0, "estimate"});  // 32-bit cells
  } else if (sim.neighbours.realCount() > 0) {
    const double n = static_cast<double>(sim.neighbours.realCount());
    r.lines.push_back({"neighbour list", static_cast<double>(sim.neighbours.bytes()) / n, 0.0,
                       "measured: mean " +
                           std::to_string(static_cast<long>(
                               static_cast<double>(sim.neighbours.pairCount()) / n + 0.5)) +
                           " neighbours x 4 bytes + 8-byte offset" + listKind});
    if (sim.neighbourSkin > 0.0 && sim.verlet.candidates().realCount() > 0)
      r.lines.push_back({"Verlet candidates", static_cast<double>(sim.verlet.bytes()) / n, 0.0,
                         "measured: mean " +
                             std::to_string(static_cast<long>(
                                 static_cast<double>(sim.verlet.candidates().pairCount()) / n +
                                 0.5)) +
                             " within support + skin, positions at the search"});
    r.lines.push_back({"neighbour search", static_cast<double>(sim.search.bytes()) / n, 0.0,
                       "cells, sorted positions, thread buffers"});
  } else {
    // A half list holds each pair once; with a Verlet skin the candidates (support + skin) are
    // held beside it, and the exact list keeps room for as many entries as the candidates
    // (VerletNeighbours::filter writes in place).
    const double entries = neighboursPerParticle * (sim.halfNeighbourList ? 0.5 : 1.0);
    const double support = sim.kernel.support();
    if (sim.neighbourSkin > 0.0 && support > 0.0) {
      const double cand = entries * std::pow((support + sim.neighbourSkin) / support, d);
      r.lines.push_back({"neighbour list", cand * 1.0625 * sizeof(std::uint32_t) + 8.0, 0.0,
                         "lattice estimate, room for the candidates" + listKind});
      r.lines.push_back({"Verlet candidates", cand * 1.0625 * sizeof(std::uint32_t) + 8.0 + 8.0 * d,
                         0.0, "lattice estimate"});
    } else {
      r.lines.push_back({"neighbour list", entries * sizeof(std::uint32_t) + 8.0, 0.0,
                         "lattice estimate" + listKind});
    }
    r.lines.push_back({"neighbour search", 16.0 + 8.0 * d, 0.0, "estimate"});
  }
  for (const auto& l : r.lines) {
    r.bytesPerParticle += l.bytesPerParticle;
    r.foreignBytesPerParticle += l.foreignBytesPerParticle;
  }
  return r;
}

std::string describeMemory(const MemoryReport& r) {
  std::ostringstream o;
  o << "memory by owner (bytes per particle, " << r.particles << " particles):\n";
  for (const auto& l : r.lines) {
    o << "  " << std::left << std::setw(22) << l.what << std::right << std::setw(8)
      << static_cast<long>(l.bytesPerParticle + 0.5);
    if (l.foreignBytesPerParticle > 0)
      o << "  (" << static_cast<long>(l.foreignBytesPerParticle + 0.5) << " " << l.note << ")";
    else if (!l.note.empty())
      o << "  (" << l.note << ")";
    o << "\n";
  }
  o << "  " << std::left << std::setw(22) << "total" << std::right << std::setw(8)
    << static_cast<long>(r.bytesPerParticle + 0.5) << "  = " << formatBytes(r.totalBytes())
    << " for the scene";
  if (r.foreignBytesPerParticle > 0)
    o << "; " << static_cast<long>(r.foreignBytesPerParticle + 0.5)
      << " bytes per particle are fields held for particles of other modules' materials";
  o << "\n";
  return o.str();
}

}  // namespace poresph
