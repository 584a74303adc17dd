// gdp::MpiRun: starts and ends MPI when the process was launched by mpirun; the ranks' agreement before a solve.
#include "gdp/mpi_run.h"

#include <mpi.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bands/mpi_transport.h"
#include "bands/transport.h"
#include "gdp/cleanup.h"
#include "gdp/errors.h"
#include "mpi/ranks.h"
#include "mpi/wait.h"

namespace gdp {
namespace {

std::atomic<bool> started{false}, together{false};
int the_rank = 0, the_size = 1;

}  // namespace

namespace mpi {

void abort_ranks(const std::string& why) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  std::fprintf(stderr, "gdp: rank %d: %s\n", rank, why.c_str());
  std::fflush(stderr);
  cleanup::remove_tracked();  // MPI_Abort skips every destructor: this rank's temporary output goes now
  MPI_Abort(MPI_COMM_WORLD, 2);
  std::abort();  // MPI_Abort does not return
}

void agree_before_solving(const std::string& error, const std::vector<long long>& fingerprint) {
  std::vector<schedule::Bytes> all;
  {  // every rank's error and fingerprint on every rank (the hub waits for its sends before anyone throws)
    bands::MpiHub hub(1);
    schedule::ByteWriter mine;
    mine.io(std::vector<char>(error.begin(), error.end()));
    mine.io(fingerprint);
    all = bands::all_gather(hub.own(), /*tag*/ 1, std::move(mine.bytes));
  }
  bool same = true;
  for (std::size_t r = 0; r < all.size(); ++r) {
    schedule::ByteReader in(std::move(all[r]));
    std::vector<char> text;
    std::vector<long long> print;
    in.io(text);
    in.io(print);
    together = !text.empty();  // the lowest failing rank's error, else whether any fingerprint differs
    if (together) throw UsageError(fmt::format("rank {}: {}", r, std::string(text.begin(), text.end())));
    same = same && print == fingerprint;
  }
  together = !same;
  if (together)
    throw UsageError("the ranks disagree on the image or the solver options: every rank must be given the same "
                     "command");
}

}  // namespace mpi

namespace {

// Open MPI settings made before MPI_Init when every rank runs on this node (mpirun's
// OMPI_COMM_WORLD_LOCAL_SIZE equals OMPI_COMM_WORLD_SIZE): shared memory (the vader BTL, and the
// rank's own loopback) is then the only transport used, so the components for networks and their
// libraries are not opened (each rank's MPI_Init dlopens them and MPI_Finalize unmaps them; the
// PSM libraries' constructors sleep), nor hwloc's plugins for PCI, OpenCL and GL devices and its
// Linux I/O discovery, which only place network cards (on a virtual machine each read of a PCI
// device's config space takes milliseconds). What the user sets (the environment, mpirun --mca)
// stays; a value in an MCA parameter file is overridden (docs/how-bands-work.md, "mpirun's start-up").
void settle_one_node() {
  const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  const char* world = std::getenv("OMPI_COMM_WORLD_SIZE");
  if (!local || !world || std::string(local) != world) return;
  setenv("OMPI_MCA_pml", "ob1", 0);
  setenv("OMPI_MCA_btl", "self,vader", 0);
  setenv("HWLOC_PLUGINS_BLACKLIST", "hwloc_pci,hwloc_opencl,hwloc_gl,hwloc_xml_libxml", 0);
  setenv("HWLOC_COMPONENTS", "-linuxio", 0);
}

}  // namespace

bool MpiRun::launched() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") || std::getenv("PMIX_RANK");
}

MpiRun::MpiRun(int& argc, char**& argv) {
  if (!launched()) return;
  // Every MPI wait of gdp polls and sleeps (mpi/wait.h); Open MPI's own sched_yield in each poll
  // that finds nothing (on by default when a node is oversubscribed) would give each busy thread
  // on the rank's core a time slice per poll: band solves beside busy loops took twice as long. A
  // value the user set stays (docs/how-bands-work.md).
  setenv("OMPI_MCA_mpi_yield_when_idle", "0", 0);
  settle_one_node();
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_MULTIPLE, &provided);
  started = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &the_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &the_size);
  if (provided < MPI_THREAD_MULTIPLE && the_size > 1)
    mpi::abort_ranks("this MPI library does not provide MPI_THREAD_MULTIPLE, which the band schedule needs");
}

MpiRun::~MpiRun() {
  if (!started) return;
  // Ranks end at different times (rank 0 writes the rows the others sent): the first to finish
  // waits for the others here, without spinning, rather than in MPI_Finalize's fence, which
  // would hold a core for as long. Every rank that ends normally comes here (a failing one calls
  // MPI_Abort, which ends all).
  MPI_Request request;
  MPI_Ibarrier(MPI_COMM_WORLD, &request);
  mpi::wait_request(request);
  MPI_Finalize();
}

int MpiRun::rank() { return the_rank; }
int MpiRun::size() { return the_size; }
bool MpiRun::failed_together() { return together; }

void MpiRun::agree(const std::string& error) {
  if (the_size > 1) mpi::agree_before_solving(error, {});
  else if (!error.empty()) throw UsageError(error);
}

void MpiRun::abort(const std::string& why) {
  if (started) mpi::abort_ranks(why);
}

}  // namespace gdp
