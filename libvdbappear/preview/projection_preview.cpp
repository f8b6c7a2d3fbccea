#include "libvdbappear/preview/projection_preview.h"

#include "libvdbappear/io/emission_convention.h"
#include "libvdbappear/medium/emission_light.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/util/progress.h"

#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vdbappear {

namespace {

// Nearest-voxel lookups of the grids the preview needs, one set per thread.
class VoxelLookup {
 public:
  VoxelLookup(const Medium& m, const openvdb::Vec3SGrid* emission)
      : density_(m.density->getConstAccessor()),
        albedo_(m.albedo ? std::optional(m.albedo->getConstAccessor()) : std::nullopt),
        diag_(m.sggx_diag ? std::optional(m.sggx_diag->getConstAccessor()) : std::nullopt),
        offdiag_(m.sggx_offdiag ? std::optional(m.sggx_offdiag->getConstAccessor()) : std::nullopt) {
    if (emission) emission_.emplace(emission->getConstAccessor());
  }

  float density(const openvdb::Coord& c) const { return density_.getValue(c); }
  Vec3 albedo(const openvdb::Coord& c) const {
    if (!albedo_) return Vec3::Ones();
    const openvdb::Vec3s a = albedo_->getValue(c);
    return Vec3(a[0], a[1], a[2]);
  }
  bool emits() const { return bool(emission_); }
  Vec3 emission(const openvdb::Coord& c) const {  // inactive voxels emit nothing
    openvdb::Vec3s e(0.0f);
    return emission_ && emission_->probeValue(c, e) ? Vec3(e[0], e[1], e[2]) : Vec3(Vec3::Zero());
  }
  // sqrt(w^T S w): the projected area of the flakes toward w (S = I without SGGX grids).
  double sigma(const openvdb::Coord& c, const Vec3& w) const {
    if (!diag_) return 1;
    const openvdb::Vec3s d = diag_->getValue(c);
    const openvdb::Vec3s o = offdiag_ ? offdiag_->getValue(c) : openvdb::Vec3s(0.0f);
    const double q = d[0] * w.x() * w.x() + d[1] * w.y() * w.y() + d[2] * w.z() * w.z() +
                     2 * (o[0] * w.x() * w.y() + o[1] * w.x() * w.z() + o[2] * w.y() * w.z());
    return std::sqrt(std::max(0.0, q));
  }

 private:
  openvdb::FloatGrid::ConstAccessor density_;
  std::optional<openvdb::Vec3SGrid::ConstAccessor> albedo_, diag_, offdiag_, emission_;
};

openvdb::Coord nearestVoxel(const Vec3& index) {
  return openvdb::Coord(int(std::floor(index.x() + 0.5)), int(std::floor(index.y() + 0.5)),
                        int(std::floor(index.z() + 0.5)));
}

// The camera: orthographic, looking along `forward`, framing the index box `lo`..`hi`.
struct OrthoCamera {
  Vec3 forward, right, up, centre;
  double half_width, half_height;
};

OrthoCamera frameBox(const Vec3& lo, const Vec3& hi, const Vec3& view) {
  OrthoCamera cam;
  cam.forward = view.normalized();
  const Vec3 world_up = std::abs(cam.forward.z()) > 0.99 ? Vec3::UnitY() : Vec3::UnitZ();
  cam.right = cam.forward.cross(world_up).normalized();
  cam.up = cam.right.cross(cam.forward);
  cam.centre = 0.5 * (lo + hi);
  cam.half_width = cam.half_height = 0;
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
    cam.half_width = std::max(cam.half_width, std::abs((corner - cam.centre).dot(cam.right)));
    cam.half_height = std::max(cam.half_height, std::abs((corner - cam.centre).dot(cam.up)));
  }
  cam.half_width *= 1.05;
  cam.half_height *= 1.05;
  return cam;
}

// Entry and exit distances of the ray o + t d through the box, or nullopt.
std::optional<std::pair<double, double>> clipToBox(const Vec3& o, const Vec3& d, const Vec3& lo, const Vec3& hi) {
  double t0 = 0, t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const double inv = 1 / d[k];
    double a = (lo[k] - o[k]) * inv, b = (hi[k] - o[k]) * inv;
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  if (t0 >= t1) return std::nullopt;
  return std::pair{t0, t1};
}

}  // namespace

RgbImage renderPreview(const Medium& medium, const PreviewOptions& options, ProgressBar* progress) {
  const openvdb::CoordBBox box = framedVoxels(medium);
  const auto emission = voxelEmission(medium);  // nearest lookups: each voxel's emission and blackbody light
  // The medium's own light over one step (docs/medium.md §3b): E dt, or under pbrt's convention the
  // absorbed share of the step's extinction times Le.
  const bool per_length = !emission || emissionConvention(medium) == EmissionConvention::kCycles;
  const Vec3 lo = Vec3(box.min().x(), box.min().y(), box.min().z()) - Vec3::Constant(0.5);
  const Vec3 hi = Vec3(box.max().x(), box.max().y(), box.max().z()) + Vec3::Constant(0.5);
  // Index space is world space scaled by the voxel size (media have linear, axis-aligned transforms).
  const double voxel_size = medium.transform().voxelSize()[0];
  const OrthoCamera cam = frameBox(lo, hi, options.view);
  const int width = options.width;
  const int height = std::max(1, int(std::lround(width * cam.half_height / cam.half_width)));
  const Vec3 light = -options.light.normalized();  // toward the light
  const double step = 0.5;                          // voxels
  const double reach = (hi - lo).norm();
  RgbImage image(width, height);
  if (progress) progress->setTotal(std::uint64_t(height));

  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    const VoxelLookup voxels(medium, emission.get());
    auto optical_depth = [&](const openvdb::Coord& c, const Vec3& w, double length) {
      const float rho = voxels.density(c);
      return rho > 0 ? rho * voxels.sigma(c, w) * length * voxel_size : 0.0;
    };
    for (int y = rows.begin(); y != rows.end(); ++y) {
      for (int x = 0; x < width; ++x) {
        const double u = (2 * (x + 0.5) / width - 1) * cam.half_width;
        const double v = (1 - 2 * (y + 0.5) / height) * cam.half_height;
        const Vec3 origin = cam.centre + u * cam.right + v * cam.up - reach * cam.forward;
        Vec3 radiance = Vec3::Zero();
        double transmittance = 1;
        if (const auto span = clipToBox(origin, cam.forward, lo, hi)) {
          for (double t = span->first + 0.5 * step; t < span->second && transmittance > 1e-3; t += step) {
            const Vec3 p = origin + t * cam.forward;
            const openvdb::Coord c = nearestVoxel(p);
            const double tau = optical_depth(c, cam.forward, step);
            if (voxels.emits()) {
              const Vec3 e = voxels.emission(c);
              radiance += transmittance * (per_length ? Vec3(e * step * voxel_size)
                                                      : Vec3((1 - std::exp(-tau)) *
                                                             (Vec3::Ones() - voxels.albedo(c)).cwiseProduct(e)));
            }
            if (tau <= 0) continue;
            double shadow = 0;
            for (double s = 1; s <= options.shadow_voxels; s += 1)
              shadow += optical_depth(nearestVoxel(p + s * light), light, 1);
            const double lit = options.ambient + (1 - options.ambient) * std::exp(-shadow);
            const double absorbed = 1 - std::exp(-tau);
            radiance += transmittance * absorbed * lit * voxels.albedo(c);
            transmittance *= 1 - absorbed;
          }
        }
        radiance += transmittance * options.background;
        float* pixel = image.at(x, y);
        for (int k = 0; k < 3; ++k) pixel[k] = float(radiance[k]);
      }
      if (progress) progress->advance();
    }
  });
  if (progress) progress->finish();
  return image;
}

}  // namespace vdbappear
