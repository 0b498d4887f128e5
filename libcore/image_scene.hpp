#pragma once
// Scenes from images: the geometry shape `image` (docs/scene-format.md, "Images").
//
//   - shape: image
//     file: ../data/ketton_128.raw      # relative to the scene file
//     size: [128, 128, 128]             # raw only (also voxel_type, byte_order, header_bytes)
//     labels: {0: water, 255: clay}     # file value -> material (or none); or threshold: {...}
//     crop: {lo: [0, 0, 0], size: [32, 32, 32]}   # voxels of the file
//     slice: {axis: z, index: 16}       # a 2D scene from a 3D image
//     coarsen: 2                        # majority vote over 2^D blocks
//     voxel_size: 5.0e-6                # m; voxel_size x coarsen must equal spacing
//     origin: [0, 0, 0]                 # lower corner (default domain.lo), on the lattice
//
// One particle per (coarsened) voxel, on the scene's lattice, with the material its label maps
// to. The image is read, labelled, cropped, sliced and coarsened in that order while the scene is
// loaded; the regions it adds (one per material of the label map) share the label grid.
#include <vector>

#include <yaml-cpp/yaml.h>

#include "libcore/geometry.hpp"
#include "libcore/parameters.hpp"
#include "libcore/simulation.hpp"

namespace poresph {

/// Reads the image geometry entry `g` (its `shape` already read), appends its regions to
/// `regions` and describes it in `echo` (the resolved geometry entry). Errors are InputErrors
/// naming the scene file, line and key (and the image file and its numbers).
void appendImageRegions(const ParameterSet& g, const Simulation& sim, std::vector<Region>& regions,
                        YAML::Node& echo);

}  // namespace poresph
