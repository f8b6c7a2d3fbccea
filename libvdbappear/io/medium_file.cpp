#include "libvdbappear/io/medium_file.h"

#include "libvdbappear/io/mapped_grids.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_of_grids.h"
#include "libvdbappear/io/medium_validate.h"
#include "libvdbappear/io/vdb_read_error.h"
#include "libvdbappear/io/spilled_medium.h"
#include "libvdbappear/io/vdb_writer.h"
#include "libvdbappear/util/error.h"

#include <openvdb/io/Stream.h>
#include <openvdb/tree/LeafManager.h>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <unistd.h>

namespace vdbappear {

namespace {

// Opens `file` and lists its grids' names, checked; MediumError naming `path` for a file OpenVDB
// cannot read.
std::vector<std::string> openGridNames(openvdb::io::File& file, const std::string& path) {
  std::vector<std::string> names;
  try {
    file.open(/*delayLoad=*/false);
    for (auto name = file.beginName(); name != file.endName(); ++name) names.push_back(*name);
  } catch (const std::exception& e) {
    throw MediumError(fmt::format("{}: not a readable VDB file ({})", path, vdbReadError(e)));
  }
  std::vector<std::string> base_names;  // OpenVDB lists a repeated name as "name[0]", "name[1]", ...
  for (const auto& name : names)
    base_names.push_back(openvdb::io::GridDescriptor::stripSuffix(openvdb::io::GridDescriptor::stringAsUniqueName(name)));
  checkGridNames(base_names, path);
  return names;
}

constexpr const char* kStdio = "-";

struct VdbContents {
  openvdb::GridPtrVec grids;
  openvdb::MetaMap::Ptr metadata;
};

// Grids are read in parallel, one io::File per grid (decompression dominates reading), and each
// is checked on its own (validateGrid) as soon as it is read. Of several bad grids, the first by
// name is reported.
VdbContents readVdbFile(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) throw MediumError(fmt::format("{}: no such file", path));
  if (std::filesystem::is_directory(path, error)) throw MediumError(fmt::format("{}: is a directory", path));
  VdbContents contents;
  std::vector<std::string> names;
  {
    openvdb::io::File file(path);
    names = openGridNames(file, path);
    contents.metadata = file.getMetadata();
  }

  contents.grids.resize(names.size());
  std::vector<std::exception_ptr> failures(names.size());
  tbb::parallel_for(std::size_t(0), names.size(), [&](std::size_t i) {
    try {
      try {
        openvdb::io::File file(path);
        file.open(/*delayLoad=*/false);  // no lazy loading: a truncated grid fails in readGrid, not later
        contents.grids[i] = file.readGrid(names[i]);
      } catch (const std::exception& e) {
        throw MediumError(fmt::format("{}: grid '{}': cannot be read ({})", path, names[i], vdbReadError(e)));
      }
      validateGrid(*contents.grids[i], path);
    } catch (...) {
      failures[i] = std::current_exception();
    }
  });
  for (const auto& failure : failures)
    if (failure) std::rethrow_exception(failure);
  return contents;
}

// OpenVDB's header readers are checked against the bytes a stream holds only where it can seek
// (io/vdb_record_guard.cpp), so a pipe is read whole first: the medium is held in memory anyway, at
// many times its size in the file.
VdbContents readVdbStream(std::istream& in, const std::string& source) {
  std::stringstream buffered;
  std::istream* seekable = &in;
  if (in.tellg() < 0) {
    buffered << in.rdbuf();
    buffered.clear();  // an empty stream sets failbit; OpenVDB says what is wrong with it
    seekable = &buffered;
  }
  VdbContents contents;
  const std::ios_base::iostate exceptions = seekable->exceptions();  // the reader sets some (vdb_record_guard.cpp)
  try {
    openvdb::io::Stream stream(*seekable, /*delayLoad=*/false);
    contents = {*stream.getGrids(), stream.getMetadata()};
  } catch (const std::exception& e) {
    seekable->exceptions(exceptions);
    throw MediumError(fmt::format("{}: not a readable VDB stream ({})", source, vdbReadError(e)));
  }
  seekable->exceptions(exceptions);
  std::vector<std::string> names;
  for (const auto& grid : contents.grids) names.push_back(grid->getName());
  checkGridNames(names, source);
  return contents;
}

// A grey albedo or emission (FloatGrid) as RGB: the same topology, each value repeated in three channels.
openvdb::Vec3SGrid::Ptr greyToRgb(const openvdb::FloatGrid& grey) {
  auto rgb = openvdb::Vec3SGrid::create(openvdb::Vec3s(grey.background()));
  rgb->setName(grey.getName());
  rgb->setTransform(grey.transform().copy());
  rgb->tree().topologyUnion(grey.tree());
  openvdb::tree::LeafManager<openvdb::Vec3STree> leaves(rgb->tree());
  leaves.foreach([&grey](openvdb::Vec3STree::LeafNodeType& leaf, std::size_t) {
    const auto* source = grey.tree().probeConstLeaf(leaf.origin());  // same topology: present
    for (openvdb::Index n = 0; n < leaf.SIZE; ++n) leaf.setValueOnly(n, openvdb::Vec3s(source->getValue(n)));
  });
  auto tile = rgb->tree().beginValueOn();
  tile.setMaxDepth(openvdb::Vec3STree::ValueOnIter::LEAF_DEPTH - 1);
  for (; tile; ++tile) tile.setValue(openvdb::Vec3s(grey.tree().getValue(tile.getCoord())));
  return rgb;
}

template <typename GridT>
typename GridT::Ptr typedGrid(const openvdb::GridBase::Ptr& grid, const std::string& source) {
  auto typed = openvdb::gridPtrCast<GridT>(grid);
  if (!typed)
    throw MediumError(fmt::format("{}: grid '{}': holds {} values, expected {}", source, grid->getName(),
                                  grid->valueType(), openvdb::typeNameAsString<typename GridT::ValueType>()));
  return typed;
}

MediumPtr toMedium(VdbContents contents, const std::string& source) {
  namespace names = grid_names;
  auto medium = std::make_shared<Medium>();
  medium->source = source;
  if (contents.metadata) medium->metadata = *contents.metadata;
  for (auto& grid : contents.grids) {
    const std::string name = grid->getName();
    if (name == names::kDensity) {  // names are unique: checked when read
      medium->density = typedGrid<openvdb::FloatGrid>(grid, source);
    } else if (name == names::kAlbedo) {
      auto grey = openvdb::gridPtrCast<openvdb::FloatGrid>(grid);
      medium->albedo = grey ? greyToRgb(*grey) : typedGrid<openvdb::Vec3SGrid>(grid, source);
    } else if (name == names::kSggxDiag) {
      medium->sggx_diag = typedGrid<openvdb::Vec3SGrid>(grid, source);
    } else if (name == names::kSggxOffdiag) {
      medium->sggx_offdiag = typedGrid<openvdb::Vec3SGrid>(grid, source);
    } else if (name == names::kHgG) {
      medium->hg_g = typedGrid<openvdb::FloatGrid>(grid, source);
    } else if (auto grey = openvdb::gridPtrCast<openvdb::FloatGrid>(grid); grey && name == names::kEmission) {
      medium->other_grids.push_back(greyToRgb(*grey));
    } else {
      medium->other_grids.push_back(grid);
    }
  }
  return medium;
}

// The medium of a file's validated grids: mapped (io/mapped_grids.h), sorted into roles, checked
// across grids, with the rules applied and the reader's notes.
MediumPtr mappedMedium(VdbContents contents, const GridMapping& mapping, const std::string& source) {
  MappedGrids mapped = applyGridMapping(contents.grids, mapping, source);
  contents.grids = std::move(mapped.grids);
  MediumPtr medium = toMedium(std::move(contents), source);
  validateAcrossGrids(*medium, source);
  medium->grid_rules = std::move(mapped.applied);
  medium->read_notes = std::move(mapped.notes);
  return medium;
}

}  // namespace

void checkGridNames(std::vector<std::string> names, const std::string& source) {
  std::sort(names.begin(), names.end());
  if (!names.empty() && names.front().empty()) throw MediumError(fmt::format("{}: a grid has no name", source));
  const auto repeated = std::adjacent_find(names.begin(), names.end());
  if (repeated != names.end())
    throw MediumError(fmt::format("{}: grid '{}': appears more than once", source, *repeated));
}


MediumPtr mediumOfGrids(openvdb::GridPtrVec grids, openvdb::MetaMap::Ptr metadata, const GridMapping& mapping,
                        const std::string& source) {
  return mappedMedium({std::move(grids), std::move(metadata)}, mapping, source);
}

MediumPtr readMedium(const std::string& path, const GridMapping& mapping) {
  openvdb::initialize();
  if (path == kStdio) {
    if (isatty(STDIN_FILENO)) throw MediumError("stdin: is a terminal, expected a VDB stream (pipe or redirect one)");
    return readMediumStream(std::cin, "stdin", mapping);
  }
  return mappedMedium(readVdbFile(path), mapping, path);  // readVdbFile validates each grid as it is read
}

const std::vector<std::string>& readNotes(const Medium& medium) { return medium.read_notes; }

MediumPtr readMediumStream(std::istream& in, const std::string& source, const GridMapping& mapping) {
  openvdb::initialize();
  VdbContents contents = readVdbStream(in, source);
  for (const auto& grid : contents.grids) validateGrid(*grid, source);
  return mappedMedium(std::move(contents), mapping, source);
}

void checkWritable(const std::string& path) {
  if (path == kStdio) {
    if (isatty(STDOUT_FILENO)) throw MediumError("stdout: is a terminal; redirect or pipe the VDB stream");
    return;
  }
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) throw MediumError(fmt::format("{}: is a directory", path));
  const std::filesystem::path folder = std::filesystem::absolute(path).parent_path();
  if (!std::filesystem::is_directory(folder, error))
    throw MediumError(fmt::format("{}: no such folder '{}'", path, folder.string()));
  if (access(folder.c_str(), W_OK) != 0) throw MediumError(fmt::format("{}: folder is not writable", path));
}

void writeMedium(const Medium& medium, const std::string& path, const std::string& history_line) {
  openvdb::initialize();
  checkWritable(path);
  try {
    if (!isValidatedInParts(medium)) validateMedium(medium, path == kStdio ? "stdout" : path);
  } catch (const MediumError& e) {
    throw MediumError(fmt::format("not written, the result is not a valid medium: {}", e.what()));
  }
  openvdb::MetaMap metadata = medium.metadata;
  std::string history;
  if (auto previous = metadata.getMetadata<openvdb::StringMetadata>(metadata_names::kHistory))
    history = previous->value() + "\n";
  metadata.insertMeta(metadata_names::kHistory, openvdb::StringMetadata(history + history_line));
  metadata.insertMeta(metadata_names::kSchema, openvdb::Int32Metadata(metadata_names::kSchemaVersion));
  if (isValidatedInParts(medium)) writeValidatedInParts(path, medium, metadata);  // leaf by leaf, from disk
  else writeVdb(path, medium.grids(), metadata);
}

}  // namespace vdbappear
