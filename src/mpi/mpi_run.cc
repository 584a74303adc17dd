// gdp::MpiRun: starts and ends MPI when the process was launched by mpirun; the ranks' agreement before a solve.
#include "gdp/mpi_run.h"

#include <mpi.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>

#include <fmt/format.h>

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

namespace {

// MPI_Allreduce and MPI_Bcast on MPI_COMM_WORLD, waited for without spinning (the ranks may come
// to them seconds apart).
void all_reduce(const void* in, void* out, int n, MPI_Datatype type, MPI_Op op) {
  MPI_Request request;
  MPI_Iallreduce(in, out, n, type, op, MPI_COMM_WORLD, &request);
  wait_request(request);
}
void broadcast(void* data, int n, MPI_Datatype type, int root) {
  MPI_Request request;
  MPI_Ibcast(data, n, type, root, MPI_COMM_WORLD, &request);
  wait_request(request);
}

}  // namespace

void agree_before_solving(const std::string& error, const std::vector<long long>& fingerprint) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  const int mine = error.empty() ? ranks : rank;
  int first_bad = ranks;
  all_reduce(&mine, &first_bad, 1, MPI_INT, MPI_MIN);
  std::vector<long long> low(fingerprint.size()), high(fingerprint.size());
  const int n = static_cast<int>(fingerprint.size());
  all_reduce(fingerprint.data(), low.data(), n, MPI_LONG_LONG, MPI_MIN);
  all_reduce(fingerprint.data(), high.data(), n, MPI_LONG_LONG, MPI_MAX);
  if (first_bad < ranks) {
    int length = static_cast<int>(error.size());
    broadcast(&length, 1, MPI_INT, first_bad);
    std::string text = error;
    text.resize(static_cast<std::size_t>(length));
    broadcast(text.data(), length, MPI_CHAR, first_bad);
    together = true;
    throw UsageError(fmt::format("rank {}: {}", first_bad, text));
  }
  if (low != high) {
    together = true;
    throw UsageError("the ranks disagree on the image or the solver options: every rank must be given the same "
                     "command");
  }
}

}  // namespace mpi

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
