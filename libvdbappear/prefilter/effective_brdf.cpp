#include "libvdbappear/prefilter/effective_brdf.h"

#include "libvdbappear/math/frame.h"
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/render/surface_scene.h"
#include "libvdbappear/surface/height_field_mesh.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace vdbappear {

MicroGeometry::MicroGeometry(const HeightField& field, const TileStretch& stretch, double base_curvature,
                             TileEdges edges)
    : field_(field),
      stretch_(stretch),
      base_curvature_(base_curvature),
      edges_(edges),
      tile_(Eigen::Vector2d(field.cellsX(), field.cellsY()) * field.cellSize()),
      scene_(std::make_unique<SurfaceScene>()) {
  if (!(base_curvature_ >= 0) || !std::isfinite(base_curvature_))
    throw std::invalid_argument("MicroGeometry: the base's curvature must be finite and not negative");
  std::vector<Triangle> triangles = heightFieldTriangles(field_, {});
  if (!stretch_.isIdentity())
    for (Triangle& t : triangles)
      for (Vec3& vertex : t) vertex = stretched(vertex);
  highest_ = -std::numeric_limits<double>::infinity();
  double lowest = std::numeric_limits<double>::infinity();
  lo_ = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  hi_ = -lo_;
  for (const Triangle& t : triangles)
    for (const Vec3& vertex : t) {
      highest_ = std::max(highest_, vertex.z());
      lowest = std::min(lowest, vertex.z());
      lo_ = lo_.cwiseMin(vertex.head<2>());
      hi_ = hi_.cwiseMax(vertex.head<2>());
    }
  chord_sag_ = std::max((highest_ - lowest) * kChordSagOfRelief, 1e-12);
  scene_->addDiffuse(triangles, Rgb::Zero());
  scene_->commit();
}

Vec3 MicroGeometry::stretched(const Vec3& on_map) const {
  const Eigen::Vector2d xy = stretch_.matrix() * on_map.head<2>();
  return {xy.x(), xy.y(), on_map.z()};
}

MicroGeometry::~MicroGeometry() = default;

MicroGeometry::Point MicroGeometry::at(double u, double v) const {
  const int i = std::clamp(int(u), 0, field_.cellsX() - 1), j = std::clamp(int(v), 0, field_.cellsY() - 1);
  const double s = field_.cellSize();
  Triangle t = cellTriangles(field_, i, j)[u - i >= v - j ? 0 : 1];  // the triangle above (u, v)
  for (Vec3& vertex : t) vertex = Vec3(vertex.x() * s, vertex.y() * s, vertex.z());  // as heightFieldTriangles
  const Vec3 a = t[0], normal = (t[1] - a).cross(t[2] - a).normalized();
  const Vec3 base(u * s, v * s, 0);
  // The height above base on the triangle's plane: normal . (x - a) = 0.
  const double z = a.z() - (normal.x() * (base.x() - a.x()) + normal.y() * (base.y() - a.y())) / normal.z();
  if (stretch_.isIdentity()) return {Vec3(base.x(), base.y(), z), normal, Point2(u, v)};
  return {stretched(Vec3(base.x(), base.y(), z)), stretch_.normalOnSurface(normal), Point2(u, v)};
}

double MicroGeometry::rayEpsilon() const {
  const double stretch = std::max(1.0, stretch_.matrix().cwiseAbs().maxCoeff());
  return 1e-6 * std::max(1.0, stretch * field_.cellSize() * std::max(field_.cellsX(), field_.cellsY()));
}

double MicroGeometry::tileExit(const Vec3& x, const Eigen::Vector2d& d_map, int& axis) const {
  const Eigen::Vector2d m = stretch_.inverse() * x.head<2>();  // on the map
  double nearest = std::numeric_limits<double>::infinity();
  axis = 0;
  for (int k = 0; k < 2; ++k)
    if (d_map[k] != 0) {
      const double t = ((d_map[k] > 0 ? tile_[k] : 0) - m[k]) / d_map[k];
      if (t < nearest) nearest = t, axis = k;
    }
  return std::max(nearest, 0.0);
}

template <typename Visit>
bool MicroGeometry::walkPiece(Vec3& x, const Vec3& d, double t_min, double t_max, Visit&& visit) const {
  if (edges_ == TileEdges::Open) {
    const bool done = visit(x, d, t_min, t_max);
    x += t_max * d;
    return done;
  }
  const Eigen::Vector2d d_map = stretch_.inverse() * d.head<2>();
  for (;;) {
    int axis = 0;
    const double exit = tileExit(x, d_map, axis);
    if (exit >= t_max) {
      const bool done = visit(x, d, t_min, t_max);
      x += t_max * d;
      return done;
    }
    if (exit > t_min && visit(x, d, t_min, exit)) return true;
    // Across the edge: the same point of the surface on the tile's opposite side.
    Eigen::Vector2d m = stretch_.inverse() * (x.head<2>() + exit * d.head<2>());
    m[axis] = d_map[axis] > 0 ? 0 : tile_[axis];
    const Eigen::Vector2d xy = stretch_.matrix() * m;
    x = Vec3(xy.x(), xy.y(), x.z() + exit * d.z());
    t_min = std::max(t_min - exit, 0.0);
    t_max -= exit;
  }
}

double MicroGeometry::longestPeriodicRay() const {
  return kMostTilesCrossed * std::max(1.0, stretch_.matrix().cwiseAbs().maxCoeff()) * tile_.maxCoeff();
}

double MicroGeometry::periodicReach(const Vec3& x, const Vec3& w) const {
  if (w.z() <= 0) return longestPeriodicRay();
  return std::min(longestPeriodicRay(), std::max(highest_ - x.z(), 0.0) / w.z());  // above the field beyond
}

bool MicroGeometry::unoccluded(const Point& p, const Vec3& w) const {
  const double eps = rayEpsilon();
  const Vec3 origin = p.x + eps * p.normal;
  const auto occluded = [this](const Vec3& a, const Vec3& d, double t0, double t1) {
    return scene_->occluded(a, d, t0, t1);
  };
  if (bendOf(w) > 0) return !followCurvedRay(origin, w, eps, occluded);
  if (edges_ == TileEdges::Open) return !scene_->occluded(origin, w, eps, 1e30);
  Vec3 x = origin;
  return !walkPiece(x, w, eps, std::max(periodicReach(origin, w), eps), occluded);
}

// The ray origin + t w + z bend t^2, bend = base_curvature |w_xy|^2 / 2, in pieces of length
// `step` whose chords stray from it by bend step^2 / 4 = chord_sag_ at most, until it rises above
// the field's highest point, or leaves its box (an open field), or has gone longestPeriodicRay()
// (a periodic one): each chord walked through the tile by walkPiece(), until `visit` returns true
// (then this does).
template <typename Visit>
bool MicroGeometry::followCurvedRay(const Vec3& origin, const Vec3& w, double eps, Visit&& visit) const {
  const double bend = bendOf(w);
  const double step = std::sqrt(4 * chord_sag_ / bend);  // the chord over [0, step] strays by bend t (step - t)
  const double longest = longestPeriodicRay();
  const auto at = [&](double t) { return Vec3(origin + t * w + Vec3(0, 0, bend * t * t)); };
  const auto outside = [&](const Vec3& a, double t) {
    if (a.z() > highest_) return true;
    if (edges_ == TileEdges::Periodic) return t > longest;
    return (a.head<2>().array() < lo_.array()).any() || (a.head<2>().array() > hi_.array()).any();
  };
  Vec3 a = origin;  // along the ray as it goes on over the tiles
  Vec3 x = origin;  // the same point in the tile
  for (double t = 0; !outside(a, t); t += step) {
    const Vec3 b = at(t + step), chord = b - a;
    const double length = chord.norm();
    if (walkPiece(x, chord / length, t == 0 ? eps : 0, length, visit)) return true;
    if (edges_ == TileEdges::Open) x = b;  // exactly the ray's point, as in the tile
    a = b;
  }
  return false;
}

MicroGeometry::Point MicroGeometry::pointOf(const Vec3& x, const Vec3& normal) const {
  const Eigen::Vector2d on_map = stretch_.isIdentity() ? Eigen::Vector2d(x.head<2>()) : stretch_.inverse() * x.head<2>();
  return Point{x, normal, Point2(on_map / field_.cellSize())};
}

// Over a curved base the ray is followed as unoccluded() follows it, and the first chord that meets
// the surface gives the point. The direction it arrives from is taken as w: it turns by
// base_curvature times the distance travelled (0.01 radians over ten cells of a 1K map on the ball),
// and the paths of R_ir's estimates mostly meet a neighbouring bump or leave.
std::optional<MicroGeometry::Point> MicroGeometry::trace(const Point& p, const Vec3& w) const {
  const double eps = rayEpsilon();
  const Vec3 origin = p.x + eps * p.normal;
  if (edges_ == TileEdges::Open && !(bendOf(w) > 0)) {
    const std::optional<SurfaceHit> hit = scene_->intersect(origin, w, eps, 1e30);
    if (!hit) return std::nullopt;
    return pointOf(origin + hit->t * w, hit->normal);
  }
  std::optional<Point> found;
  const auto meet = [&](const Vec3& a, const Vec3& d, double t0, double t1) {
    const std::optional<SurfaceHit> hit = scene_->intersect(a, d, t0, t1);
    if (hit) found = pointOf(a + hit->t * d, hit->normal);
    return hit.has_value();
  };
  if (bendOf(w) > 0) {
    followCurvedRay(origin, w, eps, meet);
  } else {
    Vec3 x = origin;
    walkPiece(x, w, eps, std::max(periodicReach(origin, w), eps), meet);
  }
  return found;
}

PatchBrdf microfacetPatchBrdf(const MicrofacetBrdf& base) {
  return [base](const Vec3&, const Vec3& normal, const Vec3& wi, const Vec3& wo) {
    const Frame frame = Frame::fromNormal(normal);
    return base.eval(frame.toLocal(wo), frame.toLocal(wi));
  };
}

namespace {

// Calls visit(point, a, b, A) at each of the samples_per_side^2 jittered base positions that wo
// sees, A = A_G(p, wo) of Eq. (4.7); returns the sum of A.
template <typename Visit>
double forVisiblePositions(const MicroGeometry& geometry, int i0, int j0, int count, const Vec3& wo,
                           const EffectiveBrdfSettings& settings, Visit&& visit) {
  const HeightField& field = geometry.field();
  if (count < 1 || i0 < 0 || j0 < 0 || i0 + count > field.cellsX() || j0 + count > field.cellsY() ||
      settings.samples_per_side < 1)
    throw std::invalid_argument("effectiveBrdf: the patch leaves the height field, or no samples");
  RandomStream rng(settings.seed, {i0, j0, count});
  const int side = settings.samples_per_side;
  double area = 0;
  for (int b = 0; b < side; ++b)
    for (int a = 0; a < side; ++a) {
      const Point2 jitter = rng.uniform2();
      const MicroGeometry::Point p =
          geometry.at(i0 + count * (a + jitter.x()) / side, j0 + count * (b + jitter.y()) / side);
      // A_G(p, wo) of Eq. (4.7): <wo, w_m> / <w_g, w_m> V(x, wo).
      const double cos_o = p.normal.dot(wo);
      if (cos_o <= 0 || (settings.visibility && !geometry.unoccluded(p, wo))) continue;
      const double A = cos_o / p.normal.z();
      area += A;
      visit(p, a, b, A);
    }
  return area;
}

// The ratio of Eq. (4.6) from the sums over the positions, and the mean visible area.
EffectiveBrdf averageOver(const Rgb& numerator, double area, int side) {
  EffectiveBrdf result;
  result.visible_area = area / (double(side) * side);
  if (area > 0) result.value = numerator / area;
  return result;
}

}  // namespace

EffectiveBrdf visibleAreaAverage(const MicroGeometry& geometry, int i0, int j0, int count, const Vec3& wo,
                                 const EffectiveBrdfSettings& settings, const PointReflectance& r) {
  Rgb numerator = Rgb::Zero();
  const double area = forVisiblePositions(geometry, i0, j0, count, wo, settings,
                                          [&](const MicroGeometry::Point& p, int a, int b, double A) { numerator += r(p, a, b) * A; });
  return averageOver(numerator, area, settings.samples_per_side);
}

std::vector<EffectiveBrdf> visibleAreaAverages(const MicroGeometry& geometry, int i0, int j0, int count, const Vec3& wo,
                                               const EffectiveBrdfSettings& settings, std::size_t n,
                                               const PointReflectances& r) {
  std::vector<Rgb> numerators(n, Rgb::Zero()), values(n);
  const double area = forVisiblePositions(geometry, i0, j0, count, wo, settings,
                                          [&](const MicroGeometry::Point& p, int a, int b, double A) {
                                            r(p, a, b, values.data());
                                            for (std::size_t k = 0; k < n; ++k) numerators[k] += values[k] * A;
                                          });
  std::vector<EffectiveBrdf> results;
  for (const Rgb& numerator : numerators) results.push_back(averageOver(numerator, area, settings.samples_per_side));
  return results;
}

namespace {

// f <w_m, wi> V(wi) of Eq. (4.6) at a visible point.
Rgb lightedReflectance(const MicroGeometry& geometry, const MicroGeometry::Point& p, const PatchBrdf& f, const Vec3& wi,
                       const Vec3& wo, bool visibility) {
  const double cos_i = p.normal.dot(wi);
  if (cos_i <= 0 || (visibility && !geometry.unoccluded(p, wi))) return Rgb::Zero();
  return f(p.x, p.normal, wi, wo) * cos_i;
}

}  // namespace

EffectiveBrdf effectiveBrdf(const MicroGeometry& geometry, int i0, int j0, int count, const PatchBrdf& f,
                            const Vec3& wi, const Vec3& wo, const EffectiveBrdfSettings& settings) {
  return visibleAreaAverage(geometry, i0, j0, count, wo, settings, [&](const MicroGeometry::Point& p, int, int) {
    return lightedReflectance(geometry, p, f, wi, wo, settings.visibility);
  });
}

std::vector<EffectiveBrdf> effectiveBrdfs(const MicroGeometry& geometry, int i0, int j0, int count, const PatchBrdf& f,
                                          const std::vector<Vec3>& wis, const Vec3& wo,
                                          const EffectiveBrdfSettings& settings) {
  return visibleAreaAverages(geometry, i0, j0, count, wo, settings, wis.size(),
                             [&](const MicroGeometry::Point& p, int, int, Rgb* values) {
                               for (std::size_t k = 0; k < wis.size(); ++k)
                                 values[k] = lightedReflectance(geometry, p, f, wis[k], wo, settings.visibility);
                             });
}

}  // namespace vdbappear
