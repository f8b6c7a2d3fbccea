#include "libvdbappear/modularity/exemplar_layout.h"

#include "libvdbappear/io/medium.h"
#include "libvdbappear/util/error.h"
#include "libvdbappear/util/json_int.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <fstream>

namespace vdbappear {

namespace {

using nlohmann::json;

constexpr double kMaxLayoutBlocks = 1 << 24;  // 16.7M blocks: a layout of this many ids is 64 MB

// Shapes a 2-D array as one sheet, checks the nesting and the row and sheet lengths.
json sheetsOf(const json& document, const std::string& path) {
  if (!document.is_array() || document.empty())
    throw MediumError(fmt::format("{}: a layout is a non-empty array of rows (or of sheets of rows) of exemplar ids", path));
  const json sheets = document[0].is_array() && !document[0].empty() && document[0][0].is_array() ? document
                                                                                                   : json::array({document});
  for (std::size_t k = 0; k < sheets.size(); ++k) {
    if (!sheets[k].is_array() || sheets[k].size() != sheets[0].size() || sheets[k].empty())
      throw MediumError(fmt::format("{}: sheet {} has {} rows, sheet 0 has {}: every sheet needs as many rows", path, k,
                                    sheets[k].is_array() ? sheets[k].size() : 0, sheets[0].size()));
    for (std::size_t j = 0; j < sheets[k].size(); ++j) {
      const json& row = sheets[k][j];
      if (!row.is_array() || row.empty() || row.size() != sheets[0][0].size())
        throw MediumError(fmt::format("{}: sheet {}, row {}: expected an array of {} exemplar ids", path, k, j,
                                      sheets[0][0].size()));
    }
  }
  return sheets;
}

}  // namespace

ExemplarLayout readLayoutJson(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw MediumError(fmt::format("{}: cannot open the layout file", path));
  json document;
  try {
    document = json::parse(file);
  } catch (const json::exception& e) {
    throw MediumError(fmt::format("{}: not a JSON layout: {}", path, e.what()));
  }
  const json sheets = sheetsOf(document, path);
  const double blocks = double(sheets.size()) * double(sheets[0].size()) * double(sheets[0][0].size());
  if (blocks > kMaxLayoutBlocks)
    throw MediumError(fmt::format("{}: {} blocks, more than {}", path, blocks, kMaxLayoutBlocks));
  ExemplarLayout layout;
  layout.depth = int(sheets.size());
  layout.height = int(sheets[0].size());
  layout.width = int(sheets[0][0].size());
  for (int k = 0; k < layout.depth; ++k)
    for (int j = 0; j < layout.height; ++j)
      for (int i = 0; i < layout.width; ++i) {
        const json& id = sheets[k][j][i];
        try {
          layout.ids.push_back(intOf(id, "id"));
        } catch (const std::invalid_argument&) {
          throw MediumError(fmt::format("{}: block ({},{},{}): '{}' is not an exemplar id (an integer)", path, i, j, k,
                                        id.dump()));
        }
      }
  return layout;
}

ExemplarLayout layoutOfMedium(const Medium& medium) {
  const auto grid = findOtherGrid<openvdb::Int32Grid>(medium, grid_names::kExemplarLayout);
  if (!grid || grid->empty())
    throw MediumError(fmt::format("{}: no grid 'exemplar_layout' (or an empty one): give the layout with --layout",
                                  medium.source));
  openvdb::Coord hi(0);
  for (auto v = grid->cbeginValueOn(); v; ++v) {
    const openvdb::Coord ijk = v.getCoord();
    if (ijk.x() < 0 || ijk.y() < 0 || ijk.z() < 0 || !v.isVoxelValue())
      throw MediumError(fmt::format("{}: grid 'exemplar_layout': a block at ({},{},{}) {}: blocks are single voxels at "
                                    "indices >= 0", medium.source, ijk.x(), ijk.y(), ijk.z(),
                                    v.isVoxelValue() ? "below 0" : "held by a tile"));
    hi.maxComponent(ijk);
  }
  const double blocks = (double(hi.x()) + 1) * (double(hi.y()) + 1) * (double(hi.z()) + 1);
  if (blocks > kMaxLayoutBlocks)
    throw MediumError(fmt::format("{}: grid 'exemplar_layout': spans {}x{}x{} blocks, more than {}", medium.source,
                                  double(hi.x()) + 1, double(hi.y()) + 1, double(hi.z()) + 1, kMaxLayoutBlocks));
  ExemplarLayout layout;
  layout.width = hi.x() + 1;
  layout.height = hi.y() + 1;
  layout.depth = hi.z() + 1;
  layout.ids.assign(std::size_t(layout.width) * layout.height * layout.depth, ExemplarLayout::kEmpty);
  for (auto v = grid->cbeginValueOn(); v; ++v) {
    const openvdb::Coord ijk = v.getCoord();
    layout.ids[std::size_t(ijk.x() + layout.width * (ijk.y() + layout.height * ijk.z()))] = *v;
  }
  return layout;
}

void checkLayoutIds(const ExemplarLayout& layout, int count, const std::string& where) {
  for (int k = 0; k < layout.depth; ++k)
    for (int j = 0; j < layout.height; ++j)
      for (int i = 0; i < layout.width; ++i) {
        const int id = layout.at(i, j, k);
        if (id != ExemplarLayout::kEmpty && (id < 0 || id >= count))
          throw MediumError(fmt::format("{}: block ({},{},{}) names exemplar {}; the block set holds 0..{}", where, i, j,
                                        k, id, count - 1));
      }
}

}  // namespace vdbappear
