// All ranks compare their setup before a distributed band solve: MPI_Allreduce of ok flags and fingerprints.
#include "bands/mpi_agree.h"

#include <mpi.h>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "gdp/mpi_run.h"

namespace gdp::bands {


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
    mark_failed_together();
    throw UsageError(fmt::format("rank {}: {}", first_bad, text));
  }
  if (low != high) {
    mark_failed_together();
    throw UsageError("the ranks disagree on the image or the solver options: every rank must be given the same "
                     "command");
  }
}

}  // namespace gdp::bands
