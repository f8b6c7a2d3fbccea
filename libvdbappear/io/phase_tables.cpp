#include "libvdbappear/io/phase_tables.h"

#include "libvdbappear/io/medium.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace vdbappear {

std::vector<std::vector<double>> readPhaseTables(const Medium& medium) {
  const auto grid = findOtherGrid<openvdb::FloatGrid>(medium, grid_names::kPhaseTable);
  if (!grid) return {};
  const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
  int bins = box.max().x() + 1;
  if (const auto meta = medium.metadata.getMetadata<openvdb::Int32Metadata>(kPhaseTableBinsMetadata)) bins = meta->value();
  if (box.empty() || box.min().x() < 0 || box.min().y() < 0 || bins < 1)
    throw MediumError(fmt::format("{}: grid '{}': expected tables at indices (bin >= 0, id >= 0, 0)", medium.source,
                                  grid_names::kPhaseTable));
  auto values = grid->getConstAccessor();
  std::vector<std::vector<double>> tables(box.max().y() + 1, std::vector<double>(bins));
  for (int id = 0; id < int(tables.size()); ++id)
    for (int b = 0; b < bins; ++b) tables[id][b] = values.getValue(openvdb::Coord(b, id, 0));
  return tables;
}

void setPhaseTables(Medium& medium, const std::vector<std::vector<double>>& tables) {
  if (tables.empty()) throw std::invalid_argument("setPhaseTables: no tables");
  const int bins = int(tables[0].size());
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setName(grid_names::kPhaseTable);
  grid->setTransform(medium.density->transform().copy());
  auto values = grid->getAccessor();
  for (int id = 0; id < int(tables.size()); ++id) {
    if (int(tables[id].size()) != bins) throw std::invalid_argument("setPhaseTables: tables differ in bins");
    for (int b = 0; b < bins; ++b) values.setValue(openvdb::Coord(b, id, 0), float(tables[id][b]));
  }
  auto& others = medium.other_grids;
  others.erase(std::remove_if(others.begin(), others.end(),
                              [](const openvdb::GridBase::Ptr& g) { return g->getName() == grid_names::kPhaseTable; }),
               others.end());
  others.push_back(grid);
  medium.metadata.removeMeta(kPhaseTableBinsMetadata);
  medium.metadata.insertMeta(kPhaseTableBinsMetadata, openvdb::Int32Metadata(bins));
}

}  // namespace vdbappear
