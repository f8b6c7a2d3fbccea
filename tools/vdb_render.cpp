// vdb_render: an unbiased volumetric path tracer for media (docs/rendering.md).
#include "tool_main.h"

#include "libvdbappear/cluster/process_group.h"
#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/io/sh_light_grid_file.h"
#include "libvdbappear/lightgrid/sh_grid_lookup.h"
#include "libvdbappear/medium/medium_view.h"
#include "libvdbappear/prefilter/prefiltered_surface_file.h"
#include "libvdbappear/render/render_output.h"
#include "libvdbappear/render/scene_description.h"
#include "libvdbappear/render/subsurface_passes.h"
#include "libvdbappear/util/progress.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>

#include <algorithm>
#include <optional>

using namespace vdbappear;

namespace {

constexpr const char* kTool = "vdb_render";

constexpr const char* kExamples = R"(Examples:
  vdb_render twill.vdb -o twill.exr --view +z --spp 256 --env 0.2 --sun 1,1,-2,3 --ground
  vdb_render cloud.vdb -o cloud.exr --preview cloud.png --time 60 --env-map sky.exr
  vdb_render twill_4x.vdb -o train.exr --view -x --res 128x128 --sh-light 1,-1 --aov variance,cluster
  vdb_render twill_4x_lobes.vdb -o grad.exr --view +z --res 100 --aov dweights  (dI/dw per cluster and lobe)
  vdb_make_medium cloud -o - | vdb_render - -o cloud.png --camera-pos 0,-3,0.5 --camera-target 0,0,0
  vdb_render --scene scene.json -o out.exr --spp 64      (flags override the file)
  vdb_render houdini_smoke.vdb -o smoke.png --grid albedo=Cd --grid density=density:0.5   (foreign grid names)
  vdb_render fire.vdb -o fire.png --grid emission=flame:20    (a fire grid as emission, docs/medium.md 3b)
  vdb_render twill1024.vdb -o twill.exr -v     (read in pieces into the compact form: float density, half-float
      albedo and S, 26 bytes an active voxel; --full-precision holds the float grids: docs/rendering.md)
  mpirun -n 4 vdb_render velvet.vdb -o velvet.exr --res 1280x720 --spp 4096 -j 8   (ranks share the tiles;
      the same image at any rank count: docs/scaling.md)
  vdb_render --translucent-mesh bunny.obj --sss-density 2.2,2.6,3.0 --sss-albedo 0.999 --camera-pos 0,-4,1
      --camera-target 0,0,0 -o bunny.exr --sun 1,1,-1,3   (a translucent object by the dipole; docs/subsurface.md)
Without a light flag or scene lights: a dim sky and a sun from the upper side (--env 0.1
--sun 0.51,0.65,-0.565,3), which show a white smoke as well as a dark one. The white furnace
(a white sky alone, the default before 2026-11-26) is --env 1.
Without a camera, it is framed from +z (--view +z). Units: docs/rendering.md.)";

// Flags as given on the command line; each one that was given overrides the scene file.
struct Flags {
  std::string medium, output, preview, scene, report, res, view, interp, strategy, env_map, sh_lightgrid, sh_interp = "hermite";
  std::vector<double> camera_pos, camera_target, camera_up, env, sun, point_light, ground_albedo;
  std::vector<int> sh_light;
  std::vector<std::string> aovs, meshes, translucent_meshes;
  std::vector<double> sss_density, sss_albedo;
  double fov = 30, time = 0, ground_height = 0, sss_g = 0, sss_eta = 1.3, sss_spacing = 0.5, sss_solid_angle = 0.1,
         sss_error = 0.03;
  int spp = 16, max_depth = -1, sss_light_samples = 64;
  std::uint64_t seed = 0;
  bool ground = false, verbose = false, no_sggx = false, sh_unshadowed = false, full_precision = false;
  tool::SlabReading slabs;  // --memory, --in-core: how a medium file is read into the compact form
};

Vec3 vec3Of(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

std::pair<int, int> parseResolution(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  const int n = std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra);
  if (n == 1) h = w;
  else if (n != 3 || (x != 'x' && x != 'X')) throw std::runtime_error("--res '" + text + "': expected WxH or N");
  if (w < 1 || h < 1 || w > 16384 || h > 16384) throw std::runtime_error("--res '" + text + "': sizes must lie in 1..16384");
  return {w, h};
}

// A colour flag: one value (grey) or three.
nlohmann::json rgbJson(const std::vector<double>& v, const char* flag) {
  if (v.size() != 1 && v.size() != 3) throw std::runtime_error(fmt::format("{}: give one value or three (R,G,B)", flag));
  return v.size() == 1 ? nlohmann::json(v[0]) : nlohmann::json(v);
}
Rgb rgbOf(const std::vector<double>& v, const char* flag) {
  const nlohmann::json j = rgbJson(v, flag);
  return j.is_number() ? Rgb::Constant(j.get<double>()) : Rgb(v[0], v[1], v[2]);
}

// Lights given by flags replace the scene file's lights.
nlohmann::json lightsOf(const CLI::App& app, const Flags& f) {
  nlohmann::json lights = nlohmann::json::array();
  if (app.count("--env")) lights.push_back({{"type", "env"}, {"radiance", rgbJson(f.env, "--env")}});
  if (app.count("--env-map")) lights.push_back({{"type", "env_map"}, {"file", f.env_map}});
  if (app.count("--sh-light")) lights.push_back({{"type", "sh"}, {"l", f.sh_light[0]}, {"m", f.sh_light[1]}});
  if (app.count("--sun"))
    lights.push_back({{"type", "sun"}, {"direction", {f.sun[0], f.sun[1], f.sun[2]}}, {"strength", f.sun[3]}});
  if (app.count("--point-light"))
    lights.push_back({{"type", "point"}, {"position", {f.point_light[0], f.point_light[1], f.point_light[2]}},
                      {"intensity", f.point_light[3]}});
  return lights;
}

// The material of --translucent-mesh: the --sss-* flags over TranslucentMaterial's defaults. They
// describe --translucent-mesh only (a scene file gives each mesh its own "translucent" object).
TranslucentMaterial translucentOf(const CLI::App& app, const Flags& f) {
  TranslucentMaterial material;
  if (app.count("--sss-density")) material.sigma_t = rgbOf(f.sss_density, "--sss-density");
  if (app.count("--sss-albedo")) material.albedo = rgbOf(f.sss_albedo, "--sss-albedo");
  if (app.count("--sss-g")) material.g = f.sss_g;
  if (app.count("--sss-eta")) material.eta = f.sss_eta;
  try {
    validateTranslucentMaterial(material, "--translucent-mesh");
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());
  }
  return material;
}

SceneDescription sceneOf(const CLI::App& app, const Flags& f) {
  SceneDescription scene = f.scene.empty() ? SceneDescription() : readSceneFile(f.scene);
  if (!f.medium.empty()) scene.medium = f.medium;
  if (app.count("--res")) std::tie(scene.render.width, scene.render.height) = parseResolution(f.res);
  if (app.count("--spp")) scene.render.spp = f.spp;
  if (app.count("--time")) scene.render.time_seconds = f.time;
  if (app.count("--time") && !app.count("--spp") && !scene.spp_given) scene.render.spp = 1 << 30;
  if (app.count("--seed")) scene.render.seed = f.seed;
  if (app.count("--max-depth")) scene.render.path.max_depth = f.max_depth;
  if (app.count("--interp")) scene.interpolation = parseInterpolation(f.interp);
  if (app.count("--strategy")) scene.render.path.strategy = parseLightStrategy(f.strategy);
  if (app.count("--camera-pos")) {
    scene.camera.position = vec3Of(f.camera_pos);
    scene.camera_given = true;
    scene.view.reset();
  }
  if (app.count("--camera-target") && !scene.camera_given)
    throw std::runtime_error("--camera-target needs --camera-pos (or use --view)");
  if (app.count("--camera-target")) scene.camera.target = vec3Of(f.camera_target);
  if (app.count("--camera-up")) scene.camera.up = vec3Of(f.camera_up);
  if (app.count("--fov")) scene.camera.fov_degrees = f.fov;
  if (app.count("--view")) scene.view = f.view;
  const nlohmann::json flag_lights = lightsOf(app, f);
  if (!flag_lights.empty()) scene.lights = flag_lights;
  if (scene.lights.empty() && f.sh_lightgrid.empty()) scene.lights = defaultLights();
  if (f.ground || app.count("--ground-height") || app.count("--ground-albedo")) {
    GroundDescription ground = scene.ground.value_or(GroundDescription());
    if (app.count("--ground-height")) ground.height = f.ground_height;
    if (app.count("--ground-albedo")) ground.albedo = rgbOf(f.ground_albedo, "--ground-albedo");
    scene.ground = ground;
  }
  for (const char* flag : {"--sss-density", "--sss-albedo", "--sss-g", "--sss-eta"})
    if (app.count(flag) && f.translucent_meshes.empty())
      throw std::runtime_error(fmt::format("{} describes --translucent-mesh, and none is given (a scene file's meshes "
                                           "take \"translucent\": {{...}})", flag));
  if (!f.meshes.empty() || !f.translucent_meshes.empty()) scene.meshes.clear();  // flags override the file
  for (const std::string& file : f.meshes) {
    MeshDescription mesh;
    mesh.file = file;
    scene.meshes.push_back(mesh);
  }
  if (!f.translucent_meshes.empty()) {
    const TranslucentMaterial material = translucentOf(app, f);
    for (const std::string& mesh : f.translucent_meshes) scene.meshes.push_back({mesh, Rgb::Constant(0.5), std::nullopt, material});
  }
  if (app.count("--sss-spacing")) scene.subsurface.sample_spacing = f.sss_spacing;
  if (app.count("--sss-solid-angle")) scene.subsurface.max_solid_angle = f.sss_solid_angle;
  if (app.count("--sss-light-samples")) scene.subsurface.light_samples = f.sss_light_samples;
  if (app.count("--sss-error")) scene.subsurface.cache_error = f.sss_error;
  for (const std::string& aov : f.aovs) {
    if (aov == "variance" || aov == "alpha") continue;
    if (aov == "dweights") {
      scene.render.weight_gradients = true;
      continue;
    }
    if (aov == "sss") continue;
    if (aov == "time") {
      scene.render.pixel_seconds = true;
      continue;
    }
    if (aov != "cluster")
      throw std::runtime_error("--aov '" + aov + "': expected alpha, variance, cluster, dweights, sss or time");
    scene.render.cluster_coverage = true;
  }
  if (scene.medium.empty() && scene.meshes.empty() && scene.height_fields.empty() && !scene.ground)
    throw std::runtime_error("nothing to render: give a MEDIUM (or \"medium\" in --scene), a mesh, a translucent mesh, "
                             "a height field or a ground");
  if (scene.render.spp < 1) throw std::runtime_error("--spp must be >= 1");
  return scene;
}

void addFlags(CLI::App& app, Flags& f) {
  app.add_option("MEDIUM", f.medium, "medium (.vdb); - reads a VDB stream from stdin");
  app.add_option("-o,--output", f.output, "output image: .exr (linear float, with AOVs) or .png (sRGB)")->required();
  app.add_option("--preview", f.preview, "also write an sRGB PNG preview");
  app.add_option("--scene", f.scene, "JSON scene file (docs/rendering.md); flags override it");
  app.add_option("--res", f.res, "image size WxH, or N for NxN (default 256x256)");
  app.add_option("--spp", f.spp, "samples per pixel (default 16; with --time: the most to take)");
  app.add_option("--time", f.time, "render for this many seconds (passes of samples)")->check(CLI::PositiveNumber);
  app.add_option("--seed", f.seed, "random seed: same seed, same image, whatever the thread count")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--max-depth", f.max_depth, "most scattering events per path (-1: unlimited, default)")
      ->check(CLI::Range(-1, 1 << 20));
  app.add_option("--camera-pos", f.camera_pos, "camera position X,Y,Z")->delimiter(',')->expected(3);
  app.add_option("--camera-target", f.camera_target, "point the camera looks at X,Y,Z")->delimiter(',')->expected(3);
  app.add_option("--camera-up", f.camera_up, "camera up vector X,Y,Z (default 0,0,1)")->delimiter(',')->expected(3);
  app.add_option("--fov", f.fov, "vertical field of view in degrees (default 30)")->check(CLI::Range(0.01, 179.0));
  app.add_option("--view", f.view, "frame the medium from a side: +x -x +y -y +z -z");
  app.add_option("--env", f.env, "constant environment radiance R[,G,B]")->delimiter(',')->expected(1, 3);
  app.add_option("--env-map", f.env_map, "lat-long environment map (EXR, Blender's convention, z up)");
  app.add_option("--sh-light", f.sh_light, "environment radiance Y_lm(w): L,M (signed: see docs)")->delimiter(',')->expected(2);
  app.add_option("--sun", f.sun, "directional light DX,DY,DZ,STRENGTH (direction of travel; irradiance)")
      ->delimiter(',')->expected(4);
  app.add_option("--point-light", f.point_light, "point light X,Y,Z,INTENSITY")->delimiter(',')->expected(4);
  app.add_flag("--ground", f.ground, "a diffuse ground plane z = bottom of the medium");
  app.add_option("--ground-height", f.ground_height, "z of the ground plane (implies --ground)");
  app.add_option("--ground-albedo", f.ground_albedo, "ground albedo A or R,G,B (default 0.5)")->delimiter(',')->expected(1, 3);
  app.add_option("--mesh", f.meshes, "diffuse mesh (OBJ, PLY; albedo 0.5); repeatable");
  app.add_option("--translucent-mesh", f.translucent_meshes,
                 "closed mesh of a translucent interior, rendered by the dipole (docs/subsurface.md); repeatable")
      ->check(CLI::ExistingFile);
  app.add_option("--sss-density", f.sss_density, "translucent interior: extinction sigma_t D[,G,B] per world unit (100)")
      ->delimiter(',')->expected(1, 3);
  app.add_option("--sss-albedo", f.sss_albedo, "translucent interior: albedo A[,G,B] (0.99)")->delimiter(',')->expected(1, 3);
  app.add_option("--sss-g", f.sss_g, "translucent interior: HG asymmetry g (0)");
  app.add_option("--sss-eta", f.sss_eta, "translucent boundary: index of refraction n_inside/n_outside (1.3)");
  app.add_option("--sss-spacing", f.sss_spacing,
                 "longest edge of the irradiance samples' faces, in diffusion lengths 1/sigma_tr (0.5)")
      ->check(CLI::PositiveNumber);
  app.add_option("--sss-solid-angle", f.sss_solid_angle,
                 "hierarchical integration: solid angle below which a cluster of samples is one term (0.1; 0: every sample)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--sss-error", f.sss_error,
                 "cache of subsurface illuminance: error bound a, relative to S (0.03); 0: no cache, every point integrated")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--sss-light-samples", f.sss_light_samples, "irradiance samples: light samples per point and area or sky light (64)")
      ->check(CLI::Range(1, 1 << 20));
  app.add_flag("--no-sggx", f.no_sggx, "ignore the SGGX grids (S = I: isotropic extinction and scattering), to compare "
               "with renderers that lack SGGX");
  app.add_option("--interp", f.interp, "voxel lookup: nearest (default) or trilinear");
  app.add_option("--strategy", f.strategy,
                 "light estimator: auto (default: MIS, smooth skies by phase sampling alone), mis, light or phase");
  app.add_option("--sh-lightgrid", f.sh_lightgrid,
                 "direct light of the area lights from this SH light grid (vdb_sh_lightgrid) instead of sampling every "
                 "area light; shadowed by the medium toward the grid's dominant direction")
      ->check(CLI::ExistingFile);
  app.add_flag("--sh-unshadowed", f.sh_unshadowed, "with --sh-lightgrid: no shadows at all (the dissertation's unshadowed lighting)");
  app.add_option("--sh-interp", f.sh_interp, "SH grid interpolation: hermite (default), trilinear or taylor")
      ->check(CLI::IsMember({"hermite", "trilinear", "taylor"}));
  app.add_option("--aov", f.aovs,
                 "extra EXR channels: alpha, variance, cluster, dweights (gradient images of the lobe-weight factors; "
                 "docs/rendering.md), sss (translucent objects' caches, |grad S| and V; docs/subsurface.md), time (seconds "
                 "spent on each pixel: where the render's time goes, docs/scaling.md)")->delimiter(',');
  app.add_option("--report", f.report, "write a JSON report (time, paths/s, statistics); - for stdout");
  app.add_flag("-v,--verbose", f.verbose, "print a summary to stderr");
  app.add_flag("--full-precision", f.full_precision,
               "hold the medium in its float grids, read whole, instead of the compact form (float density, half-float "
               "albedo and S: docs/rendering.md)");
  f.slabs.addFlags(app);
}

nlohmann::json reportOf(const SceneDescription& scene, const CameraPose& camera, const RenderResult& r,
                        const MediumView* medium) {
  double sum = 0, variance = 0;
  for (std::size_t i = 0; i < r.mean.size(); ++i) {
    sum += r.mean[i];
    variance += r.variance[i];
  }
  const double n = double(r.mean.size());
  nlohmann::json report = {{"tool", kTool}, {"version", kVersion}, {"medium", scene.medium},
                           {"resolution", {r.width, r.height}}, {"spp", r.spp}, {"seed", scene.render.seed},
                           {"strategy", lightStrategyName(scene.render.path.strategy)},
                           {"seconds", r.seconds}, {"paths", r.paths},
                           {"paths_per_second", r.seconds > 0 ? r.paths / r.seconds : 0.0},
                           {"mean_scattering_events", r.paths ? double(r.scattering_events) / r.paths : 0.0},
                           {"mean_pixel_value", n > 0 ? sum / n : 0.0},
                           {"mean_pixel_variance", n > 0 ? variance / n : 0.0},
                           {"tentative_collisions", r.tracking.tentative_collisions},
                           {"majorant_violations", r.tracking.majorant_violations},
                           {"camera", {{"position", {camera.position.x(), camera.position.y(), camera.position.z()}},
                                       {"target", {camera.target.x(), camera.target.y(), camera.target.z()}},
                                       {"up", {camera.up.x(), camera.up.y(), camera.up.z()}},
                                       {"fov", camera.fov_degrees}}}};
  if (std::vector<double> tiles = tileSeconds(r); !tiles.empty()) {
    // Where the time went, per tile of the work the ranks share, in the order the ranks claim them
    // (docs/scaling.md's model replays them), and their distribution.
    const std::vector<double> values = tiles;
    std::sort(tiles.begin(), tiles.end());
    double total = 0;
    for (double t : tiles) total += t;
    const auto quantile = [&](double q) { return tiles[std::min(tiles.size() - 1, std::size_t(q * double(tiles.size())))]; };
    report["tile_seconds"] = {{"tile_size", kRenderTileSize}, {"tiles", tiles.size()}, {"total", total},
                              {"mean", total / double(tiles.size())}, {"median", quantile(0.5)}, {"p90", quantile(0.9)},
                              {"p99", quantile(0.99)}, {"max", tiles.back()}, {"values", values}};
  }
  if (!r.ranks.empty()) {
    nlohmann::json ranks = nlohmann::json::array();
    for (const RankWork& w : r.ranks)
      ranks.push_back({{"paths", w.paths}, {"tile_seconds", w.tile_seconds}, {"claim_seconds", w.claim_seconds},
                       {"sum_seconds", w.sum_seconds}});
    report["ranks"] = ranks;
  }
  if (medium) {
    const Aabb box = medium->worldBounds();
    report["bounds"] = {{box.lo.x(), box.lo.y(), box.lo.z()}, {box.hi.x(), box.hi.y(), box.hi.z()}};
    report["phase_function"] = phaseSourceName(medium->phaseSource());
    report["interp"] = interpolationName(medium->interpolation());
    report["majorant_voxels"] = medium->majorantVoxelCount();
    report["medium_form"] = medium->compact() ? "compact" : "full precision";
    if (const std::uint64_t voxels = medium->instancedVoxelCount()) report["instanced_model_voxels"] = voxels;
  }
  return report;
}

// Table 4.1 of the translucent-caching seed per object: N, C, H, C/H and each pass's seconds (pass 3
// is the render, shared by every object).
nlohmann::json subsurfaceReport(const SceneDescription& scene, const SubsurfaceCaching& caching,
                                const RenderScene& render_scene, const RenderResult& result) {
  nlohmann::json objects = nlohmann::json::array();
  for (std::size_t i = 0; i < caching.objects.size(); ++i) {
    const SubsurfaceObjectStats& s = caching.objects[i];
    objects.push_back({{"irradiance_samples", s.irradiance_samples}, {"caches", s.caches}, {"hit_pixels", s.hit_pixels},
                       {"caches_per_hit_pixel", s.hit_pixels ? double(s.caches) / double(s.hit_pixels) : 0.0},
                       {"pass1_seconds", s.pass1_seconds}, {"pass2_seconds", s.pass2_seconds},
                       {"uncached_lookups", render_scene.translucent[i]->uncachedLookups()}});
  }
  return {{"cache_error", scene.subsurface.cache_error}, {"pass3_seconds", result.seconds}, {"objects", objects}};
}

// The medium as the render holds it (docs/rendering.md, "The render's medium in memory"): in the
// compact form, read in pieces where the file allows it, else read whole and made compact; in its
// float grids with --full-precision or where the compact form does not hold the medium's grids.
std::shared_ptr<const MediumView> renderMedium(const Flags& flags, const std::string& path, const GridMapping& mapping,
                                               Interpolation interpolation) {
  const auto view_of = [&](const CompactMedium& compact) {
    if (flags.verbose)
      fmt::print(stderr, "{}: the medium in compact form: {} piece{} read, density {:.3g} GB, albedo and S {:.3g} GB\n", kTool,
                 compact.pieces, compact.pieces == 1 ? "" : "s", compact.density_bytes / 1e9, compact.attribute_bytes / 1e9);
    return std::make_shared<MediumView>(compact, interpolation, flags.no_sggx);
  };
  if (!flags.full_precision) {
    const auto read = [&](std::uint64_t budget, std::string* why_not, ProgressBar* progress) {
      return readCompactMedium(path, mapping, budget, why_not, progress);
    };
    if (const auto compact = flags.slabs.run(kTool, path, "reading the medium", flags.verbose, read)) return view_of(*compact);
  }
  const MediumPtr whole = tool::readInputMedium(kTool, path, mapping);
  std::string why_not = "--full-precision";
  if (!flags.full_precision)
    if (const auto compact = compactMedium(whole, &why_not)) return view_of(*compact);
  if (flags.verbose) fmt::print(stderr, "{}: note: the medium is rendered from its float grids: {}\n", kTool, why_not);
  return std::make_shared<MediumView>(whole, interpolation, flags.no_sggx);
}

// Everything a render needs, prepared on every rank of the group alike.
struct RenderJob {
  SceneDescription scene;
  RenderOutputs outputs;
  std::shared_ptr<const MediumView> medium;
  CameraPose pose;
  RenderScene render_scene;
  SubsurfaceCaching caching;
};

RenderJob prepareJob(const CLI::App& app, const Flags& flags, const GridMapping& mapping, const ProcessGroup& group) {
  RenderJob job;
  job.scene = sceneOf(app, flags);
  const SceneDescription& scene = job.scene;
  const auto asked = [&](const char* aov) { return std::find(flags.aovs.begin(), flags.aovs.end(), aov) != flags.aovs.end(); };
  job.outputs = {flags.output,      flags.preview, asked("alpha"), asked("variance"), scene.render.cluster_coverage,
                 scene.render.weight_gradients, asked("sss"), scene.render.pixel_seconds};
  const RenderOutputs& outputs = job.outputs;
  checkRenderOutputs(outputs);
  if (group.isRoot()) {  // only the root writes
    tool::checkOutputs(scene.medium, flags.output, flags.report);
    tool::checkDistinct(scene.medium, flags.preview, flags.output);
    if (!flags.preview.empty()) checkWritable(flags.preview);
  }
  if (group.isShared() && scene.medium == "-")
    throw std::runtime_error(fmt::format("a medium on stdin reaches one rank of {}: give a file every rank can read", group.size()));
  if (!scene.medium.empty())
    job.medium = renderMedium(flags, scene.medium, mapping, scene.interpolation);
  const MediumView* medium = job.medium.get();
  // The checks that need no surfaces first: pass 1 of translucent objects runs in buildRenderScene.
  job.pose = cameraOf(scene, medium);
  const PinholeCamera camera(job.pose, scene.render.width, scene.render.height);
  if (scene.render.cluster_coverage && (!medium || medium->clusterCount() == 0))
    throw std::runtime_error(scene.medium + ": --aov cluster needs a medium with a 'cluster' grid");
  if (scene.render.weight_gradients && (!medium || medium->phaseSource() != PhaseSource::kLobes || medium->clusterCount() == 0))
    throw std::runtime_error(scene.medium + ": --aov dweights needs a multi-lobe medium with a 'cluster' grid (vdb_lobe_cluster)");
  if (scene.render.weight_gradients && !flags.sh_lightgrid.empty())
    throw std::runtime_error("--aov dweights cannot be rendered with --sh-lightgrid");
  const bool translucent = std::any_of(scene.meshes.begin(), scene.meshes.end(), [](const MeshDescription& m) { return bool(m.translucent); });
  if (outputs.subsurface && !translucent) throw std::runtime_error("--aov sss needs a translucent mesh (--translucent-mesh)");
  if (outputs.subsurface) checkSubsurfaceChannelMemory(scene.render.width, scene.render.height);
  job.render_scene = buildRenderScene(scene, job.medium, readRgbImage, readPrefilteredSurface);
  if (group.isRoot()) {  // once, not per rank
    for (const std::string& warning : job.render_scene.warnings) fmt::print(stderr, "{}: warning: {}\n", kTool, warning);
    if (flags.verbose)
      for (const std::string& note : job.render_scene.notes) fmt::print(stderr, "{}: note: {}\n", kTool, note);
  }
  if (!flags.sh_lightgrid.empty()) {
    job.render_scene.sh_lights = readShLightGrid(flags.sh_lightgrid);
    job.render_scene.sh_interpolation = flags.sh_interp == "trilinear" ? CellInterpolation::kTrilinear
                                        : flags.sh_interp == "taylor"  ? CellInterpolation::kTaylor
                                                                       : CellInterpolation::kHermite;
    job.render_scene.sh_shadows = !flags.sh_unshadowed;
  }
  job.caching =
      cacheTranslucentObjects(job.render_scene, camera, scene.render.width, scene.render.height, scene.subsurface, outputs.subsurface);
  return job;
}

void writeResults(const Flags& flags, RenderJob& job, RenderResult& result) {
  const SceneDescription& scene = job.scene;
  for (auto& channel : job.caching.channels) result.extra_channels.push_back(std::move(channel));
  writeRenderOutputs(result, job.outputs);
  nlohmann::json report = reportOf(scene, job.pose, result, job.medium.get());
  if (!job.render_scene.translucent.empty()) report["subsurface"] = subsurfaceReport(scene, job.caching, job.render_scene, result);
  if (job.render_scene.sh_lights)
    report["sh_lightgrid"] = {{"file", flags.sh_lightgrid}, {"interpolation", flags.sh_interp}, {"shadows", job.render_scene.sh_shadows}};
  if (!flags.report.empty()) tool::writeJsonReport(flags.report, report);
  if (flags.verbose)
    fmt::print(stderr, "{}: {}x{} at {} spp in {:.2f} s, {:.3g} paths/s, {:.2f} scattering events per path, mean {:.4g}\n",
               kTool, result.width, result.height, result.spp, result.seconds, report["paths_per_second"].get<double>(),
               report["mean_scattering_events"].get<double>(), report["mean_pixel_value"].get<double>());
}

}  // namespace

int main(int argc, char** argv) {
  const std::unique_ptr<ProcessGroup> group = joinProcessGroup(&argc, &argv);
  CLI::App app("Renders a medium (and optional surfaces) with an unbiased volumetric path tracer: delta "
               "tracking over a hierarchical majorant, next-event estimation with MIS. Under mpirun or srun, "
               "the ranks share the image (docs/scaling.md).",
               kTool);
  app.footer(kExamples);
  app.set_version_flag("--version", kVersion);
  Flags flags;
  addFlags(app, flags);
  GridMapping mapping;
  tool::addGridMapping(app, mapping);
  tool::ThreadLimit threads(app);

  return tool::run(app, argc, argv, *group, [&] {
    threads.apply();
    // Every rank reads the medium and builds the scene; a failure on any rank ends every rank here,
    // reported once, before any rank waits for another's pixels.
    RenderJob job;
    group->together([&] { job = prepareJob(app, flags, mapping, *group); });
    job.scene.render.group = group.get();
    const PinholeCamera camera(job.pose, job.scene.render.width, job.scene.render.height);
    ProgressBar progress("render", 0, group->isRoot() && stderrIsTerminal());
    RenderResult result = renderImage(job.render_scene, camera, job.scene.render, &progress);
    if (group->isRoot()) writeResults(flags, job, result);
    return 0;
  });
}
