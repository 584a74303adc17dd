// The streamed solve (streaming and bands alike): workers (band, channel group) on threads make their
// input rows and put their results, which the caller's thread writes; under mpirun, every rank reads,
// solves and writes its share of the columns.
#include "bands/solve_streamed.h"

#include <algorithm>
#include <deque>
#include <mutex>
#include <optional>

#include <fmt/format.h>

#include "bands/cycle_worker.h"
#include "bands/incore_worker.h"
#include "bands/mpi_transport.h"
#include "bands/streamed_vcycle.h"
#include "gdp/errors.h"
#include "gdp/mpi_run.h"
#include "mpi/ranks.h"
#include "schedule/input_ring.h"
#include "multigrid/input_rows.h"
#include "util/env_int.h"
#include "util/recycle_pool.h"

namespace gdp::bands {

using schedule::Clock;
using multigrid::InputTotals;
using schedule::seconds_since;

namespace {

constexpr int kTotals = 2000;  // tag of the input sums' exchange (streamed_vcycle.cc uses < 2000)
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

// The workers of this process: bands [first, first + local) of the plan (all of them on threads,
// or under mpirun this rank's share), each in `groups` channel groups. Channels are independent
// problems: a group's bands talk among themselves only (a hub each; under mpirun one group).
struct Team {
  std::vector<std::unique_ptr<ThreadHub>> hubs;  // per channel group (under mpirun one MpiHub)
  std::unique_ptr<StreamedCheckpoint> checkpoint;  // with --checkpoint
  std::vector<schedule::ResidualLog> logs;         // per local band, all channels (band 0's lines are kept)
  int first = 0, local = 1, groups = 1;
  Transport& endpoint(int group, int band) { return hubs[group]->endpoint(band); }
  void abort(const std::string& why) { for (auto& hub : hubs) hub->stop(why); }
};

// The input sums of all bands, added in band order (the same bits however the bands are spread
// over processes) from this process's bands' sums: every rank's go to every rank (one rank:
// nothing to send).
InputTotals exchange_totals(const std::vector<InputTotals>& local, Team& team) {
  ByteWriter mine;
  for (const InputTotals& t : local) io(mine, t);
  InputTotals total;
  for (Bytes& part : all_gather(team.endpoint(0, team.first), kTotals, std::move(mine.bytes), team.local)) {
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

// Everything a solve sets up before its workers start: the problem and the column plan (in-core,
// where there is one level or --in-core asks for it: one band of whole levels; streaming: one band;
// else opt.bands per process).
template <class T>
struct Setup {
  std::unique_ptr<schedule::Problem<T>> problem;
  std::optional<BandLayout> layout;
  bool distributed = false, incore = false;
};

template <class T>
Setup<T> set_up(GuidanceSource& source, const SolverOptions& opt, SolveSummary& summary) {
  Setup<T> s;
  // Under mpirun every rank sets up the same problem; they compare before anyone starts solving.
  s.distributed = MpiRun::size() > 1;
  const int per_process = opt.schedule == Schedule::Bands ? opt.bands : 1;
  const int total_bands = per_process * MpiRun::size();
  std::string setup_error;
  try {
    s.problem = std::make_unique<schedule::Problem<T>>(source, opt, summary);
    const schedule::Problem<T>& p = *s.problem;
    const bool periodic = p.hierarchy.levels[0].x.boundary == fem::AxisBoundary::Periodic;
    s.incore = opt.schedule == Schedule::InCore || p.ops.count() == 1;
    const int whole_from = s.incore ? 0 : schedule::first_whole_level(p.ops, source.channels(), opt.incore_bytes);
    const int pre = opt.sweeps, post = opt.post_sweeps;
    s.layout = total_bands == 1 || s.incore ? single_band_layout(p.hierarchy, periodic, pre, post, whole_from)
                                            : make_band_layout(p.hierarchy, periodic, total_bands, pre, post, whole_from);
  } catch (const Error& e) {
    if (!s.distributed) throw;
    setup_error = e.what();
  }
  if (s.distributed)
    mpi::agree_before_solving(setup_error, {source.width(), source.height(), source.channels(), per_process, opt.sweeps,
                                       opt.post_sweeps, opt.vcycles, opt.max_vcycles, static_cast<long long>(opt.tolerance * 1e12),
                                       static_cast<long long>(sizeof(T)),
                                       s.problem ? s.problem->ops.count() : -1});
  s.distributed = s.distributed && !s.incore;  // (one level: every rank solves it whole)
  return s;
}

// This process's workers: under mpirun opt.bands per rank (one without --bands), else every band
// of the plan, in channel groups (up to one a channel, two threads left to the codecs). A single
// band on more than one thread takes one group per channel even where that leaves the codecs no
// core of their own: else its one worker does every V-cycle sample while the other cores wait
// (docs/scaling.md, "1 gigapixel on the 2-core machine"). In-core: a group per two threads (the two
// smooth one channel, multigrid::PassPair: one set of planes where a group per thread took two). Then their
// checkpoint (which may set the group count, resuming), hubs and logs.
template <class T>
Team make_team(const SolverOptions& opt, const Setup<T>& setup, int channels, schedule::StorePolicy& stores) {
  Team team;
  const BandLayout& layout = *setup.layout;
  team.local = setup.distributed ? (opt.schedule == Schedule::Bands ? opt.bands : 1) : layout.bands;
  if (setup.distributed) {
    team.hubs.push_back(std::make_unique<MpiHub>(team.local));
    team.first = team.hubs[0]->first();
  } else {
    const int spare = setup.incore ? opt.threads / 2 : team.local == 1 && opt.threads > 1 ? channels : (opt.threads - 2) / team.local;
    team.groups = std::clamp(spare, 1, channels);
  }
  if (!opt.checkpoint_dir.empty() && !setup.incore)
    team.checkpoint = std::make_unique<StreamedCheckpoint>(opt, setup.problem->ops, channels, layout.bands, team.local,
                                                           team.first, team.groups, stores);
  for (int g = 0; g < team.groups && !setup.distributed; ++g) team.hubs.push_back(std::make_unique<ThreadHub>(layout.bands));
  for (int i = 0; i < team.local; ++i) team.logs.emplace_back(channels, team.first + i == 0 && static_cast<bool>(opt.log));
  if (team.checkpoint) team.checkpoint->agree(setup.distributed ? &team.endpoint(0, team.first) : nullptr);
  return team;
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

// Under mpirun, this process's bands are a contiguous share of the plan: it writes their own
// columns and reads their rows' (plus margins).
void share_columns(const BandLayout& layout, const Team& team, GuidanceSource& source, RowWriter& out) {
  const int last_local = team.first + team.local - 1;
  const InputWindow window = input_window(layout, team.first, last_local, source.width());
  if (!window.whole) source.set_columns(window.guidance.first, window.guidance.second);
  out.set_columns(layout.begin(0, team.first), layout.end(0, last_local));
}

// The input units (one per local band where the source splits, else one for all) and their readers:
// each band's workers.
template <class T>
std::vector<typename schedule::InputRing<T>::Unit> input_units(const GuidanceSource& source, const BandLayout& layout,
                                                               const Team& team) {
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
// streamed solve cannot hang"). Tests set `slots` to 1 (GDP_RESULT_ROWS).
class Results {
 public:
  Results(schedule::Marks& marks, int workers, int groups, std::size_t row)
      : marks_(marks), written_(marks.add(1)), put_(marks.add(workers)), workers_(workers), groups_(groups),
        row_(row), slots_(std::max(1, util::env_int("GDP_RESULT_ROWS", 64))) {}
  // Worker k's row j (whole rows: it fills its columns), then put(k, j).
  float* row(int k, int j) {
    marks_.wait([&](std::vector<int>& m) {
      bool lags = false;  // a worker of k's group has not put the next row to write
      for (int i = k % groups_; i < workers_; i += groups_) lags = lags || m[put_ + i] <= m[written_];
      return lags || j < m[written_] + slots_;
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
    marks_.wait(put_, put_ + workers_, j, std::min({j + 4, j + slots_ - 1, h - 1}));
    const std::vector<float>* row = nullptr;
    {
      const std::lock_guard lock(mutex_);
      row = &rows_.front();  // stays where it is while rows are added
    }
    out.write_row(j, *row);
    {
      const std::lock_guard lock(mutex_);
      spare_.give(std::move(rows_.front()));
      rows_.pop_front();
      ++first_;
    }
    marks_.set(written_, j + 1);
  }

 private:
  schedule::Marks& marks_;
  const int written_, put_, workers_, groups_;  // marks: rows written, rows each worker put
  const std::size_t row_;
  int slots_, first_ = 0;  // rows_[i] is row first_ + i
  std::mutex mutex_;
  std::deque<std::vector<float>> rows_;
  util::RecyclePool<std::vector<float>> spare_;  // rows written, for reuse
};

}  // namespace

template <class T>
void solve_streamed(GuidanceSource& source, const SolverOptions& opt, RowWriter& out, SolveSummary& summary) {
  Setup<T> setup = set_up<T>(source, opt, summary);
  const multigrid::Operators<T>& ops = setup.problem->ops;
  const int channels = source.channels(), w = source.width(), h = source.height();
  const BandLayout& layout = *setup.layout;
  const auto t_start = Clock::now();
  summary.schedule = setup.incore ? "in-core" : layout.single ? "streaming" : "bands";
  summary.streamed_levels = layout.banded_levels();
  auto settings = cycle_settings(opt, ops.singular, channels, source.has_weights());

  Team team = make_team(opt, setup, channels, settings.stores);
  if (setup.distributed) share_columns(layout, team, source, out);

  // Rows between the threads: the input ring, made by the workers that read it; the input's sums
  // (mark `summed`: known); the result rows.
  schedule::Marks marks;
  const auto units = input_units<T>(source, layout, team);
  schedule::InputRing<T> input(source, setup.problem->hierarchy, units, marks, opt.progress);
  const int count = team.local * team.groups, summed = marks.add(1);
  InputTotals totals;
  Results results(marks, count, team.groups, static_cast<std::size_t>(channels) * w);
  InCoreShared<T> shared{marks, marks.add(1), marks.add(count), count, channels * opt.cycle_cap()};
  std::vector<std::unique_ptr<CycleWorker<T>>> workers;  // band-major: worker i * groups + g
  std::vector<std::unique_ptr<InCoreWorker<T>>> incore;  // (in-core: these instead)
  // Worker k (local band i): its input cut from its unit's reader straight into the V-cycle's ring
  // (in-core: its planes), the input's sums once known, its own columns of the result rows.
  const auto wire = [&](auto& wk, int i, int k) {
    const int l = i * static_cast<int>(units.size()) / team.local;  // its unit, and its reader there
    const int r = k - l * team.local / static_cast<int>(units.size()) * team.groups;
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
      if (setup.incore) {
        wire(*incore.emplace_back(std::make_unique<InCoreWorker<T>>(ops, opt, settings, c0, n, team.logs[i], shared, k)), i, k);
        continue;
      }
      if (team.checkpoint) settings.stores.name_prefix = team.checkpoint->prefix(i, g);
      auto& wk = *workers.emplace_back(
          std::make_unique<CycleWorker<T>>(ops, layout, team.endpoint(g, team.first + i), opt, settings, c0, n, team.logs[i]));
      if (team.checkpoint) team.checkpoint->attach(wk, i, g, w);
      wire(wk, i, k);
    }

  // This thread: the input's sums once every row is made, then the result rows, in order, to `out`.
  double seconds_input = 0.0;
  schedule::run_workers(
      1 + count,
      [&](int k) {
        if (k > 0) return setup.incore ? incore[k - 1]->run() : workers[k - 1]->run();
        const auto t = Clock::now();
        totals = exchange_totals(input.totals(), team);
        marks.set(summed, 1);
        seconds_input = seconds_since(t);
        if (setup.incore) shared.report(opt.progress);
        for (int j = 0; j < h; ++j) {
          results.write(j, h, out);
          if (opt.progress && !setup.incore && (j % 64 == 63 || j + 1 == h)) opt.progress(0.5 + 0.5 * (j + 1) / h);
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
    summary.scratch_bytes += wk->vcycle.store_bytes() + wk->carry_bytes();
    summary.window_bytes += wk->vcycle.window_bytes();
  }
  for (const auto& wk : incore) summary.window_bytes += wk->window_bytes();
  summary.seconds_rhs = seconds_input;
  summary.seconds_solve = seconds_since(t_start) - seconds_input;
  team.logs[0].finish(summary, opt);
}

template void solve_streamed<float>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);
template void solve_streamed<double>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);

}  // namespace gdp::bands
