#pragma once
// Two media the same grid for grid, bit for bit: names, types, transforms, nodes, masks, active and
// inactive values, tiles, and file-level metadata: what their files would hold. For the tests of
// reductions done in parts against the same reduction of the whole.

#include "libvdbappear/io/medium.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cstring>

namespace vdbappear::test {

// The same nodes, masks and values, active or not: what the file would hold.
template <typename GridT>
::testing::AssertionResult identicalTrees(const GridT& expected, const GridT& actual) {
  using ValueT = typename GridT::ValueType;
  if (expected.tree().leafCount() != actual.tree().leafCount())
    return ::testing::AssertionFailure() << expected.getName() << ": " << expected.tree().leafCount() << " leaves vs "
                                         << actual.tree().leafCount();
  if (!(expected.background() == actual.background())) return ::testing::AssertionFailure() << "backgrounds differ";
  for (auto leaf = expected.tree().cbeginLeaf(); leaf; ++leaf) {
    const auto* other = actual.tree().probeConstLeaf(leaf->origin());
    if (!other) return ::testing::AssertionFailure() << expected.getName() << ": no leaf at " << leaf->origin();
    if (leaf->getValueMask() != other->getValueMask())
      return ::testing::AssertionFailure() << expected.getName() << ": masks differ at " << leaf->origin();
    for (openvdb::Index n = 0; n < leaf->SIZE; ++n)
      if (std::memcmp(&leaf->buffer().data()[n], &other->buffer().data()[n], sizeof(ValueT)) != 0)
        return ::testing::AssertionFailure() << expected.getName() << ": values differ at " << leaf->offsetToGlobalCoord(n)
                                             << " (" << (leaf->isValueOn(n) ? "active" : "inactive") << "): "
                                             << leaf->getValue(n) << " vs " << other->getValue(n);
  }
  auto tile = expected.tree().cbeginValueAll();
  tile.setMaxDepth(GridT::TreeType::ValueAllCIter::LEAF_DEPTH - 1);
  for (; tile; ++tile)
    if (!(actual.tree().getValue(tile.getCoord()) == *tile) || actual.tree().isValueOn(tile.getCoord()) != tile.isValueOn())
      return ::testing::AssertionFailure() << expected.getName() << ": tiles differ at " << tile.getCoord();
  return ::testing::AssertionSuccess();
}

inline ::testing::AssertionResult identicalMedia(const Medium& expected, const Medium& actual) {
  const openvdb::GridCPtrVec a = expected.grids(), b = actual.grids();
  if (a.size() != b.size()) return ::testing::AssertionFailure() << a.size() << " grids vs " << b.size();
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i]->getName() != b[i]->getName() || a[i]->type() != b[i]->type())
      return ::testing::AssertionFailure() << "grid " << i << ": " << a[i]->getName() << " vs " << b[i]->getName();
    if (a[i]->transform() != b[i]->transform()) return ::testing::AssertionFailure() << a[i]->getName() << ": transforms differ";
    ::testing::AssertionResult same = ::testing::AssertionSuccess();
    if (auto f = openvdb::gridConstPtrCast<openvdb::FloatGrid>(a[i]))
      same = identicalTrees(*f, *openvdb::gridConstPtrCast<openvdb::FloatGrid>(b[i]));
    else if (auto v = openvdb::gridConstPtrCast<openvdb::Vec3SGrid>(a[i]))
      same = identicalTrees(*v, *openvdb::gridConstPtrCast<openvdb::Vec3SGrid>(b[i]));
    else if (auto n = openvdb::gridConstPtrCast<openvdb::Int32Grid>(a[i]))
      same = identicalTrees(*n, *openvdb::gridConstPtrCast<openvdb::Int32Grid>(b[i]));
    if (!same) return same;
  }
  if (expected.metadata.str() != actual.metadata.str()) return ::testing::AssertionFailure() << "file metadata differ";
  return ::testing::AssertionSuccess();
}

}  // namespace vdbappear::test
