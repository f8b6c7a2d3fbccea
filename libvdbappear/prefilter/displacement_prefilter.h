#pragma once
// The whole prefiltering of a displacement map at one scale, §4.7.1 of the displacement chapter
// (shared/papers/002_6a636dc24396287c.txt): from h_orig over the base micro-BRDF f_orig,
//   1. h_low by least squares on the meso-scale slopes (Eq. 4.9-4.10, surface/height_downsample.h);
//   2. per coarse patch, its NDF as six vMF lobes (Eq. 4.2-4.4, surface/patch_ndf.h), which with
//      f_orig give the multi-lobe SVBRDF f'_low (Eq. 4.5, 4.11, surface/multi_lobe_brdf.h);
//   3. the scaling function, R of Eq. (4.12) (shadowing and masking) or R_ir of Eq. (4.20) (with
//      interreflections, prefilter/multi_bounce_effective_brdf.h), sampled sparsely and
//   4. factorised as T_ir(x) S_ir(wi, wo) (Eq. 4.21-4.24, prefilter/scaling_factorization.h),
// so that f_low = T S f'_low (Eq. 4.13, 4.18) on h_low. Files: prefilter/prefiltered_surface_file.h.

#include "libvdbappear/prefilter/scaling_factorization.h"
#include "libvdbappear/surface/height_field.h"
#include "libvdbappear/surface/microfacet_brdf.h"
#include "libvdbappear/surface/tile_edges.h"
#include "libvdbappear/surface/tile_stretch.h"
#include "libvdbappear/surface/vmf_ndf.h"

#include <cstdint>
#include <vector>

namespace vdbappear {

class ProgressBar;

enum class ScalingKind {
  Shadowing,        // R of Eq. (4.12): single-bounce effective BRDFs
  Interreflection,  // R_ir of Eq. (4.20): the original's multi-bounce effective BRDF
};

struct DisplacementPrefilterSettings {
  int factor = 8;                   // coarse cell side in fine cells (Table 4.3: 8 to 64)
  double smoothness_weight = 0.01;  // w of Eq. (4.10)
  int normals_per_cell_side = 4;    // micro-normals per fine cell, k^2 (surface/patch_ndf.h)
  VmfFitSettings ndf;               // six lobes per patch (§4.7.1)
  ScalingKind scaling = ScalingKind::Interreflection;
  int samples_per_side = 50;        // 2500 paths per effective BRDF estimate (§4.7.1)
  int max_vertices = 32;            // of a path in the micro-geometry
  FactorizationSettings factorization;  // M = 4, N = 15, 5000 pairs per T bin, 16 p per S bin
  // Tiles that a surface lays the map out stretched as (surface/tile_stretch.h; a sphere's tiles
  // narrow toward its poles): the scaling tables also for each of them, besides the square tile's.
  std::vector<TileStretch> stretches;
  // The curvature (1 / world units) of the base the tables are made over: both micro-geometries
  // bend away from every point as a sphere of radius 1 / base_curvature does, so that what a convex
  // base's bumps shadow and mask, and where R_ir's paths bounce, is what R counts (MicroGeometry).
  // 0: a plane, the chapter's. docs/displacement.md §6, "Tables for a curved base".
  double base_curvature = 0;
  // Open: the tables of the map alone, whose cells along its edges see nothing beyond them (the
  // chapter's). Periodic: of the map as a tile among its copies, as the renderer lays tiles out
  // (docs/displacement.md §6, "Tables over a periodic tile").
  TileEdges edges = TileEdges::Open;
  // With r > 0, S also holds the relief term: R ~ T(x) [S(wi, wo) + B(wi, wo) z(x)], z the relief of
  // h_low's cells over the (2r + 1)^2 cells about them (surface/cell_relief.h), which R depends on at
  // grazing views. 0: the chapter's rank one. docs/displacement.md §6, "The relief term".
  int relief_radius = 0;
  std::uint64_t seed = 1;
};

// The scaling tables of a tile laid out stretched by `stretch`: R_ir (or R) of the stretched
// original over the model as it shades that tile, MultiLobeBrdf::onStretchedTile on the stretched
// h_low, factorised as T S with directions in the stretched surface's frame (docs/displacement.md
// §6, "Tables for stretched tiles").
struct StretchedScaling {
  TileStretch stretch;
  FactorizedScaling scaling;
};

struct PrefilteredSurface {
  HeightField height;             // h_low
  std::vector<VmfMixture> ndfs;   // coarse cell (u, v) at u + cells_x v
  FactorizedScaling scaling;      // T S of the square tile
  std::vector<StretchedScaling> stretched;  // T S of stretched tiles, one per settings.stretches
  struct {
    double height = 0, ndfs = 0, scaling = 0;  // wall-clock seconds of steps 1, 2 and 3-4
  } seconds;
};

// Throws std::invalid_argument when the factor does not divide the map's cell counts or a setting
// is out of range.
PrefilteredSurface prefilterDisplacement(const HeightField& fine, const MicrofacetBrdf& base,
                                         const DisplacementPrefilterSettings& settings,
                                         ProgressBar* progress = nullptr);

// The patch NDFs of step 2 alone, one per coarse cell (in parallel; deterministic).
std::vector<VmfMixture> fitPatchNdfs(const HeightField& fine, const DisplacementPrefilterSettings& settings);

}  // namespace vdbappear
