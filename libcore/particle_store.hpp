#pragma once
// The one particle store of PoreSPH (structure of arrays).
//
// Every phase (fluid, solid, rigid) lives here. Each field is one contiguous array, registered by
// name by the module that needs it; nothing that no active module registered is allocated. Hot
// loops never look a field up by name: modules resolve handles once at set-up and use data().
//
// Layout: indices [0, realCount()) are real particles, [realCount(), size()) are ghost (halo)
// particles: periodic images now, MPI halos later. Ghosts are copies of a source particle with a
// shifted position; modules read them as neighbours and never integrate them. Every field is
// permuted together by permute(), so per-particle state survives cell reordering.
#include <cstdint>
#include <string>
#include <vector>

#include "libcore/types.hpp"

namespace poresph {

/// How a field travels. Every field is permuted on reorder; the flags say the rest.
enum FieldFlag : unsigned {
  kFieldNone = 0,
  kFieldOutput = 1u << 0,      ///< written to VTK
  kFieldCheckpoint = 1u << 1,  ///< written to checkpoints (restart state)
  kFieldToGhosts = 1u << 2,    ///< copied from the source particle when a ghost is made
  /// Written once (initialise) and never again in the time loop, only permuted with the store
  /// (e.g. the solid's reference families): the run loop's rollback copy (RollbackState,
  /// libcore/health.hpp) does not copy it but restores the particle order instead.
  kFieldConstant = 1u << 3,
  /// The rollback copy (RollbackState, libcore/health.hpp) may hold it in single precision (a
  /// float offset from the middle of its range when the range excludes 0, else the float of the
  /// value): a state rolled back to then has this field rounded to 2^-24 of the largest
  /// |value - offset| (velocity, density, acceleration, pressure; position only
  /// while the store holds no solid or rigid particle, whose positions define strain and body
  /// shape; never the solid's reference and deformation fields).
  kFieldRollbackSingle = 1u << 4,
  kFieldDefault = kFieldOutput | kFieldCheckpoint | kFieldToGhosts,
};

enum class FieldType { Real, Int };

struct FieldSpec {
  std::string name;
  FieldType type = FieldType::Real;
  int components = 1;
  unsigned flags = kFieldDefault;
  std::string owner;  ///< the module (or "core") that registered it first
};

/// A resolved field: the index of the field in the store. Cheap to copy; valid for the store's
/// lifetime (fields are never removed).
template <class T>
struct FieldHandle {
  int id = -1;
  bool valid() const { return id >= 0; }
};
using RealField = FieldHandle<double>;
using IntField = FieldHandle<std::int32_t>;

class ParticleStore {
 public:
  explicit ParticleStore(int dimension);

  int dimension() const { return dim_; }
  Index size() const { return nReal_ + nGhost_; }
  Index realCount() const { return nReal_; }
  Index ghostCount() const { return nGhost_; }

  // ---- registration (produce = register-if-absent; consume = get-or-fail) ----
  /// Registers a real field with `components` doubles per particle (e.g. dimension() for a
  /// vector, dimension()^2 for a tensor). Registering an existing name with the same shape
  /// returns the existing handle (flags are OR-ed); a different shape is an error.
  RealField addReal(const std::string& name, int components, unsigned flags = kFieldDefault,
                    const std::string& owner = "core");
  IntField addInt(const std::string& name, int components = 1, unsigned flags = kFieldDefault,
                  const std::string& owner = "core");
  RealField real(const std::string& name) const;  ///< throws if absent
  IntField integer(const std::string& name) const;  ///< throws if absent
  bool has(const std::string& name) const;
  const std::vector<FieldSpec>& fields() const { return specs_; }
  const FieldSpec& spec(int id) const { return specs_.at(static_cast<size_t>(id)); }

  // ---- core fields, always present ----
  RealField position() const { return position_; }
  RealField velocity() const { return velocity_; }
  RealField mass() const { return mass_; }
  RealField density() const { return density_; }
  IntField phase() const { return phase_; }
  IntField material() const { return material_; }
  IntField id() const { return id_; }

  // ---- raw access (hot loops) ----
  double* data(RealField f) { return real_[static_cast<size_t>(slot_[f.id])].data(); }
  const double* data(RealField f) const { return real_[static_cast<size_t>(slot_[f.id])].data(); }
  std::int32_t* data(IntField f) { return int_[static_cast<size_t>(slot_[f.id])].data(); }
  const std::int32_t* data(IntField f) const {
    return int_[static_cast<size_t>(slot_[f.id])].data();
  }
  int components(int fieldId) const { return specs_[static_cast<size_t>(fieldId)].components; }

  /// Per-particle vector view of a D-component real field.
  template <int D>
  Eigen::Map<Vec<D>> vec(RealField f, Index i) {
    return Eigen::Map<Vec<D>>(data(f) + D * i);
  }
  template <int D>
  Eigen::Map<const Vec<D>> vec(RealField f, Index i) const {
    return Eigen::Map<const Vec<D>>(data(f) + D * i);
  }
  /// Per-particle D x D tensor view (column-major) of a D*D-component real field.
  template <int D>
  Eigen::Map<Mat<D>> mat(RealField f, Index i) {
    return Eigen::Map<Mat<D>>(data(f) + D * D * i);
  }
  template <int D>
  Eigen::Map<const Mat<D>> mat(RealField f, Index i) const {
    return Eigen::Map<const Mat<D>>(data(f) + D * D * i);
  }

  // ---- particle management ----
  /// Appends `count` real particles (fields zero, id set to a fresh global id). Only valid while
  /// there are no ghosts. Returns the index of the first new particle.
  Index addParticles(Index count);
  /// Reserves room so that growth up to `capacity` particles (real + ghost) does not allocate.
  void reserve(Index capacity);
  /// Removes all ghosts (keeps the memory).
  void clearGhosts();
  /// Appends ghosts: ghost k is a copy of particle sources[k] (a real particle) with its
  /// position shifted by shifts[D*k .. D*k+D). Only fields flagged kFieldToGhosts are copied
  /// (plus position); other fields of ghosts are left as they are.
  void addGhosts(const std::vector<Index>& sources, const std::vector<double>& shifts);
  /// Copies every kFieldToGhosts field (and the position, plus shifts[D*k .. D*k+D) for ghost
  /// k) from the sources into the existing ghosts: the ghosts follow their sources without
  /// being rebuilt (the periodic halo between two Verlet searches).
  void refreshAllGhosts(const std::vector<double>& shifts);
  /// The real particle each ghost is an image of (index g - realCount()).
  const std::vector<Index>& ghostSources() const { return ghostSource_; }
  /// Copies a field's values from the sources into the ghosts (after a module updated it).
  void refreshGhosts(RealField f);
  void refreshGhosts(IntField f);
  /// Reorders the real particles: new particle k is old particle newToOld[k]. Every field is
  /// permuted. Only valid while there are no ghosts.
  void permute(const std::vector<Index>& newToOld);
  /// Keeps only the real particles for which keep[i] is true (e.g. particles that left an open
  /// domain). Only valid while there are no ghosts.
  void compact(const std::vector<char>& keep);

  /// Bytes of particle data per particle (sum over allocated fields).
  std::size_t bytesPerParticle() const;

 private:
  /// Copies the ghost fields of ghosts firstGhost.. from their sources, shifts[D*(g - firstGhost)..].
  void copyToGhosts(Index firstGhost, const std::vector<double>& shifts);
  int addField(const std::string& name, FieldType type, int components, unsigned flags,
               const std::string& owner);
  int find(const std::string& name) const;
  void resizeAll(Index n);

  int dim_;
  Index nReal_ = 0;
  Index nGhost_ = 0;
  Index capacity_ = 0;
  std::int32_t nextId_ = 0;
  std::vector<FieldSpec> specs_;
  std::vector<int> slot_;  // field id -> index into real_ or int_
  std::vector<std::vector<double>> real_;
  std::vector<std::vector<std::int32_t>> int_;
  std::vector<Index> ghostSource_;
  std::vector<double> scratchReal_;
  std::vector<std::int32_t> scratchInt_;
  RealField position_, velocity_, mass_, density_;
  IntField phase_, material_, id_;
};

}  // namespace poresph
