// A checkpoint directory on disk: manifest, per-lane state files written atomically, named scratch (the schedule decides what and when).
#pragma once

#include <atomic>
#include <utility>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "gdp/solver.h"

namespace gdp::io {

// The directory of --checkpoint DIR / --resume DIR (docs/resume.md). Holds
//   manifest            text: identity (inputs, options), the solver's sizes and lane count,
//                       and how far each lane got (rewritten atomically at every unit)
//   laneN.G.state       lane N's states at its last two completed units (G = generation % 2,
//                       each written atomically)
//   laneN-*.store       lane N's row stores (RowStore files, kept instead of unlinked)
// Lanes save their states independently (each at its own quiescent points); the scheduler
// decides when, the state is whatever the lane's V-cycle and worker say it is.
class Checkpoint {
 public:
  // `sizes`: the solver's problem ("W H C levels bytes-per-sample"). A fresh run clears what an
  // earlier checkpoint left in the directory (creating it) and writes the manifest with `lanes`;
  // a resumed one checks the manifest (UsageError naming what changed) and sets `lanes` from it.
  // Under mpirun each rank has its own lanes [first_lane, first_lane + lanes) and manifest
  // (rank 0's "manifest", the others' "manifest.rankR"); `all_lanes`: every rank's lanes.
  Checkpoint(const SolverOptions& options, const std::string& sizes, int& lanes, int first_lane = 0, int rank = 0,
             int all_lanes = 0);

  const std::filesystem::path& dir() const { return dir_; }
  bool resuming() const { return resume_; }
  // Rows of the first restriction pass between two saves (GDP_CHECKPOINT_ROWS overrides `rows`).
  int unit_rows(int rows) const;
  // Every save is a new generation (1, 2, ...) of the lane's state, written to one of two files
  // in turn: "laneN.(G % 2).state". generations(): those on disk, and 0 (no state); choose(): the
  // one load() returns (by default the newest; 0: none) and the next save's predecessor.
  std::vector<long long> generations(int lane) const;
  void choose(int lane, long long generation);
  // The file of lane `lane`'s chosen state.
  std::string state_name(int lane) const;
  // Lane `lane`'s chosen state, when it saved one.
  std::optional<std::string> load(int lane) const;
  // Replaces lane `lane`'s state (the caller has made its stores durable first) and notes
  // `progress` in the manifest. With GDP_CHECKPOINT_KILL_AFTER=N in the environment, the
  // process kills itself (SIGKILL) after its N-th save: the tests' crash at a chosen unit.
  void save(int lane, const std::string& state, const std::string& progress);

 private:
  void write_manifest();
  std::optional<std::pair<long long, std::string>> read_slot(int lane, int slot) const;

  std::filesystem::path dir_;
  bool resume_;
  CheckpointIdentity identity_;
  std::string sizes_;
  int lanes_ = 1, first_ = 0, rank_ = 0;
  std::mutex mutex_;
  std::vector<std::string> progress_;
  std::vector<long long> generation_;  // per lane: the newest saved (or chosen) state
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
Manifest read_manifest(const std::filesystem::path& dir, int rank = 0);
// Writes `bytes` to `path` through a temporary file, synced, then renamed over it.
void write_atomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace gdp::io
