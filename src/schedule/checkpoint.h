// A checkpoint directory of a streaming solve: manifest, per-lane state files written atomically, named scratch.
#pragma once

#include <atomic>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "gdp/solver.h"

namespace gdp::schedule {

// The directory of --checkpoint DIR / --resume DIR (docs/resume.md). Holds
//   manifest            text: identity (inputs, options), the solver's sizes and lane count,
//                       and how far each lane got (rewritten atomically at every unit)
//   laneN.state         lane N's state at its last completed unit (written atomically)
//   laneN-*.store       lane N's row stores (RowStore files, kept instead of unlinked)
// Lanes save their states independently (each at its own quiescent points); the scheduler
// decides when, the state is whatever the lane's V-cycle and worker say it is.
class Checkpoint {
 public:
  // `sizes`: the solver's problem ("W H C levels bytes-per-sample"). A fresh run clears what an
  // earlier checkpoint left in the directory (creating it) and writes the manifest with `lanes`;
  // a resumed one checks the manifest (UsageError naming what changed) and sets `lanes` from it.
  Checkpoint(const SolverOptions& options, const std::string& sizes, int& lanes);

  const std::filesystem::path& dir() const { return dir_; }
  bool resuming() const { return resume_; }
  // Rows of the first restriction pass between two saves (GDP_CHECKPOINT_ROWS overrides `rows`).
  int unit_rows(int rows) const;
  // Lane `lane`'s saved state, when it saved one.
  std::optional<std::string> load(int lane) const;
  // Replaces lane `lane`'s state (the caller has made its stores durable first) and notes
  // `progress` in the manifest. With GDP_CHECKPOINT_KILL_AFTER=N in the environment, the
  // process kills itself (SIGKILL) after its N-th save: the tests' crash at a chosen unit.
  void save(int lane, const std::string& state, const std::string& progress);

 private:
  void write_manifest();

  std::filesystem::path dir_;
  bool resume_;
  CheckpointIdentity identity_;
  std::string sizes_;
  int lanes_ = 1;
  std::mutex mutex_;
  std::vector<std::string> progress_;
  int saves_ = 0, kill_after_ = 0;
};

// The manifest's parts (checkpoint.cc, gdp::check_resume).
struct Manifest {
  CheckpointIdentity identity;
  std::string sizes;
  int lanes = 0;
  std::vector<std::string> progress;  // per lane, as noted
};
// Reads DIR/manifest; UsageError naming the directory when it is missing or malformed.
Manifest read_manifest(const std::filesystem::path& dir);
// Writes `bytes` to `path` through a temporary file, synced, then renamed over it.
void write_atomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace gdp::schedule
