#pragma once
// A render as data: what `vdb_render --scene FILE.json` reads and what its flags set (flags
// override the file). docs/rendering.md documents every key. Lights stay JSON objects, one schema
// for the file and the flags:
//   {"type": "env", "radiance": L | [r,g,b]}
//   {"type": "env_map", "file": "sky.exr", "scale": 1}
//   {"type": "sh", "l": 1, "m": 0, "scale": 1}
//   {"type": "sun", "direction": [dx,dy,dz], "strength": E | [r,g,b]}     direction: where light travels
//   {"type": "point", "position": [x,y,z], "intensity": I | [r,g,b]}
//   {"type": "quad", "corner": p, "edge1": e1, "edge2": e2, "radiance": L, "two_sided": false}
//   {"type": "polygon", "vertices": [p0, p1, ...], "radiance": L, "two_sided": false}

#include "libvdbappear/image/rgb_image.h"
#include "libvdbappear/lightgrid/polygon_light.h"
#include "libvdbappear/medium/interpolation.h"
#include "libvdbappear/render/camera.h"
#include "libvdbappear/render/level_of_detail.h"
#include "libvdbappear/render/render_image.h"
#include "libvdbappear/subsurface/translucent_object.h"
#include "libvdbappear/surface/height_field_mesh.h"
#include "libvdbappear/surface/microfacet_brdf.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace vdbappear {

struct PrefilteredSurfaceFile;

// "brdf": {"distribution": "ggx" | "beckmann", "roughness": ALPHA, "specular": F0 | [r,g,b],
// "diffuse": A | [r,g,b]} makes a surface glossy (surface/microfacet_brdf.h; defaults ggx, 0.3,
// 0.04, 0); without it a surface is Lambertian of its "albedo".
struct MeshDescription {
  std::string file;
  Rgb albedo = Rgb::Constant(0.5);
  std::optional<MicrofacetBrdf> brdf;
  // A closed mesh of a translucent interior (docs/subsurface.md) instead of a diffuse surface:
  // "translucent": {"density": D | [r,g,b], "albedo": A | [r,g,b], "g": G, "eta": ETA}.
  std::optional<TranslucentMaterial> translucent;
};

struct GroundDescription {
  std::optional<double> height;  // z of the plane; default: the bottom of the medium's bounds
  Rgb albedo = Rgb::Constant(0.5);
  std::optional<MicrofacetBrdf> brdf;
};

// "height_fields": [{"file": "bumps.exr", "size": S, "origin": [x,y,z], "height_scale": K,
// "tiles": [nx, ny], "albedo" | "brdf"}]: a displacement map (first channel; docs/displacement.md)
// as a surface facing +z, one tile S wide along x, tessellated at its full resolution.
// Or {"prefiltered": "relief_8x.json", "origin", "tiles", "scaling": true}: a map prefiltered by
// vdb_displacement_prefilter (docs/displacement.md §6, §8), h_low shaded by its SVBRDF; its size,
// height scale and base BRDF come from the manifest. "scaling": false leaves out T S (f'_low alone,
// the multi-lobe model of Fig. 4.16 that the scaling function corrects).
// Or {"mipmap": ["relief_8x.json", "relief_32x.json"], "file": "relief.exr", "origin", "tiles",
// "scaling"}: a mipmap of prefiltered maps of one original, factors increasing, with the original
// (optional "file", its size, height scale and BRDF from the manifests) as its finest level; each
// path is traced on the level its camera ray's pixel footprint picks (§4.7.2;
// render/level_of_detail.h): by its width across the view ("footprint": "narrow", the default) or
// by the square root of its area ("area").
// "sphere": [x, y, z] (with "file", "prefiltered" or "mipmap", not "origin"): the tiles shell-mapped
// over a sphere centred there on which tiles[0] tiles span the equator, tiles[1] pole to pole
// (surface/sphere_shell.h; the ball of Fig. 4.18).
// "mesh": "base.obj" (with "file", "prefiltered" or "mipmap", not "origin" or "sphere"): the tiles
// shell-mapped over a mesh by its UVs, tiles[0] along u and tiles[1] along v over [0,1]^2, displaced
// along its shading normals (surface/mesh_shell.h); "vertices_per_cell": V splits the mesh's triangles so that
// their edges span at most 1 / V of the map's cells (default 1, and 2 for a prefiltered map).
struct HeightFieldDescription {
  std::string file;
  std::optional<Vec3> sphere_centre;
  std::string mesh;  // the base mesh's file, instead of the plane or the sphere
  std::optional<double> vertices_per_cell;
  std::string prefiltered;  // the manifest, instead of file
  std::vector<std::string> mipmap;  // manifests, instead of prefiltered; file: the original as level 0
  bool scaling = true;      // prefiltered: f_low = T S f'_low, or f'_low alone
  FootprintWidth footprint = FootprintWidth::narrow;  // mipmap: which width of a pixel's footprint picks the levels
  double size = 1;
  HeightFieldPlacement placement;
  Rgb albedo = Rgb::Constant(0.5);
  std::optional<MicrofacetBrdf> brdf;
};

struct SceneDescription {
  std::string medium;                // path; "" for none
  std::optional<std::string> view;   // +x ... -z: frames the medium (camera position/target/up ignored)
  CameraPose camera;
  bool camera_given = false;         // position/target set explicitly
  Interpolation interpolation = Interpolation::kNearest;
  RenderSettings render;
  bool spp_given = false;            // the file set "spp" (with "time" or --time, it caps the samples)
  nlohmann::json lights = nlohmann::json::array();
  std::optional<GroundDescription> ground;
  std::vector<MeshDescription> meshes;
  std::vector<HeightFieldDescription> height_fields;
  // "subsurface": {"sample_spacing", "max_solid_angle", "disk_radius", "light_samples", "cache_error",
  // "min_cache_radius", "max_cache_radius", "min_normal_cos"} (docs/subsurface.md §1).
  SubsurfaceSettings subsurface;
};

// The lights of a render that names none (issue 26): a dim sky of 0.1 and a sun of irradiance 3
// travelling along (0.51, 0.65, -0.565): from high on the side of -x and -y (the upper left of
// vdb_info's three-quarter view), so a terminator crosses a medium seen from the default +z or from
// that view. (A sun from behind that view lights a cloud flat: on the white smoke of
// InfoCli.SuggestedRenderFramesAndShowsAWhiteSmoke the 4x4-tile means of its footprint spread by
// 6.5%, against 49% with this one.) Under a white sky alone (the white
// furnace, `--env 1`, the default until 2026-11-26), a medium of albedo 1 absorbs nothing and
// vanishes into the background; here a white smoke and a dark absorbing one both show their shape.
nlohmann::json defaultLights();

// A "brdf" object (keys above) as a microfacet BRDF; throws std::runtime_error "SOURCE: WHERE: what".
MicrofacetBrdf brdfFromJson(const nlohmann::json& brdf, const std::string& source, const std::string& where);
// The inverse, with every key written out.
nlohmann::json brdfToJson(const MicrofacetBrdf& brdf);

// Reads a scene file; relative paths in it (medium, meshes, environment maps) are taken relative
// to the file's folder. Throws std::runtime_error "FILE: KEY: what is wrong".
SceneDescription readSceneFile(const std::string& path);
// Applies the keys of a JSON object to `scene` (the file's content; `folder` resolves paths).
void applySceneJson(const nlohmann::json& json, const std::string& folder, const std::string& source,
                    SceneDescription* scene);

// Builds the lights and surfaces, and runs pass 1 of each translucent object (its irradiance
// samples; render/direct_irradiance.h). read_image loads environment maps (the image library's
// readRgbImage in tools). The camera is framed with --view on the medium's bounds when asked.
using ImageReader = std::function<RgbImage(const std::string&)>;
// Reads a prefiltered displacement map's manifest and parts (the image library's
// readPrefilteredSurface in tools).
using PrefilteredReader = std::function<PrefilteredSurfaceFile(const std::string&)>;
RenderScene buildRenderScene(const SceneDescription& scene, std::shared_ptr<const MediumView> medium,
                             const ImageReader& read_image, const PrefilteredReader& read_prefiltered = {});
CameraPose cameraOf(const SceneDescription& scene, const MediumView* medium);

// The scene's area lights (quad, polygon, triangle) as polygons, in file order, each checked by
// validatePolygonLight: what `vdb_sh_lightgrid --scene` prefilters and what `vdb_render
// --sh-lightgrid` then stops sampling. Throws std::runtime_error "lights[K]: what is wrong".
std::vector<PolygonLight> sceneAreaLights(const SceneDescription& scene);

}  // namespace vdbappear
