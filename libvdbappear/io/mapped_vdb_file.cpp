#include "libvdbappear/io/mapped_vdb_file.h"

#include "libvdbappear/io/medium_slabs.h"
#include "libvdbappear/io/vdb_read_error.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>
#include <openvdb/io/Archive.h>
#include <openvdb/io/DelayedLoadMetadata.h>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace vdbappear {

MemoryStreamBuf::MemoryStreamBuf(const char* data, std::size_t size) {
  char* begin = const_cast<char*>(data);  // read only: no put area
  setg(begin, begin, begin + size);
}

MemoryStreamBuf::pos_type MemoryStreamBuf::seekoff(off_type offset, std::ios_base::seekdir dir,
                                                   std::ios_base::openmode which) {
  if (!(which & std::ios_base::in)) return pos_type(off_type(-1));
  const off_type from = dir == std::ios_base::beg ? 0 : dir == std::ios_base::cur ? gptr() - eback() : egptr() - eback();
  const off_type target = from + offset;
  if (target < 0 || target > egptr() - eback()) return pos_type(off_type(-1));
  setg(eback(), eback() + target, egptr());
  return pos_type(target);
}

MemoryStreamBuf::pos_type MemoryStreamBuf::seekpos(pos_type position, std::ios_base::openmode which) {
  return seekoff(off_type(position), std::ios_base::beg, which);
}

namespace {

// OpenVDB's header reader and the stream tags it sets, which io::File uses from within.
class HeaderReader : public openvdb::io::Archive {
 public:
  using Archive::inputHasGridOffsets;
  using Archive::readGridCompression;
  using Archive::readGridCount;
  using Archive::readHeader;
  using Archive::setDataCompression;
  using Archive::setFormatVersion;
  using Archive::setLibraryVersion;
};

// The tree's first values (Tree::readTopology, RootNode::readTopology): its buffer count and
// background, for the grid types a part can hold.
void readBackground(openvdb::GridBase& grid, std::istream& in) {
  grid.apply<SlabGridTypes>([&in](auto& typed) {
    using ValueT = typename std::decay_t<decltype(typed)>::ValueType;
    std::int32_t buffer_count = 0;
    in.read(reinterpret_cast<char*>(&buffer_count), sizeof(buffer_count));
    ValueT background{};
    in.read(reinterpret_cast<char*>(&background), sizeof(ValueT));
    if (in) typed.tree().root().setBackground(background, /*updateChildNodes=*/false);
  });
}

}  // namespace

MappedVdbFile::MappedVdbFile(const std::string& path, LeafSizes leaf_sizes) : path_(path), leaf_sizes_(leaf_sizes) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) throw MediumError(fmt::format("{}: cannot be opened ({})", path, std::strerror(errno)));
  struct stat info {};
  if (::fstat(fd, &info) != 0 || info.st_size <= 0) {
    ::close(fd);
    throw MediumError(fmt::format("{}: not a readable VDB file (it is empty)", path));
  }
  size_ = std::size_t(info.st_size);
  void* mapped = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
  if (mapped == MAP_FAILED) {
    ::close(fd);
    throw MediumError(fmt::format("{}: cannot be mapped ({})", path, std::strerror(errno)));
  }
  fd_ = fd;
  data_ = static_cast<const char*>(mapped);
  try {
    // As io::File::open reads a file: header, stream tags, metadata, grid descriptors.
    GridStream file(data_, size_);
    file.in.exceptions(std::ios_base::failbit | std::ios_base::badbit);
    HeaderReader reader;
    reader.readHeader(file.in);
    file.metadata = std::make_shared<openvdb::io::StreamMetadata>();
    file.metadata->setSeekable(true);
    openvdb::io::setStreamMetadataPtr(file.in, file.metadata, /*transfer=*/false);
    reader.setFormatVersion(file.in);
    reader.setLibraryVersion(file.in);
    reader.setDataCompression(file.in);
    file_version_ = reader.fileVersion();
    library_version_ = reader.libraryVersion();
    file_compression_ = reader.compression();
    has_grid_offsets_ = reader.inputHasGridOffsets();
    metadata_.readMeta(file.in);
    if (has_grid_offsets_) {
      const std::int32_t count = HeaderReader::readGridCount(file.in);
      for (std::int32_t i = 0; i < count; ++i) {
        Grid grid;
        grid.descriptor.read(file.in);
        if (grid.descriptor.getEndPos() > std::int64_t(size_) || grid.descriptor.getGridPos() < 0)
          throw MediumError(fmt::format("{}: grid '{}': the file ends inside it: truncated or damaged", path,
                                        grid.descriptor.gridName()));
        grid.descriptor.seekToEnd(file.in);
        grids_.push_back(std::move(grid));
      }
      for (Grid& grid : grids_) readGridHeader(grid);
    }
  } catch (const MediumError&) {
    ::munmap(const_cast<char*>(data_), size_);
    ::close(fd_);
    throw;
  } catch (const std::exception& e) {
    ::munmap(const_cast<char*>(data_), size_);
    ::close(fd_);
    throw MediumError(fmt::format("{}: not a readable VDB file ({})", path, vdbReadError(e)));
  }
}

MappedVdbFile::~MappedVdbFile() {
  ::munmap(const_cast<char*>(data_), size_);
  ::close(fd_);
}

// As io::Archive::readGrid begins a grid: its compression, metadata and transform.
void MappedVdbFile::readGridHeader(Grid& grid) const {
  GridStream stream(data_, size_);
  stream.in.exceptions(std::ios_base::failbit | std::ios_base::badbit);
  stream.metadata = std::make_shared<openvdb::io::StreamMetadata>();
  stream.metadata->setFileVersion(file_version_);
  stream.metadata->setLibraryVersion(library_version_);
  stream.metadata->setCompression(file_compression_);
  stream.metadata->setSeekable(true);
  openvdb::io::setStreamMetadataPtr(stream.in, stream.metadata, /*transfer=*/true);
  grid.descriptor.seekToGrid(stream.in);
  HeaderReader::readGridCompression(stream.in);
  grid.compression = openvdb::io::getDataCompression(stream.in);
  grid.header = openvdb::GridBase::createGrid(grid.descriptor.gridType());
  grid.header->setSaveFloatAsHalf(grid.descriptor.saveFloatAsHalf());
  grid.header->readMeta(stream.in);
  // OpenVDB reads the table of leaf sizes only from files of OpenVDB 6.2 and later (older ones may
  // carry a stale copy), and leaves it out of the grid it gives.
  const auto sizes = (*grid.header)[openvdb::GridBase::META_FILE_DELAYED_LOAD];
  const bool fresh = library_version_.first > 6 || (library_version_.first == 6 && library_version_.second > 1);
  if (sizes && fresh && leaf_sizes_ == LeafSizes::kIfPresent) {
    grid.leaf_sizes = std::make_shared<openvdb::MetaMap>();
    grid.leaf_sizes->insertMeta(openvdb::GridBase::META_FILE_DELAYED_LOAD, *sizes);
  }
  grid.header->removeMeta(openvdb::GridBase::META_FILE_DELAYED_LOAD);
  if (file_version_ >= openvdb::OPENVDB_FILE_VERSION_GRID_INSTANCING) grid.header->readTransform(stream.in);
  if (grid.header->getName().empty()) grid.header->setName(grid.descriptor.gridName());
  grid.topology_position = stream.in.tellg();
  if (!grid.descriptor.isInstance() && file_version_ >= openvdb::OPENVDB_FILE_VERSION_ROOTNODE_MAP)
    readBackground(*grid.header, stream.in);
}

std::optional<std::string> MappedVdbFile::whyNotInParts() const {
  // Parts are read from the node layout of files since OpenVDB 3 (mask compression, format 222),
  // whose grids say where they begin and end.
  if (!has_grid_offsets_) return std::string("it was written as a stream, without the grids' places in the file");
  if (file_version_ < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION)
    return fmt::format("it is written in VDB file format {}, older than the parts reader takes", file_version_);
  for (const Grid& grid : grids_)
    if (grid.descriptor.isInstance())
      return fmt::format("grid '{}' shares the tree of grid '{}'", grid.header->getName(),
                         openvdb::io::GridDescriptor::nameAsString(grid.descriptor.instanceParentName()));
  return std::nullopt;
}

std::unique_ptr<GridStream> MappedVdbFile::stream(std::size_t grid, bool with_leaf_sizes) const {
  auto stream = tagged(grid, data_, size_, with_leaf_sizes);
  stream->in.seekg(grids_[grid].topology_position);
  return stream;
}

std::unique_ptr<GridStream> MappedVdbFile::stream(std::size_t grid, const std::vector<char>& bytes) const {
  return tagged(grid, bytes.data(), bytes.size(), /*with_leaf_sizes=*/false);
}

void MappedVdbFile::read(std::streamoff from, std::streamoff to, std::vector<char>& bytes) const {
  if (from < 0 || to < from || std::size_t(to) > size_) throw std::ios_base::failure("a position outside the file");
  bytes.resize(std::size_t(to - from));
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::pread(fd_, bytes.data() + done, bytes.size() - done, from + std::streamoff(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw std::ios_base::failure(n < 0 ? std::strerror(errno) : "the file ends early");
    done += std::size_t(n);
  }
}

// As io::Archive::readGrid tags a stream for the grid.
std::unique_ptr<GridStream> MappedVdbFile::tagged(std::size_t index, const char* data, std::size_t size,
                                                  bool with_leaf_sizes) const {
  const Grid& grid = grids_[index];
  auto stream = std::make_unique<GridStream>(data, size);
  stream->metadata = std::make_shared<openvdb::io::StreamMetadata>();
  openvdb::io::StreamMetadata& metadata = *stream->metadata;
  metadata.setFileVersion(file_version_);
  metadata.setLibraryVersion(library_version_);
  metadata.setCompression(grid.compression);
  metadata.setSeekable(true);
  metadata.setHalfFloat(grid.descriptor.saveFloatAsHalf());
  metadata.setGridClass(grid.header->getGridClass());
  const void* background = nullptr;  // inactive values a leaf leaves out of the file are its tree's background
  grid.header->apply<SlabGridTypes>([&background](const auto& typed) { background = &typed.tree().background(); });
  metadata.setBackgroundPtr(background);
  if (with_leaf_sizes && grid.leaf_sizes) metadata.gridMetadata() = *grid.leaf_sizes;
  metadata.setLeaf(0);
  openvdb::io::setStreamMetadataPtr(stream->in, stream->metadata, /*transfer=*/true);
  stream->in.exceptions(std::ios_base::failbit | std::ios_base::badbit);
  return stream;
}

void MappedVdbFile::releasePages() const {
  ::madvise(const_cast<char*>(data_), size_, MADV_DONTNEED);
}

}  // namespace vdbappear
