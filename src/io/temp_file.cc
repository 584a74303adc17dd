// Exclusive creation of temporary output files next to their final name, and removal of stale ones.
#include "io/temp_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cerrno>
#include <cstdint>
#include <map>
#include <mutex>
#include <random>
#include <vector>
#include <system_error>

namespace gdp::io {

namespace fs = std::filesystem;

namespace {

// Bytes a temporary name adds to the stem: ".", ".tmp-", a PID (up to 10 digits), "-", 8 hex digits.
constexpr std::size_t kAdded = 1 + 5 + 10 + 1 + 8;

std::uint64_t fnv1a(const std::string& text) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::size_t name_max(const fs::path& dir) {
  const long n = ::pathconf(dir.c_str(), _PC_NAME_MAX);
  return n > 0 ? static_cast<std::size_t>(n) : 255;
}

// True when `name` is one of `prefix`'s temporaries ending in `ext` whose process has ended.
bool stale(const std::string& name, const std::string& prefix, const std::string& ext) {
  if (name.size() <= prefix.size() + ext.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - ext.size(), ext.size(), ext) != 0)
    return false;
  const std::size_t dash = name.find('-', prefix.size());
  if (dash == std::string::npos || dash == prefix.size() || dash - prefix.size() > 10) return false;
  long pid = 0;
  for (std::size_t i = prefix.size(); i < dash; ++i) {
    if (name[i] < '0' || name[i] > '9') return false;
    pid = pid * 10 + (name[i] - '0');
  }
  return pid > 0 && pid != ::getpid() && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

}  // namespace

std::string temp_prefix(const fs::path& path, std::size_t max_name) {
  std::string stem = path.stem().string();
  const std::size_t ext = path.extension().string().size();
  if (stem.size() + kAdded + ext > max_name) {
    const std::string hash = fmt::format("~{:016x}", fnv1a(stem));
    const std::size_t room = max_name > kAdded + ext + hash.size() ? max_name - kAdded - ext - hash.size() : 0;
    stem = stem.substr(0, room) + hash;
  }
  return "." + stem + ".tmp-";
}

namespace {

// The names in `dir` that look like any output's temporary, listed once per directory and
// process: a run writing thousands of files into one directory (TOAST tiles) reads it once.
std::vector<std::string>& temporaries_in(const fs::path& dir) {
  static std::map<std::string, std::vector<std::string>> listed;
  std::error_code ec;
  auto [at, added] = listed.try_emplace(fs::absolute(dir, ec).lexically_normal().string());
  if (!added) return at->second;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() > 1 && name[0] == '.' && name.find(".tmp-") != std::string::npos) at->second.push_back(name);
  }
  return at->second;
}

}  // namespace

int remove_stale_temp_files(const fs::path& path) {
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const std::string prefix = temp_prefix(path, name_max(dir)), ext = path.extension().string();
  static std::mutex mutex;
  std::lock_guard lock(mutex);
  std::vector<std::string>& names = temporaries_in(dir);
  int removed = 0;
  std::error_code ec;
  std::erase_if(names, [&](const std::string& name) {
    if (!stale(name, prefix, ext)) return false;
    if (fs::remove_all(dir / name, ec) > 0) ++removed;
    return true;
  });
  return removed;
}

fs::path temp_name(const fs::path& path) {
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  static thread_local std::mt19937 random{std::random_device{}()};
  return dir / fmt::format("{}{}-{:08x}{}", temp_prefix(path, name_max(dir)), static_cast<long>(::getpid()),
                           static_cast<unsigned>(random()), path.extension().string());
}

fs::path create_temp_file(const fs::path& path, std::string& why) {
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  const fs::file_status status = fs::status(dir, ec);
  if (!fs::exists(status)) why = fmt::format("no such directory '{}'", dir.string());
  else if (!fs::is_directory(status)) why = fmt::format("'{}' is not a directory", dir.string());
  if (!why.empty()) return {};
  remove_stale_temp_files(path);
  for (int attempt = 0; attempt < 16; ++attempt) {
    const fs::path temp = temp_name(path);
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return temp;
    }
    if (errno != EEXIST) break;
  }
  why = errno == EEXIST ? "no unused temporary file name" : std::generic_category().message(errno);
  return {};
}

}  // namespace gdp::io
