// Checkpoint directories: the manifest (text), atomic state files, the checks before a resume, removal.
#include "io/checkpoint_dir.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <system_error>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "util/env_int.h"
#include "util/exact_io.h"

namespace gdp {
namespace io {
namespace {

constexpr const char* kMagic = "gdp checkpoint 1";

// Tabs and newlines in keys and values (file names) would break the line format.
std::string escape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    if (ch == '\\') out += "\\\\";
    else if (ch == '\t') out += "\\t";
    else if (ch == '\n') out += "\\n";
    else out += ch;
  }
  return out;
}

std::string unescape(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '\\' || i + 1 == s.size()) {
      out += s[i];
      continue;
    }
    const char n = s[++i];
    out += n == 't' ? '\t' : n == 'n' ? '\n' : n;
  }
  return out;
}

std::vector<std::string> split_tabs(const std::string& line) {
  std::vector<std::string> parts;
  std::size_t at = 0;
  for (std::size_t tab; (tab = line.find('\t', at)) != std::string::npos; at = tab + 1)
    parts.push_back(line.substr(at, tab - at));
  parts.push_back(line.substr(at));
  return parts;
}

// Files a checkpoint consists of (removed by a fresh run and after success).
bool is_checkpoint_file(const std::string& name) {
  const auto ends = [&](const std::string& tail) {
    return name.size() >= tail.size() && name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
  };
  return name == "manifest" || name == "manifest.tmp" || name.rfind("manifest.rank", 0) == 0 ||
         (name.rfind("lane", 0) == 0 && (ends(".state") || ends(".state.tmp") || ends(".store")));
}

// The lane a file "laneN..." belongs to (-1: not a lane's file).
int lane_of(const std::string& name) {
  if (name.rfind("lane", 0) != 0 || name.size() < 5 || name[4] < '0' || name[4] > '9') return -1;
  return std::atoi(name.c_str() + 4);
}

// Rank r's manifest: rank 0's is "manifest" (the one gdp::check_resume reads).
std::string manifest_name(int rank) { return rank == 0 ? "manifest" : fmt::format("manifest.rank{}", rank); }

}  // namespace

void write_atomically(const std::filesystem::path& path, const std::string& bytes) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw OutputError(fmt::format("checkpoint {}: cannot create: {}", tmp.string(), util::errno_message()));
  try {
    util::write_exactly(fd, bytes.data(), bytes.size(), {tmp.native(), "checkpoint "});
    if (::fdatasync(fd) != 0) throw OutputError(fmt::format("checkpoint {}: {}", tmp.string(), util::errno_message()));
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
  if (::rename(tmp.c_str(), path.c_str()) != 0)
    throw OutputError(fmt::format("checkpoint {}: cannot rename: {}", path.string(), util::errno_message()));
}

Manifest read_manifest(const std::filesystem::path& dir, int rank) {
  const std::string where = fmt::format("--resume {}", dir.string());
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) throw UsageError(where + ": no such directory");
  std::ifstream in(dir / manifest_name(rank));
  if (!in && rank > 0)
    throw UsageError(fmt::format("{}: no checkpoint of rank {} there (it was made with fewer ranks)", where, rank));
  if (!in) throw UsageError(where + ": no checkpoint there (no manifest; start with --checkpoint DIR)");
  std::string line;
  if (!std::getline(in, line) || line != kMagic)
    throw UsageError(where + ": the manifest is not a gdp checkpoint manifest (corrupt?)");
  Manifest m;
  for (int n = 2; std::getline(in, line); ++n) {
    const std::vector<std::string> parts = split_tabs(line);
    const bool ok = (parts[0] == "sizes" && parts.size() == 2) || (parts[0] == "lanes" && parts.size() == 2) ||
                    (parts[0] == "identity" && parts.size() == 3) || (parts[0] == "lane" && parts.size() == 3);
    if (!ok) throw UsageError(fmt::format("{}: the manifest is corrupt (line {})", where, n));
    if (parts[0] == "sizes") m.sizes = parts[1];
    if (parts[0] == "lanes") m.lanes = std::atoi(parts[1].c_str());
    if (parts[0] == "identity") m.identity[unescape(parts[1])] = unescape(parts[2]);
    if (parts[0] == "lane") m.progress.push_back(unescape(parts[2]));
  }
  if (m.sizes.empty() || m.lanes < 1) throw UsageError(where + ": the manifest is corrupt (incomplete)");
  return m;
}

Checkpoint::Checkpoint(const SolverOptions& options, const std::string& sizes, int& lanes, int first_lane, int rank,
                       int all_lanes)
    : dir_(options.checkpoint_dir), resume_(options.resume), identity_(options.checkpoint_identity), sizes_(sizes),
      first_(first_lane), rank_(rank), kill_after_(util::env_int("GDP_CHECKPOINT_KILL_AFTER")) {
  if (resume_) {
    check_resume(dir_, identity_);
    const Manifest m = read_manifest(dir_, rank);
    // "problem | counts": the band and rank counts are named on their own.
    const auto part = [](const std::string& v, bool second) {
      const std::size_t bar = v.find(" | ");
      return bar == std::string::npos ? (second ? std::string() : v) : second ? v.substr(bar + 3) : v.substr(0, bar);
    };
    if (part(m.sizes, false) != part(sizes_, false))
      throw UsageError(fmt::format("--resume {}: the problem changed since the checkpoint (sizes {}, now {})",
                                   dir_.string(), part(m.sizes, false), part(sizes_, false)));
    if (part(m.sizes, true) != part(sizes_, true))
      throw UsageError(fmt::format("--resume {}: the checkpoint was made with {}, this run has {} (resume with the "
                                   "same --bands and number of ranks)",
                                   dir_.string(), part(m.sizes, true), part(sizes_, true)));
    lanes = m.lanes;
    progress_ = m.progress;
  } else {
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (!std::filesystem::is_directory(dir_, ec))
      throw UsageError(fmt::format("--checkpoint {}: cannot create the directory", dir_.string()));
    // This rank's files only (ranks share the directory); rank 0 also those of lanes no rank has now.
    for (const auto& e : std::filesystem::directory_iterator(dir_)) {
      const std::string name = e.path().filename().string();
      const int lane = lane_of(name);
      const bool mine = lane >= 0 ? (lane >= first_ && lane < first_ + lanes) || (rank_ == 0 && lane >= std::max(all_lanes, lanes))
                                  : name == manifest_name(rank_) || name == manifest_name(rank_) + ".tmp";
      if (mine && is_checkpoint_file(name)) std::filesystem::remove(e.path(), ec);
    }
  }
  lanes_ = lanes;
  progress_.resize(lanes_, "not started");
  generation_.assign(lanes_, 0);
  if (resume_)  // each lane's newest state, unless the caller chooses (a band plan's lanes agree)
    for (int l = 0; l < lanes_; ++l) generation_[l] = generations(first_ + l).back();
  write_manifest();
}

int Checkpoint::unit_rows(int rows) const {
  const int forced = util::env_int("GDP_CHECKPOINT_ROWS");
  return forced > 0 ? forced : std::max(rows, 1);
}

// A state file: "gdp state G\n" (its generation) and the state's bytes.
std::optional<std::pair<long long, std::string>> Checkpoint::read_slot(int lane, int slot) const {
  std::ifstream in(dir_ / fmt::format("lane{}.{}.state", lane, slot), std::ios::binary);
  if (!in) return std::nullopt;
  std::string head;
  long long generation = 0;
  if (!std::getline(in, head) || std::sscanf(head.c_str(), "gdp state %lld", &generation) != 1 || generation < 1)
    return std::nullopt;  // a torn write never lands (written atomically): another program's file
  std::ostringstream s;
  s << in.rdbuf();
  return std::pair{generation, s.str()};
}

std::vector<long long> Checkpoint::generations(int lane) const {
  std::vector<long long> g{0};  // 0: no state, a fresh start, is always possible
  for (int slot : {0, 1})
    if (const auto state = read_slot(lane, slot); state && state->first % 2 == slot) g.push_back(state->first);
  std::sort(g.begin(), g.end());
  return g;
}

std::string Checkpoint::state_name(int lane) const {
  return fmt::format("lane{}.{}.state", lane, generation_.at(lane - first_) % 2);
}

void Checkpoint::choose(int lane, long long generation) { generation_.at(lane - first_) = generation; }

std::optional<std::string> Checkpoint::load(int lane) const {
  const long long generation = generation_.at(lane - first_);
  if (generation == 0) return std::nullopt;
  auto state = read_slot(lane, static_cast<int>(generation % 2));
  if (!state || state->first != generation)
    throw UsageError(fmt::format("--resume {}: lane{}'s state {} is missing", dir_.string(), lane, generation));
  return std::move(state->second);
}

void Checkpoint::save(int lane, const std::string& state, const std::string& progress) {
  long long& generation = generation_.at(lane - first_);  // this lane's only: no other thread touches it
  ++generation;
  write_atomically(dir_ / fmt::format("lane{}.{}.state", lane, generation % 2),
                   fmt::format("gdp state {}\n", generation) + state);
  const std::lock_guard lock(mutex_);
  progress_[lane - first_] = progress;
  write_manifest();
  if (kill_after_ > 0 && ++saves_ == kill_after_) std::raise(SIGKILL);
}

void Checkpoint::write_manifest() {
  std::string text = std::string(kMagic) + "\n";
  text += fmt::format("sizes\t{}\nlanes\t{}\n", sizes_, lanes_);
  for (const auto& [key, value] : identity_) text += fmt::format("identity\t{}\t{}\n", escape(key), escape(value));
  for (int l = 0; l < lanes_; ++l) text += fmt::format("lane\t{}\t{}\n", first_ + l, escape(progress_[l]));
  write_atomically(dir_ / manifest_name(rank_), text);
}

}  // namespace io

std::string file_identity(const std::filesystem::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return "";
  return fmt::format("{} bytes, modified {}.{:09d}", static_cast<long long>(st.st_size),
                     static_cast<long long>(st.st_mtim.tv_sec), static_cast<long>(st.st_mtim.tv_nsec));
}

void check_resume(const std::filesystem::path& dir, const CheckpointIdentity& identity) {
  const io::Manifest m = io::read_manifest(dir);
  const std::string where = fmt::format("--resume {}", dir.string());
  for (const auto& [key, value] : m.identity) {
    const auto now = identity.find(key);
    if (now == identity.end())
      throw UsageError(fmt::format("{}: {} ({}) was given to the checkpointed run, not now", where, key, value));
    if (now->second != value)
      throw UsageError(fmt::format("{}: {} changed since the checkpoint (was {}, now {})", where, key, value,
                                   now->second.empty() ? "missing" : now->second));
  }
  for (const auto& [key, value] : identity)
    if (!m.identity.count(key))
      throw UsageError(fmt::format("{}: {} ({}) was not given to the checkpointed run", where, key, value));
}

void remove_checkpoint(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec))
    if (io::is_checkpoint_file(e.path().filename().string())) std::filesystem::remove(e.path(), ec);
  if (std::filesystem::is_empty(dir, ec)) std::filesystem::remove(dir, ec);
}

}  // namespace gdp
