// Names for temporary output files: created exclusively next to the final file; stale ones removed.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace gdp::io {

// A fresh ".NAME.tmp-PID-RANDOM.EXT" next to `path` (not created): the name of every temporary of
// `path`, files (create_temp_file) and staged directories (io/staged_directory.h) alike.
std::filesystem::path temp_name(const std::filesystem::path& path);

// Creates an empty ".NAME.tmp-PID-RANDOM.EXT" exclusively next to `path` (same extension, so a
// plugin chosen by name still matches); on failure returns the empty path and sets `why`. First
// removes the stale temporaries of `path` (remove_stale_temp_files).
std::filesystem::path create_temp_file(const std::filesystem::path& path, std::string& why);

// ".NAME.tmp-" for `path`, such that the whole temporary name fits `max_name` bytes (NAME_MAX):
// a stem too long for it is cut and followed by "~" and a 64-bit hash of the whole stem.
std::string temp_prefix(const std::filesystem::path& path, std::size_t max_name);

// Removes `path`'s temporaries left by processes that no longer run (a SIGKILL, a crash, a lost
// power): files or directory trees named with its prefix and extension and a PID that kill(PID, 0)
// says does not exist.
// Each directory is read once per process (a run writing thousands of tiles into one reads it
// once). PIDs are this host's: two hosts writing the same output in a shared directory at once
// is not supported anyway. Returns how many were removed.
int remove_stale_temp_files(const std::filesystem::path& path);

}  // namespace gdp::io
