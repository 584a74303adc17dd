// Saving the label plane (gdp's grey label map or multiblend's palette PNG) and loading edited seams back, checked against the layers' coverage.
#include "blend/seam_files.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <functional>
#include <cmath>
#include <memory>
#include <numeric>

#include <fmt/format.h>

#include "blend/layer_rows.h"
#include "blend/seam_png.h"
#include "gdp/errors.h"
#include "gdp/image_stream.h"

namespace gdp::blending {

namespace {

bool png_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e == ".png";
}

// InputError unless the seams (w x h) are the canvas's size (W x H).
void check_seam_size(const std::string& path, int w, int h, int W, int H) {
  if (w != W || h != H) throw InputError(fmt::format("{}: seams are {}x{} but the canvas is {}x{}", path, w, h, W, H));
}

// Label rows from gdp's grey label maps (1 = the first layer, 0 = none).
std::function<void(int, std::vector<Label>&)> grey_labels(const std::string& path, int n, int W, int H) {
  auto file = std::make_shared<ImageFileReader>(path);
  check_seam_size(path, file->width(), file->height(), W, H);
  const SampleType t = file->info().sample_type;
  const float scale = t == SampleType::UInt8 ? 255.0f : t == SampleType::UInt16 ? 65535.0f : 1.0f;
  auto values = std::make_shared<std::vector<float>>(static_cast<std::size_t>(file->channels()) * W);
  return [=](int y, std::vector<Label>& label) {
    file->read_row(y, *values);
    for (int x = 0; x < W; ++x) {
      const long v = std::lround((*values)[x] * scale);
      if (!(v >= 0 && v <= n))
        throw InputError(fmt::format("{}: label {} at ({}, {}); there are {} layers", path, (*values)[x] * scale, x, y, n));
      label[x] = static_cast<Label>(v);
    }
  };
}

// Label rows from multiblend's palette PNGs (index = layer, 0 = the first; kPaletteNone = none).
std::function<void(int, std::vector<Label>&)> palette_labels(const std::string& path, int n, int W, int H) {
  auto file = std::make_shared<PaletteRows>(path);
  check_seam_size(path, file->width(), file->height(), W, H);
  auto bytes = std::make_shared<std::vector<std::uint8_t>>(W);
  return [=](int y, std::vector<Label>& label) {
    file->read_row(*bytes);
    for (int x = 0; x < W; ++x) {
      const int v = (*bytes)[x];
      if (v != kPaletteNone && v >= n)
        throw InputError(fmt::format("{}: layer index {} at ({}, {}); there are {} layers", path, v, x, y, n));
      label[x] = static_cast<Label>(v == kPaletteNone ? 0 : v + 1);
    }
  };
}

}  // namespace

void save_seams(const LabelPlane& labels, int layers, const std::string& path) {
  if (png_extension(path)) return write_palette_seams(labels, layers, path);
  const int w = labels.width();
  WriteOptions options;
  options.sample_type = layers <= 255 ? SampleType::UInt8 : SampleType::UInt16;
  const float scale = layers <= 255 ? 1.0f / 255.0f : 1.0f / 65535.0f;
  ImageFileWriter out(path, w, labels.height(), 1, options);
  std::vector<Label> row(w);
  std::vector<float> values(w);
  for (int y = 0; y < labels.height(); ++y) {
    labels.read_row(y, row);
    for (int x = 0; x < w; ++x) values[x] = row[x] * scale;
    out.write_row(y, values);
  }
  out.commit();
}

SeamResult load_seams(const BlendPlan& plan, const std::string& path, const std::filesystem::path& temp_dir) {
  const int n = static_cast<int>(plan.layers.size()), W = plan.canvas.width, H = plan.canvas.height;
  const auto read_labels = is_palette_png(path) ? palette_labels(path, n, W, H) : grey_labels(path, n, W, H);
  SeamResult result;
  result.labels = std::make_unique<LabelPlane>(temp_dir, W, H);
  result.overlaps.assign(n, 1);
  result.scratch_bytes = result.labels->bytes();
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return footprint(plan, a).y0 < footprint(plan, b).y0; });
  std::vector<OpenLayer> open;
  std::vector<Label> label(W), first(W);
  std::vector<unsigned char> wanted_covers(W);
  std::size_t next = 0;
  for (int y = 0; y < H; ++y) {
    for (; next < order.size() && footprint(plan, order[next]).y0 == y; ++next) {
      open.emplace_back(plan, order[next], 0, W, open.size() < 8);
    }
    std::sort(open.begin(), open.end(), [](const OpenLayer& a, const OpenLayer& b) { return a.index < b.index; });
    read_labels(y, label);
    std::fill(first.begin(), first.end(), Label{0});
    std::fill(wanted_covers.begin(), wanted_covers.end(), 0);
    for (OpenLayer& o : open) {
      o.read(y);
      const int x0 = o.rows->where().x0;
      for (int x = 0; x < static_cast<int>(o.covered.size()); ++x) {
        if (!o.covered[x]) continue;
        if (!first[x0 + x]) first[x0 + x] = static_cast<Label>(o.index + 1);
        if (label[x0 + x] == o.index + 1) wanted_covers[x0 + x] = 1;
      }
    }
    for (int x = 0; x < W; ++x)
      if (!wanted_covers[x]) label[x] = first[x];
    result.labels->write_row(y, label);
    std::erase_if(open, [&](const OpenLayer& o) { return o.rows->where().y1 == y + 1; });
  }
  return result;
}

}  // namespace gdp::blending
