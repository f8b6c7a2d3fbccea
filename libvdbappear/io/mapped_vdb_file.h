#pragma once
// A VDB file mapped into memory and read from any position, by as many streams as there are
// threads: the header, the file's metadata and each grid's descriptor, metadata and transform are
// read at once; what lies after them (a grid's topology and leaf values) is read by the readers that
// visit parts of a grid (io/slab_tree_index.h) through the streams given here, each set up as
// OpenVDB's own reader sets up its stream for the grid (io::Archive::readGrid). Pages read are given
// back to the system on request, so that a file larger than memory is read a part at a time.
// Internal header: includes OpenVDB.

#include <openvdb/io/GridDescriptor.h>
#include <openvdb/io/io.h>
#include <openvdb/openvdb.h>

#include <cstdint>
#include <istream>
#include <memory>
#include <optional>
#include <streambuf>
#include <string>
#include <vector>

namespace vdbappear {

// A stream over bytes in memory that seeks anywhere among them (OpenVDB's readers seek over the
// values they skip); reading past the end fails the stream as a file's end does.
class MemoryStreamBuf : public std::streambuf {
 public:
  MemoryStreamBuf(const char* data, std::size_t size);

 protected:
  pos_type seekoff(off_type offset, std::ios_base::seekdir dir, std::ios_base::openmode which) override;
  pos_type seekpos(pos_type position, std::ios_base::openmode which) override;
};

// One grid's stream: the stream metadata it points to live as long as it does.
struct GridStream {
  GridStream(const char* data, std::size_t size) : buffer(data, size), in(&buffer) {}
  GridStream(const GridStream&) = delete;
  GridStream& operator=(const GridStream&) = delete;
  MemoryStreamBuf buffer;
  std::istream in;
  openvdb::io::StreamMetadata::Ptr metadata;
};

class MappedVdbFile {
 public:
  // Whether the file's tables of compressed leaf sizes are used (kIgnore: as for a file without them,
  // from another writer or an OpenVDB before 6.2).
  enum class LeafSizes { kIfPresent, kIgnore };
  // Maps `path` and reads its header and grid descriptors. MediumError naming the file for one that
  // is not a VDB file or ends before a grid it describes.
  explicit MappedVdbFile(const std::string& path, LeafSizes leaf_sizes = LeafSizes::kIfPresent);
  ~MappedVdbFile();
  MappedVdbFile(const MappedVdbFile&) = delete;
  MappedVdbFile& operator=(const MappedVdbFile&) = delete;

  const std::string& path() const { return path_; }
  const openvdb::MetaMap& metadata() const { return metadata_; }
  std::size_t gridCount() const { return grids_.size(); }
  const openvdb::io::GridDescriptor& descriptor(std::size_t grid) const { return grids_[grid].descriptor; }
  // The grid's name, metadata (the file's leaf sizes left out, as OpenVDB's reader leaves them out)
  // and transform, with an empty tree whose background is the file's (read with its topology's start).
  openvdb::GridBase::ConstPtr header(std::size_t grid) const { return grids_[grid].header; }
  // Why no part of this file's grids can be read on its own (an old file format, a grid that shares
  // another's tree), or nullopt.
  std::optional<std::string> whyNotInParts() const;

  // A stream for the grid, at its topology: tagged with the file's versions, the grid's compression,
  // half floats and background, seekable, throwing on a short read (std::ios_base::failure). `with_leaf_sizes`: the file's table of compressed leaf sizes
  // (DelayedLoadMetadata) goes with it, so that skipping a leaf reads nothing of it; that table is
  // indexed by the leaf's number in the grid (StreamMetadata::leaf), which a stream that starts at a
  // later leaf must set.
  std::unique_ptr<GridStream> stream(std::size_t grid, bool with_leaf_sizes) const;
  // A stream for the grid, tagged as above (without leaf sizes), over bytes read from the file
  // (read): a part's nodes are read into memory of their own, not through the mapping, whose pages
  // the system maps in large runs around each one touched.
  std::unique_ptr<GridStream> stream(std::size_t grid, const std::vector<char>& bytes) const;
  // The file's bytes [from, to) (std::ios_base::failure where it cannot be read).
  void read(std::streamoff from, std::streamoff to, std::vector<char>& bytes) const;
  std::streamoff blockPosition(std::size_t grid) const { return grids_[grid].descriptor.getBlockPos(); }
  std::streamoff endPosition(std::size_t grid) const { return grids_[grid].descriptor.getEndPos(); }

  // Gives back the pages of the file read so far: read again, they come from the page cache.
  void releasePages() const;

 private:
  struct Grid {
    openvdb::io::GridDescriptor descriptor;
    std::uint32_t compression = 0;
    openvdb::GridBase::Ptr header;
    openvdb::MetaMap::Ptr leaf_sizes;  // "file_delayed_load" alone, or null
    std::streamoff topology_position = 0;
  };
  void readGridHeader(Grid& grid) const;
  std::unique_ptr<GridStream> tagged(std::size_t grid, const char* data, std::size_t size, bool with_leaf_sizes) const;

  std::string path_;
  LeafSizes leaf_sizes_;
  int fd_ = -1;
  const char* data_ = nullptr;
  std::size_t size_ = 0;
  std::uint32_t file_version_ = 0;
  openvdb::VersionId library_version_;
  std::uint32_t file_compression_ = 0;
  bool has_grid_offsets_ = false;
  openvdb::MetaMap metadata_;
  std::vector<Grid> grids_;
};

}  // namespace vdbappear
