#pragma once
// Light sources for next-event estimation (pbrt-v4 Ch. 12). Units: radiance L in the scene's
// radiometric unit per steradian; directional lights give irradiance E on a plane facing them;
// point lights intensity I (irradiance I / r^2 at distance r). docs/rendering.md has the table.

#include "libvdbappear/math/rgb.h"
#include "libvdbappear/math/vector.h"

#include <cmath>
#include <limits>

namespace vdbappear {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Incident radiance toward p from a sampled direction: wi points from p toward the light.
// For delta lights, Li is what arrives (the delta is in pdf = 1 with is_delta).
struct LightSample {
  Vec3 wi;
  double distance = kInfinity;  // to the light point; kInfinity for lights at infinity
  Rgb Li = Rgb::Zero();
  double pdf = 0;               // per unit solid angle (1 for delta lights); 0: no sample
  bool is_delta = false;
};

class Light {
 public:
  virtual ~Light() = default;
  virtual bool isDelta() const = 0;
  virtual bool isEnvironment() const { return false; }
  virtual bool isArea() const { return false; }  // polygons hit as surfaces (AreaLight)
  // Radiance within a small factor of its average over the sphere (a constant or overcast sky, low
  // SH bands). Phase or BRDF sampling, whose pdf follows f, then estimates its light with bounded
  // weights (f L / pdf = albedo L where unshadowed), and sampling the light as well mostly adds a
  // shadow ray: LightStrategy::kAuto leaves smooth lights to phase sampling.
  virtual bool isSmooth() const { return false; }
  virtual LightSample sample(const Vec3& p, const Point2& u) const = 0;
  // Solid-angle density with which sample(p, .) returns wi (environment lights; area lights use
  // AreaLight::pdf with the hit point).
  virtual double pdf(const Vec3& /*p*/, const Vec3& /*wi*/) const { return 0; }
  // Environment lights: radiance arriving along -w, i.e. seen when looking toward w.
  virtual Rgb radiance(const Vec3& /*w*/) const { return Rgb::Zero(); }
};

// A light infinitely far away in direction -direction, direction being where the light travels
// (--sun DX,DY,DZ,STRENGTH). E: irradiance on a plane perpendicular to it.
class DirectionalLight final : public Light {
 public:
  DirectionalLight(const Vec3& direction, const Rgb& irradiance) : wi_(-direction.normalized()), E_(irradiance) {}
  bool isDelta() const override { return true; }
  LightSample sample(const Vec3&, const Point2&) const override { return {wi_, kInfinity, E_, 1.0, true}; }

 private:
  Vec3 wi_;
  Rgb E_;
};

// An isotropic point light of intensity I: irradiance I / r^2 at distance r, facing it.
class PointLight final : public Light {
 public:
  PointLight(const Vec3& position, const Rgb& intensity) : position_(position), I_(intensity) {}
  bool isDelta() const override { return true; }
  LightSample sample(const Vec3& p, const Point2&) const override {
    const Vec3 to_light = position_ - p;
    const double r2 = to_light.squaredNorm();
    if (!(r2 > 0)) return {};
    const double r = std::sqrt(r2);
    return {to_light / r, r, I_ / r2, 1.0, true};
  }

 private:
  Vec3 position_;
  Rgb I_;
};

}  // namespace vdbappear
