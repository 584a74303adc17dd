// Checkpoint directories: the manifest (text), atomic state files, the checks before a resume, removal.
#include "schedule/checkpoint.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <system_error>

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp {
namespace schedule {
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

std::string system_message() { return std::generic_category().message(errno); }

void write_all(int fd, const std::string& bytes, const std::filesystem::path& path) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t k = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) throw OutputError(fmt::format("checkpoint {}: cannot write: {}", path.string(), system_message()));
    done += static_cast<std::size_t>(k);
  }
}

int env_int(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : 0;
}

// Files a checkpoint consists of (removed by a fresh run and after success).
bool is_checkpoint_file(const std::string& name) {
  const auto ends = [&](const std::string& tail) {
    return name.size() >= tail.size() && name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
  };
  return name == "manifest" || name == "manifest.tmp" ||
         (name.rfind("lane", 0) == 0 && (ends(".state") || ends(".state.tmp") || ends(".store")));
}

}  // namespace

void write_atomically(const std::filesystem::path& path, const std::string& bytes) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw OutputError(fmt::format("checkpoint {}: cannot create: {}", tmp.string(), system_message()));
  try {
    write_all(fd, bytes, tmp);
    if (::fdatasync(fd) != 0) throw OutputError(fmt::format("checkpoint {}: {}", tmp.string(), system_message()));
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
  if (::rename(tmp.c_str(), path.c_str()) != 0)
    throw OutputError(fmt::format("checkpoint {}: cannot rename: {}", path.string(), system_message()));
}

Manifest read_manifest(const std::filesystem::path& dir) {
  const std::string where = fmt::format("--resume {}", dir.string());
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) throw UsageError(where + ": no such directory");
  std::ifstream in(dir / "manifest");
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

Checkpoint::Checkpoint(const SolverOptions& options, const std::string& sizes, int& lanes)
    : dir_(options.checkpoint_dir), resume_(options.resume), identity_(options.checkpoint_identity), sizes_(sizes),
      kill_after_(env_int("GDP_CHECKPOINT_KILL_AFTER")) {
  if (resume_) {
    check_resume(dir_, identity_);
    const Manifest m = read_manifest(dir_);
    if (m.sizes != sizes_)
      throw UsageError(fmt::format("--resume {}: the problem changed since the checkpoint (sizes {}, now {})",
                                   dir_.string(), m.sizes, sizes_));
    lanes = m.lanes;
    progress_ = m.progress;
  } else {
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (!std::filesystem::is_directory(dir_, ec))
      throw UsageError(fmt::format("--checkpoint {}: cannot create the directory", dir_.string()));
    for (const auto& e : std::filesystem::directory_iterator(dir_))
      if (is_checkpoint_file(e.path().filename().string())) std::filesystem::remove(e.path(), ec);
  }
  lanes_ = lanes;
  progress_.resize(lanes_, "not started");
  write_manifest();
}

int Checkpoint::unit_rows(int rows) const {
  const int forced = env_int("GDP_CHECKPOINT_ROWS");
  return forced > 0 ? forced : std::max(rows, 1);
}

std::optional<std::string> Checkpoint::load(int lane) const {
  std::ifstream in(dir_ / fmt::format("lane{}.state", lane), std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void Checkpoint::save(int lane, const std::string& state, const std::string& progress) {
  write_atomically(dir_ / fmt::format("lane{}.state", lane), state);
  const std::lock_guard lock(mutex_);
  progress_[lane] = progress;
  write_manifest();
  if (kill_after_ > 0 && ++saves_ == kill_after_) std::raise(SIGKILL);
}

void Checkpoint::write_manifest() {
  std::string text = std::string(kMagic) + "\n";
  text += fmt::format("sizes\t{}\nlanes\t{}\n", sizes_, lanes_);
  for (const auto& [key, value] : identity_) text += fmt::format("identity\t{}\t{}\n", escape(key), escape(value));
  for (int l = 0; l < lanes_; ++l) text += fmt::format("lane\t{}\t{}\n", l, escape(progress_[l]));
  write_atomically(dir_ / "manifest", text);
}

}  // namespace schedule

std::string file_identity(const std::filesystem::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return "";
  return fmt::format("{} bytes, modified {}.{:09d}", static_cast<long long>(st.st_size),
                     static_cast<long long>(st.st_mtim.tv_sec), static_cast<long>(st.st_mtim.tv_nsec));
}

void check_resume(const std::filesystem::path& dir, const CheckpointIdentity& identity) {
  const schedule::Manifest m = schedule::read_manifest(dir);
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
    if (schedule::is_checkpoint_file(e.path().filename().string())) std::filesystem::remove(e.path(), ec);
  if (std::filesystem::is_empty(dir, ec)) std::filesystem::remove(dir, ec);
}

}  // namespace gdp
