#include "libvdbappear/optimize/training_set.h"

#include "libvdbappear/math/constants.h"

#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace vdbappear {

namespace {

// A side (+x ... -z), an edge (+x+y, -x+z, +y-z, ...) or a corner (+x+y+z ... -x-y-z) of the box:
// the unit direction toward the camera. Axes appear in the order x, y, z, each at most once.
std::optional<Vec3> directionOf(const std::string& name) {
  if (name.empty() || name.size() % 2 != 0 || name.size() > 6) return std::nullopt;
  Vec3 d = Vec3::Zero();
  int last_axis = -1;
  for (std::size_t i = 0; i < name.size(); i += 2) {
    const int axis = name[i + 1] - 'x';
    if ((name[i] != '+' && name[i] != '-') || axis < 0 || axis > 2 || axis <= last_axis) return std::nullopt;
    d[axis] = name[i] == '+' ? 1 : -1;
    last_axis = axis;
  }
  return d.normalized();
}

// The 26 directions of the box's faces, edges and corners, by name.
std::vector<std::string> boxDirections(int axes) {
  std::vector<std::string> out;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z) {
        if (std::abs(x) + std::abs(y) + std::abs(z) != axes) continue;
        std::string name;
        if (x) name += std::string(x > 0 ? "+" : "-") + "x";
        if (y) name += std::string(y > 0 ? "+" : "-") + "y";
        if (z) name += std::string(z > 0 ? "+" : "-") + "z";
        out.push_back(name);
      }
  return out;
}

std::vector<std::string> splitViews(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  std::string item;
  const auto add = [&](const std::string& view) {
    for (const std::string& seen : out)
      if (seen == view) throw std::invalid_argument("training views '" + list + "': " + view + " twice");
    out.push_back(view);
  };
  const auto upper = [](const std::string& name) { return name.size() >= 2 && name.substr(name.size() - 2) == "+z"; };
  while (std::getline(in, item, ',')) {
    const bool keyword = item == "faces" || item == "edges" || item == "corners" || item == "upper-edges" ||
                         item == "upper-corners" || item == "upper-hemisphere";
    if (item == "faces") {
      for (const char* side : {"+x", "-x", "+y", "-y", "+z", "-z"}) add(side);
    } else if (item == "upper-hemisphere") {
      add("+z");
      for (const std::string& name : boxDirections(2))
        if (upper(name)) add(name);
      for (const std::string& name : boxDirections(3))
        if (upper(name)) add(name);
    } else if (keyword) {
      const bool corners = item.find("corners") != std::string::npos;
      for (const std::string& name : boxDirections(corners ? 3 : 2))
        if (item.rfind("upper-", 0) != 0 || upper(name)) add(name);
    } else if (directionOf(item)) {
      add(item);
    } else {
      throw std::invalid_argument("training views '" + list + "': '" + item +
                                  "' is not a side (+x ... -z), an edge (+x+y ... -y-z), a corner (+x+y+z ... -x-y-z) "
                                  "or one of faces, edges, corners, upper-edges, upper-corners, upper-hemisphere");
    }
  }
  if (out.empty()) throw std::invalid_argument("training views: empty list");
  return out;
}

}  // namespace

std::vector<TrainingView> boundingBoxViews(const Aabb& box, int resolution, const std::string& sides) {
  std::vector<TrainingView> views;
  for (const std::string& name : splitViews(sides)) {
    const Vec3 d = *directionOf(name);
    // Up: +z, or +y for views along z (as framedView).
    const Vec3 up = std::abs(d.z()) > 0.999 ? Vec3(0, 1, 0) : Vec3(0, 0, 1);
    const double aspect = outlineAspect(box, d, up);
    TrainingView view;
    view.name = name;
    if (aspect >= 1) {
      view.width = resolution;
      view.height = std::max(8, int(std::lround(resolution / aspect)));
    } else {
      view.height = resolution;
      view.width = std::max(8, int(std::lround(resolution * aspect)));
    }
    view.pose = name.size() == 2 ? framedView(box, name, 30, double(view.width) / view.height)
                                 : framedDirection(box, d, up, 30, double(view.width) / view.height);
    views.push_back(view);
  }
  return views;
}

namespace {

nlohmann::json sky(double radiance) { return {{"type", "env"}, {"radiance", radiance}}; }
nlohmann::json sh(int l, int m, double scale) { return {{"type", "sh"}, {"l", l}, {"m", m}, {"scale", scale}}; }

// 1 + w.a for a = +x, +y, +z: Y_1,1 = -c x, Y_1,-1 = -c y, Y_1,0 = c z with c = sqrt(3 / 4 pi)
// (math/spherical_harmonics.h).
void addBand1(std::vector<TrainingLighting>& out) {
  const double c = std::sqrt(3 / (4 * kPi));
  out.push_back({"sky+x", nlohmann::json::array({sky(1), sh(1, 1, -1 / c)})});
  out.push_back({"sky+y", nlohmann::json::array({sky(1), sh(1, -1, -1 / c)})});
  out.push_back({"sky+z", nlohmann::json::array({sky(1), sh(1, 0, 1 / c)})});
}

// 1 + Y_2m / max|Y_2m|: max |Y_2,0| = sqrt(5 / 4 pi) (at the poles), max |Y_2,m| = sqrt(15 / 16 pi)
// for m != 0.
void addBand2(std::vector<TrainingLighting>& out) {
  for (int m = -2; m <= 2; ++m) {
    const double largest = m == 0 ? std::sqrt(5 / (4 * kPi)) : std::sqrt(15 / (16 * kPi));
    out.push_back({"sky+Y2," + std::to_string(m), nlohmann::json::array({sky(1), sh(2, m, 1 / largest)})});
  }
}

// Five suns from the upper hemisphere over a dim sky: one from the zenith and four from the box's
// diagonal azimuths (45, 135, 225, 315 degrees) at an elevation of 35 degrees.
void addSuns(std::vector<TrainingLighting>& out) {
  out.push_back({"sun+z", nlohmann::json::array({sky(0.1), {{"type", "sun"}, {"direction", {0.0, 0.0, -1.0}}, {"strength", 3.0}}})});
  const double elevation = 35 * kPi / 180;
  for (int i = 0; i < 4; ++i) {
    const double azimuth = (45 + 90 * i) * kPi / 180;
    const Vec3 toward(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    out.push_back({"sun" + std::to_string(45 + 90 * i),
                   nlohmann::json::array({sky(0.1), {{"type", "sun"}, {"direction", {-toward.x(), -toward.y(), -toward.z()}}, {"strength", 3.0}}})});
  }
}

}  // namespace

std::vector<TrainingLighting> trainingLightings(const std::string& kinds) {
  std::vector<TrainingLighting> out;
  std::stringstream in(kinds);
  std::string kind;
  bool any = false, ground = false;
  while (std::getline(in, kind, '+')) {
    if (kind == "ground") {
      ground = true;
      continue;
    }
    any = true;
    if (kind == "sh0") {
      out.push_back({"sky", nlohmann::json::array({sky(1)})});
    } else if (kind == "sh1") {
      out.push_back({"sky", nlohmann::json::array({sky(1)})});
      addBand1(out);
    } else if (kind == "sh2") {
      out.push_back({"sky", nlohmann::json::array({sky(1)})});
      addBand1(out);
      addBand2(out);
    } else if (kind == "sun") {
      addSuns(out);
    } else {
      throw std::invalid_argument("training lights '" + kinds + "': unknown kind '" + kind +
                                  "' (sh0, sh1, sh2, sun, ground)");
    }
  }
  if (!any) throw std::invalid_argument("training lights '" + kinds + "': no lights (sh0, sh1, sh2 or sun)");
  for (TrainingLighting& l : out) {
    l.ground = ground;
    if (ground) l.name += "+ground";
  }
  // A kind listed twice, or sh0 with sh1, would repeat the sky: keep the first of each name.
  std::vector<TrainingLighting> unique;
  for (const TrainingLighting& l : out) {
    bool seen = false;
    for (const TrainingLighting& u : unique) seen |= u.name == l.name;
    if (!seen) unique.push_back(l);
  }
  return unique;
}

std::vector<TrainingConfig> trainingSet(const Aabb& box, int resolution, const std::string& light_kinds,
                                        const std::string& sides) {
  std::vector<TrainingConfig> set;
  const std::vector<TrainingLighting> lightings = trainingLightings(light_kinds);
  for (const TrainingView& view : boundingBoxViews(box, resolution, sides))
    for (const TrainingLighting& lighting : lightings) set.push_back({view, lighting, box.lo.z()});
  return set;
}

}  // namespace vdbappear
