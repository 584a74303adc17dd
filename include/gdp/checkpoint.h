// Checkpoints of long solves (--checkpoint DIR, --resume DIR): what identifies a run, the checks before resuming.
#pragma once

#include <filesystem>
#include <map>
#include <string>

namespace gdp {

// What must not change between a checkpointed run and its resumption: keys such as
// "option --iters" or "input a.png" with their values (an input's value: its size and
// modification time, file_identity()). Compared entry by entry; the first difference is named.
using CheckpointIdentity = std::map<std::string, std::string>;

// "SIZE bytes, modified NS" of a file (its identity in a checkpoint); empty when it is not a file.
std::string file_identity(const std::filesystem::path& path);

// Throws UsageError (one line naming the directory and what is wrong or what changed) unless `dir`
// holds a checkpoint manifest written with this identity.
void check_resume(const std::filesystem::path& dir, const CheckpointIdentity& identity);

// After a successful run: removes the checkpoint's manifest, states and scratch files from `dir`,
// and `dir` itself when nothing else is left in it.
void remove_checkpoint(const std::filesystem::path& dir);

}  // namespace gdp
