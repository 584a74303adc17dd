// Blending in another colour space: rows converted on their way into the solver and back on their way out.
#pragma once

#include <span>
#include <vector>

#include "gdp/apps.h"
#include "gdp/rows.h"

namespace gdp::apps {

// Converts one row (channel-major, `width` samples per channel) into the space or back. Log
// works per channel; Lab needs three channels (further ones pass through as they are).
// Non-finite samples stay non-finite.
void to_space(const BlendSpace& space, std::span<float> row, int width, int channels);
void from_space(const BlendSpace& space, std::span<float> row, int width, int channels);

// A reader whose rows come converted into the space.
class SpaceReader final : public RowReader {
 public:
  // `groups`: the row holds that many images of in.channels() / groups channels each, converted alike.
  SpaceReader(RowReader& in, const BlendSpace& space, int groups = 1) : in_(in), space_(space), groups_(groups) {}
  int width() const override { return in_.width(); }
  int height() const override { return in_.height(); }
  int channels() const override { return in_.channels(); }
  void read_row(int y, std::span<float> out) override {
    in_.read_row(y, out);
    const int ch = channels() / groups_;
    const std::size_t n = static_cast<std::size_t>(ch) * width();
    for (int g = 0; g < groups_; ++g) to_space(space_, out.subspan(g * n, n), width(), ch);
  }
  void rewind() override { in_.rewind(); }
  void set_columns(int begin, int end) override { in_.set_columns(begin, end); }

 private:
  RowReader& in_;
  BlendSpace space_;
  int groups_;
};

// A writer that converts rows back from the space before passing them on.
class SpaceWriter final : public RowWriter {
 public:
  SpaceWriter(RowWriter& out, const BlendSpace& space, int width, int channels)
      : out_(out), space_(space), width_(width), channels_(channels) {}
  void write_row(int y, std::span<const float> row) override {
    if (space_.kind == BlendSpace::Kind::Values) return out_.write_row(y, row);  // nothing to convert
    row_.assign(row.begin(), row.end());
    from_space(space_, row_, width_, channels_);
    out_.write_row(y, row_);
  }
  void commit() override { out_.commit(); }
  void set_columns(int begin, int end) override { out_.set_columns(begin, end); }

 private:
  RowWriter& out_;
  BlendSpace space_;
  int width_, channels_;
  std::vector<float> row_;
};

}  // namespace gdp::apps
