// The streaming solve schedule (default): V-cycles as pairs of passes over the rows, with
// channels in lanes on their own threads fed by the thread that reads the input.
#include <algorithm>
#include <cmath>
#include <exception>
#include <condition_variable>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "schedule/checkpoint.h"

#include "schedule/cycle_worker.h"
#include "schedule/input_rows.h"
#include "schedule/solve_parts.h"
#include "schedule/streaming_vcycle.h"

namespace gdp::schedule {
namespace {

// Thrown to a lane waiting for the input's sums when the solve is stopped.
struct Stopped {};

// The input's sums, handed from the reading thread to the lanes once every row was read (a lane
// resumed past its first restriction pass waits for them without reading any row).
class TotalsGate {
 public:
  void open(InputTotals totals) {
    const std::lock_guard lock(mutex_);
    totals_ = std::move(totals);
    ready_ = true;
    changed_.notify_all();
  }
  void close() {
    const std::lock_guard lock(mutex_);
    closed_ = true;
    changed_.notify_all();
  }
  const InputTotals& wait() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return ready_ || closed_; });
    if (!ready_) throw Stopped{};
    return totals_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  InputTotals totals_;
  bool ready_ = false, closed_ = false;
};

// Channels [c0, c0 + n) solved by one streaming V-cycle on its own thread: input batches in,
// result batches out, as many V-cycles as asked for.
template <class T>
class Lane {
 public:
  Lane(const multigrid::Operators<T>& ops, const SolverOptions& opt, typename StreamingVCycle<T>::Settings s,
       int c0, int n, TotalsGate& totals, ResidualLog& log)
      : c0_(c0), n_(n), width_(ops.levels[0].width), totals_(totals), log_(log), vcycle_(ops, (s.channels = n, s)),
        worker(vcycle_, opt, ops.singular, n, width_, ops.levels[0].height, s.stores, "result") {}
  int first_channel() const { return c0_; }
  int channels() const { return n_; }
  const StreamingVCycle<T>& vcycle() const { return vcycle_; }
  // Saves to `cp` as lane `lane` (restoring its state when resuming); the input rows it has.
  int use_checkpoint(Checkpoint& cp, int lane) {
    // A unit of the first pass stores about four times what a save writes (the rows held).
    const double row_bytes = 2.0 * n_ * width_ * sizeof(T);
    const int rows = static_cast<int>(std::min(1e9, 4.0 * static_cast<double>(vcycle_.window_bytes()) / row_bytes));
    return worker.use_checkpoint(cp, lane, cp.unit_rows(std::max(16, rows)), log_, c0_);
  }
  void run() {
    try {
      worker.run([this]() -> const InputTotals& { return totals_.wait(); }, log_, c0_, 0, width_);  // false: stopped
    } catch (const Stopped&) {
    }
  }

 private:
  int c0_, n_, width_;
  TotalsGate& totals_;
  ResidualLog& log_;
  StreamingVCycle<T> vcycle_;

 public:
  CycleWorker<T, StreamingVCycle<T>> worker;
};

// With opt.checkpoint_dir: the checkpoint (its lane count replaces `lanes` when resuming), scratch
// kept there under each lane's names.
template <class T>
std::unique_ptr<Checkpoint> open_checkpoint(const SolverOptions& opt, const multigrid::Operators<T>& ops, int channels,
                                            int& lanes, StorePolicy& stores) {
  if (opt.checkpoint_dir.empty()) return nullptr;
  const std::string sizes = fmt::format("{} {} {} {} {} {}", ops.levels[0].width, ops.levels[0].height, channels,
                                        ops.count(), sizeof(T), opt.half_scratch ? "half" : "native");
  auto cp = std::make_unique<Checkpoint>(opt, sizes, lanes);
  if (lanes < 1 || lanes > channels)
    throw InputError(fmt::format("--resume {}: the manifest is corrupt (lanes)", opt.checkpoint_dir.string()));
  stores.keep_dir = opt.checkpoint_dir;
  return cp;
}

}  // namespace

template <class T>
void solve_streaming(GuidanceSource& source, const SolverOptions& opt, RowWriter& out, SolveSummary& summary) {
  const Problem<T> problem(source, opt, summary);
  const multigrid::Operators<T>& ops = problem.ops;
  if (ops.count() == 1) return solve_incore<T>(source, opt, out, summary);  // nothing to stream
  const int w = source.width(), h = source.height(), channels = source.channels();
  const auto t_start = Clock::now();

  typename StreamingVCycle<T>::Settings settings{cycle_settings(opt, ops.singular, channels, source.has_weights())};
  settings.incore_from = first_whole_level(ops, channels, opt.incore_bytes);
  summary.schedule = "streaming";
  summary.streamed_levels = settings.incore_from;

  // Channels are independent problems: up to one lane each, two threads left to the codecs.
  TotalsGate totals;
  ResidualLog log(channels, static_cast<bool>(opt.log));
  std::vector<std::unique_ptr<Lane<T>>> lanes;
  int lane_count = std::clamp(opt.threads - 2, 1, channels);
  const std::unique_ptr<Checkpoint> checkpoint = open_checkpoint(opt, ops, channels, lane_count, settings.stores);
  std::vector<int> skip(lane_count, 0);  // input rows each lane already has (resumed)
  for (int t = 0; t < lane_count; ++t) {
    const int c0 = t * channels / lane_count, c1 = (t + 1) * channels / lane_count;
    if (checkpoint) settings.stores.name_prefix = fmt::format("lane{}-", t);
    lanes.push_back(std::make_unique<Lane<T>>(ops, opt, settings, c0, c1 - c0, totals, log));
    if (checkpoint) skip[t] = lanes.back()->use_checkpoint(*checkpoint, t);
  }
  std::vector<std::exception_ptr> errors(lanes.size());
  std::vector<std::thread> threads;
  const auto stop_all = [&] {
    for (auto& lane : lanes) {
      lane->worker.in.close();
      lane->worker.out.close();
    }
    totals.close();
  };
  for (std::size_t t = 0; t < lanes.size(); ++t)
    threads.emplace_back([&, t] {
      try {
        lanes[t]->run();
      } catch (...) {
        errors[t] = std::current_exception();
        stop_all();
      }
    });
  const auto join = [&] {
    for (std::thread& th : threads) th.join();
    for (const auto& e : errors)
      if (e) std::rethrow_exception(e);
  };
  const auto report = [&](double fraction) {
    if (opt.progress) opt.progress(fraction);
  };

  double seconds_input = 0.0;
  try {
    InputRows<T> input(source, problem.hierarchy);
    const std::size_t n = static_cast<std::size_t>(channels) * w;
    std::vector<T> u(n), b(n), wt(w), d(settings.diagonal ? w : 0);
    std::vector<Batch<T>> batches(lanes.size());
    for (int j = 0; j < h; ++j) {
      const auto t = Clock::now();
      input.next(u, b, wt, d);
      seconds_input += seconds_since(t);
      const bool last = j + 1 == h;
      if (last) totals.open(input.totals());
      for (std::size_t l = 0; l < lanes.size(); ++l) {
        if (j < skip[l]) continue;  // resumed: the lane has this row
        Batch<T>& batch = batches[l];
        const Lane<T>& lane = *lanes[l];
        const auto from = static_cast<std::ptrdiff_t>(lane.first_channel()) * w;
        const auto count = static_cast<std::ptrdiff_t>(lane.channels()) * w;
        if (batch.rows == 0) batch.first = j;
        batch.u.insert(batch.u.end(), u.begin() + from, u.begin() + from + count);
        batch.b.insert(batch.b.end(), b.begin() + from, b.begin() + from + count);
        if (settings.weights) batch.w.insert(batch.w.end(), wt.begin(), wt.end());
        batch.d.insert(batch.d.end(), d.begin(), d.end());
        if (++batch.rows < batch_rows(w, channels) && !last) continue;
        if (!lanes[l]->worker.in.push(std::move(batch))) throw std::runtime_error("stopped");
        batch = lanes[l]->worker.spent_in.take();
      }
      if (j % 64 == 63) report(0.5 * (j + 1) / h);
    }
    std::vector<float> row(n);
    std::vector<Batch<T>> results(lanes.size());
    for (int j = 0; j < h; ++j) {
      for (std::size_t l = 0; l < lanes.size(); ++l) {
        Batch<T>& r = results[l];
        if (r.rows == 0 || j >= r.first + r.rows) {
          auto next = lanes[l]->worker.out.pop();
          if (!next) throw std::runtime_error("stopped");
          lanes[l]->worker.spent_out.give(std::move(r));
          r = std::move(*next);
        }
        const std::size_t count = static_cast<std::size_t>(lanes[l]->channels()) * w;
        const T* src = r.u.data() + static_cast<std::size_t>(j - r.first) * count;
        std::transform(src, src + count, row.begin() + static_cast<std::ptrdiff_t>(lanes[l]->first_channel()) * w,
                       [](T v) { return static_cast<float>(v); });
      }
      out.write_row(j, row);
      if (j % 64 == 63 || j + 1 == h) report(0.5 + 0.5 * (j + 1) / h);
    }
  } catch (...) {
    stop_all();
    join();  // a lane's own error explains more than "stopped"
    throw;
  }
  join();
  for (const auto& lane : lanes) {
    summary.scratch_bytes += lane->vcycle().store_bytes() + lane->worker.carry_bytes();
    summary.window_bytes += lane->vcycle().window_bytes();
  }
  summary.seconds_rhs = seconds_input;
  summary.seconds_solve = seconds_since(t_start) - seconds_input;
  log.finish(summary, opt);
}

template void solve_streaming<float>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);
template void solve_streaming<double>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);

}  // namespace gdp::schedule
