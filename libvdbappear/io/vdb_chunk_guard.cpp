// Checked replacements of OpenVDB 10's two chunk readers, openvdb::io::bloscFromStream and
// openvdb::io::unzipFromStream (openvdb/io/Compression.h), which every leaf and node buffer of a VDB
// file passes through.
//
// OpenVDB 10.0, the version Debian 12 ships, reads an uncompressed chunk of the size the file states
// into a buffer of the size the tree expects, and compares the two sizes only afterwards: a file
// that states a larger size overflows the heap (found by scripts/mutation_fuzz.py; later OpenVDB
// releases check first). A compressed chunk's stated size is allocated as it stands, and its blosc
// header is trusted without knowing how many bytes are there. These definitions check every size
// against the expected one and against what the stream holds before anything is read or allocated,
// and otherwise behave as OpenVDB's: same exceptions, same stream positions.
//
// They take effect by symbol interposition: libopenvdb calls both through its PLT, and
// libvdbappear, which exports them (exports.map), comes before libopenvdb in every tool's lookup
// order. tests/cli/bad_input_fuzz_test.cpp replays the files that crashed without them.

#include <openvdb/Exceptions.h>
#include <openvdb/io/Compression.h>

#include <blosc.h>
#include <zlib.h>

#include <istream>
#include <memory>

namespace openvdb {
OPENVDB_USE_VERSION_NAMESPACE
namespace OPENVDB_VERSION_NAME {
namespace io {

namespace {

Int64 readChunkSize(std::istream& is, const char* codec) {
  Int64 size = 0;
  is.read(reinterpret_cast<char*>(&size), 8);
  if (!is.good()) OPENVDB_THROW(RuntimeError, "Stream failure reading the size of a " << codec << " chunk");
  return size;
}

// An uncompressed chunk (stated size -size <= 0): exactly the expected bytes, read or skipped.
void readRawChunk(std::istream& is, char* data, size_t numBytes, Int64 size) {
  if (size == std::numeric_limits<Int64>::min() || size_t(-size) != numBytes)
    OPENVDB_THROW(RuntimeError, "Expected to read a " << numBytes << "-byte uncompressed chunk, got a " << -size
                                                      << "-byte chunk");
  if (data == nullptr) {
    is.seekg(-size, std::ios_base::cur);
    return;
  }
  is.read(data, -size);
  if (is.gcount() != -size) OPENVDB_THROW(RuntimeError, "Truncated " << numBytes << "-byte chunk");
}

// The compressed bytes of a chunk whose stated size is at most max_size.
std::unique_ptr<char[]> readCompressed(std::istream& is, Int64 size, size_t max_size, size_t numBytes) {
  if (size_t(size) > max_size)
    OPENVDB_THROW(RuntimeError, "A compressed chunk of " << size << " bytes cannot hold " << numBytes << " bytes");
  std::unique_ptr<char[]> compressed(new char[size_t(size)]);
  is.read(compressed.get(), size);
  if (is.gcount() != size) OPENVDB_THROW(RuntimeError, "Truncated compressed chunk of " << size << " bytes");
  return compressed;
}

}  // namespace

void bloscFromStream(std::istream& is, char* data, size_t numBytes) {
  const Int64 size = readChunkSize(is, "blosc");
  if (size <= 0) return readRawChunk(is, data, numBytes, size);
  if (data == nullptr) {
    is.seekg(size, std::ios_base::cur);
    return;
  }
  // bloscToStream writes a compressed chunk only when it is at most the input plus blosc's overhead.
  const std::unique_ptr<char[]> compressed = readCompressed(is, size, numBytes + BLOSC_MAX_OVERHEAD, numBytes);
  size_t nbytes = 0, cbytes = 0, blocksize = 0;
  if (size < BLOSC_MIN_HEADER_LENGTH) OPENVDB_THROW(RuntimeError, "Blosc chunk of " << size << " bytes has no header");
  blosc_cbuffer_sizes(compressed.get(), &nbytes, &cbytes, &blocksize);
  if (nbytes != numBytes || cbytes > size_t(size))
    OPENVDB_THROW(RuntimeError, "Blosc chunk header states " << nbytes << " bytes in " << cbytes << ", expected "
                                                             << numBytes << " bytes in at most " << size);
  const int unpacked = blosc_decompress_ctx(compressed.get(), data, numBytes, /*numinternalthreads=*/1);
  if (unpacked != Int64(numBytes))
    OPENVDB_THROW(RuntimeError, "Expected to decompress " << numBytes << " bytes, got " << unpacked << " bytes");
}

void unzipFromStream(std::istream& is, char* data, size_t numBytes) {
  const Int64 size = readChunkSize(is, "zip");
  if (size <= 0) return readRawChunk(is, data, numBytes, size);
  if (data == nullptr) {
    is.seekg(size, std::ios_base::cur);
    return;
  }
  const std::unique_ptr<char[]> compressed = readCompressed(is, size, compressBound(uLong(numBytes)), numBytes);
  uLongf unpacked = uLongf(numBytes);
  const int status = uncompress(reinterpret_cast<Bytef*>(data), &unpacked,
                                reinterpret_cast<const Bytef*>(compressed.get()), uLong(size));
  if (status != Z_OK || unpacked != numBytes)
    OPENVDB_THROW(RuntimeError, "Expected to decompress " << numBytes << " bytes, got " << unpacked << " bytes");
}

}  // namespace io
}  // namespace OPENVDB_VERSION_NAME
}  // namespace openvdb
