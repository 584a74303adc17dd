// CPU seconds per GiB of in-memory scratch, written and read back whole, by how it is kept.
//
// Usage: scratch_memory_bench GIB ROUNDS [METHOD...]   (default: anon memfd-pread memfd-mmap)
// Each round writes GIB gibibytes in 256 KB blocks (a row store's file buffer) and reads them back in
// order into a 256 KB buffer, then frees them; it prints each pass's wall and CPU (user + sys)
// seconds per GiB and the minor faults. Round 0 takes memory the process never had; later rounds
// what the previous round freed a moment before. Methods:
//   anon         huge-page anonymous memory (util::map_big), mapped 4 MB ahead of the writer
//                (util::populate) and copied into and out of (the row stores before the memfd)
//   memfd-pread  a memfd written with pwrite and read with pread (schedule::RowStore now)
//   memfd-mmap   the same writes, read through a read-only shared mapping of the memfd
// docs/how-streaming-works.md, "Scratch in a memfd", has the figures of the development VM.
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "util/big_pages.h"

namespace {

constexpr std::size_t kBlock = std::size_t{256} << 10;

struct Usage {
  double cpu, wall;
  long faults;
};

Usage usage() {
  rusage r{};
  getrusage(RUSAGE_SELF, &r);
  const double cpu = r.ru_utime.tv_sec + r.ru_stime.tv_sec + (r.ru_utime.tv_usec + r.ru_stime.tv_usec) * 1e-6;
  return {cpu, std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(), r.ru_minflt};
}

void check(bool ok, const char* what) {
  if (ok) return;
  std::perror(what);
  std::exit(1);
}

// Writes `bytes` from `block` (then reads them back into it) the way `method` keeps them.
class Scratch {
 public:
  Scratch(const std::string& method, std::size_t bytes) : method_(method), bytes_(bytes) {
    if (method_ == "anon") {
      p_ = static_cast<unsigned char*>(gdp::util::map_big(bytes));
    } else {
      fd_ = memfd_create("scratch_memory_bench", MFD_CLOEXEC);
      check(fd_ >= 0, "memfd_create");
    }
  }
  ~Scratch() {
    if (p_ && method_ == "anon") gdp::util::unmap_big(p_, bytes_);
    else if (p_) munmap(p_, bytes_);
    if (fd_ >= 0) close(fd_);
  }
  void write(const unsigned char* block, std::size_t at, std::size_t n) {
    if (fd_ < 0) {
      constexpr std::size_t kStep = std::size_t{4} << 20;
      if (at % kStep == 0) gdp::util::populate(p_ + at, std::min(kStep, bytes_ - at));
      std::memcpy(p_ + at, block, n);
    } else {
      check(pwrite(fd_, block, n, static_cast<off_t>(at)) == static_cast<ssize_t>(n), "pwrite");
    }
  }
  void read(unsigned char* block, std::size_t at, std::size_t n) {
    if (method_ == "memfd-pread") {
      check(pread(fd_, block, n, static_cast<off_t>(at)) == static_cast<ssize_t>(n), "pread");
      return;
    }
    if (!p_) {
      void* q = mmap(nullptr, bytes_, PROT_READ, MAP_SHARED | MAP_POPULATE, fd_, 0);
      check(q != MAP_FAILED, "mmap");
      p_ = static_cast<unsigned char*>(q);
    }
    std::memcpy(block, p_ + at, n);
  }

 private:
  std::string method_;
  std::size_t bytes_;
  unsigned char* p_ = nullptr;
  int fd_ = -1;
};

void report(const char* pass, const Usage& a, const Usage& b, double gib) {
  std::printf("  %s: wall %.2f s, CPU %.2f s per GiB, %ld minor faults", pass, (b.wall - a.wall) / gib,
              (b.cpu - a.cpu) / gib, b.faults - a.faults);
}

void round(const std::string& method, std::size_t bytes, int r) {
  std::vector<unsigned char> block(kBlock);
  for (std::size_t k = 0; k < kBlock; ++k) block[k] = static_cast<unsigned char>(k * 7 + r);
  const Usage u0 = usage();
  unsigned sum = 0;
  {
    Scratch s(method, bytes);
    for (std::size_t at = 0; at < bytes; at += kBlock) s.write(block.data(), at, std::min(kBlock, bytes - at));
    const Usage u1 = usage();
    for (std::size_t at = 0; at < bytes; at += kBlock) {
      s.read(block.data(), at, std::min(kBlock, bytes - at));
      sum += block[at % 4096];
    }
    const Usage u2 = usage();
    const double gib = static_cast<double>(bytes) / double(1 << 30);
    std::printf("%-12s round %d:", method.c_str(), r);
    report("write", u0, u1, gib);
    report("; read", u1, u2, gib);
  }
  std::printf(" (%u)\n", sum & 1);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: scratch_memory_bench GIB ROUNDS [anon|memfd-pread|memfd-mmap ...]\n");
    return 2;
  }
  const auto bytes = static_cast<std::size_t>(std::atof(argv[1]) * double(1 << 30));
  const int rounds = std::atoi(argv[2]);
  std::vector<std::string> methods(argv + 3, argv + argc);
  if (methods.empty()) methods = {"anon", "memfd-pread", "memfd-mmap"};
  for (int r = 0; r < rounds; ++r)
    for (const std::string& m : methods) round(m, bytes, r);
}
