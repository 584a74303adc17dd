// The band solve schedule: one worker thread per band, fed and drained by the caller's thread; under
// mpirun, every rank reads, solves and writes only its share of the columns.
#include "bands/solve_bands.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <future>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "bands/band_vcycle.h"
#include "bands/mpi_agree.h"
#include "bands/mpi_transport.h"
#include "bands/thread_transport.h"
#include "gdp/errors.h"
#include "gdp/mpi_run.h"
#include "schedule/cycle_worker.h"
#include "schedule/input_rows.h"

namespace gdp::bands {

using schedule::Batch;
using schedule::batch_rows;
using schedule::Clock;
using schedule::seconds_since;

namespace {

constexpr int kTotals = 2000;       // tag of the input sums' exchange (band_vcycle.cc uses < 2000)
// Columns of the input a rank reads beyond its bands' rows: the right-hand side of a column
// reads the guidance of the columns within two of it.
constexpr int kInputMargin = 4;

using schedule::InputTotals;

// Input sums as one message and back.
Bytes pack(const std::vector<InputTotals>& totals) {
  std::vector<double> v;
  for (const InputTotals& t : totals) {
    v.insert(v.end(), t.weighted_sums.begin(), t.weighted_sums.end());
    v.insert(v.end(), t.rhs_norms2.begin(), t.rhs_norms2.end());
    v.push_back(t.weight_total);
  }
  Bytes bytes(v.size() * sizeof(double));
  if (!v.empty()) std::memcpy(bytes.data(), v.data(), bytes.size());
  return bytes;
}

std::vector<InputTotals> unpack(const Bytes& bytes, int count, int channels) {
  const std::size_t each = 2 * static_cast<std::size_t>(channels) + 1;
  if (bytes.size() != count * each * sizeof(double)) throw std::logic_error("input sums message of the wrong size");
  std::vector<double> v(count * each);
  if (!v.empty()) std::memcpy(v.data(), bytes.data(), bytes.size());
  std::vector<InputTotals> totals(count);
  for (int i = 0; i < count; ++i) {
    const double* p = v.data() + i * each;
    totals[i].weighted_sums.assign(p, p + channels);
    totals[i].rhs_norms2.assign(p + channels, p + 2 * channels);
    totals[i].weight_total = p[2 * channels];
  }
  return totals;
}

// The workers of this process: all bands on threads, or under mpirun this rank's bands
// [first, first + local) of opt.bands per rank.
struct Team {
  std::unique_ptr<ThreadHub> threads;
  std::unique_ptr<MpiHub> ranks;
  int first = 0, local = 1;
  Transport& endpoint(int band) { return ranks ? ranks->endpoint(band) : threads->endpoint(band); }
};

// The input sums of all bands, added in band order (the same bits however the bands are spread
// over processes) from this process's bands' sums: under mpirun the first band of every rank
// sends its rank's to band 0, whose rank adds them all up and sends the total back.
InputTotals exchange_totals(const std::vector<InputTotals>& local, Team& team, int channels) {
  const auto add_all = [](const std::vector<InputTotals>& all) {
    InputTotals total;
    for (const InputTotals& t : all) total.add(t);
    return total;
  };
  if (!team.ranks) return add_all(local);
  Transport& me = team.endpoint(team.first);
  if (team.first != 0) {
    me.send(0, kTotals, pack(local));
    return unpack(me.receive(0, kTotals), 1, channels)[0];
  }
  std::vector<InputTotals> all = local;
  for (int first = team.local; first < team.ranks->size(); first += team.local) {
    const auto part = unpack(me.receive(first, kTotals), team.local, channels);
    all.insert(all.end(), part.begin(), part.end());
  }
  const InputTotals total = add_all(all);
  for (int first = team.local; first < team.ranks->size(); first += team.local) me.send(first, kTotals, pack({total}));
  return total;
}

// Columns [origin, origin + length) of a full row of n samples: wrapped on periodic rows,
// zero outside the row otherwise.
template <class T>
void cut(const T* row, int n, bool periodic, int origin, int length, std::vector<T>& out) {
  const std::size_t at = out.size();
  out.resize(at + static_cast<std::size_t>(length), T(0));
  T* dst = out.data() + at;
  for (int x = 0; x < length;) {  // copied in runs up to the row's end
    const int i = periodic ? fem::wrap_index(origin + x, n) : origin + x;
    if (i < 0 || i >= n) {
      ++x;
      continue;
    }
    const int run = std::min(length - x, n - i);
    std::copy_n(row + i, run, dst + x);
    x += run;
  }
}

// One band's worker: its V-cycles on rows from `in`, its columns of the result to `out`.
template <class T>
class BandWorker {
 public:
  BandWorker(const multigrid::Operators<T>& ops, const BandLayout& layout, Transport& net, const SolverOptions& opt,
             const typename BandVCycle<T>::Settings& s, std::shared_future<InputTotals> totals, int channels,
             bool keep_lines)
      : log(channels, keep_lines), band_(net.rank()), layout_(layout), totals_(std::move(totals)),
        vcycle_(ops, layout, net, s),
        worker(vcycle_, opt, ops.singular, channels, layout.row_length(0, band_), ops.levels[0].height, s.stores,
               fmt::format("band{}-result", band_)) {}
  const BandVCycle<T>& vcycle() const { return vcycle_; }

  void run() {
    const int own = layout_.end(0, band_) - layout_.begin(0, band_);
    // Every band's input sums, once all are read.
    if (!worker.run([this]() -> const InputTotals& { return totals_.get(); }, log, 0, layout_.halo, own))
      throw TransportStopped("stopped");
  }

  schedule::ResidualLog log;

 private:
  int band_;
  const BandLayout& layout_;
  std::shared_future<InputTotals> totals_;
  BandVCycle<T> vcycle_;

 public:
  schedule::CycleWorker<T, BandVCycle<T>> worker;
};

}  // namespace

template <class T>
void solve_bands(GuidanceSource& source, const SolverOptions& opt, RowWriter& out, SolveSummary& summary) {
  // Under mpirun every rank sets up the same problem; they compare before anyone starts solving.
  const bool distributed = MpiRun::size() > 1;
  const int total_bands = opt.bands * MpiRun::size();
  std::unique_ptr<schedule::Problem<T>> problem_ptr;
  std::optional<BandLayout> layout_or;
  std::string setup_error;
  bool periodic = false;
  try {
    problem_ptr = std::make_unique<schedule::Problem<T>>(source, opt, summary);
    if (problem_ptr->ops.count() > 1) {
      periodic = problem_ptr->hierarchy.levels[0].x.boundary == fem::AxisBoundary::Periodic;
      layout_or = make_band_layout(problem_ptr->hierarchy, periodic, total_bands, opt.sweeps,
                                   schedule::first_whole_level(problem_ptr->ops, source.channels(), opt.incore_bytes));
    }
  } catch (const Error& e) {
    if (!distributed) throw;
    setup_error = e.what();
  }
  if (distributed)
    agree_before_solving(setup_error, {source.width(), source.height(), source.channels(), opt.bands, opt.sweeps,
                                       opt.vcycles, opt.max_vcycles, static_cast<long long>(opt.tolerance * 1e12),
                                       static_cast<long long>(sizeof(T)),
                                       problem_ptr ? problem_ptr->ops.count() : -1});
  const schedule::Problem<T>& problem = *problem_ptr;
  const multigrid::Operators<T>& ops = problem.ops;
  if (ops.count() == 1) return schedule::solve_incore<T>(source, opt, out, summary);  // nothing to band
  const int w = source.width(), h = source.height(), channels = source.channels();
  const BandLayout& layout = *layout_or;
  const auto t_start = Clock::now();
  summary.schedule = "bands";
  summary.streamed_levels = layout.banded_levels();
  const auto settings = schedule::cycle_settings(opt, ops.singular, channels, source.has_weights());

  Team team;
  if (distributed) {
    team.ranks = std::make_unique<MpiHub>(opt.bands);
    team.first = team.ranks->first();
    team.local = opt.bands;
  } else {
    team.threads = std::make_unique<ThreadHub>(layout.bands);
    team.local = layout.bands;
  }
  // This process's bands and columns: every band, or under mpirun a contiguous share of them,
  // whose own columns [own_begin, own_end) it writes and whose rows it reads (plus margins).
  const int last_local = team.first + team.local - 1;
  const int own_begin = layout.begin(0, team.first), own_end = layout.end(0, last_local);
  std::pair<int, int> input_columns{0, w};  // the columns of the input rows this process computes
  if (distributed) {
    const int rows_from = layout.origin(0, team.first);
    const int rows_to = layout.origin(0, last_local) + layout.row_length(0, last_local);
    // Whole rows where the window would wrap around a periodic image's edge, and on the sphere,
    // where the right-hand side of the first and last rows reads the guidance across the fold, at
    // the mirror image's columns; a planar image's edges clip it.
    const bool wraps = periodic && (rows_from - kInputMargin < 0 || rows_to + kInputMargin > w);
    if (!wraps && !layout.folded) {
      source.set_columns(std::max(0, rows_from - kInputMargin), std::min(w, rows_to + kInputMargin));
      input_columns = {std::max(0, rows_from), std::min(w, rows_to)};
    }
    out.set_columns(own_begin, own_end);
  }
  std::promise<InputTotals> totals_promise;
  std::shared_future<InputTotals> totals = totals_promise.get_future().share();
  std::vector<std::unique_ptr<BandWorker<T>>> workers;
  for (int i = 0; i < team.local; ++i)
    workers.push_back(std::make_unique<BandWorker<T>>(ops, layout, team.endpoint(team.first + i), opt, settings,
                                                      totals, channels,
                                                      team.first + i == 0 && static_cast<bool>(opt.log)));
  std::vector<std::exception_ptr> errors(workers.size());
  const auto stop_all = [&](const std::string& why) {
    try {  // workers waiting for the sums stop too
      totals_promise.set_exception(std::make_exception_ptr(TransportStopped(why)));
    } catch (const std::future_error&) {
    }
    team.endpoint(team.first).abort(why);
    for (auto& wk : workers) {
      wk->worker.in.close();
      wk->worker.out.close();
    }
  };
  std::vector<std::thread> threads;
  for (std::size_t b = 0; b < workers.size(); ++b)
    threads.emplace_back([&, b] {
      try {
        workers[b]->run();
      } catch (const std::exception& e) {
        errors[b] = std::current_exception();
        stop_all(fmt::format("band {} stopped: {}", team.first + b, e.what()));
      } catch (...) {
        errors[b] = std::current_exception();
        stop_all(fmt::format("band {} stopped", team.first + b));
      }
    });
  // Joins the workers; rethrows the first that failed for a reason of its own (which explains
  // more than "stopped"), and with `any` also one that was only stopped.
  const auto join = [&](bool any) {
    for (std::thread& th : threads) th.join();
    for (const auto& e : errors) {
      if (!e) continue;
      try {
        std::rethrow_exception(e);
      } catch (const TransportStopped&) {
        continue;
      }
    }
    for (const auto& e : errors)
      if (e && any) std::rethrow_exception(e);
  };
  const auto report = [&](double fraction) {
    if (opt.progress) opt.progress(fraction);
  };

  double seconds_input = 0.0;
  try {
    std::vector<std::pair<int, int>> own_columns;
    for (int band = team.first; band <= last_local; ++band) own_columns.emplace_back(layout.begin(0, band), layout.end(0, band));
    schedule::InputRows<T> input(source, problem.hierarchy, own_columns, input_columns);
    const std::size_t n = static_cast<std::size_t>(channels) * w;
    std::vector<T> u(n), b(n), wt(w), d(source.has_weights() ? w : 0);
    std::vector<Batch<T>> batches(workers.size());
    for (int j = 0; j < h; ++j) {
      const auto t = Clock::now();
      input.next(u, b, wt, d);
      seconds_input += seconds_since(t);
      const bool last = j + 1 == h;
      for (int i = 0; i < team.local; ++i) {
        const int band = team.first + i;
        Batch<T>& batch = batches[i];
        const int origin = layout.origin(0, band), length = layout.row_length(0, band);
        if (batch.rows == 0) batch.first = j;
        for (int c = 0; c < channels; ++c) {
          cut(u.data() + static_cast<std::size_t>(c) * w, w, periodic, origin, length, batch.u);
          cut(b.data() + static_cast<std::size_t>(c) * w, w, periodic, origin, length, batch.b);
        }
        if (settings.weights) cut(wt.data(), w, periodic, origin, length, batch.w);
        if (settings.diagonal) cut(d.data(), w, periodic, origin, length, batch.d);
        if (++batch.rows < batch_rows(length, channels) && !last) continue;
        if (!workers[i]->worker.in.push(std::move(batch))) throw TransportStopped("stopped");
        batch = workers[i]->worker.spent_in.take();
      }
      if (j % 64 == 63) report(0.5 * (j + 1) / h);
    }
    totals_promise.set_value(exchange_totals(input.range_totals(), team, channels));
    // This process's bands' columns of every row, in order, to `out`.
    std::vector<Batch<T>> results(team.local);
    std::vector<float> row(n, 0.0f);
    for (int j = 0; j < h; ++j) {
      for (int i = 0; i < team.local; ++i) {
        const int band = team.first + i;
        Batch<T>& r = results[i];
        if (r.rows == 0 || j >= r.first + r.rows) {
          auto next = workers[i]->worker.out.pop();
          if (!next) throw TransportStopped("stopped");
          workers[i]->worker.spent_out.give(std::move(r));
          r = std::move(*next);
        }
        const int a = layout.begin(0, band), own = layout.end(0, band) - a;
        const T* src = r.u.data() + static_cast<std::size_t>(j - r.first) * channels * own;
        for (int c = 0; c < channels; ++c)
          std::transform(src + static_cast<std::size_t>(c) * own, src + static_cast<std::size_t>(c + 1) * own,
                         row.begin() + static_cast<std::ptrdiff_t>(c) * w + a, [](T v) { return static_cast<float>(v); });
      }
      out.write_row(j, row);
      if (j % 64 == 63 || j + 1 == h) report(0.5 + 0.5 * (j + 1) / h);
    }
  } catch (const std::exception& e) {
    stop_all(fmt::format("the input/output thread stopped: {}", e.what()));
    join(false);
    throw;
  }
  join(true);
  for (const auto& wk : workers) {
    summary.scratch_bytes += wk->vcycle().store_bytes() + wk->worker.carry_bytes();
    summary.window_bytes += wk->vcycle().window_bytes();
  }
  summary.seconds_rhs = seconds_input;
  summary.seconds_solve = seconds_since(t_start) - seconds_input;
  workers[0]->log.finish(summary, opt);
}

template void solve_bands<float>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);
template void solve_bands<double>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);

}  // namespace gdp::bands
