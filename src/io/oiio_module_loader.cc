// Finding and dlopen()ing OpenImageIO's module on first use.
#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "io/oiio_backend.h"

namespace gdp::io {
namespace {

namespace fs = std::filesystem;

// Where the module may be, in order.
std::vector<std::string> candidates() {
  std::vector<std::string> paths;
  if (const char* env = std::getenv(kOiioModuleVariable); env && *env) {
    paths.emplace_back(env);
    return paths;  // an explicit choice is the only one tried
  }
  // Installed: where `cmake --install` puts it relative to the file holding this code (libgdp.so,
  // or a program linked with the static library). Then where the build tree puts it.
  Dl_info self{};
  if (dladdr(reinterpret_cast<void*>(&candidates), &self) != 0 && self.dli_fname) {
    std::error_code ec;
    fs::path binary = fs::canonical(fs::path(self.dli_fname), ec);
    if (ec) binary = fs::path(self.dli_fname);
    paths.push_back((binary.parent_path() / GDP_OIIO_MODULE_RELATIVE / kOiioModuleName).lexically_normal().string());
  }
  paths.emplace_back(GDP_OIIO_MODULE_BUILD_PATH);
  return paths;
}

struct Loaded {
  Backend* backend = nullptr;
  std::string error;
};

Loaded load() {
  Loaded result;
  std::vector<std::string> tried;
  std::string failures;
  for (const std::string& path : candidates()) {
    tried.push_back(path);
    std::error_code ec;
    if (!fs::exists(path, ec)) continue;
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = ::dlerror();
      failures += fmt::format("; {}: {}", path, why ? why : "dlopen failed");
      continue;
    }
    auto entry = reinterpret_cast<OiioEntryPoint>(::dlsym(handle, kOiioEntryPoint));
    if (!entry) {
      failures += fmt::format("; {}: no {}", path, kOiioEntryPoint);
      continue;  // the handle stays open: harmless, and never unloaded while code may use it
    }
    result.backend = entry();
    return result;
  }
  result.error = fmt::format("needs OpenImageIO's module ({}): not found at {}{} (set {} to its path)", kOiioModuleName,
                             fmt::join(tried, ", "), failures, kOiioModuleVariable);
  return result;
}

}  // namespace

Backend& oiio_backend() {
  static const Loaded module = load();
  if (!module.backend) throw CodecError(module.error);
  return *module.backend;
}


}  // namespace gdp::io
