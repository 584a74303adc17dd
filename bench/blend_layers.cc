// Cuts a photo into nona-style cropped TIFF layers (XPOSITION/YPOSITION, PIXAR canvas size, alpha)
// with exposure offsets, vignetting and wavy edges, for bench/blend_vs_enblend.sh; also scores a blend.
//
//   blend_layers cut PHOTO OUTDIR [--size WxH] [--grid CxR] [--overlap F] [--offset O] [--vignette V] [--seed S]
//                    [--ghosts N]
//       writes OUTDIR/layer_NN.tif (8-bit RGBA) and OUTDIR/original.tif (the photo at the canvas size);
//       --ghosts: N moving objects per layer (discs of one colour) near its edges, in the overlaps
//   blend_layers tiles PHOTO OUTDIR [--tile T] [--grid CxR] [--overlap F] [--offset O] [--vignette V] [--seed S]
//       [--part K/N] (K of N processes cutting one grid: the same tiles and exposures, part 0 writes the list)
//                      [--upscale N] [--headroom H]
//       writes OUTDIR/tile_NNNNN.tif (T x T layers with XPOSITION/YPOSITION but no canvas tags, no
//       wavy edges: a microscopy slide's tiles)
//       and OUTDIR/tiles.txt (a --layers list: file x y); the photo is repeated mirrored at its own
//       resolution (--upscale N: the photo enlarged N times, bilinear, first; --headroom H: its values
//       mapped to [H, 1 - H], so that offsets up to H do not clip), so any canvas size is cut
//       without holding it
//   blend_layers tiles-error BLENDED PHOTO [--upscale N] [--headroom H]
//       as error, against the mirrored photo that tiles cut (a canvas of any size, streamed), and the
//       largest step between neighbouring 256x256 blocks' mean errors (a level step between layers)
//   blend_layers error BLENDED ORIGINAL
//       prints the RMS colour error (per value, 0..1) over the blend's covered pixels, each channel's
//       mean difference removed, and the largest such error
//   blend_layers compare BLENDED REFERENCE
//       the blend against a converged solve of the same blend (float samples, clipped to 0..1 as an
//       integer output is), over the blend's covered pixels, in 8-bit levels and without removing
//       any mean: RMS and largest difference,
//       the mean difference, and the fraction of samples whose 8-bit value (round(255 v)) differs
//       from the reference's (docs/blend.md, "The solver's sweeps")
#include <tiffio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "gdp/image_io.h"
#include "gdp/image_stream.h"

namespace {

using gdp::Image;

struct Cut {
  int width = 0, height = 0, cols = 4, rows = 4;
  double overlap = 0.2, offset = 40.0 / 255.0, vignette = 0.3;
  unsigned seed = 1;
  int ghosts = 0;
  int tile = 0;  // tiles: the tile size (the canvas follows from grid and overlap)
  int upscale = 1;  // tiles: the photo enlarged this many times before it is repeated
  double headroom = 0.0;  // tiles: the photo's values mapped to [headroom, 1 - headroom]
  int part = 0, parts = 1;  // tiles: this process writes the tiles n with n % parts == part
};

// A tile's exposure: a brightness offset and a falloff towards its corners.
struct Exposure {
  double shift = 0.0, vignette = 0.0;
  double at(double value, int x, int y, int w, int h) const {
    const double u = (x + 0.5) / w - 0.5, v = (y + 0.5) / h - 0.5;
    return value * (1.0 - vignette * 2.0 * (u * u + v * v)) + shift;
  }
};

// A moving object: a disc of one colour that only one layer saw.
struct Ghost {
  double x, y, r, colour[3];
};

// Ghosts of a w x h layer near its edges (within the overlap), in layer pixels.
std::vector<Ghost> ghosts_of(const Cut& o, int w, int h, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Ghost> g(o.ghosts);
  for (Ghost& q : g) {
    const int side = static_cast<int>(u(rng) * 4) % 4;
    const double depth = o.overlap * (side < 2 ? w : h) * u(rng), along = u(rng);
    q.x = side == 0 ? depth : side == 1 ? w - 1 - depth : along * w;
    q.y = side == 2 ? depth : side == 3 ? h - 1 - depth : along * h;
    q.r = 0.2 * o.overlap * std::min(w, h);
    for (double& c : q.colour) c = u(rng);
  }
  return g;
}

// Bilinear resampling of the photo to the canvas size.
Image resize(const Image& in, int w, int h) {
  if (w == in.width && h == in.height) return in;
  Image out(w, h, in.channels);
  for (int c = 0; c < in.channels; ++c)
    for (int y = 0; y < h; ++y) {
      const double fy = std::clamp((y + 0.5) * in.height / h - 0.5, 0.0, in.height - 1.0);
      const int y0 = static_cast<int>(fy), y1 = std::min(y0 + 1, in.height - 1);
      for (int x = 0; x < w; ++x) {
        const double fx = std::clamp((x + 0.5) * in.width / w - 0.5, 0.0, in.width - 1.0);
        const int x0 = static_cast<int>(fx), x1 = std::min(x0 + 1, in.width - 1);
        const double ax = fx - x0, ay = fy - y0;
        out.at(c, x, y) = static_cast<float>((1 - ay) * ((1 - ax) * in.at(c, x0, y0) + ax * in.at(c, x1, y0)) +
                                             ay * ((1 - ax) * in.at(c, x0, y1) + ax * in.at(c, x1, y1)));
      }
    }
  return out;
}

void check(bool ok, const std::string& what) {
  if (!ok) throw std::runtime_error(what);
}

// One layer as nona writes it: cropped RGBA, 8-bit, position in resolution units, canvas size.
void write_layer(const std::string& path, const std::vector<unsigned char>& rgba, int w, int h, int x, int y,
                 int canvas_w, int canvas_h) {
  TIFF* t = TIFFOpen(path.c_str(), "w");
  check(t != nullptr, "cannot create " + path);
  const float resolution = 150.0f;
  const std::uint16_t extra[1] = {EXTRASAMPLE_UNASSALPHA};
  TIFFSetField(t, TIFFTAG_IMAGEWIDTH, w);
  TIFFSetField(t, TIFFTAG_IMAGELENGTH, h);
  TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, 4);
  TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, 8);
  TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_RGB);
  TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(t, TIFFTAG_EXTRASAMPLES, 1, extra);
  TIFFSetField(t, TIFFTAG_COMPRESSION, COMPRESSION_LZW);
  TIFFSetField(t, TIFFTAG_PREDICTOR, PREDICTOR_HORIZONTAL);
  TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, 32);
  TIFFSetField(t, TIFFTAG_RESOLUTIONUNIT, RESUNIT_INCH);
  TIFFSetField(t, TIFFTAG_XRESOLUTION, resolution);
  TIFFSetField(t, TIFFTAG_YRESOLUTION, resolution);
  TIFFSetField(t, TIFFTAG_XPOSITION, x / resolution);
  TIFFSetField(t, TIFFTAG_YPOSITION, y / resolution);
  if (canvas_w > 0) {  // 0: no canvas tags (tiles: a subset of the list is a canvas of its own)
    TIFFSetField(t, TIFFTAG_PIXAR_IMAGEFULLWIDTH, canvas_w);
    TIFFSetField(t, TIFFTAG_PIXAR_IMAGEFULLLENGTH, canvas_h);
  }
  for (int r = 0; r < h; ++r)
    check(TIFFWriteScanline(t, const_cast<unsigned char*>(rgba.data()) + static_cast<std::size_t>(r) * w * 4, r) >= 0,
          "cannot write " + path);
  TIFFClose(t);
}

void cut(const std::string& photo, const std::string& dir, const Cut& o) {
  Image img = gdp::read_image(photo).image;
  check(img.channels >= 3, "the photo must be RGB");
  img = resize(img, o.width > 0 ? o.width : img.width, o.height > 0 ? o.height : img.height);
  const int W = img.width, H = img.height;
  gdp::WriteOptions original;
  original.sample_type = gdp::SampleType::UInt8;
  gdp::write_image(dir + "/original.tif", img, original);
  // Layer size so that cols layers with the overlap span the canvas.
  const double lw = W / (1.0 + (o.cols - 1) * (1.0 - o.overlap)), lh = H / (1.0 + (o.rows - 1) * (1.0 - o.overlap));
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  int n = 0;
  for (int r = 0; r < o.rows; ++r)
    for (int c = 0; c < o.cols; ++c, ++n) {
      const int x0 = static_cast<int>(std::lround(c * lw * (1.0 - o.overlap)));
      const int y0 = static_cast<int>(std::lround(r * lh * (1.0 - o.overlap)));
      const int w = std::min(W, static_cast<int>(std::lround(x0 + lw))) - x0;
      const int h = std::min(H, static_cast<int>(std::lround(y0 + lh))) - y0;
      const double shift = o.offset * uniform(rng), phase = 6.283 * uniform(rng);
      const double margin = 0.15 * o.overlap * std::min(lw, lh);  // wavy edges, as warped photos have
      std::vector<unsigned char> rgba(static_cast<std::size_t>(w) * h * 4);
      const std::vector<Ghost> ghosts = ghosts_of(o, w, h, rng);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const double wx = margin * (1.0 + std::sin(0.02 * y + phase)), wy = margin * (1.0 + std::sin(0.02 * x - phase));
          const bool inside = std::min(x, w - 1 - x) >= wx && std::min(y, h - 1 - y) >= wy;
          unsigned char* p = rgba.data() + (static_cast<std::size_t>(y) * w + x) * 4;
          for (int ch = 0; ch < 3; ++ch) {
            double value = Exposure{shift, o.vignette}.at(img.at(ch, x0 + x, y0 + y), x, y, w, h);
            for (const Ghost& g : ghosts)
              if ((x - g.x) * (x - g.x) + (y - g.y) * (y - g.y) < g.r * g.r) value = g.colour[ch];
            p[ch] = inside ? static_cast<unsigned char>(std::clamp(value, 0.0, 1.0) * 255.0 + 0.5) : 0;
          }
          p[3] = inside ? 255 : 0;
        }
      write_layer(fmt::format("{}/layer_{:02d}.tif", dir, n), rgba, w, h, x0, y0, W, H);
    }
}

// Mirrored repetition of the photo enlarged n times (bilinear): the unbounded scene tiles cuts. A tap
// is one canvas coordinate's two photo pixels and the weight of the second, found once per row or column.
struct Tap {
  int i0, i1;
  float a;
};

std::vector<Tap> taps(long long from, int count, int pixels, int n) {
  const auto fold = [pixels](long long v) {
    const long long m = std::max(v, 0LL) % (2LL * pixels);
    return static_cast<int>(m < pixels ? m : 2LL * pixels - 1 - m);
  };
  std::vector<Tap> t(count);
  for (int k = 0; k < count; ++k) {
    const double f = (from + k + 0.5) / n - 0.5;
    const long long i = static_cast<long long>(std::floor(f));
    t[k] = {fold(i), fold(i + 1), static_cast<float>(f - i)};
  }
  return t;
}

// The photo tiles repeats, its values mapped to [headroom, 1 - headroom].
Image scene_photo(const std::string& photo, double headroom) {
  Image img = gdp::read_image(photo).image;
  check(img.channels >= 3, "the photo must be RGB");
  for (float& v : img.data) v = static_cast<float>(headroom + (1.0 - 2.0 * headroom) * v);
  return img;
}

float scene(const Image& img, int c, const Tap& x, const Tap& y) {
  const float top = (1 - x.a) * img.at(c, x.i0, y.i0) + x.a * img.at(c, x.i1, y.i0);
  const float bottom = (1 - x.a) * img.at(c, x.i0, y.i1) + x.a * img.at(c, x.i1, y.i1);
  return (1 - y.a) * top + y.a * bottom;
}

void tiles(const std::string& photo, const std::string& dir, const Cut& o) {
  const Image img = scene_photo(photo, o.headroom);
  const int t = o.tile;
  const double step = t * (1.0 - o.overlap);
  const int W = static_cast<int>(std::lround((o.cols - 1) * step)) + t, H = static_cast<int>(std::lround((o.rows - 1) * step)) + t;
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::FILE* list = o.part == 0 ? std::fopen((dir + "/tiles.txt").c_str(), "w") : nullptr;
  check(o.part != 0 || list != nullptr, "cannot create " + dir + "/tiles.txt");
  std::vector<unsigned char> rgba(static_cast<std::size_t>(t) * t * 4);
  for (int r = 0, n = 0; r < o.rows; ++r)
    for (int c = 0; c < o.cols; ++c, ++n) {
      const int x0 = static_cast<int>(std::lround(c * step)), y0 = static_cast<int>(std::lround(r * step));
      const Exposure e{o.offset * uniform(rng), o.vignette};
      const std::string name = fmt::format("{}/tile_{:05d}.tif", dir, n);
      if (list != nullptr) std::fprintf(list, "%s %d %d\n", name.c_str(), x0, y0);
      if (n % o.parts != o.part) continue;
      const std::vector<Tap> tx = taps(x0, t, img.width, o.upscale), ty = taps(y0, t, img.height, o.upscale);
      for (int y = 0; y < t; ++y)
        for (int x = 0; x < t; ++x) {
          unsigned char* p = rgba.data() + (static_cast<std::size_t>(y) * t + x) * 4;
          for (int ch = 0; ch < 3; ++ch)
            p[ch] = static_cast<unsigned char>(
                std::clamp(e.at(scene(img, ch, tx[x], ty[y]), x, y, t, t), 0.0, 1.0) * 255.0 + 0.5);
          p[3] = 255;
        }
      write_layer(name, rgba, t, t, x0, y0, 0, 0);
    }
  if (list != nullptr) std::fclose(list);
  std::printf("%d tiles of %dx%d, canvas %dx%d\n", o.cols * o.rows, t, t, W, H);
}

void error(const std::string& blended, const std::string& original) {
  gdp::ImageFileReader a(blended), b(original);
  check(a.width() == b.width() && a.height() == b.height(), "sizes differ");
  const int w = a.width(), ch = std::min(3, b.channels());
  const bool alpha = a.channels() == 4 || a.channels() == 2;
  std::vector<float> ra(static_cast<std::size_t>(a.channels()) * w), rb(static_cast<std::size_t>(b.channels()) * w);
  std::vector<double> sum(ch, 0.0), sum2(ch, 0.0);
  double n = 0.0;
  for (int y = 0; y < a.height(); ++y) {
    a.read_row(y, ra);
    b.read_row(y, rb);
    for (int x = 0; x < w; ++x) {
      if (alpha && ra[static_cast<std::size_t>(a.channels() - 1) * w + x] < 0.5f) continue;
      n += 1.0;
      for (int c = 0; c < ch; ++c) {
        const double d = double(ra[static_cast<std::size_t>(c) * w + x]) - rb[static_cast<std::size_t>(c) * w + x];
        sum[c] += d;
        sum2[c] += d * d;
      }
    }
  }
  double total = 0.0;
  for (int c = 0; c < ch; ++c) total += sum2[c] / n - (sum[c] / n) * (sum[c] / n);
  std::printf("rms_error %.6f (x255: %.3f) over %.0f pixels\n", std::sqrt(total / ch), 255.0 * std::sqrt(total / ch), n);
}

// A blend against a converged solve of the same blend: what the solve's own error does to the output.
void compare(const std::string& blended, const std::string& reference) {
  gdp::ImageFileReader a(blended), b(reference);
  check(a.width() == b.width() && a.height() == b.height(), "sizes differ");
  const int w = a.width(), ch = std::min(3, std::min(a.channels(), b.channels()));
  const bool alpha = a.channels() == 4 || a.channels() == 2;
  std::vector<float> ra(static_cast<std::size_t>(a.channels()) * w), rb(static_cast<std::size_t>(b.channels()) * w);
  double n = 0.0, sum = 0.0, sum2 = 0.0, largest = 0.0, changed = 0.0;
  for (int y = 0; y < a.height(); ++y) {
    a.read_row(y, ra);
    b.read_row(y, rb);
    for (int x = 0; x < w; ++x) {
      if (alpha && ra[static_cast<std::size_t>(a.channels() - 1) * w + x] < 0.5f) continue;
      n += ch;
      for (int c = 0; c < ch; ++c) {
        const double va = 255.0 * ra[static_cast<std::size_t>(c) * w + x];
        const double vb = std::clamp(255.0 * rb[static_cast<std::size_t>(c) * w + x], 0.0, 255.0), d = va - vb;
        sum += d;
        sum2 += d * d;
        largest = std::max(largest, std::abs(d));
        if (std::lround(va) != std::lround(vb)) changed += 1.0;
      }
    }
  }
  std::printf("rms %.4f max %.4f mean %+.4f (8-bit levels) changed %.6f over %.0f samples\n", std::sqrt(sum2 / n),
              largest, sum / n, changed / n, n);
}

// RMS error of a blend against the scene tiles cut (mean removed), streamed; and the largest step
// between the mean errors of neighbouring 256x256 blocks (per channel): a level step left between
// layers shows there, a smooth drift of the level does not.
void tiles_error(const std::string& blended, const std::string& photo, const Cut& o) {
  const Image img = scene_photo(photo, o.headroom);
  const int upscale = o.upscale;
  gdp::ImageFileReader a(blended);
  const int w = a.width(), ch = 3, block = 256, bw = (w + block - 1) / block;
  const bool alpha = a.channels() == 4;
  std::vector<float> row(static_cast<std::size_t>(a.channels()) * w);
  std::vector<double> sum(ch, 0.0), sum2(ch, 0.0), bsum(static_cast<std::size_t>(bw) * ch), bn(bw);
  std::vector<double> above(bsum.size(), NAN), mean(bsum.size());
  const std::vector<Tap> tx = taps(0, w, img.width, upscale);
  double n = 0.0, step = 0.0;
  const auto close_blocks = [&] {
    for (std::size_t i = 0; i < mean.size(); ++i) mean[i] = bn[i / ch] > 0 ? bsum[i] / bn[i / ch] : NAN;
    for (std::size_t i = 0; i < mean.size(); ++i) {
      const double left = i >= static_cast<std::size_t>(ch) ? mean[i - ch] : NAN;
      for (const double other : {left, above[i]})  // NaN (no neighbour, or an empty block) never counts
        if (std::abs(mean[i] - other) > step) step = std::abs(mean[i] - other);
    }
    above = mean;
    std::fill(bsum.begin(), bsum.end(), 0.0);
    std::fill(bn.begin(), bn.end(), 0.0);
  };
  for (int y = 0; y < a.height(); ++y) {
    a.read_row(y, row);
    const Tap ty = taps(y, 1, img.height, upscale)[0];
    for (int x = 0; x < w; ++x) {
      if (alpha && row[static_cast<std::size_t>(3) * w + x] < 0.5f) continue;
      n += 1.0;
      bn[x / block] += 1.0;
      for (int c = 0; c < ch; ++c) {
        const double d = double(row[static_cast<std::size_t>(c) * w + x]) - scene(img, c, tx[x], ty);
        sum[c] += d;
        sum2[c] += d * d;
        bsum[static_cast<std::size_t>(x / block) * ch + c] += d;
      }
    }
    if ((y + 1) % block == 0 || y + 1 == a.height()) close_blocks();
  }
  double total = 0.0;
  for (int c = 0; c < ch; ++c) total += sum2[c] / n - (sum[c] / n) * (sum[c] / n);
  std::printf("rms_error %.6f (x255: %.3f) over %.0f pixels; largest step between neighbouring %dx%d blocks' mean "
              "errors %.3f x255\n",
              std::sqrt(total / ch), 255.0 * std::sqrt(total / ch), n, block, block, 255.0 * step);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::vector<std::string> a(argv + 1, argv + argc);
    if (a.size() == 3 && a[0] == "error") {
      error(a[1], a[2]);
      return 0;
    }
    if (a.size() == 3 && a[0] == "compare") {
      compare(a[1], a[2]);
      return 0;
    }
    if (a.size() < 3 || (a[0] != "cut" && a[0] != "tiles" && a[0] != "tiles-error")) {
      std::fprintf(stderr, "usage: blend_layers cut|tiles PHOTO OUTDIR [options] | blend_layers tiles-error BLENDED PHOTO [--upscale N] [--headroom H] | blend_layers error BLENDED ORIGINAL | blend_layers compare BLENDED REFERENCE\n");
      return 2;
    }
    Cut o;
    for (std::size_t i = 3; i + 1 < a.size(); i += 2) {
      const std::string& k = a[i];
      const std::string& v = a[i + 1];
      if (k == "--size") std::sscanf(v.c_str(), "%dx%d", &o.width, &o.height);
      else if (k == "--grid") std::sscanf(v.c_str(), "%dx%d", &o.cols, &o.rows);
      else if (k == "--overlap") o.overlap = std::stod(v);
      else if (k == "--offset") o.offset = std::stod(v) / 255.0;
      else if (k == "--vignette") o.vignette = std::stod(v);
      else if (k == "--tile") o.tile = std::stoi(v);
      else if (k == "--seed") o.seed = static_cast<unsigned>(std::stoul(v));
      else if (k == "--ghosts") o.ghosts = std::stoi(v);
      else if (k == "--upscale") o.upscale = std::max(1, std::stoi(v));
      else if (k == "--headroom") o.headroom = std::stod(v);
      else if (k == "--part")
        check(std::sscanf(v.c_str(), "%d/%d", &o.part, &o.parts) == 2 && o.part >= 0 && o.part < o.parts,
              "--part wants K/N with 0 <= K < N");
      else throw std::runtime_error("unknown option " + k);
    }
    if (a[0] == "tiles-error") {
      tiles_error(a[1], a[2], o);
    } else if (a[0] == "tiles") {
      if (o.tile < 1) o.tile = 512;
      tiles(a[1], a[2], o);
    } else {
      cut(a[1], a[2], o);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "blend_layers: %s\n", e.what());
    return 1;
  }
  return 0;
}
