// HDF5 checkpoints (C API). Layout:
//   /                 attributes: format ("poresph-checkpoint-1"), time, dt (double), step,
//                     particle_count (int64), dimension (int32), domain_lo, domain_hi
//                     (double[3]), domain_periodic (int32[3]), scene_signature (string: a
//                     hash of the scene's physics and geometry, compared on restart)
//   /fields/<name>    one dataset per kFieldCheckpoint field: [particle_count, components],
//                     IEEE float64 little endian or int32 little endian
//   /integrator/<entry>  Integrator::saveState (rates and the scheme's state, by particle id)
//   /modules/<module>/<entry>  Module::saveState of each module that has one: 1D float64
//   /settings         one string attribute per resolved setting of the run (name: the setting's
//                     key, e.g. fluid.pressure_gradient; Module::settings), compared on restart
//                     by runner.cpp; absent from checkpoints written before 2026-11-28
#include "libcore/checkpoint.hpp"

#include <hdf5.h>

#include <cstring>
#include <filesystem>
#include <system_error>
#include <string>
#include <vector>

#include "libcore/simulation.hpp"

namespace poresph {

namespace {

const char* kFormat = "poresph-checkpoint-1";

/// Silences HDF5's own error printing for the lifetime of the object (errors are reported as
/// exceptions instead).
class QuietHdf5 {
 public:
  QuietHdf5() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

/// Closes an HDF5 identifier on scope exit.
struct Handle {
  hid_t id = -1;
  herr_t (*close)(hid_t) = nullptr;
  Handle(hid_t i, herr_t (*c)(hid_t)) : id(i), close(c) {}
  ~Handle() {
    if (id >= 0 && close) close(id);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id; }
};

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw InputError("checkpoint '" + path + "': " + what);
}

void writeAttr(hid_t loc, const char* name, hid_t fileType, hid_t memType, const void* v,
               hsize_t count, const std::string& path) {
  Handle space(count == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &count, nullptr),
               H5Sclose);
  Handle attr(H5Acreate2(loc, name, fileType, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (attr < 0 || H5Awrite(attr, memType, v) < 0)
    fail(path, std::string("cannot write attribute '") + name + "'");
}

void readAttr(hid_t loc, const char* name, hid_t memType, void* v, hsize_t count,
              const std::string& path) {
  if (H5Aexists(loc, name) <= 0) fail(path, std::string("attribute '") + name + "' is missing");
  Handle attr(H5Aopen(loc, name, H5P_DEFAULT), H5Aclose);
  Handle space(H5Aget_space(attr), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (attr < 0 || n != static_cast<hssize_t>(count))
    fail(path, std::string("attribute '") + name + "' has the wrong size");
  if (H5Aread(attr, memType, v) < 0)
    fail(path, std::string("cannot read attribute '") + name + "'");
}

herr_t collectName(hid_t, const char* name, const H5L_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->emplace_back(name);
  return 0;
}

/// One group of named 1D float64 datasets (a ModuleState) at `where`.
void writeStateGroup(hid_t parent, const std::string& where, const ModuleState& state,
                     const std::string& path) {
  Handle group(H5Gcreate2(parent, where.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
               H5Gclose);
  if (group < 0) fail(path, "cannot create group '" + where + "'");
  for (const auto& [name, values] : state) {
    const hsize_t n = values.size();
    Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
    Handle set(H5Dcreate2(group, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT,
                          H5P_DEFAULT),
               H5Dclose);
    if (set < 0 || (n > 0 && H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                                      values.data()) < 0))
      fail(path, "cannot write state '" + where + "/" + name + "'");
  }
}

/// Every dataset of the group `where` (entries in name order).
ModuleState readStateGroup(hid_t file, const std::string& where, const std::string& path) {
  ModuleState state;
  Handle group(H5Gopen2(file, where.c_str(), H5P_DEFAULT), H5Gclose);
  if (group < 0) fail(path, "cannot open group '" + where + "'");
  std::vector<std::string> names;
  H5Literate(group, H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, collectName, &names);
  for (const auto& name : names) {
    Handle set(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose);
    Handle space(H5Dget_space(set), H5Sclose);
    const hssize_t n = H5Sget_simple_extent_npoints(space);
    if (set < 0 || n < 0) fail(path, "cannot read state '" + where + "/" + name + "'");
    std::vector<double> values(static_cast<size_t>(n));
    if (n > 0 &&
        H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
      fail(path, "cannot read state '" + where + "/" + name + "'");
    state.emplace_back(name, std::move(values));
  }
  return state;
}

void writeModuleStates(const Simulation& sim, hid_t file, const std::string& path) {
  bool any = false;
  for (const auto& m : sim.modules) any = any || !m->saveState().empty();
  if (!any) return;
  Handle modules(H5Gcreate2(file, "modules", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (modules < 0) fail(path, "cannot create group 'modules'");
  for (const auto& m : sim.modules) {
    const ModuleState state = m->saveState();
    if (!state.empty()) writeStateGroup(modules, m->name(), state, path);
  }
}

/// Reads every module's state (checked: same entries and lengths as the module's own state)
/// before anything is restored; returns one state per module (empty for modules without one).
std::vector<ModuleState> readModuleStates(const Simulation& sim, hid_t file,
                                          const std::string& path) {
  std::vector<ModuleState> out;
  for (const auto& m : sim.modules) {
    ModuleState expected = m->saveState();
    if (expected.empty()) {
      out.emplace_back();
      continue;
    }
    const std::string where = "modules/" + m->name();
    const bool hasGroup = H5Lexists(file, "modules", H5P_DEFAULT) > 0 &&
                          H5Lexists(file, where.c_str(), H5P_DEFAULT) > 0;
    if (!hasGroup)
      fail(path, "the state of module '" + m->name() + "' (group '" + where +
                     "') is missing from the file");
    Handle group(H5Gopen2(file, where.c_str(), H5P_DEFAULT), H5Gclose);
    for (auto& [name, values] : expected) {
      if (H5Lexists(group, name.c_str(), H5P_DEFAULT) <= 0)
        fail(path, "module state '" + where + "/" + name + "' is missing from the file");
      Handle set(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose);
      Handle space(H5Dget_space(set), H5Sclose);
      const hssize_t n = H5Sget_simple_extent_npoints(space);
      if (set < 0 || n != static_cast<hssize_t>(values.size()))
        fail(path, "module state '" + where + "/" + name + "' has " + std::to_string(n) +
                       " values in the file but " + std::to_string(values.size()) +
                       " are expected");
      if (n > 0 && H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                           values.data()) < 0)
        fail(path, "cannot read module state '" + where + "/" + name + "'");
    }
    out.push_back(std::move(expected));
  }
  return out;
}

/// The run's settings (ModuleSetting) as string attributes of the group /settings.
void writeSettings(hid_t file, const ModuleSettings& settings, const std::string& path) {
  Handle group(H5Gcreate2(file, "settings", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (group < 0) fail(path, "cannot create group 'settings'");
  for (const ModuleSetting& s : settings) {
    if (H5Aexists(group, s.key.c_str()) > 0) continue;  // one value per key (the first)
    Handle strType(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(strType, s.value.size() + 1);  // with the terminating zero: "" is allowed
    H5Tset_strpad(strType, H5T_STR_NULLTERM);
    writeAttr(group, s.key.c_str(), strType, strType, s.value.c_str(), 1, path);
  }
}

herr_t collectAttrName(hid_t, const char* name, const H5A_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->emplace_back(name);
  return 0;
}

/// The string value of attribute `name` of `loc` ("" if it cannot be read).
std::string readStringAttr(hid_t loc, const char* name) {
  Handle attr(H5Aopen(loc, name, H5P_DEFAULT), H5Aclose);
  if (attr < 0) return "";
  Handle type(H5Aget_type(attr), H5Tclose);
  const size_t size = H5Tget_size(type);
  if (size == 0 || H5Tget_class(type) != H5T_STRING) return "";
  std::string got(size, '\0');
  Handle memType(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(memType, size);
  if (H5Aread(attr, memType, got.data()) < 0) return "";
  const size_t end = got.find('\0');
  if (end != std::string::npos) got.resize(end);
  return got;
}

}  // namespace

CheckpointRecord readCheckpointRecord(const std::string& path) {
  QuietHdf5 quiet;
  CheckpointRecord r;
  if (H5Fis_hdf5(path.c_str()) <= 0) return r;
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (file < 0) return r;
  if (H5Aexists(file, "scene_signature") > 0) r.signature = readStringAttr(file, "scene_signature");
  if (H5Lexists(file, "settings", H5P_DEFAULT) <= 0) return r;
  Handle group(H5Gopen2(file, "settings", H5P_DEFAULT), H5Gclose);
  if (group < 0) return r;
  r.hasSettings = true;
  std::vector<std::string> names;
  H5Aiterate2(group, H5_INDEX_NAME, H5_ITER_INC, nullptr, collectAttrName, &names);
  for (const auto& name : names) r.settings.emplace_back(name, readStringAttr(group, name.c_str()));
  return r;
}

namespace {

// Writes the checkpoint into `target`; errors name `path`, the checkpoint the user asked for.
void writeCheckpointInto(const std::string& target, const Simulation& sim, const std::string& path,
                         const std::string& signature, const ModuleState* integratorState,
                         const ModuleSettings* settings) {
  QuietHdf5 quiet;
  const ParticleStore& s = sim.store;
  Handle file(H5Fcreate(target.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
  if (file < 0) fail(path, "cannot create the file");

  {
    Handle strType(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(strType, std::strlen(kFormat));
    writeAttr(file, "format", strType, strType, kFormat, 1, path);
  }
  if (!signature.empty()) {
    Handle strType(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(strType, signature.size());
    writeAttr(file, "scene_signature", strType, strType, signature.data(), 1, path);
  }
  const std::int64_t step = sim.step, count = s.realCount();
  const std::int32_t dim = sim.dimension();
  writeAttr(file, "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &sim.time, 1, path);
  writeAttr(file, "dt", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &sim.dt, 1, path);
  writeAttr(file, "step", H5T_STD_I64LE, H5T_NATIVE_INT64, &step, 1, path);
  writeAttr(file, "particle_count", H5T_STD_I64LE, H5T_NATIVE_INT64, &count, 1, path);
  writeAttr(file, "dimension", H5T_STD_I32LE, H5T_NATIVE_INT32, &dim, 1, path);
  const std::int32_t periodic[3] = {sim.domain.periodic[0], sim.domain.periodic[1],
                                    sim.domain.periodic[2]};
  writeAttr(file, "domain_lo", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, sim.domain.lo.data(), 3, path);
  writeAttr(file, "domain_hi", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, sim.domain.hi.data(), 3, path);
  writeAttr(file, "domain_periodic", H5T_STD_I32LE, H5T_NATIVE_INT32, periodic, 3, path);

  Handle group(H5Gcreate2(file, "fields", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (group < 0) fail(path, "cannot create group 'fields'");
  for (size_t k = 0; k < s.fields().size(); ++k) {
    const FieldSpec& spec = s.fields()[k];
    if (!(spec.flags & kFieldCheckpoint)) continue;
    const hsize_t dims[2] = {static_cast<hsize_t>(count), static_cast<hsize_t>(spec.components)};
    Handle space(H5Screate_simple(2, dims, nullptr), H5Sclose);
    const bool isReal = spec.type == FieldType::Real;
    Handle set(H5Dcreate2(group, spec.name.c_str(), isReal ? H5T_IEEE_F64LE : H5T_STD_I32LE,
                          space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
               H5Dclose);
    if (set < 0) fail(path, "cannot create dataset for field '" + spec.name + "'");
    herr_t rc = 0;
    if (count > 0) {
      const int id = static_cast<int>(k);
      rc = isReal ? H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                             s.data(RealField{id}))
                  : H5Dwrite(set, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                             s.data(IntField{id}));
    }
    if (rc < 0) fail(path, "cannot write field '" + spec.name + "'");
  }
  writeModuleStates(sim, file, path);
  if (settings) {
    writeSettings(file, *settings, path);
  } else {
    ModuleSettings all;
    for (const auto& m : sim.modules)
      for (ModuleSetting& st : m->settings()) all.push_back(std::move(st));
    writeSettings(file, all, path);
  }
  if (integratorState && !integratorState->empty())
    writeStateGroup(file, "integrator", *integratorState, path);
  if (H5Fflush(file, H5F_SCOPE_GLOBAL) < 0) fail(path, "cannot flush the file");
}

}  // namespace

void writeCheckpoint(const Simulation& sim, const std::string& path,
                     const std::string& signature, const ModuleState* integratorState,
                     const ModuleSettings* settings) {
  // Written beside the old one and renamed over it once complete (rename is atomic on POSIX
  // file systems): a run killed while writing (SIGKILL, a lost machine) keeps the previous
  // checkpoint instead of a truncated file. Periodic checkpoints rely on it (docs/output.md).
  const std::string part = path + ".part";
  try {
    writeCheckpointInto(part, sim, path, signature, integratorState, settings);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(part, ignored);
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(part, path, ec);
  if (ec) fail(path, "cannot move the completed checkpoint " + part + " into place: " + ec.message());
}

void readCheckpoint(Simulation& sim, const std::string& path,
                    const std::string& expectedSignature, ModuleState* integratorState) {
  QuietHdf5 quiet;
  ParticleStore& s = sim.store;
  if (H5Fis_hdf5(path.c_str()) <= 0)
    fail(path, "not a readable HDF5 file");
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (file < 0) fail(path, "cannot open the file");

  std::int32_t dim = 0;
  std::int64_t step = 0, count = 0;
  double time = 0.0, dt = 0.0;
  std::array<double, 3> lo{}, hi{};
  std::int32_t periodic[3] = {0, 0, 0};
  readAttr(file, "dimension", H5T_NATIVE_INT32, &dim, 1, path);
  if (dim != sim.dimension())
    fail(path, "dimension " + std::to_string(dim) + " differs from the simulation's " +
                   std::to_string(sim.dimension()));
  readAttr(file, "time", H5T_NATIVE_DOUBLE, &time, 1, path);
  readAttr(file, "dt", H5T_NATIVE_DOUBLE, &dt, 1, path);
  readAttr(file, "step", H5T_NATIVE_INT64, &step, 1, path);
  readAttr(file, "particle_count", H5T_NATIVE_INT64, &count, 1, path);
  readAttr(file, "domain_lo", H5T_NATIVE_DOUBLE, lo.data(), 3, path);
  readAttr(file, "domain_hi", H5T_NATIVE_DOUBLE, hi.data(), 3, path);
  readAttr(file, "domain_periodic", H5T_NATIVE_INT32, periodic, 3, path);
  if (count < 0) fail(path, "negative particle_count");
  // A checkpoint of another scene: other particle count, or other physics and geometry.
  if (!expectedSignature.empty() && count != s.realCount())
    fail(path, "holds " + std::to_string(count) + " particles but the scene builds " +
                   std::to_string(s.realCount()) +
                   ": it was written by another scene (restart with the scene that wrote it)");
  if (!expectedSignature.empty() && H5Aexists(file, "scene_signature") > 0) {
    Handle attr(H5Aopen(file, "scene_signature", H5P_DEFAULT), H5Aclose);
    Handle type(H5Aget_type(attr), H5Tclose);
    const size_t size = H5Tget_size(type);
    std::string got(size, '\0');
    Handle memType(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(memType, size);
    if (size == 0 || H5Aread(attr, memType, got.data()) < 0)
      fail(path, "cannot read attribute 'scene_signature'");
    if (got != expectedSignature)
      fail(path, "was written by a scene with other physics or geometry (scene signature " + got +
                     ", this scene " + expectedSignature +
                     "): restart with the scene that wrote it; only end_time, max_steps, "
                     "time_step, output, health and drainage.stop_after_percolation may change "
                     "between the runs");
  }

  if (H5Lexists(file, "fields", H5P_DEFAULT) <= 0) fail(path, "group 'fields' is missing");
  Handle group(H5Gopen2(file, "fields", H5P_DEFAULT), H5Gclose);
  if (group < 0) fail(path, "cannot open group 'fields'");
  std::vector<std::string> inFile;
  H5Literate(group, H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, collectName, &inFile);

  // ---- check every name and shape before touching the simulation ----
  std::vector<int> ids;
  for (size_t k = 0; k < s.fields().size(); ++k) {
    const FieldSpec& spec = s.fields()[k];
    if (!(spec.flags & kFieldCheckpoint)) continue;
    if (H5Lexists(group, spec.name.c_str(), H5P_DEFAULT) <= 0)
      fail(path, "field '" + spec.name + "' (registered by '" + spec.owner +
                     "') is missing from the file");
    Handle set(H5Dopen2(group, spec.name.c_str(), H5P_DEFAULT), H5Dclose);
    Handle space(H5Dget_space(set), H5Sclose);
    Handle type(H5Dget_type(set), H5Tclose);
    hsize_t dims[2] = {0, 0};
    if (set < 0 || H5Sget_simple_extent_ndims(space) != 2 ||
        H5Sget_simple_extent_dims(space, dims, nullptr) != 2)
      fail(path, "field '" + spec.name + "' is not a 2D dataset");
    const H5T_class_t cls = H5Tget_class(type);
    const bool isReal = spec.type == FieldType::Real;
    if ((isReal && cls != H5T_FLOAT) || (!isReal && cls != H5T_INTEGER))
      fail(path, "field '" + spec.name + "' has type " + (cls == H5T_FLOAT ? "real" : "integer") +
                     " in the file but " + (isReal ? "real" : "integer") + " in the simulation");
    if (dims[0] != static_cast<hsize_t>(count) ||
        dims[1] != static_cast<hsize_t>(spec.components))
      fail(path, "field '" + spec.name + "' has shape [" + std::to_string(dims[0]) + ", " +
                     std::to_string(dims[1]) + "] in the file but [" + std::to_string(count) +
                     ", " + std::to_string(spec.components) + "] is expected");
    ids.push_back(static_cast<int>(k));
  }
  for (const auto& name : inFile) {
    bool known = false;
    for (int id : ids) known = known || s.spec(id).name == name;
    if (!known)
      fail(path, "field '" + name +
                     "' in the file is not a checkpoint field of this simulation (a module "
                     "configured differently?)");
  }

  const std::vector<ModuleState> moduleStates = readModuleStates(sim, file, path);
  if (integratorState) {
    integratorState->clear();
    if (H5Lexists(file, "integrator", H5P_DEFAULT) > 0)
      *integratorState = readStateGroup(file, "integrator", path);
  }

  // ---- restore ----
  s.clearGhosts();
  if (s.realCount() > count) {
    std::vector<char> keep(static_cast<size_t>(s.realCount()), 0);
    for (Index i = 0; i < count; ++i) keep[static_cast<size_t>(i)] = 1;
    s.compact(keep);
  } else if (s.realCount() < count) {
    s.addParticles(count - s.realCount());
  }
  for (int id : ids) {
    const FieldSpec& spec = s.spec(id);
    Handle set(H5Dopen2(group, spec.name.c_str(), H5P_DEFAULT), H5Dclose);
    herr_t rc = 0;
    if (count > 0)
      rc = spec.type == FieldType::Real
               ? H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                         s.data(RealField{id}))
               : H5Dread(set, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                         s.data(IntField{id}));
    if (rc < 0) fail(path, "cannot read field '" + spec.name + "'");
  }
  sim.time = time;
  sim.dt = dt;
  sim.step = step;
  sim.domain.dimension = dim;
  sim.domain.lo = lo;
  sim.domain.hi = hi;
  for (int a = 0; a < 3; ++a) sim.domain.periodic[static_cast<size_t>(a)] = periodic[a] != 0;
  for (size_t k = 0; k < sim.modules.size(); ++k)
    if (!moduleStates[k].empty()) sim.modules[k]->restoreState(moduleStates[k]);
}

}  // namespace poresph
