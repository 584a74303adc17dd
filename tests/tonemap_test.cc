// gdp tonemap: a real HDR map (range, local contrast), schedules, the beta = 1 identity, wrap and folds, CLI errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "apps/tonemap_window.h"
#include "cli_fixture.h"
#include "gdp/apps.h"
#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "test_util.h"


namespace gdp {
namespace {

// A real HDR environment map (Poly Haven venice_sunset, sun in view; tests/data holds it at
// 256x128, box-filtered by 4 from the 1024x512 original), box-filtered by `factor`.
Image real_map(int factor) {
  const Image full = read_image(GDP_TEST_DATA "/polyhaven/venice_sunset_256.hdr").image;
  Image out(full.width / factor, full.height / factor, full.channels);
  for (int c = 0; c < full.channels; ++c)
    for (int y = 0; y < out.height; ++y)
      for (int x = 0; x < out.width; ++x) {
        double s = 0.0;
        for (int b = 0; b < factor; ++b)
          for (int a = 0; a < factor; ++a) s += full.at(c, x * factor + a, y * factor + b);
        out.at(c, x, y) = static_cast<float>(s / (factor * factor));
      }
  return out;
}

double luminance(const Image& img, int x, int y) {
  if (img.channels < 3) return img.at(0, x, y);
  return 0.2126 * img.at(0, x, y) + 0.7152 * img.at(1, x, y) + 0.0722 * img.at(2, x, y);
}

// Log luminance per pixel, values first raised to `gamma` (to undo a display encoding).
std::vector<double> log_luminance(const Image& img, double gamma = 1.0) {
  std::vector<double> out;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      Image lin(1, 1, 3);
      double l = 0.0;
      if (gamma == 1.0) {
        l = luminance(img, x, y);
      } else {
        for (int c = 0; c < std::min(3, img.channels); ++c)
          l += (img.channels < 3 ? 1.0 : c == 0 ? 0.2126 : c == 1 ? 0.7152 : 0.0722) *
               std::pow(std::max(0.0f, img.at(c, x, y)), gamma);
      }
      out.push_back(std::log(std::max(l, 1e-6)));
    }
  return out;
}

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p / 100.0 * double(v.size())))];
}

// |5-point Laplacian| of a log-luminance field at the interior pixels where `mask` is set.
std::vector<double> laplacians(const std::vector<double>& f, int w, int h, const std::vector<bool>& mask) {
  std::vector<double> out;
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      const std::size_t k = static_cast<std::size_t>(y) * w + x;
      if (mask[k]) out.push_back(std::abs(f[k - 1] + f[k + 1] + f[k - w] + f[k + w] - 4.0 * f[k]));
    }
  return out;
}

SolverOptions solver_options() {
  SolverOptions o;
  o.vcycles = 2;
  o.coarsest_size = 16;
  return o;
}

TEST(Tonemap, RealMapUsesTheRangeAndKeepsLocalContrast) {
  const Image in = real_map(1);  // 256 x 128
  const TonemapOptions opt;
  const Image out = tonemap(in, opt, solver_options());
  ASSERT_EQ(out.channels, 3);
  for (float v : out.data) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f) << v;
  // Range: the 1st..99th percentile of the display luminance spans most of [0, 1].
  std::vector<double> display;
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) display.push_back(luminance(out, x, y));
  const double span = percentile(display, 99) - percentile(display, 1);
  EXPECT_GE(span, 0.6);
  // Dynamic range compressed: the 1..99 percentile span of log luminance, output over input.
  // Contrast, measured without the black point (low percentile 0: display values are then
  // the solved luminance scaled, to the power 1 / gamma) so that it cannot stretch the darks.
  TonemapOptions plain = opt;
  plain.low_percentile = 0.0;
  const Image scaled = tonemap(in, plain, solver_options());
  const std::vector<double> lin = log_luminance(in), lout = log_luminance(scaled, opt.gamma);
  // Dynamic range: the 1..99 percentile span of log luminance, output over input.
  const double global = (percentile(lout, 99) - percentile(lout, 1)) / (percentile(lin, 99) - percentile(lin, 1));
  // Local contrast in the mid-tones (display luminance 0.1..0.9): mean |Laplacian| of log
  // luminance, output over input.
  std::vector<bool> mid(display.size());
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const double l = luminance(scaled, x, y);
      mid[static_cast<std::size_t>(y) * out.width + x] = l > 0.1 && l < 0.9;
    }
  const std::vector<double> lap_in = laplacians(lin, in.width, in.height, mid),
                            lap_out = laplacians(lout, in.width, in.height, mid);
  const auto mean = [](const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size()); };
  const double local = mean(lap_out) / mean(lap_in), median = percentile(lap_out, 50) / percentile(lap_in, 50);
  std::cout << "display 1..99% span " << span << "; log-luminance 1..99% span ratio " << global
            << "; mid-tone |Laplacian| ratio: mean " << local << ", median " << median << "\n";
  RecordProperty("display_span", std::to_string(span));
  RecordProperty("local_contrast_ratio", std::to_string(local));
  RecordProperty("median_contrast_ratio", std::to_string(median));
  // A global tone curve with the same compression would give local == median == global.
  EXPECT_LT(global, 0.6);            // the dynamic range is compressed ...
  EXPECT_GT(local, 1.15 * global);   // ... more than the local contrast (edges included) ...
  EXPECT_GT(median, 1.4 * global);   // ... and much more than the typical detail
  EXPECT_GT(local, 0.3);
  EXPECT_LT(local, 1.5);
}

TEST(Tonemap, StreamingAndInCoreAgree) {
  const Image in = real_map(2);  // 128 x 64
  SolverOptions streaming = solver_options();
  streaming.incore_bytes = 0;  // every level streams, every store is a scratch file
  SolverOptions incore = solver_options();
  incore.schedule = Schedule::InCore;
  TonemapOptions opt;
  opt.scales = 3;
  SolveSummary s;
  const Image a = tonemap(in, opt, streaming, &s), b = tonemap(in, opt, incore);
  EXPECT_EQ(s.schedule, "streaming");
  EXPECT_GT(s.streamed_levels, 0);
  EXPECT_EQ(test::max_difference(a, b), 0.0);
}

// Luminance only (colour channels may clip at 1 where the luminance does not).
Image grey(const Image& in) {
  Image out(in.width, in.height, 1);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) out.at(0, x, y) = static_cast<float>(luminance(in, x, y));
  return out;
}

// beta = 1 leaves every gradient alone, so the solve rebuilds the input's log luminance: with
// gamma 1 and no black point the output is the input times a constant.
void expect_identity(const Image& in, Domain domain, int scales) {
  TonemapOptions opt;
  opt.beta = 1.0;
  opt.scales = scales;
  opt.saturation = 1.0;
  opt.gamma = 1.0;
  opt.low_percentile = 0.0;
  opt.high_percentile = 100.0;
  SolverOptions o = solver_options();
  o.domain = domain;
  o.precision = Precision::Float64;
  o.tolerance = 1e-11;
  o.coarsest_size = 8;
  const Image out = tonemap(in, opt, o);
  const std::vector<double> a = log_luminance(in), b = log_luminance(out);
  double mean = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) mean += (b[k] - a[k]) / double(a.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(b[k] - a[k] - mean));
  EXPECT_LT(worst, 1e-4);
  EXPECT_NEAR(*std::max_element(out.data.begin(), out.data.end()), 1.0, 1e-5);  // the brightest maps to 1
}

TEST(Tonemap, BetaOneReproducesTheLogLuminance) {
  expect_identity(grey(real_map(2)), Domain::Planar, 1);
}

TEST(Tonemap, BetaOneReproducesTheLogLuminanceOnTheSphere) {
  // A random PQ image: exact only when the gradients across both folds are given.
  Image in = test::random_image(128, 32, 1, 7);
  for (float& v : in.data) v = std::exp(6.0f * v);
  expect_identity(in, Domain::Spherical, 1);
}

// Columns shifted by `shift` (wrapping around).
Image rolled(const Image& in, int shift) {
  Image out(in.width, in.height, in.channels);
  for (int c = 0; c < in.channels; ++c)
    for (int y = 0; y < in.height; ++y)
      for (int x = 0; x < in.width; ++x) out.at(c, (x + shift) % in.width, y) = in.at(c, x, y);
  return out;
}

TEST(Tonemap, CylinderHasNoSeam) {
  // On a cylinder the result cannot depend on where the image was cut: tone mapping a map
  // rolled by half its width gives the rolled result (pyramid filters and gradients wrap).
  const Image in = real_map(1);  // 256 x 128
  TonemapOptions opt;
  opt.scales = 4;  // half the width is a multiple of 2^3: every level rolls by whole pixels
  SolverOptions o = solver_options();
  o.domain = Domain::Cylindrical;
  o.precision = Precision::Float64;
  o.tolerance = 1e-10;
  const Image a = rolled(tonemap(in, opt, o), in.width / 2), b = tonemap(rolled(in, in.width / 2), opt, o);
  EXPECT_LT(test::max_difference(a, b), 1e-4);
  o.domain = Domain::Planar;  // the same on a plane: the cut shows
  const Image c = rolled(tonemap(in, opt, o), in.width / 2), d = tonemap(rolled(in, in.width / 2), opt, o);
  EXPECT_GT(test::max_difference(c, d), 1e-2);
}

// A PQ image (4H x H) that is smooth across both folds (cos(2 pi k x / W) cos(pi m y / H) and
// sin sin with k even are unchanged by the two 180-degree rotations), with a wide range: the
// log luminance spans 8 (a factor of about 3000).
Image fold_continuous_pq(int h) {
  const int w = 4 * h;
  Image img(w, h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double px = 2 * M_PI * (x + 0.5) / w, py = M_PI * (y + 0.5) / h;
      img.at(0, x, y) = static_cast<float>(std::exp(2.5 * std::cos(2 * px) * std::cos(3 * py) +
                                                    1.5 * std::sin(4 * px) * std::sin(py)));
    }
  return img;
}

// Largest |difference of log values| between fold partners ((i, 0) and (W-1-i, 0); (i, H-1) and
// (W/2-1-i mod W, H-1)), and between vertical neighbours inside.
std::pair<double, double> fold_and_inner_jumps(const Image& img) {
  const int w = img.width, h = img.height;
  const auto l = [&](int x, int y) { return std::log(std::max(1e-6, double(img.at(0, x, y)))); };
  double fold = 0.0, inner = 0.0;
  for (int i = 0; i < w; ++i) {
    fold = std::max(fold, std::abs(l(i, 0) - l(w - 1 - i, 0)));
    fold = std::max(fold, std::abs(l(i, h - 1) - l(((w / 2 - 1 - i) % w + w) % w, h - 1)));
    for (int y = 0; y + 1 < h; ++y) inner = std::max(inner, std::abs(l(i, y + 1) - l(i, y)));
  }
  return {fold, inner};
}

TEST(Tonemap, SphereIsContinuousAcrossTheFolds) {
  const Image in = fold_continuous_pq(32);  // 128 x 32
  const auto [fold_in, inner_in] = fold_and_inner_jumps(in);
  ASSERT_LT(fold_in, 0.5 * inner_in);
  TonemapOptions opt;
  opt.beta = 0.8;
  opt.gamma = 1.0;
  opt.low_percentile = 0.0;
  opt.high_percentile = 100.0;
  SolverOptions o = solver_options();
  o.domain = Domain::Spherical;
  o.precision = Precision::Float64;
  o.tolerance = 1e-10;
  o.coarsest_size = 8;
  const Image out = tonemap(in, opt, o);
  const auto [fold_out, inner_out] = fold_and_inner_jumps(out);
  std::cout << "fold jump / inner jump: input " << fold_in / inner_in << ", output " << fold_out / inner_out << "\n";
  EXPECT_LT(fold_out, 0.5 * inner_out);
  EXPECT_LT(fold_out / inner_out, 1.5 * fold_in / inner_in);
}

TEST(Tonemap, PyramidRowsContinueAcrossTheDomainsEdges) {
  // The rows every pyramid filter reads beyond the top and bottom: reflected on the plane,
  // read mirrored across the folds on a PQ domain (docs/sphere-solver.md).
  const int w = 8, h = 4;
  const auto value = [](int i, int y) { return static_cast<float>(10 * y + i); };
  for (Domain d : {Domain::Planar, Domain::Spherical}) {
    apps::tonemap::RowWindow window(d, w, h, 4);
    for (int y = 0; y < h; ++y) {
      std::vector<float> row(w);
      for (int i = 0; i < w; ++i) row[i] = value(i, y);
      window.push(row);
    }
    const bool pq = d == Domain::Spherical;
    for (int i = 0; i < w; ++i) {
      const int top = pq ? w - 1 - i : i, bottom = pq ? ((w / 2 - 1 - i) % w + w) % w : i;
      EXPECT_EQ(window.row(-1)[i], value(top, 0));
      EXPECT_EQ(window.row(-2)[i], value(top, 1));
      EXPECT_EQ(window.row(h)[i], value(bottom, h - 1));
      EXPECT_EQ(window.row(h + 1)[i], value(bottom, h - 2));
    }
    EXPECT_EQ(window.column(-1), pq ? w - 1 : 0);
    EXPECT_EQ(window.column(w), pq ? 0 : w - 1);
  }
}

// Each pixel repeated f x f times.
Image enlarged(const Image& in, int f) {
  Image out(in.width * f, in.height * f, in.channels);
  for (int c = 0; c < in.channels; ++c)
    for (int y = 0; y < out.height; ++y)
      for (int x = 0; x < out.width; ++x) out.at(c, x, y) = in.at(c, x / f, y / f);
  return out;
}

// Mean of each f x f block.
Image shrunk(const Image& in, int f) {
  Image out(in.width / f, in.height / f, in.channels);
  for (int c = 0; c < in.channels; ++c)
    for (int y = 0; y < in.height; ++y)
      for (int x = 0; x < in.width; ++x) out.at(c, x / f, y / f) += in.at(c, x, y) / float(f * f);
  return out;
}

double mean_difference(const Image& a, const Image& b) {
  double s = 0.0;
  for (std::size_t k = 0; k < a.data.size(); ++k) s += std::abs(double(a.data[k]) - b.data[k]);
  return s / double(a.data.size());
}

TEST(Tonemap, PreviewAndFullSizeAgreeWithAResolution) {
  // The same scene at 128x64 and at 4x that size: with the attenuation tied to the 128-wide
  // level, the large one (shrunk back) looks like the small one; attenuating every level of
  // the large one compresses it more.
  const Image small = real_map(2), large = enlarged(small, 4);
  TonemapOptions opt;
  opt.resolution = 128;
  SolverOptions o = solver_options();
  o.domain = Domain::Cylindrical;
  const Image preview = tonemap(small, opt, o);
  const double tied = mean_difference(preview, shrunk(tonemap(large, opt, o), 4));
  opt.resolution = 0;
  const double every = mean_difference(preview, shrunk(tonemap(large, opt, o), 4));
  std::cout << "preview vs shrunk full size, mean difference: resolution 128 " << tied << ", every level " << every
            << "\n";
  EXPECT_LT(tied, 0.02);
  EXPECT_GT(every, 4.0 * tied);
}

TEST(Tonemap, BadOptionsAreUsageErrors) {
  const Image in = test::random_image(16, 16, 3);
  for (auto change : {+[](TonemapOptions& o) { o.beta = 0.0; }, +[](TonemapOptions& o) { o.alpha = -1.0; },
                      +[](TonemapOptions& o) { o.gamma = 0.0; }, +[](TonemapOptions& o) { o.scales = -2; }, +[](TonemapOptions& o) { o.resolution = -1; },
                      +[](TonemapOptions& o) { o.high_percentile = 0.5; }}) {
    TonemapOptions opt;
    change(opt);
    EXPECT_THROW(tonemap(in, opt, solver_options()), UsageError);
  }
}

class TonemapCli : public test::CliFixture {};

TEST_F(TonemapCli, NamesABadInputAndLeavesNothing) {
  std::ofstream(path("broken.exr")) << "not an image";
  expect_failure("tonemap " + path("broken.exr") + " -o " + path("out.png"), "broken.exr");
  EXPECT_EQ(files(), std::set<std::string>{"broken.exr"});
}

}  // namespace
}  // namespace gdp
