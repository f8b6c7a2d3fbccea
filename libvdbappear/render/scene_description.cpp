#include "libvdbappear/render/scene_description.h"

#include "libvdbappear/prefilter/prefiltered_brdf.h"
#include "libvdbappear/prefilter/prefiltered_surface_file.h"
#include "libvdbappear/render/area_light.h"
#include "libvdbappear/render/direct_irradiance.h"
#include "libvdbappear/render/environment_light.h"
#include "libvdbappear/render/mesh_file.h"
#include "libvdbappear/subsurface/closed_mesh.h"
#include "libvdbappear/subsurface/surface_samples.h"
#include "libvdbappear/util/json_int.h"

#include <fmt/format.h>

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace vdbappear {

namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& source, const std::string& key, const std::string& what) {
  throw std::runtime_error(fmt::format("{}: {}: {}", source, key, what));
}

// A string value read by `parse`, whose complaint (std::invalid_argument) gains the file and key.
template <typename Parse>
auto parsedString(const json& value, const std::string& source, const std::string& key, Parse parse) {
  if (!value.is_string()) fail(source, key, "expected a string");
  try {
    return parse(value.get<std::string>());
  } catch (const std::invalid_argument& e) {
    fail(source, key, e.what());
  }
}

Vec3 vec3Of(const json& value, const std::string& source, const std::string& key) {
  if (!value.is_array() || value.size() != 3 || !value[0].is_number() || !value[1].is_number() || !value[2].is_number())
    fail(source, key, "expected [x, y, z]");
  return {value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
}

// A number (grey) or [r, g, b].
Rgb rgbOf(const json& value, const std::string& source, const std::string& key) {
  if (value.is_number()) return Rgb::Constant(value.get<double>());
  const Vec3 v = vec3Of(value, source, key);
  return {v.x(), v.y(), v.z()};
}

std::string resolve(const std::string& folder, const std::string& path) {
  if (folder.empty() || path.empty() || path == "-" || std::filesystem::path(path).is_absolute()) return path;
  return (std::filesystem::path(folder) / path).lexically_normal().string();
}

// A number; an integer key takes only integers within its type's range (util/json_int.h).
template <typename T>
T numberOf(const json& value, const std::string& source, const std::string& key) {
  if (!value.is_number()) fail(source, key, "expected a number");
  if constexpr (std::is_integral_v<T>) {
    try {
      return integerOf<T>(value, "");
    } catch (const std::invalid_argument& e) {
      fail(source, key, e.what());
    }
  }
  return value.get<T>();
}

void checkKeys(const json& object, std::initializer_list<const char*> allowed, const std::string& source,
               const std::string& where) {
  if (!object.is_object()) fail(source, where, "expected a JSON object");
  for (const auto& item : object.items()) {
    bool known = false;
    for (const char* key : allowed) known = known || item.key() == key;
    if (!known) fail(source, where.empty() ? item.key() : where + "." + item.key(), "unknown key");
  }
}

void applyCamera(const json& camera, const std::string& source, SceneDescription* scene) {
  checkKeys(camera, {"position", "target", "up", "fov", "view"}, source, "camera");
  if (camera.contains("position")) {
    scene->camera.position = vec3Of(camera["position"], source, "camera.position");
    scene->camera_given = true;
  }
  if (camera.contains("target")) scene->camera.target = vec3Of(camera["target"], source, "camera.target");
  if (camera.contains("up")) scene->camera.up = vec3Of(camera["up"], source, "camera.up");
  if (camera.contains("fov")) scene->camera.fov_degrees = numberOf<double>(camera["fov"], source, "camera.fov");
  if (camera.contains("view")) scene->view = camera["view"].get<std::string>();
}

// Checks a light's keys and makes its paths absolute.
json checkedLight(json light, const std::string& folder, const std::string& source, const std::string& where) {
  if (!light.is_object() || !light.contains("type") || !light["type"].is_string())
    fail(source, where, "a light needs a \"type\"");
  const std::string type = light["type"];
  if (type == "env") checkKeys(light, {"type", "radiance"}, source, where);
  else if (type == "env_map") checkKeys(light, {"type", "file", "scale"}, source, where);
  else if (type == "sh") checkKeys(light, {"type", "l", "m", "scale"}, source, where);
  else if (type == "sun") checkKeys(light, {"type", "direction", "strength"}, source, where);
  else if (type == "point") checkKeys(light, {"type", "position", "intensity"}, source, where);
  else if (type == "quad") checkKeys(light, {"type", "corner", "edge1", "edge2", "radiance", "two_sided"}, source, where);
  else if (type == "polygon" || type == "triangle") checkKeys(light, {"type", "vertices", "radiance", "two_sided"}, source, where);
  else fail(source, where, "unknown light type '" + type + "' (env, env_map, sh, sun, point, quad, polygon)");
  if (type == "env_map") {
    if (!light.contains("file") || !light.at("file").is_string()) fail(source, where, "env_map needs a \"file\"");
    light.at("file") = resolve(folder, light.at("file"));
  }
  return light;
}

}  // namespace

MicrofacetBrdf brdfFromJson(const json& b, const std::string& source, const std::string& where) {
  checkKeys(b, {"distribution", "roughness", "specular", "diffuse"}, source, where);
  try {
    const MicrofacetKind kind =
        b.contains("distribution") ? parseMicrofacetKind(b["distribution"].get<std::string>()) : MicrofacetKind::GGX;
    const double alpha = b.contains("roughness") ? numberOf<double>(b["roughness"], source, where + ".roughness") : 0.3;
    const Rgb specular = b.contains("specular") ? rgbOf(b["specular"], source, where + ".specular") : Rgb::Constant(0.04);
    const Rgb diffuse = b.contains("diffuse") ? rgbOf(b["diffuse"], source, where + ".diffuse") : Rgb::Zero();
    return MicrofacetBrdf(MicrofacetDistribution(kind, alpha), specular, diffuse);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(fmt::format("{}: {}: {}", source, where, e.what()));
  } catch (const json::exception& e) {
    throw std::runtime_error(fmt::format("{}: {}: {}", source, where, e.what()));
  }
}

json brdfToJson(const MicrofacetBrdf& brdf) {
  const auto rgb = [](const Rgb& c) { return json::array({c[0], c[1], c[2]}); };
  return {{"distribution", brdf.distribution().kind() == MicrofacetKind::GGX ? "ggx" : "beckmann"},
          {"roughness", brdf.distribution().alpha()},
          {"specular", rgb(brdf.specular())},
          {"diffuse", rgb(brdf.diffuse())}};
}

namespace {

HeightFieldDescription heightFieldOf(const json& h, const std::string& folder, const std::string& source,
                                     const std::string& where) {
  checkKeys(h, {"file", "prefiltered", "mipmap", "footprint", "scaling", "size", "origin", "sphere", "mesh", "vertices_per_cell",
                "height_scale", "tiles", "albedo", "brdf"},
            source, where);
  if (h.contains("footprint") && !h.contains("mipmap")) fail(source, where + ".footprint", "only with \"mipmap\"");
  HeightFieldDescription field;
  if (h.contains("mesh")) {
    for (const char* key : {"origin", "sphere"})
      if (h.contains(key)) fail(source, where + ".mesh", fmt::format("not with \"{}\" (the mesh places the tiles)", key));
    if (!h["mesh"].is_string()) fail(source, where + ".mesh", "expected the path of a mesh with UVs");
    field.mesh = resolve(folder, h["mesh"].get<std::string>());
  }
  if (h.contains("vertices_per_cell")) {
    if (!h.contains("mesh")) fail(source, where + ".vertices_per_cell", "only with \"mesh\"");
    field.vertices_per_cell = numberOf<double>(h["vertices_per_cell"], source, where + ".vertices_per_cell");
    if (!(*field.vertices_per_cell > 0) || *field.vertices_per_cell > 64)
      fail(source, where + ".vertices_per_cell", "must be above 0 and at most 64");
  }
  if (h.contains("sphere")) {
    if (h.contains("origin")) fail(source, where + ".sphere", "not with \"origin\" (the sphere's centre places it)");
    field.sphere_centre = vec3Of(h["sphere"], source, where + ".sphere");
  }
  if (h.contains("mipmap")) {
    const json& m = h["mipmap"];
    if (!m.is_array() || m.empty()) fail(source, where + ".mipmap", "expected [\"LEVEL.json\", ...], finest first");
    for (const json& level : m) {
      if (!level.is_string()) fail(source, where + ".mipmap", "expected the paths of manifests");
      field.mipmap.push_back(resolve(folder, level.get<std::string>()));
    }
    for (const char* key : {"prefiltered", "size", "height_scale", "albedo", "brdf"})
      if (h.contains(key)) fail(source, where + "." + key, "not with \"mipmap\" (the manifests give it)");
    if (h.contains("file")) {
      if (!h["file"].is_string()) fail(source, where + ".file", "expected the path of the original map");
      field.file = resolve(folder, h["file"].get<std::string>());
    }
    if (h.contains("footprint")) {
      const json& f = h["footprint"];
      if (f != "narrow" && f != "area") fail(source, where + ".footprint", "expected \"narrow\" or \"area\"");
      field.footprint = f == "narrow" ? FootprintWidth::narrow : FootprintWidth::area;
    }
  } else if (h.contains("prefiltered")) {
    if (!h["prefiltered"].is_string()) fail(source, where + ".prefiltered", "expected the path of a manifest");
    for (const char* key : {"file", "size", "height_scale", "albedo", "brdf"})
      if (h.contains(key)) fail(source, where + "." + key, "not with \"prefiltered\" (the manifest gives it)");
    field.prefiltered = resolve(folder, h["prefiltered"].get<std::string>());
  } else {
    if (h.contains("scaling")) fail(source, where + ".scaling", "only with \"prefiltered\" or \"mipmap\"");
    if (!h.contains("file") || !h["file"].is_string()) fail(source, where, "a height field needs a \"file\" or \"prefiltered\"");
    field.file = resolve(folder, h["file"].get<std::string>());
  }
  if (h.contains("scaling")) {
    if (!h["scaling"].is_boolean()) fail(source, where + ".scaling", "expected true or false");
    field.scaling = h["scaling"].get<bool>();
  }
  if (h.contains("size")) field.size = numberOf<double>(h["size"], source, where + ".size");
  if (!(field.size > 0) || !std::isfinite(field.size)) fail(source, where + ".size", "must be positive");
  if (h.contains("origin")) field.placement.origin = vec3Of(h["origin"], source, where + ".origin");
  if (h.contains("height_scale"))
    field.placement.height_scale = numberOf<double>(h["height_scale"], source, where + ".height_scale");
  if (!std::isfinite(field.placement.height_scale)) fail(source, where + ".height_scale", "must be finite");
  if (h.contains("tiles")) {
    const json& t = h["tiles"];
    if (!t.is_array() || t.size() != 2) fail(source, where + ".tiles", "expected [nx, ny]");
    field.placement.tiles_x = numberOf<int>(t[0], source, where + ".tiles");
    field.placement.tiles_y = numberOf<int>(t[1], source, where + ".tiles");
    if (field.placement.tiles_x < 1 || field.placement.tiles_y < 1) fail(source, where + ".tiles", "must be >= 1");
  }
  if (h.contains("albedo")) field.albedo = rgbOf(h["albedo"], source, where + ".albedo");
  if (h.contains("brdf")) field.brdf = brdfFromJson(h["brdf"], source, where + ".brdf");
  return field;
}

TranslucentMaterial translucentOf(const json& t, const std::string& source, const std::string& where) {
  checkKeys(t, {"density", "albedo", "g", "eta"}, source, where);
  TranslucentMaterial material;
  if (t.contains("density")) material.sigma_t = rgbOf(t["density"], source, where + ".density");
  if (t.contains("albedo")) material.albedo = rgbOf(t["albedo"], source, where + ".albedo");
  if (t.contains("g")) material.g = numberOf<double>(t["g"], source, where + ".g");
  if (t.contains("eta")) material.eta = numberOf<double>(t["eta"], source, where + ".eta");
  try {
    validateTranslucentMaterial(material, where);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(fmt::format("{}: {}", source, e.what()));
  }
  return material;
}

void applySubsurface(const json& settings, const std::string& source, SubsurfaceSettings* subsurface) {
  checkKeys(settings, {"sample_spacing", "max_solid_angle", "disk_radius", "light_samples", "cache_error",
                       "min_cache_radius", "max_cache_radius", "min_normal_cos"},
            source, "subsurface");
  const auto positive = [&](const char* key, double* value) {
    if (!settings.contains(key)) return;
    *value = numberOf<double>(settings[key], source, std::string("subsurface.") + key);
    if (!(*value > 0)) fail(source, std::string("subsurface.") + key, "must be > 0");
  };
  positive("sample_spacing", &subsurface->sample_spacing);
  positive("disk_radius", &subsurface->disk_radius);
  positive("min_cache_radius", &subsurface->min_cache_radius);
  positive("max_cache_radius", &subsurface->max_cache_radius);
  if (subsurface->max_cache_radius < subsurface->min_cache_radius)
    fail(source, "subsurface.max_cache_radius", "must be >= min_cache_radius");
  if (settings.contains("cache_error")) {
    subsurface->cache_error = numberOf<double>(settings["cache_error"], source, "subsurface.cache_error");
    if (!(subsurface->cache_error >= 0)) fail(source, "subsurface.cache_error", "must be >= 0 (0: no cache)");
  }
  if (settings.contains("min_normal_cos")) {
    subsurface->min_normal_cos = numberOf<double>(settings["min_normal_cos"], source, "subsurface.min_normal_cos");
    if (!(std::abs(subsurface->min_normal_cos) <= 1)) fail(source, "subsurface.min_normal_cos", "must lie in [-1, 1]");
  }
  if (settings.contains("max_solid_angle")) {
    subsurface->max_solid_angle = numberOf<double>(settings["max_solid_angle"], source, "subsurface.max_solid_angle");
    if (!(subsurface->max_solid_angle >= 0)) fail(source, "subsurface.max_solid_angle", "must be >= 0");
  }
  if (settings.contains("light_samples")) {
    subsurface->light_samples = numberOf<int>(settings["light_samples"], source, "subsurface.light_samples");
    if (subsurface->light_samples < 1 || subsurface->light_samples > (1 << 20))
      fail(source, "subsurface.light_samples", "must lie in 1..1048576");
  }
}

}  // namespace

void applySceneJson(const json& json, const std::string& folder, const std::string& source, SceneDescription* scene) {
  checkKeys(json, {"medium", "resolution", "spp", "time", "seed", "max_depth", "interp", "strategy", "camera",
                   "lights", "ground", "meshes", "height_fields", "subsurface"},
            source, "");
  if (json.contains("medium")) scene->medium = resolve(folder, json["medium"].get<std::string>());
  if (json.contains("resolution")) {
    const auto& r = json["resolution"];
    if (!r.is_array() || r.size() != 2 || !r[0].is_number_integer() || !r[1].is_number_integer())
      fail(source, "resolution", "expected [width, height]");
    scene->render.width = numberOf<int>(r[0], source, "resolution");
    scene->render.height = numberOf<int>(r[1], source, "resolution");
    if (scene->render.width < 1 || scene->render.height < 1 || scene->render.width > 16384 || scene->render.height > 16384)
      fail(source, "resolution", "sizes must lie in 1..16384");
  }
  if (json.contains("spp")) {
    scene->spp_given = true;
    scene->render.spp = numberOf<int>(json["spp"], source, "spp");
    if (scene->render.spp < 1) fail(source, "spp", "must be >= 1");
  }
  if (json.contains("time")) {
    scene->render.time_seconds = numberOf<double>(json["time"], source, "time");
    if (!(scene->render.time_seconds > 0)) fail(source, "time", "must be > 0 seconds");
    if (!json.contains("spp")) scene->render.spp = 1 << 30;  // the time decides
  }
  if (json.contains("seed")) scene->render.seed = numberOf<std::uint64_t>(json["seed"], source, "seed");
  if (json.contains("max_depth")) {
    scene->render.path.max_depth = numberOf<int>(json["max_depth"], source, "max_depth");
    if (scene->render.path.max_depth < -1) fail(source, "max_depth", "must be >= 0, or -1 for unlimited");
  }
  if (json.contains("interp")) scene->interpolation = parsedString(json["interp"], source, "interp", parseInterpolation);
  if (json.contains("strategy"))
    scene->render.path.strategy = parsedString(json["strategy"], source, "strategy", parseLightStrategy);
  if (json.contains("camera")) applyCamera(json["camera"], source, scene);
  if (json.contains("lights")) {
    if (!json["lights"].is_array()) fail(source, "lights", "expected an array");
    scene->lights = nlohmann::json::array();
    for (std::size_t i = 0; i < json["lights"].size(); ++i)
      scene->lights.push_back(checkedLight(json["lights"][i], folder, source, fmt::format("lights[{}]", i)));
  }
  if (json.contains("ground")) {
    checkKeys(json["ground"], {"height", "albedo", "brdf"}, source, "ground");
    GroundDescription& ground = scene->ground.emplace();  // a failure below ends the whole read
    if (json["ground"].contains("height")) ground.height = numberOf<double>(json["ground"]["height"], source, "ground.height");
    if (json["ground"].contains("albedo")) ground.albedo = rgbOf(json["ground"]["albedo"], source, "ground.albedo");
    if (json["ground"].contains("brdf")) ground.brdf = brdfFromJson(json["ground"]["brdf"], source, "ground.brdf");
  }
  if (json.contains("subsurface")) applySubsurface(json["subsurface"], source, &scene->subsurface);
  if (json.contains("meshes")) {
    if (!json["meshes"].is_array()) fail(source, "meshes", "expected an array");
    for (std::size_t i = 0; i < json["meshes"].size(); ++i) {
      const auto& m = json["meshes"][i];
      const std::string where = fmt::format("meshes[{}]", i);
      checkKeys(m, {"file", "albedo", "brdf", "translucent"}, source, where);
      if (!m.contains("file")) fail(source, where, "a mesh needs a \"file\"");
      MeshDescription mesh;
      mesh.file = resolve(folder, m["file"].get<std::string>());
      if (m.contains("albedo")) mesh.albedo = rgbOf(m["albedo"], source, where + ".albedo");
      if (m.contains("brdf")) mesh.brdf = brdfFromJson(m["brdf"], source, where + ".brdf");
      if (m.contains("translucent")) mesh.translucent = translucentOf(m["translucent"], source, where + ".translucent");
      scene->meshes.push_back(mesh);
    }
  }
  if (json.contains("height_fields")) {
    if (!json["height_fields"].is_array()) fail(source, "height_fields", "expected an array");
    for (std::size_t i = 0; i < json["height_fields"].size(); ++i)
      scene->height_fields.push_back(
          heightFieldOf(json["height_fields"][i], folder, source, fmt::format("height_fields[{}]", i)));
  }
}

nlohmann::json defaultLights() {
  return nlohmann::json::array({{{"type", "env"}, {"radiance", 0.1}},
                                {{"type", "sun"}, {"direction", {0.51, 0.65, -0.565}}, {"strength", 3.0}}});
}

SceneDescription readSceneFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open the scene file");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format("{}: not valid JSON ({})", path, e.what()));
  }
  SceneDescription scene;
  try {
    applySceneJson(json, std::filesystem::path(path).parent_path().string(), path, &scene);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format("{}: {}", path, e.what()));
  } catch (const std::invalid_argument& e) {  // a value a parser refused without knowing the file
    throw std::runtime_error(fmt::format("{}: {}", path, e.what()));
  }
  return scene;
}

namespace {

bool isAreaLight(const json& light) {
  const std::string type = light["type"];
  return type == "quad" || type == "polygon" || type == "triangle";
}

// The polygon of a quad ({corner, edge1, edge2}: counter-clockwise corner, +e1, +e1+e2, +e2) or of
// a polygon or triangle light (its vertices).
std::vector<Vec3> areaLightVertices(const json& light, const std::string& source) {
  const auto required = [&](const char* key) -> const json& {
    if (!light.contains(key)) fail(source, key, fmt::format("missing ({} lights need it)", light["type"].get<std::string>()));
    return light[key];
  };
  if (light["type"] == "quad") {
    const Vec3 corner = vec3Of(required("corner"), source, "corner");
    const Vec3 e1 = vec3Of(required("edge1"), source, "edge1"), e2 = vec3Of(required("edge2"), source, "edge2");
    return {corner, corner + e1, corner + e1 + e2, corner + e2};
  }
  if (!required("vertices").is_array()) fail(source, "vertices", "expected [[x, y, z], ...]");
  std::vector<Vec3> vertices;
  for (const auto& v : light["vertices"]) vertices.push_back(vec3Of(v, source, "vertices"));
  return vertices;
}

std::unique_ptr<Light> makeLight(const json& light, const ImageReader& read_image, std::vector<Triangle>* triangles) {
  const std::string type = light["type"];
  const std::string source = "light";
  if (type == "env") return EnvironmentLight::constant(rgbOf(light.value("radiance", json(1.0)), source, "radiance"));
  if (type == "env_map") {
    const RgbImage image = read_image(light.at("file").get<std::string>());
    return EnvironmentLight::fromImage(image.width, image.height, image.pixels, light.value("scale", 1.0));
  }
  if (type == "sh") return EnvironmentLight::sphericalHarmonic(light.value("l", 0), light.value("m", 0), light.value("scale", 1.0));
  if (type == "sun")
    return std::make_unique<DirectionalLight>(vec3Of(light.at("direction"), source, "direction"),
                                              rgbOf(light.value("strength", json(1.0)), source, "strength"));
  if (type == "point")
    return std::make_unique<PointLight>(vec3Of(light.at("position"), source, "position"),
                                        rgbOf(light.value("intensity", json(1.0)), source, "intensity"));
  *triangles = AreaLight::fanTriangulate(areaLightVertices(light, source));
  return std::make_unique<AreaLight>(*triangles, rgbOf(light.value("radiance", json(1.0)), source, "radiance"),
                                     light.value("two_sided", false));
}

std::vector<Triangle> groundPlane(double height, const Aabb& around) {
  const Vec3 c = around.empty() ? Vec3::Zero() : around.centre();
  const double r = 100 * std::max(1.0, around.empty() ? 1.0 : around.extent().norm());
  const Vec3 a(c.x() - r, c.y() - r, height), b(c.x() + r, c.y() - r, height), d(c.x() + r, c.y() + r, height),
      e(c.x() - r, c.y() + r, height);
  return {{a, b, d}, {a, d, e}};  // counter-clockwise seen from +z: normal +z
}

// A diffuse surface, or a glossy one with its BRDF appended to the scene's.
void addOpaque(const std::vector<Triangle>& triangles, const Rgb& albedo, const std::optional<MicrofacetBrdf>& brdf,
               RenderScene* scene) {
  if (!brdf) return scene->surfaces->addDiffuse(triangles, albedo);
  scene->brdfs.push_back(*brdf);
  scene->surfaces->addGlossy(triangles, int(scene->brdfs.size() - 1));
}

HeightField readHeightField(const HeightFieldDescription& field, const ImageReader& read_image) {
  if (!read_image) throw std::runtime_error(field.file + ": no image reader for height fields");
  const RgbImage image = read_image(field.file);
  return heightFieldFromImage(image, field.size / std::max(1, image.width - 1), field.file);
}

void extendBounds(const std::vector<Triangle>& triangles, Aabb* bounds) {
  for (const Triangle& t : triangles)
    for (const Vec3& v : t) bounds->extend(v);
}

std::optional<SphereShell> shellOf(const HeightFieldDescription& field, double size) {
  if (!field.sphere_centre) return std::nullopt;
  return SphereShell::ofTiles(*field.sphere_centre, size, field.placement.tiles_x, field.placement.tiles_y);
}

// What a height field's tiles lie on, other than the plane through its origin.
// The mesh is read once per height field: a mipmap's levels and original displace copies of it.
struct CurvedBase {
  std::optional<SphereShell> sphere;
  std::shared_ptr<const MeshShell> mesh;  // not displaced yet
  std::string mesh_file;
};

CurvedBase curvedBaseOf(const HeightFieldDescription& field, double size) {
  CurvedBase base{shellOf(field, size), nullptr, field.mesh};
  if (!field.mesh.empty()) {
    try {
      base.mesh = std::make_shared<MeshShell>(readUvMesh(field.mesh), field.placement.tiles_x, field.placement.tiles_y);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(field.mesh + ": " + e.what());
    }
  }
  return base;
}

// Over a mesh, the vertices per map cell: `prefiltered`: h_low, whose few cells each carry much of
// the shading; resampled at one vertex per cell its facets' kinks are cut and the ball of
// Surfaces.MeshShellOverAUvSphereRendersAsTheSphereShell came out 1.4% darker than over the analytic
// sphere (within Monte Carlo error at two).
double verticesPerCell(const HeightFieldDescription& field, bool prefiltered) {
  return field.vertices_per_cell.value_or(prefiltered ? 2.0 : 1.0);
}

// A height field's triangles as meshes and their copies (SurfaceScene instances): on a plane its first
// tile and the others as translations of it (one tile's triangles in memory); over a sphere the first
// tile of each latitude band and the band's others as turns of it (one tile's per band); over a mesh
// all of them.
struct MeshPart {
  std::vector<Triangle> triangles;
  std::vector<RigidMotion> copies;  // empty: the triangles alone
};

struct PlacedMesh {
  std::vector<MeshPart> parts;
  std::shared_ptr<const MeshShell> shell;  // over a mesh: the copy displaced, whose subdivision its hits need
};

PlacedMesh sphereMesh(const HeightField& height, const SphereShell& sphere, double height_scale) {
  PlacedMesh mesh;
  for (int b = 0; b < sphere.tiles_y; ++b) {
    MeshPart band{shellTileTriangles(height, sphere, height_scale, 0, b), {}};
    if (sphere.tiles_x > 1)
      for (int a = 0; a < sphere.tiles_x; ++a) band.copies.push_back(sphere.turn(a));
    mesh.parts.push_back(std::move(band));
  }
  return mesh;
}

PlacedMesh placedMesh(const HeightField& height, const CurvedBase& base, HeightFieldPlacement placement,
                      double vertices_per_cell, std::vector<std::string>* notes) {
  if (base.mesh) {
    try {
      auto shell = std::make_shared<MeshShell>(*base.mesh);  // each displacement fixes its own subdivision
      PlacedMesh placed{{{shell->displace(height, placement.height_scale, vertices_per_cell), {}}}, shell};
      if (notes)
        notes->push_back(fmt::format("{}: {} triangles, each split {} times for a map of {} x {} cells per tile: {} triangles",
                                     base.mesh_file, shell->baseTriangles(), shell->subdivisions() * shell->subdivisions(),
                                     height.cellsX(), height.cellsY(), placed.parts[0].triangles.size()));
      return placed;
    } catch (const std::length_error& e) {
      throw std::runtime_error(base.mesh_file + ": " + e.what());
    }
  }
  if (base.sphere) return sphereMesh(height, *base.sphere, placement.height_scale);
  MeshPart tile;
  if (placement.tiles_x * placement.tiles_y > 1)
    for (int b = 0; b < placement.tiles_y; ++b)
      for (int a = 0; a < placement.tiles_x; ++a)
        tile.copies.push_back(RigidMotion::translation(Vec3(a * height.cellsX(), b * height.cellsY(), 0) * height.cellSize()));
  placement.tiles_x = placement.tiles_y = 1;
  tile.triangles = heightFieldTriangles(height, placement);
  return {{std::move(tile)}, nullptr};
}

PlacedMesh placedMesh(const HeightField& height, const HeightFieldDescription& field, const CurvedBase& base,
                      std::vector<std::string>* notes) {
  return placedMesh(height, base, field.placement, verticesPerCell(field, false), notes);
}

void extendBounds(const PlacedMesh& mesh, Aabb* bounds) {
  for (const MeshPart& part : mesh.parts) {
    Aabb tile;
    extendBounds(part.triangles, &tile);
    if (part.copies.empty() || tile.empty()) {
      extendBounds(part.triangles, bounds);
      continue;
    }
    for (const RigidMotion& copy : part.copies)
      for (int corner = 0; corner < 8; ++corner)
        bounds->extend(copy(Vec3(corner & 1 ? tile.hi.x() : tile.lo.x(), corner & 2 ? tile.hi.y() : tile.lo.y(),
                                 corner & 4 ? tile.hi.z() : tile.lo.z())));
  }
}

// A placed height field's parts with one BRDF, or diffuse.
void addOpaque(const PlacedMesh& mesh, const Rgb& albedo, const std::optional<MicrofacetBrdf>& brdf, RenderScene* scene) {
  if (brdf) scene->brdfs.push_back(*brdf);
  for (const MeshPart& part : mesh.parts) {
    if (brdf)
      scene->surfaces->addGlossy(part.triangles, int(scene->brdfs.size() - 1), {}, part.copies);
    else
      scene->surfaces->addDiffuse(part.triangles, albedo, part.copies);
  }
}

// h_low of a prefiltered map, tessellated as a height field on the field's plane, sphere or mesh (its
// heights are world units), and its SVBRDF f_low = T S f'_low (prefilter/prefiltered_brdf.h).
void placePrefiltered(PrefilteredSurfaceFile file, const HeightFieldDescription& field, const CurvedBase& base,
                      DetailLevels levels, RenderScene* scene, Aabb* bounds) {
  if (!field.scaling) {  // f'_low alone
    file.surface.scaling = FactorizedScaling();  // T = S = 1, no relief term
    file.surface.scaling.T.values = {Rgb::Ones()};
    file.surface.scaling.S.values = {Rgb::Ones()};
    file.surface.stretched.clear();
  }
  HeightFieldPlacement placement = field.placement;
  placement.height_scale = 1;
  const PlacedMesh mesh = placedMesh(file.surface.height, base, placement, verticesPerCell(field, true), &scene->notes);
  if (base.mesh) {
    // Heights are not stretched with the UVs: the model's slopes are the original's only where a
    // tile is as wide as the map was prefiltered for.
    const double width = base.mesh->meanTileWidth();
    if (std::abs(width / file.info.size - 1) > 0.05)
      scene->warnings.push_back(fmt::format(
          "{}: a tile spans {:.3g} world units on {} (its mean), the map was prefiltered {:.3g} wide: its slopes, "
          "and the prefiltered model, hold only at that width (scale the mesh or its UVs, or prefilter the map at "
          "--size {:.3g})",
          field.prefiltered, width, base.mesh_file, file.info.size, width));
  }
  extendBounds(mesh, bounds);
  const bool curved = base.sphere || base.mesh;
  scene->prefiltered.push_back(
      {std::make_shared<PrefilteredBrdf>(file.surface, file.base,
                                         curved ? PrefilteredBrdf::Base::kCurved : PrefilteredBrdf::Base::kPlane),
       placement.origin, file.info.size, base.sphere, mesh.shell});
  for (const MeshPart& part : mesh.parts)
    scene->surfaces->addPrefiltered(part.triangles, int(scene->prefiltered.size() - 1), levels, part.copies);
}

void addPrefiltered(const HeightFieldDescription& field, const PrefilteredReader& read, RenderScene* scene, Aabb* bounds) {
  if (!read) throw std::runtime_error(field.prefiltered + ": no reader for prefiltered displacement maps");
  PrefilteredSurfaceFile file = read(field.prefiltered);
  const CurvedBase base = curvedBaseOf(field, file.info.size);
  placePrefiltered(std::move(file), field, base, {}, scene, bounds);
}

// The levels of a mipmap in one scene: level j of n sees paths of level j, its last also those of
// every level above (render/surface_scene.h).
DetailLevels mipmapLevel(std::size_t j, std::size_t n) {
  return {int(j), j + 1 == n ? DetailLevels::kLastLevel : int(j)};
}

// The levels of a mipmap must prefilter one original, finest first: the same cells, size, height
// scale, base BRDF and scaling (the manifests' "source" is not compared: maps move). Returns the
// original's cells across.
int checkMipmapLevels(const HeightFieldDescription& field, const std::vector<PrefilteredSurfaceFile>& levels) {
  const PrefilteredSurfaceFile& first = levels.front();
  const int fine_cells = first.surface.height.cellsX() * first.info.factor;
  for (std::size_t j = 0; j < levels.size(); ++j) {
    const PrefilteredSurfaceFile& level = levels[j];
    const auto mismatch = [&](const std::string& what) {
      throw std::runtime_error(field.mipmap[j] + ": " + what + " differs from " + field.mipmap.front() +
                               "'s: the levels of a mipmap must prefilter one map");
    };
    if (j > 0 && !(level.info.factor > levels[j - 1].info.factor))
      throw std::runtime_error(field.mipmap[j] + ": factor " + std::to_string(level.info.factor) +
                               " after factor " + std::to_string(levels[j - 1].info.factor) + ": list the levels finest first");
    if (level.surface.height.cellsX() * level.info.factor != fine_cells ||
        level.surface.height.cellsY() * level.info.factor != first.surface.height.cellsY() * first.info.factor)
      mismatch("the original's cell count");
    if (level.info.scaling != first.info.scaling) mismatch("the scaling (shadowing or interreflection)");
    if (level.info.size != first.info.size) mismatch("size");
    if (level.info.height_scale != first.info.height_scale) mismatch("height_scale");
    if (brdfToJson(level.base) != brdfToJson(first.base)) mismatch("the base BRDF");
  }
  return fine_cells;
}

// A mipmap (§4.7.2): its prefiltered levels, and the original below them when "file" is given,
// each a surface of its own level of detail.
void addMipmap(const HeightFieldDescription& field, const ImageReader& read_image, const PrefilteredReader& read,
               RenderScene* scene, Aabb* bounds) {
  if (!read) throw std::runtime_error(field.mipmap.front() + ": no reader for prefiltered displacement maps");
  std::vector<PrefilteredSurfaceFile> levels;
  for (const std::string& manifest : field.mipmap) levels.push_back(read(manifest));
  const int fine_cells = checkMipmapLevels(field, levels);
  const PrefilteredSurfaceFile& first = levels.front();
  const HeightFieldPlacement& placement = field.placement;
  MipmapFootprint footprint{placement.origin, first.info.size * placement.tiles_x, first.info.size * placement.tiles_y,
                            first.info.size / fine_cells, {}, {}};
  footprint.levels_by = field.footprint;
  const int fine_cells_y = first.surface.height.cellsY() * first.info.factor;
  const CurvedBase base = curvedBaseOf(field, first.info.size);
  if (base.sphere) footprint.curved = sphereBase(*base.sphere, fine_cells, fine_cells_y);
  if (base.mesh) footprint.curved = meshBase(*base.mesh, fine_cells, fine_cells_y);
  const std::size_t n = levels.size() + (field.file.empty() ? 0 : 1);
  std::size_t j = 0;
  if (!field.file.empty()) {
    HeightFieldDescription original = field;
    original.size = first.info.size;
    original.placement.height_scale = first.info.height_scale;
    const HeightField height = readHeightField(original, read_image);
    if (height.cellsX() != fine_cells)
      throw std::runtime_error(field.file + ": " + std::to_string(height.cellsX()) + " cells across, the mipmap's levels prefilter " +
                               std::to_string(fine_cells));
    const PlacedMesh mesh = placedMesh(height, original, base, &scene->notes);
    extendBounds(mesh, bounds);
    scene->brdfs.push_back(first.base);
    for (const MeshPart& part : mesh.parts)
      scene->surfaces->addGlossy(part.triangles, int(scene->brdfs.size() - 1), mipmapLevel(j, n), part.copies);
    ++j;
    footprint.factors.push_back(1);
  }
  for (PrefilteredSurfaceFile& level : levels) {
    footprint.factors.push_back(level.info.factor);
    placePrefiltered(std::move(level), field, base, mipmapLevel(j++, n), scene, bounds);
  }
  scene->mipmaps.push_back(std::move(footprint));
}

// Pass 1 of a translucent object: irradiance samples at the centroids of its faces, split to the
// sample spacing, lit by the scene built so far (docs/subsurface.md §2).
std::shared_ptr<TranslucentObject> translucentObject(const std::string& file, const TranslucentMaterial& material,
                                                     const std::vector<Triangle>& triangles,
                                                     const SceneDescription& description, const RenderScene& scene) {
  const auto start = std::chrono::steady_clock::now();
  const SubsurfaceSettings& settings = description.subsurface;
  const double spacing = settings.sample_spacing * RgbDipole(material).shortestDiffusionLength();
  std::vector<SurfacePoint> points;
  try {
    points = surfacePoints(triangles, spacing);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(fmt::format("{}: {} (--sss-spacing {} diffusion lengths = {:.3g} world units)", file, e.what(),
                                         settings.sample_spacing, spacing));
  }
  std::vector<IrradianceSample> samples =
      directIrradiance(points, material.eta, scene, settings.light_samples, description.render.seed);
  auto object = std::make_shared<TranslucentObject>(material, std::move(samples), settings);
  object->setPass1Seconds(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return object;
}

}  // namespace

RenderScene buildRenderScene(const SceneDescription& description, std::shared_ptr<const MediumView> medium,
                             const ImageReader& read_image, const PrefilteredReader& read_prefiltered) {
  RenderScene scene;
  scene.medium = std::move(medium);
  const Aabb bounds = scene.medium ? scene.medium->worldBounds() : Aabb();
  scene.surfaces = std::make_unique<SurfaceScene>();
  Aabb everything = bounds;
  for (std::size_t i = 0; i < description.lights.size(); ++i) {
    std::vector<Triangle> triangles;
    try {
      scene.lights.push_back(makeLight(description.lights[i], read_image, &triangles));
    } catch (const nlohmann::json::exception& e) {
      throw std::runtime_error(fmt::format("lights[{}]: {}", i, e.what()));
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(fmt::format("lights[{}]: {}", i, e.what()));
    }
    if (!triangles.empty()) scene.surfaces->addLight(triangles, int(i));
    extendBounds(triangles, &everything);
  }
  std::vector<std::pair<const MeshDescription*, std::vector<Triangle>>> translucent;
  for (const MeshDescription& mesh : description.meshes) {
    std::vector<Triangle> triangles = readMesh(mesh.file);
    extendBounds(triangles, &everything);
    if (!mesh.translucent) {
      addOpaque(triangles, mesh.albedo, mesh.brdf, &scene);
      continue;
    }
    triangles = outwardClosedMesh(std::move(triangles), mesh.file);
    scene.surfaces->addTranslucent(triangles, int(translucent.size()));
    translucent.emplace_back(&mesh, std::move(triangles));
  }
  for (const HeightFieldDescription& field : description.height_fields) {
    if (!field.mipmap.empty()) {
      addMipmap(field, read_image, read_prefiltered, &scene, &everything);
      continue;
    }
    if (!field.prefiltered.empty()) {
      addPrefiltered(field, read_prefiltered, &scene, &everything);
      continue;
    }
    const PlacedMesh mesh = placedMesh(readHeightField(field, read_image), field, curvedBaseOf(field, field.size), &scene.notes);
    extendBounds(mesh, &everything);
    addOpaque(mesh, field.albedo, field.brdf, &scene);
  }
  if (description.ground) {
    const double height = description.ground->height.value_or(bounds.empty() ? 0.0 : bounds.lo.z());
    addOpaque(groundPlane(height, bounds), description.ground->albedo, description.ground->brdf, &scene);
  }
  scene.surfaces->commit();
  if (scene.surfaces->empty()) scene.surfaces.reset();
  scene.ray_epsilon = 1e-5 * std::max(1.0, everything.empty() ? 1.0 : everything.extent().norm());
  for (const auto& [mesh, triangles] : translucent)
    scene.translucent.push_back(translucentObject(mesh->file, *mesh->translucent, triangles, description, scene));
  return scene;
}


CameraPose cameraOf(const SceneDescription& scene, const MediumView* medium) {
  const double aspect = double(scene.render.width) / scene.render.height;
  if (scene.view || !scene.camera_given) {
    if (!scene.view && !scene.camera.target.isZero())
      throw std::runtime_error("a camera target without a camera position: give both (or --view)");
    if (!medium) throw std::runtime_error("--view needs a medium to frame; give --camera-pos and --camera-target");
    return framedView(medium->worldBounds(), scene.view.value_or("+z"), scene.camera.fov_degrees, aspect);
  }
  return scene.camera;
}

std::vector<PolygonLight> sceneAreaLights(const SceneDescription& scene) {
  std::vector<PolygonLight> lights;
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    const json& light = scene.lights[i];
    if (!isAreaLight(light)) continue;
    const std::string where = fmt::format("lights[{}]", i);
    try {
      const Rgb radiance = rgbOf(light.value("radiance", json(1.0)), where, "radiance");
      PolygonLight polygon{areaLightVertices(light, where), radiance.matrix(), light.value("two_sided", false)};
      validatePolygonLight(polygon, where);
      lights.push_back(std::move(polygon));
    } catch (const nlohmann::json::exception& e) {
      throw std::runtime_error(fmt::format("{}: {}", where, e.what()));
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(e.what());
    }
  }
  return lights;
}

}  // namespace vdbappear
