#pragma once
// Fast reads of one 8^3 block of a tree: the raw buffer of its leaf node, or the single tile or
// background value that covers the block. For loops that visit several aligned grids leaf by leaf.

#include <openvdb/openvdb.h>

namespace vdbappear {

template <typename TreeT>
class LeafValues {
 public:
  using ValueT = typename TreeT::ValueType;

  // The block at leaf origin `origin` of a tree or of a value accessor to one.
  template <typename SourceT>
  LeafValues(const SourceT& source, const openvdb::Coord& origin) : leaf_(source.probeConstLeaf(origin)) {
    if (leaf_) {
      data_ = leaf_->buffer().data();
    } else {
      constant_active_ = source.probeValue(origin, constant_);
    }
  }
  // A block of one value everywhere (a grid that is absent).
  explicit LeafValues(const ValueT& constant) : constant_(constant) {}

  ValueT operator[](openvdb::Index offset) const { return data_ ? data_[offset] : constant_; }
  const typename TreeT::LeafNodeType* leaf() const { return leaf_; }
  bool empty() const { return !leaf_ && !constant_active_; }  // no active value in the block
  const ValueT& constant() const { return constant_; }

 private:
  const typename TreeT::LeafNodeType* leaf_ = nullptr;
  const ValueT* data_ = nullptr;
  ValueT constant_{};
  bool constant_active_ = false;
};

}  // namespace vdbappear
