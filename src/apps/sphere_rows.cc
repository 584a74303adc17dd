// Readers and writers that move an application's rows between equirectangular and PQ images.
#include "gdp/sphere_rows.h"

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp {
namespace {

const sphere::Projection kEquirect{sphere::Layout::Equirect};
const sphere::Projection kPq{sphere::Layout::Pq};

// The PQ image resampled from an equirectangular reader, served row by row (rewind() serves it
// again).
class PqReader final : public RowReader {
 public:
  PqReader(RowReader& equirect, int pq_height, bool nearest) : pq_(4 * pq_height, pq_height, equirect.channels()) {
    sphere::ResampleOptions o;
    o.nearest = nearest;
    ImageRowWriter w(pq_);
    sphere::resample(equirect, kEquirect, w, kPq, pq_.width, pq_.height, o);
  }
  int width() const override { return pq_.width; }
  int height() const override { return pq_.height; }
  int channels() const override { return pq_.channels; }
  void read_row(int y, std::span<float> out) override { ImageRowReader(pq_).read_row(y, out); }
  void rewind() override {}

 private:
  Image pq_;
};

// Collects PQ rows; commit() resamples them to the equirectangular writer and commits it.
class EquirectWriter final : public RowWriter {
 public:
  EquirectWriter(RowWriter& out, int pq_height, int channels, int width, int height)
      : out_(out), pq_(4 * pq_height, pq_height, channels), width_(width), height_(height) {}
  void write_row(int y, std::span<const float> row) override { ImageRowWriter(pq_).write_row(y, row); }
  void commit() override {
    ImageRowReader r(pq_);
    sphere::resample(r, kPq, out_, kEquirect, width_, height_);
    out_.commit();
  }

 private:
  RowWriter& out_;
  Image pq_;
  int width_, height_;
};

}  // namespace

SphereRows::SphereRows(int width, int height, const std::string& name, int pq_height)
    : width_(width), height_(height), name_(name) {
  if (width == 4 * height) {
    resampled_ = false;
    pq_height_ = height;
  } else if (width == 2 * height) {
    resampled_ = true;
    pq_height_ = pq_height > 0 ? pq_height : sphere::default_pq_height(static_cast<long long>(width) * height);
  } else {
    throw InputError(fmt::format("{}: a spherical image must be equirectangular (2:1) or PQ (4:1), not {}x{}", name,
                                 width, height));
  }
}

SphereRows::~SphereRows() = default;

RowReader& SphereRows::input(RowReader& input, const std::string& input_name, bool nearest) {
  if (input.width() != width_ || input.height() != height_)
    throw InputError(fmt::format("{}: {}x{}, but {} is {}x{}", input_name, input.width(), input.height(), name_,
                                 width_, height_));
  if (!resampled_) return input;
  readers_.push_back(std::make_unique<PqReader>(input, pq_height_, nearest));
  return *readers_.back();
}

RowWriter& SphereRows::output(RowWriter& out, int channels) {
  if (!resampled_) return out;
  writer_ = std::make_unique<EquirectWriter>(out, pq_height_, channels, width_, height_);
  return *writer_;
}

}  // namespace gdp
