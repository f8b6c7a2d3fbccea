#include "libvdbappear/io/spilled_medium.h"

#include "libvdbappear/io/atomic_file.h"
#include "libvdbappear/io/mapped_pages.h"
#include "libvdbappear/io/medium_slabs.h"
#include "libvdbappear/io/medium_validate.h"
#include "libvdbappear/io/scratch_parts.h"
#include "libvdbappear/io/vdb_read_error.h"
#include "libvdbappear/io/vdb_writer.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>
#include <openvdb/io/Compression.h>
#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/io/File.h>
#include <openvdb/io/GridDescriptor.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <filesystem>
#include <map>

namespace vdbappear {

namespace {

// Leaves read between two givings-back of the scratch files' mapped pages.
constexpr std::size_t kLeavesPerRelease = 4096;

}  // namespace

// What the whole's unread leaves refer to: the scratch files, and the grids read from them. A leaf
// read with delayed loading reads its inactive values with its grid's background, which OpenVDB
// finds through a pointer to the root of the tree it was read into: those trees, emptied by the
// merge, must live as long as the leaves.
struct SpilledMedium::Scratch {
  std::vector<std::string> files;
  std::vector<openvdb::GridBase::Ptr> read_back;
};

namespace {

// A grid whose leaves' values are on a scratch file: written, each leaf is read into a copy of its
// own (an unread leaf's copy refers to the file too), written, and freed, so a write holds one leaf
// at a time instead of reading the whole tree into memory.
template <typename TreeT>
class LeafByLeafGrid final : public openvdb::Grid<TreeT> {
 public:
  LeafByLeafGrid(openvdb::Grid<TreeT>& on_scratch, std::shared_ptr<const SpilledMedium::Scratch> scratch)
      : openvdb::Grid<TreeT>(on_scratch, openvdb::ShallowCopy()), scratch_(std::move(scratch)) {}

  const std::vector<std::string>& scratchFiles() const { return scratch_->files; }

  // What the grid takes read into memory: the file's file_mem_bytes, as the whole read writes it.
  openvdb::Index64 memUsage() const override {
    using LeafT = typename TreeT::LeafNodeType;
    constexpr openvdb::Index64 kInCore = sizeof(typename LeafT::Buffer) + LeafT::SIZE * sizeof(typename TreeT::ValueType);
    openvdb::Index64 bytes = this->tree().memUsage();
    for (auto leaf = this->tree().cbeginLeaf(); leaf; ++leaf)
      if (leaf->buffer().isOutOfCore()) bytes += kInCore - leaf->buffer().memUsage();
    return bytes;
  }

  void writeBuffers(std::ostream& os) const override {
    std::size_t written = 0;
    for (auto leaf = this->tree().cbeginLeaf(); leaf; ++leaf) {
      const typename TreeT::LeafNodeType copy(*leaf);
      copy.writeBuffers(os, this->saveFloatAsHalf());
      if (++written % kLeavesPerRelease == 0) releaseMappedPages(scratch_->files);
    }
    releaseMappedPages(scratch_->files);
  }

 private:
  std::shared_ptr<const SpilledMedium::Scratch> scratch_;
};

// Moves `from`'s leaves into `into`, unread, and copies its tiles (the active ones, and inactive ones
// of another value than the background). Not Tree::merge: a node it moves is given the new tree's
// background, which reads every leaf under it into memory.
template <typename TreeT>
void moveLeavesAndTiles(TreeT& from, TreeT& into) {
  std::vector<typename TreeT::LeafNodeType*> leaves;
  from.stealNodes(leaves);  // leaves replaced by inactive background tiles
  for (auto* leaf : leaves) into.addLeaf(leaf);
  auto tile = from.cbeginValueAll();
  tile.setMaxDepth(TreeT::ValueAllCIter::LEAF_DEPTH - 1);
  for (; tile; ++tile)
    if (tile.isValueOn() || !(*tile == from.background()))
      into.addTile(tile.getLevel(), tile.getCoord(), *tile, tile.isValueOn());
  // Its internal nodes, emptied (some 0.8 MB a grid a part at 1024^3, all parts kept): freed. The tree
  // and its root, whose background the moved leaves read through, stay.
  from.clear();
}

// The value types whose grids OpenVDB gives delayed-loading metadata (io::Archive::writeGrid).
using DelayedLoadGridTypes = openvdb::TypeList<openvdb::Int32Grid, openvdb::Int64Grid, openvdb::FloatGrid,
                                               openvdb::DoubleGrid, openvdb::Vec3IGrid, openvdb::Vec3SGrid,
                                               openvdb::Vec3DGrid>;

// A leaf's entry in the file's delayed-loading metadata: how its inactive values are compressed
// and, with blosc or zip, its compressed size and the 8 bytes that say it (what io::Archive::writeGrid
// computes).
template <typename LeafT>
std::pair<std::int8_t, std::int64_t> delayedLoadEntry(const LeafT& leaf, const typename LeafT::ValueType& background,
                                                      bool to_half, std::uint32_t compression) {
  using MaskT = typename LeafT::NodeMaskType;
  const openvdb::io::MaskCompress<typename LeafT::ValueType, MaskT> inactive(leaf.valueMask(), MaskT(), leaf.buffer().data(),
                                                                             background);
  if (!(compression & (openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ZIP))) return {inactive.metadata, 0};
  return {inactive.metadata, std::int64_t(openvdb::io::writeCompressedValuesSize(
                                 leaf.buffer().data(), LeafT::SIZE, leaf.valueMask(), inactive.metadata, to_half, compression)) + 8};
}

// That entry, computed when a part is spilled (its values in memory) for the compression the whole
// is written with, kept in the leaf's transient data (LeafNode::setTransientData: never written to a
// file) until the write, which then reads no leaf for it: set bit, half-float bit, the inactive
// values' compression (3 bits) and the size (24 bits; a leaf of 512 Vec3d is 12 KB).
struct SpilledLeafEntry {
  static constexpr openvdb::Index32 kSet = 1u << 31, kHalf = 1u << 30;
  static std::uint32_t compression() { return openvdb::io::Archive::DEFAULT_COMPRESSION_FLAGS; }  // LeafByLeafArchive's
  static openvdb::Index32 pack(const std::pair<std::int8_t, std::int64_t>& entry, bool half) {
    if (entry.first < 0 || entry.first > 7 || entry.second < 0 || entry.second >= (1 << 24)) return 0;
    return kSet | (half ? kHalf : 0) | (openvdb::Index32(entry.first) << 24) | openvdb::Index32(entry.second);
  }
  static bool holds(openvdb::Index32 tag, bool half) { return (tag & kSet) && bool(tag & kHalf) == half; }
  static std::int8_t mask(openvdb::Index32 tag) { return std::int8_t((tag >> 24) & 7); }
  static std::int64_t size(openvdb::Index32 tag) { return std::int64_t(tag & ((1u << 24) - 1)); }
};

// Each leaf read back from a part's scratch file gets its entry, from the part's leaf in memory.
template <typename GridT>
void tagSpilledLeaves(const GridT& in_memory, GridT& read_back) {
  using LeafT = typename GridT::TreeType::LeafNodeType;
  std::vector<const LeafT*> leaves;
  for (auto leaf = in_memory.tree().cbeginLeaf(); leaf; ++leaf) leaves.push_back(leaf.getLeaf());
  const bool half = in_memory.saveFloatAsHalf();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size()), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      if (LeafT* target = read_back.tree().probeLeaf(leaves[i]->origin()))  // no value is read
        target->setTransientData(SpilledLeafEntry::pack(
            delayedLoadEntry(*leaves[i], in_memory.background(), half, SpilledLeafEntry::compression()), half));
  });
}

// The file's delayed-loading metadata of `grid` (per leaf, in the order the leaves are written),
// from the entries computed when the leaves were spilled, or else from copies of the leaves read a
// few thousand at a time.
template <typename GridT>
void fillDelayedLoadMetadata(openvdb::io::DelayedLoadMetadata& metadata, const GridT& grid, std::uint32_t compression,
                             const std::vector<std::string>& scratch_files) {
  using LeafT = typename GridT::TreeType::LeafNodeType;
  std::vector<const LeafT*> leaves;
  for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) leaves.push_back(leaf.getLeaf());
  if (leaves.empty()) return;
  const bool sized = compression & (openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ZIP);
  const bool half = grid.saveFloatAsHalf();
  metadata.resizeMask(leaves.size());
  if (sized) metadata.resizeCompressedSize(leaves.size());
  const bool tagged = compression == SpilledLeafEntry::compression() &&
                      std::all_of(leaves.begin(), leaves.end(),
                                  [half](const LeafT* leaf) { return SpilledLeafEntry::holds(leaf->transientData(), half); });
  if (tagged) {
    for (std::size_t i = 0; i < leaves.size(); ++i) {
      metadata.setMask(i, SpilledLeafEntry::mask(leaves[i]->transientData()));
      if (sized) metadata.setCompressedSize(i, SpilledLeafEntry::size(leaves[i]->transientData()));
    }
    return;
  }
  for (std::size_t first = 0; first < leaves.size(); first += kLeavesPerRelease) {
    const std::size_t last = std::min(leaves.size(), first + kLeavesPerRelease);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(first, last), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const LeafT copy(*leaves[i]);
        const auto entry = delayedLoadEntry(copy, grid.background(), half, compression);
        metadata.setMask(i, entry.first);
        if (sized) metadata.setCompressedSize(i, entry.second);
      }
    });
    releaseMappedPages(scratch_files);
  }
}

// io::Archive::write for grids whose leaves wait on scratch files: OpenVDB's writer reads every leaf
// of a grid into memory before it writes any (to fill the delayed-loading metadata above); this one
// writes the same file, its metadata made from leaf copies and its leaves written by
// LeafByLeafGrid::writeBuffers. The grids' names are unique (a medium's are), so no suffixes, and
// no grid shares another's tree, so no instances.
class LeafByLeafArchive : public openvdb::io::Archive {
 public:
  void writeStream(std::ostream& os, bool seekable, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& metadata) const {
    auto stream_metadata = openvdb::io::getStreamMetadataPtr(os);
    if (!stream_metadata) {
      stream_metadata = std::make_shared<openvdb::io::StreamMetadata>();
      openvdb::io::setStreamMetadataPtr(os, stream_metadata, /*transfer=*/false);
    }
    openvdb::io::setDataCompression(os, compression());
    openvdb::io::setWriteGridStatsMetadata(os, isGridStatsMetadataEnabled());
    writeHeader(os, seekable);
    metadata.writeMeta(os);
    const std::int32_t count = std::int32_t(grids.size());
    os.write(reinterpret_cast<const char*>(&count), sizeof(count));
    for (const auto& grid : grids) {
      writeOneGrid(*grid, os, seekable);
      openvdb::io::setDataCompression(os, compression());  // a grid may have changed it
    }
  }

 private:
  void writeOneGrid(const openvdb::GridBase& grid, std::ostream& os, bool seekable) const {
    auto file_metadata = openvdb::io::getStreamMetadataPtr(os);
    auto grid_metadata = file_metadata ? std::make_shared<openvdb::io::StreamMetadata>(*file_metadata)
                                       : std::make_shared<openvdb::io::StreamMetadata>();
    grid_metadata->setHalfFloat(grid.saveFloatAsHalf());
    grid_metadata->gridMetadata() = static_cast<const openvdb::MetaMap&>(grid);
    openvdb::io::setStreamMetadataPtr(os, grid_metadata, /*transfer=*/false);

    openvdb::io::GridDescriptor descriptor(grid.getName(), grid.type(), grid.saveFloatAsHalf());
    descriptor.writeHeader(os);
    const std::int64_t offsets_at = seekable ? std::int64_t(os.tellp()) : 0;
    descriptor.writeStreamPos(os);  // a placeholder until the offsets are known
    if (seekable) descriptor.setGridPos(os.tellp());
    setGridCompression(os, grid);

    const auto copy = openvdb::ConstPtrCast<openvdb::GridBase>(grid.copyGrid());  // shares the tree
    copy->insertMeta(openvdb::GridBase::META_FILE_DELAYED_LOAD, openvdb::io::DelayedLoadMetadata());
    auto delayed_load = copy->getMetadata<openvdb::io::DelayedLoadMetadata>(openvdb::GridBase::META_FILE_DELAYED_LOAD);
    const bool filled = grid.apply<DelayedLoadGridTypes>([&](const auto& typed) {
      using TreeT = typename std::decay_t<decltype(typed)>::TreeType;
      const auto* spilled = dynamic_cast<const LeafByLeafGrid<TreeT>*>(&typed);
      fillDelayedLoadMetadata(*delayed_load, typed, compression(),
                              spilled ? spilled->scratchFiles() : std::vector<std::string>{});
    });
    if (!filled) copy->removeMeta(openvdb::GridBase::META_FILE_DELAYED_LOAD);
    if (openvdb::io::getWriteGridStatsMetadata(os)) {
      copy->addStatsMetadata();  // topology only; the copy is a plain grid, so:
      copy->insertMeta(openvdb::GridBase::META_FILE_MEM_BYTES, openvdb::Int64Metadata(grid.memUsage()));
      copy->insertMeta(openvdb::GridBase::META_FILE_COMPRESSION,
                       openvdb::StringMetadata(openvdb::io::compressionToString(openvdb::io::getDataCompression(os))));
    }
    copy->writeMeta(os);
    grid.writeTransform(os);
    grid.writeTopology(os);
    if (seekable) descriptor.setBlockPos(os.tellp());
    grid.writeBuffers(os);
    if (seekable) {
      descriptor.setEndPos(os.tellp());
      os.seekp(offsets_at, std::ios_base::beg);
      descriptor.writeStreamPos(os);
      descriptor.seekToEnd(os);
    }
    openvdb::io::setStreamMetadataPtr(os, file_metadata, /*transfer=*/false);
  }
};

}  // namespace

SpilledMedium::SpilledMedium(const std::string& output)
    : folder_(scratchFolderFor(output)), scratch_(std::make_shared<Scratch>()) {}

void SpilledMedium::add(const Medium& part, const std::string& source) {
  const openvdb::GridCPtrVec grids = part.grids();
  for (const auto& grid : grids) validateGridPart(*grid, source, /*whole=*/false);
  validateAcrossGrids(part, source);

  openvdb::GridCPtrVec voxel_grids;
  for (const auto& grid : grids)
    if (isVoxelIndexed(grid->getName())) voxel_grids.push_back(grid);
  // Written, mapped with delayed loading, and removed (by `scratch`'s destructor) once mapped.
  AtomicFile scratch((std::filesystem::path(folder_) / "vdbappear-part").string());
  writeScratchVdb(scratch.temporaryPath(), voxel_grids);
  std::map<std::string, openvdb::GridBase::Ptr> on_scratch;
  try {
    openvdb::io::File file(scratch.temporaryPath());
    file.setCopyMaxBytes(0);  // map the scratch file itself
    file.open(/*delayLoad=*/true);
    for (auto name = file.beginName(); name != file.endName(); ++name) on_scratch[*name] = file.readGrid(*name);
  } catch (const std::exception& e) {
    throw MediumError(fmt::format("{}: cannot be read back ({})", scratch.temporaryPath(), vdbReadError(e)));
  }
  scratch_->files.push_back(scratch.temporaryPath());
  for (const auto& entry : on_scratch) scratch_->read_back.push_back(entry.second);
  for (const auto& grid : voxel_grids) {  // the write's delayed-loading metadata, while the values are in memory
    const auto found = on_scratch.find(grid->getName());
    if (found == on_scratch.end() || found->second->type() != grid->type()) continue;
    grid->apply<DelayedLoadGridTypes>([&](const auto& typed) {
      tagSpilledLeaves(typed, static_cast<std::decay_t<decltype(typed)>&>(*found->second));
    });
  }
  // Reading the topology back faulted in pages around it (the kernel maps 64 KB around a fault): for
  // small parts, much of the file. They are given back, or a few thousand parts hold their files.
  releaseMappedPages({scratch.temporaryPath()});

  // The grid that stands for `grid` in the whole: its leaves on the scratch file, or `grid` itself.
  const auto spilled = [&](const openvdb::GridBase::ConstPtr& grid) -> openvdb::GridBase::Ptr {
    if (!isVoxelIndexed(grid->getName())) return openvdb::ConstPtrCast<openvdb::GridBase>(grid);
    openvdb::GridBase::Ptr result;
    on_scratch.at(grid->getName())->apply<SlabGridTypes>([&](auto& on_file) {
      using TreeT = typename std::decay_t<decltype(on_file)>::TreeType;
      result = std::make_shared<LeafByLeafGrid<TreeT>>(on_file, scratch_);
    });
    if (!result) throw MediumError(fmt::format("{}: grid '{}' holds {} values, which a part cannot", source,
                                               grid->getName(), grid->valueType()));
    return result;
  };
  if (!whole_) {
    whole_ = std::make_shared<Medium>(part);
    const auto take = [&](auto& role) {
      using GridT = typename std::decay_t<decltype(role)>::element_type;
      if (role) role = openvdb::gridPtrCast<GridT>(spilled(role));
    };
    take(whole_->density);
    take(whole_->albedo);
    take(whole_->sggx_diag);
    take(whole_->sggx_offdiag);
    take(whole_->hg_g);
    for (auto& grid : whole_->other_grids) grid = spilled(grid);
    return;
  }
  // Parts share no leaf: the part's (unread) leaves move into the whole's trees.
  for (const auto& grid : whole_->grids()) {
    if (!isVoxelIndexed(grid->getName())) continue;
    const auto found = on_scratch.find(grid->getName());
    if (found == on_scratch.end() || found->second->type() != grid->type())
      throw MediumError(fmt::format("{}: grid '{}' is not in every part, or not of one type", source, grid->getName()));
    openvdb::ConstPtrCast<openvdb::GridBase>(grid)->apply<SlabGridTypes>([&](auto& whole_grid) {
      using GridT = std::decay_t<decltype(whole_grid)>;
      moveLeavesAndTiles(static_cast<GridT&>(*found->second).tree(), whole_grid.tree());
    });
    on_scratch.erase(found);
  }
  if (!on_scratch.empty())
    throw MediumError(fmt::format("{}: grid '{}' is in a part but not in the first", source, on_scratch.begin()->first));
}

void writeValidatedInParts(const std::string& path, const Medium& medium, const openvdb::MetaMap& metadata) {
  const openvdb::GridCPtrVec grids = medium.grids();
  writeVdbWith(path, [&](std::ostream& os, bool seekable) { LeafByLeafArchive().writeStream(os, seekable, grids, metadata); });
}

bool isValidatedInParts(const Medium& medium) {
  if (!medium.density) return false;
  for (const auto& grid : medium.grids()) {
    if (!isVoxelIndexed(grid->getName())) continue;
    bool spilled = false;
    grid->apply<SlabGridTypes>([&](const auto& typed) {
      using TreeT = typename std::decay_t<decltype(typed)>::TreeType;
      spilled = dynamic_cast<const LeafByLeafGrid<TreeT>*>(&typed) != nullptr;
    });
    if (!spilled) return false;
  }
  return true;
}

}  // namespace vdbappear
