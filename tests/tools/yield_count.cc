// Test preload: counts the sched_yield calls made from libgdp and Open MPI, printed on stderr at exit.
#include <dlfcn.h>
#include <sched.h>

#include <atomic>
#include <cstdio>
#include <cstring>
#include <initializer_list>

namespace {

std::atomic<long> yields{0};

// True when `address` lies in libgdp or in Open MPI (libmpi, libopen-pal, its mca_ plugins).
bool from_gdp_or_mpi(void* address) {
  Dl_info info;
  if (dladdr(address, &info) == 0 || info.dli_fname == nullptr) return false;
  for (const char* name : {"libgdp", "libmpi", "libopen-pal", "libopen-rte", "mca_"})
    if (std::strstr(info.dli_fname, name)) return true;
  return false;
}

__attribute__((destructor)) void report() { std::fprintf(stderr, "sched_yield calls from gdp or MPI: %ld\n", yields.load()); }

}  // namespace

extern "C" int sched_yield() {
  static auto real = reinterpret_cast<int (*)()>(dlsym(RTLD_NEXT, "sched_yield"));
  if (from_gdp_or_mpi(__builtin_return_address(0))) ++yields;
  return real();
}
