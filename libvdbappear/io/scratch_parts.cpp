#include "libvdbappear/io/scratch_parts.h"

#include "libvdbappear/io/atomic_file.h"
#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/io/vdb_writer.h"
#include "libvdbappear/util/error.h"

#include <fmt/format.h>

#include <filesystem>
#include <sstream>

namespace vdbappear {

std::string scratchFolderFor(const std::string& output) {
  std::error_code error;
  const std::string folder = output == "-" ? std::filesystem::temp_directory_path(error).string()
                                           : std::filesystem::absolute(output, error).parent_path().string();
  return folder.empty() ? "." : folder;
}

ScratchParts::ScratchParts(const std::string& output) {
  // Made, opened, and removed (by `scratch`'s destructor) once open: the open stream keeps it.
  const AtomicFile scratch((std::filesystem::path(scratchFolderFor(output)) / "vdbappear-parts").string());
  path_ = scratch.temporaryPath();
  file_.open(path_, std::ios::in | std::ios::out | std::ios::binary | std::ios::trunc);
  if (!file_) throw MediumError(fmt::format("{}: cannot open a scratch file for parts of the medium", path_));
}

// Each part goes through a string stream of its own: OpenVDB's reader and writer leave a pointer to
// their (then freed) stream metadata in the stream they were given, which a second use dereferences.
std::size_t ScratchParts::put(const Medium& part) {
  std::ostringstream bytes(std::ios::binary);
  try {
    writeScratchVdbStream(bytes, part.grids(), part.metadata);
  } catch (const std::exception& e) {
    throw MediumError(fmt::format("{}: cannot write a part of the medium ({})", path_, e.what()));
  }
  const std::string written = std::move(bytes).str();
  file_.clear();
  file_.seekp(end_);
  file_.write(written.data(), std::streamsize(written.size()));
  file_.flush();
  if (!file_) throw MediumError(fmt::format("{}: cannot write a part of the medium (disk full?)", path_));
  offsets_.push_back(end_);
  end_ += std::streamoff(written.size());
  return offsets_.size() - 1;
}

MediumPtr ScratchParts::take(std::size_t i, const std::string& source) {
  const std::streamoff begin = offsets_.at(i), end = i + 1 < offsets_.size() ? offsets_[i + 1] : end_;
  std::string bytes(std::size_t(end - begin), '\0');
  file_.clear();
  file_.seekg(begin);
  file_.read(bytes.data(), std::streamsize(bytes.size()));
  if (!file_) throw MediumError(fmt::format("{}: cannot read back {}", path_, source));
  std::istringstream in(std::move(bytes), std::ios::binary);
  GridMapping as_written;
  as_written.preset = GridPreset::kNone;
  MediumPtr part = readMediumStream(in, source, as_written);
  part->source = source;
  return part;
}

}  // namespace vdbappear
