#pragma once
// Lights at infinity that surround the scene: a constant sky, a lat-long environment map, or a
// real spherical-harmonic basis function (the training lights of §6.3, downsampling paper).
//
// Lat-long maps use Blender's equirectangular convention, with z up: pixel column u in [0,1)
// (left to right) is the azimuth phi = pi (1 - 2u), so the centre column looks along +x and u
// grows clockwise seen from above; row v in [0,1) (top to bottom) is the elevation pi (1/2 - v).
// radiance(w) is what is seen looking toward w. Maps are sampled in proportion to
// mean(RGB) * cos(elevation) per pixel (pbrt-v4 §12.5.2); a pixel is constant over its cell.
//
// Spherical-harmonic lights have radiance scale * Y_lm(w) in every channel, Y_lm as in
// math/spherical_harmonics.h. Y_lm is negative on half of its lobes and the light keeps that sign:
// transport is linear, so a render under Y_lm is the response to that basis function, negative
// pixels included (EXR keeps them; PNG previews clamp them to black). Sampling follows |Y_lm|,
// tabulated on a 128x64 lat-long grid plus 5% of its maximum so that no direction has pdf 0.

#include "libvdbappear/math/piecewise_constant.h"
#include "libvdbappear/render/light.h"

#include <memory>
#include <vector>

namespace vdbappear {

class EnvironmentLight final : public Light {
 public:
  static std::unique_ptr<EnvironmentLight> constant(const Rgb& radiance);
  // rgb: width * height * 3 linear floats, row 0 at the top.
  static std::unique_ptr<EnvironmentLight> fromImage(int width, int height, std::vector<float> rgb, double scale);
  static std::unique_ptr<EnvironmentLight> sphericalHarmonic(int l, int m, double scale);

  bool isDelta() const override { return false; }
  bool isEnvironment() const override { return true; }
  // Smooth: the largest radiance at most kSmoothPeakToMean times the average over the sphere
  // (mean of RGB; for SH lights of |radiance|). 1 for a constant sky, 2 for a band-1 SH light, 2.6
  // for Y_20; a sky with a sun in it is in the hundreds.
  static constexpr double kSmoothPeakToMean = 4;
  bool isSmooth() const override { return peak_to_mean_ <= kSmoothPeakToMean; }
  double peakToMean() const { return peak_to_mean_; }
  LightSample sample(const Vec3& p, const Point2& u) const override;
  double pdf(const Vec3& p, const Vec3& wi) const override;
  Rgb radiance(const Vec3& w) const override;

  // Direction <-> lat-long coordinates (u, v) in [0,1)^2, as above.
  static Vec3 directionOf(const Point2& uv);
  static Point2 latLongOf(const Vec3& w);

 private:
  enum class Kind { kConstant, kImage, kSphericalHarmonic };
  EnvironmentLight() = default;
  void buildDistribution(const std::vector<double>& weights, int width, int height);
  // peak_to_mean_ of lat-long weights, each weighing its cell's solid angle (cos elevation).
  void measurePeakToMean(const std::vector<double>& weights, int width, int height);

  Kind kind_ = Kind::kConstant;
  Rgb constant_ = Rgb::Zero();
  int width_ = 0, height_ = 0;
  std::vector<float> rgb_;
  double scale_ = 1;
  double peak_to_mean_ = 1;
  int l_ = 0, m_ = 0;
  PiecewiseConstant2D distribution_;  // over (u, v); unused for kConstant (uniform sphere)
};

}  // namespace vdbappear
