#pragma once
// Woven fabric of twisted fibers: warp yarns along x and weft yarns along y cross over and under
// per a weave pattern (plain, twill, satin); each yarn is a bundle of helical fibers. Density comes
// from fiber occupancy (supersampled), S from the local fiber tangent (fiber-like SGGX), albedo
// from the yarn set, so warp and weft can carry different colours (the two-coloured twill of Fig. 9,
// downsampling paper). Layers stack along z. Geometry is in world units (yarn spacing 1) and does
// not change with the resolution.

#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/math/vector.h"
#include "libvdbappear/procedural/fiber_field.h"
#include "libvdbappear/procedural/fill_memory.h"
#include "libvdbappear/procedural/weave_pattern.h"

#include <cstdint>
#include <string>

namespace vdbappear {

struct WeaveParams {
  int resolution = 128;          // voxels along the largest side
  std::uint64_t seed = 1;        // fiber placement and per-fiber colour jitter
  std::string pattern = "twill"; // plain, twill or satin
  int harness = 0;               // pattern repeat; 0: the pattern's default (twill 4, satin 5)
  int yarns = 4;                 // warp and weft yarns per side
  int layers = 1;                // fabric layers, one world unit apart along z
  double fiber_density = 40;     // rho inside a fiber, 1/world unit
  double roughness = 0.1;        // SGGX fiber roughness: eigenvalue roughness^2 along the fiber
  double twist_pitch = 4;        // world units per full turn of the fibers about the yarn axis
  Vec3 warp_albedo = Vec3(0.85, 0.30, 0.45);  // pink warp, yellow weft: Fig. 9's colours
  Vec3 weft_albedo = Vec3(0.85, 0.75, 0.25);
  FillMemory memory;             // by default made whole in memory
};

// Yarn cross-section and fiber layout, world units (yarn spacing 1). Fibers are discs of radius
// kFiberRadius around jittered centres of a kFiberSpacing grid in the cross-section, the jitter small
// enough that a disc never leaves its cell: fibers cover pi (r/spacing)^2 = 45.4% of a yarn.
struct WeaveGeometryConstants {
  static constexpr double kHalfWidth = 0.42;      // cross-section semi-axis across the fabric
  static constexpr double kHalfHeight = 0.14;     // cross-section semi-axis through the fabric
  static constexpr double kAmplitude = 0.16;      // crimp: centreline height at a crossing (> kHalfHeight)
  static constexpr double kFiberSpacing = 0.05;
  static constexpr double kFiberRadius = 0.019;
  static constexpr double kFiberJitter = 0.5 * kFiberSpacing - kFiberRadius;  // max centre offset per axis
  static constexpr double kFiberCoverage = 3.14159265358979323846 * (kFiberRadius / kFiberSpacing) *
                                           (kFiberRadius / kFiberSpacing);
};

// A point inside a yarn: where the yarn runs, and the point's offset in its cross-section.
struct YarnPoint {
  bool warp;
  int layer, yarn;  // the yarn's index across the fabric
  double u, v;      // offsets across the fabric and through it (vertically) from the centreline
  double along;     // position along the yarn
  double slope;     // d(centreline height) / d(along)
};

// The yarn's frame at a point: its unit centreline tangent and the cross-section's two axes.
struct YarnFrame {
  Vec3 axis, across, through;
};
YarnFrame yarnFrame(const YarnPoint& y);

class WeaveGeometry : public FiberField, public WeaveGeometryConstants {
 public:
  explicit WeaveGeometry(const WeaveParams& params);  // pattern by name, from params
  WeaveGeometry(const WeaveParams& params, WeavePattern pattern);

  // The yarn of set `warp` whose cross-section holds p, if any.
  std::optional<YarnPoint> locateYarn(const Vec3& p, bool warp) const;
  std::optional<FiberPoint> fiberAt(const Vec3& p) const override;
  // Supersampled voxel, with a quick rejection of voxels far from every yarn.
  std::optional<VoxelSample> sampleVoxel(const Vec3& centre, double voxel_size) const;
  // Can the slab z0 <= z <= z1 meet a yarn?
  bool slabMayHoldYarns(double z0, double z1) const;

  const WeaveParams& params() const { return params_; }
  const WeavePattern& pattern() const { return pattern_; }

 private:
  bool onTop(bool warp, int yarn, int crossing) const;
  double fiberAngle(double along) const;

  WeaveParams params_;
  WeavePattern pattern_;
};

MediumPtr makeWeave(const WeaveParams& params);

}  // namespace vdbappear
