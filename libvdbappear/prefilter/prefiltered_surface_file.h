#pragma once
// The files of a prefiltered displacement map (docs/displacement.md §6): a JSON manifest OUT.json
// and four OpenEXR files beside it, named after it,
//   OUT.height.exr  h_low, (n/F + 1)^2 heights, the height-map contract of §1;
//   OUT.lobes.exr   the SVNDF, one pixel per coarse cell, channels lobeK.{A,kappa,X,Y,Z};
//   OUT.T.exr       T_ir(x), M x M RGB;   OUT.S.exr  S_ir(wi, wo), N^2 x N^2 RGB;
// and for each stretched tile's tables (PrefilteredSurface::stretched) OUT.stretchK.T.exr and
// OUT.stretchK.S.exr, K from 1, listed with their stretch under the manifest's "stretched" key.
// With the relief term (a manifest's "relief_radius" r > 0) each S has its B beside it, OUT.B.exr
// and OUT.stretchK.B.exr, laid out as S; z is h_low's CellRelief of radius r, made anew on reading.
// Part of the image library (vdbappear::image).

#include "libvdbappear/prefilter/displacement_prefilter.h"

#include <nlohmann/json_fwd.hpp>

#include <string>

namespace vdbappear {

// What the manifest says besides the tables.
struct PrefilteredSurfaceInfo {
  std::string source;         // the original map
  int factor = 8;
  double size = 1;            // world width of one tile, as the scene's "size"
  double height_scale = 1;    // the file's heights times this are world units
  ScalingKind scaling = ScalingKind::Interreflection;
};

struct PrefilteredSurfaceFile {
  PrefilteredSurface surface;  // heights in world units
  MicrofacetBrdf base;         // f_orig
  PrefilteredSurfaceInfo info;
};

// Writes the four images and then the manifest, each through a temporary file and a rename.
// `extra` (settings, timings, history) is stored under the manifest's "settings" key.
void writePrefilteredSurface(const PrefilteredSurfaceFile& file, const std::string& manifest_path,
                             const nlohmann::json& extra);

// Throws MediumError naming the manifest or the image and what is wrong.
PrefilteredSurfaceFile readPrefilteredSurface(const std::string& manifest_path);

// The image beside the manifest: "dir/out.json" and "T" give "dir/out.T.exr".
std::string prefilteredPartPath(const std::string& manifest_path, const std::string& part);

}  // namespace vdbappear
