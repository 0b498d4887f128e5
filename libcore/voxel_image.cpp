#include "libcore/voxel_image.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numeric>

namespace poresph {

VoxelImage::VoxelImage(int nx, int ny, int nz, std::uint8_t fill) : n_{nx, ny, nz} {
  if (nx <= 0 || ny <= 0 || nz <= 0)
    throw InputError("voxel image: every size must be positive, got " + std::to_string(nx) + " x " +
                     std::to_string(ny) + " x " + std::to_string(nz));
  v_.assign(static_cast<size_t>(voxelCount()), fill);
}

VoxelImage VoxelImage::readRaw(const std::string& path, int nx, int ny, int nz) {
  VoxelImage img(nx, ny, nz);
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError("voxel image '" + path + "': cannot read the file (" + ec.message() + ")");
  const auto expected = static_cast<std::uintmax_t>(img.voxelCount());
  if (size != expected)
    throw InputError("voxel image '" + path + "': size " + std::to_string(size) +
                     " bytes does not match the shape " + std::to_string(nx) + " x " +
                     std::to_string(ny) + " x " + std::to_string(nz) + " (" +
                     std::to_string(expected) + " bytes of unsigned 8-bit voxels)");
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(img.v_.data()), static_cast<std::streamsize>(expected));
  if (!in) throw InputError("voxel image '" + path + "': read failed");
  return img;
}

VoxelImage VoxelImage::crop(int x0, int y0, int z0, int sx, int sy, int sz) const {
  if (x0 < 0 || y0 < 0 || z0 < 0 || sx <= 0 || sy <= 0 || sz <= 0 || x0 + sx > n_[0] ||
      y0 + sy > n_[1] || z0 + sz > n_[2])
    throw InputError("voxel image: crop [" + std::to_string(x0) + "+" + std::to_string(sx) + ", " +
                     std::to_string(y0) + "+" + std::to_string(sy) + ", " + std::to_string(z0) + "+" +
                     std::to_string(sz) + "] lies outside the image " + std::to_string(n_[0]) +
                     " x " + std::to_string(n_[1]) + " x " + std::to_string(n_[2]));
  VoxelImage out(sx, sy, sz);
  for (int z = 0; z < sz; ++z)
    for (int y = 0; y < sy; ++y)
      for (int x = 0; x < sx; ++x) out.at(x, y, z) = at(x0 + x, y0 + y, z0 + z);
  return out;
}

namespace {
Index findRoot(std::vector<Index>& parent, Index a) {
  while (parent[static_cast<size_t>(a)] != a) {
    parent[static_cast<size_t>(a)] = parent[static_cast<size_t>(parent[static_cast<size_t>(a)])];
    a = parent[static_cast<size_t>(a)];
  }
  return a;
}
void unite(std::vector<Index>& parent, Index a, Index b) {
  a = findRoot(parent, a);
  b = findRoot(parent, b);
  if (a != b) parent[static_cast<size_t>(std::max(a, b))] = std::min(a, b);
}
}  // namespace

std::vector<std::int32_t> labelPoreClusters(const VoxelImage& img, std::uint8_t pore,
                                            Index* clusterCount) {
  const Index n = img.voxelCount();
  const auto& v = img.values();
  std::vector<Index> parent(static_cast<size_t>(n));
  std::iota(parent.begin(), parent.end(), Index{0});
  for (int z = 0; z < img.nz(); ++z)
    for (int y = 0; y < img.ny(); ++y)
      for (int x = 0; x < img.nx(); ++x) {
        const Index i = img.linear(x, y, z);
        if (v[static_cast<size_t>(i)] != pore) continue;
        if (x > 0 && v[static_cast<size_t>(i - 1)] == pore) unite(parent, i, i - 1);
        if (y > 0 && v[static_cast<size_t>(img.linear(x, y - 1, z))] == pore)
          unite(parent, i, img.linear(x, y - 1, z));
        if (z > 0 && v[static_cast<size_t>(img.linear(x, y, z - 1))] == pore)
          unite(parent, i, img.linear(x, y, z - 1));
      }
  // Roots -> cluster ids ordered by decreasing size (ties: by first voxel).
  std::vector<Index> size(static_cast<size_t>(n), 0);
  for (Index i = 0; i < n; ++i)
    if (v[static_cast<size_t>(i)] == pore) ++size[static_cast<size_t>(findRoot(parent, i))];
  std::vector<Index> roots;
  for (Index i = 0; i < n; ++i)
    if (v[static_cast<size_t>(i)] == pore && parent[static_cast<size_t>(i)] == i) roots.push_back(i);
  std::stable_sort(roots.begin(), roots.end(), [&](Index a, Index b) {
    return size[static_cast<size_t>(a)] > size[static_cast<size_t>(b)];
  });
  std::vector<std::int32_t> idOfRoot(static_cast<size_t>(n), -1);
  for (size_t k = 0; k < roots.size(); ++k) idOfRoot[static_cast<size_t>(roots[k])] = static_cast<std::int32_t>(k);
  std::vector<std::int32_t> label(static_cast<size_t>(n), -1);
  for (Index i = 0; i < n; ++i)
    if (v[static_cast<size_t>(i)] == pore)
      label[static_cast<size_t>(i)] = idOfRoot[static_cast<size_t>(findRoot(parent, i))];
  if (clusterCount) *clusterCount = static_cast<Index>(roots.size());
  return label;
}

PoreStatistics poreStatistics(const VoxelImage& img, std::uint8_t pore) {
  PoreStatistics s;
  s.voxels = img.voxelCount();
  Index count = 0;
  const auto label = labelPoreClusters(img, pore, &count);
  s.clusters = count;
  std::vector<Index> sizes(static_cast<size_t>(count), 0);
  for (auto l : label)
    if (l >= 0) ++sizes[static_cast<size_t>(l)], ++s.poreVoxels;
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
