// Rigid bodies made of particles: thesis Appendix A (A.4-A.18). See rigid_module.hpp and
// docs/rigid.md.
#include "physics/rigid/rigid_module.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include "libcore/consistent_load.hpp"
#include "libcore/contact_repulsion.hpp"
#include "libcore/fluid_pair_terms.hpp"
#include "libcore/phases.hpp"
#include "libcore/simulation.hpp"
#include "libcore/time_schedule.hpp"

namespace poresph {

using rigid::M3;
using rigid::V3;

namespace {

std::string fmtNum(double v) {
  std::ostringstream o;
  o << std::setprecision(6) << v;
  return o.str();
}

/// x_a - y_a by the minimal image along a periodic axis a.
double wrapDelta(double d, const Domain& dom, int a) {
  if (dom.periodic[static_cast<size_t>(a)]) {
    const double L = dom.length(a);
    d -= L * std::round(d / L);
  }
  return d;
}

/// Union-find with path halving.
struct UnionFind {
  std::vector<Index> parent;
  explicit UnionFind(Index n) : parent(static_cast<size_t>(n)) {
    std::iota(parent.begin(), parent.end(), Index{0});
  }
  Index find(Index a) {
    while (parent[static_cast<size_t>(a)] != a) {
      parent[static_cast<size_t>(a)] = parent[static_cast<size_t>(parent[static_cast<size_t>(a)])];
      a = parent[static_cast<size_t>(a)];
    }
    return a;
  }
  void unite(Index a, Index b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[static_cast<size_t>(std::max(a, b))] = std::min(a, b);
  }
};

}  // namespace

// ---------------------------------------------------------------------------------------------
// configuration
// ---------------------------------------------------------------------------------------------
void RigidModule::configure(Simulation& sim, const std::vector<const Material*>& materials,
                            const ParameterSet* section) {
  dim_ = sim.dimension();
  const int d = dim_;
  mats_.clear();
  slot_.assign(sim.materials.size(), -1);
  for (const Material* m : materials) {
    const ParameterSet& p = m->parameters;
    RigidMaterial r;
    r.id = m->id;
    r.name = m->name;
    r.where = p.where("model");
    r.density = m->density > 0.0 ? m->density : p.real("density", Range::positive());
    const double theta = p.real("contact_angle", 90.0, Range::closed(0.0, 180.0));
    r.contactModulus = p.real("contact_modulus", 0.0, Range::nonNegative());
    r.fixed = p.boolean("fixed", false);
    if (p.has("translate")) {
      const std::vector<double> t = p.reals("translate", static_cast<size_t>(d));
      for (int a = 0; a < d; ++a) {
        if (t[static_cast<size_t>(a)] != 0.0 && t[static_cast<size_t>(a)] != 1.0)
          p.fail("translate", "must list 0 (locked) or 1 (free) for each axis");
        r.translate[static_cast<size_t>(a)] = t[static_cast<size_t>(a)];
      }
    }
    r.rotate = p.boolean("rotate", true);
    r.damping = p.real("damping", 0.0, Range::nonNegative());
    if (p.has("bonded")) {
      const std::string b = p.choice("bonded", "false", {"false", "true", "slip"});
      r.bonded = b != "false";
      r.bondSlip = b == "slip";
    }
    if (p.has("angular_velocity")) {
      if (d == 1) p.fail("angular_velocity", "a 1D body does not rotate");
      const std::vector<double> w = p.reals("angular_velocity", d == 2 ? 1u : 3u);
      if (d == 2)
        r.angularVelocity[2] = w[0];
      else
        for (int a = 0; a < 3; ++a) r.angularVelocity[static_cast<size_t>(a)] = w[static_cast<size_t>(a)];
    }
    if (p.has("plate")) {
      const ParameterSet pl = p.section("plate");
      r.plate = true;
      const std::vector<double> dir = pl.reals("direction", static_cast<size_t>(d));
      double norm = 0.0;
      for (double c : dir) norm += c * c;
      norm = std::sqrt(norm);
      if (!(norm > 0.0)) pl.fail("direction", "must be a non-zero vector");
      for (int a = 0; a < d; ++a)
        r.plateDirection[static_cast<size_t>(a)] = dir[static_cast<size_t>(a)] / norm;
      r.plateStress = pl.real("stress", Range::any());
      r.plateArea = pl.real("area", Range::positive());
      r.plateRampTime = pl.real("ramp_time", 0.0, Range::nonNegative());
      pl.finish();
      if (r.fixed) p.fail("plate", "a plate moves to carry its load: it cannot also be fixed");
    }
    if (r.bondSlip && !r.plate) {
      p.fail("bonded", "'slip' (bonded along the normal only) needs a plate: its direction is the "
                       "normal; use true for a body bonded in every direction");
      r.rotate = false;
    }
    if (d == 1) r.rotate = false;
    p.finish();
    Material& mat = sim.materials[static_cast<size_t>(m->id)];
    mat.phase = kPhaseRigid;
    mat.density = r.density;
    mat.wettingCos = std::cos(theta * 3.14159265358979323846 / 180.0);  // Eq. 1.10
    slot_[static_cast<size_t>(m->id)] = static_cast<int>(mats_.size());
    mats_.push_back(r);
  }
  gravity_ = {0, 0, 0};
  // Extrapolated (Adami) by default: with p_b extrapolated to the body particle's own depth the
  // pair sum of (p_a + p_b) grad W over a flat face is p(face) x area for a linear pressure, so
  // the buoyancy is exact; the mirror model (p_b = p_a) weights the deeper fluid particles and
  // over-estimates it by ~rho g dx per unit area (a neutrally buoyant body rises). docs/rigid.md
  fluidModel_ = BoundaryModel::Extrapolated;
  fluidModelSet_ = false;
  if (section) {
    if (section->has("gravity")) {
      const std::vector<double> g = section->reals("gravity", static_cast<size_t>(d));
      for (int a = 0; a < d; ++a) gravity_[static_cast<size_t>(a)] = g[static_cast<size_t>(a)];
    }
    fluidModelSet_ = section->has("fluid_rigid");
    fluidModel_ = section->choice("fluid_rigid", "extrapolated", {"mirror", "extrapolated"}) ==
                          "extrapolated"
                      ? BoundaryModel::Extrapolated
                      : BoundaryModel::Mirror;
    section->finish();
  }
  ParticleStore& st = sim.store;
  body_ = st.addInt("body", 1, kFieldDefault, "rigid");
  offset_ = st.addReal("body_offset", d, kFieldCheckpoint, "rigid");
  surface_ = st.addInt("body_surface", 1, kFieldCheckpoint | kFieldConstant, "rigid");
  // Bonded rigid-solid interfaces only where a material asks for them.
  bonds_ = std::any_of(mats_.begin(), mats_.end(), [](const RigidMaterial& r) { return r.bonded; });
  if (bonds_) {
    // copied to ghosts: the rigid side of a pair checks its (possibly ghost) solid neighbour's bond
    bondBody_ = st.addInt("bond_body", 1, kFieldCheckpoint | kFieldToGhosts, "rigid");
    bondAnchor_ = st.addReal("bond_anchor", d, kFieldCheckpoint, "rigid");
  }
  plateSlots_ = 0;
  if (std::any_of(mats_.begin(), mats_.end(), [](const RigidMaterial& r) { return r.bondSlip; })) {
    plateSlots_ = 2 * d;  // a particle within two supports of every face of a thin sample
    plateBond_ = st.addInt("plate_bond", plateSlots_, kFieldCheckpoint | kFieldToGhosts, "rigid");
    plateWeight_ = st.addReal("plate_bond_weight", plateSlots_, kFieldCheckpoint, "rigid");
    plateOrigin_ = st.addReal("plate_bond_origin", d, kFieldCheckpoint, "rigid");
  }
}

// ---------------------------------------------------------------------------------------------
// surface particles (App. A.2): a body particle is on the surface when a lattice site within one
// kernel support of it holds no particle of its body. Interior particles can only have
// neighbours of their own body (which exert no force), so the pair loop skips them.
// ---------------------------------------------------------------------------------------------
void RigidModule::findSurface(Simulation& sim) {
  ParticleStore& st = sim.store;
  const int d = dim_;
  const Index n = st.realCount();
  const double* x = st.data(st.position());
  const std::int32_t* body = st.data(body_);
  std::int32_t* surf = st.data(surface_);
  const double dx = sim.spacing;
  const Domain& dom = sim.domain;
  std::array<long long, 3> cells{1, 1, 1};
  for (int a = 0; a < d; ++a)
    cells[static_cast<size_t>(a)] = std::max<long long>(1, std::llround(dom.length(a) / dx));
  auto cellOf = [&](Index i) {
    std::array<long long, 3> c{0, 0, 0};
    for (int a = 0; a < d; ++a)
      c[static_cast<size_t>(a)] =
          std::llround((x[i * d + a] - dom.lo[static_cast<size_t>(a)]) / dx - 0.5);
    return c;
  };
  auto key = [](const std::array<long long, 3>& c) {
    return static_cast<unsigned long long>(c[0] & 0x1FFFFF) |
           (static_cast<unsigned long long>(c[1] & 0x1FFFFF) << 21) |
           (static_cast<unsigned long long>(c[2] & 0x1FFFFF) << 42);
  };
  std::unordered_map<unsigned long long, std::int32_t> site;
  for (Index i = 0; i < n; ++i)
    if (body[i] >= 0) site[key(cellOf(i))] = body[i];
  const double reach = sim.kernel.support() / dx;
  const int span = static_cast<int>(std::ceil(reach));
  for (Index i = 0; i < n; ++i) {
    surf[i] = 0;
    if (body[i] < 0) continue;
    const std::array<long long, 3> c = cellOf(i);
    bool onSurface = false;
    for (int ox = -span; ox <= span && !onSurface; ++ox)
      for (int oy = (d > 1 ? -span : 0); oy <= (d > 1 ? span : 0) && !onSurface; ++oy)
        for (int oz = (d > 2 ? -span : 0); oz <= (d > 2 ? span : 0) && !onSurface; ++oz) {
          if (ox * ox + oy * oy + oz * oz > reach * reach) continue;
          std::array<long long, 3> q{c[0] + ox, c[1] + oy, c[2] + oz};
          for (int a = 0; a < d; ++a)
            if (dom.periodic[static_cast<size_t>(a)]) {
              const long long m = cells[static_cast<size_t>(a)];
              q[static_cast<size_t>(a)] = ((q[static_cast<size_t>(a)] % m) + m) % m;
            }
          const auto it = site.find(key(q));
          if (it == site.end() || it->second != body[i]) onSurface = true;
        }
    surf[i] = onSurface ? 1 : 0;
  }
}

Index RigidModule::surfaceParticles(const Simulation& sim) const {
  const std::int32_t* surf = sim.store.data(surface_);
  Index count = 0;
  for (Index i = 0; i < sim.store.realCount(); ++i) count += surf[i];
  return count;
}

// ---------------------------------------------------------------------------------------------
// bonded interfaces: the first layer of solid particles around a bonded body
// ---------------------------------------------------------------------------------------------
void RigidModule::initialiseBonds(Simulation& sim) {
  ParticleStore& st = sim.store;
  const int d = dim_;
  const Index n = st.realCount();
  const double* x = st.data(st.position());
  const std::int32_t* ph = st.data(st.phase());
  const std::int32_t* body = st.data(body_);
  std::int32_t* bb = st.data(bondBody_);
  double* anchor = st.data(bondAnchor_);
  const double dx = sim.spacing;
  const Domain& dom = sim.domain;
  // Cells of side dx holding the particles of bonded bodies.
  auto cellOf = [&](const double* p) {
    std::array<long long, 3> c{0, 0, 0};
    for (int a = 0; a < d; ++a)
      c[static_cast<size_t>(a)] =
          static_cast<long long>(std::floor((p[a] - dom.lo[static_cast<size_t>(a)]) / dx));
    return c;
  };
  auto key = [](const std::array<long long, 3>& c) {
    return static_cast<unsigned long long>(c[0] & 0x1FFFFF) |
           (static_cast<unsigned long long>(c[1] & 0x1FFFFF) << 21) |
           (static_cast<unsigned long long>(c[2] & 0x1FFFFF) << 42);
  };
  std::unordered_multimap<unsigned long long, Index> cells;
  for (Index j = 0; j < n; ++j)
    if (body[j] >= 0) {
      const RigidMaterial* rm = materialOf(bodies_[static_cast<size_t>(body[j])].material);
      if (rm->bonded && !rm->bondSlip) cells.emplace(key(cellOf(x + j * d)), j);  // slip: PlateBond
    }
  const double reach = 1.5 * dx;  // first layer, concave staircase corners included
  std::vector<rigid::M3> R(bodies_.size());
  for (size_t b = 0; b < bodies_.size(); ++b) R[b] = bodies_[b].state.R();
  maxBondModulus_ = 0.0;
  for (Index i = 0; i < n; ++i) {
    bb[i] = -1;
    for (int a = 0; a < d; ++a) anchor[i * d + a] = 0.0;
    if (ph[i] != kPhaseSolid) continue;
    const std::array<long long, 3> c = cellOf(x + i * d);
    double best = reach * reach;
    Index nearest = -1;
    const int span = 2;
    for (int ox = -span; ox <= span; ++ox)
      for (int oy = (d > 1 ? -span : 0); oy <= (d > 1 ? span : 0); ++oy)
        for (int oz = (d > 2 ? -span : 0); oz <= (d > 2 ? span : 0); ++oz) {
          const auto range = cells.equal_range(key({c[0] + ox, c[1] + oy, c[2] + oz}));
          for (auto it = range.first; it != range.second; ++it) {
            const Index j = it->second;
            double r2 = 0.0;
            for (int a = 0; a < d; ++a) r2 += (x[i * d + a] - x[j * d + a]) * (x[i * d + a] - x[j * d + a]);
            if (r2 < best) {
              best = r2;
              nearest = j;
            }
          }
        }
    if (nearest < 0) continue;
    const int b = body[nearest];
    const RigidBody& B = bodies_[static_cast<size_t>(b)];
    bb[i] = b;
    V3 r = V3::Zero();
    for (int a = 0; a < d; ++a) r[a] = wrapDelta(x[i * d + a] - B.state.X[a], dom, a);
    const V3 rb = R[static_cast<size_t>(b)].transpose() * r;
    for (int a = 0; a < d; ++a) anchor[i * d + a] = rb[a];
    const double k = std::max(materialOf(B.material)->contactModulus,
                              solidModulus_[static_cast<size_t>(st.data(st.material())[i])]);
    maxBondModulus_ = std::max(maxBondModulus_, k);
  }
  rot_.assign(bodies_.size(), rigid::M3::Identity());
  place_.assign(bodies_.size(), V3::Zero());
  bondPartial_.assign(static_cast<size_t>(std::max(1, omp_get_max_threads())) * bodies_.size() * 12,
                      0.0);
}

rigid::V3 RigidModule::bondForceOn(const Simulation& sim, Index i) const {
  V3 out = V3::Zero();
  if (!bonds_ || sim.store.data(bondBody_)[i] < 0) return out;
  dispatchDimension(dim_, [&](auto dc) {
    constexpr int D = decltype(dc)::value;
    Vec<D> dvec;
    const Vec<D> f = bondForce<D>(sim, i, sim.store.data(sim.store.position()),
                                  sim.store.data(sim.store.material()), dvec);
    for (int a = 0; a < D; ++a) out[a] = f[a];
  });
  return out;
}

template <int D>
void RigidModule::bodyPlacement(const Simulation& sim) {
  const ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const double* x = st.data(st.position());
  const double* m = st.data(st.mass());
  const std::int32_t* body = st.data(body_);
  const double* off = st.data(offset_);
  const Domain& dom = sim.domain;
  const size_t nb = bodies_.size();
  const int threads = std::max(1, omp_get_max_threads());
  if (bondPartial_.size() < static_cast<size_t>(threads) * nb * 12)
    bondPartial_.assign(static_cast<size_t>(threads) * nb * 12, 0.0);
  std::fill(bondPartial_.begin(), bondPartial_.end(), 0.0);
  double* part = bondPartial_.data();
#pragma omp parallel num_threads(threads)
  {
    double* mine = part + static_cast<size_t>(omp_get_thread_num()) * nb * 12;
#pragma omp for schedule(static)
    for (Index i = 0; i < n; ++i) {
      const int b = body[i];
      if (b < 0) continue;
      const V3& X = bodies_[static_cast<size_t>(b)].state.X;
      double* s = mine + static_cast<size_t>(b) * 12;
      for (int a = 0; a < D; ++a) {
        double d = x[i * D + a] - X[a];
        if (dom.periodic[static_cast<size_t>(a)]) {
          const double L = dom.length(a);
          d -= L * std::round(d / L);
        }
        s[a] += m[i] * d;
        for (int c = 0; c < D; ++c) s[3 + 3 * a + c] += m[i] * d * off[i * D + c];
      }
    }
  }
  for (size_t b = 0; b < nb; ++b) {
    const RigidBody& B = bodies_[b];
    V3 mr = V3::Zero();
    rigid::M3 A = rigid::M3::Zero();
    for (int t = 0; t < threads; ++t) {
      const double* s = part + (static_cast<size_t>(t) * nb + b) * 12;
      for (int a = 0; a < 3; ++a) mr[a] += s[a];
      for (int a = 0; a < 9; ++a) A(a / 3, a % 3) += s[3 + a];
    }
    const V3 shift = mr / B.state.mass;
    // sum m (x - Xc) r_b^T = sum m (x - X) r_b^T - shift (sum m r_b)^T, and sum m r_b = 0
    place_[b] = B.state.X + shift;
    if (!materialOf(B.material)->rotate || D == 1) {
      rot_[b] = B.state.R();
      continue;
    }
    if (D == 2) {
      const double c = A(0, 0) + A(1, 1), sn = A(1, 0) - A(0, 1), r = std::hypot(c, sn);
      rot_[b] = rigid::M3::Identity();
      if (r > 0.0) {
        rot_[b](0, 0) = c / r;
        rot_[b](0, 1) = -sn / r;
        rot_[b](1, 0) = sn / r;
        rot_[b](1, 1) = c / r;
      }
    } else {
      Eigen::JacobiSVD<rigid::M3> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
      rigid::M3 Dg = rigid::M3::Identity();
      if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) Dg(2, 2) = -1.0;
      rot_[b] = svd.matrixU() * Dg * svd.matrixV().transpose();
    }
  }
}

template <int D>
Vec<D> RigidModule::bondForce(const Simulation& sim, Index i, const double* x,
                              const std::int32_t* mt, Vec<D>& dvec) const {
  const ParticleStore& st = sim.store;
  const int b = st.data(bondBody_)[i];
  const RigidBody& B = bodies_[static_cast<size_t>(b)];
  const double* anchor = st.data(bondAnchor_);
  V3 rb = V3::Zero();
  for (int a = 0; a < D; ++a) rb[a] = anchor[i * D + a];
  const V3 r = rot_[static_cast<size_t>(b)] * rb;
  const V3& Xc = place_[static_cast<size_t>(b)];
  const Domain& dom = sim.domain;
  for (int a = 0; a < D; ++a) {
    double dd = x[i * D + a] - Xc[a] - r[a];
    if (dom.periodic[static_cast<size_t>(a)]) {
      const double L = dom.length(a);
      dd -= L * std::round(dd / L);
    }
    dvec[a] = dd;
  }
  // Stiffness 2 k dx^(D-2): the half layer (dx / 2 thick, area dx^(D-1)) between the particle
  // and the interface, of modulus k = max(body's contact_modulus, the solid's rho0 c^2, A.17);
  // the same per-pair stiffness as the linearised A.18 repulsion of equal masses, times two.
  const double k = std::max(materialOf(B.material)->contactModulus,
                            solidModulus_[static_cast<size_t>(mt[i])]);
  double area = 1.0;
  for (int c = 2; c < D; ++c) area *= sim.spacing;
  if (D == 1) area = 1.0 / sim.spacing;
  return -(2.0 * k * area) * dvec;
}

// ---------------------------------------------------------------------------------------------
// `bonded: slip` plates: one bond per plate to the consistent-load-weighted mean of the solid
// within two supports of its face (docs/rigid.md "Plate confinement")
// ---------------------------------------------------------------------------------------------
template <int D>
void RigidModule::initialisePlateBonds(Simulation& sim) {
  ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const double* x = st.data(st.position());
  const double* m = st.data(st.mass());
  const std::int32_t* ph = st.data(st.phase());
  const std::int32_t* mt = st.data(st.material());
  const std::int32_t* body = st.data(body_);
  std::int32_t* slot = st.data(plateBond_);
  double* weight = st.data(plateWeight_);
  double* origin = st.data(plateOrigin_);
  const int S = plateSlots_;
  for (Index i = 0; i < n; ++i) {
    for (int q = 0; q < S; ++q) {
      slot[i * S + q] = -1;
      weight[i * S + q] = 0.0;
    }
    for (int a = 0; a < D; ++a) origin[i * D + a] = x[i * D + a];
  }
  // Consistent nodal load of a uniform unit stress over the solid's reference configuration
  // (Eq. 2.76, mixed-corrected gradients 2.63b; libcore/consistent_load.hpp).
  std::vector<Index> solid;
  std::vector<double> X, V;
  for (Index i = 0; i < n; ++i) {
    if (ph[i] != kPhaseSolid) continue;
    solid.push_back(i);
    for (int a = 0; a < D; ++a) X.push_back(x[i * D + a]);
    V.push_back(m[i] / sim.materials[static_cast<size_t>(mt[i])].density);
  }
  const Index ns = static_cast<Index>(solid.size());
  const std::vector<double> load = consistentLoadVectors<D>(sim.kernel, sim.domain, X.data(), V.data(), ns);
  // The solid particles within two supports of the plate's plane (its innermost particle row,
  // n . x = max over the plate) and, across it, of the plate's extent carry the plate's s_a:
  // beyond two supports of a surface s_a is zero (a particle's family and its neighbours' families
  // are complete). The plane, not the plate's particles: along the edges and corners of a sample
  // the missing lattice sites are neither plate's, and the particles they leave s_a on lie up to
  // two supports from the plane but further from the plate's particles.
  const double reach = 2.0 * sim.kernel.support();
  const Domain& dom = sim.domain;
  std::vector<std::vector<std::pair<Index, double>>> plateMembers;  // (particle, n . s_a)
  for (size_t b = 0; b < bodies_.size(); ++b) {
    const RigidMaterial& rm = *materialOf(bodies_[b].material);
    if (!rm.bondSlip) continue;
    PlateBond P;
    P.body = static_cast<int>(b);
    for (int a = 0; a < D; ++a) P.n[a] = rm.plateDirection[static_cast<size_t>(a)];
    // plane and lateral extent (bounding box of (1 - n n) x over the plate's particles)
    const V3 X0 = bodies_[b].state.X;
    double plane = -std::numeric_limits<double>::infinity();
    V3 lo = V3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (Index j = 0; j < n; ++j) {
      if (body[j] != static_cast<int>(b)) continue;
      V3 r = V3::Zero();
      for (int a = 0; a < D; ++a) r[a] = wrapDelta(x[j * D + a] - X0[a], dom, a);
      plane = std::max(plane, P.n.dot(r));
      const V3 lat = r - P.n.dot(r) * P.n;
      lo = lo.cwiseMin(lat);
      hi = hi.cwiseMax(lat);
    }
    std::vector<std::pair<Index, double>> members;  // (particle, n . s_a)
    double total = 0.0, kmax = rm.contactModulus;
    for (Index k = 0; k < ns; ++k) {
      const Index i = solid[static_cast<size_t>(k)];
      V3 r = V3::Zero();
      for (int a = 0; a < D; ++a) r[a] = wrapDelta(x[i * D + a] - X0[a], dom, a);
      const double depth = P.n.dot(r) - plane;
      if (!(depth > 0.0 && depth < reach)) continue;
      const V3 lat = r - P.n.dot(r) * P.n;
      bool inside = true;
      for (int a = 0; a < D; ++a)
        inside = inside && lat[a] > lo[a] - reach && lat[a] < hi[a] + reach;
      if (!inside) continue;
      double ns_a = 0.0;
      for (int a = 0; a < D; ++a) ns_a += P.n[a] * load[static_cast<size_t>(k) * D + a];
      members.emplace_back(i, ns_a);
      total += ns_a;
      kmax = std::max(kmax, solidModulus_[static_cast<size_t>(mt[i])]);
    }
    P.loadArea = total;
    P.particles = static_cast<Index>(members.size());
    // The per-particle bonds of the face summed: 2 k dx^(D-2) per particle of area dx^(D-1)
    // (the half layer between the face row and the plate, A.17).
    P.stiffness = 2.0 * kmax * rm.plateArea / sim.spacing;
    maxBondModulus_ = std::max(maxBondModulus_, kmax);
    plateBonds_.push_back(P);
    plateMembers.push_back(std::move(members));
  }
  // Opposite plates closer than four supports: their consistent loads would mix in s_a.
  for (size_t p = 0; p < plateBonds_.size(); ++p) {
    const RigidMaterial& rm = *materialOf(bodies_[static_cast<size_t>(plateBonds_[p].body)].material);
    for (const auto& [i, c] : plateMembers[p]) {
      (void)c;
      for (int q = 0; q < S && slot[i * S + q] >= 0; ++q)
        if (plateBonds_[static_cast<size_t>(slot[i * S + q])].n.dot(plateBonds_[p].n) < -0.5)
          throw InputError("rigid: `bonded: slip` plate material '" + rm.name + "' (" + rm.where +
                           ") and the plate opposite it are less than four kernel supports (" +
                           fmtNum(2.0 * reach) + " m) apart: their consistent loads overlap in "
                           "the solid between them; use a thicker sample or a smaller spacing");
      int q = 0;
      while (q < S && slot[i * S + q] >= 0) ++q;
      if (q == S)
        throw InputError("rigid: a solid particle lies within two kernel supports of more than " +
                         std::to_string(S) + " `bonded: slip` plates (plate material '" + rm.name +
                         "', " + rm.where + "): the sample is too thin for its plates");
      slot[i * S + q] = static_cast<int>(p);
    }
  }
  for (size_t p = 0; p < plateBonds_.size(); ++p) {
    PlateBond& P = plateBonds_[p];
    const RigidMaterial& rm = *materialOf(bodies_[static_cast<size_t>(P.body)].material);
    if (plateMembers[p].empty() || !(std::abs(P.loadArea) > 0.0))
      throw InputError("rigid: plate body " + std::to_string(P.body) + " of material '" + rm.name +
                       "' has `bonded: slip` but no elastic solid surface within two kernel "
                       "supports (" + fmtNum(reach) + " m) of it; place the plate against the "
                       "solid or drop `bonded` in " + rm.where);
    for (const auto& [i, c] : plateMembers[p])
      for (int q = 0; q < S; ++q)
        if (slot[i * S + q] == static_cast<int>(p)) weight[i * S + q] = c / P.loadArea;
    P.loadArea = std::abs(P.loadArea);
  }
  platePartial_.assign(static_cast<size_t>(std::max(1, omp_get_max_threads())) * plateBonds_.size() * 3,
                       0.0);
}

template <int D>
void RigidModule::plateBondDeltas(const Simulation& sim) {
  const ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const double* x = st.data(st.position());
  const std::int32_t* slot = st.data(plateBond_);
  const double* weight = st.data(plateWeight_);
  const double* origin = st.data(plateOrigin_);
  const int S = plateSlots_;
  const size_t np = plateBonds_.size();
  // Damage-aware weights (docs/rigid.md "Damage-aware weights"). c_a = n . s_a / sum n . s_a is
  // the consistent load (Eq. 2.76) of the UNDAMAGED solid: the share of a uniform traction each
  // tied particle takes through its reference corrected gradients. A particle of damage D_a
  // carries, in the continuum-damage reading of D (effective stress sigma / (1 - D), the damaged
  // fraction of its section carries none; g(D) = 1 - D of the Rankine/Mohr-Coulomb law of the
  // main job, Eq. 4.18a), the fraction (1 - D_a) of that share; fixed c_a would hand a fully
  // damaged particle the load of a sound one and crush it. Hence
  //   c~_a = c_a (1 - D_a) / sum_b c_b (1 - D_b),
  // in the mean displacement and in the force K delta c~_a n alike (the bond's energy
  // K delta^2 / 2 at frozen weights), sum_a c~_a = 1 (action = reaction, -K delta n on the plate).
  // No damage among a plate's particles: c~_a = c_a exactly (the undamaged case unchanged bit for
  // bit). All of them fully damaged (sum c_b (1 - D_b) <= 1e-12): c_a kept (nothing sound left to
  // prefer). Known limit (docs/rigid.md): the volumetric split (4.17) keeps the bulk stiffness in
  // compression, which 1 - D ignores; where most of a face is damaged the renormalisation puts
  // the plate's load on its few sound particles (1 / sum c_b (1 - D_b) times their share).
  const double* dmg = st.has("damage") ? st.data(st.real("damage")) : nullptr;
  // Two parallel passes over the particles (the tied ones carry slot >= 0), each thread summing
  // into its own row of platePartial_ (sized at initialise: no allocation in the time loop);
  // rows summed serially per plate afterwards. Pass 1: sum c_b (1 - D_b), whether any tied
  // particle is damaged, the fixed-weight share of D > 0.5 particles. Pass 2 (needs pass 1's
  // sums for the weights): the weighted mean normal displacement and the damaged share.
  constexpr size_t K = 3;  // partial sums per plate and pass
  const int threads = std::max(1, omp_get_max_threads());
  if (platePartial_.size() < static_cast<size_t>(threads) * np * K)  // more threads than at set-up
    platePartial_.assign(static_cast<size_t>(threads) * np * K, 0.0);
  double* part = platePartial_.data();
  // One pass: perTied(i, row) adds particle i's terms into its thread's row (K sums per plate),
  // then perPlate(p, sums) receives plate p's K totals over the threads.
  auto pass = [&](auto&& perTied, auto&& perPlate) {
    std::fill(platePartial_.begin(), platePartial_.end(), 0.0);
#pragma omp parallel num_threads(threads)
    {
      double* row = part + static_cast<size_t>(omp_get_thread_num()) * np * K;
#pragma omp for schedule(static)
      for (Index i = 0; i < n; ++i)
        if (slot[i * S] >= 0) perTied(i, row);
    }
    for (size_t p = 0; p < np; ++p) {
      double sums[K] = {0.0, 0.0, 0.0};
      for (int t = 0; t < threads; ++t)
        for (size_t k = 0; k < K; ++k) sums[k] += part[(static_cast<size_t>(t) * np + p) * K + k];
      perPlate(p, sums);
    }
  };
  pass(
      [&](Index i, double* row) {  // sums: damaged tied particles, sum c_b (1 - D_b), fixed share
        const double Da = dmg ? std::clamp(dmg[i], 0.0, 1.0) : 0.0;
        for (int q = 0; q < S && slot[i * S + q] >= 0; ++q) {
          double* s = row + static_cast<size_t>(slot[i * S + q]) * K;
          if (Da > 0.0) s[0] += 1.0;
          s[1] += weight[i * S + q] * plateSoundFactor(Da);
          if (Da > 0.5) s[2] += weight[i * S + q];
        }
      },
      [&](size_t p, const double* sums) {
        PlateBond& P = plateBonds_[p];
        P.degraded = sums[0] > 0.0 && sums[1] > 1e-12;
        P.sound = P.degraded ? sums[1] : 1.0;
        P.damagedShareFixed = sums[2];
      });
  pass(
      [&](Index i, double* row) {  // sums: weighted mean normal displacement, damaged share
        Vec<D> u;
        for (int a = 0; a < D; ++a) u[a] = wrapDelta(x[i * D + a] - origin[i * D + a], sim.domain, a);
        for (int q = 0; q < S && slot[i * S + q] >= 0; ++q) {
          const PlateBond& P = plateBonds_[static_cast<size_t>(slot[i * S + q])];
          double* s = row + static_cast<size_t>(slot[i * S + q]) * K;
          double un = 0.0;
          for (int a = 0; a < D; ++a) un += P.n[a] * u[a];
          const double c = plateWeightOf(P, weight[i * S + q], dmg ? dmg[i] : 0.0);
          s[0] += c * un;
          if (dmg && dmg[i] > 0.5) s[1] += c;
        }
      },
      [&](size_t p, const double* sums) {
        PlateBond& P = plateBonds_[p];
        P.damagedShare = sums[1];
        const RigidBody& B = bodies_[static_cast<size_t>(P.body)];
        P.delta = P.n.dot(place_[static_cast<size_t>(P.body)] - B.X0) - sums[0];
      });
}

const RigidMaterial* RigidModule::materialOf(int id) const {
  if (id < 0 || id >= static_cast<int>(slot_.size()) || slot_[static_cast<size_t>(id)] < 0)
    return nullptr;
  return &mats_[static_cast<size_t>(slot_[static_cast<size_t>(id)])];
}

// ---------------------------------------------------------------------------------------------
// bodies: connected clusters of the lattice, mass, centre of mass (A.7), inertia (A.8)
// ---------------------------------------------------------------------------------------------
BodyPartition RigidModule::partition(const Simulation& sim) const {
  const ParticleStore& st = sim.store;
  const int d = sim.dimension();
  const Index n = st.realCount();
  const double* x = st.data(st.position());
  const double* m = st.data(st.mass());
  const std::int32_t* mt = st.data(st.material());
  const double dx = sim.spacing;
  BodyPartition out;
  out.bodyOf.assign(static_cast<size_t>(n), -1);
  std::vector<Index> rigidIdx;
  for (Index i = 0; i < n; ++i)
    if (materialOf(mt[i])) rigidIdx.push_back(i);
  const Index nr = static_cast<Index>(rigidIdx.size());
  if (nr == 0) return out;
  // Lattice cell of each rigid particle; neighbours along the axes at one spacing are linked
  // when they have the same material (6-connected clusters in 3D, 4-connected in 2D).
  auto key = [&](const std::array<long long, 3>& c) {
    return static_cast<unsigned long long>(c[0] & 0x1FFFFF) |
           (static_cast<unsigned long long>(c[1] & 0x1FFFFF) << 21) |
           (static_cast<unsigned long long>(c[2] & 0x1FFFFF) << 42);
  };
  std::vector<std::array<long long, 3>> cell(static_cast<size_t>(nr));
  std::unordered_map<unsigned long long, Index> at;
  at.reserve(static_cast<size_t>(2 * nr));
  for (Index k = 0; k < nr; ++k) {
    const Index i = rigidIdx[static_cast<size_t>(k)];
    std::array<long long, 3> c{0, 0, 0};
    for (int a = 0; a < d; ++a)
      c[static_cast<size_t>(a)] =
          std::llround((x[i * d + a] - sim.domain.lo[static_cast<size_t>(a)]) / dx - 0.5);
    cell[static_cast<size_t>(k)] = c;
    at[key(c)] = k;
  }
  UnionFind uf(nr);
  for (Index k = 0; k < nr; ++k) {
    const Index i = rigidIdx[static_cast<size_t>(k)];
    for (int a = 0; a < d; ++a) {
      std::array<long long, 3> c = cell[static_cast<size_t>(k)];
      c[static_cast<size_t>(a)] += 1;
      if (sim.domain.periodic[static_cast<size_t>(a)] &&
          c[static_cast<size_t>(a)] == std::llround(sim.domain.length(a) / dx))
        c[static_cast<size_t>(a)] = 0;  // a body across a periodic face is one body
      auto it = at.find(key(c));
      if (it == at.end()) continue;
      const Index j = rigidIdx[static_cast<size_t>(it->second)];
      if (mt[j] != mt[i]) continue;
      double r2 = 0.0;
      for (int b = 0; b < d; ++b) {
        const double db = wrapDelta(x[i * d + b] - x[j * d + b], sim.domain, b);
        r2 += db * db;
      }
      if (r2 < 1.5 * 1.5 * dx * dx) uf.unite(k, it->second);
    }
  }
  std::unordered_map<Index, int> bodyOfRoot;
  for (Index k = 0; k < nr; ++k) {
    const Index root = uf.find(k);
    auto it = bodyOfRoot.find(root);
    int b;
    if (it == bodyOfRoot.end()) {
      b = static_cast<int>(out.bodies.size());
      bodyOfRoot[root] = b;
      out.bodies.emplace_back();
      out.bodies.back().material = mt[rigidIdx[static_cast<size_t>(k)]];
      out.bodies.back().state.dimension = d;
    } else {
      b = it->second;
    }
    out.bodyOf[static_cast<size_t>(rigidIdx[static_cast<size_t>(k)])] = b;
  }
  // Mass and centre of mass (A.7). Along a periodic axis a body may cross the face: its
  // particles are unwrapped by cutting the axis at the body's largest run of empty lattice
  // layers (cyclically), so the centre is right for any body shorter than the period - the
  // minimal image against one particle would fold a body longer than half the period onto
  // itself. The inertia (A.8) and the body frame then use the minimal image against this centre,
  // exact for a body shorter than the period.
  const size_t nb = out.bodies.size();
  std::vector<std::array<long long, 3>> cutOf(nb, std::array<long long, 3>{0, 0, 0});
  for (int a = 0; a < d; ++a) {
    if (!sim.domain.periodic[static_cast<size_t>(a)]) continue;
    const long long N = std::llround(sim.domain.length(a) / dx);
    std::vector<std::vector<char>> occupied(nb);
    for (Index k = 0; k < nr; ++k) {
      const int b = out.bodyOf[static_cast<size_t>(rigidIdx[static_cast<size_t>(k)])];
      auto& o = occupied[static_cast<size_t>(b)];
      if (o.empty()) o.assign(static_cast<size_t>(N), 0);
      const long long c = ((cell[static_cast<size_t>(k)][static_cast<size_t>(a)] % N) + N) % N;
      o[static_cast<size_t>(c)] = 1;
    }
    for (size_t b = 0; b < nb; ++b) {
      const auto& o = occupied[b];
      // the layer after the longest cyclic run of empty layers starts the body along axis a
      long long bestLen = -1, bestStart = 0, run = 0;
      for (long long t = 0; t < 2 * N; ++t) {
        if (!o[static_cast<size_t>(t % N)]) {
          ++run;
          continue;
        }
        if (run > bestLen) {
          bestLen = run;
          bestStart = t % N;
        }
        run = 0;
      }
      cutOf[b][static_cast<size_t>(a)] = bestStart;
    }
  }
  for (Index k = 0; k < nr; ++k) {
    const Index i = rigidIdx[static_cast<size_t>(k)];
    const int b = out.bodyOf[static_cast<size_t>(i)];
    RigidBody& B = out.bodies[static_cast<size_t>(b)];
    V3 p = V3::Zero();
    for (int a = 0; a < d; ++a) {
      p[a] = x[i * d + a];
      if (!sim.domain.periodic[static_cast<size_t>(a)]) continue;
      const long long N = std::llround(sim.domain.length(a) / dx);
      const long long c = ((cell[static_cast<size_t>(k)][static_cast<size_t>(a)] % N) + N) % N;
      if (c < cutOf[static_cast<size_t>(b)][static_cast<size_t>(a)]) p[a] += sim.domain.length(a);
    }
    B.count += 1;
    B.state.mass += m[i];
    B.state.X += m[i] * p;
  }
  for (RigidBody& B : out.bodies) B.state.X /= B.state.mass;
  // Inertia tensor about the centre of mass (A.8).
  std::vector<M3> inertia(out.bodies.size(), M3::Zero());
  for (Index i = 0; i < n; ++i) {
    const int b = out.bodyOf[static_cast<size_t>(i)];
    if (b < 0) continue;
    V3 r = V3::Zero();
    for (int a = 0; a < d; ++a)
      r[a] = wrapDelta(x[i * d + a] - out.bodies[static_cast<size_t>(b)].state.X[a], sim.domain, a);
    inertia[static_cast<size_t>(b)] += m[i] * (r.squaredNorm() * M3::Identity() - r * r.transpose());
  }
  for (size_t b = 0; b < out.bodies.size(); ++b) {
    RigidBody& B = out.bodies[b];
    const RigidMaterial& rm = *materialOf(B.material);
    std::ostringstream where;
    where << "rigid: body " << b << " of material '" << rm.name << "' (" << B.count
          << " particle" << (B.count == 1 ? "" : "s") << ", centre of mass (";
    for (int a = 0; a < d; ++a) where << (a ? ", " : "") << fmtNum(B.state.X[a]);
    where << ") m)";
    if (B.count < 2 && !rm.fixed)
      throw InputError(where.str() + " has a single particle: a free body needs at least two "
                       "(its inertia would be zero); use a larger region or a smaller spacing, or "
                       "set fixed: true in " + rm.where);
    const M3& I = inertia[b];
    if (d == 3) {
      Eigen::SelfAdjointEigenSolver<M3> es(I);
      V3 ev = es.eigenvalues();
      M3 axes = es.eigenvectors();
      if (axes.determinant() < 0.0) axes.col(2) = -axes.col(2);
      const double scale = std::max(ev.maxCoeff(), B.state.mass * dx * dx);
      if (!rm.fixed && rm.rotate && !(ev.minCoeff() > 1e-9 * scale))
        throw InputError(where.str() + " has zero moment of inertia about an axis (its particles "
                         "lie on one line): its rotation about that axis is undefined; make it "
                         "thicker or set rotate: false in " + rm.where);
      B.state.Ib = ev.cwiseMax(1e-300);
      B.state.q = Eigen::Quaterniond(axes).normalized();
    } else if (d == 2) {
      if (!rm.fixed && rm.rotate && !(I(2, 2) > 0.0))
        throw InputError(where.str() + " has zero moment of inertia: set rotate: false in " +
                         rm.where);
      B.state.Ib = V3(I(0, 0), I(1, 1), std::max(I(2, 2), 1e-300));
      B.state.q = Eigen::Quaterniond::Identity();
    } else {
      B.state.Ib = V3::Ones();
    }
    B.X0 = B.state.X;
  }
  return out;
}

void RigidModule::initialise(Simulation& sim) {
  ParticleStore& st = sim.store;
  const int d = dim_;
  const Index n = st.realCount();
  BodyPartition part = partition(sim);
  bodies_ = std::move(part.bodies);
  std::int32_t* body = st.data(body_);
  double* off = st.data(offset_);
  std::int32_t* mo = st.data(sim.motion);
  const double* x = st.data(st.position());
  const double* v = st.data(st.velocity());
  const double* m = st.data(st.mass());
  // Fixed bodies: the material's key, or every particle of the body in a fixed region.
  std::vector<int> allFixed(bodies_.size(), 1);
  for (Index i = 0; i < n; ++i) {
    body[i] = part.bodyOf[static_cast<size_t>(i)];
    if (body[i] >= 0 && mo[i] != kMotionFixed) allFixed[static_cast<size_t>(body[i])] = 0;
  }
  // Initial velocity and angular momentum from the particles' velocities (their rigid part)
  // plus the material's angular velocity.
  std::vector<V3> P(bodies_.size(), V3::Zero()), Lsum(bodies_.size(), V3::Zero());
  for (Index i = 0; i < n; ++i) {
    if (body[i] < 0) continue;
    const RigidBody& B = bodies_[static_cast<size_t>(body[i])];
    V3 r = V3::Zero(), vi = V3::Zero();
    for (int a = 0; a < d; ++a) {
      r[a] = wrapDelta(x[i * d + a] - B.state.X[a], sim.domain, a);
      vi[a] = v[i * d + a];
    }
    P[static_cast<size_t>(body[i])] += m[i] * vi;
    Lsum[static_cast<size_t>(body[i])] += m[i] * r.cross(vi);
    // Body-frame offset.
    const V3 rb = B.state.R().transpose() * r;
    for (int a = 0; a < d; ++a) off[i * d + a] = rb[a];
  }
  for (size_t b = 0; b < bodies_.size(); ++b) {
    RigidBody& B = bodies_[b];
    const RigidMaterial& rm = *materialOf(B.material);
    const bool fixed = rm.fixed || allFixed[b];
    if (fixed) {
      B.state.V.setZero();
      B.state.L.setZero();
      continue;
    }
    B.state.V = P[b] / B.state.mass;
    const V3 w0(rm.angularVelocity[0], rm.angularVelocity[1], rm.angularVelocity[2]);
    B.state.L = Lsum[b] + B.state.inertiaWorld() * w0;
    if (d == 2) B.state.L.x() = B.state.L.y() = 0.0;
    if (!rm.rotate || d == 1) B.state.L.setZero();
    for (int a = 0; a < 3; ++a)
      if (rm.translate[static_cast<size_t>(a)] == 0.0) B.state.V[a] = 0.0;
    if (rm.plate) {
      const V3 dir(rm.plateDirection[0], rm.plateDirection[1], rm.plateDirection[2]);
      B.state.V = B.state.V.dot(dir) * dir;
    }
  }
  for (Index i = 0; i < n; ++i) {
    if (body[i] < 0) continue;
    const RigidBody& B = bodies_[static_cast<size_t>(body[i])];
    const RigidMaterial& rm = *materialOf(B.material);
    mo[i] = (rm.fixed || allFixed[static_cast<size_t>(body[i])]) ? kMotionFixed : kMotionFree;
  }
  dispatchDimension(d, [&](auto dc) { this->placeD<decltype(dc)::value>(sim, -1); });

  // Materials of the other side of the contacts (A.17): k_s = rho0 c^2 of the solids.
  solidModulus_.assign(sim.materials.size(), 0.0);
  for (const Material& mat : sim.materials)
    if (mat.phase == kPhaseSolid && mat.waveSpeed > 0.0 && mat.density > 0.0)
      solidModulus_[static_cast<size_t>(mat.id)] = mat.density * mat.waveSpeed * mat.waveSpeed;
  maxContactModulus_ = 0.0;
  minRigidDensity_ = std::numeric_limits<double>::infinity();
  for (const RigidMaterial& r : mats_) {
    maxContactModulus_ = std::max(maxContactModulus_, r.contactModulus);
    minRigidDensity_ = std::min(minRigidDensity_, r.density);
  }
  // The contact springs also act on the particles of elastic solids (rigid-solid pairs): the
  // lightest particle on either side sets the contact's time step.
  for (const Material& mat : sim.materials)
    if (mat.phase == kPhaseSolid && mat.density > 0.0)
      minRigidDensity_ = std::min(minRigidDensity_, mat.density);
  // Fluid-rigid pairs: the fluid module's extrapolated boundary state.
  fluidPairs_ = st.has("pressure") && st.has("wall_velocity");
  if (fluidPairs_) {
    pressure_ = st.real("pressure");
    wallVelocity_ = st.real("wall_velocity");
    viscousFactor_ = st.has("viscous_factor") ? st.real("viscous_factor") : RealField{};
    densityRate_ = st.has("density_rate") ? st.real("density_rate") : RealField{};
    // One boundary model for every moving boundary a fluid particle sees (docs/coupling.md,
    // "Pores opening onto a plate"). Where the fluid also meets elastic solids (the coupling
    // module is present: it owns fluid-solid), the plates and grains take the coupling's model
    // (default mirror) unless the scene sets `rigid: {fluid_rigid}`. The two models' continuity
    // terms differ by a factor 2 (mirror: the reflected relative velocity), so with mirror clay
    // and an extrapolated plate in one support, water moving along a one-voxel clay channel
    // towards the plate reads as an expansion (the clay above counted twice against the plate
    // below): its gauge pressure falls, the plate's extrapolated pressure follows it, the
    // tension pulls it further in, and it is sucked into the plate-clay contact (measured:
    // the 16^3 Ketton crop of the main job with such a channel stopped by the density check at
    // 2.08 ms; 4 ms, 1.6 % with one model).
    if (!fluidModelSet_ && sim.published.fluidSolidModel) fluidModel_ = *sim.published.fluidSolidModel;
  }
  findSurface(sim);
  {
    // A body with no particle within one support of its surface (it fills every lattice site of
    // a periodic domain) has no neighbour of another phase: nothing could ever act on it.
    std::vector<Index> surfaceCount(bodies_.size(), 0);
    const std::int32_t* surf = st.data(surface_);
    const std::int32_t* body = st.data(body_);
    for (Index i = 0; i < st.realCount(); ++i)
      if (body[i] >= 0 && surf[i]) ++surfaceCount[static_cast<size_t>(body[i])];
    for (size_t b = 0; b < bodies_.size(); ++b)
      if (surfaceCount[b] == 0) {
        const RigidMaterial& rm = *materialOf(bodies_[b].material);
        throw InputError("rigid: body " + std::to_string(b) + " of material '" + rm.name + "' (" +
                         std::to_string(bodies_[b].count) +
                         " particles) has no particle within one kernel support of its surface: "
                         "it fills the periodic domain, so no other particle can ever touch it; "
                         "leave room for another phase or drop the body (" + rm.where + ")");
      }
  }
  if (bonds_) initialiseBonds(sim);
  plateBonds_.clear();
  if (plateSlots_ > 0)
    dispatchDimension(d, [&](auto dc) { this->initialisePlateBonds<decltype(dc)::value>(sim); });
  threads_ = std::max(1, omp_get_max_threads());
  partial_.assign(static_cast<size_t>(threads_) * bodies_.size() * 9, 0.0);
}

std::string RigidModule::describe(const Simulation& sim) const {
  std::ostringstream o;
  BodyPartition part;
  try {
    part = partition(sim);
  } catch (const InputError& e) {
    return std::string("rigid bodies: ") + e.what() + "\n";
  }
  o << "rigid bodies: " << part.bodies.size() << "\n";
  const size_t shown = std::min<size_t>(part.bodies.size(), 20);
  for (size_t b = 0; b < shown; ++b) {
    const RigidBody& B = part.bodies[b];
    const RigidMaterial& rm = *materialOf(B.material);
    o << "  body " << b << " (" << rm.name << "): " << B.count << " particles, mass "
      << fmtNum(B.state.mass) << (dim_ == 3 ? " kg" : dim_ == 2 ? " kg/m" : " kg/m^2")
      << ", centre (";
    for (int a = 0; a < dim_; ++a) o << (a ? ", " : "") << fmtNum(B.state.X[a]);
    o << ") m, ";
    if (dim_ == 3)
      o << "principal inertia (" << fmtNum(B.state.Ib[0]) << ", " << fmtNum(B.state.Ib[1]) << ", "
        << fmtNum(B.state.Ib[2]) << ") kg m^2";
    else if (dim_ == 2)
      o << "inertia " << fmtNum(B.state.Ib[2]) << " kg m";
    o << (rm.fixed ? ", fixed" : rm.plate ? ", plate" : "") << "\n";
  }
  if (shown < part.bodies.size()) o << "  ... (" << part.bodies.size() - shown << " more)\n";
  return o.str();
}

// ---------------------------------------------------------------------------------------------
// placing particles: x = X + R r_body, v = V + omega x R r_body (A.14 with the exact rotation)
// ---------------------------------------------------------------------------------------------
template <int D>
void RigidModule::placeD(Simulation& sim, int onlyBody) {
  ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const std::int32_t* body = st.data(body_);
  const double* off = st.data(offset_);
  const std::int32_t* mo = st.data(sim.motion);
  double* x = st.data(st.position());
  double* v = st.data(st.velocity());
  const Domain& dom = sim.domain;
  // Per-body rotation and angular velocity, computed once.
  const size_t nb = bodies_.size();
  std::vector<M3> R(nb);
  std::vector<V3> W(nb);
  for (size_t b = 0; b < nb; ++b) {
    R[b] = bodies_[b].state.R();
    W[b] = bodies_[b].state.omega();
  }
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) {
    const int b = body[i];
    if (b < 0 || mo[i] == kMotionFixed || (onlyBody >= 0 && b != onlyBody)) continue;
    const rigid::BodyState& s = bodies_[static_cast<size_t>(b)].state;
    V3 rb = V3::Zero();
    for (int a = 0; a < D; ++a) rb[a] = off[i * D + a];
    const V3 r = R[static_cast<size_t>(b)] * rb;
    const V3 vel = s.V + W[static_cast<size_t>(b)].cross(r);
    for (int a = 0; a < D; ++a) {
      double p = s.X[a] + r[a];
      if (dom.periodic[static_cast<size_t>(a)]) {
        const double L = dom.length(a);
        p -= L * std::floor((p - dom.lo[static_cast<size_t>(a)]) / L);
      }
      x[i * D + a] = p;
      v[i * D + a] = vel[a];
    }
  }
}

void RigidModule::setBodyVelocity(Simulation& sim, size_t b, const V3& V, const V3& omega) {
  RigidBody& B = bodies_.at(b);
  B.state.V = V;
  B.state.L = B.state.inertiaWorld() * omega;
  if (dim_ == 2) B.state.L.x() = B.state.L.y() = 0.0;
  dispatchDimension(dim_, [&](auto dc) { this->placeD<decltype(dc)::value>(sim, static_cast<int>(b)); });
  B.started = false;
}

// ---------------------------------------------------------------------------------------------
// pair forces: fluid-rigid (moving wall), rigid-solid / rigid-rigid / rigid-wall (A.18)
// ---------------------------------------------------------------------------------------------
void RigidModule::interfaces(Simulation& sim) {
  dispatchDimension(dim_, [&](auto dc) { this->interfacesD<decltype(dc)::value>(sim); });
}

template <int D>
void RigidModule::interfacesD(Simulation& sim) {
  ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const auto& nl = sim.neighbours;
  const Kernel& W = sim.kernel;
  const double* x = st.data(st.position());
  const double* v = st.data(st.velocity());
  const double* m = st.data(st.mass());
  const double* rho = st.data(st.density());
  const std::int32_t* ph = st.data(st.phase());
  const std::int32_t* mt = st.data(st.material());
  const std::int32_t* mo = st.data(sim.motion);
  const std::int32_t* body = st.data(body_);
  double* acc = st.data(sim.acceleration);
  const std::vector<Material>& mats = sim.materials;
  const double dx = sim.spacing;
  const double* p = fluidPairs_ ? st.data(pressure_) : nullptr;
  const double* vw = fluidPairs_ ? st.data(wallVelocity_) : nullptr;
  const double* visc = viscousFactor_.valid() ? st.data(viscousFactor_) : nullptr;
  double* drho = densityRate_.valid() ? st.data(densityRate_) : nullptr;
  const FluidPairSettings settings = sim.fluidPairSettings;
  const BoundaryModel model = fluidModel_;
  const std::int32_t* bondBody = bonds_ ? st.data(bondBody_) : nullptr;
  const std::int32_t* surf = st.data(surface_);
  if (bonds_) bodyPlacement<D>(sim);
  const int S = plateSlots_;
  const std::int32_t* plateSlot = S > 0 ? st.data(plateBond_) : nullptr;
  const double* plateW = S > 0 ? st.data(plateWeight_) : nullptr;
  if (!plateBonds_.empty()) plateBondDeltas<D>(sim);
  const double* dmg = (S > 0 && st.has("damage")) ? st.data(st.real("damage")) : nullptr;
  // Solid particle j is tied to rigid body b (by its own bond or a plate's weighted bond): the
  // bond replaces the A.18 contact between them, on both sides of the pair.
  auto tiedTo = [&](Index j, int b) {
    if (bondBody && bondBody[j] == b) return true;
    if (plateSlot)
      for (int q = 0; q < S && plateSlot[j * S + q] >= 0; ++q)
        if (plateBonds_[static_cast<size_t>(plateSlot[j * S + q])].body == b) return true;
    return false;
  };

  auto isFluid = [&](Index i) {
    return ph[i] == kPhaseFluid && mats[static_cast<size_t>(mt[i])].fluid.valid();
  };
  // Force of rigid particle b on fluid particle a (m_a times the shared pair terms); both sides
  // call it with the fluid particle first, so the two evaluations are identical.
  const FluidBoundaryForce<D> fluidPair{x, v, m, rho, p, vw, visc,
                                      mt, mats.data(), &W, settings, model};
  // Contact modulus of a rigid particle i with neighbour j (A.17: the stiffer side).
  auto modulus = [&](Index i, Index j) {
    const RigidMaterial* ri = materialOf(mt[i]);
    double k = ri ? ri->contactModulus : 0.0;
    if (ph[j] == kPhaseSolid) k = std::max(k, solidModulus_[static_cast<size_t>(mt[j])]);
    if (ph[j] == kPhaseRigid) {
      const RigidMaterial* rj = materialOf(mt[j]);
      if (rj) k = std::max(k, rj->contactModulus);
    }
    return k;
  };

#pragma omp parallel for schedule(dynamic, 256)
  for (Index i = 0; i < n; ++i) {
    const std::int32_t phi = ph[i];
    if (phi == kPhaseWall) continue;
    if (phi == kPhaseFluid) {
      if (!fluidPairs_ || mo[i] == kMotionFixed || !isFluid(i)) continue;
      double divv = 0.0;
      const Vec<D> f = fluidPair.onFluid(i, nl, ph, kPhaseRigid, divv);
      for (int c = 0; c < D; ++c) acc[i * D + c] += f[c] / m[i];
      if (drho) drho[i] += rho[i] * divv;  // Eq. 5.1a over the rigid neighbours
    } else if (phi == kPhaseSolid) {
      if (mo[i] == kMotionFixed) continue;
      Vec<D> f = Vec<D>::Zero();
      const int bonded = bondBody ? bondBody[i] : -1;
      if (bonded >= 0) {
        Vec<D> dvec;
        f += bondForce<D>(sim, i, x, mt, dvec);
      }
      // plate bonds: K delta c~_a n of every plate the particle is tied to (damage-aware c~_a)
      for (int q = 0; plateSlot && q < S && plateSlot[i * S + q] >= 0; ++q) {
        const PlateBond& P = plateBonds_[static_cast<size_t>(plateSlot[i * S + q])];
        const double ca = plateWeightOf(P, plateW[i * S + q], dmg ? dmg[i] : 0.0);
        for (int c = 0; c < D; ++c) f[c] += P.stiffness * P.delta * ca * P.n[c];
      }
      for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
        const Index j = nl.index[static_cast<size_t>(k)];
        if (ph[j] != kPhaseRigid) continue;
        if (tiedTo(i, body[j])) continue;  // the bond replaces the contact with its body
        Vec<D> r;
        for (int c = 0; c < D; ++c) r[c] = x[i * D + c] - x[j * D + c];
        const double dist = r.norm();
        if (dist >= dx) continue;
        // the same expression as on the rigid side, with the roles exchanged: f_i = -f_j
        f += pairRepulsion<D>(r, dist, m[i], m[j], modulus(j, i), dx);
      }
      for (int c = 0; c < D; ++c) acc[i * D + c] += f[c] / m[i];
    } else if (phi == kPhaseRigid) {
      if (!surf[i]) continue;  // interior: only its own body within reach (A.2)
      Vec<D> f = Vec<D>::Zero();
      for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
        const Index j = nl.index[static_cast<size_t>(k)];
        const std::int32_t phj = ph[j];
        if (phj == kPhaseFluid) {
          if (!fluidPairs_ || !isFluid(j)) continue;
          double div = 0.0;
          f -= fluidPair.reaction(j, i, div);  // reaction of the force on the fluid particle j (p - p_b
                                              // with solid_gauge)
          continue;
        }
        if (phj == kPhaseRigid && body[j] == body[i]) continue;  // same body: no force
        if (phj == kPhaseSolid && tiedTo(j, body[i])) continue;  // bonded: as on the solid side
        Vec<D> r;
        for (int c = 0; c < D; ++c) r[c] = x[i * D + c] - x[j * D + c];
        const double dist = r.norm();
        if (dist >= dx) continue;
        f += pairRepulsion<D>(r, dist, m[i], m[j], modulus(i, j), dx);
      }
      for (int c = 0; c < D; ++c) acc[i * D + c] += f[c] / m[i];
    }
  }
}

// ---------------------------------------------------------------------------------------------
// constraints: force and torque of each body (A.9-A.10), constrained accelerations (A.11)
// ---------------------------------------------------------------------------------------------
void RigidModule::constrain(RigidBody& B, const V3& F, const V3& T, V3& acc, V3& torque) const {
  const RigidMaterial& rm = *materialOf(B.material);
  const double M = B.state.mass;
  acc.setZero();
  torque.setZero();
  if (rm.fixed) return;
  if (rm.plate) {
    const V3 dir(rm.plateDirection[0], rm.plateDirection[1], rm.plateDirection[2]);
    // Ramped like the solid's and the drainage module's loads (no step: no stress wave).
    const double ramp = linearRamp(time_, rm.plateRampTime);  // libcore/time_schedule.hpp
    const double load = rm.plateStress * rm.plateArea * ramp;
    acc = ((F.dot(dir) + load) / M - rm.damping * B.state.V.dot(dir)) * dir;
    return;
  }
  // Viscous damping of the body's motion (dynamic relaxation to a static state): -c V, -c L.
  for (int a = 0; a < 3; ++a)
    acc[a] = rm.translate[static_cast<size_t>(a)] * (F[a] / M - rm.damping * B.state.V[a]);
  if (rm.rotate) torque = T - rm.damping * B.state.L;
  if (dim_ == 2) torque.x() = torque.y() = 0.0;
}

void RigidModule::constraints(Simulation& sim) {
  if (bodies_.empty()) return;
  dispatchDimension(dim_, [&](auto dc) { this->constraintsD<decltype(dc)::value>(sim); });
}

template <int D>
void RigidModule::constraintsD(Simulation& sim) {
  ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const double* x = st.data(st.position());
  const double* m = st.data(st.mass());
  const std::int32_t* body = st.data(body_);
  const std::int32_t* mo = st.data(sim.motion);
  double* acc = st.data(sim.acceleration);
  const Domain& dom = sim.domain;
  const size_t nb = bodies_.size();
  const int threads = threads_;
  const std::int32_t* bondBody = bonds_ ? st.data(bondBody_) : nullptr;
  const std::int32_t* mt = st.data(st.material());
  // bonds: the placement the interfaces() stage found (the body has not moved since)
  std::fill(partial_.begin(), partial_.end(), 0.0);
  double* part = partial_.data();
  // Lever arm of particle i about the body's centre of mass at the start of the step (minimal
  // image across periodic faces); the reduction finds the current centre from it.
  auto lever = [&](Index i, const V3& X) {
    V3 r = V3::Zero();
    for (int a = 0; a < D; ++a) {
      double d = x[i * D + a] - X[a];
      if (dom.periodic[static_cast<size_t>(a)]) {
        const double L = dom.length(a);
        d -= L * std::round(d / L);
      }
      r[a] = d;
    }
    return r;
  };
#pragma omp parallel num_threads(threads)
  {
    double* mine = part + static_cast<size_t>(omp_get_thread_num()) * nb * 9;
#pragma omp for schedule(static)
    for (Index i = 0; i < n; ++i) {
      if (bondBody && bondBody[i] >= 0) {
        // reaction of a bond on its body, at the anchor point (A.6, action = reaction)
        const int bb = bondBody[i];
        Vec<D> dvec;
        const Vec<D> fs = bondForce<D>(sim, i, x, mt, dvec);
        V3 f = V3::Zero(), r = lever(i, bodies_[static_cast<size_t>(bb)].state.X);
        for (int a = 0; a < D; ++a) {
          f[a] = -fs[a];
          r[a] -= dvec[a];
        }
        const V3 t = r.cross(f);
        double* s = mine + static_cast<size_t>(bb) * 9;
        for (int a = 0; a < 3; ++a) {
          s[a] += f[a];
          s[6 + a] += t[a];
        }
      }
      const int b = body[i];
      if (b < 0) continue;
      const V3 r = lever(i, bodies_[static_cast<size_t>(b)].state.X);
      V3 f = V3::Zero();
      for (int a = 0; a < D; ++a) f[a] = m[i] * acc[i * D + a];  // A.10: m_s a_a
      const V3 t = r.cross(f);                                   // A.9
      double* s = mine + static_cast<size_t>(b) * 9;
      for (int a = 0; a < 3; ++a) {
        s[a] += f[a];
        s[3 + a] += m[i] * r[a];
        s[6 + a] += t[a];
      }
    }
  }
  std::vector<V3>& shift = shift_;
  shift.assign(nb, V3::Zero());
  for (size_t b = 0; b < nb; ++b) {
    RigidBody& B = bodies_[b];
    V3 F = V3::Zero(), mr = V3::Zero(), T = V3::Zero();
    for (int t = 0; t < threads; ++t) {
      const double* s = part + (static_cast<size_t>(t) * nb + b) * 9;
      for (int a = 0; a < 3; ++a) {
        F[a] += s[a];
        mr[a] += s[3 + a];
        T[a] += s[6 + a];
      }
    }
    const double M = B.state.mass;
    for (const PlateBond& P : plateBonds_)  // reaction of a plate's weighted bond: -K delta n
      if (P.body == static_cast<int>(b)) F -= P.stiffness * P.delta * P.n;
    shift[b] = mr / M;  // current centre of mass - X
    T -= shift[b].cross(F);  // torque about the current centre of mass
    for (int a = 0; a < D; ++a) F[a] += M * gravity_[static_cast<size_t>(a)];
    B.force = F;
    B.torque = T;
    time_ = sim.time;
    // The start-of-step acceleration of the kick in endOfStep is that of the evaluation before
    // the step's own one: the one whose accelerations the integrator's first kick gave every
    // other particle. Before the first step (a scene's set-up evaluation and the integrator's
    // priming one, both at t = 0) each evaluation passes its result on here, so the first kick
    // takes the priming one's (they differ where the fluid's wall pressure reads the body's
    // previous acceleration: measured, a one-time momentum jump of 2.4e-8 kg m/s per m in a
    // viscous fluid with 1000 moving grains with the set-up one, none with the priming one).
    // From the first step on endOfStep keeps the step's own (`started`, checkpointed), so the
    // evaluations of a restart at the same time do not replace it: a restarted run repeats the
    // uninterrupted one (tests DrainageRestart, Rigid.CheckpointRestartContinuesTheBodyExactly).
    if (!B.started) {
      B.accStart = B.acc;
      B.alphaTorqueStart = B.alphaTorque;
    }
    constrain(B, F, T, B.acc, B.alphaTorque);
  }
  // Rigid acceleration of each body particle: A + alpha x r + omega x (omega x r).
  std::vector<V3>& alpha = alpha_;
  std::vector<V3>& omega = omega_;
  alpha.assign(nb, V3::Zero());
  omega.assign(nb, V3::Zero());
  for (size_t b = 0; b < nb; ++b) {
    omega[b] = bodies_[b].state.omega();
    alpha[b] = bodies_[b].state.angularAcceleration(bodies_[b].alphaTorque);
    if (!materialOf(bodies_[b].material)->rotate) alpha[b].setZero();
  }
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) {
    const int b = body[i];
    if (b < 0) continue;
    if (mo[i] == kMotionFixed) {
      for (int a = 0; a < D; ++a) acc[i * D + a] = 0.0;
      continue;
    }
    const RigidBody& B = bodies_[static_cast<size_t>(b)];
    const V3 r = lever(i, B.state.X) - shift[static_cast<size_t>(b)];
    const V3& w = omega[static_cast<size_t>(b)];
    const V3 a = B.acc + alpha[static_cast<size_t>(b)].cross(r) + w.cross(w.cross(r));
    for (int c = 0; c < D; ++c) acc[i * D + c] = a[c];
  }
}

// ---------------------------------------------------------------------------------------------
// Newton-Euler step (kick-drift-kick) and placement of the particles
// ---------------------------------------------------------------------------------------------
void RigidModule::endOfStep(Simulation& sim, double dt) {
  if (bodies_.empty()) return;
  for (RigidBody& B : bodies_) {
    const RigidMaterial& rm = *materialOf(B.material);
    if (rm.fixed) continue;
    rigid::BodyState& s = B.state;
    // kick (forces at the start of the step: accStart, the evaluation before this step's, see
    // constraintsD), drift, kick (forces of the step's evaluation)
    s.V += 0.5 * dt * B.accStart;
    s.L += 0.5 * dt * B.alphaTorqueStart;
    s.X += dt * s.V;
    if (rm.rotate && dim_ > 1) s.rotateFree(dt);
    s.V += 0.5 * dt * B.acc;
    s.L += 0.5 * dt * B.alphaTorque;
    B.accStart = B.acc;  // the next step's start: this step's evaluation
    B.alphaTorqueStart = B.alphaTorque;
    B.started = true;
  }
  dispatchDimension(dim_, [&](auto dc) { this->placeD<decltype(dc)::value>(sim, -1); });
}

// ---------------------------------------------------------------------------------------------
// checkpoints and rollback: the body states in body order (initialise() rebuilds the same
// partition from the same scene before a checkpoint is read)
// ---------------------------------------------------------------------------------------------
namespace {
constexpr size_t kStatePerBody = 35;
void put(std::vector<double>& out, const V3& v) {
  for (int a = 0; a < 3; ++a) out.push_back(v[a]);
}
V3 take(const double*& p) {
  V3 v(p[0], p[1], p[2]);
  p += 3;
  return v;
}
}  // namespace

ModuleState RigidModule::saveState() const {
  std::vector<double> out;
  out.reserve(bodies_.size() * kStatePerBody);
  for (const RigidBody& b : bodies_) {
    put(out, b.state.X);
    put(out, b.state.V);
    out.push_back(b.state.q.w());
    out.push_back(b.state.q.x());
    out.push_back(b.state.q.y());
    out.push_back(b.state.q.z());
    put(out, b.state.L);
    put(out, b.X0);
    put(out, b.force);
    put(out, b.torque);
    put(out, b.accStart);
    put(out, b.alphaTorqueStart);
    put(out, b.acc);
    put(out, b.alphaTorque);
    out.push_back(b.started ? 1.0 : 0.0);
  }
  return {{"bodies", out}};
}

void RigidModule::restoreState(const ModuleState& state) {
  for (const auto& [name, values] : state) {
    if (name != "bodies") continue;
    if (values.size() != bodies_.size() * kStatePerBody)
      throw InputError("rigid: the saved state holds " +
                       std::to_string(values.size() / kStatePerBody) + " bodies, the scene has " +
                       std::to_string(bodies_.size()));
    const double* p = values.data();
    for (RigidBody& b : bodies_) {
      b.state.X = take(p);
      b.state.V = take(p);
      b.state.q = Eigen::Quaterniond(p[0], p[1], p[2], p[3]);
      p += 4;
      b.state.L = take(p);
      b.X0 = take(p);
      b.force = take(p);
      b.torque = take(p);
      b.accStart = take(p);
      b.alphaTorqueStart = take(p);
      b.acc = take(p);
      b.alphaTorque = take(p);
      b.started = *p++ != 0.0;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// time step and diagnostics
// ---------------------------------------------------------------------------------------------
double RigidModule::timeStepLimit(const Simulation& sim) const {
  double dt = std::numeric_limits<double>::infinity();
  if (bodies_.empty()) return dt;
  const double h = sim.kernel.h();
  // Eq. 2.49 over the body particles: 0.25 h / |v|_max, 0.25 sqrt(h / |a|_max).
  const ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const int d = dim_;
  const std::int32_t* body = st.data(body_);
  const double* v = st.data(st.velocity());
  const double* a = st.data(sim.acceleration);
  double v2 = 0.0, a2 = 0.0;
#pragma omp parallel for schedule(static) reduction(max : v2, a2)
  for (Index i = 0; i < n; ++i) {
    if (body[i] < 0) continue;
    double sv = 0.0, sa = 0.0;
    for (int c = 0; c < d; ++c) {
      sv += v[i * d + c] * v[i * d + c];
      sa += a[i * d + c] * a[i * d + c];
    }
    v2 = std::max(v2, sv);
    a2 = std::max(a2, sa);
  }
  if (v2 > 0.0) dt = std::min(dt, 0.25 * h / std::sqrt(v2));
  if (a2 > 0.0) dt = std::min(dt, 0.25 * std::sqrt(h / std::sqrt(a2)));
  // Contacts of stiffness k (A.17-A.18): the wave speed sqrt(k / rho) of the lightest particle
  // in a contact (rigid or elastic).
  if (maxContactModulus_ > 0.0)
    dt = std::min(dt, 0.25 * h / std::sqrt(maxContactModulus_ / minRigidDensity_));
  // Bonds: a solid particle of mass rho dx^D on a spring 2 k dx^(D-2) rings at
  // omega = sqrt(2 k / rho) / dx; omega dt <= 0.7 h / dx (~0.9), half the leapfrog limit of 2.
  if (maxBondModulus_ > 0.0)
    dt = std::min(dt, 0.7 * h / std::sqrt(2.0 * maxBondModulus_ / minRigidDensity_));
  return dt;
}

void RigidModule::diagnostics(const Simulation& sim,
                              std::vector<std::pair<std::string, double>>& columns) const {
  const char* axis[3] = {"x", "y", "z"};
  const int d = dim_;
  const bool each = bodies_.size() <= 8;
  for (size_t b = 0; b < bodies_.size(); ++b) {
    const RigidBody& B = bodies_[b];
    const RigidMaterial& rm = *materialOf(B.material);
    const std::string pre = "body" + std::to_string(b) + "_";
    if (rm.plate) {
      const V3 dir(rm.plateDirection[0], rm.plateDirection[1], rm.plateDirection[2]);
      columns.emplace_back("plate" + std::to_string(b) + "_displacement",
                           (B.state.X - B.X0).dot(dir));
      // force the plate receives from the scene along its direction (minus the load when static)
      columns.emplace_back("plate" + std::to_string(b) + "_force", B.force.dot(dir));
      continue;
    }
    if (!each) continue;
    for (int a = 0; a < d; ++a) columns.emplace_back(pre + axis[a], B.state.X[a]);
    for (int a = 0; a < d; ++a) columns.emplace_back(pre + "v" + axis[a], B.state.V[a]);
    const V3 w = B.state.omega();
    if (d == 2) columns.emplace_back(pre + "omega_z", w.z());
    if (d == 3)
      for (int a = 0; a < 3; ++a) columns.emplace_back(pre + "omega_" + axis[a], w[a]);
    for (int a = 0; a < d; ++a) columns.emplace_back(pre + "f" + axis[a], B.force[a]);
  }
}

PORESPH_REGISTER_MODULE(RigidModule, "rigid")

}  // namespace poresph
