// Output fixups: one flag byte per pixel, recorded from input rows, applied to output rows.
#include "apps/output_fixups.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "util/clones.h"

namespace gdp::apps {
namespace {
constexpr unsigned char kZero = 0x80;  // bits 0..6: channel c not finite
}

OutputFixups::OutputFixups(RowWriter& out, int width, int height, int channels, const SolverOptions& solver)
    : out_(out), width_(width), height_(height), channels_(channels), end_(width), flag_row_(width),
      row_(static_cast<std::size_t>(width) * channels) {
  policy_.dir = solver.temp_dir;
  policy_.budget = &schedule::ScratchBudget::process();  // one byte a pixel, in memory while it fits
  policy_.budget->apply(solver);
}

OutputFixups::~OutputFixups() = default;

void OutputFixups::set_columns(int begin, int end) {
  if (unflagged_ > 0 || flags_) throw std::logic_error("OutputFixups::set_columns after the first record");
  begin_ = begin;
  end_ = end;
  flag_row_.resize(end - begin);
  out_.set_columns(begin, end);
}

namespace {

// Whether any of the n samples is not finite (v - v != 0 exactly then, as record() tests a
// sample): whether the largest exponent field met is all ones, a maximum over integers that the
// compiler vectorises (a reduction of the float comparisons into a bool it does not).
GDP_CLONES bool any_not_finite(const float* v, int n) {
  constexpr std::uint32_t kExponent = 0x7f800000u;
  std::uint32_t top = 0;
  for (int i = 0; i < n; ++i) {
    std::uint32_t bits;
    std::memcpy(&bits, v + i, sizeof bits);
    top = std::max(top, bits & kExponent);
  }
  return top == kExponent;
}

GDP_CLONES bool any_set(const unsigned char* f, int n) {
  unsigned char any = 0;
  for (int i = 0; i < n; ++i) any |= f[i];
  return any != 0;
}

}  // namespace

void OutputFixups::record(int, std::span<const float> input, std::span<const unsigned char> zero) {
  const int n = end_ - begin_;
  unsigned char* flags = flag_row_.data();
  // Most rows have no flag at all (8- and 16-bit inputs never hold a non-finite sample): tested
  // first, a row at a time, without building the row's flags.
  bool some = !zero.empty() && any_set(zero.data() + begin_, n);
  for (int c = 0; c < channels_ && c < 7 && !some; ++c)
    some = any_not_finite(input.data() + static_cast<std::size_t>(c) * width_ + begin_, n);
  if (!some && !any_) {  // rows before the first flagged one are not stored (most images have none at all)
    ++unflagged_;
    return;
  }
  if (!some || zero.empty())
    std::fill(flag_row_.begin(), flag_row_.end(), 0);
  else
    for (int i = 0; i < n; ++i) flags[i] = zero[begin_ + i] ? kZero : 0;
  for (int c = 0; some && c < channels_ && c < 7; ++c) {
    const float* in = input.data() + static_cast<std::size_t>(c) * width_ + begin_;
    const auto bit = static_cast<unsigned char>(1u << c);
    // v - v != 0 exactly when v is not finite: a test the compiler vectorises (std::isfinite is not).
    for (int i = 0; i < n; ++i) flags[i] |= in[i] - in[i] != 0.0f ? bit : 0;
  }
  any_ = true;
  if (!flags_)
    flags_ = std::make_unique<schedule::RowStore<unsigned char>>(policy_, end_ - begin_, height_ - unflagged_, "flags");
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
  for (int i = begin_; i < end_; ++i) {
    const unsigned char f = flag_row_[i - begin_];
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
