#include "libcore/image_scene.hpp"

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "libcore/image_analysis.hpp"
#include "libcore/image_io.hpp"

namespace fs = std::filesystem;

namespace poresph {

namespace {

std::string num(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

YAML::Node flow(const std::vector<double>& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (double x : v) n.push_back(num(x));
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

int axisIndex(const ParameterSet& p, const std::string& key) {
  const std::string a = p.choice(key, {"x", "y", "z"});
  return a == "x" ? 0 : a == "y" ? 1 : 2;
}

}  // namespace

void appendImageRegions(const ParameterSet& g, const Simulation& sim, std::vector<Region>& regions,
                        YAML::Node& echo) {
  const int dim = sim.dimension();
  if (dim < 2) g.fail("shape", "an image needs a 2D or 3D scene");
  echo["shape"] = "image";

  // ---- the file ----
  ImageFileSpec spec;
  const std::string file = g.string("file");
  const fs::path p(file);
  spec.path = p.is_absolute() ? file : (fs::path(g.file()).parent_path() / p).lexically_normal().string();
  if (spec.path.empty()) spec.path = file;
  try {
    spec.format = g.has("format") ? g.choice("format", imageFormats()) : detectImageFormat(spec.path);
  } catch (const InputError& e) {
    g.fail("file", e.what());
  }
  if (!g.has("format")) g.string("format", "");
  std::error_code ec;
  echo["file"] = fs::absolute(spec.path, ec).lexically_normal().string();  // run.yaml elsewhere
  echo["format"] = spec.format;
  if (spec.format == "raw") {
    const auto size = g.reals("size", 3, Range{1.0, 2147483647.0, false, false});
    for (int a = 0; a < 3; ++a) {
      const double s = size[static_cast<size_t>(a)];
      if (s != std::floor(s)) g.fail("size", "expected whole numbers of voxels along x, y, z");
      spec.shape[static_cast<size_t>(a)] = static_cast<int>(s);
    }
    try {
      spec.type = parseVoxelType(g.string("voxel_type", "uint8"), g.where("voxel_type"));
    } catch (const InputError& e) {
      throw InputError(e.what());
    }
    spec.bigEndian = g.choice("byte_order", "little", {"little", "big"}) == "big";
    spec.headerBytes = static_cast<std::uint64_t>(g.integer("header_bytes", 0, 0, 1L << 40));
    echo["size"] = flow(size);
    echo["voxel_type"] = voxelTypeName(spec.type);
    echo["byte_order"] = spec.bigEndian ? "big" : "little";
    if (spec.headerBytes) echo["header_bytes"] = static_cast<long>(spec.headerBytes);
  } else {
    for (const char* key : {"size", "voxel_type", "byte_order", "header_bytes"})
      if (g.has(key)) g.fail(key, "only a raw image takes it (its header gives it): remove it");
  }
  spec.dataset = g.string("dataset", "");
  if (!spec.dataset.empty()) echo["dataset"] = spec.dataset;

  // ---- labels -> materials: member 0.. per distinct material, ImageGrid::kNoMember for none ----
  std::vector<int> memberMaterial;
  auto memberOf = [&](const std::string& key, const std::string& name) -> int {
    if (name == "none") return ImageGrid::kNoMember;
    int id = -1;
    std::string names;
    for (const auto& m : sim.materials) {
      if (m.name == name) id = m.id;
      names += (names.empty() ? "" : ", ") + m.name;
    }
    if (id < 0)
      g.fail(key, "no material named '" + name + "' (defined: " + names + "; or 'none' for no particle)");
    for (size_t k = 0; k < memberMaterial.size(); ++k)
      if (memberMaterial[k] == id) return static_cast<int>(k);
    memberMaterial.push_back(id);
    if (memberMaterial.size() >= ImageGrid::kNoMember) g.fail(key, "too many materials");
    return static_cast<int>(memberMaterial.size()) - 1;
  };
  LabelRule rule;
  if (g.has("labels") == g.has("threshold"))
    g.fail(g.has("labels") ? "threshold" : "labels",
           "give either labels (file value -> material, e.g. {0: water, 255: clay}) or threshold "
           "({level: L, below: material, above: material}), not both and not neither");
  if (g.has("labels")) {
    const YAML::Node labels = g.raw("labels");
    if (!labels.IsMap() || labels.size() == 0)
      g.fail("labels", "expected a mapping of file value -> material name, e.g. {0: water, 255: clay}");
    YAML::Node e(YAML::NodeType::Map);
    for (const auto& kv : labels) {
      double value = 0.0;
      if (!kv.first.IsScalar() || !YAML::convert<double>::decode(kv.first, value) || !std::isfinite(value))
        g.fail("labels", "the key '" + (kv.first.IsScalar() ? kv.first.Scalar() : std::string("?")) +
                             "' is not a number (keys are the file's voxel values)");
      if (!kv.second.IsScalar()) g.fail("labels", "the value of " + kv.first.Scalar() + " must be a material name");
      rule.map.emplace_back(value, memberOf("labels", kv.second.Scalar()));
      e[kv.first.Scalar()] = kv.second.Scalar();
    }
    echo["labels"] = e;
  } else {
    const ParameterSet t = g.section("threshold");
    rule.threshold = true;
    rule.level = t.real("level");
    rule.below = memberOf("threshold", t.string("below"));
    rule.above = memberOf("threshold", t.string("above"));
    t.finish();
    echo["threshold"]["level"] = num(rule.level);
    echo["threshold"]["below"] = g.raw("threshold")["below"].Scalar();
    echo["threshold"]["above"] = g.raw("threshold")["above"].Scalar();
  }
  rule.requireEveryLabel = !g.boolean("allow_empty_labels", false);
  echo["allow_empty_labels"] = !rule.requireEveryLabel;

  // ---- read, label, crop, slice, coarsen ----
  auto imageError = [&](const std::string& key, const InputError& e) -> void {
    throw InputError(g.where(key) + ": " + e.what());
  };
  VoxelImage img;
  try {
    img = applyLabels(readVolume(spec, 1), rule);
  } catch (const InputError& e) {
    imageError("file", e);
  }
  if (g.has("crop")) {
    const ParameterSet c = g.section("crop");
    const auto lo = c.reals("lo", 3, Range::nonNegative());
    const auto size = c.reals("size", 3, Range{1.0, 2147483647.0, false, false});
    c.finish();
    try {
      img = img.crop(static_cast<int>(lo[0]), static_cast<int>(lo[1]), static_cast<int>(lo[2]),
                     static_cast<int>(size[0]), static_cast<int>(size[1]), static_cast<int>(size[2]));
    } catch (const InputError& e) {
      imageError("crop", e);
    }
    echo["crop"]["lo"] = flow(lo);
    echo["crop"]["size"] = flow(size);
  }
  if (g.has("slice")) {
    const ParameterSet s = g.section("slice");
    const int axis = axisIndex(s, "axis");
    const int index = static_cast<int>(s.integer("index", 0, 2147483647));
    s.finish();
    try {
      img = sliceImage(img, axis, index);
    } catch (const InputError& e) {
      imageError("slice", e);
    }
    echo["slice"]["axis"] = std::string(1, "xyz"[axis]);
    echo["slice"]["index"] = index;
  }
  const int coarsen = static_cast<int>(g.integer("coarsen", 1, 1, 1024));
  try {
    img = coarsenImage(img, coarsen);
  } catch (const InputError& e) {
    imageError("coarsen", e);
  }
  echo["coarsen"] = coarsen;
  if (dim == 2 && !img.flat())
    g.fail("shape", "a 2D scene needs a 2D image: the image is " + std::to_string(img.nx()) + " x " +
                        std::to_string(img.ny()) + " x " + std::to_string(img.nz()) +
                        " voxels; add slice: {axis: z, index: N}");

  // ---- voxel size and placement ----
  const double dx = sim.spacing;
  if (g.has("voxel_size")) {
    const double vs = g.real("voxel_size", Range::positive());
    if (std::abs(vs * coarsen - dx) > 1e-9 * dx)
      g.fail("voxel_size", "voxel_size x coarsen = " + num(vs * coarsen) +
                               " m must equal the scene's spacing " + num(dx) +
                               " m (one particle per coarsened voxel): set spacing: " +
                               num(vs * coarsen) + " or coarsen by spacing / voxel_size");
    echo["voxel_size"] = num(vs);
  } else {
    echo["voxel_size"] = num(dx / coarsen);
  }
  auto grid = std::make_shared<ImageGrid>();
  grid->n = {img.nx(), img.ny(), img.nz()};
  grid->voxel = dx;
  std::vector<double> origin(static_cast<size_t>(dim));
  for (int a = 0; a < dim; ++a) origin[static_cast<size_t>(a)] = sim.domain.lo[static_cast<size_t>(a)];
  if (g.has("origin")) origin = g.reals("origin", static_cast<size_t>(dim));
  for (int a = 0; a < dim; ++a) {
    const double cells = (origin[static_cast<size_t>(a)] - sim.domain.lo[static_cast<size_t>(a)]) / dx;
    if (std::abs(cells - std::round(cells)) > 1e-6)
      g.fail("origin", std::string("must lie on the lattice: (origin - domain.lo) / spacing along ") +
                           "xyz"[a] + " is " + num(cells) + ", not a whole number");
    grid->origin[static_cast<size_t>(a)] = origin[static_cast<size_t>(a)];
  }
  echo["origin"] = flow(origin);
  grid->member.assign(img.values().begin(), img.values().end());  // labels are members already
  grid->members = static_cast<int>(memberMaterial.size());
  if (grid->members == 0) g.fail("labels", "maps every value to none: the image holds no particle");

  Region base;
  base.shape = Region::Shape::Image;
  base.where = g.where("shape");
  for (int a = 0; a < dim; ++a) {
    base.lo[static_cast<size_t>(a)] = grid->origin[static_cast<size_t>(a)];
    base.hi[static_cast<size_t>(a)] =
        grid->origin[static_cast<size_t>(a)] + dx * grid->n[static_cast<size_t>(a)];
  }
  const std::string motion = g.choice("motion", "free", {"free", "fixed", "prescribed"});
  base.motion = motion == "fixed" ? kMotionFixed : motion == "prescribed" ? kMotionPrescribed : kMotionFree;
  if (g.has("velocity")) {
    const auto v = g.reals("velocity", static_cast<size_t>(dim));
    for (int a = 0; a < dim; ++a) base.velocity[static_cast<size_t>(a)] = v[static_cast<size_t>(a)];
    echo["velocity"] = flow(v);
  }
  echo["motion"] = motion;
  YAML::Node shape(YAML::NodeType::Sequence);
  for (int a = 0; a < 3; ++a) shape.push_back(grid->n[static_cast<size_t>(a)]);
  shape.SetStyle(YAML::EmitterStyle::Flow);
  echo["voxels"] = shape;
  base.image = grid;
  for (int m = 0; m < grid->members; ++m) {
    Region r = base;
    r.material = memberMaterial[static_cast<size_t>(m)];
    r.imageMember = m;
    regions.push_back(r);
  }
}

}  // namespace poresph
