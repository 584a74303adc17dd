// Output fixups: one flag byte per pixel, recorded from input rows, applied to output rows.
#include "apps/output_fixups.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gdp::apps {
namespace {
constexpr unsigned char kZero = 0x80;  // bits 0..6: channel c not finite
}

OutputFixups::OutputFixups(RowWriter& out, int width, int height, int channels, const SolverOptions& solver)
    : out_(out), width_(width), height_(height), channels_(channels), flag_row_(width),
      row_(static_cast<std::size_t>(width) * channels) {
  policy_.dir = solver.temp_dir;
  policy_.budget = &schedule::ScratchBudget::process();  // one byte a pixel, in memory while it fits
  policy_.budget->set_limit(solver.scratch_memory);
}

OutputFixups::~OutputFixups() = default;

void OutputFixups::record(int, std::span<const float> input, std::span<const unsigned char> zero) {
  for (int i = 0; i < width_; ++i) {
    unsigned char f = !zero.empty() && zero[i] ? kZero : 0;
    for (int c = 0; c < channels_ && c < 7; ++c)
      if (!std::isfinite(input[static_cast<std::size_t>(c) * width_ + i])) f |= static_cast<unsigned char>(1u << c);
    flag_row_[i] = f;
    any_ = any_ || f != 0;
  }
  // Rows before the first flagged one are not stored (most images have none at all).
  if (!any_) {
    ++unflagged_;
    return;
  }
  if (!flags_)
    flags_ = std::make_unique<schedule::RowStore<unsigned char>>(policy_, width_, height_ - unflagged_, "flags");
  flags_->append(flag_row_);
}

void OutputFixups::write_row(int y, std::span<const float> row) {
  if (y < unflagged_ || !flags_) return out_.write_row(y, row);
  if (!reading_) {
    flags_->rewind();
    reading_ = true;
  }
  flags_->read(flag_row_);
  std::copy(row.begin(), row.end(), row_.begin());
  for (int i = 0; i < width_; ++i) {
    const unsigned char f = flag_row_[i];
    if (f == 0) continue;
    for (int c = 0; c < channels_; ++c) {
      float& v = row_[static_cast<std::size_t>(c) * width_ + i];
      if (f & kZero) v = 0.0f;
      if (c < 7 && (f & (1u << c))) v = std::numeric_limits<float>::quiet_NaN();
    }
  }
  out_.write_row(y, row_);
}

}  // namespace gdp::apps
