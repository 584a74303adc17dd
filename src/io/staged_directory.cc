// A directory written under a hidden name beside its destination, renamed into place at the end, removed on errors.
#include "io/staged_directory.h"

#include <random>

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp::io {

namespace fs = std::filesystem;

void write_staged_directory(const fs::path& out, const std::function<void(const fs::path&)>& fill) {
  const fs::path dir = out.has_filename() ? out : out.parent_path();  // "dir/" names dir
  const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
  const fs::path temp = parent / fmt::format(".{}.gdp-{}", dir.filename().string(), std::random_device{}());
  try {
    fs::create_directories(temp);
    fill(temp);
    if (fs::exists(dir)) fs::remove(dir);
    fs::rename(temp, dir);
  } catch (const fs::filesystem_error& e) {
    std::error_code ignore;
    fs::remove_all(temp, ignore);
    throw OutputError(dir.string() + ": " + e.code().message());
  } catch (...) {
    std::error_code ignore;
    fs::remove_all(temp, ignore);
    throw;
  }
}

}  // namespace gdp::io
