// Exclusive creation of temporary output files next to their final name.
#include "io/temp_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cerrno>
#include <random>
#include <system_error>

namespace gdp::io {

namespace fs = std::filesystem;

fs::path create_temp_file(const fs::path& path, std::string& why) {
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  const fs::file_status status = fs::status(dir, ec);
  if (!fs::exists(status)) why = fmt::format("no such directory '{}'", dir.string());
  else if (!fs::is_directory(status)) why = fmt::format("'{}' is not a directory", dir.string());
  if (!why.empty()) return {};
  std::random_device random;
  for (int attempt = 0; attempt < 16; ++attempt) {
    const fs::path temp = dir / fmt::format(".{}.tmp-{}-{:08x}{}", path.stem().string(), static_cast<long>(::getpid()),
                                            static_cast<unsigned>(random()), path.extension().string());
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return temp;
    }
    if (errno != EEXIST) break;
  }
  why = errno == EEXIST ? "no unused temporary file name" : std::generic_category().message(errno);
  return {};
}

}  // namespace gdp::io
