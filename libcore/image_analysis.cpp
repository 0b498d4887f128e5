#include "libcore/image_analysis.hpp"

#include <vtkCellData.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLImageDataWriter.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

namespace poresph {

namespace {
std::string shapeText(const VoxelImage& img) {
  return std::to_string(img.nx()) + " x " + std::to_string(img.ny()) + " x " +
         std::to_string(img.nz());
}
}  // namespace

VoxelImage coarsenImage(const VoxelImage& img, int f) {
  if (f < 1) throw InputError("coarsen: the factor must be a whole number >= 1, got " + std::to_string(f));
  if (f == 1) return img;
  const int fz = img.flat() ? 1 : f;
  if (img.nx() % f || img.ny() % f || img.nz() % fz)
    throw InputError("coarsen " + std::to_string(f) + ": the image " + shapeText(img) +
                     " is not a whole number of " + std::to_string(f) + "-voxel blocks along " +
                     (img.nx() % f ? "x" : img.ny() % f ? "y" : "z") + "; crop it to a multiple of " +
                     std::to_string(f) + " first");
  VoxelImage out(img.nx() / f, img.ny() / f, img.nz() / fz);
  std::array<int, 256> count{};
  std::vector<int> touched;
  touched.reserve(static_cast<size_t>(f) * f * fz);
  for (int Z = 0; Z < out.nz(); ++Z)
    for (int Y = 0; Y < out.ny(); ++Y)
      for (int X = 0; X < out.nx(); ++X) {
        touched.clear();
        for (int z = Z * fz; z < (Z + 1) * fz; ++z)
          for (int y = Y * f; y < (Y + 1) * f; ++y)
            for (int x = X * f; x < (X + 1) * f; ++x) {
              const int l = img.at(x, y, z);
              if (count[static_cast<size_t>(l)]++ == 0) touched.push_back(l);
            }
        int best = -1, bestCount = 0;
        for (int l : touched) {
          const int c = count[static_cast<size_t>(l)];
          if (c > bestCount || (c == bestCount && l < best)) {
            best = l;
            bestCount = c;
          }
          count[static_cast<size_t>(l)] = 0;
        }
        out.at(X, Y, Z) = static_cast<std::uint8_t>(best);
      }
  return out;
}

VoxelImage sliceImage(const VoxelImage& img, int axis, int index) {
  const int n[3] = {img.nx(), img.ny(), img.nz()};
  if (axis < 0 || axis > 2) throw InputError("slice: the axis must be x, y or z");
  if (index < 0 || index >= n[axis])
    throw InputError(std::string("slice: index ") + std::to_string(index) + " along " + "xyz"[axis] +
                     " lies outside the image " + shapeText(img) + " (0 .. " +
                     std::to_string(n[axis] - 1) + ")");
  const int a1 = axis == 0 ? 1 : 0, a2 = axis == 2 ? 1 : 2;
  VoxelImage out(n[a1], n[a2], 1);
  for (int v = 0; v < n[a2]; ++v)
    for (int u = 0; u < n[a1]; ++u) {
      int c[3];
      c[axis] = index;
      c[a1] = u;
      c[a2] = v;
      out.at(u, v, 0) = img.at(c[0], c[1], c[2]);
    }
  return out;
}

namespace {

/// One line of the Felzenszwalb-Huttenlocher transform: d[q] = min_p (q - p)^2 + f[p] over the
/// finite f[p] (f = kInf: no parabola). v, z, out are scratch of the line's length (+1 for z).
constexpr std::int64_t kInf = std::numeric_limits<std::int64_t>::max() / 4;

void edtLine(const std::uint32_t* f, std::uint32_t* d, int n, std::vector<int>& v,
             std::vector<std::int64_t>& zn, std::vector<std::int64_t>& zd) {
  // Breakpoints z[k] = zn[k] / zd[k] (zd > 0) between parabolas v[k-1] and v[k], compared by
  // 128-bit cross-multiplication: exact, and without a division per comparison.
  using Wide = __int128;
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] == kNoSolid) continue;
    const std::int64_t fq = std::int64_t{f[q]} + std::int64_t{q} * q;
    std::int64_t num = 0, den = 1;
    while (k >= 0) {
      const int p = v[static_cast<size_t>(k)];
      num = fq - (std::int64_t{f[p]} + std::int64_t{p} * p);
      den = 2 * std::int64_t{q - p};
      if (k > 0 && Wide{num} * zd[static_cast<size_t>(k)] <= Wide{zn[static_cast<size_t>(k)]} * den) {
        --k;
      } else {
        break;
      }
    }
    ++k;
    v[static_cast<size_t>(k)] = q;
    zn[static_cast<size_t>(k)] = num;
    zd[static_cast<size_t>(k)] = den;
  }
  if (k < 0) {
    for (int q = 0; q < n; ++q) d[q] = kNoSolid;
    return;
  }
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (j < k && Wide{zn[static_cast<size_t>(j + 1)]} < Wide{q} * zd[static_cast<size_t>(j + 1)]) ++j;
    const std::int64_t p = v[static_cast<size_t>(j)];
    const std::int64_t e = (q - p) * (q - p) + std::int64_t{f[p]};
    d[q] = e >= std::int64_t{kNoSolid} ? kNoSolid : static_cast<std::uint32_t>(e);
  }
}

}  // namespace

std::vector<std::uint32_t> squaredDistanceToSolid(const VoxelImage& img, std::uint8_t pore) {
  const int n[3] = {img.nx(), img.ny(), img.nz()};
  const Index total = img.voxelCount();
  std::vector<std::uint32_t> out(static_cast<size_t>(total));
  const std::uint8_t* v = img.values().data();
  // Squared distances fit 32 bits: at most nx^2 + ny^2 + nz^2 along a real line of voxels; the
  // transform is exact in 64-bit integers and double intersections (|values| < 2^53).
  const int longest = std::max({n[0], n[1], n[2]});
  std::vector<std::int64_t> d(static_cast<size_t>(longest));
  std::vector<int> vv(static_cast<size_t>(longest));
  std::vector<std::int64_t> zn(static_cast<size_t>(longest) + 1), zd(static_cast<size_t>(longest) + 1);
  const std::uint32_t big = kNoSolid;
  // x: from the image directly. For a binary input the lower envelope is the nearest solid voxel
  // of the row, found by one sweep each way (same result as edtLine, several times faster).
  for (Index row = 0; row < total / n[0]; ++row) {
    const Index base = row * n[0];
    std::int64_t last = -1;  // position of the last solid voxel seen
    for (int x = 0; x < n[0]; ++x) {
      if (v[base + x] != pore) last = x;
      d[static_cast<size_t>(x)] = last < 0 ? kInf : x - last;
    }
    last = -1;
    for (int x = n[0] - 1; x >= 0; --x) {
      if (v[base + x] != pore) last = x;
      std::int64_t& e = d[static_cast<size_t>(x)];
      if (last >= 0 && last - x < e) e = last - x;
      out[static_cast<size_t>(base + x)] = e >= kInf ? big : static_cast<std::uint32_t>(e * e);
    }
  }
  // y, then z: strided lines, done kBlock neighbouring x at a time so that the gathers and
  // scatters read whole cache lines (one line at a time along z strides by nx ny voxels).
  constexpr int kBlock = 32;
  std::vector<std::uint32_t> fb(static_cast<size_t>(kBlock) * static_cast<size_t>(longest));
  std::vector<std::uint32_t> line(static_cast<size_t>(longest));
  for (int axis = 1; axis < 3; ++axis) {
    if (n[axis] == 1) continue;
    const Index stride = axis == 1 ? n[0] : Index{n[0]} * n[1];
    const Index outer = axis == 1 ? n[2] : 1;
    const Index inner = axis == 1 ? n[0] : Index{n[0]} * n[1];
    const Index outerStride = Index{n[0]} * n[1];
    const size_t len = static_cast<size_t>(n[axis]);
    for (Index o = 0; o < outer; ++o)
      for (Index i0 = 0; i0 < inner; i0 += kBlock) {
        const int b = static_cast<int>(std::min<Index>(kBlock, inner - i0));
        const Index base = o * outerStride + i0;
        for (int q = 0; q < n[axis]; ++q) {
          const std::uint32_t* src = &out[static_cast<size_t>(base + q * stride)];
          for (int j = 0; j < b; ++j) fb[static_cast<size_t>(j) * len + static_cast<size_t>(q)] = src[j];
        }
        for (int j = 0; j < b; ++j) {
          // A line with no pore voxel left (all 0) or no solid (all kNoSolid) stays as it is.
          std::uint32_t* col = &fb[static_cast<size_t>(j) * len];
          bool zero = true, none = true;
          for (size_t q = 0; q < len && (zero || none); ++q) {
            zero = zero && col[q] == 0;
            none = none && col[q] == kNoSolid;
          }
          if (zero || none) continue;
          edtLine(col, line.data(), n[axis], vv, zn, zd);
          std::copy(line.begin(), line.begin() + n[axis], col);
        }
        for (int q = 0; q < n[axis]; ++q) {
          std::uint32_t* dst = &out[static_cast<size_t>(base + q * stride)];
          for (int j = 0; j < b; ++j) dst[j] = fb[static_cast<size_t>(j) * len + static_cast<size_t>(q)];
        }
      }
  }
  return out;
}

PoreSizeDistribution poreSizeDistribution(const std::vector<std::uint32_t>& d2,
                                          const VoxelImage& img, std::uint8_t pore) {
  PoreSizeDistribution p;
  const std::uint8_t* v = img.values().data();
  double sum = 0.0;
  std::uint32_t maxD2 = 0;
  for (size_t i = 0; i < d2.size(); ++i)
    if (v[i] == pore && d2[i] != kNoSolid) maxD2 = std::max(maxD2, d2[i]);
  // A dense histogram (max d2 <= nx^2 + ny^2 + nz^2, small next to the image) when it fits.
  std::vector<std::pair<std::uint32_t, std::int64_t>> entries;
  if (maxD2 < (1u << 26)) {
    std::vector<std::int64_t> dense(static_cast<size_t>(maxD2) + 1, 0);
    for (size_t i = 0; i < d2.size(); ++i)
      if (v[i] == pore && d2[i] != kNoSolid) ++dense[d2[i]];
    for (size_t k = 0; k < dense.size(); ++k)
      if (dense[k]) entries.emplace_back(static_cast<std::uint32_t>(k), dense[k]);
  } else {
    std::map<std::uint32_t, std::int64_t> h;
    for (size_t i = 0; i < d2.size(); ++i)
      if (v[i] == pore && d2[i] != kNoSolid) ++h[d2[i]];
    entries.assign(h.begin(), h.end());
  }
  for (const auto& [k, c] : entries) {
    p.histogram.emplace_back(k, c);
    p.poreVoxels += c;
    sum += std::sqrt(static_cast<double>(k)) * static_cast<double>(c);
  }
  if (p.poreVoxels == 0) return p;
  p.meanRadius = sum / static_cast<double>(p.poreVoxels);
  p.maxRadius = std::sqrt(static_cast<double>(p.histogram.back().first));
  std::int64_t acc = 0;
  for (const auto& [k, c] : p.histogram) {
    acc += c;
    if (2 * acc >= p.poreVoxels) {
      p.medianRadius = std::sqrt(static_cast<double>(k));
      break;
    }
  }
  return p;
}

std::array<Index, 3> percolatingClusterCount(const VoxelImage& img,
                                             const std::vector<std::int32_t>& labels) {
  std::array<Index, 3> out{0, 0, 0};
  const int n[3] = {img.nx(), img.ny(), img.nz()};
  std::int32_t maxLabel = -1;
  for (auto l : labels) maxLabel = std::max(maxLabel, l);
  if (maxLabel < 0) return out;
  std::vector<std::uint8_t> seen(static_cast<size_t>(maxLabel) + 1);
  for (int axis = 0; axis < 3; ++axis) {
    std::fill(seen.begin(), seen.end(), 0);
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side)
      for (int u = 0; u < n[a1]; ++u)
        for (int w = 0; w < n[a2]; ++w) {
          int c[3];
          c[a1] = u;
          c[a2] = w;
          c[axis] = side == 0 ? 0 : n[axis] - 1;
          const std::int32_t l = labels[static_cast<size_t>(img.linear(c[0], c[1], c[2]))];
          if (l < 0) continue;
          auto& s = seen[static_cast<size_t>(l)];
          if (side == 0) s = 1;
          else if (s == 1) s = 2;
        }
    for (auto s : seen) out[static_cast<size_t>(axis)] += s == 2;
  }
  return out;
}

void writeLabelledVti(const std::string& path, const VoxelImage& img, double voxelSize,
                      const std::vector<VoxelField>& extra) {
  vtkNew<vtkImageData> g;
  g->SetDimensions(img.nx() + 1, img.ny() + 1, img.flat() ? 1 : img.nz() + 1);
  const double h = voxelSize > 0 ? voxelSize : 1.0;
  g->SetSpacing(h, h, h);
  const Index n = img.voxelCount();
  vtkNew<vtkUnsignedCharArray> lab;
  lab->SetName("label");
  lab->SetNumberOfTuples(n);
  std::memcpy(lab->GetPointer(0), img.values().data(), static_cast<size_t>(n));
  g->GetCellData()->AddArray(lab);
  for (const auto& e : extra) {
    if (e.ints) {
      vtkNew<vtkIntArray> a;
      a->SetName(e.name.c_str());
      a->SetNumberOfTuples(n);
      std::memcpy(a->GetPointer(0), e.ints->data(), static_cast<size_t>(n) * 4);
      g->GetCellData()->AddArray(a);
    } else if (e.reals) {
      vtkNew<vtkFloatArray> a;
      a->SetName(e.name.c_str());
      a->SetNumberOfTuples(n);
      std::memcpy(a->GetPointer(0), e.reals->data(), static_cast<size_t>(n) * 4);
      g->GetCellData()->AddArray(a);
    }
  }
  g->GetCellData()->SetActiveScalars("label");
  vtkNew<vtkXMLImageDataWriter> w;
  w->SetFileName(path.c_str());
  w->SetInputData(g);
  w->SetDataModeToAppended();
  w->SetCompressorTypeToZLib();
  if (w->Write() != 1) throw InputError("'" + path + "': cannot write the .vti file");
}

namespace {
/// splitmix64 (Steele, Lea, Flood 2014): a fixed sequence on every platform.
struct SplitMix {
  std::uint64_t s;
  std::uint64_t next() {
    std::uint64_t z = (s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
};

/// Paints label `to` over voxels of label `from` within radius r of c; returns how many changed.
Index paintBall(VoxelImage& img, const double c[3], double r, std::uint8_t from, std::uint8_t to,
                Index limit) {
  Index changed = 0;
  const int n[3] = {img.nx(), img.ny(), img.nz()};
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(0, static_cast<int>(std::floor(c[a] - r)));
    hi[a] = std::min(n[a] - 1, static_cast<int>(std::ceil(c[a] + r)));
  }
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x) {
        const double dx = x + 0.5 - c[0], dy = y + 0.5 - c[1], dz = img.flat() ? 0.0 : z + 0.5 - c[2];
        if (dx * dx + dy * dy + dz * dz > r * r) continue;
        auto& v = img.at(x, y, z);
        if (v != from || changed >= limit) continue;
        v = to;
        ++changed;
      }
  return changed;
}
}  // namespace

VoxelImage synthClay(const SynthClayOptions& o) {
  if (!(o.porosity >= 0 && o.inclusionFraction >= 0 && o.porosity + o.inclusionFraction < 1.0))
    throw InputError("synthetic clay: porosity and inclusion fraction must be >= 0 with a sum below 1");
  if (!(o.poreRadius >= 0.5) || !(o.inclusionRadius >= 0.5))
    throw InputError("synthetic clay: pore and inclusion radii must be at least 0.5 voxel");
  VoxelImage img(o.n[0], o.n[1], o.n[2], 1);
  SplitMix rng{o.seed};
  const Index total = img.voxelCount();
  auto fill = [&](double fraction, double radius, std::uint8_t label) {
    const Index target = static_cast<Index>(std::llround(fraction * static_cast<double>(total)));
    Index have = 0;
    for (long tries = 0; have < target; ++tries) {
      if (tries > 100 * total + 1000)
        throw InputError("synthetic clay: cannot reach the requested fraction");
      double c[3];
      for (int a = 0; a < 3; ++a) c[a] = rng.uniform() * (a == 0 ? o.n[0] : a == 1 ? o.n[1] : o.n[2]);
      if (img.flat()) c[2] = 0.5;
      // The last ball is cut at the target count (voxels in scan order), so the fraction is exact.
      have += paintBall(img, c, radius, 1, label, target - have);
    }
  };
  fill(o.inclusionFraction, o.inclusionRadius, 2);
  fill(o.porosity, o.poreRadius, 0);
  return img;
}

}  // namespace poresph
