#include "libcore/particle_store.hpp"

#include <algorithm>
#include <cstring>

namespace poresph {

ParticleStore::ParticleStore(int dimension) : dim_(dimension) {
  if (dimension < 1 || dimension > 3)
    throw InputError("particle store: dimension must be 1, 2 or 3, got " +
                     std::to_string(dimension));
  // Single precision in the rollback copy only without solid or rigid particles (health.cpp).
  position_ = addReal("position", dim_, kFieldDefault | kFieldRollbackSingle, "core");
  velocity_ = addReal("velocity", dim_, kFieldDefault | kFieldRollbackSingle, "core");
  mass_ = addReal("mass", 1, kFieldDefault, "core");
  density_ = addReal("density", 1, kFieldDefault | kFieldRollbackSingle, "core");
  phase_ = addInt("phase", 1, kFieldDefault, "core");
  material_ = addInt("material", 1, kFieldDefault, "core");
  id_ = addInt("id", 1, kFieldDefault, "core");
}

int ParticleStore::find(const std::string& name) const {
  for (size_t k = 0; k < specs_.size(); ++k)
    if (specs_[k].name == name) return static_cast<int>(k);
  return -1;
}

bool ParticleStore::has(const std::string& name) const { return find(name) >= 0; }

int ParticleStore::addField(const std::string& name, FieldType type, int components,
                            unsigned flags, const std::string& owner) {
  if (components < 1)
    throw std::logic_error("field '" + name + "' needs at least one component");
  const int existing = find(name);
  if (existing >= 0) {
    FieldSpec& s = specs_[static_cast<size_t>(existing)];
    if (s.type != type || s.components != components)
      throw std::logic_error("field '" + name + "' registered by '" + owner +
                             "' with a different shape than by '" + s.owner + "'");
    s.flags |= flags;
    return existing;
  }
  FieldSpec s{name, type, components, flags, owner};
  specs_.push_back(s);
  const size_t n = static_cast<size_t>(size()) * static_cast<size_t>(components);
  const size_t cap = static_cast<size_t>(capacity_) * static_cast<size_t>(components);
  if (type == FieldType::Real) {
    slot_.push_back(static_cast<int>(real_.size()));
    real_.emplace_back();
    real_.back().reserve(cap);
    real_.back().assign(n, 0.0);
  } else {
    slot_.push_back(static_cast<int>(int_.size()));
    int_.emplace_back();
    int_.back().reserve(cap);
    int_.back().assign(n, 0);
  }
  return static_cast<int>(specs_.size() - 1);
}

RealField ParticleStore::addReal(const std::string& name, int components, unsigned flags,
                                 const std::string& owner) {
  return RealField{addField(name, FieldType::Real, components, flags, owner)};
}

IntField ParticleStore::addInt(const std::string& name, int components, unsigned flags,
                               const std::string& owner) {
  return IntField{addField(name, FieldType::Int, components, flags, owner)};
}

RealField ParticleStore::real(const std::string& name) const {
  const int k = find(name);
  if (k < 0 || specs_[static_cast<size_t>(k)].type != FieldType::Real)
    throw std::logic_error("no real field '" + name + "' in the particle store");
  return RealField{k};
}

IntField ParticleStore::integer(const std::string& name) const {
  const int k = find(name);
  if (k < 0 || specs_[static_cast<size_t>(k)].type != FieldType::Int)
    throw std::logic_error("no integer field '" + name + "' in the particle store");
  return IntField{k};
}

void ParticleStore::resizeAll(Index n) {
  for (size_t k = 0; k < specs_.size(); ++k) {
    const size_t len = static_cast<size_t>(n) * static_cast<size_t>(specs_[k].components);
    if (specs_[k].type == FieldType::Real)
      real_[static_cast<size_t>(slot_[k])].resize(len, 0.0);
    else
      int_[static_cast<size_t>(slot_[k])].resize(len, 0);
  }
  capacity_ = std::max(capacity_, n);
}

void ParticleStore::reserve(Index capacity) {
  for (size_t k = 0; k < specs_.size(); ++k) {
    const size_t len = static_cast<size_t>(capacity) * static_cast<size_t>(specs_[k].components);
    if (specs_[k].type == FieldType::Real)
      real_[static_cast<size_t>(slot_[k])].reserve(len);
    else
      int_[static_cast<size_t>(slot_[k])].reserve(len);
  }
  ghostSource_.reserve(static_cast<size_t>(std::max<Index>(0, capacity - nReal_)));
  capacity_ = std::max(capacity_, capacity);
}

Index ParticleStore::addParticles(Index count) {
  if (nGhost_ != 0) throw std::logic_error("addParticles: remove ghosts first");
  const Index first = nReal_;
  nReal_ += count;
  resizeAll(nReal_);
  std::int32_t* ids = data(id_);
  for (Index i = first; i < nReal_; ++i) ids[i] = nextId_++;
  return first;
}

void ParticleStore::clearGhosts() {
  nGhost_ = 0;
  ghostSource_.clear();
  resizeAll(nReal_);
}

void ParticleStore::addGhosts(const std::vector<Index>& sources, const std::vector<double>& shifts) {
  const Index add = static_cast<Index>(sources.size());
  if (add == 0) return;
  nGhost_ += add;
  resizeAll(size());
  ghostSource_.insert(ghostSource_.end(), sources.begin(), sources.end());
  copyToGhosts(nGhost_ - add, shifts);
}

void ParticleStore::refreshAllGhosts(const std::vector<double>& shifts) {
  if (static_cast<Index>(shifts.size()) != nGhost_ * dim_)
    throw std::logic_error("refreshAllGhosts: " + std::to_string(shifts.size()) +
                           " shift components for " + std::to_string(nGhost_) + " ghosts");
  copyToGhosts(0, shifts);
}

void ParticleStore::copyToGhosts(Index firstGhost, const std::vector<double>& shifts) {
  const Index add = nGhost_ - firstGhost;
  const Index first = nReal_ + firstGhost;
  const Index* sources = ghostSource_.data() + firstGhost;
  for (size_t k = 0; k < specs_.size(); ++k) {
    const FieldSpec& s = specs_[k];
    const bool isPosition = static_cast<int>(k) == position_.id;
    if (!(s.flags & kFieldToGhosts) && !isPosition) continue;
    const Index c = s.components;
    if (s.type == FieldType::Real) {
      double* d = real_[static_cast<size_t>(slot_[k])].data();
#pragma omp parallel for schedule(static)
      for (Index g = 0; g < add; ++g)
        for (Index q = 0; q < c; ++q) d[(first + g) * c + q] = d[sources[g] * c + q];
    } else {
      std::int32_t* d = int_[static_cast<size_t>(slot_[k])].data();
#pragma omp parallel for schedule(static)
      for (Index g = 0; g < add; ++g)
        for (Index q = 0; q < c; ++q) d[(first + g) * c + q] = d[sources[g] * c + q];
    }
  }
  double* x = data(position_);
#pragma omp parallel for schedule(static)
  for (Index g = 0; g < add; ++g)
    for (int q = 0; q < dim_; ++q) x[(first + g) * dim_ + q] += shifts[g * dim_ + q];
}

void ParticleStore::refreshGhosts(RealField f) {
  const Index c = components(f.id);
  double* d = data(f);
  const Index n0 = nReal_;
#pragma omp parallel for schedule(static)
  for (Index g = 0; g < nGhost_; ++g)
    for (Index q = 0; q < c; ++q) d[(n0 + g) * c + q] = d[ghostSource_[g] * c + q];
}

void ParticleStore::refreshGhosts(IntField f) {
  const Index c = components(f.id);
  std::int32_t* d = data(f);
  const Index n0 = nReal_;
#pragma omp parallel for schedule(static)
  for (Index g = 0; g < nGhost_; ++g)
    for (Index q = 0; q < c; ++q) d[(n0 + g) * c + q] = d[ghostSource_[g] * c + q];
}

void ParticleStore::permute(const std::vector<Index>& newToOld) {
  if (nGhost_ != 0) throw std::logic_error("permute: remove ghosts first");
  if (static_cast<Index>(newToOld.size()) != nReal_)
    throw std::logic_error("permute: permutation size differs from the particle count");
  // Gather into a scratch buffer, then copy back: the fields keep their memory (reserved
  // capacity and data() pointers survive a reorder, so a time loop does not allocate).
  for (size_t k = 0; k < specs_.size(); ++k) {
    const Index c = specs_[k].components;
    const size_t len = static_cast<size_t>(nReal_) * static_cast<size_t>(c);
    if (specs_[k].type == FieldType::Real) {
      double* d = real_[static_cast<size_t>(slot_[k])].data();
      if (scratchReal_.size() < len) scratchReal_.resize(len);
      double* tmp = scratchReal_.data();
#pragma omp parallel for schedule(static)
      for (Index i = 0; i < nReal_; ++i)
        for (Index q = 0; q < c; ++q) tmp[i * c + q] = d[newToOld[i] * c + q];
      std::copy(tmp, tmp + len, d);
    } else {
      std::int32_t* d = int_[static_cast<size_t>(slot_[k])].data();
      if (scratchInt_.size() < len) scratchInt_.resize(len);
      std::int32_t* tmp = scratchInt_.data();
#pragma omp parallel for schedule(static)
      for (Index i = 0; i < nReal_; ++i)
        for (Index q = 0; q < c; ++q) tmp[i * c + q] = d[newToOld[i] * c + q];
      std::copy(tmp, tmp + len, d);
    }
  }
}

void ParticleStore::compact(const std::vector<char>& keep) {
  if (nGhost_ != 0) throw std::logic_error("compact: remove ghosts first");
  if (static_cast<Index>(keep.size()) != nReal_)
    throw std::logic_error("compact: mask size differs from the particle count");
  std::vector<Index> order;
  order.reserve(static_cast<size_t>(nReal_));
  for (Index i = 0; i < nReal_; ++i)
    if (keep[static_cast<size_t>(i)]) order.push_back(i);
  const Index kept = static_cast<Index>(order.size());
  for (Index i = 0; i < nReal_; ++i)
    if (!keep[static_cast<size_t>(i)]) order.push_back(i);
  permute(order);
  nReal_ = kept;
  resizeAll(nReal_);
}

std::size_t ParticleStore::bytesPerParticle() const {
  std::size_t b = 0;
  for (const auto& s : specs_)
    b += static_cast<std::size_t>(s.components) *
         (s.type == FieldType::Real ? sizeof(double) : sizeof(std::int32_t));
  return b;
}

}  // namespace poresph
