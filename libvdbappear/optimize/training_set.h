#pragma once
// The training renderings of the weight optimisation (§6.3, §8.1, Fig. 7 of the downsampling paper):
// the six views along the axes of the medium's bounding box, each under a few smooth lights, at
// about 100 pixels on the long side.
//
// The paper's lights are the SH basis functions of bands 0-1. Y_1m is negative on half the sphere,
// so its renders are signed and their means near 0, where c_r = 1 / max(mean, 0.05) of Eq. 14 is a
// poor normalisation. The same four-dimensional space of lights is spanned by non-negative ones:
// a constant sky L = 1 and the three skies L = 1 + w.a (a = +x, +y, +z, brightest looking toward a,
// zero opposite), which is what "sh1" renders. "sh0" is the constant sky alone; "sh2" adds the
// nine skies 1 + Y_2m / max|Y_2m| (Fig. 13's band 2); "sun" adds five suns over a dim sky, from the
// zenith and from the four diagonal azimuths at an elevation of 35 degrees (harsh light; see
// docs/optimize.md). The modifier "ground" puts a diffuse ground (albedo 0.5) under the medium in
// every lighting: light from below then comes only from the ground's bounce. Light header.

#include "libvdbappear/render/camera.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace vdbappear {

struct TrainingView {
  std::string name;  // "+x" ... "-z"
  CameraPose pose;
  int width = 0, height = 0;
};

struct TrainingLighting {
  std::string name;       // "sky", "sky+x", ...
  nlohmann::json lights;  // scene-file lights (render/scene_description.h)
  bool ground = false;    // a diffuse ground (albedo 0.5) at the bottom of the box
};

struct TrainingConfig {
  TrainingView view;
  TrainingLighting lighting;
  double ground_height = 0;  // z of the ground, when lighting.ground (the bottom of the full medium's box)
  std::string name() const { return view.name + "/" + lighting.name; }
};

// Views framed on `box` (vertical fov 30), each image `resolution` pixels on its long side with the
// aspect of the box's outline (at least 8 on the short). views: a comma-separated list of the 26
// directions of the box's sides (+x ... -z: the views of Fig. 7, render/camera.h framedView), edges
// (+x+y, -x+z, +y-z, ...) and corners (+x+y+z ... -x-y-z; framedDirection), axes in the order x, y,
// z, and the words faces (the six sides), edges (the twelve), corners (the eight), upper-edges and
// upper-corners (those with +z) and upper-hemisphere (+z, the upper edges and corners: nine views
// every 45 degrees of azimuth). Throws std::invalid_argument for anything else.
inline constexpr const char* kFaces = "faces";
std::vector<TrainingView> boundingBoxViews(const Aabb& box, int resolution, const std::string& sides = kFaces);

// Lightings by a '+'-separated list of kinds: sh0, sh1, sh2, sun, and the modifier ground (above). Throws
// std::invalid_argument for an unknown kind.
std::vector<TrainingLighting> trainingLightings(const std::string& kinds);

// Every view under every lighting, views outermost.
std::vector<TrainingConfig> trainingSet(const Aabb& box, int resolution, const std::string& light_kinds,
                                        const std::string& sides = kFaces);

}  // namespace vdbappear
