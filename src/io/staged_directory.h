// Output directories (tile pyramids) built beside their destination and renamed into place: never seen half written.
#pragma once

#include <filesystem>
#include <functional>

namespace gdp::io {

// Calls fill(temp) on a new hidden directory ".NAME.tmp-PID-RANDOM" beside `dir` (io::temp_name),
// then replaces `dir` (absent or an empty directory) with it. First removes the hidden
// directories of `dir` left by runs that no longer exist (io::remove_stale_temp_files: a SIGKILL
// cannot be caught). On any exception the hidden directory is removed; filesystem errors become
// OutputError "`dir`: problem", others pass through.
void write_staged_directory(const std::filesystem::path& dir, const std::function<void(const std::filesystem::path&)>& fill);

}  // namespace gdp::io
