#include "libcore/voxel_image.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

#include "libcore/memory.hpp"

namespace poresph {

namespace {

std::string shapeText(int nx, int ny, int nz) {
  return std::to_string(nx) + " x " + std::to_string(ny) + " x " + std::to_string(nz);
}

/// a * b, or UINT64_MAX when it overflows: byte counts only need to compare as "too large".
std::uint64_t mulSaturated(std::uint64_t a, std::uint64_t b) {
  std::uint64_t r = 0;
  return __builtin_mul_overflow(a, b, &r) ? std::numeric_limits<std::uint64_t>::max() : r;
}

/// nx * ny * nz, refused (naming `what` and the shape) when a size is not positive or the count
/// exceeds kMaxVoxels. The product is formed in 64-bit with overflow checks: ints near 2^22
/// already overflow a 64-bit product of three of them.
Index checkedVoxelCount(int nx, int ny, int nz, const std::string& what) {
  if (nx <= 0 || ny <= 0 || nz <= 0)
    throw InputError(what + ": every size must be positive, got " + shapeText(nx, ny, nz));
  std::int64_t xy = 0, xyz = 0;
  const bool overflow = __builtin_mul_overflow(std::int64_t{nx}, std::int64_t{ny}, &xy) ||
                        __builtin_mul_overflow(xy, std::int64_t{nz}, &xyz);
  if (overflow || xyz > kMaxVoxels) {
    char count[32];
    std::snprintf(count, sizeof(count), "%.3g", double(nx) * double(ny) * double(nz));
    throw InputError(what + ": the shape " + shapeText(nx, ny, nz) + " has " + count +
                     " voxels, more than the limit of 2^48 = " + std::to_string(kMaxVoxels) +
                     " voxels");
  }
  return xyz;
}

/// Refuses (naming `what`, the bytes needed and what they are for) when `needed` exceeds the
/// memory available; no check when the available memory is unknown.
void requireMemory(std::uint64_t needed, const std::string& what, const std::string& detail) {
  const std::uint64_t available = availableMemoryBytes();
  if (available == 0 || needed <= available) return;
  throw InputError(what + ": needs " + formatBytes(needed) + " of memory (" + detail +
                   ") but only " + formatBytes(available) +
                   " is available (MemAvailable in /proc/meminfo)");
}

}  // namespace

VoxelImage::VoxelImage(int nx, int ny, int nz, std::uint8_t fill) : n_{nx, ny, nz} {
  const Index n = checkedVoxelCount(nx, ny, nz, "voxel image");
  requireMemory(static_cast<std::uint64_t>(n), "voxel image " + shapeText(nx, ny, nz),
                "1 byte per voxel");
  v_.assign(static_cast<size_t>(n), fill);
}

VoxelImage VoxelImage::readRaw(const std::string& path, int nx, int ny, int nz,
                               std::uint64_t extraBytesPerVoxel) {
  // Every check before the allocation: a wrong shape must give a message, not a crash.
  const std::string what = "voxel image '" + path + "'";
  const Index n = checkedVoxelCount(nx, ny, nz, what);
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(what + ": cannot read the file (" + ec.message() + ")");
  const auto expected = static_cast<std::uintmax_t>(n);
  if (size != expected)
    throw InputError(what + ": size " + std::to_string(size) + " bytes does not match the shape " +
                     shapeText(nx, ny, nz) + " (" + std::to_string(expected) +
                     " bytes of unsigned 8-bit voxels)");
  const std::uint64_t perVoxel = 1 + extraBytesPerVoxel;
  requireMemory(mulSaturated(static_cast<std::uint64_t>(n), perVoxel),
                what + " (" + shapeText(nx, ny, nz) + ")",
                std::to_string(perVoxel) + " bytes per voxel: 1 for the image" +
                    (extraBytesPerVoxel ? ", " + std::to_string(extraBytesPerVoxel) +
                                              " for the analysis"
                                        : std::string()));
  VoxelImage img;
  img.n_ = {nx, ny, nz};
  img.v_.resize(static_cast<size_t>(n));
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(img.v_.data()), static_cast<std::streamsize>(expected));
  if (!in) throw InputError(what + ": read failed");
  return img;
}

VoxelImage VoxelImage::crop(int x0, int y0, int z0, int sx, int sy, int sz) const {
  if (x0 < 0 || y0 < 0 || z0 < 0 || sx <= 0 || sy <= 0 || sz <= 0 || sx > n_[0] - x0 ||
      sy > n_[1] - y0 || sz > n_[2] - z0)
    throw InputError("voxel image: crop [" + std::to_string(x0) + "+" + std::to_string(sx) + ", " +
                     std::to_string(y0) + "+" + std::to_string(sy) + ", " + std::to_string(z0) + "+" +
                     std::to_string(sz) + "] lies outside the image " + shapeText(n_[0], n_[1], n_[2]));
  VoxelImage out(sx, sy, sz);
  for (int z = 0; z < sz; ++z)
    for (int y = 0; y < sy; ++y)
      for (int x = 0; x < sx; ++x) out.at(x, y, z) = at(x0 + x, y0 + y, z0 + z);
  return out;
}

std::vector<std::array<int, 3>> neighbourOffsets(int connectivity) {
  // 6, 18, 26 = offsets with at most 1, 2, 3 non-zero components.
  const int maxNonZero = connectivity == 6 ? 1 : connectivity == 18 ? 2 : connectivity == 26 ? 3 : 0;
  if (maxNonZero == 0)
    throw InputError("voxel connectivity must be 6, 18 or 26, got " + std::to_string(connectivity));
  std::vector<std::array<int, 3>> out;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nonZero = (dx != 0) + (dy != 0) + (dz != 0);
        if (nonZero > 0 && nonZero <= maxNonZero) out.push_back({dx, dy, dz});
      }
  return out;
}

namespace {

/// The neighbours met before a voxel in x-fastest order (half of neighbourOffsets), as linear
/// deltas with the bounds each needs. The labelling scans rows and asks only these.
struct BackwardNeighbours {
  struct Offset {
    Index delta;
    int dx, dy, dz;
  };
  std::vector<Offset> all;
  std::vector<Offset> row;  ///< those valid for the current (y, z) row
  BackwardNeighbours(const VoxelImage& img, int connectivity) {
    for (const auto& o : neighbourOffsets(connectivity)) {
      const bool backward = o[2] < 0 || (o[2] == 0 && (o[1] < 0 || (o[1] == 0 && o[0] < 0)));
      if (backward)
        all.push_back({(Index{o[2]} * img.ny() + o[1]) * img.nx() + o[0], o[0], o[1], o[2]});
    }
  }
  void selectRow(const VoxelImage& img, int y, int z) {
    row.clear();
    for (const auto& o : all)
      if ((o.dz == 0 || z > 0) && (o.dy >= 0 || y > 0) && (o.dy <= 0 || y < img.ny() - 1))
        row.push_back(o);
  }
  static bool inRow(const Offset& o, int x, int nx) {
    return (o.dx >= 0 || x > 0) && (o.dx <= 0 || x < nx - 1);
  }
};

std::int32_t findRoot(std::vector<std::int32_t>& parent, std::int32_t a) {
  while (parent[static_cast<size_t>(a)] != a) {
    parent[static_cast<size_t>(a)] = parent[static_cast<size_t>(parent[static_cast<size_t>(a)])];
    a = parent[static_cast<size_t>(a)];
  }
  return a;
}

/// Joins the sets of a and b; the smaller root (the earlier provisional label, hence the earlier
/// first voxel) stays root, which the numbering below relies on. Returns it.
std::int32_t unite(std::vector<std::int32_t>& parent, std::int32_t a, std::int32_t b) {
  a = findRoot(parent, a);
  b = findRoot(parent, b);
  if (a == b) return a;
  if (a > b) std::swap(a, b);
  parent[static_cast<size_t>(b)] = a;
  return a;
}

}  // namespace

std::vector<std::int32_t> labelPoreClusters(const VoxelImage& img, std::uint8_t pore,
                                            Index* clusterCount, int connectivity,
                                            std::vector<Index>* clusterSizes) {
  const Index n = img.voxelCount();
  const int nx = img.nx();
  const std::uint8_t* v = img.values().data();
  BackwardNeighbours nb(img, connectivity);

  // Pass 0 (image only): count the provisional labels, i.e. the pore voxels with no pore
  // neighbour before them, so that the equivalence table is allocated once at its exact size and
  // the memory check below is exact rather than a guess.
  Index provisional = 0;
  for (int z = 0; z < img.nz(); ++z)
    for (int y = 0; y < img.ny(); ++y) {
      nb.selectRow(img, y, z);
      const Index base = img.linear(0, y, z);
      for (int x = 0; x < nx; ++x) {
        const Index i = base + x;
        if (v[i] != pore) continue;
        bool joined = false;
        for (const auto& o : nb.row)
          if (BackwardNeighbours::inRow(o, x, nx) && v[i + o.delta] == pore) {
            joined = true;
            break;
          }
        if (!joined) ++provisional;
      }
    }
  if (provisional > std::numeric_limits<std::int32_t>::max())
    throw InputError("voxel image " + shapeText(img.nx(), img.ny(), img.nz()) + ": " +
                     std::to_string(provisional) +
                     " provisional pore clusters, more than the 2^31 - 1 that 32-bit labels hold");
  // Peak: the labels, the table, and per cluster (at most one per provisional label) its size
  // (8 bytes), its order (4), then its rank (4) or its size reordered (8).
  const auto perVoxel = kLabelBytesPerVoxel;
  requireMemory(static_cast<std::uint64_t>(n) * perVoxel + static_cast<std::uint64_t>(provisional) * 24,
                "pore cluster labels of the voxel image " + shapeText(img.nx(), img.ny(), img.nz()),
                std::to_string(perVoxel) + " bytes per voxel and at most 24 per provisional cluster, " +
                    std::to_string(provisional) + " of them");

  // Pass 1: provisional labels, joined in the table where two meet.
  std::vector<std::int32_t> label(static_cast<size_t>(n), -1);
  std::vector<std::int32_t> parent(static_cast<size_t>(provisional));
  std::int32_t next = 0;
  for (int z = 0; z < img.nz(); ++z)
    for (int y = 0; y < img.ny(); ++y) {
      nb.selectRow(img, y, z);
      const Index base = img.linear(0, y, z);
      for (int x = 0; x < nx; ++x) {
        const Index i = base + x;
        if (v[i] != pore) continue;
        std::int32_t cur = -1;
        for (const auto& o : nb.row) {
          if (!BackwardNeighbours::inRow(o, x, nx)) continue;
          const std::int32_t l = label[static_cast<size_t>(i + o.delta)];
          if (l < 0 || l == cur) continue;
          cur = cur < 0 ? l : unite(parent, cur, l);
        }
        if (cur < 0) {
          cur = next++;
          parent[static_cast<size_t>(cur)] = cur;
        }
        label[static_cast<size_t>(i)] = cur;
      }
    }

  // Roots -> compact ids in place: a root is its set's smallest label, so one increasing sweep
  // sees every label's parent already numbered. Ids follow the first voxel of each cluster.
  std::int32_t clusters = 0;
  for (std::int32_t l = 0; l < next; ++l) {
    const std::int32_t p = parent[static_cast<size_t>(l)];
    parent[static_cast<size_t>(l)] = p == l ? clusters++ : parent[static_cast<size_t>(p)];
  }
  std::vector<Index> size(static_cast<size_t>(clusters), 0);
  for (Index i = 0; i < n; ++i) {
    const std::int32_t l = label[static_cast<size_t>(i)];
    if (l >= 0) ++size[static_cast<size_t>(parent[static_cast<size_t>(l)])];
  }
  // Order by decreasing size; the stable sort keeps ties in first-voxel order.
  std::vector<std::int32_t> order(static_cast<size_t>(clusters));
  for (std::int32_t c = 0; c < clusters; ++c) order[static_cast<size_t>(c)] = c;
  std::stable_sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    return size[static_cast<size_t>(a)] > size[static_cast<size_t>(b)];
  });
  {
    std::vector<std::int32_t> rank(static_cast<size_t>(clusters));
    for (std::int32_t k = 0; k < clusters; ++k) rank[static_cast<size_t>(order[static_cast<size_t>(k)])] = k;
    for (auto& p : parent) p = rank[static_cast<size_t>(p)];
  }
  for (auto& l : label)
    if (l >= 0) l = parent[static_cast<size_t>(l)];
  if (clusterSizes) {
    clusterSizes->resize(static_cast<size_t>(clusters));
    for (std::int32_t k = 0; k < clusters; ++k)
      (*clusterSizes)[static_cast<size_t>(k)] = size[static_cast<size_t>(order[static_cast<size_t>(k)])];
  }
  if (clusterCount) *clusterCount = clusters;
  return label;
}

PoreStatistics poreStatistics(const VoxelImage& img, std::uint8_t pore, int connectivity) {
  PoreStatistics s;
  s.connectivity = connectivity;
  s.voxels = img.voxelCount();
  Index count = 0;
  std::vector<Index> sizes;
  const auto label = labelPoreClusters(img, pore, &count, connectivity, &sizes);
  s.clusters = count;
  for (const Index c : sizes) s.poreVoxels += c;
  s.porosity = s.voxels ? static_cast<double>(s.poreVoxels) / static_cast<double>(s.voxels) : 0.0;
  if (count == 0) return s;
  s.largestCluster = sizes[0];
  s.largestFraction = static_cast<double>(sizes[0]) / static_cast<double>(s.poreVoxels);
  // Percolation of cluster 0: present on both faces normal to each axis.
  const int n[3] = {img.nx(), img.ny(), img.nz()};
  for (int axis = 0; axis < 3; ++axis) {
    bool lo = false, hi = false;
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int u = 0; u < n[a1] && !(lo && hi); ++u)
      for (int w = 0; w < n[a2]; ++w) {
        int c[3];
        c[a1] = u;
        c[a2] = w;
        c[axis] = 0;
        if (label[static_cast<size_t>(img.linear(c[0], c[1], c[2]))] == 0) lo = true;
        c[axis] = n[axis] - 1;
        if (label[static_cast<size_t>(img.linear(c[0], c[1], c[2]))] == 0) hi = true;
      }
    s.largestPercolates[static_cast<size_t>(axis)] = lo && hi;
  }
  return s;
}

}  // namespace poresph
