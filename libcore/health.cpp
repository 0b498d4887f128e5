#include "libcore/health.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <unordered_map>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "libcore/parameters.hpp"
#include "libcore/phases.hpp"
#include "libcore/simulation.hpp"

namespace poresph {

namespace {

// Passes over fewer values than this run on the calling thread, outside any OpenMP region
// (issue 11 speed, the small 2D box): a region costs ~1,500-2,500 instructions even with one
// thread or a false `if` clause (GOMP_parallel still builds a team; callgrind) and microseconds of
// fork and join with two, more than a pass over a few thousand values. The results do not depend
// on it (copies, exact min / max, palettes in order of first appearance either way).
constexpr std::size_t kParallelMin = 4096;

// Range of each of the NC components of count / NC values (lo = min, hi = max, std::min /
// std::max in index order: the same results as one pass per component), in one pass over memory.
// Used by the rollback copy's single-precision fields and the health check's domain and density
// bounds. In parallel (issue 17): min and max are exact, so the chunks' ranges merged in any order give
// the same values for finite data (the copied state passed checkFinite; a signed zero may come
// out with either sign, which the offset's test lo > 0 || hi < 0 does not see).
template <int NC>
void componentRange(const double* p, std::size_t count, double* lo, double* hi) {
  double l[NC], h[NC];
  for (int a = 0; a < NC; ++a) l[a] = h[a] = p[a];
  const std::size_t rows = count / NC;
  if (count < kParallelMin) {
#if defined(__SSE2__)
    // Two values a instruction (SSE2 minpd / maxpd; the compiler does not vectorise std::min
    // reductions without -ffast-math): a row of 2 components, or 2 rows of 1 (issue 11 speed).
    if (NC <= 2 && (NC == 2 || rows >= 2)) {
      __m128d vl = _mm_loadu_pd(p), vh = vl;
      const std::size_t pairs = NC == 2 ? rows : rows / 2;
      for (std::size_t k = 0; k < pairs; ++k) {
        const __m128d v = _mm_loadu_pd(p + 2 * k);
        vl = _mm_min_pd(vl, v);
        vh = _mm_max_pd(vh, v);
      }
      double bl[2], bh[2];
      _mm_storeu_pd(bl, vl);
      _mm_storeu_pd(bh, vh);
      if constexpr (NC == 2) {
        lo[0] = bl[0];
        lo[1] = bl[1];
        hi[0] = bh[0];
        hi[1] = bh[1];
      } else {
        double l0 = std::min(bl[0], bl[1]), h0 = std::max(bh[0], bh[1]);
        if (rows % 2) {
          l0 = std::min(l0, p[rows - 1]);
          h0 = std::max(h0, p[rows - 1]);
        }
        lo[0] = l0;
        hi[0] = h0;
      }
      return;
    }
#endif
    for (std::size_t i = 0; i < rows; ++i)
      for (int a = 0; a < NC; ++a) {
        l[a] = std::min(l[a], p[i * NC + static_cast<std::size_t>(a)]);
        h[a] = std::max(h[a], p[i * NC + static_cast<std::size_t>(a)]);
      }
  } else {
#pragma omp parallel for schedule(static) reduction(min : l[:NC]) reduction(max : h[:NC])
    for (std::size_t i = 0; i < rows; ++i)
      for (int a = 0; a < NC; ++a) {
        l[a] = std::min(l[a], p[i * NC + static_cast<std::size_t>(a)]);
        h[a] = std::max(h[a], p[i * NC + static_cast<std::size_t>(a)]);
      }
  }
  for (int a = 0; a < NC; ++a) {
    lo[a] = l[a];
    hi[a] = h[a];
  }
}

}  // namespace

HealthLimits readHealthLimits(const ParameterSet* section) {
  HealthLimits h;
  if (!section) return h;
  const ParameterSet& s = *section;
  h.densityVariation = s.real("density_variation", h.densityVariation, Range::positive());
  h.maxMach = s.real("max_mach", h.maxMach, Range::positive());
  h.dtFloor = s.real("dt_floor", h.dtFloor, Range{0.0, 1.0, false, true});
  h.energyGrowth = s.real("energy_growth", h.energyGrowth, Range::positive());
  h.domainMargin = s.real("domain_margin", h.domainMargin, Range::nonNegative());
  h.rollbackEvery = static_cast<Index>(s.integer("rollback_every", 1, 1, 1000000000));
  h.keepGoing = s.boolean("keep_going", false);
  s.finish();
  return h;
}

double HealthMonitor::energyBalance(const Simulation& sim, EnergyAccount& total) const {
  total = EnergyAccount{};
  bool complete = true;
  for (const auto& m : sim.modules) complete = m->energyAccount(sim, total) && complete;
  total.complete = complete;
  return sim.kineticEnergy() + total.stored + total.dissipated - total.workIn;
}

void HealthMonitor::start(const Simulation& sim, double initialStableTimeStep) {
  initialStable_ = initialStableTimeStep;
  const int d = sim.dimension();
  // The box particles may occupy: the domain and the initial particles (wall layers may lie
  // outside the domain along non-periodic axes).
  for (int a = 0; a < 3; ++a) {
    boxLo_[static_cast<size_t>(a)] = sim.domain.lo[static_cast<size_t>(a)];
    boxHi_[static_cast<size_t>(a)] = sim.domain.hi[static_cast<size_t>(a)];
  }
  const double* x = sim.store.data(sim.store.position());
  const Index n = sim.store.realCount();
  for (int a = 0; a < d; ++a) {
    double lo = boxLo_[static_cast<size_t>(a)], hi = boxHi_[static_cast<size_t>(a)];
#pragma omp parallel for schedule(static) reduction(min : lo) reduction(max : hi)
    for (Index i = 0; i < n; ++i) {
      lo = std::min(lo, x[i * d + a]);
      hi = std::max(hi, x[i * d + a]);
    }
    boxLo_[static_cast<size_t>(a)] = lo;
    boxHi_[static_cast<size_t>(a)] = hi;
  }
  EnergyAccount account;
  energy0_ = energyBalance(sim, account);
  kinetic0_ = sim.kineticEnergy();
  stored0_ = account.stored;
  energyScale0_ = kinetic0_ + account.storedRange + account.untrackedScale;
  energyChecked_ = account.complete && !sim.modules.empty();
  workIn0_ = account.workIn;
  started_ = true;
}

std::vector<HealthIssue> HealthMonitor::check(const Simulation& sim) {
  std::vector<HealthIssue> issues;
  const ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const int d = sim.dimension();

  // One pass for the two per-particle checks of the core (issue 11 speed: was one pass each):
  // density <= 0 in any phase (the continuity equation went through zero, Eq. 2.29 / 5.1a), and
  // particles flying off the box along a non-periodic axis (once started).
  const double* rho = st.data(st.density());
  const double* x = st.data(st.position());
  double margin[3] = {0, 0, 0};
  for (int a = 0; a < d; ++a)
    margin[a] = limits_.domainMargin *
                std::max(boxHi_[static_cast<size_t>(a)] - boxLo_[static_cast<size_t>(a)],
                         sim.spacing);
  const auto periodic = sim.domain.periodic;
  const auto lo = boxLo_, hi = boxHi_;
  const bool domain = started_;
  auto scan = [&](Index i, MaxAt& rhoWorst, MaxAt& outWorst) {
    if (-rho[i] > rhoWorst.value || (-rho[i] == rhoWorst.value && i < rhoWorst.particle))
      rhoWorst = MaxAt{-rho[i], i};
    if (!domain) return;
    for (int a = 0; a < d; ++a) {
      if (periodic[static_cast<size_t>(a)]) continue;
      const double out = std::max(lo[static_cast<size_t>(a)] - x[i * d + a],
                                  x[i * d + a] - hi[static_cast<size_t>(a)]) -
                         margin[a];
      if (out > outWorst.value || (out == outWorst.value && i < outWorst.particle))
        outWorst = MaxAt{out, i};
    }
  };
  MaxAt rhoWorst, outWorst;
  if (static_cast<std::size_t>(n) < kParallelMin) {
    // Below kParallelMin particles the bounds first (issue 11 speed: componentRange's vector
    // min / max): the smallest density and each coordinate's range give the largest -rho and
    // the largest distance beyond the box exactly (a subtraction is monotone, so the extreme
    // coordinate gives the extreme distance); only a crossing is looked up particle by particle.
    bool crossed = true;
    if (n > 0) {
      double rhoLo, rhoHi;
      componentRange<1>(rho, static_cast<std::size_t>(n), &rhoLo, &rhoHi);
      crossed = rhoLo <= 0.0;
      if (domain) {
        double xl[3], xh[3];
        const std::size_t count = static_cast<std::size_t>(n) * static_cast<std::size_t>(d);
        if (d == 1) componentRange<1>(x, count, xl, xh);
        else if (d == 2) componentRange<2>(x, count, xl, xh);
        else componentRange<3>(x, count, xl, xh);
        for (int a = 0; a < d; ++a)
          if (!periodic[static_cast<size_t>(a)])
            crossed = crossed || std::max(lo[static_cast<size_t>(a)] - xl[a],
                                          xh[a] - hi[static_cast<size_t>(a)]) -
                                         margin[a] > 0.0;
      }
    }
    if (crossed)
      for (Index i = 0; i < n; ++i) scan(i, rhoWorst, outWorst);
  } else {
#pragma omp parallel for schedule(static) reduction(maxAt : rhoWorst, outWorst)
    for (Index i = 0; i < n; ++i) scan(i, rhoWorst, outWorst);
  }
  if (rhoWorst.particle >= 0 && rhoWorst.value >= 0.0)
    issues.push_back({"density_variation", "density", rhoWorst.particle, -rhoWorst.value, 0.0,
                      "a density that is not positive: the state has blown up"});

  // The time step has collapsed (adaptive steps follow the fastest particle).
  if (started_ && initialStable_ > 0.0 && std::isfinite(initialStable_) && sim.dt > 0.0 &&
      sim.dt < limits_.dtFloor * initialStable_)
    issues.push_back({"dt_floor", "dt", -1, sim.dt, limits_.dtFloor * initialStable_,
                      "the time step fell below dt_floor x the initial stable step " +
                          std::to_string(initialStable_) +
                          " s: a particle is accelerating without bound"});

  if (domain && outWorst.particle >= 0 && outWorst.value > 0.0)
    issues.push_back({"domain_margin", "position", outWorst.particle, outWorst.value, 0.0,
                      "m beyond the box of the domain and the initial particles enlarged by "
                      "domain_margin: the particle has left the domain"});

  // Energy put into the system without work (a numerical instability feeds itself).
  if (started_ && energyChecked_) {
    EnergyAccount account;
    const double e = energyBalance(sim, account);
    const double scale = energyScale0_ + std::abs(account.workIn - workIn0_);
    const double growth = e - energy0_;
    if (scale > 0.0 && growth > limits_.energyGrowth * scale)
      issues.push_back({"energy_growth", "energy", -1, growth / scale, limits_.energyGrowth,
                        "the energy (kinetic + stored + dissipated - work put in) grew by this "
                        "many times the scene's energy scale " + std::to_string(scale) +
                            " J without work input"});
  }

  for (const auto& m : sim.modules) m->checkHealth(sim, limits_, issues);
  return issues;
}

std::string HealthMonitor::describe(const Simulation& sim, const HealthIssue& issue) {
  std::ostringstream o;
  o.precision(6);
  o << "health check '" << issue.check << "' (field '" << issue.field << "'): ";
  if (issue.particle >= 0) {
    const ParticleStore& st = sim.store;
    const Index i = issue.particle;
    o << "particle " << i << " (id " << st.data(st.id())[i] << ", material "
      << st.data(st.material())[i] << ", at";
    const double* x = st.data(st.position());
    for (int a = 0; a < sim.dimension(); ++a) o << " " << x[i * sim.dimension() + a];
    o << " m) ";
  }
  o << "value " << issue.value << ", limit " << issue.limit;
  if (!issue.detail.empty()) o << " (" << issue.detail << ")";
  o << " at step " << sim.step << ", time " << sim.time << " s";
  return o.str();
}

}  // namespace poresph

namespace poresph {

bool RollbackState::copies(unsigned flags) {
  return (flags & (kFieldCheckpoint | kFieldOutput)) != 0 && (flags & kFieldConstant) == 0;
}

namespace {

using Storage = RollbackState::Storage;


std::uint64_t bitsOf(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
double doubleOf(std::uint64_t b) {
  double v;
  std::memcpy(&v, &b, sizeof v);
  return v;
}
std::uint64_t bitsOf(std::int32_t v) { return static_cast<std::uint32_t>(v); }

// The distinct bit patterns of values [0, count), in order of first appearance, when there are
// at most RollbackState::kPaletteSize of them (palette.size() > kPaletteSize otherwise: the scan
// stops at the first value beyond). `code` (optional) receives each value's index.
template <class T>
void paletteOf(const T* v, std::size_t count, std::vector<std::uint64_t>& palette,
               std::uint8_t* code) {
  palette.clear();
  std::uint64_t pal[RollbackState::kPaletteSize];
  int k = 0, last = 0;
  for (std::size_t q = 0; q < count; ++q) {
    const std::uint64_t b = bitsOf(v[q]);
    if (k == 0 || pal[last] != b) {
      int m = 0;
      while (m < k && pal[m] != b) ++m;
      if (m == k) {
        if (k == RollbackState::kPaletteSize) {
          palette.assign(pal, pal + k);
          palette.push_back(b);  // too many: the caller copies the field plainly
          return;
        }
        pal[k++] = b;
      }
      last = m;
    }
    if (code) code[q] = static_cast<std::uint8_t>(last);
  }
  palette.assign(pal, pal + k);
}

// paletteOf with codes, in parallel (issue 17: the serial passes of the rollback copy): the
// values in kChunks fixed chunks, each coded against its own palette (in order of first appearance
// within the chunk), then the chunks' palettes merged in chunk order, which gives the palette of
// the whole field in order of first appearance, and the codes renumbered where a chunk's order
// differs. The palette and codes are those of paletteOf whatever the thread count; with more
// than kPaletteSize values (in one chunk or in all) palette.size() > kPaletteSize and the codes
// are not to be used.
constexpr int kChunks = 64;
template <class T>
void paletteCodesParallel(const T* v, std::size_t count, std::vector<std::uint64_t>& palette,
                          std::uint8_t* code) {
  constexpr int K = RollbackState::kPaletteSize;
  std::uint64_t pal[kChunks][K];
  int size[kChunks];
  std::uint8_t map[kChunks][K];
#pragma omp parallel for schedule(static)
  for (int c = 0; c < kChunks; ++c) {
    const std::size_t q0 = count * static_cast<std::size_t>(c) / kChunks,
                      q1 = count * static_cast<std::size_t>(c + 1) / kChunks;
    std::uint64_t* pc = pal[c];
    int k = 0, last = 0;
    for (std::size_t q = q0; q < q1; ++q) {
      const std::uint64_t b = bitsOf(v[q]);
      if (k == 0 || pc[last] != b) {
        int m = 0;
        while (m < k && pc[m] != b) ++m;
        if (m == k) {
          if (k == K) {
            k = K + 1;  // too many in this chunk alone
            break;
          }
          pc[k++] = b;
        }
        last = m;
      }
      code[q] = static_cast<std::uint8_t>(last);
    }
    size[c] = k;
  }
  palette.clear();
  bool renumber = false;
  for (int c = 0; c < kChunks; ++c) {
    if (size[c] > K) {
      palette.assign(static_cast<std::size_t>(K) + 1, 0);  // too many: the caller copies plainly
      return;
    }
    for (int m = 0; m < size[c]; ++m) {
      std::size_t g = 0;
      while (g < palette.size() && palette[g] != pal[c][m]) ++g;
      if (g == palette.size()) {
        if (static_cast<int>(g) == K) {
          palette.push_back(pal[c][m]);
          return;
        }
        palette.push_back(pal[c][m]);
      }
      map[c][m] = static_cast<std::uint8_t>(g);
      renumber = renumber || static_cast<int>(g) != m;
    }
  }
  if (!renumber) return;
#pragma omp parallel for schedule(static)
  for (int c = 0; c < kChunks; ++c) {
    bool same = true;
    for (int m = 0; m < size[c]; ++m) same = same && map[c][m] == m;
    if (same) continue;
    const std::size_t q0 = count * static_cast<std::size_t>(c) / kChunks,
                      q1 = count * static_cast<std::size_t>(c + 1) / kChunks;
    for (std::size_t q = q0; q < q1; ++q) code[q] = map[c][code[q]];
  }
}

// paletteCodesParallel, or paletteOf in one pass on the calling thread below kParallelMin
// values (the same palette and codes: both in order of first appearance).
template <class T>
void paletteCodes(const T* v, std::size_t count, std::vector<std::uint64_t>& palette,
                  std::uint8_t* code) {
  if (count < kParallelMin) paletteOf(v, count, palette, code);
  else paletteCodesParallel(v, count, palette, code);
}

// Whether the palette and codes of the last capture still give values [0, count) bit for bit
// (the steady state of mass, phase, material, motion between reorders): then they are the palette
// and codes a new coding would give (order of first appearance of the same values), and the field
// needs no new coding. A branch-free pass (~5 instructions per value against ~18 for the coding).
template <class T>
bool paletteHolds(const T* v, std::size_t count, const std::vector<std::uint64_t>& palette,
                  const std::uint8_t* code) {
  const std::uint64_t* pal = palette.data();
  const std::size_t size = palette.size();
  if (size == 0) return false;
  unsigned bad = 0;
  if (count < kParallelMin) {
    for (std::size_t q = 0; q < count; ++q)
      bad |= static_cast<unsigned>((code[q] >= size) | (pal[code[q] < size ? code[q] : 0] != bitsOf(v[q])));
  } else {
#pragma omp parallel for schedule(static) reduction(| : bad)
    for (std::size_t q = 0; q < count; ++q)
      bad |= static_cast<unsigned>((code[q] >= size) | (pal[code[q] < size ? code[q] : 0] != bitsOf(v[q])));
  }
  return bad == 0;
}

// Whether field f may be copied in single precision: flagged so, and for the positions, no
// solid or rigid particle in the store (their positions define strain and body shape).
bool singleAllowed(const ParticleStore& st, int f, bool everyField) {
  const FieldSpec& spec = st.fields()[static_cast<size_t>(f)];
  if (everyField || spec.type != FieldType::Real || (spec.flags & kFieldRollbackSingle) == 0)
    return false;
  if (f != st.position().id) return true;
  const std::int32_t* phase = st.data(st.phase());
  const Index n = st.realCount();
  int body = 0;
  if (static_cast<std::size_t>(n) < kParallelMin) {
#pragma omp simd reduction(| : body)
    for (Index i = 0; i < n; ++i) body |= (phase[i] == kPhaseSolid) | (phase[i] == kPhaseRigid);
    return body == 0;
  }
#pragma omp parallel for simd schedule(static) reduction(| : body)
  for (Index i = 0; i < n; ++i) body |= (phase[i] == kPhaseSolid) | (phase[i] == kPhaseRigid);
  return body == 0;
}

template <int NC>
void toSingle(const double* p, std::size_t count, const double* off, float* q) {
  const std::size_t rows = count / NC;
  if (count < kParallelMin) {
    for (std::size_t i = 0; i < rows; ++i)
      for (int a = 0; a < NC; ++a) {
        const std::size_t m = i * NC + static_cast<std::size_t>(a);
        q[m] = static_cast<float>(p[m] - off[a]);
      }
    return;
  }
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < rows; ++i)
    for (int a = 0; a < NC; ++a) {
      const std::size_t m = i * NC + static_cast<std::size_t>(a);
      q[m] = static_cast<float>(p[m] - off[a]);
    }
}
// A plain copy in parallel (the Double and Int columns; resize allocates only when the column
// grows or was released).
template <class T>
void copyParallel(const T* p, std::size_t count, std::vector<T>& out) {
  out.resize(count);
  T* o = out.data();
  if (count < kParallelMin) {
    if (count > 0) std::memcpy(o, p, count * sizeof(T));
    return;
  }
#pragma omp parallel for simd schedule(static)
  for (std::size_t k = 0; k < count; ++k) o[k] = p[k];
}

}  // namespace

RollbackState::Storage RollbackState::storageOf(const ParticleStore& st, int f, bool everyField) {
  const FieldSpec& spec = st.fields()[static_cast<size_t>(f)];
  if (!everyField && !copies(spec.flags)) return Storage::None;
  const bool real = spec.type == FieldType::Real;
  if (singleAllowed(st, f, everyField)) return Storage::Single;
  const std::size_t count =
      static_cast<std::size_t>(st.realCount()) * static_cast<std::size_t>(spec.components);
  std::vector<std::uint64_t> palette;
  if (real) paletteOf(st.data(RealField{f}), count, palette, nullptr);
  else paletteOf(st.data(IntField{f}), count, palette, nullptr);
  if (count > 0 && static_cast<int>(palette.size()) <= kPaletteSize) return Storage::Palette;
  return real ? Storage::Double : Storage::Int;
}

std::size_t RollbackState::bytesPerParticle(const ParticleStore& st) {
  std::size_t b = 0;
  for (size_t f = 0; f < st.fields().size(); ++f) {
    const std::size_t c = static_cast<std::size_t>(st.fields()[f].components);
    switch (storageOf(st, static_cast<int>(f))) {
      case Storage::Double: b += c * sizeof(double); break;
      case Storage::Single: b += c * sizeof(float); break;
      case Storage::Int: b += c * sizeof(std::int32_t); break;
      case Storage::Palette: b += c; break;
      case Storage::None: break;
    }
  }
  return b;
}

void RollbackState::Column::releaseAllBut(Storage keep) {
  if (keep != Storage::Double) std::vector<double>().swap(real);
  if (keep != Storage::Single) {
    std::vector<float>().swap(single);
    std::vector<double>().swap(offset);
  }
  if (keep != Storage::Int) std::vector<std::int32_t>().swap(ints);
  if (keep != Storage::Palette) {
    std::vector<std::uint8_t>().swap(code);
    std::vector<std::uint64_t>().swap(palette);
  }
}

std::size_t RollbackState::Column::bytes() const {
  return (real.capacity() + offset.capacity()) * sizeof(double) + single.capacity() * sizeof(float) +
         ints.capacity() * sizeof(std::int32_t) + code.capacity() +
         palette.capacity() * sizeof(std::uint64_t);
}

std::size_t RollbackState::bytes() const {
  std::size_t b = 0;
  for (const Column& c : columns_) b += c.bytes();
  return b;
}

bool RollbackState::capture(const Simulation& sim) {
  if (valid_ && sim.step != step_ && (sim.step - step_) % every_ != 0) return false;
  const ParticleStore& st = sim.store;
  const auto& specs = st.fields();
  if (columns_.size() != specs.size()) columns_.resize(specs.size());
  n_ = st.realCount();
  for (size_t f = 0; f < specs.size(); ++f) {
    Column& col = columns_[f];
    const bool real = specs[f].type == FieldType::Real;
    const size_t count = static_cast<size_t>(n_) * static_cast<size_t>(specs[f].components);
    Storage want = Storage::None;
    if (everyField_ || copies(specs[f].flags))
      want = singleAllowed(st, static_cast<int>(f), everyField_)
                 ? Storage::Single
                 : Storage::Palette;  // tried first; falls back to Double / Int below
    // A field copied plainly at the last capture stays so (both are exact; no count of its
    // distinct values per step: the mass of a hydrostatic start, the ids).
    if (want == Storage::Palette &&
        (real ? col.storage == Storage::Double : col.storage == Storage::Int))
      want = col.storage;
    if (want == Storage::Palette) {
      // Lossless: a byte per value when the field holds at most kPaletteSize distinct values.
      const RealField rf{static_cast<int>(f)};
      const IntField inf{static_cast<int>(f)};
      // A field that was a palette at the last capture (the steady state: mass, phase, material,
      // motion) is coded in one pass that counts as it writes; any other is first only counted
      // (the count stops at the 17th distinct value: a few values for a field of many), then
      // coded in a second pass if it fits.
      const bool onePass = col.storage == Storage::Palette;
      if (onePass && col.code.size() == count && count > 0 &&
          (real ? paletteHolds(st.data(rf), count, col.palette, col.code.data())
                : paletteHolds(st.data(inf), count, col.palette, col.code.data()))) {
        // unchanged since the last capture: its palette and codes stand
      } else if (onePass) {
        col.code.resize(count);
        if (real) paletteCodes(st.data(rf), count, col.palette, col.code.data());
        else paletteCodes(st.data(inf), count, col.palette, col.code.data());
      } else if (real) {
        paletteOf(st.data(rf), count, col.palette, nullptr);
      } else {
        paletteOf(st.data(inf), count, col.palette, nullptr);
      }
      if (count == 0 || static_cast<int>(col.palette.size()) > kPaletteSize) {
        want = real ? Storage::Double : Storage::Int;
      } else if (!onePass) {
        col.code.resize(count);
        if (real) paletteOf(st.data(rf), count, col.palette, col.code.data());
        else paletteOf(st.data(inf), count, col.palette, col.code.data());
      }
    }
    // A field registered since the last capture may need no copy, and a field that changed its
    // storage keeps no stale buffer.
    col.releaseAllBut(want);
    col.storage = want;
    if (want == Storage::Double) {
      copyParallel(st.data(RealField{static_cast<int>(f)}), count, col.real);
    } else if (want == Storage::Int) {
      copyParallel(st.data(IntField{static_cast<int>(f)}), count, col.ints);
    } else if (want == Storage::Single) {
      // Per component: the float of the value minus the middle of its range when the range
      // excludes 0 (positions in a box, density around rho0: the rounding is then 2^-24 of the
      // half range, not of the value), else of the value itself.
      const double* p = st.data(RealField{static_cast<int>(f)});
      const int nc = specs[f].components;
      col.offset.assign(static_cast<size_t>(nc), 0.0);
      col.single.resize(count);
      float* q = col.single.data();
      const double* off = col.offset.data();
      // Components 1-3 (every flagged field) with the count known to the compiler: one pass for
      // the ranges and one for the conversion (issue 17: 0f22d92's strided passes were ~4 % of a
      // case B step); any other count per component, as before.
      if (n_ > 0 && nc >= 1 && nc <= 3) {
        double lo[3], hi[3];
        if (nc == 1) componentRange<1>(p, count, lo, hi);
        else if (nc == 2) componentRange<2>(p, count, lo, hi);
        else componentRange<3>(p, count, lo, hi);
        for (int a = 0; a < nc; ++a)
          if ((lo[a] > 0.0 || hi[a] < 0.0) && std::isfinite(lo[a]) && std::isfinite(hi[a]))
            col.offset[static_cast<size_t>(a)] = 0.5 * (lo[a] + hi[a]);
        if (nc == 1) toSingle<1>(p, count, off, q);
        else if (nc == 2) toSingle<2>(p, count, off, q);
        else toSingle<3>(p, count, off, q);
      } else {
        for (int a = 0; a < nc && n_ > 0; ++a) {
          double lo = p[a], hi = p[a];
          for (size_t k = static_cast<size_t>(a); k < count; k += static_cast<size_t>(nc)) {
            lo = std::min(lo, p[k]);
            hi = std::max(hi, p[k]);
          }
          if ((lo > 0.0 || hi < 0.0) && std::isfinite(lo) && std::isfinite(hi))
            col.offset[static_cast<size_t>(a)] = 0.5 * (lo + hi);
        }
        for (size_t i = 0; i < static_cast<size_t>(n_); ++i)
          for (int a = 0; a < nc; ++a) {
            const size_t k = i * static_cast<size_t>(nc) + static_cast<size_t>(a);
            q[k] = static_cast<float>(p[k] - off[a]);
          }
      }
    }
  }
  time_ = sim.time;
  dt_ = sim.dt;
  step_ = sim.step;
  modules_.resize(sim.modules.size());
  for (size_t k = 0; k < sim.modules.size(); ++k) modules_[k] = sim.modules[k]->saveState();
  valid_ = true;
  return true;
}

bool RollbackState::restore(Simulation& sim) const {
  if (!valid_) return false;
  ParticleStore& st = sim.store;
  st.clearGhosts();
  if (st.realCount() != n_) return false;
  const auto& specs = st.fields();
  // Fields that are not copied (constant ones, scratch) follow their particles: put the store
  // back into the captured particle order first (a cell reorder may have happened since), by
  // the ids of the copy. Allocates, but only once, on the way out of a failed run.
  const size_t idField = static_cast<size_t>(st.id().id);
  std::vector<std::int32_t> capturedIds;
  if (idField < columns_.size()) {
    const Column& c = columns_[idField];
    if (c.storage == Storage::Int) {
      capturedIds = c.ints;
    } else if (c.storage == Storage::Palette) {
      capturedIds.resize(c.code.size());
      for (size_t k = 0; k < c.code.size(); ++k)
        capturedIds[k] = static_cast<std::int32_t>(static_cast<std::uint32_t>(c.palette[c.code[k]]));
    }
  }
  if (capturedIds.size() == static_cast<size_t>(n_)) {
    const std::int32_t* ids = st.data(st.id());
    bool same = true;
    for (Index i = 0; i < n_ && same; ++i) same = ids[i] == capturedIds[static_cast<size_t>(i)];
    if (!same) {
      std::unordered_map<std::int32_t, Index> where;
      where.reserve(static_cast<size_t>(n_));
      for (Index i = 0; i < n_; ++i) where[ids[i]] = i;
      std::vector<Index> newToOld(static_cast<size_t>(n_));
      for (Index k = 0; k < n_; ++k) {
        auto it = where.find(capturedIds[static_cast<size_t>(k)]);
        if (it == where.end()) return false;  // a particle was removed and another added
        newToOld[static_cast<size_t>(k)] = it->second;
      }
      st.permute(newToOld);
    }
  }
  for (size_t f = 0; f < specs.size() && f < columns_.size(); ++f) {
    const Column& col = columns_[f];
    const size_t count = static_cast<size_t>(n_) * static_cast<size_t>(specs[f].components);
    const bool real = specs[f].type == FieldType::Real;
    switch (col.storage) {
      case Storage::None:
        break;
      case Storage::Double:
        if (real && col.real.size() == count)
          std::memcpy(st.data(RealField{static_cast<int>(f)}), col.real.data(),
                      count * sizeof(double));
        break;
      case Storage::Int:
        if (!real && col.ints.size() == count)
          std::memcpy(st.data(IntField{static_cast<int>(f)}), col.ints.data(),
                      count * sizeof(std::int32_t));
        break;
      case Storage::Single:
        if (real && col.single.size() == count) {
          double* p = st.data(RealField{static_cast<int>(f)});
          const int nc = specs[f].components;
          for (size_t i = 0; i < static_cast<size_t>(n_); ++i)
            for (int a = 0; a < nc; ++a) {
              const size_t k = i * static_cast<size_t>(nc) + static_cast<size_t>(a);
              p[k] = col.offset[static_cast<size_t>(a)] + static_cast<double>(col.single[k]);
            }
        }
        break;
      case Storage::Palette:
        if (col.code.size() != count) break;
        if (real) {
          double* p = st.data(RealField{static_cast<int>(f)});
          for (size_t k = 0; k < count; ++k) p[k] = doubleOf(col.palette[col.code[k]]);
        } else {
          std::int32_t* p = st.data(IntField{static_cast<int>(f)});
          for (size_t k = 0; k < count; ++k)
            p[k] = static_cast<std::int32_t>(static_cast<std::uint32_t>(col.palette[col.code[k]]));
        }
        break;
    }
  }
  sim.time = time_;
  sim.dt = dt_;
  sim.step = step_;
  for (size_t k = 0; k < sim.modules.size() && k < modules_.size(); ++k)
    if (!modules_[k].empty()) sim.modules[k]->restoreState(modules_[k]);
  return true;
}

}  // namespace poresph
