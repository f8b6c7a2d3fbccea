#pragma once
// A cloud: smooth heterogeneous smoke-like density inside a sphere, dense and forward scattering
// (HG g, constant or varying with density), for the similarity work. Density is fractal gradient noise plus a bump that
// favours the centre, thresholded so that a chosen share of the sphere holds smoke, with soft edges.

#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/math/vector.h"

#include <cstdint>
#include <optional>

namespace vdbappear {

struct CloudParams {
  int resolution = 128;         // voxels along the largest side
  std::uint64_t seed = 1;
  double size = 2;              // diameter of the bounding sphere (world units), centred on the origin
  double density = 40;          // peak rho, 1/world unit
  double coverage = 0.5;        // share of the sphere's voxels that hold smoke (density > 0)
  double feature_size = 0.6;    // world size of the largest noise features
  int octaves = 5;
  double edge_softness = 0.15;  // width of the density ramp at the cloud's edge, in noise units
  Vec3 albedo = Vec3::Constant(0.98);
  double g = 0.9;               // HG asymmetry, written as file metadata hg_g
  // When set: an hg_g grid instead, g_edge where the density vanishes rising linearly with the
  // density to g at the peak (a continuous per-voxel g).
  std::optional<double> g_edge;
};

MediumPtr makeCloud(const CloudParams& params);

}  // namespace vdbappear
