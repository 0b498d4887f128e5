#pragma once
// Periodic images for set-up searches that reach beyond the run's ghost halo (reference families
// of the Total-Lagrangian solid, the consistent nodal load of Eq. 2.76, the wide wall normal of
// the wetting model): an image of every point within `width` of a periodic face joins the point
// set, shifted by +-period (edges and corners included), so that a plain NeighbourSearch over
// points + images finds the pairs that cross the face. `origin` maps each entry (point or image)
// back to its point. The time loop's halo (libcore/halo.hpp) does the same for the store's
// particles at one support; this is for positions that are not (or not only) the store's.
#include <Eigen/Dense>
#include <cstddef>
#include <vector>

#include "libcore/domain.hpp"
#include "libcore/types.hpp"

namespace poresph {

/// X holds n = X.size() / D points on entry; appends their images within `width` of a periodic
/// face of `domain` and sets origin to 0..n-1 followed by the source point of each image.
/// Returns the number of images appended. The caller checks that each period is long enough for
/// its use (a period shorter than the search radius would make a point its own neighbour).
template <int D>
Index appendPeriodicImages(const Domain& domain, double width, std::vector<double>& X,
                           std::vector<Index>& origin) {
  const Index n = static_cast<Index>(X.size() / D);
  origin.resize(static_cast<size_t>(n));
  for (Index k = 0; k < n; ++k) origin[static_cast<size_t>(k)] = k;
  if (!domain.anyPeriodic()) return 0;
  int shifts = 1;
  for (int a = 0; a < D; ++a) shifts *= 3;
  for (Index k = 0; k < n; ++k)
    for (int code = 0; code < shifts; ++code) {
      bool any = false, keep = true;
      Vec<D> Y = Eigen::Map<const Vec<D>>(X.data() + k * D);
      for (int a = 0, c = code; a < D; ++a, c /= 3) {
        const int sh = c % 3 - 1;
        if (sh == 0) continue;
        if (!domain.periodic[static_cast<size_t>(a)]) { keep = false; break; }
        any = true;
        Y[a] += sh * domain.length(a);
        if (Y[a] < domain.lo[static_cast<size_t>(a)] - width ||
            Y[a] > domain.hi[static_cast<size_t>(a)] + width)
          keep = false;
      }
      if (!any || !keep) continue;
      for (int a = 0; a < D; ++a) X.push_back(Y[a]);
      origin.push_back(k);
    }
  return static_cast<Index>(origin.size()) - n;
}

}  // namespace poresph
