// The resampling driver: output rows in parallel, footprint-sized supersampling or interpolation.
#include <algorithm>
#include <cmath>
#include <thread>

#include "gdp/errors.h"
#include "gdp/size_check.h"
#include "sphere/source.h"
#include "sphere/target.h"
#include "sphere/vec3.h"
#include "util/workers.h"

namespace gdp::sphere {

namespace {

// Subsamples along one output axis: one (plain interpolation, no blur) while the output pixel is
// under 1.5 source pixels; beyond, two per source pixel across the output pixel (a box of
// samples spaced at one source pixel would alias the source's Nyquist frequency), at most 16.
int subsamples(const Vec3& step, double source_pixel) {
  const double ratio = norm(step) / source_pixel;
  if (ratio < 1.5) return 1;
  return static_cast<int>(std::min(16.0, std::ceil(2.0 * ratio)));
}

// The TOAST inverse's depth for a PQ source. Stopping at triangles of side h misplaces points by
// under 1e-3 h^2 radians (measured: SphereGrid tests), so half the pixel level plus two keeps
// that below a thousandth of a pixel at any size (8 levels for N = 4096 instead of 30).
int toast_depth(const Projection& from, int height) {
  int level = 1;
  while ((1LL << level) < 2LL * height) ++level;
  return from.layout == Layout::Pq ? std::min(30, std::max(4, (level + 1) / 2 + 2)) : 30;
}

void check_size(const Projection& p, int width, int height, const char* what) {
  const bool ok = width > 0 && height > 0 && (p.layout != Layout::Pq || width == 4 * height) &&
                  (p.layout != Layout::Cube || height == 6 * width);
  if (!ok)
    throw UsageError(std::string(what) + " size " + std::to_string(width) + "x" + std::to_string(height) +
                     " does not fit its layout (PQ: W = 4H; cube strip: F x 6F)");
}

void resample_rows(const Image& src, const SourceGrid& grid, const Projection& to, const ResampleOptions& opt,
                   Image& out, int j0, int j1) {
  auto target = make_target(to, out.width, out.height);
  const int nc = src.channels;
  std::vector<float> acc(nc);
  const double pixel = grid.pixel_angle();
  for (int j = j0; j < j1; ++j) {
    const TargetRow& r = target->row(j);
    for (int i = 0; i < out.width; ++i) {
      const Vec3 d = rotate(opt.rotation, r.d[i]);
      if (opt.nearest) {
        nearest(src, grid, d, acc.data());
      } else {
        const Vec3 du = rotate(opt.rotation, r.du[i]), dv = rotate(opt.rotation, r.dv[i]);
        const int nu = subsamples(du, pixel), nv = subsamples(dv, pixel);
        std::fill(acc.begin(), acc.end(), 0.0f);
        const float weight = 1.0f / static_cast<float>(nu * nv);
        for (int b = 0; b < nv; ++b)
          for (int a = 0; a < nu; ++a) {
            const double u = (a + 0.5) / nu - 0.5, v = (b + 0.5) / nv - 0.5;
            const Vec3 ds = (nu == 1 && nv == 1) ? d : d + u * du + v * dv;
            add_interpolated(src, grid, ds, weight, acc.data());
          }
      }
      for (int c = 0; c < nc; ++c) out.at(c, i, j) = acc[c];
    }
  }
}

}  // namespace

std::array<int, 2> layout_size(Layout layout, int size) {
  switch (layout) {
    case Layout::Equirect: return {size, std::max(1, size / 2)};
    case Layout::Pq: return {4 * size, size};
    case Layout::Cube: break;
  }
  return {size, 6 * size};
}

int default_size(Layout layout, long long source_pixels) {
  switch (layout) {
    case Layout::Pq: return default_pq_height(source_pixels);
    case Layout::Equirect: return 2 * static_cast<int>(std::lround(std::sqrt(source_pixels / 2.0)));
    case Layout::Cube: break;
  }
  return std::max(1, static_cast<int>(std::lround(std::sqrt(source_pixels / 6.0))));
}

std::array<int, 2> plan_resampling(bool to_pq, Layout& other, int size, int width, int height, int channels,
                                   const std::string& name) {
  if (to_pq) {
    try {
      other = guess_layout(width, height);
    } catch (const InputError& e) {
      throw InputError(name + ": " + e.what());
    }
    if (other == Layout::Pq) throw InputError(name + ": is already a PQ image (4:1)");
  } else if (width != 4 * height) {
    throw InputError(name + ": " + std::to_string(width) + "x" + std::to_string(height) +
                     " is not a PQ image (width must be 4 x height)");
  }
  const Layout out = to_pq ? Layout::Pq : other;
  const long long side = size > 0 ? size : default_size(out, static_cast<long long>(width) * height);
  // Sides in long long, so that an option's product cannot have overflowed before the check.
  const long long w = out == Layout::Pq ? 4 * side : side;
  const long long h = out == Layout::Pq ? side : out == Layout::Cube ? 6 * side : std::max(1LL, side / 2);
  check_derived_size(std::string(to_pq ? "--height " : "--width ") + std::to_string(side), w, h, channels);
  return layout_size(out, static_cast<int>(side));
}

Layout guess_layout(int width, int height) {
  if (width == 4 * height) return Layout::Pq;
  if (height == 6 * width) return Layout::Cube;
  if (width == 2 * height) return Layout::Equirect;
  throw InputError("image of " + std::to_string(width) + "x" + std::to_string(height) +
                   " is none of equirectangular (2:1), PQ (4:1) or cube strip (1:6)");
}

Image resample(const Image& source, const Projection& from, const Projection& to, int out_width, int out_height,
               const ResampleOptions& options) {
  check_size(from, source.width, source.height, "source");
  check_size(to, out_width, out_height, "output");
  const auto grid = make_source(from, source.width, source.height, toast_depth(from, source.height));
  Image out(out_width, out_height, source.channels);
  int threads = options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency());
  threads = std::clamp(threads, 1, std::max(1, out_height));
  // Contiguous blocks of rows (a PQ cursor reuses neighbouring rows).
  util::run_workers(threads, [&](int t) {
    const int j0 = static_cast<int>(static_cast<long long>(out_height) * t / threads);
    const int j1 = static_cast<int>(static_cast<long long>(out_height) * (t + 1) / threads);
    resample_rows(source, *grid, to, options, out, j0, j1);
  });
  return out;
}

void resample(RowReader& source, const Projection& from, RowWriter& out, const Projection& to, int out_width,
              int out_height, const ResampleOptions& options) {
  Image src(source.width(), source.height(), source.channels());
  ImageRowWriter fill(src);
  std::vector<float> row(static_cast<std::size_t>(src.width) * src.channels);
  for (int y = 0; y < src.height; ++y) {
    source.read_row(y, row);
    fill.write_row(y, row);
  }
  const Image result = resample(src, from, to, out_width, out_height, options);
  ImageRowReader rows(result);
  row.resize(static_cast<std::size_t>(result.width) * result.channels);
  for (int y = 0; y < result.height; ++y) {
    rows.read_row(y, row);
    out.write_row(y, row);
  }
}

}  // namespace gdp::sphere
