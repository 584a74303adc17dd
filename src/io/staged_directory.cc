// A directory written under a hidden name beside its destination, renamed into place at the end, removed on errors.
#include "io/staged_directory.h"

#include <fmt/format.h>

#include "gdp/errors.h"
#include "io/temp_file.h"

namespace gdp::io {

namespace fs = std::filesystem;

void write_staged_directory(const fs::path& out, const std::function<void(const fs::path&)>& fill) {
  const fs::path dir = out.has_filename() ? out : out.parent_path();  // "dir/" names dir
  // Named as the output files' temporaries, so that a run killed before the rename (SIGKILL, a
  // crash) leaves a directory that the next run writing `dir` removes.
  remove_stale_temp_files(dir);
  std::error_code ec;
  if (dir.has_parent_path()) fs::create_directories(dir.parent_path(), ec);
  fs::path temp;
  for (int attempt = 0; attempt < 16 && temp.empty(); ++attempt) {
    const fs::path name = temp_name(dir);
    if (fs::create_directory(name, ec)) temp = name;
    else if (ec) throw OutputError(fmt::format("{}: {}", dir.string(), ec.message()));
  }
  if (temp.empty()) throw OutputError(dir.string() + ": no unused temporary directory name");
  try {
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
