#pragma once
// Reading segmented or grey voxel images from the common file formats, and turning their values
// into labels (docs/voxel-images.md).
//
//   raw    headerless, shape / voxel type / byte order / header bytes given by the caller
//   mhd    MetaImage header (.mhd, data in a file named by ElementDataFile, or LOCAL after it;
//          also .mha)
//   nhdr   NRRD header (.nhdr detached, .nrrd attached), encoding raw
//   tiff   TIFF stack: one multi-page file, or a folder of single- or multi-page files in name
//          order (baseline TIFF, uncompressed, one sample per pixel)
//   vti    VTK XML image data (point or cell data; the array named by `dataset`, or the only one)
//   hdf5   an HDF5 dataset of rank 2 (y, x) or 3 (z, y, x) (the one named by `dataset`, or the
//          only dataset at the root)
//
// Voxel types: uint8, uint16, int32, float32 (other integer types a header or VTK / HDF5 file
// declares are converted when their values fit). x varies fastest, then y, then z.
//
// Every size is checked before anything is allocated: a header whose sizes disagree with the
// data, a truncated file, an unknown type or encoding, an offset beyond the end of a TIFF: an
// InputError naming the file and the numbers, never a crash (tests/unit/test_image_io.cpp fuzzes
// them).
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "libcore/types.hpp"
#include "libcore/voxel_image.hpp"

namespace poresph {

enum class VoxelType { UInt8, UInt16, Int32, Float32 };

/// "uint8", "uint16", "int32", "float32".
std::string voxelTypeName(VoxelType t);
/// Bytes per voxel of the type.
int voxelTypeBytes(VoxelType t);
/// Parses a type name (also u8/uchar, u16/ushort, i32/int, f32/float); InputError listing the
/// names otherwise. `what` prefixes the message.
VoxelType parseVoxelType(const std::string& name, const std::string& what);

/// The image formats; "" = from the file name (extension, or a folder = TIFF stack).
std::vector<std::string> imageFormats();
/// The format of `path` from its extension (.raw .mhd .mha .nhdr .nrrd .tif .tiff .vti .h5 .hdf5)
/// or "tiff" for a folder; InputError naming the path and the formats otherwise.
std::string detectImageFormat(const std::string& path);

struct ImageFileSpec {
  std::string path;
  std::string format;                   ///< one of imageFormats(); "" = detectImageFormat(path)
  std::array<int, 3> shape{0, 0, 0};    ///< raw: voxels along x, y, z (z = 1 for a 2D image)
  VoxelType type = VoxelType::UInt8;    ///< raw
  bool bigEndian = false;               ///< raw
  std::uint64_t headerBytes = 0;        ///< raw: bytes skipped before the voxels
  std::string dataset;                  ///< hdf5: dataset path; vti: array name ("" = the only one)
};

/// Voxel values as read, before labelling: native byte order, x fastest.
struct RawVolume {
  std::string source;                     ///< "image 'path'" for messages
  std::array<int, 3> n{0, 0, 0};
  VoxelType type = VoxelType::UInt8;
  std::vector<unsigned char> bytes;       ///< voxelCount() x voxelTypeBytes(type)
  std::array<double, 3> spacing{0.0, 0.0, 0.0};  ///< from a header, in its own unit; 0 = none

  Index voxelCount() const { return static_cast<Index>(n[0]) * n[1] * n[2]; }
  /// Value of voxel i (x-fastest linear index) as a double (exact for every type).
  double value(Index i) const;
};

/// Reads the image `spec` describes. `extraBytesPerVoxel`: what the caller allocates next per
/// voxel (labels, analysis), part of the memory check made before the image is allocated.
RawVolume readVolume(const ImageFileSpec& spec, std::uint64_t extraBytesPerVoxel = 0);

/// Writes `v` in `format` (raw, mhd, nhdr, tiff, vti, hdf5): used by tests and conversions.
/// mhd / nhdr write a detached header (path) and the data next to it (path with .raw). hdf5
/// writes the dataset `dataset` ("image" if empty).
void writeVolume(const RawVolume& v, const std::string& path, const std::string& format,
                 const std::string& dataset = "");

/// From file values to labels (0..255).
///  - map: each listed file value becomes its label; a voxel whose value is not listed is an
///    error naming the value, how many voxels hold it and the first one;
///  - threshold: value < level -> `below`, otherwise `above` (grey images);
///  - neither: integer values 0..255 are their own labels (other values are refused).
/// With requireEveryLabel, a mapped label (or threshold side) that no voxel holds is an error
/// (an empty phase).
struct LabelRule {
  std::vector<std::pair<double, int>> map;  ///< file value -> label
  bool threshold = false;
  double level = 0.0;
  int below = 0, above = 1;
  bool requireEveryLabel = true;
  bool identity() const { return map.empty() && !threshold; }
};

VoxelImage applyLabels(const RawVolume& v, const LabelRule& rule);

/// Distinct values of the volume with their voxel counts (at most `limit` of them: more is
/// reported by a count of -1 in the last entry's second member).
std::vector<std::pair<double, Index>> valueHistogram(const RawVolume& v, size_t limit = 64);

}  // namespace poresph
