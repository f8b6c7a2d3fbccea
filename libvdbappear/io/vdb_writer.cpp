#include "libvdbappear/io/vdb_writer.h"

#include "libvdbappear/io/atomic_file.h"
#include "libvdbappear/util/error.h"

#include <openvdb/io/Stream.h>

#include <fmt/format.h>

#include <fstream>
#include <iostream>

namespace vdbappear {

namespace {

// io::File's writer on a stream of our own, so that a failed write (a full disk) is noticed
// instead of a truncated file being renamed into place.
class CheckedFileWriter : public openvdb::io::Archive {
 public:
  // Writes `temporary`; errors name `target`, the file the user asked for.
  void writeFile(const std::string& temporary, const std::string& target, const openvdb::GridCPtrVec& grids,
                 const openvdb::MetaMap& metadata) const {
    std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
    if (!file) throw MediumError(fmt::format("{}: cannot open a temporary file beside it for writing", target));
    Archive::write(file, grids, /*seekable=*/true, metadata);
    file.close();
    if (!file) throw MediumError(fmt::format("{}: write failed (disk full?)", target));
  }
};

}  // namespace

void writeVdb(const std::string& path, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& metadata) {
  if (path == "-") {
    try {
      openvdb::io::Stream(std::cout).write(grids, metadata);
      std::cout.flush();
    } catch (const std::exception& e) {
      throw MediumError(fmt::format("stdout: cannot write the VDB stream ({})", e.what()));
    }
    if (!std::cout) throw MediumError("stdout: write failed");
    return;
  }
  AtomicFile output(path);
  try {
    CheckedFileWriter().writeFile(output.temporaryPath(), path, grids, metadata);
  } catch (const MediumError&) {
    throw;
  } catch (const std::exception& e) {
    throw MediumError(fmt::format("{}: cannot write ({})", path, e.what()));
  }
  output.commit();
}

}  // namespace vdbappear
