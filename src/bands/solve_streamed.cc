// The streamed solve (streaming and bands alike): workers (band, channel group) on threads, fed and
// drained by the caller's thread; under mpirun, every rank reads, solves and writes its share of the columns.
#include "bands/solve_streamed.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <future>
#include <optional>

#include <fmt/format.h>

#include "bands/cycle_worker.h"
#include "bands/mpi_transport.h"
#include "bands/streamed_vcycle.h"
#include "bands/thread_transport.h"
#include "gdp/errors.h"
#include "gdp/mpi_run.h"
#include "mpi/ranks.h"
#include "schedule/input_ring.h"
#include "multigrid/input_rows.h"

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
  int first = 0, local = 1, groups = 1;
  Transport& endpoint(int group, int band) { return hubs[group]->endpoint(band); }
  void abort(const std::string& why) { for (auto& hub : hubs) hub->endpoint(first).abort(why); }
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

// Columns [origin, origin + length) of a full row of n samples: wrapped on periodic rows,
// zero outside the row otherwise.
template <class T>
void cut(const T* row, int n, bool periodic, int origin, int length, std::vector<T>& out) {
  for (int x = 0; x < length;) {  // appended in runs (no zero fill of what is copied)
    const int i = periodic ? fem::wrap_index(origin + x, n) : origin + x;
    const int run = i < 0 ? std::min(length - x, -i) : i >= n ? length - x : std::min(length - x, n - i);
    if (i < 0 || i >= n)
      out.insert(out.end(), static_cast<std::size_t>(run), T(0));
    else
      out.insert(out.end(), row + i, row + i + run);
    x += run;
  }
}

// Everything a streamed solve sets up before its workers start: the problem, the column plan
// (one band, or opt.bands per process), the team and the columns this process reads and writes.
template <class T>
struct Setup {
  std::unique_ptr<schedule::Problem<T>> problem;
  std::optional<BandLayout> layout;
  bool distributed = false;
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
    if (p.ops.count() > 1) {
      const bool periodic = p.hierarchy.levels[0].x.boundary == fem::AxisBoundary::Periodic;
      const int whole_from = schedule::first_whole_level(p.ops, source.channels(), opt.incore_bytes);
      const SweepCounts sweeps(opt.sweeps, opt.post_sweeps);
      s.layout = total_bands == 1 ? single_band_layout(p.hierarchy, periodic, sweeps, whole_from)
                                  : make_band_layout(p.hierarchy, periodic, total_bands, sweeps, whole_from);
    }
  } catch (const Error& e) {
    if (!s.distributed) throw;
    setup_error = e.what();
  }
  if (s.distributed)
    mpi::agree_before_solving(setup_error, {source.width(), source.height(), source.channels(), per_process, opt.sweeps,
                                       opt.post_sweeps, opt.vcycles, opt.max_vcycles, static_cast<long long>(opt.tolerance * 1e12),
                                       static_cast<long long>(sizeof(T)),
                                       s.problem ? s.problem->ops.count() : -1});
  return s;
}

// This process's workers: under mpirun opt.bands per rank (one without --bands), else every band
// of the plan, in channel groups (up to one a channel, two threads left to the codecs). A single
// band on more than one thread takes one group per channel even where that leaves the codecs no
// core of their own: else its one worker does every V-cycle sample while the other cores wait
// (docs/scaling.md, "1 gigapixel on the 2-core machine").
Team make_team(const SolverOptions& opt, const BandLayout& layout, bool distributed, int channels) {
  Team team;
  team.local = distributed ? (opt.schedule == Schedule::Bands ? opt.bands : 1) : layout.bands;
  if (distributed) {
    team.hubs.push_back(std::make_unique<MpiHub>(team.local));
    team.first = team.hubs[0]->first();
  } else {
    const int spare = team.local == 1 && opt.threads > 1 ? channels : (opt.threads - 2) / team.local;
    team.groups = std::clamp(spare, 1, channels);
  }
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

// One reader of the input pass: local bands [first, last) (worker indices first * groups ..),
// their input rows made from the ring's decoded rows.
template <class T>
struct Reader {
  int first, last;
  std::unique_ptr<multigrid::InputRows<T>> input;
};

// The input pass's ring and readers: one reader per local band where the source splits
// (GuidanceSource::splits), each computing its band's columns; else one reader for all.
template <class T>
struct InputPass {
  std::unique_ptr<schedule::InputRing> ring;
  std::vector<Reader<T>> readers;
};

template <class T>
InputPass<T> make_input_pass(GuidanceSource& source, const schedule::Problem<T>& problem, const BandLayout& layout,
                             const Team& team) {
  const int count = source.splits() && !layout.folded ? team.local : 1;
  InputPass<T> pass{std::make_unique<schedule::InputRing>(source, count), {}};
  for (int l = 0; l < count; ++l) {
    const int first = team.first + l * team.local / count, last = team.first + (l + 1) * team.local / count;
    const InputWindow window = input_window(layout, first, last - 1, source.width());
    std::vector<std::pair<int, int>> own;
    for (int i = first; i < last; ++i) own.emplace_back(layout.begin(0, i), layout.end(0, i));
    pass.readers.push_back({first - team.first, last - team.first,
                            std::make_unique<multigrid::InputRows<T>>(
                                source, problem.hierarchy, own, window.rows,
                                [ring = pass.ring.get(), l, g = window.guidance](int j, GuidanceRow& row) {
                                  ring->read(l, j, row, g.first, g.second);
                                })});
  }
  return pass;
}

// A reader's thread: every input row of its bands cut into their workers' batches (columns of their
// band with its halo, channels of their group). Returns its CPU seconds.
template <class T>
double feed(Reader<T>& reader, const GuidanceSource& source, const SolverOptions& opt,
            const schedule::Problem<T>& problem, const BandLayout& layout, const Team& team, std::vector<std::unique_ptr<CycleWorker<T>>>& workers,
            const std::vector<int>& skip) {
  const int w = source.width(), h = source.height();
  const std::size_t n = static_cast<std::size_t>(source.channels()) * w;
  std::vector<T> u(n), b(n), wt(w), d(source.has_weights() ? w : 0);
  std::vector<Batch<T>> batches(workers.size());
  for (int j = 0; j < h; ++j) {
    reader.input->next(u, b, wt, d);
    const bool last = j + 1 == h;
    for (int k = reader.first * team.groups; k < reader.last * team.groups; ++k) {
      if (j < skip[k]) continue;  // resumed: the worker has this row
      CycleWorker<T>& wk = *workers[k];
      Batch<T>& batch = batches[k];
      const int origin = layout.origin(0, wk.band), length = layout.row_length(0, wk.band);
      if (batch.rows == 0) batch.first = j;
      for (int c = wk.c0; c < wk.c0 + wk.n; ++c) {
        cut(u.data() + static_cast<std::size_t>(c) * w, w, layout.periodic, origin, length, batch.u);
        cut(b.data() + static_cast<std::size_t>(c) * w, w, layout.periodic, origin, length, batch.b);
      }
      if (!wt.empty() && problem.ops.singular) cut(wt.data(), w, layout.periodic, origin, length, batch.w);
      if (!d.empty()) cut(d.data(), w, layout.periodic, origin, length, batch.d);
      if (++batch.rows < batch_rows(length, wk.n) && !last) continue;
      if (!wk.in.push(std::move(batch))) throw TransportStopped("stopped");
      batch = wk.spent_in.take();
    }
    if (opt.progress && reader.first == 0 && j % 64 == 63) opt.progress(0.5 * (j + 1) / h);
  }
  return schedule::thread_cpu_seconds();
}

// Then: this process's columns of every result row, in order, to `out`.
template <class T>
void drain(const SolverOptions& opt, const BandLayout& layout, std::vector<std::unique_ptr<CycleWorker<T>>>& workers,
           int w, int h, int channels, RowWriter& out) {
  std::vector<Batch<T>> results(workers.size());
  std::vector<float> row(static_cast<std::size_t>(channels) * w, 0.0f);
  for (int j = 0; j < h; ++j) {
    for (std::size_t k = 0; k < workers.size(); ++k) {
      CycleWorker<T>& wk = *workers[k];
      Batch<T>& r = results[k];
      if (r.rows == 0 || j >= r.first + r.rows) {
        auto next = wk.out.pop();
        if (!next) throw TransportStopped("stopped");
        wk.spent_out.give(r.emptied());
        r = std::move(*next);
      }
      const int a = layout.begin(0, wk.band), own = layout.end(0, wk.band) - a;
      const T* src = r.u.data() + static_cast<std::size_t>(j - r.first) * wk.n * own;
      for (int c = 0; c < wk.n; ++c)
        std::transform(src + static_cast<std::size_t>(c) * own, src + static_cast<std::size_t>(c + 1) * own,
                       row.begin() + static_cast<std::ptrdiff_t>(wk.c0 + c) * w + a,
                       [](T v) { return static_cast<float>(v); });
    }
    out.write_row(j, row);
    if (opt.progress && (j % 64 == 63 || j + 1 == h)) opt.progress(0.5 + 0.5 * (j + 1) / h);
  }
}

}  // namespace

template <class T>
void solve_streamed(GuidanceSource& source, const SolverOptions& opt, RowWriter& out, SolveSummary& summary) {
  Setup<T> setup = set_up<T>(source, opt, summary);
  const schedule::Problem<T>& problem = *setup.problem;
  const multigrid::Operators<T>& ops = problem.ops;
  if (ops.count() == 1) return schedule::solve_incore<T>(source, opt, out, summary);  // nothing to stream
  const int channels = source.channels();
  const BandLayout& layout = *setup.layout;
  const auto t_start = Clock::now();
  summary.schedule = layout.single ? "streaming" : "bands";
  summary.streamed_levels = layout.banded_levels();
  auto settings = cycle_settings(opt, ops.singular, channels, source.has_weights());

  Team team = make_team(opt, layout, setup.distributed, channels);
  if (setup.distributed) share_columns(layout, team, source, out);
  std::unique_ptr<StreamedCheckpoint> checkpoint;
  if (!opt.checkpoint_dir.empty())
    checkpoint = std::make_unique<StreamedCheckpoint>(opt, ops, channels, layout.bands, team.local, team.first,
                                                      team.groups, settings.stores);
  if (!setup.distributed)
    for (int g = 0; g < team.groups; ++g) team.hubs.push_back(std::make_unique<ThreadHub>(layout.bands));

  std::promise<InputTotals> totals_promise;
  std::shared_future<InputTotals> totals = totals_promise.get_future().share();
  std::vector<schedule::ResidualLog> logs;  // per local band, all channels (band 0's lines are kept)
  for (int i = 0; i < team.local; ++i) logs.emplace_back(channels, team.first + i == 0 && static_cast<bool>(opt.log));
  if (checkpoint) checkpoint->agree(setup.distributed ? &team.endpoint(0, team.first) : nullptr);
  std::vector<std::unique_ptr<CycleWorker<T>>> workers;  // band-major: worker i * groups + g
  std::vector<int> skip;  // input rows each worker already has (resumed)
  for (int i = 0; i < team.local; ++i)
    for (int g = 0; g < team.groups; ++g) {
      const int c0 = g * channels / team.groups, c1 = (g + 1) * channels / team.groups;
      if (checkpoint) settings.stores.name_prefix = checkpoint->prefix(i, g);
      workers.push_back(std::make_unique<CycleWorker<T>>(ops, layout, team.endpoint(g, team.first + i), opt, settings,
                                                         c0, c1 - c0, logs[i]));
      skip.push_back(checkpoint ? checkpoint->attach(*workers.back(), i, g, source.width()) : 0);
    }

  // The input pass: this thread decodes every input row (then writes the results), readers make
  // their bands' input rows from them (run_workers' workers 1 .. readers), the others solve.
  InputPass<T> input = make_input_pass(source, problem, layout, team);
  std::vector<Reader<T>>& readers = input.readers;
  schedule::InputRing& ring = *input.ring;
  const int reader_count = static_cast<int>(readers.size());
  const auto stop_all = [&](const std::string& why) {
    try {  // workers waiting for the sums stop too
      totals_promise.set_exception(std::make_exception_ptr(TransportStopped(why)));
    } catch (const std::future_error&) {
    }
    ring.stop();
    team.abort(why);
    for (auto& wk : workers) {
      wk->in.close();
      wk->out.close();
    }
  };
  double seconds_input = 0.0;
  std::vector<double> reader_cpu(reader_count, 0.0);
  schedule::run_workers(
      1 + reader_count + static_cast<int>(workers.size()),
      [&](int k) {
        if (k > reader_count) return workers[k - 1 - reader_count]->run(totals);
        if (k > 0) {
          reader_cpu[k - 1] = feed(readers[k - 1], source, opt, problem, layout, team, workers, skip);
          return ring.finished(k - 1);
        }
        const auto t = Clock::now();
        const double cpu = schedule::thread_cpu_seconds();
        ring.decode_all();  // returns when every reader has finished
        summary.cpu_rhs_decode = schedule::thread_cpu_seconds() - cpu;
        std::vector<InputTotals> sums;  // every local band's, in band order
        for (const Reader<T>& reader : readers)
          sums.insert(sums.end(), reader.input->range_totals().begin(), reader.input->range_totals().end());
        totals_promise.set_value(exchange_totals(sums, team));
        seconds_input = seconds_since(t);
        drain(opt, layout, workers, source.width(), source.height(), channels, out);
      },
      [&](int k, const std::string& what) {
        if (k == 0) return stop_all(fmt::format("the input/output thread stopped: {}", what));
        if (k <= reader_count)
          return stop_all(fmt::format("the input of band {} stopped: {}", team.first + readers[k - 1].first, what));
        stop_all(fmt::format("band {} stopped: {}", workers[k - 1 - reader_count]->band, what));
      });
  for (const double cpu : reader_cpu) summary.cpu_rhs_columns += cpu;
  for (const auto& wk : workers) {
    summary.scratch_bytes += wk->vcycle.store_bytes() + wk->carry_bytes();
    summary.window_bytes += wk->vcycle.window_bytes();
  }
  summary.seconds_rhs = seconds_input;
  summary.seconds_solve = seconds_since(t_start) - seconds_input;
  logs[0].finish(summary, opt);
}

template void solve_streamed<float>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);
template void solve_streamed<double>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);

}  // namespace gdp::bands
