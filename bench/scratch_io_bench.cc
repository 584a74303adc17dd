// CPU seconds per GB of a scratch stream written and read back through a file, by I/O method.
//
// Usage: scratch_io_bench DIR GB [METHOD...]   (methods: buffered dropbehind direct direct-huge; default all)
// Each method writes GB gigabytes to an unlinked file in DIR in 1 MB blocks, rewinds and reads
// them back in order (as a schedule::RowStore does between a V-cycle's two passes), then prints,
// per phase, wall seconds, this process's user and system CPU seconds, and the system CPU seconds
// of the whole machine (from /proc/stat: includes the kernel's writeback and reclaim threads,
// which run on the same two cores, and other processes: compare it only on a quiet machine).
//   buffered    plain write()/read() through the page cache (what RowStore did first)
//   dropbehind  the same, with RowStore's io::DropBehind (32 MB window): written ranges
//               pushed to the disk and dropped from the cache behind the writer, read ones too
//   direct      O_DIRECT: no page cache, 1 MB aligned blocks (the last one padded)
//   direct-huge the same from a buffer in a transparent huge page (io::AlignedBytes(.., true)):
//               each request pins one page, not 256 (docs/how-streaming-works.md, "Cheaper O_DIRECT stores")
#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

#include "io/aligned_bytes.h"
#include "io/drop_behind.h"

namespace {

constexpr std::size_t kBlock = std::size_t{1} << 20;
constexpr std::size_t kWindow = gdp::io::kDropBehindWindow;  // as schedule::StorePolicy's

struct Sample {
  double wall, user, sys, machine_sys;
};

double machine_sys_seconds() {
  std::ifstream stat("/proc/stat");
  std::string cpu;
  long long user, nice, system, idle, iowait, irq, softirq;
  stat >> cpu >> user >> nice >> system >> idle >> iowait >> irq >> softirq;
  return static_cast<double>(system + irq + softirq) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

Sample now() {
  rusage r{};
  getrusage(RUSAGE_SELF, &r);
  auto seconds = [](timeval t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  return {wall, seconds(r.ru_utime), seconds(r.ru_stime), machine_sys_seconds()};
}

void report(const char* method, const char* phase, const Sample& a, const Sample& b, double gb) {
  std::printf("%-10s %-5s %6.2f GB  wall %6.2f s  user %5.2f  sys %5.2f  (sys %5.2f s/GB)  machine sys %6.2f\n", method,
              phase, gb, b.wall - a.wall, b.user - a.user, b.sys - a.sys, (b.sys - a.sys) / gb,
              b.machine_sys - a.machine_sys);
}

int open_scratch(const std::string& dir, bool direct) {
  std::string pattern = dir + "/scratch-io-bench-XXXXXX";
  const int fd = mkostemp(pattern.data(), direct ? O_DIRECT : 0);
  if (fd < 0) {
    std::perror(dir.c_str());
    std::exit(2);
  }
  unlink(pattern.c_str());
  return fd;
}

void must(bool ok, const char* what) {
  if (!ok) {
    std::perror(what);
    std::exit(2);
  }
}

unsigned long run(const std::string& dir, std::size_t blocks, const std::string& method) {
  const bool huge = method == "direct-huge", direct = method == "direct" || huge, drop = method == "dropbehind";
  const int fd = open_scratch(dir, direct);
  const gdp::io::AlignedBytes bytes(kBlock, huge);
  unsigned char* buffer = bytes.data();
  const double gb = static_cast<double>(blocks * kBlock) / 1e9;
  gdp::io::DropBehind behind(drop ? kWindow : 0);
  Sample a = now();
  for (std::size_t i = 0; i < blocks; ++i) {
    std::memset(buffer, static_cast<int>(i & 0xff), kBlock);
    must(write(fd, buffer, kBlock) == static_cast<ssize_t>(kBlock), "write");
    must(behind.wrote(fd, (i + 1) * kBlock), "sync_file_range");
  }
  Sample b = now();
  report(method.c_str(), "write", a, b, gb);
  must(lseek(fd, 0, SEEK_SET) == 0, "lseek");
  if (drop) posix_fadvise(fd, 0, 0, POSIX_FADV_SEQUENTIAL);
  behind.restart(0);
  unsigned long sum = 0;
  a = now();
  for (std::size_t i = 0; i < blocks; ++i) {
    must(read(fd, buffer, kBlock) == static_cast<ssize_t>(kBlock), "read");
    sum += buffer[i % kBlock];
    behind.read(fd, (i + 1) * kBlock);
  }
  b = now();
  report(method.c_str(), "read", a, b, gb);
  close(fd);
  return sum;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: scratch_io_bench DIR GB [buffered|dropbehind|direct|direct-huge ...]\n");
    return 2;
  }
  const std::string dir = argv[1];
  const auto blocks = static_cast<std::size_t>(std::atof(argv[2]) * 1e9 / kBlock);
  std::vector<std::string> methods(argv + 3, argv + argc);
  if (methods.empty()) methods = {"buffered", "dropbehind", "direct", "direct-huge"};
  unsigned long sum = 0;
  for (const std::string& m : methods) sum += run(dir, blocks, m);
  std::printf("(checksum %lu)\n", sum);
  return 0;
}
