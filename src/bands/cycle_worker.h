// One worker of a streamed solve (a band's channel group): rows in, V-cycles, mean shift, rows out; checkpoint lanes.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "bands/streamed_vcycle.h"
#include "gdp/errors.h"
#include "gdp/mpi_run.h"
#include "gdp/solver.h"
#include "io/checkpoint_dir.h"
#include "multigrid/input_rows.h"
#include "schedule/row_store.h"
#include "schedule/solve_parts.h"

namespace gdp::bands {

using schedule::CorruptState;
using schedule::RowStore;

// How far a worker got, saved with its state (docs/resume.md): in V-cycle `cycle` (from 0), pass
// 0 is the restriction pass with `rows` rows pushed, 1 the restriction pass done (the in-core
// tail solved), 2 the cycle's result stored for the next.
struct CycleMark {
  int cycle = 0, pass = 0, rows = 0;
  std::string describe(int height) const {
    if (pass == 0) return fmt::format("V-cycle {}: restriction pass, {} of {} rows", cycle + 1, rows, height);
    if (pass == 1) return fmt::format("V-cycle {}: restriction pass and in-core levels done", cycle + 1);
    return fmt::format("V-cycle {} done", cycle + 1);
  }
};

// Where a worker's rows come from and go (set by the driver): row j of its band's input into the
// V-cycle's slots (u and b: its channels, w and d: empty where it takes none), the input's sums
// (every band's: once the worker asks for no more input), and its own columns of result row j.
template <class T>
struct WorkerRows {
  std::function<void(int j, const typename StreamedVCycle<T>::Slots& to)> input;
  std::function<const multigrid::InputTotals&()> totals;
  std::function<void(int j, std::span<const T> u)> result;
};

// Channels [c0, c0 + n) of band `net.rank()`: the V-cycles of its StreamedVCycle on rows of the
// band's columns with their halo, the first cycle's from its input, later cycles' from the
// previous result (a row store), each result shifted to keep the input's mean (alpha == 0),
// V-cycles until `opt`'s count or tolerance, and the last result to `rows.result`.
template <class T>
class CycleWorker {
 public:
  CycleWorker(const multigrid::Operators<T>& ops, const BandLayout& layout, Transport& net, const SolverOptions& opt,
              CycleSettings s, int c0, int n, schedule::ResidualLog& log)
      : c0(c0), n(n), band(net.rank()), vcycle(ops, layout, net, (s.channels = n, s)), opt_(opt),
        singular_(ops.singular), log_(log), length_(layout.row_length(0, band)), height_(ops.levels[0].height) {
    if (cycles() > 1)
      carry_ = std::make_unique<RowStore<T>>(s.stores, static_cast<std::size_t>(n) * length_, height_,
                                             fmt::format("band{}-c{}-result", band, c0));
  }
  std::size_t carry_bytes() const { return carry_ ? carry_->bytes() : 0; }
  int height() const { return height_; }

  // Checkpoints (docs/resume.md): `at` is where the worker is, saved with its state (a restored
  // worker resumes there); `unit_done` (null: no checkpoint) is called after every `unit_rows` rows
  // of the first restriction pass, after every restriction pass (in-core levels included) and after
  // every V-cycle whose result is stored for the next.
  CycleMark at;
  int unit_rows = 1 << 30;
  std::function<void()> unit_done;
  // Everything the worker holds, written (ByteWriter) and read back (ByteReader) by the same steps:
  // where it is, its V-cycle's state, the carried result's length and the log's channels.
  template <class Archive>
  void state(Archive& a) {
    int version = kStateVersion;
    a.io(version);
    a.io(at);
    if (version != kStateVersion)  // a refusal of the whole checkpoint, not a corrupt file (docs/resume.md)
      throw InputError(fmt::format("--resume {}: saved by {} gdp (state version {}, this one reads {}): run again without "
                                   "--resume", opt_.checkpoint_dir.string(), version < kStateVersion ? "an older" : "another",
                                   version, kStateVersion));
    if (at.cycle < 0 || at.cycle >= cycles() || at.pass < 0 || at.pass > 2 || at.rows < 0 ||
        at.rows > height_)
      throw CorruptState("unknown position");
    vcycle.state(a);
    store_state(a, carry_.get());
    log_.state(a, c0, n);
  }

  // Throws util::Stopped once the solve is stopped.
  void run() {
    std::vector<T> u(static_cast<std::size_t>(n) * length_);  // a result row (every channel)
    std::vector<double> shift(n);
    const CycleMark from = at;  // restored, or the start
    for (int k = from.cycle; k < cycles(); ++k) {
      const int pass = k == from.cycle ? from.pass : 0;
      if (pass == 2) continue;  // this cycle's result is stored: on to the next
      if (pass == 0) restriction_pass(k, k == from.cycle ? from.rows : 0);
      const multigrid::InputTotals& sums = rows.totals();
      for (int c = 0; c < n; ++c) {
        if (k == 0) {
          log_.set_rhs_norm(c0 + c, std::sqrt(sums.rhs_norms2[c0 + c]));
          log_.initial(c0 + c, vcycle.initial_norm(c));
        }
        shift[c] = schedule::mean_shift(singular_, sums.weighted_sums[c0 + c], sums.weight_total,
                                        vcycle.probe(c).dots);
      }
      const bool surely_last = k + 1 == cycles();
      if (carry_ && !surely_last) carry_->clear();
      for (int j = 0; j < height_; ++j) {
        vcycle.pull(u);
        for (int c = 0; c < n; ++c) schedule::shift_mean(std::span<T>(u).subspan(static_cast<std::size_t>(c) * length_, length_), shift[c]);
        if (!surely_last) carry_->append(u);
        else rows.result(j, u);
      }
      bool converged = opt_.tolerance > 0.0;
      for (int c = 0; c < n; ++c) {
        log_.cycle(c0 + c, vcycle.final_norm(c), vcycle.probe(c));
        converged = converged && log_.settled(c0 + c, opt_.tolerance);
      }
      if (surely_last) return;
      if (converged) {  // the carried result is the answer (every worker sees the same sums)
        carry_->rewind();
        for (int j = 0; j < height_; ++j) {
          carry_->read(u);
          rows.result(j, u);
        }
        return;
      }
      save({k, 2, 0});
    }
  }

  WorkerRows<T> rows;
  const int c0, n, band;
  StreamedVCycle<T> vcycle;

 private:
  int cycles() const { return opt_.cycle_cap(); }

  // Pushes cycle k's rows from `first` on (the first cycle's from the input, later ones' from the
  // previous result).
  void restriction_pass(int k, int first) {
    if (first == 0) {
      vcycle.begin_cycle();
      if (carry_) carry_->rewind();
    }
    for (int j = first; j < height_; ++j) {  // into the V-cycle's ring
      const auto slots = vcycle.next_row();
      if (k > 0) carry_->read(slots.u);
      else rows.input(j, slots);
      vcycle.push();
      if (k == 0 && (j + 1) % unit_rows == 0 && j + 1 < height_) save({k, 0, j + 1});
    }
    save({k, 1, 0});
  }

  void save(CycleMark m) {
    at = m;
    if (unit_done) unit_done();
  }
  const SolverOptions& opt_;
  bool singular_;
  schedule::ResidualLog& log_;
  int length_, height_;
  std::unique_ptr<RowStore<T>> carry_;
  static constexpr int kStateVersion = 3;  // 2: the gathered level is a Level; 3: rings of 2(G + k) + 10 rows
};

// The streamed solve's checkpoint (docs/resume.md): one lane per worker (band, channel group) of
// this process. Lane numbers are global: band b's channel group g is lane b * groups + g, so that
// ranks sharing a directory never write the same files (each rank keeps its own manifest, rank 0's
// named "manifest"). The problem's sizes, the band count and the rank count are in every manifest: a
// resume with other counts is refused, naming them.
class StreamedCheckpoint {
 public:
  // In opt.checkpoint_dir (its group count replaces `groups` when resuming); scratch kept there
  // under each lane's names.
  template <class T>
  StreamedCheckpoint(const SolverOptions& opt, const multigrid::Operators<T>& ops, int channels, int bands, int local,
                     int first, int& groups, schedule::StorePolicy& stores)
      : first_(first), local_(local) {
    const std::string sizes = fmt::format("{} {} {} {} {} {} | {} bands on {} ranks", ops.levels[0].width,
                                          ops.levels[0].height, channels, ops.count(), sizeof(T),
                                          stores.half.any() ? "half" : "native", bands, MpiRun::size());
    int lanes = local * groups;
    cp_ = std::make_unique<io::Checkpoint>(opt, sizes, lanes, first * groups, MpiRun::rank(), lanes * MpiRun::size());
    if (lanes < 1 || lanes % local != 0)
      throw InputError(fmt::format("--resume {}: the manifest is corrupt (lanes)", opt.checkpoint_dir.string()));
    groups = groups_ = lanes / local;
    stores.keep_dir = opt.checkpoint_dir;
  }
  // Resuming: the bands of a plan go back to the newest save they all made (a kill may have come
  // between two bands' saves; none is two saves ahead, StreamedVCycle::saved), agreed on through
  // `net`, this process's first band (under mpirun, ranks are every local_-th worker of it).
  void agree(Transport& net) {
    if (!cp_->resuming()) return;
    for (int g = 0; g < groups_; ++g) {
      ByteWriter mine;  // the saves on disk of this process's lanes (`all`: every rank's lanes')
      for (int i = 0; i < local_; ++i) mine.io(cp_->generations(lane(i, g)));
      std::vector<std::vector<long long>> all;
      for (Bytes& part : all_gather(net, kGenerations, std::move(mine.bytes), local_))
        for (ByteReader in(std::move(part)); !in.at_end();) in.io(all.emplace_back());
      long long common = 0;  // every lane has 0 (a fresh start)
      for (long long at : all[0])
        if (std::ranges::all_of(all, [at](const auto& saves) { return std::ranges::binary_search(saves, at); })) common = at;
      for (int i = 0; i < local_; ++i) cp_->choose(lane(i, g), common);
    }
  }
  // Row stores of local band i's group g are named with this prefix.
  std::string prefix(int i, int g) const { return fmt::format("lane{}-", lane(i, g)); }
  // Local band i's group g (worker, V-cycle) saves here; when resuming, its state is restored.
  template <class T>
  void attach(CycleWorker<T>& worker, int i, int g, int width) {
    // A unit of the first pass stores about four times what a save writes (the rows held). The
    // bands of a plan must save at the same rows: theirs is a function of the plan, about four
    // times the rows its levels' rings hold (twice level 0's), not of the band.
    const BandLayout& plan = worker.vcycle.layout();
    const double row_bytes = 2.0 * worker.n * width * sizeof(T);
    const double rows_held = plan.single ? static_cast<double>(worker.vcycle.bytes().window) / row_bytes
                                         : 2.0 * plan.ring_rows();
    const int rows = static_cast<int>(std::min(1e9, 4.0 * rows_held)), lane = this->lane(i, g);
    worker.unit_rows = std::max(1, cp_->unit_rows(std::max(16, rows)));
    worker.unit_done = [this, &worker, lane] {
      ByteWriter out;
      worker.state(out);
      cp_->save(lane, {out.bytes.begin(), out.bytes.end()}, worker.at.describe(worker.height()));
      worker.vcycle.saved();  // every band of the plan has saved
    };
    const std::optional<std::string> saved = cp_->resuming() ? cp_->load(lane) : std::nullopt;
    if (!saved) return;
    try {
      ByteReader in(Bytes(saved->begin(), saved->end()));
      worker.state(in);
      in.finish();
    } catch (const CorruptState& e) {
      throw InputError(fmt::format("--resume {}: {} is corrupt ({})", cp_->dir().string(), cp_->state_name(lane), e.what()));
    }
  }

 private:
  int lane(int i, int g) const { return (first_ + i) * groups_ + g; }
  std::unique_ptr<io::Checkpoint> cp_;
  int first_, local_, groups_ = 1;
};

}  // namespace gdp::bands
