#include "libcore/geometry.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace poresph {

bool Region::contains(const double* x, int dim, double tol) const {
  if (shape == Shape::Box) {
    for (int a = 0; a < dim; ++a)
      if (x[a] < lo[static_cast<size_t>(a)] - tol || x[a] > hi[static_cast<size_t>(a)] + tol)
        return false;
    return true;
  }
  double r2 = 0.0;
  for (int a = 0; a < dim; ++a) {
    const double d = x[a] - centre[static_cast<size_t>(a)];
    r2 += d * d;
  }
  const double r = radius + tol;
  return r2 <= r * r;
}

void Region::bounds(int dim, std::array<double, 3>& blo, std::array<double, 3>& bhi) const {
  for (size_t a = 0; a < 3; ++a) {
    if (static_cast<int>(a) >= dim) {
      blo[a] = bhi[a] = 0.0;
    } else if (shape == Shape::Box) {
      blo[a] = lo[a];
      bhi[a] = hi[a];
    } else {
      blo[a] = centre[a] - radius;
      bhi[a] = centre[a] + radius;
    }
  }
}

LatticeFill fillLattice(const std::vector<Region>& regions, const Domain& domain, double dx) {
  const int dim = domain.dimension;
  if (!(dx > 0.0) || !std::isfinite(dx))
    throw InputError("lattice spacing must be positive and finite, got " + std::to_string(dx));
  LatticeFill out;
  out.dimension = dim;
  const double tol = 1e-9 * dx;

  // Index range of the union of the (non-subtracting) regions, per axis. Site i sits at
  // lo + (i + 1/2) dx; a bound b contains sites with i in [ceil((b_lo-lo)/dx - 1/2), floor(...)].
  std::array<long long, 3> first{0, 0, 0}, last{0, 0, 0};
  bool any = false;
  for (const Region& r : regions) {
    if (r.subtracts()) continue;
    std::array<double, 3> blo, bhi;
    r.bounds(dim, blo, bhi);
    for (int a = 0; a < dim; ++a) {
      const size_t s = static_cast<size_t>(a);
      const double l = domain.lo[s];
      const long long i0 = static_cast<long long>(std::ceil((blo[s] - l) / dx - 0.5 - 1e-9));
      const long long i1 = static_cast<long long>(std::floor((bhi[s] - l) / dx - 0.5 + 1e-9));
      if (!any) {
        first[s] = i0;
        last[s] = i1;
      } else {
        first[s] = std::min(first[s], i0);
        last[s] = std::max(last[s], i1);
      }
    }
    any = true;
  }
  if (!any) return out;

  // Periodic axes: only the sites of [lo, hi); the length must be a whole number of spacings.
  for (int a = 0; a < dim; ++a) {
    const size_t s = static_cast<size_t>(a);
    if (!domain.periodic[s]) continue;
    const double cells = domain.length(a) / dx;
    const long long n = std::llround(cells);
    if (n < 1 || std::abs(cells - static_cast<double>(n)) > 1e-6 * std::max(1.0, cells)) {
      std::ostringstream m;
      m.precision(12);
      m << "the periodic length along axis " << "xyz"[a] << " (" << domain.length(a)
        << " m) is not a whole number of spacings dx = " << dx << " m (" << cells
        << " spacings); particles would overlap or leave a gap across the periodic boundary";
      throw InputError(m.str());
    }
    first[s] = std::max(first[s], 0LL);
    last[s] = std::min(last[s], n - 1);
  }

  std::array<long long, 3> count{1, 1, 1};
  double total = 1.0;
  for (int a = 0; a < dim; ++a) {
    const size_t s = static_cast<size_t>(a);
    count[s] = std::max(0LL, last[s] - first[s] + 1);
    total *= static_cast<double>(count[s]);
  }
  if (total == 0.0) return out;
  if (total > 2147483647.0) {
    std::ostringstream m;
    m << "the regions span " << total << " lattice sites of spacing " << dx
      << " m (more than 2^31); the spacing is too small for the geometry";
    throw InputError(m.str());
  }

  // Owner of every site of the bounding lattice: -1 empty, else region index (later wins).
  const long long nx = count[0], ny = count[1], nz = count[2];
  std::vector<std::int32_t> owner(static_cast<size_t>(nx * ny * nz), -1);
  for (size_t k = 0; k < regions.size(); ++k) {
    const Region& r = regions[k];
    std::array<double, 3> blo, bhi;
    r.bounds(dim, blo, bhi);
    std::array<long long, 3> r0{0, 0, 0}, r1{0, 0, 0};
    bool empty = false;
    for (int a = 0; a < dim; ++a) {
      const size_t s = static_cast<size_t>(a);
      const double l = domain.lo[s];
      r0[s] = std::max(first[s],
                       static_cast<long long>(std::ceil((blo[s] - l) / dx - 0.5 - 1e-9)));
      r1[s] = std::min(last[s],
                       static_cast<long long>(std::floor((bhi[s] - l) / dx - 0.5 + 1e-9)));
      if (r1[s] < r0[s]) empty = true;
    }
    if (empty) continue;
    const std::int32_t value = r.subtracts() ? -1 : static_cast<std::int32_t>(k);
#pragma omp parallel for collapse(2) schedule(static)
    for (long long iz = r0[2]; iz <= r1[2]; ++iz)
      for (long long iy = r0[1]; iy <= r1[1]; ++iy) {
        double x[3] = {0.0, 0.0, 0.0};
        if (dim > 2) x[2] = domain.lo[2] + (static_cast<double>(iz) + 0.5) * dx;
        if (dim > 1) x[1] = domain.lo[1] + (static_cast<double>(iy) + 0.5) * dx;
        for (long long ix = r0[0]; ix <= r1[0]; ++ix) {
          x[0] = domain.lo[0] + (static_cast<double>(ix) + 0.5) * dx;
          if (r.contains(x, dim, tol)) {
            const long long cell =
                ((iz - first[2]) * ny + (iy - first[1])) * nx + (ix - first[0]);
            owner[static_cast<size_t>(cell)] = value;
          }
        }
      }
  }

  Index n = 0;
  for (std::int32_t o : owner) n += o >= 0 ? 1 : 0;
  out.position.reserve(static_cast<size_t>(n * dim));
  out.region.reserve(static_cast<size_t>(n));
  for (long long iz = 0; iz < nz; ++iz)
    for (long long iy = 0; iy < ny; ++iy)
      for (long long ix = 0; ix < nx; ++ix) {
        const std::int32_t o = owner[static_cast<size_t>((iz * ny + iy) * nx + ix)];
        if (o < 0) continue;
        const long long idx[3] = {ix + first[0], iy + first[1], iz + first[2]};
        for (int a = 0; a < dim; ++a)
          out.position.push_back(domain.lo[static_cast<size_t>(a)] +
                                 (static_cast<double>(idx[a]) + 0.5) * dx);
        out.region.push_back(o);
      }
  return out;
}

}  // namespace poresph
