#include "libcore/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace poresph {

std::uint8_t ImageGrid::memberAt(const double* x, int dim) const {
  std::size_t index = 0, stride = 1;
  for (int a = 0; a < 3; ++a) {
    const double u = a < dim ? (x[a] - origin[static_cast<size_t>(a)]) / voxel : 0.0;
    const long long i = static_cast<long long>(std::floor(u));
    if (i < 0 || i >= n[static_cast<size_t>(a)]) return kNoMember;
    index += static_cast<std::size_t>(i) * stride;
    stride *= static_cast<std::size_t>(n[static_cast<size_t>(a)]);
  }
  return member[index];
}

bool Region::contains(const double* x, int dim, double tol) const {
  if (shape == Shape::Image) return image && image->memberAt(x, dim) == imageMember;
  if (shape == Shape::Box) {
    for (int a = 0; a < dim; ++a)
      if (x[a] < lo[static_cast<size_t>(a)] - tol || x[a] > hi[static_cast<size_t>(a)] + tol)
        return false;
    return true;
  }
  double r2 = 0.0, s = 0.0;
  for (int a = 0; a < dim; ++a) {
    const double d = x[a] - centre[static_cast<size_t>(a)];
    r2 += d * d;
    s += d * axis[static_cast<size_t>(a)];
  }
  const double r = radius + tol;
  if (shape == Shape::Sphere) return r2 <= r * r;
  // Cylinder: within half its length along the axis, within its radius of the axis.
  if (std::fabs(s) > 0.5 * length + tol) return false;
  return r2 - s * s <= r * r;
}

bool Region::rowSpan(const double* x, int dim, double tol, double& x0, double& x1) const {
  if (shape == Shape::Box || shape == Shape::Image) {
    x0 = lo[0] - tol;
    x1 = hi[0] + tol;
    return true;
  }
  if (shape == Shape::Sphere) {
    double d2 = 0.0;
    for (int a = 1; a < dim; ++a) {
      const double d = x[a] - centre[static_cast<size_t>(a)];
      d2 += d * d;
    }
    const double R = radius + tol;
    const double rem = R * R - d2;
    if (rem < 0.0) return false;
    const double half = std::sqrt(rem);
    x0 = centre[0] - half;
    x1 = centre[0] + half;
    return true;
  }
  // Cylinder: on the line p(t) = (t, x1, x2), d(t) = d0 + t e_x with d0 = p(0) - centre; the
  // axial coordinate s(t) = d0.a + t a_x must stay within +-(L/2 + tol) (an interval of t, or
  // all or no t when a_x = 0), the squared distance from the axis
  // |d(t)|^2 - s(t)^2 = A t^2 + B t + C within (R + tol)^2 (A = 1 - a_x^2 >= 0).
  double d0[3] = {-centre[0], 0.0, 0.0};
  for (int a = 1; a < dim; ++a) d0[a] = x[a] - centre[static_cast<size_t>(a)];
  double s0 = 0.0, dd = 0.0;
  for (int a = 0; a < dim; ++a) {
    s0 += d0[a] * axis[static_cast<size_t>(a)];
    dd += d0[a] * d0[a];
  }
  const double ax = axis[0], halfL = 0.5 * length + tol, R = radius + tol;
  double lo0 = -std::numeric_limits<double>::infinity(), hi0 = std::numeric_limits<double>::infinity();
  if (ax != 0.0) {
    const double ta = (-halfL - s0) / ax, tb = (halfL - s0) / ax;
    lo0 = std::min(ta, tb);
    hi0 = std::max(ta, tb);
  } else if (std::fabs(s0) > halfL) {
    return false;
  }
  const double A = 1.0 - ax * ax, B = 2.0 * (d0[0] - s0 * ax), C = dd - s0 * s0 - R * R;
  if (A > 1e-12) {
    const double disc = B * B - 4.0 * A * C;
    if (disc < 0.0) return false;
    const double root = std::sqrt(disc);
    lo0 = std::max(lo0, (-B - root) / (2.0 * A));
    hi0 = std::min(hi0, (-B + root) / (2.0 * A));
  } else if (C > 0.0) {  // axis along x: the line is parallel to it, inside or outside
    return false;
  }
  if (!(lo0 <= hi0)) return false;
  x0 = lo0;
  x1 = hi0;
  return true;
}

void Region::bounds(int dim, std::array<double, 3>& blo, std::array<double, 3>& bhi) const {
  for (size_t a = 0; a < 3; ++a) {
    if (static_cast<int>(a) >= dim) {
      blo[a] = bhi[a] = 0.0;
    } else if (shape == Shape::Box || shape == Shape::Image) {
      blo[a] = lo[a];
      bhi[a] = hi[a];
    } else if (shape == Shape::Cylinder) {
      // Extent of a cylinder along e_a: L/2 |a_a| from the axis, R sqrt(1 - a_a^2) from the
      // radius (the largest component of a unit vector normal to the axis along e_a).
      const double c = std::min(1.0, std::fabs(axis[a]));
      const double e = 0.5 * length * c + radius * std::sqrt(1.0 - c * c);
      blo[a] = centre[a] - e;
      bhi[a] = centre[a] + e;
    } else {
      blo[a] = centre[a] - radius;
      bhi[a] = centre[a] + radius;
    }
  }
}

namespace {

// Index bound of the lattice: |i| <= 2^62, so that differences of indices fit in 64 bits.
constexpr double kMaxIndex = 4.6e18;
// Rows along x of the bounding lattice that the counting pass will visit.
constexpr double kMaxRows = 268435456.0;  // 2^28

std::string num(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

[[noreturn]] void tooLarge(double dx, const std::string& what) {
  throw LatticeTooLarge("spacing dx = " + num(dx) + " m " + what +
                        "; the spacing is too small for the geometry");
}

struct Run {
  long long a, b;  // sites [a, b] along x
  int owner;       // region index
};

/// The lattice of the regions: per-axis index ranges of the sites that may hold a particle.
struct Lattice {
  int dim = 3;
  double dx = 0.0, tol = 0.0;
  std::array<double, 3> origin{0.0, 0.0, 0.0};
  std::array<long long, 3> first{0, 0, 0}, last{0, 0, 0};
  bool empty = true;
  double site(int a, long long i) const {
    return origin[static_cast<size_t>(a)] + (static_cast<double>(i) + 0.5) * dx;
  }
};

/// ceil / floor of a lattice coordinate, refused when beyond 64-bit indices.
long long latticeIndex(double v, bool up, double dx, int axis) {
  const double f = up ? std::ceil(v) : std::floor(v);
  if (!(std::fabs(f) <= kMaxIndex))
    tooLarge(dx, std::string("puts a region bound about ") + num(std::fabs(v)) +
                     " spacings from domain.lo along axis " + "xyz"[axis] +
                     ", beyond 64-bit lattice indices");
  return static_cast<long long>(f);
}

/// Index range [i0, i1] of the sites between b0 and b1 (bounds of a region) along axis a.
void siteRange(const Lattice& lat, int a, double b0, double b1, long long& i0, long long& i1) {
  const double l = lat.origin[static_cast<size_t>(a)];
  i0 = latticeIndex((b0 - l) / lat.dx - 0.5 - 1e-9, true, lat.dx, a);
  i1 = latticeIndex((b1 - l) / lat.dx - 0.5 + 1e-9, false, lat.dx, a);
}

Lattice makeLattice(const std::vector<Region>& regions, const Domain& domain, double dx) {
  Lattice lat;
  lat.dim = domain.dimension;
  lat.dx = dx;
  lat.tol = 1e-9 * dx;
  lat.origin = domain.lo;
  if (!(dx > 0.0) || !std::isfinite(dx))
    throw InputError("lattice spacing must be positive and finite, got " + num(dx));
  const int dim = lat.dim;
  // Index range of the union of the (non-subtracting) regions, per axis. Site i sits at
  // lo + (i + 1/2) dx; a bound b contains sites with i in [ceil((b_lo-lo)/dx - 1/2), floor(...)].
  bool any = false;
  for (const Region& r : regions) {
    if (r.subtracts()) continue;
    std::array<double, 3> blo, bhi;
    r.bounds(dim, blo, bhi);
    for (int a = 0; a < dim; ++a) {
      const size_t s = static_cast<size_t>(a);
      long long i0 = 0, i1 = 0;
      siteRange(lat, a, blo[s], bhi[s], i0, i1);
      lat.first[s] = any ? std::min(lat.first[s], i0) : i0;
      lat.last[s] = any ? std::max(lat.last[s], i1) : i1;
    }
    any = true;
  }
  if (!any) return lat;

  // Periodic axes: only the sites of [lo, hi); the length must be a whole number of spacings.
  for (int a = 0; a < dim; ++a) {
    const size_t s = static_cast<size_t>(a);
    if (!domain.periodic[s]) continue;
    const double cells = domain.length(a) / dx;
    if (!(cells < kMaxIndex))
      tooLarge(dx, std::string("gives about ") + num(cells) + " spacings along the periodic axis " +
                       "xyz"[a] + ", beyond 64-bit lattice indices");
    const long long n = std::llround(cells);
    if (n < 1 || std::abs(cells - static_cast<double>(n)) > 1e-6 * std::max(1.0, cells)) {
      std::ostringstream m;
      m.precision(12);
      m << "the periodic length along axis " << "xyz"[a] << " (" << domain.length(a)
        << " m) is not a whole number of spacings dx = " << dx << " m (" << cells
        << " spacings); particles would overlap or leave a gap across the periodic boundary";
      throw InputError(m.str());
    }
    lat.first[s] = std::max(lat.first[s], 0LL);
    lat.last[s] = std::min(lat.last[s], n - 1);
  }
  lat.empty = false;
  for (int a = 0; a < dim; ++a)
    if (lat.last[static_cast<size_t>(a)] < lat.first[static_cast<size_t>(a)]) lat.empty = true;
  return lat;
}

/// Index ranges of each region clipped to the lattice (empty: r1 < r0 on some axis).
struct RegionRange {
  std::array<long long, 3> r0{0, 0, 0}, r1{0, 0, 0};
  bool empty = false;
};

std::vector<RegionRange> regionRanges(const std::vector<Region>& regions, const Lattice& lat) {
  std::vector<RegionRange> out(regions.size());
  for (size_t k = 0; k < regions.size(); ++k) {
    std::array<double, 3> blo, bhi;
    regions[k].bounds(lat.dim, blo, bhi);
    RegionRange& rr = out[k];
    for (int a = 0; a < lat.dim; ++a) {
      const size_t s = static_cast<size_t>(a);
      long long i0 = 0, i1 = 0;
      siteRange(lat, a, blo[s], bhi[s], i0, i1);
      rr.r0[s] = std::max(lat.first[s], i0);
      rr.r1[s] = std::min(lat.last[s], i1);
      if (rr.r1[s] < rr.r0[s]) rr.empty = true;
    }
  }
  return out;
}

/// Paints [a, b] with `owner` (-1: clears it) over the disjoint, sorted runs.
void paint(std::vector<Run>& runs, std::vector<Run>& scratch, long long a, long long b, int owner) {
  scratch.clear();
  for (const Run& r : runs) {
    if (r.b < a || r.a > b) {
      scratch.push_back(r);
      continue;
    }
    if (r.a < a) scratch.push_back({r.a, a - 1, r.owner});
    if (r.b > b) scratch.push_back({b + 1, r.b, r.owner});
  }
  if (owner >= 0) scratch.push_back({a, b, owner});
  std::sort(scratch.begin(), scratch.end(), [](const Run& p, const Run& q) { return p.a < q.a; });
  runs.swap(scratch);
}

/// An image group (regions k .. k + members - 1) in row (iy, iz): its box clears what earlier
/// regions put there, then each voxel of the row goes to the region of its member (none: empty).
/// x holds the row's site coordinates along y and z.
void imageRow(const std::vector<Region>& regions, size_t k, const RegionRange& rr, const Lattice& lat,
              const double* x, std::vector<Run>& runs, std::vector<Run>& scratch) {
  const ImageGrid& g = *regions[k].image;
  const int dim = lat.dim;
  auto voxelIndex = [&](int a, double coord) {
    return std::llround((coord - g.origin[static_cast<size_t>(a)]) / g.voxel - 0.5);
  };
  const long long j = dim > 1 ? voxelIndex(1, x[1]) : 0, kz = dim > 2 ? voxelIndex(2, x[2]) : 0;
  if (j < 0 || j >= g.n[1] || kz < 0 || kz >= g.n[2]) return;
  const long long a = rr.r0[0], b = rr.r1[0];
  paint(runs, scratch, a, b, -1);
  const size_t base = (static_cast<size_t>(kz) * static_cast<size_t>(g.n[1]) + static_cast<size_t>(j)) *
                      static_cast<size_t>(g.n[0]);
  const long long i0 = voxelIndex(0, lat.site(0, a));
  Run cur{0, -1, -1};
  for (long long ix = a; ix <= b; ++ix) {
    const long long i = i0 + (ix - a);
    const int m = i >= 0 && i < g.n[0] ? g.member[base + static_cast<size_t>(i)] : ImageGrid::kNoMember;
    const int owner = m == ImageGrid::kNoMember ? -1 : static_cast<int>(k) + m;
    if (owner == cur.owner && cur.b == ix - 1) {
      cur.b = ix;
      continue;
    }
    if (cur.owner >= 0) runs.push_back(cur);
    cur = {ix, ix, owner};
  }
  if (cur.owner >= 0) runs.push_back(cur);
  std::sort(runs.begin(), runs.end(), [](const Run& p, const Run& q) { return p.a < q.a; });
}

/// The filled sites of row (iy, iz), as runs of one owner each, sorted along x: every region is
/// convex, so its sites in a row are one interval, found from its bounds and refined with
/// Region::contains (the same test as a site-by-site fill).
void rowRuns(const std::vector<Region>& regions, const std::vector<RegionRange>& ranges,
             const Lattice& lat, long long iy, long long iz, std::vector<Run>& runs,
             std::vector<Run>& scratch) {
  runs.clear();
  const int dim = lat.dim;
  double x[3] = {0.0, 0.0, 0.0};
  if (dim > 1) x[1] = lat.site(1, iy);
  if (dim > 2) x[2] = lat.site(2, iz);
  for (size_t k = 0; k < regions.size(); ++k) {
    const Region& r = regions[k];
    const RegionRange& rr = ranges[k];
    if (rr.empty) continue;
    if (dim > 1 && (iy < rr.r0[1] || iy > rr.r1[1])) continue;
    if (dim > 2 && (iz < rr.r0[2] || iz > rr.r1[2])) continue;
    if (r.shape == Region::Shape::Image) {
      if (r.imageMember == 0) imageRow(regions, k, rr, lat, x, runs, scratch);
      continue;
    }
    long long a = rr.r0[0], b = rr.r1[0];
    if (r.shape != Region::Shape::Box) {
      // The region's exact interval on this row, clipped to its bounding range.
      double t0 = 0.0, t1 = 0.0;
      if (!r.rowSpan(x, dim, lat.tol, t0, t1)) continue;
      const double l = lat.origin[0];
      const double fa = std::ceil((t0 - l) / lat.dx - 0.5);
      const double fb = std::floor((t1 - l) / lat.dx - 0.5);
      const double lo = static_cast<double>(a), hi = static_cast<double>(b);
      a = std::max(a, static_cast<long long>(std::min(std::max(fa, lo), hi + 1.0)));
      b = std::min(b, static_cast<long long>(std::max(std::min(fb, hi), lo - 1.0)));
    }
    auto in = [&](long long i) {
      x[0] = lat.site(0, i);
      return r.contains(x, dim, lat.tol);
    };
    for (int s = 0; s < 2 && a - 1 >= rr.r0[0] && in(a - 1); ++s) --a;
    for (int s = 0; s < 2 && b + 1 <= rr.r1[0] && in(b + 1); ++s) ++b;
    for (int s = 0; s < 3 && a <= b && !in(a); ++s) ++a;
    for (int s = 0; s < 3 && a <= b && !in(b); ++s) --b;
    if (a > b || !in(a) || !in(b)) continue;
    paint(runs, scratch, a, b, r.subtracts() ? -1 : static_cast<int>(k));
  }
}

}  // namespace

LatticeCount countLattice(const std::vector<Region>& regions, const Domain& domain, double dx) {
  LatticeCount out;
  out.perRegion.assign(regions.size(), 0);
  const Lattice lat = makeLattice(regions, domain, dx);
  if (lat.empty) return out;
  const int dim = lat.dim;
  std::array<long long, 3> n{1, 1, 1};
  double bounding = 1.0;
  for (int a = 0; a < dim; ++a) {
    const size_t s = static_cast<size_t>(a);
    n[s] = lat.last[s] - lat.first[s] + 1;  // <= 2 kMaxIndex + 1 < 2^63
    bounding *= static_cast<double>(n[s]);
  }
  out.boundingSites = bounding;
  const double rows = static_cast<double>(n[1]) * static_cast<double>(n[2]);
  if (rows > kMaxRows)
    tooLarge(dx, "gives a lattice of about " + num(bounding) +
                     " sites around the regions (" + num(rows) +
                     " rows, more than 2^28), far more than a run can hold");
  const std::vector<RegionRange> ranges = regionRanges(regions, lat);
  std::vector<Run> runs, scratch;
  std::uint64_t total = 0;
  double approx = 0.0;
  bool overflow = false;
  for (long long iz = lat.first[2]; iz <= lat.last[2]; ++iz)
    for (long long iy = lat.first[1]; iy <= lat.last[1]; ++iy) {
      rowRuns(regions, ranges, lat, iy, iz, runs, scratch);
      for (const Run& r : runs) {
        const std::uint64_t len = static_cast<std::uint64_t>(r.b - r.a) + 1;
        approx += static_cast<double>(len);
        std::uint64_t& reg = out.perRegion[static_cast<size_t>(r.owner)];
        if (__builtin_add_overflow(total, len, &total)) overflow = true;
        if (__builtin_add_overflow(reg, len, &reg)) overflow = true;
      }
    }
  if (overflow || total > kMaxLatticeParticles) {
    tooLarge(dx, "fills the regions with about " + num(approx) + " particles (more than 2^31 - 1 = " +
                     std::to_string(kMaxLatticeParticles) + ", the most a run can index)");
  }
  out.sites = total;
  return out;
}

LatticeFill fillLattice(const std::vector<Region>& regions, const Domain& domain, double dx) {
  const LatticeCount count = countLattice(regions, domain, dx);
  LatticeFill out;
  out.dimension = domain.dimension;
  if (count.sites == 0) return out;
  const Lattice lat = makeLattice(regions, domain, dx);
  const int dim = lat.dim;
  const std::vector<RegionRange> ranges = regionRanges(regions, lat);
  out.position.reserve(static_cast<size_t>(count.sites) * static_cast<size_t>(dim));
  out.region.reserve(static_cast<size_t>(count.sites));
  std::vector<Run> runs, scratch;
  for (long long iz = lat.first[2]; iz <= lat.last[2]; ++iz)
    for (long long iy = lat.first[1]; iy <= lat.last[1]; ++iy) {
      rowRuns(regions, ranges, lat, iy, iz, runs, scratch);
      const long long idx[3] = {0, iy, iz};
      for (const Run& r : runs)
        for (long long ix = r.a; ix <= r.b; ++ix) {
          out.position.push_back(lat.site(0, ix));
          for (int a = 1; a < dim; ++a) out.position.push_back(lat.site(a, idx[a]));
          out.region.push_back(r.owner);
        }
    }
  return out;
}

}  // namespace poresph
