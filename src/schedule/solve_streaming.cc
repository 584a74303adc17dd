// The streaming solve schedule (default): V-cycles as pairs of passes over the rows, with
// channels in lanes on their own threads fed by the thread that reads the input.
#include <algorithm>
#include <cmath>
#include <exception>
#include <thread>

#include "schedule/bounded_queue.h"
#include "schedule/input_rows.h"
#include "schedule/solve_parts.h"
#include "schedule/streaming_vcycle.h"

namespace gdp::schedule {
namespace {

// Rows handed between threads at a time: about 256K samples (1 MB of floats), 1 to 16 rows.
int batch_rows(int width, int channels) {
  return std::clamp((1 << 18) / std::max(1, width * channels), 1, 16);
}
constexpr std::size_t kQueued = 2;  // batches in flight per lane and direction

// Rows first .. first + rows - 1 of some channels: u and b (channels * width per row), w and d.
template <class T>
struct Batch {
  int first = 0, rows = 0;
  std::vector<T> u, b, w, d;
};

// The first level (>= 1) whose planes, u and b for every channel, fit in `bytes`.
template <class T>
int first_incore_level(const multigrid::Operators<T>& ops, int channels, std::size_t bytes) {
  for (int l = 1; l < ops.count(); ++l) {
    const auto& op = ops.levels[l];
    if (2.0 * channels * op.width * static_cast<double>(op.height) * sizeof(T) <= static_cast<double>(bytes)) return l;
  }
  return ops.count() - 1;
}

// Channels [c0, c0 + n) solved by one streaming V-cycle on its own thread: input batches in,
// result batches out, as many V-cycles as asked for.
template <class T>
class Lane {
 public:
  Lane(const multigrid::Operators<T>& ops, const SolverOptions& opt, typename StreamingVCycle<T>::Settings s,
       int c0, int n, const InputTotals& totals, ResidualLog& log)
      : in(kQueued), out(kQueued), ops_(ops), opt_(opt), c0_(c0), n_(n), width_(ops.levels[0].width),
        height_(ops.levels[0].height), totals_(totals), log_(log),
        vcycle_(ops, (s.channels = n, s)) {
    if (cycles() > 1)
      carry_ = std::make_unique<RowStore<T>>(s.stores, static_cast<std::size_t>(n) * width_, height_, "result");
  }
  int first_channel() const { return c0_; }
  int channels() const { return n_; }
  const StreamingVCycle<T>& vcycle() const { return vcycle_; }
  std::size_t carry_bytes() const { return carry_ ? carry_->bytes() : 0; }

  void run() {
    const std::size_t n = static_cast<std::size_t>(n_) * width_;
    std::vector<T> u(n);
    std::vector<double> shift(n_);
    Batch<T> batch;
    int next_in = 0;  // row of `batch` to push next
    for (int k = 0; k < cycles(); ++k) {
      vcycle_.begin_cycle();
      if (carry_) carry_->rewind();
      for (int j = 0; j < height_; ++j) {
        if (k > 0) {
          carry_->read(u);
          vcycle_.push(u, {}, {});
          continue;
        }
        if (next_in == batch.rows) {
          auto b = in.pop();
          if (!b) return;  // stopped
          batch = std::move(*b);
          next_in = 0;
        }
        const std::size_t at = static_cast<std::size_t>(next_in) * n;
        const auto pixel_row = [&](const std::vector<T>& v) {
          return v.empty() ? std::span<const T>{}
                           : std::span<const T>{v.data() + static_cast<std::size_t>(next_in) * width_,
                                                static_cast<std::size_t>(width_)};
        };
        vcycle_.push({batch.u.data() + at, n}, {batch.b.data() + at, n}, pixel_row(batch.w), pixel_row(batch.d));
        ++next_in;
      }
      for (int c = 0; c < n_; ++c) {
        if (k == 0) {
          log_.set_rhs_norm(c0_ + c, std::sqrt(totals_.rhs_norms2[c0_ + c]));
          log_.initial(c0_ + c, vcycle_.initial_norm(c));
        }
        shift[c] = mean_shift(ops_.singular, totals_.weighted_sums[c0_ + c], totals_.weight_total,
                              vcycle_.probe(c).dots);
      }
      const bool surely_last = k + 1 == cycles();
      if (carry_ && !surely_last) carry_->clear();
      Batch<T> result;
      for (int j = 0; j < height_; ++j) {
        vcycle_.pull(u);
        for (int c = 0; c < n_; ++c) {
          if (shift[c] == 0.0) continue;
          T* p = u.data() + static_cast<std::size_t>(c) * width_;
          for (int i = 0; i < width_; ++i) p[i] = static_cast<T>(static_cast<double>(p[i]) + shift[c]);
        }
        if (!surely_last) carry_->append(u);
        else if (!emit(result, j, u)) return;
      }
      bool converged = opt_.tolerance > 0.0;
      for (int c = 0; c < n_; ++c) {
        log_.cycle(c0_ + c, vcycle_.final_norm(c), vcycle_.probe(c));
        converged = converged && log_.last(c0_ + c) <= opt_.tolerance;
      }
      if (surely_last) return;
      if (converged) {  // the carried result is the answer
        carry_->rewind();
        for (int j = 0; j < height_; ++j) {
          carry_->read(u);
          if (!emit(result, j, u)) return;
        }
        return;
      }
    }
  }

  BoundedQueue<Batch<T>> in, out;

 private:
  int cycles() const { return opt_.tolerance > 0.0 ? opt_.max_vcycles : opt_.vcycles; }
  // Adds row j to the result batch, sending it when full or last; false when stopped.
  bool emit(Batch<T>& result, int j, const std::vector<T>& u) {
    if (result.rows == 0) result.first = j;
    result.u.insert(result.u.end(), u.begin(), u.end());
    ++result.rows;
    if (result.rows < batch_rows(width_, n_) && j + 1 < height_) return true;
    const bool ok = out.push(std::move(result));
    result = Batch<T>{};
    return ok;
  }

  const multigrid::Operators<T>& ops_;
  const SolverOptions& opt_;
  int c0_, n_, width_, height_;
  const InputTotals& totals_;
  ResidualLog& log_;
  StreamingVCycle<T> vcycle_;
  std::unique_ptr<RowStore<T>> carry_;
};

}  // namespace

template <class T>
void solve_streaming(GuidanceSource& source, const SolverOptions& opt, RowWriter& out, SolveSummary& summary) {
  const Problem<T> problem(source, opt, summary);
  const multigrid::Operators<T>& ops = problem.ops;
  if (ops.count() == 1) return solve_incore<T>(source, opt, out, summary);  // nothing to stream
  const int w = source.width(), h = source.height(), channels = source.channels();
  const auto t_start = Clock::now();

  typename StreamingVCycle<T>::Settings settings;
  settings.sweeps = opt.sweeps;
  settings.coarse_tolerance = opt.coarse_tolerance;
  settings.incore_from = first_incore_level(ops, channels, opt.incore_bytes);
  settings.measure_initial = settings.measure_final = true;
  settings.weights = ops.singular;
  settings.diagonal = source.has_weights();
  settings.more_cycles = (opt.tolerance > 0.0 ? opt.max_vcycles : opt.vcycles) > 1;
  settings.stores.dir = opt.temp_dir;
  settings.stores.encoding = opt.half_scratch ? StoreEncoding::Half : StoreEncoding::Native;
  summary.schedule = "streaming";
  summary.streamed_levels = settings.incore_from;

  // Channels are independent problems: up to one lane each, two threads left to the codecs.
  InputTotals totals;
  ResidualLog log(channels, static_cast<bool>(opt.log));
  std::vector<std::unique_ptr<Lane<T>>> lanes;
  const int lane_count = std::clamp(opt.threads - 2, 1, channels);
  for (int t = 0; t < lane_count; ++t) {
    const int c0 = t * channels / lane_count, c1 = (t + 1) * channels / lane_count;
    lanes.push_back(std::make_unique<Lane<T>>(ops, opt, settings, c0, c1 - c0, totals, log));
  }
  std::vector<std::exception_ptr> errors(lanes.size());
  std::vector<std::thread> threads;
  const auto stop_all = [&] {
    for (auto& lane : lanes) {
      lane->in.close();
      lane->out.close();
    }
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
      if (last) totals = input.totals();
      for (std::size_t l = 0; l < lanes.size(); ++l) {
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
        if (!lanes[l]->in.push(std::move(batch))) throw std::runtime_error("stopped");
        batch = Batch<T>{};
      }
      if (j % 64 == 63) report(0.5 * (j + 1) / h);
    }
    std::vector<float> row(n);
    std::vector<Batch<T>> results(lanes.size());
    for (int j = 0; j < h; ++j) {
      for (std::size_t l = 0; l < lanes.size(); ++l) {
        Batch<T>& r = results[l];
        if (r.rows == 0 || j >= r.first + r.rows) {
          auto next = lanes[l]->out.pop();
          if (!next) throw std::runtime_error("stopped");
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
    summary.scratch_bytes += lane->vcycle().store_bytes() + lane->carry_bytes();
    summary.window_bytes += lane->vcycle().window_bytes();
  }
  summary.seconds_rhs = seconds_input;
  summary.seconds_solve = seconds_since(t_start) - seconds_input;
  log.finish(summary, opt);
}

template void solve_streaming<float>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);
template void solve_streaming<double>(GuidanceSource&, const SolverOptions&, RowWriter&, SolveSummary&);

}  // namespace gdp::schedule
