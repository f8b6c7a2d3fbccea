#include "libvdbappear/optimize/lobe_medium.h"

#include "libvdbappear/downsample/coarse_transform.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>

#include <cmath>

namespace vdbappear {

namespace {

std::string lobeGridName(int j, const char* what) { return fmt::format("lobe{}_{}", j, what); }

}  // namespace

LobeMediumLayout inspectLobeMedium(const Medium& medium) {
  const std::string& source = medium.source;
  if (medium.metadata["weight_factors"])
    throw MediumError(fmt::format("{}: already holds optimised lobe weights (metadata 'weight_factors'); give the "
                                  "output of vdb_lobe_cluster", source));
  LobeMediumLayout layout;
  std::vector<openvdb::Vec3SGrid::Ptr> weights;
  while (auto w = findOtherGrid<openvdb::Vec3SGrid>(medium, lobeGridName(layout.lobes, "weight"))) {
    weights.push_back(w);
    ++layout.lobes;
  }
  if (layout.lobes == 0)
    throw MediumError(fmt::format("{}: no grid 'lobe0_weight': not a multi-lobe medium (give the output of "
                                  "vdb_lobe_cluster)", source));
  const auto cluster = findOtherGrid<openvdb::Int32Grid>(medium, grid_names::kCluster);
  if (!cluster)
    throw MediumError(fmt::format("{}: no grid 'cluster': the weight factors are per voxel cluster (give the output "
                                  "of vdb_lobe_cluster)", source));
  for (auto id = cluster->cbeginValueOn(); id; ++id) {
    if (*id < 0) throw MediumError(fmt::format("{}: grid 'cluster': negative cluster id {}", source, *id));
    layout.clusters = std::max(layout.clusters, *id + 1);
  }
  if (layout.clusters == 0) throw MediumError(fmt::format("{}: grid 'cluster': no active voxel", source));
  layout.naive_weights.resize(layout.clusters);
  std::vector<openvdb::Vec3SGrid::ConstAccessor> accessors;
  for (const auto& w : weights) accessors.push_back(w->getConstAccessor());
  auto density = medium.density->getConstAccessor();
  for (auto id = cluster->cbeginValueOn(); id; ++id) {
    const openvdb::Coord ijk = id.getCoord();
    float rho = 0;
    if (!density.probeValue(ijk, rho) || !(rho > 0)) continue;
    std::vector<float>& out = layout.naive_weights[*id];
    for (auto& a : accessors) {
      openvdb::Vec3s w(0.0f);
      a.probeValue(ijk, w);
      out.insert(out.end(), {w[0], w[1], w[2]});
      layout.coloured |= w[0] != w[1] || w[1] != w[2];
    }
  }
  return layout;
}

namespace {

bool sameMap(const openvdb::math::Transform& a, const openvdb::math::Transform& b) {
  const openvdb::Mat4d A = a.baseMap()->getAffineMap()->getMat4(), B = b.baseMap()->getAffineMap()->getMat4();
  double scale = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) scale = std::max(scale, std::abs(A(i, j)));
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (!(std::abs(A(i, j) - B(i, j)) <= 1e-9 * scale)) return false;
  return true;
}

double mass(const openvdb::FloatGrid& density) {
  double sum = 0;
  for (auto v = density.cbeginValueOn(); v; ++v) sum += double(*v) * double(v.getVoxelCount());
  return sum;
}

}  // namespace

int downsamplingFactor(const Medium& full, const Medium& lobes) {
  if (!full.transform().isLinear() || !lobes.transform().isLinear())
    throw MediumError(fmt::format("{}: grid 'density': a linear transform is needed", full.transform().isLinear() ? lobes.source : full.source));
  int factor = 0;
  for (int F = 2; F <= 64 && !factor; ++F)
    if (sameMap(*coarseTransform(full.transform(), F, full.source), lobes.transform())) factor = F;
  if (!factor)
    throw MediumError(fmt::format("{}: grid 'density': its transform is not {}'s coarsened by a factor 2..64: "
                                  "LOBES must be vdb_lobe_cluster's output on FULL", lobes.source, full.source));
  const double fine = mass(*full.density), coarse = mass(*lobes.density) * factor * factor * factor;
  if (!(std::abs(fine - coarse) <= 1e-4 * std::max(fine, coarse)))
    throw MediumError(fmt::format("{}: grid 'density': not downsampled from {}: its mass is {:.6g} x {}^3, {}'s is "
                                  "{:.6g} (Eq. 6 keeps it)", lobes.source, full.source, mass(*lobes.density), factor,
                                  full.source, fine));
  return factor;
}

MediumPtr applyWeightFactors(const Medium& lobes, const WeightFactors& factors, const nlohmann::json& record) {
  auto out = std::make_shared<Medium>(lobes);  // shares the grids; the weight grids are replaced below
  const auto cluster = findOtherGrid<openvdb::Int32Grid>(lobes, grid_names::kCluster);
  if (!cluster) throw MediumError(fmt::format("{}: no grid 'cluster'", lobes.source));
  for (auto& grid : out->other_grids) {
    int j = -1;
    if (std::sscanf(grid->getName().c_str(), "lobe%d_weight", &j) != 1 || grid->getName() != lobeGridName(j, "weight"))
      continue;
    if (j < 0 || j >= factors.lobes()) throw MediumError(fmt::format("{}: grid '{}': no weight factor for this slot", lobes.source, grid->getName()));
    auto weights = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grid)->deepCopy();
    auto ids = cluster->getConstAccessor();
    for (auto leaf = weights->tree().beginLeaf(); leaf; ++leaf)
      for (auto v = leaf->beginValueOn(); v; ++v) {
        int k = -1;
        if (!ids.probeValue(v.getCoord(), k) || k < 0 || k >= factors.clusters()) continue;
        const Rgb scale = factors.s(k) * factors.w(k, j);
        const openvdb::Vec3s w = *v;
        v.setValue(openvdb::Vec3s(float(w[0] * scale[0]), float(w[1] * scale[1]), float(w[2] * scale[2])));
      }
    grid = weights;
  }
  out->metadata = lobes.metadata;  // a copy, so that LOBES keeps its own
  out->metadata.removeMeta("weight_factors");
  out->metadata.insertMeta("weight_factors", openvdb::StringMetadata(record.dump()));
  return out;
}

namespace {

// The largest effective albedo sum_j W_ij^c of cluster k's voxels, per channel.
Rgb largestEffectiveAlbedo(const LobeMediumLayout& layout, const WeightFactors& factors, int k) {
  const std::vector<float>& B = layout.naive_weights[k];
  const int m = layout.lobes;
  Rgb largest = Rgb::Zero();
  for (std::size_t v = 0; v < B.size(); v += 3 * m) {
    Rgb albedo = Rgb::Zero();
    for (int j = 0; j < m && j < factors.lobes(); ++j)
      albedo += Rgb(B[v + 3 * j], B[v + 3 * j + 1], B[v + 3 * j + 2]) * factors.s(k) * factors.w(k, j);
    largest = largest.max(albedo);
  }
  return largest;
}

}  // namespace

bool isFeasible(const LobeMediumLayout& layout, const WeightFactors& factors) {
  for (int k = 0; k < factors.clusters() && k < int(layout.naive_weights.size()); ++k)
    if ((largestEffectiveAlbedo(layout, factors, k) > 1).any()) return false;
  return true;
}

bool constrainFactors(const LobeMediumLayout& layout, WeightFactors& factors) {
  for (int k = 0; k < factors.clusters(); ++k)
    for (int j = 0; j < factors.lobes(); ++j) factors.w(k, j) = factors.w(k, j).max(kMinFactor);
  if (factors.mode() == ColourMode::kColourScales)
    for (int k = 0; k < factors.clusters(); ++k) factors.s(k) = factors.s(k).max(kMinFactor);
  bool limited = false;
  for (int k = 0; k < factors.clusters() && k < int(layout.naive_weights.size()); ++k) {
    const Rgb largest = largestEffectiveAlbedo(layout, factors, k);
    if (!(largest > 1).any()) continue;
    limited = true;
    const Rgb excess = largest.max(1.0);
    if (factors.mode() == ColourMode::kColourScales) {
      factors.s(k) /= excess;
    } else {
      const Rgb divide = factors.mode() == ColourMode::kPerChannel ? excess : Rgb(Rgb::Constant(excess.maxCoeff()));
      for (int j = 0; j < factors.lobes(); ++j) factors.w(k, j) /= divide;
    }
  }
  factors.normaliseColourScales();  // keeps every s_k w_kj
  return limited;
}

}  // namespace vdbappear
