#pragma once
// Test media of simple shape: a cube, a sphere or a slab centred on the origin, homogeneous or with
// a smooth density variation, with a chosen density, albedo and phase function. Analytic cases
// (Beer-Lambert, white furnace) and the similarity work render these.

#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/math/vector.h"

#include <cstdint>
#include <string>
#include <vector>

namespace vdbappear {

enum class Shape { Cube, Sphere, Slab };

// How a test medium scatters.
enum class PhaseChoice {
  Isotropic,    // no SGGX grids, no hg_g: the contract's isotropic default
  Hg,           // constant Henyey-Greenstein g, as file metadata hg_g
  SggxFiber,    // constant S = Sggx::fiberMatrix(axis, roughness)
  SggxSurface,  // constant S = Sggx::surfaceMatrix(axis, roughness)
};
PhaseChoice phaseChoiceByName(const std::string& name);  // isotropic, hg, sggx-fiber, sggx-surface
const std::vector<std::string>& phaseChoiceNames();

struct ShapeParams {
  Shape shape = Shape::Cube;
  int resolution = 64;          // voxels along the largest side
  std::uint64_t seed = 1;       // phase of the density variation
  double size = 1;              // world edge of the cube and of the slab's square, sphere diameter
  double thickness = 0.25;      // slab thickness (world units, along z), rounded to whole voxels
  double density = 10;          // rho, 1/world unit
  Vec3 albedo = Vec3::Constant(0.8);
  PhaseChoice phase = PhaseChoice::Isotropic;
  double g = 0;                 // HG asymmetry
  Vec3 axis = Vec3::UnitZ();    // SGGX fiber tangent or surface normal
  double roughness = 0.3;       // SGGX roughness
  double variation = 0;         // density = rho (1 + variation * v(p)), v a smooth field in [-1,1] of mean 0
};

MediumPtr makeShape(const ShapeParams& params);

}  // namespace vdbappear
