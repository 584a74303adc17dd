// Names for temporary output files: created exclusively next to the final file.
#pragma once

#include <filesystem>
#include <string>

namespace gdp::io {

// Creates an empty ".NAME.tmp-PID-RANDOM.EXT" exclusively next to `path` (same extension, so a
// plugin chosen by name still matches); on failure returns the empty path and sets `why`.
std::filesystem::path create_temp_file(const std::filesystem::path& path, std::string& why);

}  // namespace gdp::io
