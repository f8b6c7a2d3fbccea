#include "libvdbappear/io/slab_tree_index.h"

#include "libvdbappear/io/medium_slabs.h"

#include <openvdb/io/Compression.h>
#include <openvdb/io/DelayedLoadMetadata.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <map>
#include <memory>
#include <stdexcept>

namespace vdbappear {

namespace {

template <typename T>
void readValue(std::istream& in, T& value) {
  in.read(reinterpret_cast<char*>(&value), sizeof(T));
}

// The origin of slot n of an internal node at `origin`.
template <typename NodeT>
openvdb::Coord slotOrigin(const openvdb::Coord& origin, openvdb::Index n) {
  openvdb::Coord local;
  NodeT::offsetToLocalCoord(n, local);
  return origin + (local << NodeT::ChildNodeType::TOTAL);
}

// A lower internal node's topology, read by OpenVDB's InternalNode::readTopology once walked through
// here first: that reader cannot unwind (a read that throws midway, on a short or damaged file, leaves
// child bits set over slots that hold no child, whose deletion the node's destructor then attempts).
// The walk reads the masks and tile values and seeks over each leaf's value mask on the same stream,
// which throws cleanly, and puts the stream back.
template <typename NodeT>
std::unique_ptr<NodeT> readNodeTopology(std::istream& in, const openvdb::Coord& origin,
                                        const typename NodeT::ValueType& background, bool from_half) {
  const std::streampos start = in.tellg();
  typename NodeT::NodeMaskType child_mask, value_mask;
  child_mask.load(in);
  value_mask.load(in);
  std::vector<typename NodeT::ValueType> values(NodeT::NUM_VALUES);
  openvdb::io::readCompressedValues(in, values.data(), NodeT::NUM_VALUES, value_mask, from_half);
  const std::streamoff leaf_mask_bytes = typename NodeT::ChildNodeType::NodeMaskType().memUsage();
  in.seekg(std::streamoff(child_mask.countOn()) * leaf_mask_bytes, std::ios_base::cur);
  in.seekg(start);
  auto node = std::make_unique<NodeT>(openvdb::PartialCreate(), origin, background);
  node->readTopology(in, from_half);
  return node;
}

}  // namespace

SlabTreeIndex::SlabTreeIndex(const MappedVdbFile& file, std::size_t grid) : file_(&file), grid_(grid) {
  const bool typed = file.header(grid)->apply<SlabGridTypes>([this](const auto& header) { walk(header); });
  if (!typed) throw std::invalid_argument("a grid of values that a part does not hold");
}

// The tree's topology as Tree, RootNode and InternalNode::readTopology read it (file format 222 and
// later), the upper internal nodes by hand and each lower one by OpenVDB, freed once noted; then a
// second stream seeks over each lower node's leaf values as InternalNode::readBuffers does, so that
// where each x slice of them begins is known. With the file's table of leaf sizes the seeks read
// nothing; without it they read each leaf's few header bytes (pages given back as it goes).
template <typename GridT>
void SlabTreeIndex::walk(const GridT& header) {
  using ValueT = typename GridT::ValueType;
  using Node5 = typename GridT::TreeType::RootNodeType::ChildNodeType;
  using Node4 = typename Node5::ChildNodeType;
  const ValueT background = header.background();
  const bool from_half = header.saveFloatAsHalf();
  auto topology = file_->stream(grid_, /*with_leaf_sizes=*/false);
  auto values = file_->stream(grid_, /*with_leaf_sizes=*/true);
  values->in.seekg(file_->blockPosition(grid_));
  std::istream& in = topology->in;

  typename GridT::Ptr tiles;
  auto addTile = [&](const openvdb::CoordBBox& box, const ValueT& value, bool active) {
    if (!active && value == background) return;
    if (!tiles) tiles = GridT::create(background);
    tiles->tree().fill(box, value, active);
    if (active) active_voxels_ += box.volume();
  };

  in.seekg(sizeof(std::int32_t) + sizeof(ValueT), std::ios_base::cur);  // buffer count, background: the header's
  openvdb::Index tile_count = 0, child_count = 0;
  readValue(in, tile_count);
  readValue(in, child_count);
  for (openvdb::Index n = 0; n < tile_count; ++n) {  // root tiles
    openvdb::Coord origin;
    ValueT value{};
    std::uint8_t active = 0;  // a bool in the file: any byte other than 0 reads as on
    in.read(reinterpret_cast<char*>(origin.asPointer()), 3 * sizeof(openvdb::Int32));
    readValue(in, value);
    readValue(in, active);
    if (origin != (origin & ~(int(Node5::DIM) - 1))) throw std::runtime_error("a root tile off its grid of nodes: damaged");
    addTile(openvdb::CoordBBox::createCube(origin, Node5::DIM), value, active != 0);
  }
  std::vector<ValueT> slot_values(Node5::NUM_VALUES);
  for (openvdb::Index c = 0; c < child_count; ++c) {  // the upper internal nodes
    openvdb::Coord origin5;
    in.read(reinterpret_cast<char*>(origin5.asPointer()), 3 * sizeof(openvdb::Int32));
    if (origin5 != (origin5 & ~(int(Node5::DIM) - 1))) throw std::runtime_error("a node off its grid of nodes: damaged");
    typename Node5::NodeMaskType child_mask, value_mask;
    child_mask.load(in);
    value_mask.load(in);
    openvdb::io::readCompressedValues(in, slot_values.data(), Node5::NUM_VALUES, value_mask, from_half);
    for (auto off = child_mask.beginOff(); off; ++off)
      addTile(openvdb::CoordBBox::createCube(slotOrigin<Node5>(origin5, off.pos()), Node4::DIM), slot_values[off.pos()],
              value_mask.isOn(off.pos()));
    for (auto on = child_mask.beginOn(); on; ++on) {  // the lower internal nodes, one at a time
      Node entry;
      entry.origin = slotOrigin<Node5>(origin5, on.pos());
      entry.topology_position = in.tellg();
      const auto node = readNodeTopology<Node4>(in, entry.origin, background, from_half);
      entry.topology_end = in.tellg();
      entry.leaves = node->getChildMask();
      for (auto tile = node->cbeginValueAll(); tile; ++tile)
        addTile(openvdb::CoordBBox::createCube(tile.getCoord(), Node4::ChildNodeType::DIM), *tile, tile.isValueOn());
      for (auto leaf = node->cbeginChildOn(); leaf; ++leaf) active_voxels_ += leaf->onVoxelCount();
      leaf_count_ += entry.leaves.countOn();
      nodes_.push_back(entry);
    }
  }
  if (in.tellg() != file_->blockPosition(grid_)) throw std::runtime_error("its topology does not end where the file says: damaged");
  tiles_ = tiles;

  // The values, node by node (each node's topology read again for its leaves' masks), seeking over
  // each leaf as LeafNode::readBuffers does outside every box. The file's table of leaf sizes, where
  // used, is first made as long as the grid has leaves: OpenVDB indexes it unchecked.
  if (auto table = values->metadata->gridMetadata().getMetadata<openvdb::io::DelayedLoadMetadata>(
          openvdb::GridBase::META_FILE_DELAYED_LOAD)) {
    table->resizeMask(leaf_count_);
    table->resizeCompressedSize(leaf_count_);
  }
  for (Node& entry : nodes_) {
    in.seekg(entry.topology_position);
    const auto node = readNodeTopology<Node4>(in, entry.origin, background, from_half);
    int slice = 0;
    for (auto leaf = node->beginChildOn(); leaf; ++leaf) {
      for (; slice <= int(leaf.pos() >> 8); ++slice) entry.slice_position[slice] = values->in.tellg();
      leaf->readBuffers(values->in, openvdb::CoordBBox(), from_half);
    }
    for (; slice <= 16; ++slice) entry.slice_position[slice] = values->in.tellg();
    if ((&entry - nodes_.data()) % 64 == 63) file_->releasePages();
  }
  if (values->in.tellg() != file_->endPosition(grid_)) throw std::runtime_error("its values do not end where the file says: damaged");
}

void SlabTreeIndex::forEachLeaf(const std::function<void(const openvdb::Coord&)>& f) const {
  for (const Node& node : nodes_)
    for (auto on = node.leaves.beginOn(); on; ++on) {
      const openvdb::Index n = on.pos();  // InternalNode::offsetToLocalCoord for 16^3 slots of 8^3 voxels
      f(node.origin + (openvdb::Coord(int(n >> 8), int((n >> 4) & 15), int(n & 15)) << 3));
    }
}

std::uint64_t SlabTreeIndex::memoryBytes() const {
  return sizeof(*this) + nodes_.capacity() * sizeof(Node) + (tiles_ ? tiles_->memUsage() : 0);
}

void SlabTreeIndex::addTiles(openvdb::GridBase& part, const openvdb::CoordBBox& box) const {
  if (!tiles_) return;
  part.apply<SlabGridTypes>([&](auto& grid) {
    using GridT = std::decay_t<decltype(grid)>;
    const auto& tiles = static_cast<const GridT&>(*tiles_);
    auto tile = tiles.tree().cbeginValueAll();
    tile.setMaxDepth(GridT::TreeType::ValueAllCIter::LEAF_DEPTH - 1);
    for (; tile; ++tile) {
      if (!tile.isValueOn() && *tile == grid.background()) continue;
      openvdb::CoordBBox cut;
      tile.getBoundingBox(cut);
      cut.intersect(box);
      if (!cut.empty()) grid.tree().fill(cut, *tile, tile.isValueOn());
    }
  });
}

openvdb::GridBase::Ptr SlabTreeIndex::readWhole() const {
  openvdb::GridBase::Ptr whole = readLeaves(openvdb::CoordBBox::inf());
  addTiles(*whole, openvdb::CoordBBox::inf());
  return whole;
}

openvdb::GridBase::Ptr SlabTreeIndex::readLeaves(const openvdb::CoordBBox& box) const {
  openvdb::GridBase::Ptr part;
  file_->header(grid_)->apply<SlabGridTypes>([&](const auto& header) { part = readLeavesOf(header, box); });
  return part;
}

// Each node that crosses `box` read as OpenVDB reads it, on a stream of its own: its topology, then
// the values of its leaves in the box's x range, from the first of them on (LeafNode::readBuffers
// reads a leaf inside the box and seeks over one outside it); InternalNode::clip then drops the leaves
// left unread. The nodes that keep a leaf go into the part's tree under upper nodes made for them;
// tiles are the caller's.
template <typename GridT>
openvdb::GridBase::Ptr SlabTreeIndex::readLeavesOf(const GridT& header, const openvdb::CoordBBox& box) const {
  using Node5 = typename GridT::TreeType::RootNodeType::ChildNodeType;
  using Node4 = typename Node5::ChildNodeType;
  std::vector<const Node*> crossing;
  for (const Node& node : nodes_)
    if (box.hasOverlap(openvdb::CoordBBox::createCube(node.origin, Node4::DIM))) crossing.push_back(&node);
  std::vector<std::unique_ptr<Node4>> read(crossing.size());
  const bool from_half = header.saveFloatAsHalf();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, crossing.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
    std::vector<char> topology_bytes, value_bytes;
    for (std::size_t k = r.begin(); k != r.end(); ++k) {
      const Node& entry = *crossing[k];
      file_->read(entry.topology_position, entry.topology_end, topology_bytes);
      auto topology = file_->stream(grid_, topology_bytes);
      auto node = readNodeTopology<Node4>(topology->in, entry.origin, header.background(), from_half);
      const int x0 = int(std::clamp<std::int64_t>((std::int64_t(box.min().x()) - entry.origin.x()) >> 3, 0, 16));
      const int x1 = int(std::clamp<std::int64_t>(((std::int64_t(box.max().x()) - entry.origin.x()) >> 3) + 1, x0, 16));
      file_->read(entry.slice_position[x0], entry.slice_position[x1], value_bytes);
      auto values = file_->stream(grid_, value_bytes);
      for (auto leaf = node->beginChildOn(); leaf; ++leaf) {
        const int x = int(leaf.pos() >> 8);
        if (x >= x1) break;
        if (x >= x0) leaf->readBuffers(values->in, box, from_half);
      }
      if (topology->in.tellg() != std::streamoff(topology_bytes.size()) || values->in.tellg() != std::streamoff(value_bytes.size()))
        throw std::runtime_error("a node's data do not end where its index says: the file changed or is damaged");
      node->clip(box, header.background());
      read[k] = std::move(node);
    }
  });
  auto part = openvdb::gridPtrCast<GridT>(header.copyGridWithNewTree());
  std::map<openvdb::Coord, Node5*> parents;
  for (auto& node : read) {
    if (node->getChildMask().isOff()) continue;  // no leaf in the box: its tiles are the caller's
    const openvdb::Coord origin5 = node->origin() & ~(int(Node5::DIM) - 1);
    Node5*& parent = parents[origin5];
    if (!parent) {
      parent = new Node5(origin5, header.background());
      part->tree().root().addChild(parent);
    }
    parent->addChild(node.release());
  }
  return part;
}

}  // namespace vdbappear
