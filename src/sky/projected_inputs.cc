// gdp sky --projected's inputs: files and directories (Montage's projdir) to images with their area images.
#include <algorithm>
#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "gdp/sky_projected.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

// ".fits", ".fit", ".fts", with ".gz" after them: the extension, or "" for other names.
std::string fits_extension(const std::string& name) {
  for (const char* ext : {".fits", ".fit", ".fts", ".fits.gz", ".fit.gz", ".fts.gz"}) {
    const std::string e = ext;
    if (name.size() > e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0) return e;
  }
  return "";
}

// NAME_area.EXT -> NAME.EXT ("" for other names).
std::string image_of_area(const std::string& path) {
  const std::string ext = fits_extension(path), tail = "_area" + ext;
  if (ext.empty() || path.size() <= tail.size() || path.compare(path.size() - tail.size(), tail.size(), tail) != 0)
    return "";
  return path.substr(0, path.size() - tail.size()) + ext;
}

std::string area_of(const std::string& image) {
  const std::string ext = fits_extension(image);
  return image.substr(0, image.size() - ext.size()) + "_area" + ext;
}

std::vector<std::string> fits_files(const fs::path& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file() && !fits_extension(e.path().filename().string()).empty()) files.push_back(e.path().string());
  if (ec) throw InputError(fmt::format("{}: cannot list the directory ({})", dir.string(), ec.message()));
  if (files.empty()) throw InputError(fmt::format("{}: no FITS images (.fits, .fit, .fts) in the directory", dir.string()));
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

std::vector<ProjectedInput> projected_inputs(const std::vector<std::string>& paths) {
  std::vector<std::string> files;
  for (const std::string& p : paths) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      const std::vector<std::string> in = fits_files(p);
      files.insert(files.end(), in.begin(), in.end());
    } else if (fs::exists(p, ec)) {
      files.push_back(p);
    } else {
      throw InputError(fmt::format("{}: no such file or directory", p));
    }
  }
  std::vector<ProjectedInput> inputs;
  for (const std::string& f : files) {
    const std::string image = image_of_area(f);
    std::error_code ec;
    if (!image.empty() && fs::is_regular_file(image, ec)) continue;  // an area image: its image takes it
    const std::string area = fits_extension(f).empty() ? "" : area_of(f);
    inputs.push_back({f, !area.empty() && fs::is_regular_file(area, ec) ? area : ""});
  }
  if (inputs.empty()) throw UsageError("gdp sky --projected: no images (only area images were given)");
  return inputs;
}

}  // namespace gdp
