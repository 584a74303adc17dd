// Files that must not survive an interrupted run (temporary outputs now, scratch streams later).
#pragma once

#include <string>

namespace gdp::cleanup {

// Registers a path to delete if the process is interrupted or exits (exit()) while it is still
// tracked; returns a handle for untrack()
// (-1 when the fixed-size registry is full, in which case the path is not tracked).
int track(const std::string& path);
void untrack(int handle);

// Deletes every tracked path. Async-signal-safe (only unlink()).
void remove_tracked() noexcept;

// SIGINT, SIGTERM, SIGHUP, SIGQUIT: delete the tracked files, then die of the same signal.
// SIGXFSZ is ignored: a write beyond the file-size limit fails (EFBIG) and is reported.
// (SIGKILL cannot be caught: the next run writing the same output removes what it left,
// io/temp_file.h.)
void install_signal_handlers();

}  // namespace gdp::cleanup
