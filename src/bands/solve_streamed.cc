// The streamed solve (streaming and bands alike): workers (band, channel group) on threads make their
// input rows and put their results, which the caller's thread writes; under mpirun, every rank reads,
// solves and writes its share of the columns.
#include "bands/solve_streamed.h"

#include <algorithm>
#include <deque>
#include <mutex>

#include <fmt/format.h>

#include "bands/cycle_worker.h"
#include "bands/incore_worker.h"
#include "bands/mpi_transport.h"
#include "bands/streamed_vcycle.h"
#include "gdp/errors.h"
#include "gdp/mpi_run.h"
#include "mpi/ranks.h"
#include "schedule/input_ring.h"
#include "util/seconds.h"
#include "multigrid/input_rows.h"
#include "util/env_int.h"
#include "util/recycle_pool.h"

namespace gdp::bands {

using multigrid::InputTotals;

namespace {

// Columns of the input a rank reads beyond its bands' rows: the right-hand side of a column
// reads the guidance of the columns within two of it.
constexpr int kInputMargin = 4;

// Input sums as message parts and back (Archive: a ByteWriter or a ByteReader).
template <class Archive, class Totals>
void io(Archive& a, Totals& t) {
  a.io(t.weighted_sums);
  a.io(t.rhs_norms2);
  a.io(t.weight_total);
}

// The input sums of all bands, added in band order (the same bits however the bands are spread
// over processes) from this process's bands' sums: every rank's go to every rank (one rank:
// nothing to send).
InputTotals exchange_totals(const std::vector<InputTotals>& local, Transport& net, int step) {
  ByteWriter mine;
  for (const InputTotals& t : local) io(mine, t);
  InputTotals total;
  for (Bytes& part : all_gather(net, kTotals, std::move(mine.bytes), step)) {
    ByteReader r(std::move(part));
    while (!r.at_end()) {
      InputTotals t;
      io(r, t);
      total.add(t);
    }
  }
  return total;
}

// Columns [origin, origin + out.size()) of a full row of n samples into `out`: wrapped on periodic
// rows, zero outside the row otherwise (copied in runs).
template <class T>
void cut(const T* row, int n, bool periodic, int origin, std::span<T> out) {
  const int length = static_cast<int>(out.size());
  for (int x = 0; x < length;) {
    const int i = periodic ? fem::wrap_index(origin + x, n) : origin + x;
    const int run = i < 0 ? std::min(length - x, -i) : i >= n ? length - x : std::min(length - x, n - i);
    if (i < 0 || i >= n) std::fill_n(out.begin() + x, run, T(0));
    else std::copy_n(row + i, run, out.begin() + x);
    x += run;
  }
}

// The columns bands [first, last] read: their rows' (own columns and halos) and the guidance
// kInputMargin beyond them; whole rows where that would wrap around a periodic image's edge, and
// on the sphere, where the right-hand side of the first and last rows reads the guidance across
// the fold, at the mirror image's columns. A planar image's edges clip them.
struct InputWindow {
  std::pair<int, int> rows, guidance;
  bool whole = false;
};

InputWindow input_window(const BandLayout& layout, int first, int last, int w) {
  const int from = layout.origin(0, first), to = layout.origin(0, last) + layout.row_length(0, last);
  if (layout.folded || (layout.periodic && (from - kInputMargin < 0 || to + kInputMargin > w)))
    return {{0, w}, {0, w}, true};
  return {{std::max(0, from), std::min(w, to)}, {std::max(0, from - kInputMargin), std::min(w, to + kInputMargin)}};
}

// What a solve sets up before its workers start: the problem, the column plan (in-core, where there
// is one level or --in-core asks for it: one band of whole levels; streaming: one band; else
// opt.bands per process) and this process's workers: bands [first, first + local) of the plan (all
// of them on threads; under mpirun this rank's opt.bands, one without --bands), each in `groups`
// channel groups (up to one a channel, two threads left to the codecs), then their checkpoint
// (which may set the group count, resuming), hubs and logs. Channels are independent problems: a
// group's bands talk among themselves only (a hub each; under mpirun one group). A single band on
// more than one thread takes one group per channel even where that leaves the codecs no core of
// their own: else its one worker does every V-cycle sample while the other cores wait
// (docs/scaling.md, "1 gigapixel on the 2-core machine"). In-core: a group per two threads (the two
// smooth one channel, multigrid::PassPair: one set of planes where a group per thread took two).
template <class T>
struct Team {
  Team(GuidanceSource& source, const SolverOptions& opt, SolveSummary& summary, RowWriter& out);
  std::unique_ptr<schedule::Problem<T>> problem;
  BandLayout layout;
  CycleSettings settings;
  bool incore = false;
  std::vector<std::unique_ptr<ThreadHub>> hubs;    // per channel group (under mpirun one MpiHub)
  std::unique_ptr<StreamedCheckpoint> checkpoint;  // with --checkpoint
  std::vector<schedule::ResidualLog> logs;         // per local band, all channels (band 0's lines are kept)
  int first = 0, local = 1, groups = 1;
  void abort(const std::string& why) { for (auto& hub : hubs) hub->stop(why); }
};

template <class T>
Team<T>::Team(GuidanceSource& source, const SolverOptions& opt, SolveSummary& summary, RowWriter& out) {
  // Under mpirun every rank sets up the same problem; they compare before anyone starts solving.
  bool distributed = MpiRun::size() > 1;
  const int per_process = opt.schedule == Schedule::Bands ? opt.bands : 1, channels = source.channels();
  std::string setup_error;
  try {
    problem = std::make_unique<schedule::Problem<T>>(source, opt, summary);
    const multigrid::Operators<T>& ops = problem->ops;
    incore = opt.schedule == Schedule::InCore || ops.count() == 1;
    const int whole_from = incore ? 0 : schedule::first_whole_level(ops, channels, opt.incore_bytes);
    const int pre = opt.sweeps, post = opt.post_sweeps, total_bands = per_process * MpiRun::size();
    layout = total_bands == 1 || incore ? single_band_layout(problem->hierarchy, pre, post, whole_from)
                                        : make_band_layout(problem->hierarchy, total_bands, pre, post, whole_from);
  } catch (const Error& e) {
    if (!distributed) throw;
    setup_error = e.what();
  }
  if (distributed)
    mpi::agree_before_solving(setup_error, {source.width(), source.height(), channels, per_process, opt.sweeps,
                                       opt.post_sweeps, opt.vcycles, opt.max_vcycles, static_cast<long long>(opt.tolerance * 1e12),
                                       static_cast<long long>(sizeof(T)), problem ? problem->ops.count() : -1});
  distributed = distributed && !incore;  // (one level: every rank solves it whole)
  settings = cycle_settings(opt, problem->ops.singular, source.has_weights());
  local = distributed ? per_process : layout.bands;
  if (distributed) {  // this rank's bands, a contiguous share: it writes their own columns, reads their rows'
    hubs.push_back(std::make_unique<MpiHub>(local));
    first = hubs[0]->first();
    const InputWindow window = input_window(layout, first, first + local - 1, source.width());
    if (!window.whole) source.set_columns(window.guidance.first, window.guidance.second);
    out.set_columns(layout.begin(0, first), layout.end(0, first + local - 1));
  } else {
    const int spare = incore ? opt.threads / 2 : local == 1 && opt.threads > 1 ? channels : (opt.threads - 2) / local;
    groups = std::clamp(spare, 1, channels);
  }
  if (!opt.checkpoint_dir.empty() && !incore)
    checkpoint = std::make_unique<StreamedCheckpoint>(opt, problem->ops, channels, layout.bands, local, first, groups,
                                                      settings.stores);
  for (int g = 0; g < groups && !distributed; ++g) hubs.push_back(std::make_unique<ThreadHub>(layout.bands));
  for (int i = 0; i < local; ++i) logs.emplace_back(channels, first + i == 0 && static_cast<bool>(opt.log));
  if (checkpoint) checkpoint->agree(hubs[0]->own());
}

// The input units (one per local band where the source splits, else one for all) and their readers:
// each band's workers.
template <class T>
std::vector<typename schedule::InputRing<T>::Unit> input_units(const GuidanceSource& source, const Team<T>& team) {
  const BandLayout& layout = team.layout;
  const int count = source.splits() && !layout.folded ? team.local : 1;
  std::vector<typename schedule::InputRing<T>::Unit> units;
  for (int l = 0; l < count; ++l) {
    const int first = team.first + l * team.local / count, last = team.first + (l + 1) * team.local / count;
    const InputWindow window = input_window(layout, first, last - 1, source.width());
    units.push_back({{}, window.rows, window.guidance, (last - first) * team.groups});
    for (int i = first; i < last; ++i) units.back().sums.emplace_back(layout.begin(0, i), layout.end(0, i));
  }
  return units;
}

// Result rows of every local worker put together, from the first not yet written on, as many as the
// workers put: a worker waits for the writing only while `slots` rows are ahead of it and every
// worker of its channel group (every worker it exchanges with here) has put the next row to write,
// so that the writing then waits for no worker that waits for it (docs/how-bands-work.md, "Why a
// streamed solve cannot hang"). Tests set `slots` to 1 (GDP_RESULT_ROWS). Wake-ups are batched
// (docs/multigrid.md): a worker that had to wait goes on once `slack` rows more are written; the
// writing, once it had to wait, once `slack` rows more are put, but row by row for a group with a
// worker `slots - slack` rows ahead (one that may wait for the writing holds no row back).
class Results {
 public:
  Results(schedule::Marks& marks, int workers, int groups, std::size_t row)
      : marks_(marks), written_(marks.add(1)), put_(marks.add(workers)), workers_(workers), groups_(groups),
        row_(row), slots_(std::max(1, util::env_int("GDP_RESULT_ROWS", 64))), slack_(slots_ / 4) {}
  // Worker k's row j (whole rows: it fills its columns; rows in order), then put(k, j).
  float* row(int k, int j) {
    int ahead = slots_;  // then slots_ - slack_, once it waits
    marks_.wait([&](std::vector<int>& m) {
      // A worker of k's group has not put the next row to write:
      const bool lags = puts(m, k % groups_).first <= m[written_];
      const bool go = lags || j < m[written_] + ahead;
      ahead = slots_ - slack_;
      return go;
    });
    const std::lock_guard lock(mutex_);
    while (first_ + static_cast<int>(rows_.size()) <= j) {
      rows_.push_back(spare_.take());
      rows_.back().resize(row_);
    }
    return rows_[j - first_].data();
  }
  void put(int k, int j) { marks_.set(put_ + k, j + 1); }
  // The calling thread: row j (of h) to `out` once every worker put it.
  void write(int j, int h, RowWriter& out) {
    const int until = std::min(j + slack_, h - 1);
    bool waited = false;
    marks_.wait([&](std::vector<int>& m) {
      bool row_put = true, batch_put = true;  // row j by every worker; `until` by every group but those ahead
      for (int g = 0; g < groups_; ++g) {
        const auto [lo, hi] = puts(m, g);
        row_put = row_put && lo > j;
        batch_put = batch_put && (lo > until || hi >= j + slots_ - slack_);
      }
      const bool go = row_put && (!waited || batch_put);
      waited = true;
      return go;
    });
    std::vector<float> row;  // every worker has put it: none comes back to it
    {
      const std::lock_guard lock(mutex_);
      row = std::move(rows_.front());
      rows_.pop_front();
      ++first_;
    }
    out.write_row(j, row);
    spare_.give(std::move(row));
    marks_.set(written_, j + 1);
  }

 private:
  // The fewest and the most rows a worker of group g has put.
  std::pair<int, int> puts(const std::vector<int>& m, int g) const {
    std::pair<int, int> range{m[put_ + g], m[put_ + g]};
    for (int i = g + groups_; i < workers_; i += groups_)
      range = {std::min(range.first, m[put_ + i]), std::max(range.second, m[put_ + i])};
    return range;
  }

  schedule::Marks& marks_;
  const int written_, put_, workers_, groups_;  // marks: rows written, rows each worker put
  const std::size_t row_;
  int slots_, slack_, first_ = 0;  // rows_[i] is row first_ + i
  std::mutex mutex_;
  std::deque<std::vector<float>> rows_;
  util::RecyclePool<std::vector<float>> spare_;  // rows written, for reuse
};

}  // namespace

template <class T>
void solve_streamed(GuidanceSource& source, const SolverOptions& opt, RowWriter& out, SolveSummary& summary) {
  Team<T> team(source, opt, summary, out);
  const multigrid::Operators<T>& ops = team.problem->ops;
  const int channels = source.channels(), w = source.width(), h = source.height();
  const BandLayout& layout = team.layout;
  const auto t_start = util::SteadyClock::now();
  summary.schedule = team.incore ? "in-core" : layout.single ? "streaming" : "bands";
  summary.streamed_levels = layout.banded_levels();
  CycleSettings& settings = team.settings;

  // Rows between the threads: the input ring, made by the workers that read it; the input's sums
  // (mark `summed`: known); the result rows.
  schedule::Marks marks;
  const auto units = input_units(source, team);
  schedule::InputRing<T> input(source, team.problem->hierarchy, units, marks, opt.progress);
  const int count = team.local * team.groups, summed = marks.add(1);
  InputTotals totals;
  Results results(marks, count, team.groups, static_cast<std::size_t>(channels) * w);
  InCoreShared<T> shared{marks, marks.add(1), marks.add(count), count, channels * opt.cycle_cap()};
  std::vector<std::unique_ptr<CycleWorker<T>>> workers;  // band-major: worker i * groups + g
  std::vector<std::unique_ptr<InCoreWorker<T>>> incore;  // (in-core: these instead)
  // Worker k (local band i): its input cut from its unit's reader straight into the V-cycle's ring
  // (in-core: its planes), the input's sums once known, its own columns of the result rows.
  const auto wire = [&](auto& wk, int i, int k) {
    const int l = units.size() == 1 ? 0 : i, r = units.size() == 1 ? k : k - i * team.groups;  // its unit, its reader there
    const int c0 = wk.c0, n = wk.n, length = layout.row_length(0, wk.band), origin = layout.origin(0, wk.band);
    wk.rows.input = [&, l, r, c0, n, length, origin](int j, const typename StreamedVCycle<T>::Slots& to) {
      const auto in = input.row(l, r, j);
      for (int c = 0; c < n; ++c) {
        cut(in.u.data() + static_cast<std::size_t>(c0 + c) * w, w, layout.periodic, origin, to.u.subspan(c * length, length));
        cut(in.b.data() + static_cast<std::size_t>(c0 + c) * w, w, layout.periodic, origin, to.b.subspan(c * length, length));
      }
      if (!to.w.empty()) cut(in.w.data(), w, layout.periodic, origin, to.w);
      if (!to.d.empty()) cut(in.d.data(), w, layout.periodic, origin, to.d);
    };
    wk.rows.totals = [&, l, r]() -> const InputTotals& {
      input.done(l, r);
      marks.wait(summed, 0);
      return totals;
    };
    const int a = layout.begin(0, wk.band), own = layout.end(0, wk.band) - a;
    wk.rows.result = [&, k, c0, n, length, a, own](int j, std::span<const T> u) {
      float* row = results.row(k, j) + a;
      for (int c = 0; c < n; ++c)
        std::transform(u.begin() + c * length + layout.halo, u.begin() + c * length + layout.halo + own,
                       row + static_cast<std::size_t>(c0 + c) * w, [](T v) { return static_cast<float>(v); });
      results.put(k, j);
    };
  };
  for (int i = 0; i < team.local; ++i)
    for (int g = 0; g < team.groups; ++g) {
      const int c0 = g * channels / team.groups, n = (g + 1) * channels / team.groups - c0, k = i * team.groups + g;
      if (team.incore) {
        wire(*incore.emplace_back(std::make_unique<InCoreWorker<T>>(ops, opt, settings, c0, n, team.logs[i], shared, k)), i, k);
        continue;
      }
      if (team.checkpoint) settings.stores.name_prefix = team.checkpoint->prefix(i, g);
      auto& wk = *workers.emplace_back(
          std::make_unique<CycleWorker<T>>(ops, layout, team.hubs[g]->endpoint(team.first + i), opt, settings, c0, n, team.logs[i]));
      if (team.checkpoint) team.checkpoint->attach(wk, i, g, w);
      wire(wk, i, k);
    }

  // This thread: the input's sums once every row is made, then the result rows, in order, to `out`.
  double seconds_input = 0.0;
  util::run_workers(
      1 + count,
      [&](int k) {
        if (k > 0) return team.incore ? incore[k - 1]->run() : workers[k - 1]->run();
        const auto t = util::SteadyClock::now();
        totals = exchange_totals(input.totals(), team.hubs[0]->own(), team.local);
        marks.set(summed, 1);
        seconds_input = util::seconds_since(t);
        if (team.incore) shared.report(opt.progress);
        for (int j = 0; j < h; ++j) {
          results.write(j, h, out);
          if (opt.progress && !team.incore && (j % 64 == 63 || j + 1 == h)) opt.progress(0.5 + 0.5 * (j + 1) / h);
        }
      },
      [&](int k, const std::string& what) {
        marks.stop();
        team.abort(k == 0 ? fmt::format("the input/output thread stopped: {}", what)
                          : fmt::format("band {} stopped: {}", team.first + (k - 1) / team.groups, what));
      });
  summary.cpu_rhs_decode = input.decode_cpu();
  summary.cpu_rhs_columns = input.column_cpu();
  for (const auto& wk : workers) {
    const auto held = wk->vcycle.bytes();
    summary.scratch_bytes += held.scratch + wk->carry_bytes();
    summary.window_bytes += held.window;
  }
  for (const auto& wk : incore) summary.window_bytes += wk->window_bytes();
  summary.seconds_rhs = seconds_input;
  summary.seconds_solve = util::seconds_since(t_start) - seconds_input;
  team.logs[0].finish(summary, opt);
}

template void solve_streamed<float>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);
template void solve_streamed<double>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);

}  // namespace gdp::bands
