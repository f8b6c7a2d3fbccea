#pragma once
// A hairy ball: straight fur strands rooted on a sphere, over a dense isotropic core. The colour
// varies smoothly from one pole to the other (Fig. 18, fourth row, downsampling paper); or, with
// two materials, the +x and -x hemispheres carry fur of different albedo and roughness (Fig. 11).
// World units: the ball is centred on the origin.

#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/math/vector.h"
#include "libvdbappear/procedural/fill_memory.h"

#include <cstdint>

namespace vdbappear {

struct HairyBallParams {
  int resolution = 128;          // voxels along the largest side
  std::uint64_t seed = 1;
  double radius = 1.0;           // core radius
  double hair_length = 0.6;
  double strand_spacing = 0.04;  // roots are a Fibonacci lattice of 4 pi r^2 / spacing^2 points
  double strand_radius = 0.012;
  double tilt_degrees = 25;      // strands lean from the normal by up to this angle, random azimuth
  double strand_density = 50;    // rho inside a strand
  double core_density = 30;      // rho of the core (isotropic flakes)
  bool two_materials = false;
  Vec3 colour_a = Vec3(0.90, 0.55, 0.10);  // gradient: at the -z pole ...
  Vec3 colour_b = Vec3(0.15, 0.35, 0.85);  // ... to the +z pole
  Vec3 material_a = Vec3(0.90, 0.85, 0.75);  // two materials: +x hemisphere, roughness 0.1
  Vec3 material_b = Vec3(0.45, 0.25, 0.12);  // -x hemisphere, roughness 0.4
  double roughness = 0.2;        // gradient fur roughness
  FillMemory memory;             // by default made whole in memory
};

// Number of strands the root lattice holds.
int hairyBallStrandCount(const HairyBallParams& params);

MediumPtr makeHairyBall(const HairyBallParams& params);

}  // namespace vdbappear
