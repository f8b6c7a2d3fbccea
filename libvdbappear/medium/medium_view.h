#pragma once
// A read-only view of a medium for rendering: point lookups (extinction, scattering function,
// cluster id) and the two tracking primitives a volumetric path tracer needs, over the hierarchical
// majorant (medium/majorant_grid.h). OpenVDB stays behind the implementation: this header is light.
//
// Positions and directions are in world space; distances are world units. A MediumView is shared
// by all threads; each thread makes its own MediumLookup (OpenVDB accessors are not thread-safe).

#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/medium/compact_medium.h"
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/medium/interpolation.h"
#include "libvdbappear/medium/scattering_function.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace vdbappear {

struct Aabb {
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  bool empty() const { return (lo.array() > hi.array()).any(); }
  Vec3 centre() const { return (lo + hi) / 2; }
  Vec3 extent() const { return hi - lo; }
  void extend(const Vec3& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
};

// Which phase function the voxels use, by the precedence of docs/medium.md §7.
enum class PhaseSource { kLobes, kSggx, kTable, kHgGrid, kHgConstant, kIsotropic };
const char* phaseSourceName(PhaseSource source);

// Counts kept by a MediumLookup, summed over threads for reports.
struct TrackingStats {
  std::uint64_t tentative_collisions = 0;  // majorant events (real and null)
  std::uint64_t majorant_violations = 0;   // sigma_t > sigma_maj at an event: must stay 0
  TrackingStats& operator+=(const TrackingStats& o) {
    tentative_collisions += o.tentative_collisions;
    majorant_violations += o.majorant_violations;
    return *this;
  }
};

class MediumLookup;

class MediumView {
 public:
  // Builds the majorant grid and the phase tables; checks what the reader leaves to the tools
  // that use it (lobe S positive definite where the lobe has weight, phase_id within the tables,
  // tables normalisable), throwing MediumError that names the file and the grid.
  // ignore_sggx: render as if the medium had no SGGX grids, base or lobe (S = I, isotropic
  // scattering), for comparisons with renderers that lack SGGX.
  MediumView(MediumPtr medium, Interpolation interpolation, bool ignore_sggx = false);
  // The same view of a medium in its compact form (medium/compact_medium.h): albedo and S read from
  // its records, as half floats.
  MediumView(const CompactMedium& medium, Interpolation interpolation, bool ignore_sggx = false);
  ~MediumView();
  MediumView(const MediumView&) = delete;
  MediumView& operator=(const MediumView&) = delete;

  Aabb worldBounds() const;  // of the cells of the density's active voxels, and of the emission's
  Interpolation interpolation() const;
  PhaseSource phaseSource() const;
  int lobeCount() const;     // lobes per voxel when phaseSource() is kLobes, else 1
  int clusterCount() const;  // 1 + the largest id of the `cluster` grid; 0 without one
  bool emits() const;        // the medium has an `emission` or `blackbody_temperature` grid (docs/medium.md §3b)
  std::size_t majorantVoxelCount() const;
  // An instanced model (docs/modularity.md): the voxels it would have if built; 0 for other media.
  std::uint64_t instancedVoxelCount() const;
  const std::string& source() const;
  bool compact() const;  // made from a CompactMedium

  std::unique_ptr<MediumLookup> lookup() const;

  struct Impl;

 private:
  void build(MediumPtr medium, Interpolation interpolation, bool ignore_sggx);
  std::unique_ptr<Impl> impl_;
};

class MediumLookup {
 public:
  explicit MediumLookup(const MediumView::Impl& view);
  ~MediumLookup();

  // sigma_t(w) at p = rho sqrt(w^T S w), w a unit vector (docs/medium.md §4).
  double extinction(const Vec3& p, const Vec3& w);
  // Albedo and phase function at p, into f (cleared first: a path reuses one function).
  void scattering(const Vec3& p, ScatteringFunction* f);
  // Id of the voxel cluster at p (nearest voxel), -1 where the `cluster` grid is inactive or absent.
  int cluster(const Vec3& p);

  // Delta (Woodcock) tracking: the distance to the first real collision along o + t d, t in
  // (0, t_max), sampled with density sigma_t(t) T(t); nullopt if the ray leaves first
  // (probability T(t_max)). d is a unit vector.
  // emitted (media that emit, docs/medium.md §3b): adds an unbiased estimate of the light the medium
  // emits toward o along the ray up to the collision (or t_max), the integral of T(t) E(t) dt; it
  // draws no random numbers of its own, so the collision is the one sampled without it.
  std::optional<double> sampleCollision(const Vec3& o, const Vec3& d, double t_max, RandomStream& rng,
                                        Rgb* emitted = nullptr);
  // Ratio tracking (Novák et al. 2014): an unbiased estimate of the transmittance T(t_max), with
  // Russian roulette once the estimate falls below 0.1.
  double transmittance(const Vec3& o, const Vec3& d, double t_max, RandomStream& rng);
  // Sum of sigma_maj dt along the ray: the majorant optical depth (for tests and statistics).
  double majorantOpticalDepth(const Vec3& o, const Vec3& d, double t_max);

  const TrackingStats& stats() const { return stats_; }

  struct Accessors;  // OpenVDB accessors, defined in the .cpp

 private:
  const MediumView::Impl& view_;
  std::unique_ptr<Accessors> accessors_;
  TrackingStats stats_;
};

}  // namespace vdbappear
