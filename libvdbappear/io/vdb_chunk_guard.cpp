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

// The compressed bytes of one chunk, empty when there is nothing to decompress.
struct CompressedChunk {
  std::unique_ptr<char[]> bytes;
  Int64 size = 0;
};

// Reads a chunk's stated size and then: an uncompressed chunk (stated size -size <= 0) of exactly
// numBytes, into data; a skipped chunk (data null), by seeking; a compressed chunk of at most
// max_size bytes, returned whole. Every size is checked before anything is read or allocated.
CompressedChunk readChunk(std::istream& is, char* data, size_t numBytes, const char* codec, size_t max_size) {
  CompressedChunk chunk;
  Int64 size = 0;
  is.read(reinterpret_cast<char*>(&size), 8);
  if (!is.good()) OPENVDB_THROW(RuntimeError, "Stream failure reading the size of a " << codec << " chunk");
  if (size <= 0 && (size == std::numeric_limits<Int64>::min() || size_t(-size) != numBytes))
    OPENVDB_THROW(RuntimeError, "Expected to read a " << numBytes << "-byte uncompressed chunk, got a " << -size
                                                      << "-byte chunk");
  if (data == nullptr) {
    is.seekg(size <= 0 ? -size : size, std::ios_base::cur);
    return chunk;
  }
  if (size <= 0) {
    is.read(data, -size);
    if (is.gcount() != -size) OPENVDB_THROW(RuntimeError, "Truncated " << numBytes << "-byte chunk");
    return chunk;
  }
  if (size_t(size) > max_size)
    OPENVDB_THROW(RuntimeError, "A compressed chunk of " << size << " bytes cannot hold " << numBytes << " bytes");
  chunk.bytes.reset(new char[size_t(size)]);
  chunk.size = size;
  is.read(chunk.bytes.get(), size);
  if (is.gcount() != size) OPENVDB_THROW(RuntimeError, "Truncated compressed chunk of " << size << " bytes");
  return chunk;
}

}  // namespace

void bloscFromStream(std::istream& is, char* data, size_t numBytes) {
  // bloscToStream writes a compressed chunk only when it is at most the input plus blosc's overhead.
  const CompressedChunk chunk = readChunk(is, data, numBytes, "blosc", numBytes + BLOSC_MAX_OVERHEAD);
  if (!chunk.bytes) return;
  if (chunk.size < BLOSC_MIN_HEADER_LENGTH)
    OPENVDB_THROW(RuntimeError, "Blosc chunk of " << chunk.size << " bytes has no header");
  size_t nbytes = 0, cbytes = 0, blocksize = 0;
  blosc_cbuffer_sizes(chunk.bytes.get(), &nbytes, &cbytes, &blocksize);
  if (nbytes != numBytes || cbytes > size_t(chunk.size))
    OPENVDB_THROW(RuntimeError, "Blosc chunk header states " << nbytes << " bytes in " << cbytes << ", expected "
                                                             << numBytes << " bytes in at most " << chunk.size);
  const int unpacked = blosc_decompress_ctx(chunk.bytes.get(), data, numBytes, /*numinternalthreads=*/1);
  if (unpacked != Int64(numBytes))
    OPENVDB_THROW(RuntimeError, "Expected to decompress " << numBytes << " bytes, got " << unpacked << " bytes");
}

void unzipFromStream(std::istream& is, char* data, size_t numBytes) {
  const CompressedChunk chunk = readChunk(is, data, numBytes, "zip", compressBound(uLong(numBytes)));
  if (!chunk.bytes) return;
  uLongf unpacked = uLongf(numBytes);
  const int status = uncompress(reinterpret_cast<Bytef*>(data), &unpacked,
                                reinterpret_cast<const Bytef*>(chunk.bytes.get()), uLong(chunk.size));
  if (status != Z_OK || unpacked != numBytes)
    OPENVDB_THROW(RuntimeError, "Expected to decompress " << numBytes << " bytes, got " << unpacked << " bytes");
}

}  // namespace io
}  // namespace OPENVDB_VERSION_NAME
}  // namespace openvdb
