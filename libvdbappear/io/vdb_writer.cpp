#include "libvdbappear/io/vdb_writer.h"

#include "libvdbappear/io/atomic_file.h"
#include "libvdbappear/util/error.h"

#include <openvdb/io/Archive.h>

#include <fmt/format.h>

#include <fstream>
#include <iostream>

namespace vdbappear {

namespace {

// OpenVDB's archive writer with the compression asked for.
class CompressingArchive : public openvdb::io::Archive {
 public:
  explicit CompressingArchive(std::uint32_t compression) { setCompression(compression); }
  void writeTo(std::ostream& os, bool seekable, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& metadata) const {
    Archive::write(os, grids, seekable, metadata);
  }
};

// `write` on a stream of our own, so that a failed write (a full disk) is noticed instead of a
// truncated file being renamed into place. Errors name `target`, the file the user asked for.
void writeChecked(const std::string& file, const std::string& target, const VdbStreamWriter& write) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw MediumError(fmt::format("{}: cannot open a temporary file beside it for writing", target));
  try {
    write(out, /*seekable=*/true);
  } catch (const MediumError&) {
    throw;
  } catch (const std::exception& e) {
    throw MediumError(fmt::format("{}: cannot write ({})", target, e.what()));
  }
  out.close();
  if (!out) throw MediumError(fmt::format("{}: write failed (disk full?)", target));
}

}  // namespace

void writeVdbWith(const std::string& path, const VdbStreamWriter& write) {
  if (path == "-") {
    try {
      write(std::cout, /*seekable=*/false);
      std::cout.flush();
    } catch (const std::exception& e) {
      throw MediumError(fmt::format("stdout: cannot write the VDB stream ({})", e.what()));
    }
    if (!std::cout) throw MediumError("stdout: write failed");
    return;
  }
  AtomicFile output(path);
  writeChecked(output.temporaryPath(), path, write);
  output.commit();
}

void writeVdb(const std::string& path, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& metadata) {
  writeVdbWith(path, [&](std::ostream& os, bool seekable) {
    CompressingArchive(openvdb::io::Archive::DEFAULT_COMPRESSION_FLAGS).writeTo(os, seekable, grids, metadata);
  });
}

void writeScratchVdb(const std::string& file, const openvdb::GridCPtrVec& grids) {
  writeChecked(file, file, [&](std::ostream& os, bool seekable) {
    CompressingArchive(openvdb::io::COMPRESS_ACTIVE_MASK).writeTo(os, seekable, grids, openvdb::MetaMap());
  });
}

void writeScratchVdbStream(std::ostream& os, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& metadata) {
  CompressingArchive(openvdb::io::COMPRESS_ACTIVE_MASK).writeTo(os, /*seekable=*/false, grids, metadata);
}

}  // namespace vdbappear
