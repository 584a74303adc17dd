// Stored PQ -> target WCS: target pixel -> (lon, lat) -> PQ coordinates -> cubic (bilinear near blanks) among finite PQ pixels.
#include "sky/reproject.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "sky/interpolate.h"
#include "sky/plate.h"
#include "sphere/source.h"
#include "util/workers.h"

namespace gdp::sky {

namespace {
constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr int kStencil = 3;  // rows a sample reaches beyond its nearest (Catmull-Rom: 2; the folds mirror)
}  // namespace

PqSampler::PqSampler(const PqStore& pq)
    : pq_(pq),
      window_(pq.window()),
      grid_(sphere::make_source({sphere::Layout::Pq, sphere::SquareMap::Toast, false}, 4 * window_.height,
                                window_.height, toast_depth(window_.height))) {}

PqSampler::~PqSampler() = default;

void PqSampler::hold(int lo, int hi) {
  lo = std::max(lo, 0);
  hi = std::min(hi, window_.rows - 1);
  std::vector<std::vector<float>> rows(std::max(0, hi - lo + 1));
  const int old_hi = lo_ + static_cast<int>(rows_.size()) - 1;
  for (int j = lo; j <= hi; ++j) {
    std::vector<float>& r = rows[j - lo];
    if (j >= lo_ && j <= old_hi) {
      r = std::move(rows_[j - lo_]);
    } else {
      r.resize(window_.width);
      pq_.read_row(j, r);
    }
  }
  rows_ = std::move(rows);
  lo_ = lo;
  peak_rows_ = std::max(peak_rows_, static_cast<int>(rows_.size()));
}

void PqSampler::sample(std::span<const sphere::Vec3> dirs, std::span<float> out, int threads) {
  coords_.resize(dirs.size());
  int lo = window_.rows, hi = -1;
  for (std::size_t k = 0; k < dirs.size(); ++k) {
    coords_[k] = grid_->coords(dirs[k]);
    const int ly = std::clamp(static_cast<int>(std::floor(coords_[k].y)), 0, window_.height - 1) - window_.j0;
    lo = std::min(lo, ly - kStencil);
    hi = std::max(hi, ly + kStencil);
  }
  hold(lo, hi);
  const std::size_t n = dirs.size();
  threads = static_cast<int>(std::clamp<std::size_t>(threads, 1, std::max<std::size_t>(1, n / 4096)));
  util::run_workers(threads, [&](int t) {
    for (std::size_t k = n * t / threads; k < n * (t + 1) / threads; ++k) out[k] = value(coords_[k]);
  });
}

float PqSampler::at(const sphere::Vec3& d) {
  float v = kNan;
  sample({&d, 1}, {&v, 1});
  return v;
}

float PqSampler::value(const sphere::Point2& p) const {
  const int H = window_.height;
  const int hx = std::clamp(static_cast<int>(std::floor(p.x)), 0, 4 * H - 1);
  const int hy = std::clamp(static_cast<int>(std::floor(p.y)), 0, H - 1);
  const int lx = hx - window_.i0, ly = hy - window_.j0;  // in the window
  if (lx < 0 || ly < 0 || lx >= window_.width || ly >= window_.rows) return kNan;
  if (!std::isfinite(pixel(lx, ly))) return kNan;
  // Finite: the nearest pixel is. The whole sphere wraps across its folds; a window (which
  // meets none) clamps.
  if (window_.whole())
    return interpolate_finite(p.x, p.y, [&](int i, int j) {
      const std::size_t o = grid_->offset(i, j, hx, hy), w = window_.width;
      return pixel(static_cast<int>(o % w), static_cast<int>(o / w));
    });
  return interpolate_finite(p.x - window_.i0, p.y - window_.j0, [&](int i, int j) {
    return pixel(std::clamp(i, 0, window_.width - 1), std::clamp(j, 0, window_.rows - 1));
  });
}

long long reproject_pq(const PqStore& pq, const Wcs& target, RowWriter& out) {
  constexpr int kTileRows = 64, kTileColumns = 256;
  const int w = target.width(), h = target.height();
  PqSampler sampler(pq);
  std::vector<double> xy, sky;
  std::vector<unsigned char> ok;
  std::vector<sphere::Vec3> dirs;
  std::vector<float> values, band(static_cast<std::size_t>(w) * kTileRows);
  long long covered = 0;
  for (int y0 = 0; y0 < h; y0 += kTileRows) {
    const int rows = std::min(kTileRows, h - y0);
    for (int x0 = 0; x0 < w; x0 += kTileColumns) {
      const int columns = std::min(kTileColumns, w - x0);
      const std::size_t n = static_cast<std::size_t>(rows) * columns;
      xy.resize(2 * n);
      sky.resize(2 * n);
      ok.resize(n);
      for (std::size_t k = 0; k < n; ++k) {
        xy[2 * k] = x0 + static_cast<int>(k % columns) + 0.5;
        xy[2 * k + 1] = y0 + static_cast<int>(k / columns) + 0.5;
      }
      target.pixel_to_sky(xy, sky, ok);
      dirs.clear();
      for (std::size_t k = 0; k < n; ++k)
        if (ok[k]) dirs.push_back(direction(sky[2 * k], sky[2 * k + 1]));
      values.resize(dirs.size());
      sampler.sample(dirs, values);
      for (std::size_t k = 0, d = 0; k < n; ++k)
        band[(k / columns) * w + x0 + k % columns] = ok[k] ? values[d++] : kNan;
    }
    for (int r = 0; r < rows; ++r) {
      const std::span<const float> row(band.data() + static_cast<std::size_t>(r) * w, w);
      covered += std::count_if(row.begin(), row.end(), [](float v) { return std::isfinite(v); });
      out.write_row(y0 + r, row);
    }
  }
  return covered;
}

}  // namespace gdp::sky
