// Under mpirun: rank 0's label plane broadcast to the other ranks, and the per-layer overlaps reduced over the ranks.
#include "blend/seam_share.h"

#include <mpi.h>

#include <algorithm>

#include "mpi/wait.h"
#include "gdp/mpi_run.h"

namespace gdp::blending {

bool several_ranks() { return MpiRun::size() > 1; }

void share_labels(LabelPlane& labels) {
  if (!several_ranks()) return;
  const int W = labels.width(), H = labels.height();
  const bool root = MpiRun::rank() == 0;
  const int block = std::max(1, std::min(H, static_cast<int>((std::size_t{4} << 20) / (sizeof(Label) * W))));
  std::vector<Label> rows(static_cast<std::size_t>(block) * W);
  for (int y0 = 0; y0 < H; y0 += block) {
    const int n = std::min(block, H - y0);
    if (root)
      for (int y = 0; y < n; ++y) labels.read_row(y0 + y, std::span<Label>(rows).subspan(static_cast<std::size_t>(y) * W, W));
    MPI_Request request;
    MPI_Ibcast(rows.data(), static_cast<int>(static_cast<std::size_t>(n) * W * sizeof(Label)), MPI_BYTE, 0,
               MPI_COMM_WORLD, &request);
    mpi::wait_request(request);
    if (!root)
      for (int y = 0; y < n; ++y) labels.write_row(y0 + y, std::span<const Label>(rows).subspan(static_cast<std::size_t>(y) * W, W));
  }
}

void gather_overlaps(std::vector<signed char>& overlaps) {
  if (!several_ranks() || overlaps.empty()) return;
  std::vector<signed char> mine = overlaps;
  MPI_Request request;
  MPI_Iallreduce(mine.data(), overlaps.data(), static_cast<int>(overlaps.size()), MPI_SIGNED_CHAR, MPI_MAX,
                 MPI_COMM_WORLD, &request);
  mpi::wait_request(request);
}

}  // namespace gdp::blending
