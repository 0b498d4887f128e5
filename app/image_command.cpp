// `poresph image` (statistics of a segmented or grey image) and `poresph synth` (the seeded
// synthetic clay-like image); docs/voxel-images.md, docs/cli.md.
#include <cmath>
#include <ctime>
#include <sstream>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>

#include "app/commands.hpp"
#include "libcore/image_analysis.hpp"
#include "libcore/image_io.hpp"
#include "libcore/voxel_image.hpp"

namespace poresph::app {

long long wholeNumber(const std::string& option, const std::string& text, long long lo,
                      long long hi, const std::string& rule) {
  std::size_t used = 0;
  long long value = 0;
  try {
    value = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || value < lo || value > hi)
    throw InputError(option + ": " + rule + ", got " + (text.empty() ? "an empty value" : text));
  return value;
}

namespace {

double realOption(const std::string& option, const std::string& text, bool positive) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(v) || (positive && !(v > 0)))
    throw InputError(option + ": expected " + (positive ? "a positive number" : "a number") +
                     ", got " + (text.empty() ? "an empty value" : text));
  return v;
}

struct ImageOptions {
  std::string path, format, type = "uint8", byteOrder = "little", headerBytes = "0", dataset;
  std::vector<std::string> shape, crop, slice;
  std::string poreLabel = "0", threshold, connectivity, coarsen = "1", voxelSize;
  bool poreAbove = false;
  std::string psd, vti;
};

void printStats(PoreStatistics s, const std::array<Index, 3>& perc, bool flat) {
  if (flat) s.largestPercolates[2] = false;  // a 2D image has no z faces to connect
  std::cout << "clusters:     " << s.clusters << " (" << s.connectivity << "-connected)\n"
            << "largest:      " << s.largestCluster << " voxels, " << s.largestFraction
            << " of the pore space, percolates along" << (s.largestPercolates[0] ? " x" : "")
            << (s.largestPercolates[1] ? " y" : "") << (s.largestPercolates[2] ? " z" : "")
            << (s.largestPercolates[0] || s.largestPercolates[1] || s.largestPercolates[2] ? ""
                                                                                        : " no axis")
            << "\n"
            << "percolating:  clusters touching both faces: x " << perc[0] << ", y " << perc[1];
  if (!flat) std::cout << ", z " << perc[2];
  std::cout << "\n";
}

int runImage(const ImageOptions& o) {
  // CPU seconds per phase, printed at the end (docs/voxel-images.md quotes them).
  std::clock_t mark = std::clock();
  std::string cpu;
  auto phase = [&](const std::string& name) {
    const std::clock_t now = std::clock();
    std::ostringstream t;
    t << std::setprecision(2) << std::fixed << double(now - mark) / CLOCKS_PER_SEC;
    cpu += (cpu.empty() ? "" : ", ") + name + " " + t.str() + " s";
    mark = now;
  };
  // ---- what to read ----
  const bool plainRaw8 = (o.format.empty() || o.format == "raw") && o.type == "uint8" &&
                         o.headerBytes == "0" && o.byteOrder == "little";
  ImageFileSpec spec;
  spec.path = o.path;
  spec.format = o.format.empty() ? detectImageFormat(o.path) : o.format;
  if (!o.shape.empty()) {
    if (spec.format != "raw") throw InputError("--shape: only a raw image takes it ('" + o.path + "' is read as " + spec.format + ", which gives its own shape)");
    for (int a = 0; a < 3; ++a)
      spec.shape[static_cast<size_t>(a)] = static_cast<int>(wholeNumber(
          "--shape", o.shape[static_cast<size_t>(a)], 1, std::numeric_limits<int>::max(),
          "every size must be a positive whole number of at most " +
              std::to_string(std::numeric_limits<int>::max()) + " voxels"));
  } else if (spec.format == "raw") {
    throw InputError("--shape NX NY NZ: a headerless raw image needs its shape");
  }
  spec.type = parseVoxelType(o.type, "--type");
  if (o.byteOrder != "little" && o.byteOrder != "big")
    throw InputError("--byte-order: must be little or big, got " + o.byteOrder);
  spec.bigEndian = o.byteOrder == "big";
  spec.headerBytes = static_cast<std::uint64_t>(
      wholeNumber("--header-bytes", o.headerBytes, 0, std::numeric_limits<long long>::max(),
                  "must be a whole number >= 0"));
  spec.dataset = o.dataset;
  const int connectivity =
      o.connectivity.empty()
          ? 0
          : static_cast<int>(wholeNumber("--connectivity", o.connectivity, 6, 26, "must be 6, 18 or 26"));
  if (connectivity != 0 && connectivity != 6 && connectivity != 18 && connectivity != 26)
    throw InputError("--connectivity: must be 6, 18 or 26, got " + o.connectivity);
  const int coarsen = static_cast<int>(wholeNumber("--coarsen", o.coarsen, 1, 1024, "must be a whole number from 1 to 1024"));
  const double voxelSize = o.voxelSize.empty() ? 0.0 : realOption("--voxel-size", o.voxelSize, true);

  // ---- read and label: pore voxels -> 0, the rest -> 1 (or the file's labels for plain raw) ----
  VoxelImage img;
  std::uint8_t pore = 0;
  std::string labelText;
  if (plainRaw8 && o.threshold.empty()) {
    // The historical path: every check before the image is allocated, the labels' 4 bytes per
    // voxel included (docs/voxel-images.md).
    pore = static_cast<std::uint8_t>(
        wholeNumber("--pore-label", o.poreLabel, 0, 255, "must be a whole number from 0 to 255"));
    img = VoxelImage::readRaw(o.path, spec.shape[0], spec.shape[1], spec.shape[2], kLabelBytesPerVoxel);
    labelText = "pore label " + std::to_string(pore);
  } else if (!o.threshold.empty()) {
    LabelRule rule;
    rule.requireEveryLabel = false;
    rule.threshold = true;
    rule.level = realOption("--threshold", o.threshold, false);
    rule.below = o.poreAbove ? 1 : 0;
    rule.above = o.poreAbove ? 0 : 1;
    labelText = std::string("pore = values ") + (o.poreAbove ? ">= " : "< ") + o.threshold;
    img = applyLabels(readVolume(spec, kLabelBytesPerVoxel), rule);
  } else {
    const long long lo = spec.type == VoxelType::Int32 ? std::numeric_limits<std::int32_t>::min() : 0;
    const long long hi = spec.type == VoxelType::UInt8    ? 255
                         : spec.type == VoxelType::UInt16 ? 65535
                                                          : std::numeric_limits<std::int32_t>::max();
    const double label =
        spec.type == VoxelType::Float32
            ? realOption("--pore-label", o.poreLabel, false)
            : static_cast<double>(wholeNumber("--pore-label", o.poreLabel, lo, hi,
                                              "must be a whole number from " + std::to_string(lo) +
                                                  " to " + std::to_string(hi)));
    // Pore voxels -> 0, every other value -> 1.
    const RawVolume v = readVolume(spec, kLabelBytesPerVoxel);
    img = VoxelImage(v.n[0], v.n[1], v.n[2], 1);
    std::uint8_t* out = img.data();
    for (Index i = 0; i < v.voxelCount(); ++i) out[i] = v.value(i) == label ? 0 : 1;
    labelText = "pore label " + o.poreLabel;
  }
  phase("read");
  std::cout << "image:        " << o.path << " (" << img.nx() << " x " << img.ny() << " x " << img.nz()
            << " voxels, " << labelText << ")\n";
  if (!o.crop.empty()) {
    int c[6];
    for (int k = 0; k < 6; ++k)
      c[k] = static_cast<int>(wholeNumber("--crop", o.crop[static_cast<size_t>(k)], k < 3 ? 0 : 1,
                                          std::numeric_limits<int>::max(), "X0 Y0 Z0 SX SY SZ are whole numbers (sizes >= 1)"));
    img = img.crop(c[0], c[1], c[2], c[3], c[4], c[5]);
    std::cout << "crop:         from (" << c[0] << ", " << c[1] << ", " << c[2] << "), " << c[3] << " x "
              << c[4] << " x " << c[5] << "\n";
  }
  if (!o.slice.empty()) {
    const std::string& ax = o.slice[0];
    if (ax != "x" && ax != "y" && ax != "z") throw InputError("--slice: the axis must be x, y or z, got " + ax);
    const int index = static_cast<int>(wholeNumber("--slice", o.slice[1], 0, std::numeric_limits<int>::max(), "the index must be a whole number >= 0"));
    img = sliceImage(img, ax == "x" ? 0 : ax == "y" ? 1 : 2, index);
    std::cout << "slice:        normal to " << ax << " at " << index << " -> " << img.nx() << " x " << img.ny() << "\n";
  }
  if (coarsen > 1) {
    img = coarsenImage(img, coarsen);
    std::cout << "coarsen:      " << coarsen << " (majority vote) -> " << img.nx() << " x " << img.ny()
              << " x " << img.nz() << "\n";
  }

  // ---- statistics: 6- and 26-connected clusters (or the one asked for) ----
  const std::vector<int> conns = connectivity ? std::vector<int>{connectivity} : std::vector<int>{6, 26};
  std::vector<std::int32_t> keptLabels;
  for (size_t k = 0; k < conns.size(); ++k) {
    Index count = 0;
    std::vector<Index> sizes;
    std::vector<std::int32_t> labels = labelPoreClusters(img, pore, &count, conns[k], &sizes);
    PoreStatistics s;
    s.connectivity = conns[k];
    s.voxels = img.voxelCount();
    for (Index c : sizes) s.poreVoxels += c;
    s.porosity = s.voxels ? double(s.poreVoxels) / double(s.voxels) : 0.0;
    s.clusters = count;
    if (count > 0) {
      s.largestCluster = sizes[0];
      s.largestFraction = double(sizes[0]) / double(s.poreVoxels);
    }
    std::array<Index, 3> perc = percolatingClusterCount(img, labels);
    // Largest cluster percolation: cluster 0 on both faces.
    if (count > 0) {
      const int n[3] = {img.nx(), img.ny(), img.nz()};
      for (int axis = 0; axis < 3; ++axis) {
        bool lo = false, hi = false;
        const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
        for (int u = 0; u < n[a1]; ++u)
          for (int w = 0; w < n[a2]; ++w) {
            int c[3];
            c[a1] = u;
            c[a2] = w;
            c[axis] = 0;
            lo = lo || labels[static_cast<size_t>(img.linear(c[0], c[1], c[2]))] == 0;
            c[axis] = n[axis] - 1;
            hi = hi || labels[static_cast<size_t>(img.linear(c[0], c[1], c[2]))] == 0;
          }
        s.largestPercolates[static_cast<size_t>(axis)] = lo && hi;
      }
    }
    if (k == 0)
      std::cout << "pore voxels:  " << s.poreVoxels << " of " << s.voxels << "\n"
                << "porosity:     " << s.porosity << "\n";
    printStats(s, perc, img.flat());
    phase("clusters (" + std::to_string(conns[k]) + ")");
    if (k == 0 && !o.vti.empty()) keptLabels = std::move(labels);
  }

  // ---- pore sizes from the exact distance transform ----
  std::vector<std::uint32_t> d2 = squaredDistanceToSolid(img, pore);
  const PoreSizeDistribution p = poreSizeDistribution(d2, img, pore);
  phase("distance transform");
  const double unit = voxelSize > 0 ? voxelSize * coarsen : 0.0;
  std::cout << std::setprecision(6) << "pore size:    radius (distance to the nearest solid voxel centre) mean "
            << p.meanRadius << ", median " << p.medianRadius << ", max " << p.maxRadius << " voxels";
  if (unit > 0) std::cout << " (" << p.meanRadius * unit << ", " << p.medianRadius * unit << ", " << p.maxRadius * unit << " m)";
  std::cout << "\n";
  if (!o.psd.empty()) {
    std::ofstream f(o.psd);
    f << "squared_distance_voxels,radius_voxels" << (unit > 0 ? ",radius_m" : "") << ",voxels,fraction,cumulative_fraction\n";
    std::int64_t acc = 0;
    f << std::setprecision(10);
    for (const auto& [k, c] : p.histogram) {
      acc += c;
      const double r = std::sqrt(double(k));
      f << k << "," << r;
      if (unit > 0) f << "," << r * unit;
      f << "," << c << "," << double(c) / double(p.poreVoxels) << "," << double(acc) / double(p.poreVoxels) << "\n";
    }
    if (!f) throw InputError("--psd '" + o.psd + "': cannot write the file");
    std::cout << "pore sizes:   " << o.psd << " (" << p.histogram.size() << " distances)\n";
  }
  if (!o.vti.empty()) {
    std::vector<float> dist(d2.size());
    for (size_t i = 0; i < d2.size(); ++i) dist[i] = d2[i] == kNoSolid ? -1.0f : std::sqrt(static_cast<float>(d2[i]));
    d2 = {};
    const std::string cname = "cluster_" + std::to_string(conns[0]);
    writeLabelledVti(o.vti, img, unit, {{cname, &keptLabels, nullptr}, {"pore_radius", nullptr, &dist}});
    std::cout << "ParaView:     " << o.vti << " (cell data: label, " << cname << " (-1 solid), pore_radius in voxels)\n";
  }
  phase("output");
  std::cout << "cpu time:     " << cpu << "\n";
  return 0;
}

struct SynthOptions {
  std::string out, porosity = "0.15", poreRadius = "2.5", inclusion = "0.10", inclusionRadius = "4",
              seed = "1", format;
  std::vector<std::string> shape{"48", "48", "48"};
};

int runSynth(const SynthOptions& o) {
  SynthClayOptions s;
  for (int a = 0; a < 3; ++a)
    s.n[static_cast<size_t>(a)] = static_cast<int>(wholeNumber("--shape", o.shape[static_cast<size_t>(a)], 1, 4096, "sizes are whole numbers from 1 to 4096"));
  s.porosity = realOption("--porosity", o.porosity, false);
  s.poreRadius = realOption("--pore-radius", o.poreRadius, true);
  s.inclusionFraction = realOption("--inclusion-fraction", o.inclusion, false);
  s.inclusionRadius = realOption("--inclusion-radius", o.inclusionRadius, true);
  s.seed = static_cast<std::uint64_t>(wholeNumber("--seed", o.seed, 0, std::numeric_limits<long long>::max(), "must be a whole number >= 0"));
  const VoxelImage img = synthClay(s);
  RawVolume v;
  v.n = {img.nx(), img.ny(), img.nz()};
  v.type = VoxelType::UInt8;
  v.bytes.assign(img.values().begin(), img.values().end());
  const std::string fmt = o.format.empty() ? detectImageFormat(o.out) : o.format;
  writeVolume(v, o.out, fmt);
  Index count[3] = {0, 0, 0};
  for (auto x : img.values()) ++count[x];
  const double n = static_cast<double>(img.voxelCount());
  std::cout << "synthetic clay: " << o.out << " (" << v.n[0] << " x " << v.n[1] << " x " << v.n[2]
            << " uint8, x fastest; labels 0 pore, 1 clay, 2 inclusion)\n"
            << "pore " << count[0] << " (" << count[0] / n << "), clay " << count[1] << " ("
            << count[1] / n << "), inclusion " << count[2] << " (" << count[2] / n << ")\n";
  return 0;
}

}  // namespace

Command addImageCommand(CLI::App& app) {
  auto o = std::make_shared<ImageOptions>();
  CLI::App* c = app.add_subcommand("image", "Statistics of a segmented or grey voxel image");
  c->add_option("file", o->path, "Image file (raw, .mhd, .nhdr/.nrrd, .tif or a folder of them, .vti, .h5)")->required();
  c->add_option("--format", o->format, "raw, mhd, nhdr, tiff, vti, hdf5 (default: from the extension)");
  c->add_option("--shape", o->shape, "Raw image: voxels along x, y, z")->expected(3);
  c->add_option("--type", o->type, "Raw image: uint8 (default), uint16, int32, float32");
  c->add_option("--byte-order", o->byteOrder, "Raw image: little (default) or big");
  c->add_option("--header-bytes", o->headerBytes, "Raw image: bytes before the voxels (default 0)");
  c->add_option("--dataset", o->dataset, "HDF5 dataset or .vti array (default: the only one)");
  c->add_option("--pore-label", o->poreLabel, "Voxel value of the pore space (default 0)");
  c->add_option("--threshold", o->threshold, "Grey image: pore = values below T (see --pore-above)");
  c->add_flag("--pore-above", o->poreAbove, "With --threshold: pore = values at or above T");
  c->add_option("--connectivity", o->connectivity,
                "Only this connectivity: 6 (faces), 18 (edges), 26 (corners); default 6 and 26");
  c->add_option("--crop", o->crop, "Sub-volume X0 Y0 Z0 SX SY SZ (voxels)")->expected(6);
  c->add_option("--slice", o->slice, "A 2D plane: AXIS INDEX (e.g. z 64)")->expected(2);
  c->add_option("--coarsen", o->coarsen, "Coarsen by a whole factor (majority vote)");
  c->add_option("--voxel-size", o->voxelSize, "Voxel edge in metres (pore sizes also in m)");
  c->add_option("--psd", o->psd, "Write the pore-size distribution (CSV)");
  c->add_option("--vti", o->vti, "Write a labelled .vti for ParaView (label, clusters, pore radius)");
  return {c, [o] { return runImage(*o); }};
}

Command addSynthCommand(CLI::App& app) {
  auto o = std::make_shared<SynthOptions>();
  CLI::App* c = app.add_subcommand("synth", "Write a seeded synthetic clay-like image (labels 0 pore, 1 clay, 2 inclusion)");
  c->add_option("out", o->out, "Output image (.raw, .tif, .vti, .h5, ...)")->required();
  c->add_option("--shape", o->shape, "Voxels along x, y, z (default 48 48 48; z = 1 for 2D)")->expected(3);
  c->add_option("--porosity", o->porosity, "Pore volume fraction (default 0.15)");
  c->add_option("--pore-radius", o->poreRadius, "Pore sphere radius in voxels (default 2.5)");
  c->add_option("--inclusion-fraction", o->inclusion, "Inclusion volume fraction (default 0.10)");
  c->add_option("--inclusion-radius", o->inclusionRadius, "Inclusion sphere radius in voxels (default 4)");
  c->add_option("--seed", o->seed, "Random seed (default 1)");
  c->add_option("--format", o->format, "Output format (default: from the extension)");
  return {c, [o] { return runSynth(*o); }};
}

}  // namespace poresph::app
