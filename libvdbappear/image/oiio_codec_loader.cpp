#include "libvdbappear/image/oiio_codec.h"

#include "libvdbappear/util/error.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <filesystem>

namespace vdbappear {

namespace {

constexpr const char* kModuleFile = "libvdbappear_oiio.so";

// The module next to the shared library this function lies in.
std::string modulePath() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&modulePath), &info) == 0 || info.dli_fname == nullptr) return kModuleFile;
  return (std::filesystem::path(info.dli_fname).parent_path() / kModuleFile).string();
}

}  // namespace

const OiioCodec& oiioCodec(const std::string& path) {
  const std::string module = modulePath();
  // Never closed: the loader keeps one copy however often it is opened, and OpenImageIO is not
  // made to be unloaded.
  void* handle = dlopen(module.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr)
    throw MediumError(fmt::format("{}: formats other than OpenEXR need {}, which did not load: {}", path, module,
                                  dlerror()));
  auto* entry = reinterpret_cast<const OiioCodec* (*)()>(dlsym(handle, "vdbappear_oiio_codec"));
  if (entry == nullptr) throw MediumError(fmt::format("{}: {} has no vdbappear_oiio_codec", path, module));
  return *entry();
}

}  // namespace vdbappear
