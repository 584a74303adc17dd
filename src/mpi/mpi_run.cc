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

void agree_before_solving(const std::string& error, const std::vector<long long>& fingerprint) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  const int mine = error.empty() ? ranks : rank;
  int first_bad = ranks;
  MPI_Allreduce(&mine, &first_bad, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  std::vector<long long> low(fingerprint.size()), high(fingerprint.size());
  const int n = static_cast<int>(fingerprint.size());
  MPI_Allreduce(fingerprint.data(), low.data(), n, MPI_LONG_LONG, MPI_MIN, MPI_COMM_WORLD);
  MPI_Allreduce(fingerprint.data(), high.data(), n, MPI_LONG_LONG, MPI_MAX, MPI_COMM_WORLD);
  if (first_bad < ranks) {
    int length = static_cast<int>(error.size());
    MPI_Bcast(&length, 1, MPI_INT, first_bad, MPI_COMM_WORLD);
    std::string text = error;
    text.resize(static_cast<std::size_t>(length));
    MPI_Bcast(text.data(), length, MPI_CHAR, first_bad, MPI_COMM_WORLD);
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
  // Open MPI's blocking calls left (the collective check, MPI_Finalize after every rank has
  // arrived) yield the core while they wait instead of spinning on it; a value the user set stays
  // (docs/how-bands-work.md).
  setenv("OMPI_MCA_mpi_yield_when_idle", "1", 0);
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
