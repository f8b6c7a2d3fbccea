// Checked front ends of OpenVDB 10's readers of counts and length-prefixed records in a VDB file's
// headers: io::Archive::readGridCount, io::GridDescriptor::read (a grid's name, type and instance
// parent), MetaMap::readMeta (metadata names, types and values) and math::Transform::read (map
// type names).
//
// OpenVDB 10.0, the version Debian 12 ships, reads such a string (readString, util/Name.h) by
// allocating the length the file states, up to 4 GiB, before it knows whether the bytes are there,
// and a metadata value likewise (StringMetadata, UnknownMetadata, DelayedLoadMetadata). A file of
// 27 KB that states a 1 GiB grid name made vdb_preview run 88 s and take 6.7 GB of memory
// (tests/fuzz/regressions/, found by libFuzzer). Each definition here first walks the records the
// original is about to read, checks every stated size against the bytes the stream holds, then puts
// the stream back and hands it to OpenVDB's own definition (dlsym(RTLD_NEXT)): a sound file is read
// by OpenVDB exactly as before, a file that states more than it holds is refused before anything
// is allocated. And from the metadata on, a read that fails throws rather than letting OpenVDB
// loop on a failed stream (failOnShortReads: the counts of a root node's tiles and children).
//
// They take effect by symbol interposition, like the chunk readers of vdb_chunk_guard.cpp:
// libopenvdb calls all four through its PLT, and libvdbappear, which exports them (exports.map),
// comes first in every tool's lookup order. A stream that cannot seek (a pipe) cannot be walked
// ahead and goes to OpenVDB unchecked; readMediumStream therefore buffers such a stream first.

#include <openvdb/Exceptions.h>
#include <openvdb/MetaMap.h>
#include <openvdb/Metadata.h>
#include <openvdb/io/Archive.h>
#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/io/GridDescriptor.h>
#include <openvdb/io/io.h>
#include <openvdb/math/Maps.h>
#include <openvdb/math/Transform.h>
#include <openvdb/points/StreamCompression.h>

#include <blosc.h>
#include <dlfcn.h>

#include <cstdint>
#include <istream>
#include <limits>
#include <string>

// The definitions replaced, and the names under which dlsym finds OpenVDB's own, are those of 10.0.
static_assert(OPENVDB_LIBRARY_MAJOR_VERSION_NUMBER == 10, "vdb_record_guard.cpp replaces OpenVDB 10's readers");

namespace openvdb {
OPENVDB_USE_VERSION_NAMESPACE
namespace OPENVDB_VERSION_NAME {

namespace {

// Reads ahead of an OpenVDB reader on a seekable stream, checking each stated size against the
// bytes left, and puts the stream back where it found it when it goes out of scope.
class RecordWalk {
 public:
  explicit RecordWalk(std::istream& is) : is_(is) {
    if (!is.good()) return;
    start_ = is.tellg();
    if (start_ < 0) return;  // a pipe
    is.seekg(0, std::ios_base::end);
    const std::streamoff end = is.tellg();
    seekable_ = end >= start_ && is.good();
    end_ = seekable_ ? end : start_;
    pos_ = start_;
    is.clear();
    is.seekg(start_);
  }
  ~RecordWalk() {
    if (start_ < 0) return;
    try {  // a stream with exceptions set (failOnShortReads) could throw here; OpenVDB then fails on it
      is_.clear();
      is_.seekg(start_);
    } catch (const std::ios_base::failure&) {
    }
  }
  RecordWalk(const RecordWalk&) = delete;
  RecordWalk& operator=(const RecordWalk&) = delete;

  bool seekable() const { return seekable_; }
  std::uint64_t left() const { return std::uint64_t(end_ - pos_); }
  std::uint64_t position() const { return std::uint64_t(pos_ - start_); }

  template <typename T>
  T value(const std::string& what) {
    T v{};
    read(reinterpret_cast<char*>(&v), sizeof(T), what);
    return v;
  }
  // A length-prefixed string (writeString/readString of util/Name.h).
  std::string string(const std::string& what) {
    const std::uint32_t size = value<std::uint32_t>("the length of " + what);
    std::string s(checked(size, what), '\0');
    if (size > 0) read(&s[0], size, what);
    return s;
  }
  void skip(std::uint64_t size, const std::string& what) {
    is_.seekg(std::streamoff(checked(size, what)), std::ios_base::cur);
    pos_ += std::streamoff(size);
  }
  void read(char* bytes, std::uint64_t size, const std::string& what) {
    is_.read(bytes, std::streamsize(checked(size, what)));
    if (is_.gcount() != std::streamsize(size)) OPENVDB_THROW(IoError, "Stream failure reading " << what);
    pos_ += std::streamoff(size);
  }
  std::uint64_t checked(std::uint64_t size, const std::string& what) const {
    if (size > left())
      OPENVDB_THROW(IoError, what << " states " << size << " bytes, but the stream holds only " << left() << " more");
    return size;
  }

 private:
  std::istream& is_;
  std::streamoff start_ = -1, end_ = -1, pos_ = -1;
  bool seekable_ = false;
};

// libopenvdb's own definition of a function this file replaces. Members are called as functions
// whose first parameter is `this`, which is how the Itanium C++ ABI passes it.
template <typename Function>
Function openvdbDefinition(const char* mangled_name) {
  void* symbol = dlsym(RTLD_NEXT, mangled_name);
  if (symbol == nullptr) OPENVDB_THROW(RuntimeError, "libopenvdb does not define " << mangled_name);
  return reinterpret_cast<Function>(symbol);
}

// One array of DelayedLoadMetadata (io/DelayedLoadMetadata.cc, readValue): `count` elements, raw
// when `bytes` is 0, else a blosc chunk of `bytes` bytes whose header must state the array's size
// (or blosc's padding of a short array) and at most `bytes` compressed bytes.
void walkDelayedLoadArray(RecordWalk& walk, Index32 bytes, Index32 count, std::size_t element, const std::string& what) {
  const std::uint64_t expected = std::uint64_t(count) * element;
  if (bytes == 0) return walk.skip(expected, what);
  if (bytes < BLOSC_MIN_HEADER_LENGTH) OPENVDB_THROW(IoError, what << ": a blosc chunk of " << bytes << " bytes has no header");
  char header[BLOSC_MIN_HEADER_LENGTH];
  walk.read(header, sizeof header, what);
  walk.skip(bytes - sizeof header, what);
  size_t nbytes = 0, cbytes = 0, blocksize = 0;
  blosc_cbuffer_sizes(header, &nbytes, &cbytes, &blocksize);
  const bool padded = nbytes == std::size_t(compression::BLOSC_PAD_BYTES) && expected <= nbytes;
  if ((nbytes != expected && !padded) || cbytes > bytes)
    OPENVDB_THROW(IoError, what << ": a blosc chunk of " << bytes << " bytes states " << nbytes << " bytes in " << cbytes
                                << ", expected " << expected);
}

// DelayedLoadMetadata::readValue: a leaf count, the leaves' mask compression and, unless marked
// absent, their compressed sizes. Each leaf takes more than a byte of the grid that follows, which
// bounds the count before OpenVDB allocates by it.
void walkDelayedLoad(RecordWalk& walk, Index32 num_bytes, const std::string& what) {
  if (num_bytes == 0) return;
  const std::uint64_t start = walk.position();
  const Index32 count = walk.value<Index32>(what + ": leaf count");
  if (count > walk.left())
    OPENVDB_THROW(IoError, what << " counts " << count << " leaves, but the stream holds only " << walk.left() << " more bytes");
  walkDelayedLoadArray(walk, walk.value<Index32>(what + ": mask bytes"), count, sizeof(io::DelayedLoadMetadata::MaskType),
                       what + ": leaf masks");
  const Index32 size_bytes = walk.value<Index32>(what + ": compressed-size bytes");
  if (size_bytes != std::numeric_limits<Index32>::max())
    walkDelayedLoadArray(walk, size_bytes, count, sizeof(io::DelayedLoadMetadata::CompressedSizeType),
                         what + ": compressed sizes");
  const std::uint64_t read = walk.position() - start;
  if (read < num_bytes) walk.skip(num_bytes - read, what);
}

// A metadata value of `num_bytes` bytes as Metadata::read reads it: a string or an unknown type
// reads all of them, a fixed-size type (TypedMetadata<T>) reads sizeof(T), so the two must agree.
void walkMetadataValue(RecordWalk& walk, const Name& type, Index32 num_bytes, const std::string& what) {
  if (!Metadata::isRegisteredType(type) || type == StringMetadata::staticTypeName()) return walk.skip(num_bytes, what);
  if (type == io::DelayedLoadMetadata::staticTypeName()) return walkDelayedLoad(walk, num_bytes, what);
  const Index32 size = Metadata::createMetadata(type)->size();
  if (num_bytes != size) OPENVDB_THROW(IoError, what << " states " << num_bytes << " bytes, a " << type << " takes " << size);
  walk.skip(size, what);
}

void walkMetaMap(RecordWalk& walk) {
  const Index32 count = walk.value<Index32>("the metadata count");
  for (Index32 i = 0; i < count; ++i) {
    const Name name = walk.string("the name of metadata item " + std::to_string(i));
    const Name type = walk.string("the type of metadata '" + name + "'");
    const Index32 num_bytes = walk.value<Index32>("the size of metadata '" + name + "'");
    walkMetadataValue(walk, type, num_bytes, "metadata '" + name + "' (" + type + ")");
  }
}

void walkGridDescriptor(RecordWalk& walk, std::istream& is) {
  const Name name = walk.string("a grid name");
  walk.string("the type of grid '" + name + "'");
  if (io::getFormatVersion(is) >= OPENVDB_FILE_VERSION_GRID_INSTANCING) walk.string("the instance parent of grid '" + name + "'");
  walk.skip(3 * sizeof(int64_t), "the offsets of grid '" + name + "'");
}

// Transform::read and, for a frustum, NonlinearFrustumMap::read (math/Maps.h), which names a
// second map after its box, taper and depth. Older formats and other maps are of fixed size.
void walkTransform(RecordWalk& walk, std::istream& is) {
  const Name type = walk.string("a transform's map type");
  const uint32_t version = io::getFormatVersion(is);
  if (version < OPENVDB_FILE_VERSION_NEW_TRANSFORM || type != math::NonlinearFrustumMap::mapType()) return;
  const std::uint64_t box_bytes = version < OPENVDB_FILE_VERSION_FLOAT_FRUSTUM_BBOX ? 6 * sizeof(Int32) : 6 * sizeof(double);
  walk.skip(box_bytes + 2 * sizeof(double), "a frustum's box, taper and depth");
  walk.string("a frustum's second map type");
}

// Archive::readGridCount: a stream's grid count, for which io::Stream reserves descriptors (some
// 136 bytes each) before it reads any: 2^31 of them asked for 283 GB (tests/fuzz/regressions/).
// Each grid takes at least its descriptor's name and type lengths and three offsets.
void walkGridCount(RecordWalk& walk) {
  constexpr std::uint64_t kMinGridBytes = 2 * sizeof(std::uint32_t) + 3 * sizeof(int64_t);
  const std::int32_t count = walk.value<std::int32_t>("the grid count");
  if (count < 0 || std::uint64_t(count) * kMinGridBytes > walk.left())
    OPENVDB_THROW(IoError, "the grid count " << count << " does not fit in the " << walk.left() << " bytes the stream holds");
}

// From a VDB's metadata on (the file's, then each grid's, before its transform and tree), a read
// that fails throws (std::ios_base::failure) instead of leaving OpenVDB to go on reading a failed
// stream: a root node that counts 4 billion tiles (RootNode::readTopology) in a stream of 57 KB read
// nothing 4 billion times, 52 s (tests/fuzz/regressions/). A sound file never reads past its end.
void failOnShortReads(std::istream& is) { is.exceptions(is.exceptions() | std::ios_base::failbit | std::ios_base::badbit); }

// Runs `walk_records` over the records ahead of `is` where the stream can seek, then puts it back.
template <typename WalkRecords>
void walkAhead(std::istream& is, WalkRecords walk_records) {
  RecordWalk walk(is);
  if (walk.seekable()) walk_records(walk);
}

}  // namespace

void MetaMap::readMeta(std::istream& is) {
  walkAhead(is, walkMetaMap);
  using Read = void (*)(MetaMap*, std::istream&);
  static const Read read = openvdbDefinition<Read>("_ZN7openvdb5v10_07MetaMap8readMetaERSi");
  read(this, is);
  failOnShortReads(is);
}

namespace io {

int32_t Archive::readGridCount(std::istream& is) {
  walkAhead(is, walkGridCount);
  using Read = int32_t (*)(std::istream&);
  static const Read read = openvdbDefinition<Read>("_ZN7openvdb5v10_02io7Archive13readGridCountERSi");
  return read(is);
}

GridBase::Ptr GridDescriptor::read(std::istream& is) {
  walkAhead(is, [&is](RecordWalk& walk) { walkGridDescriptor(walk, is); });
  using Read = GridBase::Ptr (*)(GridDescriptor*, std::istream&);
  static const Read read = openvdbDefinition<Read>("_ZN7openvdb5v10_02io14GridDescriptor4readERSi");
  return read(this, is);
}

}  // namespace io

namespace math {

void Transform::read(std::istream& is) {
  walkAhead(is, [&is](RecordWalk& walk) { walkTransform(walk, is); });
  using Read = void (*)(Transform*, std::istream&);
  static const Read read = openvdbDefinition<Read>("_ZN7openvdb5v10_04math9Transform4readERSi");
  read(this, is);
}

}  // namespace math

}  // namespace OPENVDB_VERSION_NAME
}  // namespace openvdb
