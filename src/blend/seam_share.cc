// Under mpirun: rank 0's label plane broadcast to the other ranks, and the per-layer overlaps reduced over the ranks.
#include "blend/seam_share.h"

#include <algorithm>
#include <cstddef>

#include "bands/mpi_transport.h"
#include "gdp/mpi_run.h"

namespace gdp::blending {
namespace {

enum Tag { kReady = 1, kLabels, kOverlaps };

}  // namespace

bool several_ranks() { return MpiRun::size() > 1; }

void share_labels(LabelPlane& labels) {
  if (!several_ranks()) return;
  bands::MpiHub hub(1);  // the ranks' ordered collectives (bands/transport.h)
  bands::Transport& net = hub.own();
  const std::size_t W = static_cast<std::size_t>(labels.width());
  const int H = labels.height();
  const bool root = net.rank() == 0;
  const int block = std::max(1, std::min(H, static_cast<int>((std::size_t{4} << 20) / (sizeof(Label) * W))));
  std::vector<Label> rows(block * W);
  for (int y0 = 0; y0 < H; y0 += block) {
    const int n = std::min(block, H - y0);
    const auto row = [&](int y) { return std::span<Label>(rows).subspan(y * W, W); };
    bands::ByteWriter out;
    if (root) {
      for (int y = 0; y < n; ++y) labels.read_row(y0 + y, row(y));
      out.put(rows.data(), n * W);
    }
    // Every rank has taken the last block before rank 0 sends the next: one block in flight.
    bands::gather(net, kReady, {});
    bands::ByteReader in(bands::broadcast(net, kLabels, std::move(out.bytes)));
    if (root) continue;
    in.get(rows.data(), n * W);
    in.finish();
    for (int y = 0; y < n; ++y) labels.write_row(y0 + y, row(y));
  }
}

void gather_overlaps(std::vector<signed char>& overlaps) {
  if (!several_ranks() || overlaps.empty()) return;
  bands::MpiHub hub(1);
  bands::ByteWriter mine;
  mine.io(overlaps);
  std::vector<signed char> part;
  for (bands::Bytes& bytes : bands::all_gather(hub.own(), kOverlaps, std::move(mine.bytes))) {
    bands::ByteReader in(std::move(bytes));
    part.resize(overlaps.size());
    in.io_sized(std::span(part));
    in.finish();
    for (std::size_t k = 0; k < overlaps.size(); ++k) overlaps[k] = std::max(overlaps[k], part[k]);
  }
}

}  // namespace gdp::blending
