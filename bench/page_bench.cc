// CPU seconds per GiB of fresh anonymous memory, by page size and mapping method (util/big_pages.h).
//
// Usage: page_bench GIB ROUNDS [METHOD...]   (methods: 4k 4k-populate huge huge-populate; default all)
// Each round maps GIB gibibytes, writes one byte per 64-byte line of it (as a row store's first pass
// does, every page first touched by the writer) and unmaps it; it prints the round's wall seconds,
// this process's user and system CPU seconds and minor faults. Round 0 takes memory the process
// never had; later rounds take what the previous round freed a moment before (warm, where the
// system recycles it). Methods:
//   4k             plain mmap, faulted in 4 KB at a time by the writes
//   4k-populate    plain mmap, mapped 4 MB at a time ahead of the writes (MADV_POPULATE_WRITE)
//   huge           util::map_big (2 MiB-aligned, MADV_HUGEPAGE), faulted in by the writes
//   huge-populate  util::map_big, mapped ahead with util::populate (what ScratchMemory did)
// docs/how-streaming-works.md, "Huge pages", has the figures of the development VM.
#include <sys/mman.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "util/big_pages.h"

namespace {

struct Usage {
  double user, sys;
  long faults;
};

Usage usage() {
  rusage r{};
  getrusage(RUSAGE_SELF, &r);
  return {r.ru_utime.tv_sec + r.ru_utime.tv_usec * 1e-6, r.ru_stime.tv_sec + r.ru_stime.tv_usec * 1e-6, r.ru_minflt};
}

void round(const std::string& method, std::size_t bytes, int r) {
  constexpr std::size_t kStep = std::size_t{4} << 20;
  const bool huge = method.rfind("huge", 0) == 0, populate = method.find("populate") != std::string::npos;
  const Usage u0 = usage();
  const auto t0 = std::chrono::steady_clock::now();
  unsigned char* p = nullptr;
  if (huge) {
    p = static_cast<unsigned char*>(gdp::util::map_big(bytes));
  } else {
    void* q = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (q == MAP_FAILED) std::exit(1);
    p = static_cast<unsigned char*>(q);
  }
  for (std::size_t at = 0; at < bytes; at += kStep) {
    const std::size_t n = std::min(kStep, bytes - at);
    if (populate) gdp::util::populate(p + at, n);
    for (std::size_t k = 0; k < n; k += 64) p[at + k] = static_cast<unsigned char>(k);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (huge) gdp::util::unmap_big(p, bytes);
  else munmap(p, bytes);
  const Usage u1 = usage();
  const double gib = static_cast<double>(bytes) / double(1 << 30);
  std::printf("%-14s round %d: wall %.2f s, user %.2f s, sys %.2f s, CPU %.2f s per GiB, %ld minor faults\n",
              method.c_str(), r, wall, u1.user - u0.user, u1.sys - u0.sys,
              (u1.user - u0.user + u1.sys - u0.sys) / gib, u1.faults - u0.faults);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: page_bench GIB ROUNDS [4k|4k-populate|huge|huge-populate ...]\n");
    return 2;
  }
  const auto bytes = static_cast<std::size_t>(std::atof(argv[1]) * double(1 << 30));
  const int rounds = std::atoi(argv[2]);
  std::vector<std::string> methods(argv + 3, argv + argc);
  if (methods.empty()) methods = {"4k", "4k-populate", "huge", "huge-populate"};
  for (const std::string& m : methods)
    for (int r = 0; r < rounds; ++r) round(m, bytes, r);
}
