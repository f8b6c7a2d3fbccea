#pragma once
// Renders of small test scenes and their checks against expected images, for the path tracer's
// tests (render_test.cpp, emission_test.cpp).

#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/math/rgb.h"
#include "libvdbappear/math/vector.h"
#include "libvdbappear/medium/interpolation.h"
#include "libvdbappear/render/render_image.h"
#include "libvdbappear/render/scene_description.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace vdbappear::test {

// A cube of res^3 voxels and edge `size`: voxel i covers [i - 1/2, i + 1/2] h, h = size / res.
MediumPtr cube(int res, double size, float rho, float albedo);

struct Render {
  RenderResult result;
  double mean = 0, error = 0;  // image mean and its standard error
};

// The image mean and its standard error.
Render summarize(RenderResult result);

Render render(const MediumPtr& medium, const nlohmann::json& lights, const RenderSettings& settings,
              Interpolation interp, const std::string& view = "+z",
              std::optional<GroundDescription> ground = std::nullopt);

// A narrow camera far above `target` (the medium's centre by default): every ray within 0.02
// degrees of -z.
Render renderStraightDown(const MediumPtr& medium, const nlohmann::json& lights, const RenderSettings& settings,
                          std::optional<Vec3> target = std::nullopt, Interpolation interp = Interpolation::kNearest);

RenderSettings small(int size, int spp, std::uint64_t seed = 1);

// Every pixel within 5 standard errors of `expected`, the image mean within 4.
void expectImage(const Render& r, double expected, const std::string& what);
// The same per RGB channel.
void expectImage(const Render& r, const Rgb& expected, const std::string& what);

// Two renders of one scene agree: the means within 4 combined standard errors, every pixel within 5.
void expectSameImage(const Render& a, const Render& b, const std::string& what);

}  // namespace vdbappear::test
