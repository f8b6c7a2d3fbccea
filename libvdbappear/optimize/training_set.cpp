#include "libvdbappear/optimize/training_set.h"

#include "libvdbappear/math/constants.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace vdbappear {

std::vector<TrainingView> boundingBoxViews(const Aabb& box, int resolution) {
  const Vec3 e = box.extent();
  std::vector<TrainingView> views;
  for (const char* side : {"+x", "-x", "+y", "-y", "+z", "-z"}) {
    // The face seen from the side: image axes (horizontal, vertical) as framedView orients them.
    const int axis = side[1] - 'x';
    const double across = axis == 0 ? e.y() : e.x();
    const double up = axis == 2 ? e.y() : e.z();
    TrainingView view;
    view.name = side;
    if (across >= up) {
      view.width = resolution;
      view.height = std::max(8, int(std::lround(resolution * up / std::max(across, 1e-300))));
    } else {
      view.height = resolution;
      view.width = std::max(8, int(std::lround(resolution * across / std::max(up, 1e-300))));
    }
    view.pose = framedView(box, side, 30, double(view.width) / view.height);
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
  out.push_back({"sky+x", {sky(1), sh(1, 1, -1 / c)}});
  out.push_back({"sky+y", {sky(1), sh(1, -1, -1 / c)}});
  out.push_back({"sky+z", {sky(1), sh(1, 0, 1 / c)}});
}

// 1 + Y_2m / max|Y_2m|: max |Y_2,0| = sqrt(5 / 4 pi) (at the poles), max |Y_2,m| = sqrt(15 / 16 pi)
// for m != 0.
void addBand2(std::vector<TrainingLighting>& out) {
  for (int m = -2; m <= 2; ++m) {
    const double largest = m == 0 ? std::sqrt(5 / (4 * kPi)) : std::sqrt(15 / (16 * kPi));
    out.push_back({"sky+Y2," + std::to_string(m), {sky(1), sh(2, m, 1 / largest)}});
  }
}

void addSuns(std::vector<TrainingLighting>& out) {
  const char* names[] = {"+x", "-x", "+y", "-y", "+z", "-z"};
  for (int i = 0; i < 6; ++i) {
    Vec3 toward = Vec3::Zero();
    toward[i / 2] = i % 2 ? -1 : 1;
    out.push_back({std::string("sun") + names[i],
                   {sky(0.1), {{"type", "sun"}, {"direction", {-toward.x(), -toward.y(), -toward.z()}}, {"strength", 3.0}}}});
  }
}

}  // namespace

std::vector<TrainingLighting> trainingLightings(const std::string& kinds) {
  std::vector<TrainingLighting> out;
  std::stringstream in(kinds);
  std::string kind;
  bool any = false;
  while (std::getline(in, kind, '+')) {
    any = true;
    if (kind == "sh0") {
      out.push_back({"sky", {sky(1)}});
    } else if (kind == "sh1") {
      out.push_back({"sky", {sky(1)}});
      addBand1(out);
    } else if (kind == "sh2") {
      out.push_back({"sky", {sky(1)}});
      addBand1(out);
      addBand2(out);
    } else if (kind == "sun") {
      addSuns(out);
    } else {
      throw std::invalid_argument("training lights '" + kinds + "': unknown kind '" + kind + "' (sh0, sh1, sh2, sun)");
    }
  }
  if (!any) throw std::invalid_argument("training lights: empty list");
  // A kind listed twice, or sh0 with sh1, would repeat the sky: keep the first of each name.
  std::vector<TrainingLighting> unique;
  for (const TrainingLighting& l : out) {
    bool seen = false;
    for (const TrainingLighting& u : unique) seen |= u.name == l.name;
    if (!seen) unique.push_back(l);
  }
  return unique;
}

std::vector<TrainingConfig> trainingSet(const Aabb& box, int resolution, const std::string& light_kinds) {
  std::vector<TrainingConfig> set;
  const std::vector<TrainingLighting> lightings = trainingLightings(light_kinds);
  for (const TrainingView& view : boundingBoxViews(box, resolution))
    for (const TrainingLighting& lighting : lightings) set.push_back({view, lighting});
  return set;
}

}  // namespace vdbappear
