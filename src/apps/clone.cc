// Seamless cloning (Perez et al. 2003): a source's gradients inside a mask, the target pinned outside it.
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "apps/image_guidance.h"
#include "gdp/apps.h"
#include "gdp/errors.h"

namespace gdp {
namespace {

// Target rows are ImageGuidance's own (values, starting guess, gradients outside the mask);
// on edges touching the mask the gradient is replaced by the source's (offset = target's
// difference - source's), and pixels outside the mask are pinned. Source and mask rows are
// read in step with the target's, shifted by the offset.
class CloneGuidance final : public apps::ImageGuidance {
 public:
  CloneGuidance(RowReader& target, RowReader& source, RowReader& mask, const CloneOptions& o)
      : ImageGuidance(target, 0.0, 1.0, true), source_(source), mask_(mask), o_(o) {
    for (int k = 0; k < 2; ++k) {
      src_rows_[k].assign(static_cast<std::size_t>(source.channels()) * source.width(), 0.0f);
      mask_rows_[k].assign(static_cast<std::size_t>(mask.channels()) * mask.width(), 0.0f);
      valid_[k] = false;
    }
  }
  bool has_weights() const override { return true; }
  void read_row(int j, GuidanceRow& out) override {
    ImageGuidance::read_row(j, out);
    std::copy(out.initial.begin(), out.initial.end(), out.value.begin());
    for (int i = 0; i < width(); ++i) out.weight[i] = in_mask(i, j) ? 0.0 : kPinned;
  }

 protected:
  bool has_offsets() const override { return true; }
  double offset(int c, int i, int j, bool horizontal) const override {
    const int i2 = horizontal ? (i + 1) % width() : i, j2 = horizontal ? j : j + 1;
    if (!in_mask(i, j) && !in_mask(i2, j2)) return 0.0;
    if (!in_source(i, j) || !in_source(i2, j2)) return 0.0;  // the target's own gradient
    if (o_.mixed) {  // keep the target's gradient where it is the stronger one (over all channels)
      double t = 0.0, s = 0.0;
      for (int k = 0; k < channels(); ++k) {
        t += std::abs(target_at(k, i2, j2) - target_at(k, i, j));
        s += std::abs(source_at(k, i2, j2) - source_at(k, i, j));
      }
      if (t > s) return 0.0;
    }
    return (target_at(c, i2, j2) - target_at(c, i, j)) - (source_at(c, i2, j2) - source_at(c, i, j));
  }
  void on_source_row(int y, std::span<const float> /*row*/) override {
    const int sy = y - o_.offset_y;
    valid_[y % 2] = sy >= 0 && sy < source_.height();
    if (!valid_[y % 2]) return;
    while (next_ <= sy) {  // rows above the target's top are read and dropped
      source_.read_row(next_, src_rows_[y % 2]);
      mask_.read_row(next_, mask_rows_[y % 2]);
      ++next_;
    }
  }

 private:
  bool in_source(int i, int j) const {
    const int sx = i - o_.offset_x;
    return valid_[j % 2] && sx >= 0 && sx < source_.width();
  }
  bool in_mask(int i, int j) const {
    return in_source(i, j) && mask_rows_[j % 2][i - o_.offset_x] > 0.5f;  // the first channel
  }
  double target_at(int c, int i, int j) const {
    return source_row(j)[static_cast<std::size_t>(c) * width() + i];
  }
  double source_at(int c, int i, int j) const {
    return src_rows_[j % 2][static_cast<std::size_t>(c) * source_.width() + (i - o_.offset_x)];
  }

  RowReader& source_;
  RowReader& mask_;
  CloneOptions o_;
  std::vector<float> src_rows_[2], mask_rows_[2];
  bool valid_[2];
  int next_ = 0;
};

// A file's name, or the role ("the mask") where the input is not a file.
std::string subject(const std::string& role, const std::string& name) { return name.empty() ? "the " + role : name; }
// "the source s.png", or "the source".
std::string mention(const std::string& role, const std::string& name) {
  return name.empty() ? "the " + role : "the " + role + " " + name;
}

}  // namespace

void check_clone_inputs(const RowReader& target, const RowReader& source, const RowReader& mask,
                        const CloneOptions& o) {
  if (mask.width() != source.width() || mask.height() != source.height())
    throw InputError(fmt::format("{}: {}x{}, but {} is {}x{}", subject("mask", o.mask_name), mask.width(),
                                 mask.height(), mention("source", o.source_name), source.width(), source.height()));
  if (source.channels() < target.channels())
    throw InputError(fmt::format("{}: {} channel(s), but {} has {}", subject("source", o.source_name),
                                 source.channels(), mention("target", o.target_name), target.channels()));
}

void clone(RowReader& target, RowReader& source, RowReader& mask, const CloneOptions& options,
           const SolverOptions& solver, RowWriter& out, SolveSummary* summary) {
  check_clone_inputs(target, source, mask, options);
  if (solver.domain == Domain::Spherical) throw UsageError("clone works on planar and cylindrical images");
  CloneGuidance guidance(target, source, mask, options);
  solve(guidance, solver, out, summary);
}

Image clone(const Image& target, const Image& source, const Image& mask, const CloneOptions& options,
            const SolverOptions& solver, SolveSummary* summary) {
  ImageRowReader t(target), s(source), m(mask);
  Image out(target.width, target.height, target.channels);
  ImageRowWriter writer(out);
  clone(t, s, m, options, solver, writer, summary);
  return out;
}

}  // namespace gdp
