#include "libcore/image_io.hpp"

#include <hdf5.h>
#include <vtkCallbackCommand.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkExecutive.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnsignedShortArray.h>
#include <vtkIntArray.h>
#include <vtkFloatArray.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLImageDataWriter.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "libcore/memory.hpp"

namespace fs = std::filesystem;

namespace poresph {

namespace {

std::string shapeText(const std::array<int, 3>& n) {
  return std::to_string(n[0]) + " x " + std::to_string(n[1]) + " x " + std::to_string(n[2]);
}

std::string numText(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

bool hostBigEndian() {
  const std::uint16_t one = 1;
  unsigned char c;
  std::memcpy(&c, &one, 1);
  return c == 0;
}

/// Voxel count of the shape (each size positive, at most kMaxVoxels), else InputError.
Index checkedCount(const std::array<int, 3>& n, const std::string& what) {
  if (n[0] <= 0 || n[1] <= 0 || n[2] <= 0)
    throw InputError(what + ": every size must be positive, got " + shapeText(n));
  std::int64_t xy = 0, xyz = 0;
  if (__builtin_mul_overflow(std::int64_t{n[0]}, std::int64_t{n[1]}, &xy) ||
      __builtin_mul_overflow(xy, std::int64_t{n[2]}, &xyz) || xyz > kMaxVoxels)
    throw InputError(what + ": the shape " + shapeText(n) + " has more than 2^48 voxels");
  return xyz;
}

void checkMemory(Index voxels, int bytesPerVoxel, std::uint64_t extra, const std::string& what) {
  const std::uint64_t per = static_cast<std::uint64_t>(bytesPerVoxel) + 1 + extra;
  std::uint64_t need = 0;
  if (__builtin_mul_overflow(static_cast<std::uint64_t>(voxels), per, &need))
    need = std::numeric_limits<std::uint64_t>::max();
  const std::uint64_t avail = availableMemoryBytes();
  if (avail != 0 && need > avail)
    throw InputError(what + ": needs " + formatBytes(need) + " of memory (" + std::to_string(per) +
                     " bytes per voxel) but only " + formatBytes(avail) +
                     " is available (MemAvailable in /proc/meminfo)");
}

std::uintmax_t fileSize(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(what + ": is a folder, not a file");
  const auto size = fs::file_size(path, ec);
  if (ec) throw InputError(what + ": cannot read the file (" + ec.message() + ")");
  return size;
}

void swapBytes(std::vector<unsigned char>& b, int width) {
  if (width == 1) return;
  for (size_t i = 0; i + static_cast<size_t>(width) <= b.size(); i += static_cast<size_t>(width))
    std::reverse(b.begin() + static_cast<long>(i), b.begin() + static_cast<long>(i) + width);
}

/// Reads `count` voxels of `type` from `path` at `offset` into v (allocating it), after checking
/// that the file holds exactly (or, with exact = false, at least) offset + count x bytes.
void readBlock(RawVolume& v, const std::string& path, std::uint64_t offset, bool bigEndian,
               bool exact, std::uint64_t extra, const std::string& detail) {
  const Index n = checkedCount(v.n, v.source);
  const int w = voxelTypeBytes(v.type);
  const std::uintmax_t size = fileSize(path, "image '" + path + "'");
  const std::uint64_t need = static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(w);
  std::uint64_t total = 0;
  const bool overflow = __builtin_add_overflow(need, offset, &total);
  if (overflow || (exact ? size != total : size < total))
    throw InputError("image '" + path + "': size " + std::to_string(size) + " bytes does not " +
                     (exact ? "match" : "hold") + " the shape " + shapeText(v.n) + " (" +
                     (offset ? std::to_string(offset) + " header bytes + " : std::string()) +
                     std::to_string(n) + " voxels x " + std::to_string(w) + " bytes of " +
                     voxelTypeName(v.type) + " = " + std::to_string(total) + " bytes" +
                     (detail.empty() ? std::string() : ", " + detail) + ")" +
                     (!exact && size < total ? ": the file is truncated" : ""));
  checkMemory(n, w, extra, v.source);
  v.bytes.resize(static_cast<size_t>(need));
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(offset));
  in.read(reinterpret_cast<char*>(v.bytes.data()), static_cast<std::streamsize>(need));
  if (!in) throw InputError("image '" + path + "': read failed");
  if (bigEndian != hostBigEndian()) swapBytes(v.bytes, w);
}

long long parseWhole(const std::string& text, const std::string& what, long long lo, long long hi) {
  std::size_t used = 0;
  long long v = 0;
  try {
    v = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || trim(text.substr(used)).size() != 0 || v < lo || v > hi)
    throw InputError(what + ": expected a whole number from " + std::to_string(lo) + " to " +
                     std::to_string(hi) + ", got '" + text + "'");
  return v;
}

double parseReal(const std::string& text, const std::string& what) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || !trim(text.substr(used)).empty() || !std::isfinite(v))
    throw InputError(what + ": expected a number, got '" + text + "'");
  return v;
}

std::vector<std::string> words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  std::string w;
  while (in >> w) out.push_back(w);
  return out;
}

/// Sizes of a header (2 or 3 of them) -> shape x, y, z.
std::array<int, 3> shapeFromWords(const std::vector<std::string>& w, const std::string& what) {
  if (w.size() < 2 || w.size() > 3)
    throw InputError(what + ": expected 2 or 3 sizes, got " + std::to_string(w.size()));
  std::array<int, 3> n{1, 1, 1};
  for (size_t a = 0; a < w.size(); ++a)
    n[a] = static_cast<int>(parseWhole(w[a], what, 1, std::numeric_limits<int>::max()));
  return n;
}

fs::path besideHeader(const std::string& header, const std::string& file) {
  const fs::path p(file);
  return p.is_absolute() ? p : fs::path(header).parent_path() / p;
}

// ---------------------------------------------------------------------------------- MetaImage
RawVolume readMhd(const ImageFileSpec& spec, std::uint64_t extra) {
  const std::string what = "image header '" + spec.path + "'";
  std::ifstream in(spec.path, std::ios::binary);
  if (!in) throw InputError(what + ": cannot open the file");
  std::map<std::string, std::string> kv;
  std::map<std::string, int> lineOf;
  std::string line;
  int lineNo = 0;
  std::uint64_t dataStart = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (lineNo > 200) throw InputError(what + ": no ElementDataFile within 200 lines");
    const auto eq = line.find('=');
    if (eq == std::string::npos) {
      if (trim(line).empty()) continue;
      throw InputError(what + ":" + std::to_string(lineNo) + ": expected 'Key = Value', got '" +
                       line.substr(0, 80) + "'");
    }
    const std::string key = trim(line.substr(0, eq));
    kv[key] = trim(line.substr(eq + 1));
    lineOf[key] = lineNo;
    if (key == "ElementDataFile") {
      dataStart = static_cast<std::uint64_t>(in.tellg());
      break;
    }
  }
  auto need = [&](const std::string& key) {
    auto it = kv.find(key);
    if (it == kv.end()) throw InputError(what + ": required key '" + key + "' is missing");
    return it->second;
  };
  auto at = [&](const std::string& key) { return what + ":" + std::to_string(lineOf[key]) + ": " + key; };
  RawVolume v;
  v.source = "image '" + spec.path + "'";
  const long long dims = parseWhole(need("NDims"), at("NDims"), 2, 3);
  const auto sizes = words(need("DimSize"));
  if (static_cast<long long>(sizes.size()) != dims)
    throw InputError(at("DimSize") + ": " + std::to_string(sizes.size()) + " sizes for NDims = " +
                     std::to_string(dims));
  v.n = shapeFromWords(sizes, at("DimSize"));
  const std::string et = need("ElementType");
  static const std::map<std::string, VoxelType> types = {{"MET_UCHAR", VoxelType::UInt8},
                                                         {"MET_USHORT", VoxelType::UInt16},
                                                         {"MET_INT", VoxelType::Int32},
                                                         {"MET_FLOAT", VoxelType::Float32}};
  auto t = types.find(et);
  if (t == types.end())
    throw InputError(at("ElementType") + " = '" + et +
                     "': not supported (MET_UCHAR, MET_USHORT, MET_INT, MET_FLOAT)");
  v.type = t->second;
  if (kv.count("ElementNumberOfChannels") && trim(kv["ElementNumberOfChannels"]) != "1")
    throw InputError(at("ElementNumberOfChannels") + " = '" + kv["ElementNumberOfChannels"] +
                     "': only one channel is supported");
  for (const char* key : {"CompressedData"})
    if (kv.count(key) && lower(kv[key]) == "true")
      throw InputError(at(key) + " = True: compressed MetaImage data is not supported");
  bool big = false;
  for (const char* key : {"BinaryDataByteOrderMSB", "ElementByteOrderMSB"})
    if (kv.count(key)) big = lower(kv[key]) == "true";
  for (const char* key : {"ElementSpacing", "ElementSize"})
    if (kv.count(key)) {
      const auto w = words(kv[key]);
      for (size_t a = 0; a < w.size() && a < 3; ++a) v.spacing[a] = parseReal(w[a], at(key));
      break;
    }
  std::uint64_t headerSize = 0;
  bool headerAuto = false;
  if (kv.count("HeaderSize")) {
    if (trim(kv["HeaderSize"]) == "-1")
      headerAuto = true;
    else
      headerSize = static_cast<std::uint64_t>(
          parseWhole(kv["HeaderSize"], at("HeaderSize"), 0, std::numeric_limits<long long>::max()));
  }
  const std::string file = need("ElementDataFile");
  if (file == "LOCAL") {
    readBlock(v, spec.path, dataStart + headerSize, big, true, extra, "data after the header");
    return v;
  }
  if (file == "LIST" || file.find('%') != std::string::npos)
    throw InputError(at("ElementDataFile") + " = '" + file +
                     "': file lists are not supported (one data file)");
  const fs::path data = besideHeader(spec.path, file);
  if (headerAuto) {
    // HeaderSize = -1: the data are the last bytes of the file.
    const std::uintmax_t size = fileSize(data.string(), "image '" + data.string() + "'");
    const std::uint64_t need =
        static_cast<std::uint64_t>(checkedCount(v.n, v.source)) * voxelTypeBytes(v.type);
    if (size < need)
      throw InputError("image '" + data.string() + "': size " + std::to_string(size) +
                       " bytes is less than the " + std::to_string(need) +
                       " bytes of the shape " + shapeText(v.n) + ": the file is truncated");
    headerSize = size - need;
  }
  v.source = "image '" + data.string() + "' (header '" + spec.path + "')";
  readBlock(v, data.string(), headerSize, big, true, extra, "");
  return v;
}

// ---------------------------------------------------------------------------------- NRRD
RawVolume readNrrd(const ImageFileSpec& spec, std::uint64_t extra) {
  const std::string what = "image header '" + spec.path + "'";
  std::ifstream in(spec.path, std::ios::binary);
  if (!in) throw InputError(what + ": cannot open the file");
  std::string line;
  if (!std::getline(in, line) || line.rfind("NRRD000", 0) != 0)
    throw InputError(what + ": not a NRRD file (the first line must start with NRRD000)");
  std::map<std::string, std::string> kv;
  int lineNo = 1;
  bool blank = false;
  while (std::getline(in, line)) {
    ++lineNo;
    if (lineNo > 500) throw InputError(what + ": header longer than 500 lines");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) {
      blank = true;
      break;
    }
    if (line[0] == '#') continue;
    const auto c = line.find(':');
    if (c == std::string::npos) continue;
    if (c + 1 < line.size() && line[c + 1] == '=') continue;  // key:=value pairs
    kv[lower(trim(line.substr(0, c)))] = trim(line.substr(c + 1));
  }
  const std::uint64_t dataStart = blank ? static_cast<std::uint64_t>(in.tellg()) : 0;
  auto need = [&](const std::string& key) {
    auto it = kv.find(key);
    if (it == kv.end()) throw InputError(what + ": required field '" + key + "' is missing");
    return it->second;
  };
  RawVolume v;
  v.source = "image '" + spec.path + "'";
  const long long dims = parseWhole(need("dimension"), what + ": dimension", 2, 3);
  const auto sizes = words(need("sizes"));
  if (static_cast<long long>(sizes.size()) != dims)
    throw InputError(what + ": sizes has " + std::to_string(sizes.size()) +
                     " entries for dimension " + std::to_string(dims));
  v.n = shapeFromWords(sizes, what + ": sizes");
  const std::string type = lower(need("type"));
  static const std::map<std::string, VoxelType> types = {
      {"uchar", VoxelType::UInt8},          {"unsigned char", VoxelType::UInt8},
      {"uint8", VoxelType::UInt8},          {"uint8_t", VoxelType::UInt8},
      {"ushort", VoxelType::UInt16},        {"unsigned short", VoxelType::UInt16},
      {"unsigned short int", VoxelType::UInt16}, {"uint16", VoxelType::UInt16},
      {"uint16_t", VoxelType::UInt16},      {"int", VoxelType::Int32},
      {"signed int", VoxelType::Int32},     {"int32", VoxelType::Int32},
      {"int32_t", VoxelType::Int32},        {"float", VoxelType::Float32}};
  auto t = types.find(type);
  if (t == types.end())
    throw InputError(what + ": type '" + type + "' is not supported (uint8, uint16, int32, float)");
  v.type = t->second;
  const std::string enc = lower(need("encoding"));
  if (enc != "raw")
    throw InputError(what + ": encoding '" + enc + "' is not supported (raw only)");
  const bool big = kv.count("endian") ? lower(kv["endian"]) == "big" : false;
  if (kv.count("spacings")) {
    const auto w = words(kv["spacings"]);
    for (size_t a = 0; a < w.size() && a < 3; ++a)
      v.spacing[a] = parseReal(w[a], what + ": spacings");
  } else if (kv.count("space directions")) {
    // (a,0,0) (0,b,0) (0,0,c): the length of each vector.
    std::string s = kv["space directions"];
    for (auto& ch : s)
      if (ch == '(' || ch == ')' || ch == ',') ch = ' ';
    const auto w = words(s);
    for (size_t a = 0; a < 3 && (a + 1) * static_cast<size_t>(dims) <= w.size(); ++a) {
      double l2 = 0.0;
      for (size_t b = 0; b < static_cast<size_t>(dims); ++b) {
        const double c = parseReal(w[a * static_cast<size_t>(dims) + b], what + ": space directions");
        l2 += c * c;
      }
      v.spacing[a] = std::sqrt(l2);
    }
  }
  std::uint64_t skip = 0;
  for (const char* key : {"byte skip", "byteskip"})
    if (kv.count(key))
      skip = static_cast<std::uint64_t>(parseWhole(kv[key], what + ": byte skip", 0,
                                                   std::numeric_limits<long long>::max()));
  std::string file;
  for (const char* key : {"data file", "datafile"})
    if (kv.count(key)) file = kv[key];
  if (file.empty()) {
    if (!blank) throw InputError(what + ": no 'data file' field and no data after the header");
    readBlock(v, spec.path, dataStart + skip, big, true, extra, "data after the header");
    return v;
  }
  if (file.rfind("LIST", 0) == 0 || file.find('%') != std::string::npos)
    throw InputError(what + ": data file '" + file + "': file lists are not supported");
  const fs::path data = besideHeader(spec.path, file);
  v.source = "image '" + data.string() + "' (header '" + spec.path + "')";
  readBlock(v, data.string(), skip, big, true, extra, "");
  return v;
}

// ---------------------------------------------------------------------------------- TIFF
/// Baseline TIFF pages: uncompressed, one sample per pixel, strips (or tiles refused).
class TiffFile {
 public:
  TiffFile(const std::string& path) : path_(path), what_("TIFF '" + path + "'") {
    size_ = fileSize(path, what_);
    in_.open(path, std::ios::binary);
    if (!in_) throw InputError(what_ + ": cannot open the file");
    unsigned char h[8];
    if (size_ < 8) throw InputError(what_ + ": " + std::to_string(size_) + " bytes, too short for a TIFF header");
    readAt(0, h, 8);
    if (h[0] == 'I' && h[1] == 'I')
      big_ = false;
    else if (h[0] == 'M' && h[1] == 'M')
      big_ = true;
    else
      throw InputError(what_ + ": not a TIFF file (no II/MM byte-order mark)");
    if (u16(h + 2) == 43) throw InputError(what_ + ": BigTIFF is not supported");
    if (u16(h + 2) != 42) throw InputError(what_ + ": not a TIFF file (magic " + std::to_string(u16(h + 2)) + ", not 42)");
    next_ = u32(h + 4);
  }

  struct Page {
    int width = 0, height = 0;
    VoxelType type = VoxelType::UInt8;
    std::vector<std::uint64_t> offsets, counts;
    int rowsPerStrip = 0;
  };

  /// Next page, or false at the end of the chain.
  bool nextPage(Page& p, int pageNo) {
    if (next_ == 0) return false;
    const std::string at = what_ + " page " + std::to_string(pageNo);
    if (next_ + 2 > size_) throw InputError(at + ": directory offset " + std::to_string(next_) + " beyond the file's " + std::to_string(size_) + " bytes (truncated?)");
    if (++visited_ > 1000000) throw InputError(what_ + ": more than 10^6 pages (a directory loop?)");
    unsigned char b[12];
    readAt(next_, b, 2);
    const std::uint64_t entries = u16(b);
    if (next_ + 2 + entries * 12 + 4 > size_) throw InputError(at + ": directory of " + std::to_string(entries) + " entries runs past the end of the file (truncated?)");
    p = Page{};
    int bits = 8, format = 1, compression = 1, samples = 1;
    for (std::uint64_t e = 0; e < entries; ++e) {
      readAt(next_ + 2 + e * 12, b, 12);
      const unsigned tag = u16(b), type = u16(b + 2);
      const std::uint64_t count = u32(b + 4);
      auto values = [&]() { return readValues(type, count, b + 8, at, tag); };
      switch (tag) {
        case 256: p.width = static_cast<int>(first(values(), at, tag)); break;
        case 257: p.height = static_cast<int>(first(values(), at, tag)); break;
        case 258: bits = static_cast<int>(first(values(), at, tag)); break;
        case 259: compression = static_cast<int>(first(values(), at, tag)); break;
        case 273: p.offsets = values(); break;
        case 277: samples = static_cast<int>(first(values(), at, tag)); break;
        case 278: p.rowsPerStrip = static_cast<int>(std::min<std::uint64_t>(first(values(), at, tag), 1u << 30)); break;
        case 279: p.counts = values(); break;
        case 322: case 323: throw InputError(at + ": tiled TIFF is not supported (strips only)");
        case 339: format = static_cast<int>(first(values(), at, tag)); break;
        default: break;
      }
    }
    unsigned char nb[4];
    readAt(next_ + 2 + entries * 12, nb, 4);
    const std::uint64_t following = u32(nb);
    if (following != 0 && following <= next_ && ++backwards_ > 100000)
      throw InputError(what_ + ": page directories loop");
    next_ = following;
    if (compression != 1)
      throw InputError(at + ": compression " + std::to_string(compression) + " is not supported (uncompressed TIFF only; e.g. `tiffcp -c none in.tif out.tif`)");
    if (samples != 1) throw InputError(at + ": " + std::to_string(samples) + " samples per pixel (one, a grey or label image, is supported)");
    if (p.width <= 0 || p.height <= 0) throw InputError(at + ": width or height missing or zero");
    if (bits == 8 && format == 1) p.type = VoxelType::UInt8;
    else if (bits == 16 && format == 1) p.type = VoxelType::UInt16;
    else if (bits == 32 && format == 2) p.type = VoxelType::Int32;
    else if (bits == 32 && format == 3) p.type = VoxelType::Float32;
    else throw InputError(at + ": " + std::to_string(bits) + "-bit samples of format " + std::to_string(format) + " are not supported (8/16-bit unsigned, 32-bit signed or float)");
    if (p.offsets.empty() || p.offsets.size() != p.counts.size())
      throw InputError(at + ": " + std::to_string(p.offsets.size()) + " strip offsets and " + std::to_string(p.counts.size()) + " strip byte counts");
    if (p.rowsPerStrip <= 0) p.rowsPerStrip = p.height;
    return true;
  }

  /// Copies the page's pixels (row by row, x fastest) to out (width x height x bytes).
  void readPage(const Page& p, unsigned char* out, int pageNo) {
    const std::string at = what_ + " page " + std::to_string(pageNo);
    const std::uint64_t w = static_cast<std::uint64_t>(voxelTypeBytes(p.type));
    const std::uint64_t need = static_cast<std::uint64_t>(p.width) * static_cast<std::uint64_t>(p.height) * w;
    std::uint64_t done = 0;
    for (size_t s = 0; s < p.offsets.size() && done < need; ++s) {
      const std::uint64_t len = std::min(p.counts[s], need - done);
      if (p.offsets[s] > size_ || len > size_ - p.offsets[s])
        throw InputError(at + ": strip " + std::to_string(s) + " (" + std::to_string(len) + " bytes at " + std::to_string(p.offsets[s]) + ") runs past the end of the file's " + std::to_string(size_) + " bytes (truncated?)");
      readAt(p.offsets[s], out + done, len);
      done += len;
    }
    if (done != need)
      throw InputError(at + ": its strips hold " + std::to_string(done) + " bytes, the page " + std::to_string(p.width) + " x " + std::to_string(p.height) + " of " + voxelTypeName(p.type) + " needs " + std::to_string(need));
    if (big_ != hostBigEndian() && w > 1)
      for (std::uint64_t i = 0; i < need; i += w) std::reverse(out + i, out + i + w);
  }

 private:
  std::uint64_t u16(const unsigned char* b) const { return big_ ? (b[0] << 8 | b[1]) : (b[1] << 8 | b[0]); }
  std::uint64_t u32(const unsigned char* b) const {
    return big_ ? (std::uint64_t{b[0]} << 24 | std::uint64_t{b[1]} << 16 | std::uint64_t{b[2]} << 8 | b[3])
                : (std::uint64_t{b[3]} << 24 | std::uint64_t{b[2]} << 16 | std::uint64_t{b[1]} << 8 | b[0]);
  }
  void readAt(std::uint64_t off, unsigned char* out, std::uint64_t n) {
    if (off > size_ || n > size_ - off) throw InputError(what_ + ": read of " + std::to_string(n) + " bytes at " + std::to_string(off) + " past the end of the file's " + std::to_string(size_) + " bytes (truncated?)");
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(off));
    in_.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(n));
    if (!in_) throw InputError(what_ + ": read failed at byte " + std::to_string(off));
  }
  std::vector<std::uint64_t> readValues(unsigned type, std::uint64_t count, const unsigned char* inl, const std::string& at, unsigned tag) {
    const int w = type == 3 ? 2 : type == 4 ? 4 : 0;  // SHORT or LONG
    if (w == 0) throw InputError(at + ": tag " + std::to_string(tag) + " has field type " + std::to_string(type) + " (SHORT or LONG expected)");
    if (count > (1u << 24)) throw InputError(at + ": tag " + std::to_string(tag) + " has " + std::to_string(count) + " values");
    std::vector<unsigned char> raw(static_cast<size_t>(count * static_cast<std::uint64_t>(w)));
    if (count * static_cast<std::uint64_t>(w) <= 4) std::memcpy(raw.data(), inl, raw.size());
    else readAt(u32(inl), raw.data(), raw.size());
    std::vector<std::uint64_t> out(static_cast<size_t>(count));
    for (size_t i = 0; i < out.size(); ++i) out[i] = w == 2 ? u16(&raw[i * 2]) : u32(&raw[i * 4]);
    return out;
  }
  static std::uint64_t first(const std::vector<std::uint64_t>& v, const std::string& at, unsigned tag) {
    if (v.empty()) throw InputError(at + ": tag " + std::to_string(tag) + " has no value");
    return v[0];
  }

  std::string path_, what_;
  std::uint64_t size_ = 0, next_ = 0, visited_ = 0, backwards_ = 0;
  bool big_ = false;
  std::ifstream in_;
};

RawVolume readTiff(const ImageFileSpec& spec, std::uint64_t extra) {
  std::vector<std::string> files;
  std::error_code ec;
  if (fs::is_directory(spec.path, ec)) {
    for (const auto& e : fs::directory_iterator(spec.path, ec)) {
      const std::string ext = lower(e.path().extension().string());
      if (ext == ".tif" || ext == ".tiff") files.push_back(e.path().string());
    }
    std::sort(files.begin(), files.end());
    if (files.empty()) throw InputError("TIFF stack '" + spec.path + "': no .tif or .tiff file in the folder");
  } else {
    files.push_back(spec.path);
  }
  // Pass 1: the pages and their sizes (nothing per voxel allocated yet).
  struct Item {
    size_t file;
    TiffFile::Page page;
    int pageNo;
  };
  std::vector<Item> items;
  RawVolume v;
  v.source = files.size() == 1 ? "TIFF '" + files[0] + "'" : "TIFF stack '" + spec.path + "'";
  for (size_t f = 0; f < files.size(); ++f) {
    TiffFile t(files[f]);
    TiffFile::Page p;
    for (int k = 0; t.nextPage(p, k); ++k) {
      if (!items.empty()) {
        const auto& q = items.front().page;
        if (p.width != q.width || p.height != q.height || p.type != q.type)
          throw InputError("TIFF '" + files[f] + "' page " + std::to_string(k) + ": " +
                           std::to_string(p.width) + " x " + std::to_string(p.height) + " " +
                           voxelTypeName(p.type) + ", but the first page is " +
                           std::to_string(q.width) + " x " + std::to_string(q.height) + " " +
                           voxelTypeName(q.type));
      }
      items.push_back({f, p, k});
      if (items.size() > static_cast<size_t>(std::numeric_limits<int>::max()))
        throw InputError(v.source + ": too many pages");
    }
  }
  if (items.empty()) throw InputError(v.source + ": no page");
  const auto& p0 = items.front().page;
  v.n = {p0.width, p0.height, static_cast<int>(items.size())};
  v.type = p0.type;
  const Index n = checkedCount(v.n, v.source);
  checkMemory(n, voxelTypeBytes(v.type), extra, v.source);
  v.bytes.resize(static_cast<size_t>(n) * static_cast<size_t>(voxelTypeBytes(v.type)));
  const size_t pageBytes = static_cast<size_t>(p0.width) * static_cast<size_t>(p0.height) *
                           static_cast<size_t>(voxelTypeBytes(v.type));
  size_t z = 0;
  for (size_t f = 0; f < files.size(); ++f) {
    TiffFile t(files[f]);
    TiffFile::Page p;
    for (int k = 0; t.nextPage(p, k); ++k) t.readPage(p, v.bytes.data() + pageBytes * z++, k);
  }
  return v;
}

// ---------------------------------------------------------------------------------- VTK
struct VtkErrors {
  std::string text;
  static void callback(vtkObject*, unsigned long, void* self, void* data) {
    auto* e = static_cast<VtkErrors*>(self);
    if (data && e->text.size() < 2000) e->text += trim(static_cast<const char*>(data)) + " ";
  }
};

RawVolume readVti(const ImageFileSpec& spec, std::uint64_t extra) {
  const std::string what = "image '" + spec.path + "'";
  fileSize(spec.path, what);
  vtkNew<vtkXMLImageDataReader> reader;
  VtkErrors errors;
  vtkNew<vtkCallbackCommand> cb;
  cb->SetCallback(&VtkErrors::callback);
  cb->SetClientData(&errors);
  reader->AddObserver(vtkCommand::ErrorEvent, cb);
  reader->AddObserver(vtkCommand::WarningEvent, cb);
  // VTK reports through its output window; keep it quiet and report through InputError.
  struct Quiet {
    int was = vtkObject::GetGlobalWarningDisplay();
    Quiet() { vtkObject::GlobalWarningDisplayOff(); }
    ~Quiet() { vtkObject::SetGlobalWarningDisplay(was); }
  } quiet;
  if (!reader->CanReadFile(spec.path.c_str()))
    throw InputError(what + ": not a VTK XML image data (.vti) file");
  reader->SetFileName(spec.path.c_str());
  reader->Update();
  vtkImageData* img = reader->GetOutput();
  if (!errors.text.empty() || !img || reader->GetErrorCode() != 0 ||
      reader->GetExecutive()->GetNumberOfOutputPorts() == 0)
    throw InputError(what + ": VTK could not read it" +
                     (errors.text.empty() ? std::string(" (damaged or truncated file)")
                                          : ": " + errors.text));
  int dims[3];
  img->GetDimensions(dims);
  // Point data: one value per point; cell data: one per cell (dims - 1 per axis, at least 1).
  vtkDataArray* arr = nullptr;
  bool cells = false;
  std::vector<std::string> names;
  auto pick = [&](vtkFieldData* fd, bool isCell) {
    for (int k = 0; k < fd->GetNumberOfArrays(); ++k) {
      vtkDataArray* a = vtkDataArray::SafeDownCast(fd->GetAbstractArray(k));
      if (!a) continue;
      const std::string name = a->GetName() ? a->GetName() : "";
      names.push_back(name + (isCell ? " (cells)" : " (points)"));
      if (spec.dataset.empty() ? arr == nullptr : name == spec.dataset) {
        if (arr == nullptr) {
          arr = a;
          cells = isCell;
        }
      }
    }
  };
  pick(img->GetPointData(), false);
  pick(img->GetCellData(), true);
  if (!arr || (spec.dataset.empty() && names.size() > 1)) {
    std::string list;
    for (const auto& s : names) list += (list.empty() ? "" : ", ") + s;
    throw InputError(what + ": " +
                     (spec.dataset.empty()
                          ? (names.empty() ? std::string("holds no data array")
                                           : "holds several arrays (" + list + "); name one (dataset)")
                          : "no array named '" + spec.dataset + "' (arrays: " + list + ")"));
  }
  if (arr->GetNumberOfComponents() != 1)
    throw InputError(what + ": array '" + std::string(arr->GetName() ? arr->GetName() : "") +
                     "' has " + std::to_string(arr->GetNumberOfComponents()) +
                     " components (one expected)");
  RawVolume v;
  v.source = what;
  for (int a = 0; a < 3; ++a) v.n[static_cast<size_t>(a)] = cells ? std::max(1, dims[a] - 1) : dims[a];
  double sp[3];
  img->GetSpacing(sp);
  v.spacing = {sp[0], sp[1], sp[2]};
  const Index n = checkedCount(v.n, what);
  if (arr->GetNumberOfTuples() != n)
    throw InputError(what + ": the array has " + std::to_string(arr->GetNumberOfTuples()) +
                     " values, the shape " + shapeText(v.n) + " needs " + std::to_string(n));
  switch (arr->GetDataType()) {
    case VTK_UNSIGNED_CHAR: v.type = VoxelType::UInt8; break;
    case VTK_UNSIGNED_SHORT: v.type = VoxelType::UInt16; break;
    case VTK_FLOAT: case VTK_DOUBLE: v.type = VoxelType::Float32; break;
    default: v.type = VoxelType::Int32; break;
  }
  checkMemory(n, voxelTypeBytes(v.type), extra, what);
  v.bytes.resize(static_cast<size_t>(n) * static_cast<size_t>(voxelTypeBytes(v.type)));
  for (Index i = 0; i < n; ++i) {
    const double x = arr->GetComponent(i, 0);
    unsigned char* out = v.bytes.data() + static_cast<size_t>(i) * voxelTypeBytes(v.type);
    switch (v.type) {
      case VoxelType::UInt8: { const std::uint8_t t = static_cast<std::uint8_t>(x); std::memcpy(out, &t, 1); break; }
      case VoxelType::UInt16: { const std::uint16_t t = static_cast<std::uint16_t>(x); std::memcpy(out, &t, 2); break; }
      case VoxelType::Float32: { const float t = static_cast<float>(x); std::memcpy(out, &t, 4); break; }
      case VoxelType::Int32: {
        if (!(x >= -2147483648.0 && x <= 2147483647.0) || x != std::floor(x))
          throw InputError(what + ": value " + numText(x) + " of voxel " + std::to_string(i) +
                           " does not fit a 32-bit integer label");
        const std::int32_t t = static_cast<std::int32_t>(x);
        std::memcpy(out, &t, 4);
        break;
      }
    }
  }
  return v;
}

void writeVti(const RawVolume& v, const std::string& path, const std::string& name) {
  vtkNew<vtkImageData> img;
  img->SetDimensions(v.n[0] + 1, v.n[1] + 1, v.n[2] > 1 ? v.n[2] + 1 : 1);
  const bool flat = v.n[2] == 1;
  if (flat) img->SetDimensions(v.n[0] + 1, v.n[1] + 1, 1);
  img->SetSpacing(v.spacing[0] > 0 ? v.spacing[0] : 1.0, v.spacing[1] > 0 ? v.spacing[1] : 1.0,
                  v.spacing[2] > 0 ? v.spacing[2] : 1.0);
  const Index n = v.voxelCount();
  vtkSmartPointer<vtkDataArray> arr;
  switch (v.type) {
    case VoxelType::UInt8: arr = vtkSmartPointer<vtkUnsignedCharArray>::New(); break;
    case VoxelType::UInt16: arr = vtkSmartPointer<vtkUnsignedShortArray>::New(); break;
    case VoxelType::Int32: arr = vtkSmartPointer<vtkIntArray>::New(); break;
    case VoxelType::Float32: arr = vtkSmartPointer<vtkFloatArray>::New(); break;
  }
  arr->SetName(name.empty() ? "label" : name.c_str());
  arr->SetNumberOfComponents(1);
  arr->SetNumberOfTuples(n);
  std::memcpy(arr->GetVoidPointer(0), v.bytes.data(), v.bytes.size());
  img->GetCellData()->AddArray(arr);
  vtkNew<vtkXMLImageDataWriter> w;
  w->SetFileName(path.c_str());
  w->SetInputData(img);
  w->SetDataModeToAppended();
  w->SetCompressorTypeToZLib();
  if (w->Write() != 1) throw InputError("image '" + path + "': cannot write the .vti file");
}

// ---------------------------------------------------------------------------------- HDF5
class QuietHdf5 {
 public:
  QuietHdf5() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

struct H5Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  ~H5Handle() {
    if (id >= 0) close(id);
  }
};

herr_t collectDataset(hid_t group, const char* name, const H5L_info_t*, void* out) {
  H5O_info_t info;
  if (H5Oget_info_by_name2(group, name, &info, H5O_INFO_BASIC, H5P_DEFAULT) >= 0 &&
      info.type == H5O_TYPE_DATASET)
    static_cast<std::vector<std::string>*>(out)->push_back(name);
  return 0;
}

RawVolume readHdf5(const ImageFileSpec& spec, std::uint64_t extra) {
  const std::string what = "image '" + spec.path + "'";
  fileSize(spec.path, what);
  QuietHdf5 quiet;
  if (H5Fis_hdf5(spec.path.c_str()) <= 0)
    throw InputError(what + ": not an HDF5 file");
  // Strong close: whatever a damaged file left open is closed with it.
  H5Handle fapl{H5Pcreate(H5P_FILE_ACCESS), H5Pclose};
  H5Pset_fclose_degree(fapl.id, H5F_CLOSE_STRONG);
  H5Handle file{H5Fopen(spec.path.c_str(), H5F_ACC_RDONLY, fapl.id), H5Fclose};
  if (file.id < 0) throw InputError(what + ": cannot open the HDF5 file");
  std::string name = spec.dataset;
  if (name.empty()) {
    std::vector<std::string> found;
    H5Literate(file.id, H5_INDEX_NAME, H5_ITER_INC, nullptr, collectDataset, &found);
    if (found.size() != 1) {
      std::string list;
      for (const auto& s : found) list += (list.empty() ? "" : ", ") + s;
      throw InputError(what + ": " + std::to_string(found.size()) +
                       " datasets at the root" + (list.empty() ? "" : " (" + list + ")") +
                       "; name the one to read (dataset)");
    }
    name = found[0];
  }
  H5Handle ds{H5Dopen2(file.id, name.c_str(), H5P_DEFAULT), H5Dclose};
  if (ds.id < 0) throw InputError(what + ": no dataset '" + name + "'");
  H5Handle space{H5Dget_space(ds.id), H5Sclose};
  const int rank = H5Sget_simple_extent_ndims(space.id);
  if (rank != 2 && rank != 3)
    throw InputError(what + ": dataset '" + name + "' has rank " + std::to_string(rank) +
                     " (2: y, x or 3: z, y, x expected)");
  hsize_t dims[3] = {1, 1, 1};
  H5Sget_simple_extent_dims(space.id, dims, nullptr);
  RawVolume v;
  v.source = what + " dataset '" + name + "'";
  for (int a = 0; a < rank; ++a) {
    const hsize_t d = dims[rank - 1 - a];
    if (d == 0 || d > static_cast<hsize_t>(std::numeric_limits<int>::max()))
      throw InputError(v.source + ": size " + std::to_string(d) + " along axis " + "xyz"[a] +
                       " is not usable");
    v.n[static_cast<size_t>(a)] = static_cast<int>(d);
  }
  if (rank == 2) v.n[2] = 1;
  H5Handle type{H5Dget_type(ds.id), H5Tclose};
  const H5T_class_t cls = H5Tget_class(type.id);
  const size_t size = H5Tget_size(type.id);
  hid_t memType = -1;
  if (cls == H5T_INTEGER) {
    const bool sign = H5Tget_sign(type.id) == H5T_SGN_2;
    if (!sign && size == 1) { v.type = VoxelType::UInt8; memType = H5T_NATIVE_UINT8; }
    else if (!sign && size == 2) { v.type = VoxelType::UInt16; memType = H5T_NATIVE_UINT16; }
    else { v.type = VoxelType::Int32; memType = H5T_NATIVE_INT32; }
  } else if (cls == H5T_FLOAT) {
    v.type = VoxelType::Float32;
    memType = H5T_NATIVE_FLOAT;
  } else {
    throw InputError(v.source + ": the element type is neither integer nor floating point");
  }
  const Index n = checkedCount(v.n, v.source);
  checkMemory(n, voxelTypeBytes(v.type), extra, v.source);
  v.bytes.resize(static_cast<size_t>(n) * static_cast<size_t>(voxelTypeBytes(v.type)));
  // Wider types (e.g. numpy's int64) are converted; a value beyond the 32-bit range aborts the
  // read instead of being clipped.
  H5Handle xfer{H5Pcreate(H5P_DATASET_XFER), H5Pclose};
  H5Pset_type_conv_cb(xfer.id, [](H5T_conv_except_t except, hid_t, hid_t, void*, void*, void*) {
    return except == H5T_CONV_EXCEPT_PRECISION || except == H5T_CONV_EXCEPT_TRUNCATE
               ? H5T_CONV_UNHANDLED : H5T_CONV_ABORT;
  }, nullptr);
  if (H5Dread(ds.id, memType, H5S_ALL, H5S_ALL, xfer.id, v.bytes.data()) < 0)
    throw InputError(v.source + ": read failed (truncated or damaged file, or values beyond " +
                     voxelTypeName(v.type) + ")");
  return v;
}

void writeHdf5(const RawVolume& v, const std::string& path, const std::string& dataset) {
  QuietHdf5 quiet;
  H5Handle file{H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose};
  if (file.id < 0) throw InputError("image '" + path + "': cannot create the HDF5 file");
  const hsize_t dims[3] = {static_cast<hsize_t>(v.n[2]), static_cast<hsize_t>(v.n[1]),
                           static_cast<hsize_t>(v.n[0])};
  H5Handle space{H5Screate_simple(3, dims, nullptr), H5Sclose};
  hid_t t = v.type == VoxelType::UInt8    ? H5T_NATIVE_UINT8
            : v.type == VoxelType::UInt16 ? H5T_NATIVE_UINT16
            : v.type == VoxelType::Int32  ? H5T_NATIVE_INT32
                                          : H5T_NATIVE_FLOAT;
  H5Handle ds{H5Dcreate2(file.id, dataset.c_str(), t, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
              H5Dclose};
  if (ds.id < 0 || H5Dwrite(ds.id, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.bytes.data()) < 0)
    throw InputError("image '" + path + "': cannot write dataset '" + dataset + "'");
}

void writeTiff(const RawVolume& v, const std::string& path) {
  // Little-endian multi-page baseline TIFF, one strip per page.
  std::ofstream f(path, std::ios::binary);
  if (!f) throw InputError("image '" + path + "': cannot write the file");
  auto put16 = [&](std::uint16_t x) { f.put(static_cast<char>(x & 255)); f.put(static_cast<char>(x >> 8)); };
  auto put32 = [&](std::uint32_t x) { for (int k = 0; k < 4; ++k) f.put(static_cast<char>((x >> (8 * k)) & 255)); };
  const int w = voxelTypeBytes(v.type);
  const std::uint32_t pageBytes = static_cast<std::uint32_t>(v.n[0]) * static_cast<std::uint32_t>(v.n[1]) * static_cast<std::uint32_t>(w);
  const int entries = 9;
  const std::uint32_t ifdBytes = 2 + entries * 12 + 4;
  f.write("II", 2);
  put16(42);
  put32(8);
  std::uint32_t pos = 8;
  const int bits = 8 * w;
  const int format = v.type == VoxelType::Int32 ? 2 : v.type == VoxelType::Float32 ? 3 : 1;
  for (int z = 0; z < v.n[2]; ++z) {
    const std::uint32_t data = pos + ifdBytes;
    const std::uint32_t next = z + 1 < v.n[2] ? data + pageBytes : 0;
    put16(entries);
    auto entry = [&](std::uint16_t tag, std::uint16_t type, std::uint32_t value) {
      put16(tag); put16(type); put32(1);
      if (type == 3) { put16(static_cast<std::uint16_t>(value)); put16(0); } else put32(value);
    };
    entry(256, 4, static_cast<std::uint32_t>(v.n[0]));
    entry(257, 4, static_cast<std::uint32_t>(v.n[1]));
    entry(258, 3, static_cast<std::uint32_t>(bits));
    entry(259, 3, 1);
    entry(262, 3, 1);
    entry(273, 4, data);
    entry(277, 3, 1);
    entry(279, 4, pageBytes);
    entry(339, 3, static_cast<std::uint32_t>(format));
    put32(next);
    f.write(reinterpret_cast<const char*>(v.bytes.data()) + static_cast<size_t>(z) * pageBytes, pageBytes);
    pos = data + pageBytes;
  }
  if (!f) throw InputError("image '" + path + "': write failed");
}

}  // namespace

std::string voxelTypeName(VoxelType t) {
  switch (t) {
    case VoxelType::UInt8: return "uint8";
    case VoxelType::UInt16: return "uint16";
    case VoxelType::Int32: return "int32";
    case VoxelType::Float32: return "float32";
  }
  return "?";
}

int voxelTypeBytes(VoxelType t) {
  return t == VoxelType::UInt8 ? 1 : t == VoxelType::UInt16 ? 2 : 4;
}

VoxelType parseVoxelType(const std::string& name, const std::string& what) {
  const std::string s = lower(name);
  if (s == "uint8" || s == "u8" || s == "uchar") return VoxelType::UInt8;
  if (s == "uint16" || s == "u16" || s == "ushort") return VoxelType::UInt16;
  if (s == "int32" || s == "i32" || s == "int") return VoxelType::Int32;
  if (s == "float32" || s == "f32" || s == "float") return VoxelType::Float32;
  throw InputError(what + ": unknown voxel type '" + name + "' (uint8, uint16, int32, float32)");
}

std::vector<std::string> imageFormats() { return {"raw", "mhd", "nhdr", "tiff", "vti", "hdf5"}; }

std::string detectImageFormat(const std::string& path) {
  std::error_code ec;
  std::string ext = lower(fs::path(path).extension().string());
  // A folder is a TIFF stack, unless its name says another format (then that reader refuses it).
  if (fs::is_directory(path, ec) && (ext.empty() || ext == ".tif" || ext == ".tiff")) return "tiff";
  if (ext == ".gz")
    throw InputError("image '" + path + "': compressed (.gz) images are not read; unpack it first (gunzip -k)");
  if (ext == ".raw" || ext == ".bin" || ext == ".dat") return "raw";
  if (ext == ".mhd" || ext == ".mha") return "mhd";
  if (ext == ".nhdr" || ext == ".nrrd") return "nhdr";
  if (ext == ".tif" || ext == ".tiff") return "tiff";
  if (ext == ".vti") return "vti";
  if (ext == ".h5" || ext == ".hdf5" || ext == ".hdf") return "hdf5";
  throw InputError("image '" + path + "': cannot tell the format from the extension '" + ext +
                   "'; give it (raw, mhd, nhdr, tiff, vti, hdf5)");
}

double RawVolume::value(Index i) const {
  const unsigned char* p = bytes.data() + static_cast<size_t>(i) * voxelTypeBytes(type);
  switch (type) {
    case VoxelType::UInt8: return *p;
    case VoxelType::UInt16: { std::uint16_t t; std::memcpy(&t, p, 2); return t; }
    case VoxelType::Int32: { std::int32_t t; std::memcpy(&t, p, 4); return t; }
    case VoxelType::Float32: { float t; std::memcpy(&t, p, 4); return t; }
  }
  return 0.0;
}

RawVolume readVolume(const ImageFileSpec& specIn, std::uint64_t extra) {
  ImageFileSpec spec = specIn;
  if (spec.path.empty()) throw InputError("image: no file given");
  if (spec.format.empty()) spec.format = detectImageFormat(spec.path);
  const auto formats = imageFormats();
  if (std::find(formats.begin(), formats.end(), spec.format) == formats.end())
    throw InputError("image '" + spec.path + "': unknown format '" + spec.format +
                     "' (raw, mhd, nhdr, tiff, vti, hdf5)");
  std::error_code ec;
  if (!fs::exists(spec.path, ec)) throw InputError("image '" + spec.path + "': no such file");
  if (spec.format == "raw") {
    RawVolume v;
    v.source = "image '" + spec.path + "'";
    v.n = spec.shape;
    v.type = spec.type;
    if (v.n[0] == 0 && v.n[1] == 0 && v.n[2] == 0)
      throw InputError(v.source + ": a headerless raw image needs its shape (voxels along x, y, z)");
    readBlock(v, spec.path, spec.headerBytes, spec.bigEndian, true, extra, "");
    return v;
  }
  if (spec.format == "mhd") return readMhd(spec, extra);
  if (spec.format == "nhdr") return readNrrd(spec, extra);
  if (spec.format == "tiff") return readTiff(spec, extra);
  if (spec.format == "vti") return readVti(spec, extra);
  return readHdf5(spec, extra);
}

void writeVolume(const RawVolume& v, const std::string& path, const std::string& format,
                 const std::string& dataset) {
  auto writeRaw = [&](const std::string& p) {
    std::ofstream f(p, std::ios::binary);
    f.write(reinterpret_cast<const char*>(v.bytes.data()), static_cast<std::streamsize>(v.bytes.size()));
    if (!f) throw InputError("image '" + p + "': cannot write the file");
  };
  const std::string dataName = fs::path(path).stem().string() + ".raw";
  const std::string dataPath = (fs::path(path).parent_path() / dataName).string();
  if (format == "raw") {
    writeRaw(path);
  } else if (format == "mhd") {
    std::ofstream h(path);
    static const char* et[] = {"MET_UCHAR", "MET_USHORT", "MET_INT", "MET_FLOAT"};
    h << "ObjectType = Image\nNDims = 3\nDimSize = " << v.n[0] << " " << v.n[1] << " " << v.n[2]
      << "\nElementType = " << et[static_cast<int>(v.type)] << "\nBinaryData = True\n"
      << "BinaryDataByteOrderMSB = " << (hostBigEndian() ? "True" : "False")
      << "\nElementSpacing = " << (v.spacing[0] > 0 ? v.spacing[0] : 1) << " "
      << (v.spacing[1] > 0 ? v.spacing[1] : 1) << " " << (v.spacing[2] > 0 ? v.spacing[2] : 1)
      << "\nElementDataFile = " << dataName << "\n";
    if (!h) throw InputError("image '" + path + "': cannot write the header");
    writeRaw(dataPath);
  } else if (format == "nhdr") {
    std::ofstream h(path);
    static const char* tn[] = {"uint8", "uint16", "int32", "float"};
    h << "NRRD0004\ntype: " << tn[static_cast<int>(v.type)] << "\ndimension: 3\nsizes: " << v.n[0]
      << " " << v.n[1] << " " << v.n[2] << "\nencoding: raw\nendian: "
      << (hostBigEndian() ? "big" : "little") << "\ndata file: " << dataName << "\n";
    if (!h) throw InputError("image '" + path + "': cannot write the header");
    writeRaw(dataPath);
  } else if (format == "tiff") {
    writeTiff(v, path);
  } else if (format == "vti") {
    writeVti(v, path, dataset);
  } else if (format == "hdf5") {
    writeHdf5(v, path, dataset.empty() ? "image" : dataset);
  } else {
    throw InputError("image '" + path + "': unknown format '" + format + "'");
  }
}

VoxelImage applyLabels(const RawVolume& v, const LabelRule& rule) {
  const Index n = v.voxelCount();
  if (static_cast<Index>(v.bytes.size()) != n * voxelTypeBytes(v.type))
    throw InputError(v.source + ": holds " + std::to_string(v.bytes.size()) + " bytes for " +
                     std::to_string(n) + " voxels of " + voxelTypeName(v.type));
  for (const auto& [value, label] : rule.map)
    if (label < 0 || label > 255)
      throw InputError(v.source + ": label " + std::to_string(label) + " for value " +
                       numText(value) + " is outside 0..255");
  VoxelImage img(v.n[0], v.n[1], v.n[2]);
  std::uint8_t* out = const_cast<std::uint8_t*>(img.values().data());
  std::vector<Index> used(256, 0);
  std::vector<Index> usedValue;                      // map: voxels per map entry
  std::vector<std::pair<double, int>> sortedMap;     // map entries in value order
  auto refuse = [&](double value, Index i, const std::string& why) {
    Index count = 0;
    for (Index k = 0; k < n; ++k) count += v.value(k) == value || (std::isnan(value) && std::isnan(v.value(k)));
    const Index x = i % v.n[0], y = (i / v.n[0]) % v.n[1], z = i / (Index{v.n[0]} * v.n[1]);
    throw InputError(v.source + ": value " + numText(value) + " (" + std::to_string(count) +
                     " voxels, the first at x " + std::to_string(x) + ", y " + std::to_string(y) +
                     ", z " + std::to_string(z) + ") " + why);
  };
  if (rule.threshold) {
    for (Index i = 0; i < n; ++i) {
      const double x = v.value(i);
      if (std::isnan(x)) refuse(x, i, "is not a number; it cannot be thresholded");
      const int l = x < rule.level ? rule.below : rule.above;
      out[i] = static_cast<std::uint8_t>(l);
      ++used[static_cast<size_t>(l)];
    }
  } else if (!rule.map.empty()) {
    // Integer images with small values: a lookup table; otherwise a sorted search.
    std::vector<std::pair<double, int>> sorted = rule.map;
    std::sort(sorted.begin(), sorted.end());
    for (size_t k = 1; k < sorted.size(); ++k)
      if (sorted[k].first == sorted[k - 1].first && sorted[k].second != sorted[k - 1].second)
        throw InputError(v.source + ": value " + numText(sorted[k].first) + " is mapped twice");
    sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
    std::string listed;
    for (const auto& p : sorted) listed += (listed.empty() ? "" : ", ") + numText(p.first);
    usedValue.assign(sorted.size(), 0);
    sortedMap = sorted;
    if (v.type == VoxelType::UInt8 || v.type == VoxelType::UInt16) {
      std::vector<int> table(v.type == VoxelType::UInt8 ? 256 : 65536, -1);
      for (size_t k = 0; k < sorted.size(); ++k) {
        const double x = sorted[k].first;
        if (x >= 0 && x < static_cast<double>(table.size()) && x == std::floor(x))
          table[static_cast<size_t>(x)] = static_cast<int>(k);
      }
      for (Index i = 0; i < n; ++i) {
        const int k = table[static_cast<size_t>(v.value(i))];
        if (k < 0) refuse(v.value(i), i, "has no entry in the label map (values mapped: " + listed + ")");
        out[i] = static_cast<std::uint8_t>(sorted[static_cast<size_t>(k)].second);
        ++usedValue[static_cast<size_t>(k)];
      }
    } else {
      for (Index i = 0; i < n; ++i) {
        const double x = v.value(i);
        auto it = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(x, -1));
        if (it == sorted.end() || it->first != x)
          refuse(x, i, "has no entry in the label map (values mapped: " + listed + ")");
        out[i] = static_cast<std::uint8_t>(it->second);
        ++usedValue[static_cast<size_t>(it - sorted.begin())];
      }
    }
  } else {
    for (Index i = 0; i < n; ++i) {
      const double x = v.value(i);
      if (!(x >= 0 && x <= 255 && x == std::floor(x)))
        refuse(x, i, "is not a label 0..255; give a label map or a threshold");
      out[i] = static_cast<std::uint8_t>(x);
      ++used[static_cast<size_t>(x)];
    }
  }
  if (rule.requireEveryLabel) {
    auto check = [&](int label, const std::string& what) {
      if (used[static_cast<size_t>(label)] == 0)
        throw InputError(v.source + ": " + what + " (label " + std::to_string(label) +
                         ") has no voxel in the " + shapeText(v.n) + " image: an empty phase");
    };
    if (rule.threshold) {
      check(rule.below, "no value lies below the threshold " + numText(rule.level));
      check(rule.above, "no value lies at or above the threshold " + numText(rule.level));
    }
    for (size_t k = 0; k < sortedMap.size(); ++k)
      if (usedValue[k] == 0)
        throw InputError(v.source + ": value " + numText(sortedMap[k].first) + " (label " +
                         std::to_string(sortedMap[k].second) + ") has no voxel in the " +
                         shapeText(v.n) + " image: an empty phase");
  }
  return img;
}

std::vector<std::pair<double, Index>> valueHistogram(const RawVolume& v, size_t limit) {
  std::map<double, Index> h;
  const Index n = v.voxelCount();
  for (Index i = 0; i < n; ++i) {
    auto it = h.find(v.value(i));
    if (it != h.end()) {
      ++it->second;
    } else if (h.size() < limit) {
      h.emplace(v.value(i), 1);
    } else {
      std::vector<std::pair<double, Index>> out(h.begin(), h.end());
      out.emplace_back(std::numeric_limits<double>::quiet_NaN(), -1);
      return out;
    }
  }
  return {h.begin(), h.end()};
}

}  // namespace poresph
