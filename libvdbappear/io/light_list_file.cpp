#include "libvdbappear/io/light_list_file.h"

#include "libvdbappear/util/error.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <iostream>

namespace vdbappear {

namespace {

Vec3 vec3(const nlohmann::json& v, const std::string& what) {
  if (v.is_number()) return Vec3::Constant(v.get<double>());
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    throw std::invalid_argument(fmt::format("{}: expected [x, y, z] numbers", what));
  return Vec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
}

PolygonLight parseLight(const nlohmann::json& j, const std::string& what) {
  if (!j.is_object()) throw std::invalid_argument(fmt::format("{}: expected an object", what));
  for (const auto& [key, value] : j.items())
    if (key != "vertices" && key != "radiance" && key != "two_sided" && key != "type")
      throw std::invalid_argument(fmt::format("{}: unknown key '{}' (vertices, radiance, two_sided)", what, key));
  if (!j.contains("vertices") || !j["vertices"].is_array()) throw std::invalid_argument(fmt::format("{}: needs a \"vertices\" array", what));
  PolygonLight light;
  for (std::size_t v = 0; v < j["vertices"].size(); ++v) {
    if (j["vertices"][v].is_number()) throw std::invalid_argument(fmt::format("{}: vertices[{}]: expected [x, y, z]", what, v));
    light.vertices.push_back(vec3(j["vertices"][v], fmt::format("{}: vertices[{}]", what, v)));
  }
  if (j.contains("radiance")) light.radiance = vec3(j["radiance"], what + ": radiance");
  if (j.contains("two_sided")) {
    if (!j["two_sided"].is_boolean()) throw std::invalid_argument(fmt::format("{}: two_sided must be true or false", what));
    light.two_sided = j["two_sided"].get<bool>();
  }
  validatePolygonLight(light, what);
  return light;
}

}  // namespace

std::vector<PolygonLight> readLightList(const std::string& path) {
  nlohmann::json json;
  try {
    if (path == "-") {
      json = nlohmann::json::parse(std::cin);
    } else {
      std::ifstream file(path);
      if (!file) throw MediumError(fmt::format("{}: cannot open the lights file", path));
      json = nlohmann::json::parse(file);
    }
  } catch (const nlohmann::json::exception& e) {
    throw MediumError(fmt::format("{}: not valid JSON ({})", path, e.what()));
  }
  if (!json.is_object() || !json.contains("lights") || !json["lights"].is_array())
    throw MediumError(fmt::format("{}: expected {{\"lights\": [...]}}", path));
  std::vector<PolygonLight> lights;
  try {
    for (std::size_t k = 0; k < json["lights"].size(); ++k) lights.push_back(parseLight(json["lights"][k], fmt::format("lights[{}]", k)));
  } catch (const std::invalid_argument& e) {
    throw MediumError(fmt::format("{}: {}", path, e.what()));
  }
  if (lights.empty()) throw MediumError(fmt::format("{}: \"lights\" is empty", path));
  return lights;
}

void lightBounds(const std::vector<PolygonLight>& lights, Vec3* lo, Vec3* hi) {
  *lo = Vec3::Constant(INFINITY);
  *hi = Vec3::Constant(-INFINITY);
  for (const PolygonLight& light : lights)
    for (const Vec3& p : light.vertices) {
      *lo = lo->cwiseMin(p);
      *hi = hi->cwiseMax(p);
    }
}

}  // namespace vdbappear
