// A guidance source that forwards every call to another: the base of sources that change a few.
#pragma once

#include "gdp/guidance.h"

namespace gdp::util {

// Forwards the size, alpha, the weights and initial flags, read_row and set_columns to `inner`
// (which outlives it). Not a splitting source: splits() stays false, so read_row is all there is.
class ForwardingGuidance : public GuidanceSource {
 public:
  explicit ForwardingGuidance(GuidanceSource& inner) : inner_(inner) {}
  int width() const override { return inner_.width(); }
  int height() const override { return inner_.height(); }
  int channels() const override { return inner_.channels(); }
  double alpha() const override { return inner_.alpha(); }
  bool has_weights() const override { return inner_.has_weights(); }
  bool has_initial() const override { return inner_.has_initial(); }
  bool start_from_initial() const override { return inner_.start_from_initial(); }
  void read_row(int j, GuidanceRow& out) override { inner_.read_row(j, out); }
  void set_columns(int begin, int end) override { inner_.set_columns(begin, end); }

 protected:
  GuidanceSource& inner_;
};

}  // namespace gdp::util
