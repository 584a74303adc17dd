// The input pass by band: rows decoded once, each band's columns made by its workers, the same bits as one reader.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <thread>
#include <limits>
#include <stdexcept>
#include <string>

#include "apps/image_guidance.h"
#include "gdp/errors.h"
#include "gdp/rows.h"
#include "gdp/solver.h"
#include "schedule/input_ring.h"
#include "schedule/parallel.h"
#include "schedule_problems.h"
#include "test_util.h"

namespace gdp {
namespace {

// An image's differences with edges cut and offsets at some of the kept ones, per-row data kept in
// the decode slots and blank samples: what a stitch's guidance does, on a pattern. It splits.
class Patterned final : public apps::ImageGuidance {
 public:
  Patterned(RowReader& image, int fail_decode = -1, int fail_column = -1)
      : ImageGuidance(image, 0.0, 1.0), fail_decode_(fail_decode), fail_column_(fail_column) {
    set_slots(slots());
  }
  bool splits() const override { return true; }
  void set_slots(int slots) override {
    ImageGuidance::set_slots(slots);
    shift_.assign(slots, 0.0);
  }
  void compute(int j, GuidanceRow& out, int begin, int end) const override {
    if (j == height() / 2 && begin <= fail_column_ && fail_column_ < end)
      throw InputError("row " + std::to_string(j) + " column " + std::to_string(fail_column_) + " is bad");
    ImageGuidance::compute(j, out, begin, end);
    for (int i = begin; i < end; ++i) out.counted[i] = (i + j) % 9 != 0;
  }

 protected:
  void on_source_row(int y, std::span<const float> row) override {
    if (y == fail_decode_) throw InputError("cannot decode row " + std::to_string(y));
    shift_[slot(y)] = 0.01 * row[0];
  }
  void keep_edges(int j, int begin, int end, std::span<unsigned char> right, std::span<unsigned char> down,
                  std::span<unsigned char> above) const override {
    for (int i = begin; i < end; ++i) {
      right[i] = (i * 7 + j) % 5 != 0;
      down[i] = down[i] && (i + 3 * j) % 6 != 0;
    }
    for (std::size_t i = 0; i < above.size(); ++i) above[i] = i % 4 != 0;
  }
  bool has_offsets() const override { return true; }
  bool offset_edges(int j, int begin, int end, std::span<unsigned char> right,
                    std::span<unsigned char> down) const override {
    for (int i = begin; i < end; ++i) {
      right[i] = (i + j) % 3 == 0;
      down[i] = (2 * i + j) % 5 == 0;
    }
    return true;
  }
  double offset(int c, int i, int j, bool horizontal) const override {
    return shift_[slot(j)] * (horizontal ? 1.0 : -0.5) + 0.001 * c + 1e-4 * i;
  }

 private:
  int fail_decode_, fail_column_;
  std::vector<double> shift_;
};

// The same rows read whole by one reader: a source that does not split.
class Whole final : public GuidanceSource {
 public:
  explicit Whole(GuidanceSource& s) : s_(s) {}
  int width() const override { return s_.width(); }
  int height() const override { return s_.height(); }
  int channels() const override { return s_.channels(); }
  bool has_initial() const override { return true; }
  void read_row(int j, GuidanceRow& out) override { s_.read_row(j, out); }

 private:
  GuidanceSource& s_;
};

Image pattern_image(int w, int h, int channels) {
  Image img(w, h, channels);
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        img.at(c, x, y) = (x * 13 + y * 7 + c * 5) % 17 == 0 ? std::numeric_limits<float>::quiet_NaN()
                                                              : std::sin(0.1f * x + 0.2f * c) * std::cos(0.07f * y) + 0.01f * x;
  return img;
}

struct Solved {
  Image out;
  SolveSummary summary;
};

Solved solve_with(GuidanceSource& source, Domain domain, int bands, Precision precision) {
  SolverOptions o;
  o.domain = domain;
  o.precision = precision;
  o.vcycles = 2;
  o.residuals = true;
  o.incore_bytes = 1;  // stream every level the plan allows
  if (bands > 0) {
    o.schedule = Schedule::Bands;
    o.bands = bands;
  }
  Solved r{Image(source.width(), source.height(), source.channels()), {}};
  ImageRowWriter writer(r.out);
  solve(source, o, writer, &r.summary);
  return r;
}

bool same_bits(const Image& a, const Image& b) {
  return a.data.size() == b.data.size() && std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0;
}

struct Case {
  Domain domain;
  int width, height, bands;
  Precision precision;
};

class InputRing : public ::testing::TestWithParam<Case> {};

// Each band's input rows made by its workers from rows decoded once give the same result, bit
// for bit, as one thread reading whole rows (what the solver did before; 0 bands: streaming).
TEST_P(InputRing, BandsMakeTheirColumnsWithTheSameBitsAsOneReader) {
  const Case k = GetParam();
  const Image img = pattern_image(k.width, k.height, 2);
  ImageRowReader a(img), b(img);
  Patterned split(a), serial(b);
  Whole whole(serial);
  ASSERT_TRUE(split.splits());
  const Solved readers = solve_with(split, k.domain, k.bands, k.precision);
  const Solved one = solve_with(whole, k.domain, k.bands, k.precision);
  EXPECT_TRUE(same_bits(readers.out, one.out));
  EXPECT_EQ(readers.summary.relative_residuals, one.summary.relative_residuals);
  EXPECT_GT(readers.summary.cpu_rhs_columns, 0.0);
}

INSTANTIATE_TEST_SUITE_P(Domains, InputRing,
                         ::testing::Values(Case{Domain::Planar, 200, 96, 0, Precision::Float32},
                                           Case{Domain::Planar, 200, 96, 1, Precision::Float64},
                                           Case{Domain::Planar, 211, 70, 3, Precision::Float32},
                                           Case{Domain::Planar, 300, 64, 5, Precision::Float64},
                                           Case{Domain::Cylindrical, 240, 64, 4, Precision::Float32},
                                           Case{Domain::Spherical, 256, 64, 2, Precision::Float32}),
                         [](const ::testing::TestParamInfo<Case>& i) {
                           std::string d = test::domain_name(i.param.domain);
                           return d.substr(0, d.size() - 1) + "_" + std::to_string(i.param.bands) + "bands_" +
                                  (i.param.precision == Precision::Float64 ? "double" : "float");
                         });

// The ring never makes a row into a slot whose row a reader may still read, and every reader sees
// every row in order, whoever made it (readers dawdle at different rows, so that each makes some).
TEST(RowRingSlots, ARowStaysInItsSlotUntilEveryReaderIsPastIt) {
  constexpr int kRows = 300, kSlots = 16;
  std::vector<std::atomic<int>> held(kSlots);
  std::vector<int> made_by(kRows, -1), wrong(3, 0);
  thread_local int me = -1;
  schedule::Marks marks;
  schedule::RowRing ring(marks, 3, kSlots, kRows, [&](int y) {
    held[y % kSlots] = y;
    made_by[y] = me;
  });
  util::run_workers(3, [&](int k) {
    me = k;
    for (int j = 0; j < kRows; ++j) {
      ring.need(k, j, std::min(j + 1, kRows - 1));
      if (j % 7 == k * 2) std::this_thread::sleep_for(std::chrono::microseconds(200));
      wrong[k] += held[j % kSlots] != j || (j + 1 < kRows && held[(j + 1) % kSlots] != j + 1);
    }
    ring.done(k);
  });
  EXPECT_EQ(wrong, std::vector<int>(3, 0));
  EXPECT_EQ(std::count(made_by.begin(), made_by.end(), -1), 0);
}

// A stop ends every wait on the marks with Stopped, and later waits too.
TEST(RowRingSlots, StopEndsEveryWait) {
  schedule::Marks marks;
  const int m = marks.add(2);
  util::run_workers(3, [&](int k) {
    if (k == 0) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      return marks.stop();
    }
    EXPECT_THROW(marks.wait(m + k - 1, 5), util::Stopped);
  });
  EXPECT_THROW(marks.wait(m, m + 2, -1, -1), util::Stopped);
}

// A row that cannot be decoded, or a band's columns that cannot be made, stops the whole run with
// that error (not "stopped", no hang).
TEST(InputRingErrors, ADecodeOrColumnFailureStopsTheRunWithTheRealError) {
  const Image img = pattern_image(240, 96, 2);
  for (const auto& [decode, column] : {std::pair{50, -1}, std::pair{-1, 200}, std::pair{-1, 3}}) {
    ImageRowReader r(img);
    Patterned failing(r, decode, column);
    try {
      solve_with(failing, Domain::Planar, 3, Precision::Float32);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(decode >= 0 ? "cannot decode row 50" : "column"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace gdp
