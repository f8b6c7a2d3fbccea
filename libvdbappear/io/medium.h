#pragma once
// A medium in memory: the grids of docs/medium.md, typed. Includes OpenVDB: keep this header out
// of code that does not touch grids (tools include io/medium_file.h instead).

#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/math/vector.h"

#include <openvdb/openvdb.h>

#include <optional>
#include <string>
#include <vector>

namespace vdbappear {

namespace grid_names {
inline constexpr const char* kDensity = "density";
inline constexpr const char* kAlbedo = "albedo";
inline constexpr const char* kSggxDiag = "sggx_diag";
inline constexpr const char* kSggxOffdiag = "sggx_offdiag";
inline constexpr const char* kHgG = "hg_g";
inline constexpr const char* kEmission = "emission";  // Vec3SGrid, docs/medium.md §3b
inline constexpr const char* kBlackbodyTemperature = "blackbody_temperature";  // FloatGrid, kelvin (§3b)
inline constexpr const char* kCluster = "cluster";
inline constexpr const char* kPhaseId = "phase_id";
inline constexpr const char* kPhaseTable = "phase_table";
inline constexpr const char* kExemplarLayout = "exemplar_layout";  // Int32Grid: (i,j,k) -> exemplar id
inline constexpr const char* kExemplarStacking = "exemplar_stacking";  // Int32Grid: stacked block -> exemplar id
}  // namespace grid_names

// Values of the base grids where a medium has no such grid (docs/medium.md, section 3).
namespace defaults {
inline const openvdb::Vec3s kAlbedo(1.0f);
inline const openvdb::Vec3s kSggxDiag(1.0f);     // S = I: isotropic flakes
inline const openvdb::Vec3s kSggxOffdiag(0.0f);
inline constexpr float kHgG = 0.0f;
}  // namespace defaults

namespace metadata_names {
inline constexpr const char* kSchema = "schema";
inline constexpr const char* kHistory = "history";
inline constexpr const char* kHgG = "hg_g";
inline constexpr int kSchemaVersion = 1;
inline constexpr const char* kEmissionConvention = "emission_convention";  // string: cycles, pbrt (§3b)
inline constexpr const char* kBlackbodyIntensity = "blackbody_intensity";  // float in [0, 1], on blackbody_temperature's grid (§3b)
inline constexpr const char* kExemplarCount = "exemplar_count";  // int N
inline constexpr const char* kExemplarBlock = "exemplar_block";  // vec3i: voxels per block along x,y,z
inline constexpr const char* kExemplarVoxelSize = "exemplar_voxel_size";  // vec3d: the voxels exemplar_block counts
inline constexpr const char* kExemplarKind = "exemplar_kind";  // string: blocks, stacked, model
inline constexpr const char* kExemplarSet = "exemplar_set";    // string: "xxh3:HASH NAME" of the block set
}  // namespace metadata_names

// Grid values to and from the library's double-precision vectors.
inline Vec3 toVec3(const openvdb::Vec3s& v) { return {v[0], v[1], v[2]}; }
inline Vec3 toVec3(const openvdb::Vec3d& v) { return {v[0], v[1], v[2]}; }
inline openvdb::Vec3s toVec3s(const Vec3& v) { return openvdb::Vec3s(float(v.x()), float(v.y()), float(v.z())); }

struct Medium {
  openvdb::FloatGrid::Ptr density;      // rho, required
  openvdb::Vec3SGrid::Ptr albedo;       // null: (1,1,1); a FloatGrid on file is read as grey
  openvdb::Vec3SGrid::Ptr sggx_diag;    // null: S = I
  openvdb::Vec3SGrid::Ptr sggx_offdiag; // null: zeros
  openvdb::FloatGrid::Ptr hg_g;         // null: metadata hg_g, else 0
  openvdb::GridPtrVec other_grids;      // multi-lobe, tabulated phase and unknown grids, as read
  openvdb::MetaMap metadata;            // file-level metadata: history, schema, ...
  std::string source;                   // where it was read from, for messages ("stdin", a path)
  std::vector<GridRule> grid_rules;     // the grid mapping applied as it was read (io/grid_mapping.h)
  std::vector<std::string> read_notes;  // what the reader decided for the user (a preset), a line each

  bool hasSggx() const { return sggx_diag || sggx_offdiag; }
  const openvdb::math::Transform& transform() const { return density->transform(); }

  // Every grid, base grids first, in the order they are written.
  openvdb::GridCPtrVec grids() const;
};

// The grid of other_grids with this name, cast to GridT (null if absent or of another type).
template <typename GridT>
typename GridT::Ptr findOtherGrid(const Medium& medium, const std::string& name) {
  for (const auto& grid : medium.other_grids)
    if (grid->getName() == name) return openvdb::gridPtrCast<GridT>(grid);
  return nullptr;
}

// The world-space box of the cells of the voxels in `voxels` (each voxel's cell reaches half a voxel
// beyond its centre): the corners of the index box grown by 1/2, through the transform.
openvdb::BBoxd worldBoxOfCells(const openvdb::math::Transform& transform, const openvdb::CoordBBox& voxels);

// The index box of the density's active voxels and of the emission's and blackbody temperature's (a
// flame may reach beyond the smoke): what a picture of the medium frames.
openvdb::CoordBBox framedVoxels(const Medium& medium);

// Drops the grids of other_grids with this name.
void removeOtherGrid(Medium& medium, const std::string& name);

// lobe{j}_diag, lobe{j}_offdiag, lobe{j}_fraction, lobe{j}_weight (j = 0, 1, ...): multi-lobe grids.
bool isLobeGridName(const std::string& name);

// exemplar_layout, exemplar_stacking: indexed by block, not by voxel (docs/medium.md, section 6b).
bool isBlockIndexedGridName(const std::string& name);

// The constant HG asymmetry stored as file metadata `hg_g` (float or double), if any.
std::optional<double> hgGMetadata(const openvdb::MetaMap& metadata);

// The `blackbody_intensity` of a blackbody_temperature grid (float or double metadata), if any.
std::optional<double> blackbodyIntensityMetadata(const openvdb::MetaMap& grid);

}  // namespace vdbappear
