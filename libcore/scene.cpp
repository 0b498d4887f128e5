#include "libcore/scene.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

#include "libcore/image_scene.hpp"
#include "libcore/integrator.hpp"
#include "libcore/memory.hpp"

namespace poresph {

namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

std::vector<std::string> knownKernels() {
  return {"cubic_spline", "gaussian", "wendland_c2", "quintic_spline"};
}

std::vector<std::string> knownModels() {
  std::vector<std::string> out;
  for (const auto& name : ModuleRegistry::names()) {
    auto m = ModuleRegistry::create(name);
    for (const auto& model : m->materialModels()) out.push_back(model);
  }
  return out;
}

/// A list of `dim` booleans (periodic flags).
std::array<bool, 3> readFlags(const ParameterSet& ps, const std::string& key, int dim) {
  std::array<bool, 3> out{false, false, false};
  if (!ps.has(key)) {
    ps.boolean(key, false);  // marks the key as read
    return out;
  }
  const YAML::Node n = ps.raw(key);
  if (!n.IsSequence() || static_cast<int>(n.size()) != dim)
    ps.fail(key, "expected a list of " + std::to_string(dim) + " true/false values, one per axis");
  for (int a = 0; a < dim; ++a) {
    bool v = false;
    if (!n[static_cast<size_t>(a)].IsScalar() ||
        !YAML::convert<bool>::decode(n[static_cast<size_t>(a)], v))
      ps.fail(key, "expected a list of " + std::to_string(dim) + " true/false values, one per axis");
    out[static_cast<size_t>(a)] = v;
  }
  return out;
}

std::array<double, 3> toArray(const std::vector<double>& v) {
  std::array<double, 3> a{0.0, 0.0, 0.0};
  for (size_t k = 0; k < v.size() && k < 3; ++k) a[k] = v[k];
  return a;
}

/// A real as a YAML scalar with 15 significant digits (0.1 stays 0.1 in run.yaml).
YAML::Node num(double v) {
  std::ostringstream s;
  s.precision(15);
  s << v;
  return YAML::Node(s.str());
}

YAML::Node seq(const std::array<double, 3>& a, int dim) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (int k = 0; k < dim; ++k) n.push_back(num(a[static_cast<size_t>(k)]));
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

const char* motionName(std::int32_t m) {
  switch (m) {
    case kMotionFixed: return "fixed";
    case kMotionPrescribed: return "prescribed";
    default: return "free";
  }
}

Scene buildScene(const YAML::Node& root, const std::string& file, const SceneOptions& options) {
  Scene scene;
  scene.file = file;
  scene.source = root;
  if (!root.IsDefined() || root.IsNull())
    throw InputError(file + ":1: the scene is empty (expected a mapping of key: value)");
  if (!root.IsMap()) {
    std::string got = root.IsSequence() ? "a list" : "the text '" + root.Scalar() + "'";
    if (got.size() > 80) got = got.substr(0, 77) + "...'";
    throw InputError(file + ":" + std::to_string(root.Mark().line + 1) +
                     ": the scene must be a mapping of key: value (dimension: ..., domain: ..., "
                     "spacing: ..., see docs/scene-format.md), got " + got);
  }
  const ParameterSet top(root, file, "");
  YAML::Node& res = scene.resolved;

  // ---- dimension, domain, lattice, kernel ----
  const int dim = static_cast<int>(top.integer("dimension", 1, 3));
  res["dimension"] = dim;
  scene.sim = std::make_unique<Simulation>(dim);
  Simulation& sim = *scene.sim;

  {
    const ParameterSet d = top.section("domain");
    const auto lo = d.reals("lo", static_cast<size_t>(dim));
    const auto hi = d.reals("hi", static_cast<size_t>(dim));
    for (int a = 0; a < dim; ++a)
      if (!(hi[static_cast<size_t>(a)] > lo[static_cast<size_t>(a)]))
        d.fail("hi", std::string("must exceed domain.lo along every axis (axis ") + "xyz"[a] +
                         ": lo = " + fmt(lo[static_cast<size_t>(a)]) + ", hi = " +
                         fmt(hi[static_cast<size_t>(a)]) + ")");
    sim.domain.dimension = dim;
    sim.domain.lo = toArray(lo);
    sim.domain.hi = toArray(hi);
    sim.domain.periodic = readFlags(d, "periodic", dim);
    d.finish();
    res["domain"]["lo"] = seq(sim.domain.lo, dim);
    res["domain"]["hi"] = seq(sim.domain.hi, dim);
    YAML::Node p(YAML::NodeType::Sequence);
    for (int a = 0; a < dim; ++a) p.push_back(static_cast<bool>(sim.domain.periodic[static_cast<size_t>(a)]));
    p.SetStyle(YAML::EmitterStyle::Flow);
    res["domain"]["periodic"] = p;
  }

  sim.spacing = top.real("spacing", Range::positive());
  scene.hOverDx = top.real("h_over_dx", 1.3, Range{0.5, 10.0, false, false});
  scene.kernelName = top.choice("kernel", "cubic_spline", knownKernels());
  scene.spacingWhere = top.where("spacing") + " = '" + top.raw("spacing").Scalar() + "'";
  {
    // The kernel divides by h^D and its gradient by h^(D+1): both must be finite and non-zero.
    const double h = scene.hOverDx * sim.spacing;
    const double hPow = std::pow(h, dim + 1);
    if (!(h > 0.0) || !std::isfinite(h) || !(hPow >= std::numeric_limits<double>::min()) ||
        !std::isfinite(hPow))
      top.fail("spacing", "gives a smoothing length h = h_over_dx * spacing = " + fmt(h) +
                              " m, unusable in double precision (h^" + std::to_string(dim + 1) +
                              " = " + fmt(hPow) + " " +
                              (hPow >= std::numeric_limits<double>::min() ? "overflows" : "underflows") +
                              " in the kernel normalisation); the spacing is a length in metres");
  }
  sim.kernel = Kernel(parseKernelType(scene.kernelName), dim, scene.hOverDx * sim.spacing);
  // There is no scene-wide `correction:` key (issue 11): it was parsed into
  // Simulation::correction but no module read it (each module chooses its own correction; the
  // solid always uses mixed_2.63b), so a scene giving it was told of a correction never applied.
  if (top.has("correction"))
    top.fail("correction", "unknown key: no module reads a scene-wide kernel/gradient correction "
                           "(each module chooses its own, e.g. the solid always uses mixed_2.63b; "
                           "see docs/operators.md); remove it");
  res["spacing"] = num(sim.spacing);
  res["h_over_dx"] = num(scene.hOverDx);
  res["kernel"] = scene.kernelName;
  // Verlet skin of the neighbour list, in units of dx (Simulation::neighbourSkin; 0: off).
  if (top.has("neighbour_skin")) {
    sim.neighbourSkin = top.real("neighbour_skin", Range::closed(0.0, 2.0)) * sim.spacing;
    res["neighbour_skin"] = num(sim.neighbourSkin / sim.spacing);
  }
  // Full or half neighbour list (Simulation::chooseNeighbourList once the modules are known).
  const std::string listChoice =
      top.choice("neighbour_list", "auto", {"full", "half", "auto", "cells"});
  sim.neighbourListChoice = listChoice == "half"    ? Simulation::NeighbourListChoice::Half
                            : listChoice == "auto"  ? Simulation::NeighbourListChoice::Auto
                            : listChoice == "cells" ? Simulation::NeighbourListChoice::Cells
                                                    : Simulation::NeighbourListChoice::Full;
  if (top.has("neighbour_list")) res["neighbour_list"] = listChoice;
  const std::string listWhere = top.where("neighbour_list");

  // ---- time ----
  scene.integrator = top.choice("integrator", "leapfrog", integratorNames());
  scene.endTime = top.real("end_time", Range::positive());
  scene.maxSteps = top.integer("max_steps", 0, 0, std::numeric_limits<long>::max());
  res["integrator"] = scene.integrator;
  res["end_time"] = num(scene.endTime);
  res["max_steps"] = scene.maxSteps;
  std::string dtWhere;
  {
    const ParameterSet t = top.section("time_step");
    dtWhere = t.where("dt");
    scene.timeStep.adaptive = t.boolean("adaptive", false);
    if (!scene.timeStep.adaptive && !t.has("dt"))
      t.real("dt", Range::positive());  // throws: required key 'time_step.dt' is missing
    scene.timeStep.dt = t.real("dt", 0.0, Range::positive());
    scene.timeStep.cfl = t.real("cfl", 1.0, Range{0.0, 1.0, true, false});
    if (!scene.timeStep.adaptive && t.has("cfl"))
      t.fail("cfl", "is only used with adaptive: true (a fixed dt is checked against the "
                    "modules' stable limit instead)");
    t.finish();
    res["time_step"]["adaptive"] = scene.timeStep.adaptive;
    if (scene.timeStep.dt > 0.0) res["time_step"]["dt"] = num(scene.timeStep.dt);
    if (scene.timeStep.adaptive) res["time_step"]["cfl"] = num(scene.timeStep.cfl);
  }

  // ---- output ----
  {
    const ParameterSet o = top.section("output");
    scene.output.everySteps = o.integer("every_steps", 0, 1, std::numeric_limits<long>::max());
    scene.output.everyTime = o.real("every_time", 0.0, Range::positive());
    const bool steps = o.has("every_steps"), time = o.has("every_time");
    if (steps == time)
      o.fail(steps ? "every_time" : "every_steps",
             "give exactly one of output.every_steps (snapshot every N steps) and "
             "output.every_time (every T seconds)");
    // Periodic checkpoints (docs/scene-format.md): the runner reads them from the resolved
    // scene (res), which the signature of a checkpoint leaves out with the rest of `output`.
    const long checkpointSteps =
        o.integer("checkpoint_every_steps", 0, 1, std::numeric_limits<long>::max());
    const double checkpointWall = o.real("checkpoint_every_wall", 0.0, Range::positive());
    o.finish();
    if (steps) res["output"]["every_steps"] = scene.output.everySteps;
    else res["output"]["every_time"] = num(scene.output.everyTime);
    if (checkpointSteps > 0) res["output"]["checkpoint_every_steps"] = checkpointSteps;
    if (checkpointWall > 0.0) res["output"]["checkpoint_every_wall"] = num(checkpointWall);
  }

  // ---- health checks (libcore/health.hpp) ----
  {
    const ParameterSet h = top.has("health") ? top.section("health") : ParameterSet();
    scene.health = readHealthLimits(top.has("health") ? &h : nullptr);
    res["health"]["density_variation"] = num(scene.health.densityVariation);
    res["health"]["max_mach"] = num(scene.health.maxMach);
    res["health"]["dt_floor"] = num(scene.health.dtFloor);
    res["health"]["energy_growth"] = num(scene.health.energyGrowth);
    res["health"]["domain_margin"] = num(scene.health.domainMargin);
    res["health"]["keep_going"] = scene.health.keepGoing;
  }

  // ---- materials -> modules ----
  std::vector<double> rho0;
  std::vector<std::string> moduleOrder;
  std::map<std::string, std::vector<int>> materialsOf;
  {
    const std::vector<ParameterSet> mats = top.sectionList("materials");
    if (mats.empty()) top.fail("materials", "needs at least one material");
    std::vector<std::string> known;
    for (size_t k = 0; k < mats.size(); ++k) {
      const ParameterSet& m = mats[k];
      Material mat;
      mat.id = static_cast<int>(k);
      mat.name = m.string("name");
      if (mat.name == "none")
        m.fail("name", "'none' is reserved (geometry regions with material: none subtract)");
      for (const auto& other : sim.materials)
        if (other.name == mat.name) m.fail("name", "a material of this name was defined before");
      mat.model = m.string("model");
      const std::string owner = ModuleRegistry::moduleForModel(mat.model);
      if (owner.empty()) {
        if (known.empty()) known = knownModels();
        m.fail("model", "no physics module owns this material model (known models: " +
                            (known.empty() ? std::string("none; no module is linked") : joined(known)) +
                            ")");
      }
      rho0.push_back(m.real("density", Range::positive()));
      mat.density = rho0.back();
      mat.parameters = m;
      if (!materialsOf.count(owner)) moduleOrder.push_back(owner);
      materialsOf[owner].push_back(mat.id);
      sim.materials.push_back(std::move(mat));
    }
  }
  // Module sections: a top-level key named after a registered module.
  std::map<std::string, ParameterSet> sections;
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    const auto names = ModuleRegistry::names();
    if (std::find(names.begin(), names.end(), key) == names.end()) continue;
    sections.emplace(key, top.section(key));
    scene.moduleSections.push_back(key);
    if (!materialsOf.count(key)) moduleOrder.push_back(key);
  }

  // ---- geometry ----
  {
    const std::vector<ParameterSet> regs = top.sectionList("geometry");
    if (regs.empty()) top.fail("geometry", "needs at least one region");
    for (size_t k = 0; k < regs.size(); ++k) {
      const ParameterSet& g = regs[k];
      Region r;
      r.where = g.where("shape");
      const std::string shape = g.choice("shape", {"box", "sphere", "cylinder", "image"});
      if (shape == "image") {  // one region per material of its label map (libcore/image_scene.hpp)
        YAML::Node e;
        appendImageRegions(g, sim, scene.regions, e);
        g.finish();
        res["geometry"].push_back(e);
        continue;
      }
      if (shape == "box") {
        r.shape = Region::Shape::Box;
        r.lo = toArray(g.reals("lo", static_cast<size_t>(dim)));
        r.hi = toArray(g.reals("hi", static_cast<size_t>(dim)));
        for (int a = 0; a < dim; ++a)
          if (!(r.hi[static_cast<size_t>(a)] > r.lo[static_cast<size_t>(a)]))
            g.fail("hi", std::string("must exceed lo along every axis (axis ") + "xyz"[a] + ")");
      } else if (shape == "sphere") {
        r.shape = Region::Shape::Sphere;
        r.centre = toArray(g.reals("centre", static_cast<size_t>(dim)));
        r.radius = g.real("radius", Range::positive());
      } else {
        // A cylinder of `radius` about `axis` through `centre`, `length` long (in 2D the axis
        // lies in the plane: a rectangle 2 radius x length, tilted with the axis).
        if (dim < 2) g.fail("shape", "a cylinder needs 2 or 3 dimensions (use a box in 1D)");
        r.shape = Region::Shape::Cylinder;
        r.centre = toArray(g.reals("centre", static_cast<size_t>(dim)));
        r.radius = g.real("radius", Range::positive());
        r.length = g.real("length", Range::positive());
        const std::array<double, 3> a = toArray(g.reals("axis", static_cast<size_t>(dim)));
        double n2 = 0.0;
        for (int k = 0; k < dim; ++k) n2 += a[static_cast<size_t>(k)] * a[static_cast<size_t>(k)];
        if (!(n2 > 0.0) || !std::isfinite(n2)) g.fail("axis", "must be a nonzero, finite vector");
        r.axis = {0.0, 0.0, 0.0};
        for (int k = 0; k < dim; ++k) r.axis[static_cast<size_t>(k)] = a[static_cast<size_t>(k)] / std::sqrt(n2);
      }
      const std::string material = g.string("material");
      if (material == "none") {
        r.material = -1;
        if (g.has("motion")) g.fail("motion", "a subtracting region (material: none) has no motion");
        if (g.has("velocity"))
          g.fail("velocity", "a subtracting region (material: none) has no velocity");
      } else {
        r.material = -2;
        for (const auto& m : sim.materials)
          if (m.name == material) r.material = m.id;
        if (r.material == -2) {
          std::vector<std::string> names;
          for (const auto& m : sim.materials) names.push_back(m.name);
          g.fail("material", "no material of this name (defined: " + joined(names) +
                                 "; or 'none' to subtract)");
        }
        const std::string motion = g.choice("motion", "free", {"free", "fixed", "prescribed"});
        r.motion = motion == "fixed" ? kMotionFixed
                   : motion == "prescribed" ? kMotionPrescribed : kMotionFree;
        if (g.has("velocity")) r.velocity = toArray(g.reals("velocity", static_cast<size_t>(dim)));
      }
      g.finish();
      YAML::Node e;
      e["shape"] = shape;
      if (shape == "box") {
        e["lo"] = seq(r.lo, dim);
        e["hi"] = seq(r.hi, dim);
      } else {
        e["centre"] = seq(r.centre, dim);
        e["radius"] = num(r.radius);
        if (shape == "cylinder") {
          e["axis"] = seq(r.axis, dim);
          e["length"] = num(r.length);
        }
      }
      e["material"] = material;
      if (r.material >= 0) {
        e["motion"] = motionName(r.motion);
        e["velocity"] = seq(r.velocity, dim);
      }
      res["geometry"].push_back(e);
      scene.regions.push_back(r);
    }
  }

  // ---- the quantity a run is judged by (libcore/reference.hpp; `poresph study`) ----
  if (top.has("reference")) {
    scene.reference = readReference(top.section("reference"), dim);
    res["reference"] = YAML::Clone(root["reference"]);
  }

  top.finish();

  // ---- modules: configure in order of first use (materials first, then section-only ones) ----
  for (const auto& name : moduleOrder) {
    std::unique_ptr<Module> m = ModuleRegistry::create(name);
    std::vector<const Material*> mats;
    for (int id : materialsOf[name]) mats.push_back(&sim.materials[static_cast<size_t>(id)]);
    auto sec = sections.find(name);
    const ParameterSet* section = sec == sections.end() ? nullptr : &sec->second;
    m->configure(sim, mats, section);
    // Modules call finish() themselves; doing it again here catches one that forgot.
    for (const Material* mat : mats) mat->parameters.finish();
    if (section) section->finish();
    sim.addModule(std::move(m));
  }
  try {
    sim.chooseNeighbourList();
  } catch (const InputError& e) {
    throw InputError(listWhere + ": " + e.what());
  }
  for (const auto& m : sim.materials) {
    YAML::Node e = YAML::Clone(root["materials"][static_cast<size_t>(m.id)]);
    res["materials"].push_back(e);
  }
  for (const auto& name : scene.moduleSections) res[name] = YAML::Clone(root[name]);

  // ---- counting pass and memory estimate: nothing per particle is allocated yet ----
  scene.referenceDensity = rho0;
  scene.geometryWhere = top.where("geometry");
  LatticeCount count;
  try {
    count = countLattice(scene.regions, sim.domain, sim.spacing);
  } catch (const LatticeTooLarge& e) {
    throw InputError(scene.spacingWhere + ": " + e.what());
  } catch (const InputError& e) {
    throw InputError(scene.geometryWhere + ": " + e.what());
  }
  if (count.sites == 0)
    throw InputError(scene.geometryWhere +
                     ": the regions hold no particle (every lattice site of spacing " +
                     fmt(sim.spacing) + " m is outside the regions or subtracted)");
  scene.particlesPerMaterial.assign(sim.materials.size(), 0);
  for (size_t k = 0; k < scene.regions.size(); ++k)
    if (scene.regions[k].material >= 0)
      scene.particlesPerMaterial[static_cast<size_t>(scene.regions[k].material)] +=
          static_cast<Index>(count.perRegion[k]);
  {
    MemoryEstimate& mem = scene.memory;
    mem.particles = count.sites;
    // What `poresph info` reports by owner (libcore/memory.hpp): the registered fields, the
    // integrator's scratch, the rollback copy, the neighbour list and search (lattice estimate);
    // plus the fields modules register only in initialise() (the TL reference family).
    const double sOverDx = sim.kernel.support() / sim.spacing;
    const double neighbours = static_cast<double>(latticeNeighbourCount(dim, sOverDx));
    const MemoryReport report = memoryReport(sim, count.sites, neighbours);
    double fields = 0.0, ghosts = 0.0, rollback = 0.0, lists = 0.0;
    for (const auto& l : report.lines) {
      if (l.what.rfind("fields: ", 0) == 0) fields += l.bytesPerParticle;
      else if (l.what == "periodic ghosts") ghosts += l.bytesPerParticle;
      else if (l.what == "rollback copy") rollback += l.bytesPerParticle;
      else lists += l.bytesPerParticle;
    }
    double deferred = 0.0;
    for (const auto& m : sim.modules)
      deferred += m->deferredBytesPerParticle(sim, neighbours, scene.particlesPerMaterial);
    // Periodic ghosts hold every store field; what modules allocate at initialise is held for
    // their own real particles (the TL family, outside the store), not copied to ghosts.
    fields += deferred + ghosts;
    mem.fieldBytesPerParticle = static_cast<std::uint64_t>(std::ceil(fields));
    mem.rollbackBytesPerParticle = static_cast<std::uint64_t>(std::ceil(rollback));
    mem.neighbourBytesPerParticle = static_cast<std::uint64_t>(std::ceil(lists));
    mem.bytesPerParticle =
        mem.fieldBytesPerParticle + mem.rollbackBytesPerParticle + mem.neighbourBytesPerParticle;
    if (__builtin_mul_overflow(mem.particles, mem.bytesPerParticle, &mem.totalBytes))
      mem.totalBytes = std::numeric_limits<std::uint64_t>::max();
    mem.availableBytes = options.availableMemory ? options.availableMemory : availableMemoryBytes();
    if (options.checkMemory && !mem.fits())
      throw InputError(scene.spacingWhere + ": a run would need " + mem.describe() +
                       ": it does not fit; use a larger spacing or a smaller geometry "
                       "(poresph run --force tries anyway)");
  }
  if (!options.buildParticles) return scene;
  buildParticles(scene);

  if (options.initialise) {
    initialiseScene(scene);
    if (!scene.timeStep.adaptive && scene.timeStep.dt > scene.initialStableTimeStep) {
      std::ostringstream msg;
      msg.precision(6);
      msg << dtWhere << " = '" << scene.timeStep.dt << "': the fixed time step " << scene.timeStep.dt
          << " s exceeds the stable limit " << scene.initialStableTimeStep << " s of "
          << scene.stableLimitModule
          << " (CFL conditions, thesis Eqs. 2.49-2.50); lower time_step.dt to at most "
          << scene.initialStableTimeStep << " s or set time_step.adaptive: true";
      throw InputError(msg.str());
    }
  }
  return scene;
}

/// Adds the registered modules (e.g. "coupling") that own a pair class whose phases are both
/// present and that no module of the scene owns; they need no scene section (an explicit one,
/// e.g. `coupling: {...}`, added them already).
void addPairOwners(Simulation& sim) {
  const std::vector<Index> count = sim.phaseCounts();
  auto owned = [&](const PairClass& c) {
    for (const auto& m : sim.modules)
      for (const PairClass& o : m->ownedPairs())
        if (o == c) return true;
    return false;
  };
  for (const auto& name : ModuleRegistry::names()) {
    if (sim.module(name)) continue;
    std::unique_ptr<Module> m = ModuleRegistry::create(name);
    if (!m->materialModels().empty()) continue;  // modules of materials come with them
    bool needed = false;
    for (const PairClass& c : m->ownedPairs())
      needed = needed || (count[static_cast<size_t>(c.a)] > 0 &&
                          count[static_cast<size_t>(c.b)] > 0 && !owned(c));
    if (!needed) continue;
    m->configure(sim, {}, nullptr);
    sim.addModule(std::move(m));
  }
}

}  // namespace

void buildParticles(Scene& scene) {
  Simulation& sim = *scene.sim;
  const int dim = sim.dimension();
  const std::vector<double>& rho0 = scene.referenceDensity;
  LatticeFill fill;
  try {
    fill = fillLattice(scene.regions, sim.domain, sim.spacing);
  } catch (const LatticeTooLarge& e) {
    throw InputError(scene.spacingWhere + ": " + e.what());
  } catch (const InputError& e) {
    throw InputError(scene.geometryWhere + ": " + e.what());
  }
  if (fill.count() == 0)
    throw InputError(scene.geometryWhere +
                     ": the regions hold no particle (every lattice site of spacing " +
                     fmt(sim.spacing) + " m is outside the regions or subtracted)");
  ParticleStore& st = sim.store;
  const Index first = st.addParticles(fill.count());
  double cellVolume = 1.0;
  for (int a = 0; a < dim; ++a) cellVolume *= sim.spacing;
  scene.particlesPerMaterial.assign(sim.materials.size(), 0);
  double* x = st.data(st.position());
  double* v = st.data(st.velocity());
  double* mass = st.data(st.mass());
  double* rho = st.data(st.density());
  std::int32_t* matId = st.data(st.material());
  std::int32_t* motion = st.data(sim.motion);
  std::int32_t* phase = st.data(st.phase());
  for (Index k = 0; k < fill.count(); ++k) {
    const Index i = first + k;
    const Region& r = scene.regions[static_cast<size_t>(fill.region[static_cast<size_t>(k)])];
    for (int a = 0; a < dim; ++a) {
      x[i * dim + a] = fill.position[static_cast<size_t>(k * dim + a)];
      v[i * dim + a] = r.velocity[static_cast<size_t>(a)];
    }
    const double r0 = rho0[static_cast<size_t>(r.material)];
    mass[i] = r0 * cellVolume;  // m = rho0 dx^D
    rho[i] = r0;
    matId[i] = r.material;
    motion[i] = r.motion;
    // The phase its module declared (libcore/phases.hpp): set before any module initialises,
    // so that no module reads another module's particles as fluid.
    phase[i] = sim.materials[static_cast<size_t>(r.material)].phase;
    ++scene.particlesPerMaterial[static_cast<size_t>(r.material)];
  }
  scene.particlesBuilt = true;
  // Every pair class of the phases present has exactly one owner (libcore/phases.hpp).
  try {
    addPairOwners(sim);
    sim.checkPairOwners();
    sim.chooseNeighbourList();  // again: a pair owner added here may need the full list
  } catch (const InputError& e) {
    throw InputError(scene.geometryWhere + ": " + e.what());
  }
}

void initialiseScene(Scene& scene) {
  Simulation& sim = *scene.sim;
  sim.updateNeighbours();
  for (auto& m : sim.modules) m->initialise(sim);
  sim.evaluateRates();
  // Eq. 2.49 (velocity and acceleration) for every particle, then each module's own limits.
  scene.initialStableTimeStep = cflTimeStep(sim, sim.kernel.h());
  scene.stableLimitModule = "CFL of Eq. 2.49";
  for (const auto& m : sim.modules) {
    const double limit = m->timeStepLimit(sim);
    if (limit < scene.initialStableTimeStep) {
      scene.initialStableTimeStep = limit;
      scene.stableLimitModule = "module '" + m->name() + "'";
    }
  }
}

Scene loadSceneText(const std::string& text, const std::string& fileName,
                    const SceneOptions& options) {
  // A scene is UTF-8 text: refuse binary data (NUL bytes, invalid UTF-8) with the offset.
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    std::size_t len = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xe ? 3 : (c >> 3) == 0x1e ? 4 : 0;
    bool ok = c != 0 && len > 0 && i + len <= text.size();
    for (std::size_t k = 1; ok && k < len; ++k)
      ok = (static_cast<unsigned char>(text[i + k]) >> 6) == 0x2;
    if (!ok) {
      std::ostringstream m;
      m << fileName << ": is not a text file (byte " << i << " is 0x" << std::hex << std::setw(2)
        << std::setfill('0') << static_cast<int>(c)
        << "); a scene is a YAML text file (docs/scene-format.md)";
      throw InputError(m.str());
    }
    i += len;
  }
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(fileName + ":" + std::to_string(e.mark.line + 1) + ":" +
                     std::to_string(e.mark.column + 1) + ": malformed YAML: " + e.msg);
  }
  try {
    checkDuplicateKeys(root, fileName);
    return buildScene(root, fileName, options);
  } catch (const YAML::Exception& e) {
    throw InputError(fileName + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
}

Scene loadScene(const std::string& path, const SceneOptions& options) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path + ": is a directory, not a scene file (give the YAML file itself)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the scene file (missing or unreadable)");
  std::ostringstream text;
  text << in.rdbuf();
  return loadSceneText(text.str(), path, options);
}

std::string MemoryEstimate::describe() const {
  std::ostringstream o;
  o << "about " << formatBytes(totalBytes) << " (" << particles << " particles x "
    << bytesPerParticle << " bytes per particle: fields " << fieldBytesPerParticle
    << ", rollback copy " << rollbackBytesPerParticle << ", neighbour lists ~"
    << neighbourBytesPerParticle << ")";
  if (availableBytes > 0)
    o << "; available " << formatBytes(availableBytes) << " (MemAvailable)";
  else
    o << "; available memory unknown";
  return o.str();
}

double Scene::nextTimeStep() const {
  const Simulation& s = *sim;
  const double remaining = endTime - s.time;
  double dt = timeStep.dt;
  if (timeStep.adaptive) {
    const double limit = timeStep.cfl * std::min(s.stableTimeStep(), cflTimeStep(s, s.kernel.h()));
    dt = timeStep.dt > 0.0 ? std::min(timeStep.dt, limit) : limit;
    if (!(dt > 0.0) || !std::isfinite(dt)) {
      std::ostringstream m;
      m << "the adaptive time step is " << dt << " s at step " << s.step << ", time " << s.time
        << " s (stable limit " << std::min(s.stableTimeStep(), cflTimeStep(s, s.kernel.h()))
        << " s); no module limits the step (give time_step.dt as a cap) or the state blew up";
      throw NumericalError(m.str());
    }
  }
  // Land on end_time exactly, and never leave a sliver for a last step: a remainder within 1 %
  // beyond dt is taken in this step (1 % over the stable step, once), since a sliver (an adaptive
  // run ending 1.7e-9 s past a 5e-6 s step, measured) trips the health check's dt_floor.
  if (remaining < dt * 1.01) dt = remaining;
  return dt;
}

bool Scene::finished() const {
  if (maxSteps > 0 && sim->step >= maxSteps) return true;
  if (sim->time >= endTime * (1.0 - 1e-12)) return true;
  return !endConditionMet().empty();
}

std::string Scene::endConditionMet() const {
  for (const auto& m : sim->modules) {
    std::string reason = m->endCondition(*sim);
    if (!reason.empty()) return reason;
  }
  return {};
}

Index latticeNeighbourCount(int dimension, double supportOverDx) {
  const long r = static_cast<long>(std::ceil(supportOverDx)) + 1;
  Index count = 0;
  const long rz = dimension > 2 ? r : 0, ry = dimension > 1 ? r : 0;
  for (long k = -rz; k <= rz; ++k)
    for (long j = -ry; j <= ry; ++j)
      for (long i = -r; i <= r; ++i) {
        const double d2 = static_cast<double>(i * i + j * j + k * k);
        if (d2 > 0.0 && d2 < supportOverDx * supportOverDx) ++count;
      }
  return count;
}

std::string resolvedSceneYaml(const Scene& scene) {
  const Simulation& sim = *scene.sim;
  std::string modules;
  for (const auto& m : sim.modules) modules += (modules.empty() ? "" : ", ") + m->name();
  std::ostringstream h;
  h.precision(15);
  h << "PoreSPH " PORESPH_VERSION ": every scene value used by this run, defaults included\n"
    << "(scene: " << scene.file << "). It is itself a valid scene file.\n"
    << "smoothing length h = " << sim.kernel.h() << " m; modules in stage order: "
    << (modules.empty() ? std::string("none") : modules);
  YAML::Emitter e;
  e << YAML::Comment(h.str());
  e << scene.resolved;
  return std::string(e.c_str()) + "\n";
}

std::string describeScene(const Scene& scene) {
  const Simulation& sim = *scene.sim;
  const int dim = sim.dimension();
  std::ostringstream o;
  o.precision(6);
  o << "scene:        " << scene.file << "\n";
  o << "dimension:    " << dim << "\n";
  o << "domain:       ";
  for (int a = 0; a < dim; ++a)
    o << (a ? " x " : "") << "[" << sim.domain.lo[static_cast<size_t>(a)] << ", "
      << sim.domain.hi[static_cast<size_t>(a)] << "]" << (sim.domain.periodic[static_cast<size_t>(a)] ? " periodic" : "");
  o << " m\n";
  o << "spacing:      dx = " << sim.spacing << " m, h = " << sim.kernel.h() << " m (h/dx = "
    << scene.hOverDx << "), kernel " << scene.kernelName << " (support " << sim.kernel.support()
    << " m)\n";
  if (scene.particlesBuilt || sim.store.realCount() > 0)
    o << "particles:    " << sim.store.realCount() << "\n";
  else
    o << "particles:    " << scene.memory.particles << " (counted; not built)\n";
  for (const auto& m : sim.materials)
    o << "  " << std::left << std::setw(16) << m.name << std::right << std::setw(12)
      << scene.particlesPerMaterial[static_cast<size_t>(m.id)] << "  (model " << m.model << ")\n";
  o << "modules:      ";
  if (sim.modules.empty()) o << "(none)";
  for (size_t k = 0; k < sim.modules.size(); ++k) o << (k ? ", " : "") << sim.modules[k]->name();
  o << "\n";
  if (scene.particlesBuilt || sim.store.realCount() > 0)
    for (const auto& m : sim.modules) o << m->describe(sim);
  o << "fields:       " << sim.store.fields().size() << "\n";
  for (const auto& f : sim.store.fields()) {
    std::string flags;
    if (f.flags & kFieldOutput) flags += " output";
    if (f.flags & kFieldCheckpoint) flags += " checkpoint";
    if (f.flags & kFieldToGhosts) flags += " ghosts";
    o << "  " << std::left << std::setw(24) << f.name << ' ' << std::setw(5)
      << (f.type == FieldType::Real ? "real" : "int") << std::right << std::setw(3) << f.components
      << " x " << std::left << std::setw(8)
      << (f.type == FieldType::Real ? "8 bytes" : "4 bytes") << " owner " << std::setw(10)
      << f.owner << flags << std::right << "\n";
  }
  const std::size_t bpp = sim.store.bytesPerParticle();
  const double nParticles = scene.particlesBuilt || sim.store.realCount() > 0
                                ? static_cast<double>(sim.store.realCount())
                                : static_cast<double>(scene.memory.particles);
  o << "bytes/particle: " << bpp << " (fields), "
    << fmt(static_cast<double>(bpp) * nParticles / 1048576.0) << " MiB for all particles\n";
  if (scene.memory.particles > 0)
    o << "memory:       a run needs " << scene.memory.describe()
      << (scene.memory.fits() ? "" : ": does NOT fit") << "\n";
  const double sOverDx = sim.kernel.support() / sim.spacing;
  o << "neighbours:   ~" << latticeNeighbourCount(dim, sOverDx)
    << " per interior particle (lattice estimate, support " << fmt(sOverDx) << " dx)";
  if (sim.neighbours.realCount() > 0)
    o << ", measured mean " << fmt(static_cast<double>(sim.neighbours.pairCount()) /
                                   static_cast<double>(sim.neighbours.realCount()))
      << (sim.neighbours.half ? " in the half list (each pair of real particles once)" : "")
      << (sim.neighbourPairMask() != kAllPairClasses ? " (the pair classes the modules read)" : "")
      << ", list " << fmt(static_cast<double>(sim.neighbours.bytes()) / 1048576.0) << " MiB";
  o << "\n";
  o << "time:         end_time " << scene.endTime << " s, integrator " << scene.integrator << ", ";
  if (scene.timeStep.adaptive)
    o << "adaptive dt (cfl " << scene.timeStep.cfl << (scene.timeStep.dt > 0 ? ", cap " + fmt(scene.timeStep.dt) + " s" : std::string()) << ")";
  else
    o << "fixed dt " << scene.timeStep.dt << " s (~" << std::llround(std::ceil(scene.endTime / scene.timeStep.dt - 1e-9)) << " steps)";
  if (std::isfinite(scene.initialStableTimeStep))
    o << ", stable limit " << scene.initialStableTimeStep << " s (" << scene.stableLimitModule << ")";
  o << "\n";
  o << "output:       ";
  if (scene.output.everySteps > 0) o << "every " << scene.output.everySteps << " steps\n";
  else o << "every " << scene.output.everyTime << " s\n";
  return o.str();
}

}  // namespace poresph
