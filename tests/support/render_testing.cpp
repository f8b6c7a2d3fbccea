#include "support/render_testing.h"

#include "libvdbappear/io/medium.h"
#include "libvdbappear/medium/medium_view.h"
#include "libvdbappear/render/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace vdbappear::test {

using nlohmann::json;

MediumPtr cube(int res, double size, float rho, float albedo) {
  auto medium = std::make_shared<Medium>();
  medium->source = "test cube";
  medium->density = openvdb::FloatGrid::create(0.0f);
  medium->density->setName(grid_names::kDensity);
  medium->density->setTransform(openvdb::math::Transform::createLinearTransform(size / res));
  const openvdb::CoordBBox box(openvdb::Coord(0), openvdb::Coord(res - 1));
  medium->density->denseFill(box, rho, true);
  medium->albedo = openvdb::Vec3SGrid::create(openvdb::Vec3s(1.0f));
  medium->albedo->setName(grid_names::kAlbedo);
  medium->albedo->setTransform(medium->density->transform().copy());
  medium->albedo->denseFill(box, openvdb::Vec3s(albedo), true);
  return medium;
}

Render summarize(RenderResult result) {
  Render r;
  r.result = std::move(result);
  const double n = double(r.result.mean.size());
  double variance = 0;
  for (std::size_t i = 0; i < r.result.mean.size(); ++i) {
    r.mean += r.result.mean[i] / n;
    variance += r.result.variance[i] / (n * n);
  }
  r.error = std::sqrt(variance);
  return r;
}

Render render(const MediumPtr& medium, const json& lights, const RenderSettings& settings, Interpolation interp,
              const std::string& view, std::optional<GroundDescription> ground) {
  SceneDescription description;
  description.lights = lights;
  description.ground = ground;
  description.render = settings;
  description.interpolation = interp;
  description.view = view;
  const auto view_of = medium ? std::make_shared<MediumView>(medium, interp) : nullptr;
  const RenderScene scene = buildRenderScene(description, view_of, [](const std::string&) -> RgbImage {
    throw std::runtime_error("no images in tests");
  });
  const PinholeCamera camera(cameraOf(description, view_of.get()), settings.width, settings.height);
  return summarize(renderImage(scene, camera, settings));
}

Render renderStraightDown(const MediumPtr& medium, const json& lights, const RenderSettings& settings,
                          std::optional<Vec3> target, Interpolation interp) {
  SceneDescription description;
  description.lights = lights;
  const auto view = std::make_shared<MediumView>(medium, interp);
  const Vec3 centre = target ? *target : view->worldBounds().centre();
  const RenderScene scene = buildRenderScene(description, view, {});
  const PinholeCamera camera({centre + Vec3(0, 0, 100), centre, Vec3(0, 1, 0), 0.05}, settings.width, settings.height);
  return summarize(renderImage(scene, camera, settings));
}

RenderSettings small(int size, int spp, std::uint64_t seed) {
  RenderSettings s;
  s.width = s.height = size;
  s.spp = spp;
  s.seed = seed;
  return s;
}

void expectImage(const Render& r, double expected, const std::string& what) {
  int outliers = 0;
  for (std::size_t i = 0; i < r.result.mean.size(); ++i) {
    const double sigma = std::sqrt(r.result.variance[i]);
    if (std::abs(r.result.mean[i] - expected) > 5 * sigma + 1e-6) ++outliers;
  }
  EXPECT_EQ(outliers, 0) << what;
  EXPECT_NEAR(r.mean, expected, 4 * r.error + 1e-9) << what;
  EXPECT_EQ(r.result.tracking.majorant_violations, 0u) << what;
}

void expectImage(const Render& r, const Rgb& expected, const std::string& what) {
  int outliers = 0;
  Rgb mean = Rgb::Zero(), variance = Rgb::Zero();
  const double pixels = double(r.result.mean.size() / 3);
  for (std::size_t i = 0; i < r.result.mean.size(); ++i) {
    const int c = int(i % 3);
    if (std::abs(r.result.mean[i] - expected[c]) > 5 * std::sqrt(r.result.variance[i]) + 1e-6) ++outliers;
    mean[c] += r.result.mean[i] / pixels;
    variance[c] += r.result.variance[i] / (pixels * pixels);
  }
  EXPECT_EQ(outliers, 0) << what;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], expected[c], 4 * std::sqrt(variance[c]) + 1e-9) << what << ", channel " << c;
  EXPECT_EQ(r.result.tracking.majorant_violations, 0u) << what;
}

void expectSameImage(const Render& a, const Render& b, const std::string& what) {
  EXPECT_NEAR(a.mean, b.mean, 4 * std::hypot(a.error, b.error)) << what;
  int outliers = 0;
  for (std::size_t i = 0; i < a.result.mean.size(); ++i)
    if (std::abs(a.result.mean[i] - b.result.mean[i]) > 5 * std::sqrt(a.result.variance[i] + b.result.variance[i]) + 1e-6)
      ++outliers;
  EXPECT_EQ(outliers, 0) << what;
}

}  // namespace vdbappear::test
