// Planning a blend from the layers' headers: pages, placement, canvas, channels and sample type.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <memory>

#include <fmt/format.h>

#include "blend/layer_rows.h"
#include "gdp/blend.h"
#include "gdp/errors.h"
#include "gdp/image_stream.h"
#include "io/exr_windows.h"
#include "io/tiff_pages.h"

namespace gdp {
namespace {

// A layer's placement as its file says: TIFF XPOSITION/YPOSITION and canvas tags, or OpenEXR's
// data window (its offset) and display window (the frame).
struct Page {
  bool positioned = false;
  long long x = 0, y = 0;
  std::optional<CanvasRect> frame;
  std::optional<GeoReference> geo;
};

// Every page of a file (one for files that are not multi-page TIFFs).
std::vector<Page> pages_of(const std::string& path) {
  std::vector<Page> pages;
  try {
    for (const io::TiffPage& t : io::tiff_pages(path)) {
      Page p{t.positioned, t.x, t.y, std::nullopt, t.geo};
      if (t.full_width > 0 && t.full_height > 0) p.frame = CanvasRect{0, 0, t.full_width, t.full_height};
      pages.push_back(p);
    }
    if (const auto w = io::exr_windows(path))
      pages.push_back({true, w->data_x, w->data_y, CanvasRect{w->display_x, w->display_y, w->display_width, w->display_height},
                       std::nullopt});
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: {}", path, e.what()));
  }
  if (pages.empty()) pages.emplace_back();
  return pages;
}

// The smallest rectangle holding both.
CanvasRect unite(const std::optional<CanvasRect>& a, const CanvasRect& b) {
  if (!a) return b;
  const long long x0 = std::min(a->x, b.x), y0 = std::min(a->y, b.y);
  const long long x1 = std::max(a->x + a->width, b.x + b.width), y1 = std::max(a->y + a->height, b.y + b.height);
  if (x1 - x0 > (1LL << 31) - 1 || y1 - y0 > (1LL << 31) - 1)
    throw InputError(fmt::format("the layers span {}x{} pixels, more than a canvas can hold", x1 - x0, y1 - y0));
  return {x0, y0, static_cast<int>(x1 - x0), static_cast<int>(y1 - y0)};
}

int rank(SampleType t) {
  switch (t) {
    case SampleType::UInt8: return 0;
    case SampleType::UInt16: return 1;
    case SampleType::Half: return 2;
    default: return 3;
  }
}

// Checks channels and fixes the canvas: a layer wholly outside it is an error, one partly outside
// it (-f cropping, as Hugin asks) is used where it lies inside.
void finish(BlendPlan& plan, const BlendOptions& options, const std::vector<int>& channels) {
  if (plan.layers.empty()) throw UsageError("no layers to blend");
  // Grey layers among RGB ones are promoted: their grey in all three channels.
  plan.colour_channels = 1;
  for (const int c : channels) plan.colour_channels = std::max(plan.colour_channels, blending::colour_channels_of(c));
  std::vector<std::string> grey;
  for (std::size_t k = 0; k < plan.layers.size(); ++k)
    if (blending::colour_channels_of(channels[k]) < plan.colour_channels) grey.push_back(plan.layers[k].name);
  if (!grey.empty())
    plan.notes.push_back(fmt::format("{} grey layer(s) among RGB ones, their grey taken for red, green and blue: {}{}",
                                     grey.size(), grey[0], grey.size() > 1 ? ", ..." : ""));
  if (options.canvas) {
    plan.canvas = *options.canvas;
    if (plan.canvas.width < 1 || plan.canvas.height < 1)
      throw UsageError(fmt::format("canvas {}x{} is empty", plan.canvas.width, plan.canvas.height));
  } else {
    std::optional<CanvasRect> all = plan.frame;
    for (const PlacedLayer& l : plan.layers) all = unite(all, {l.x, l.y, l.width, l.height});
    plan.canvas = *all;
  }
  const CanvasRect& c = plan.canvas;
  for (std::size_t k = 0; k < plan.layers.size(); ++k) {
    const PlacedLayer& l = plan.layers[k];
    const blending::Footprint f = blending::footprint(plan, static_cast<int>(k));
    if (f.width() <= 0 || f.y1 <= f.y0)
      throw InputError(fmt::format("{}: {}x{} at ({}, {}) lies wholly outside the canvas {}x{}+{}+{}", l.name, l.width,
                                   l.height, l.x, l.y, c.width, c.height, c.x, c.y));
  }
}

// GeoTIFF layers: placed by their model coordinates on a grid of their common pixel size, the
// canvas's top-left corner at the westernmost and northernmost layer's.
void place_geo(BlendPlan& plan, const std::vector<std::optional<GeoReference>>& geo) {
  const auto first = std::find_if(geo.begin(), geo.end(), [](const auto& g) { return g.has_value(); });
  if (first == geo.end()) return;
  const GeoReference& ref = **first;
  const std::string& ref_name = plan.layers[first - geo.begin()].name;
  double west = ref.origin_x, north = ref.origin_y;
  for (std::size_t k = 0; k < geo.size(); ++k) {
    if (plan.sources[k].placed) continue;
    if (!geo[k]) throw InputError(fmt::format("{}: not georeferenced, but {} is", plan.layers[k].name, ref_name));
    const GeoReference& g = *geo[k];
    if (std::abs(g.scale_x / ref.scale_x - 1) > 1e-9 || std::abs(g.scale_y / ref.scale_y - 1) > 1e-9)
      throw InputError(fmt::format("{}: pixel size {} x {}, but {} has {} x {}; resample to one pixel size first",
                                   plan.layers[k].name, g.scale_x, g.scale_y, ref_name, ref.scale_x, ref.scale_y));
    if (g.keys != ref.keys)
      throw InputError(fmt::format("{}: another coordinate reference system (GeoKeyDirectory) than {}",
                                   plan.layers[k].name, ref_name));
    west = std::min(west, g.origin_x);
    north = std::max(north, g.origin_y);
  }
  for (std::size_t k = 0; k < geo.size(); ++k) {
    if (plan.sources[k].placed) continue;
    plan.layers[k].x = std::llround((geo[k]->origin_x - west) / ref.scale_x);
    plan.layers[k].y = std::llround((north - geo[k]->origin_y) / ref.scale_y);
  }
  plan.geo = ref;  // pixel (0, 0) at (west, north); moved to the canvas's corner once it is known
  plan.geo->origin_x = west;
  plan.geo->origin_y = north;
}

}  // namespace

BlendPlan plan_blend(const std::vector<LayerSource>& sources, const BlendOptions& options) {
  BlendPlan plan;
  std::vector<int> channels;
  std::vector<std::optional<GeoReference>> geo;
  for (const LayerSource& s : sources) {
    const std::vector<Page> pages = pages_of(s.image);
    const int count = static_cast<int>(pages.size());
    for (int p = 0; p < count; ++p) {
      const ImageFileReader reader(s.image, false, ColumnRange{}, p);
      PlacedLayer l;
      l.name = count > 1 ? fmt::format("{} (page {})", s.image, p + 1) : s.image;
      l.width = reader.width();
      l.height = reader.height();
      if (s.placed) {
        l.x = s.x;
        l.y = s.y;
      } else if (pages[p].positioned) {
        l.x = pages[p].x;
        l.y = pages[p].y;
      }
      if (pages[p].frame) plan.frame = unite(plan.frame, *pages[p].frame);
      if (!s.mask.empty()) {
        const ImageFileReader mask(s.mask, false);
        if (mask.width() != l.width || mask.height() != l.height)
          throw InputError(fmt::format("{}: mask is {}x{} but its image {} is {}x{}", s.mask, mask.width(),
                                       mask.height(), l.name, l.width, l.height));
      }
      if (reader.channels() > 4) throw InputError(fmt::format("{}: {} channels; layers have 1 to 4", l.name, reader.channels()));
      if (plan.layers.empty() || rank(reader.info().sample_type) > rank(plan.sample_type)) {
        if (!plan.layers.empty())
          plan.notes.push_back(fmt::format("{}: a wider sample type than the layers before it; the output takes it", l.name));
        plan.sample_type = reader.info().sample_type;
      }
      channels.push_back(reader.channels());
      geo.push_back(pages[p].geo);
      plan.layers.push_back(l);
      plan.sources.push_back(s);
      plan.pages.push_back(p);
    }
  }
  place_geo(plan, geo);
  finish(plan, options, channels);
  if (plan.geo) {
    plan.geo->origin_x += static_cast<double>(plan.canvas.x) * plan.geo->scale_x;
    plan.geo->origin_y -= static_cast<double>(plan.canvas.y) * plan.geo->scale_y;
  }
  return plan;
}

BlendPlan plan_blend(const std::vector<ImageLayer>& layers, const BlendOptions& options) {
  BlendPlan plan;
  plan.sample_type = SampleType::Float;
  std::vector<int> channels;
  for (std::size_t k = 0; k < layers.size(); ++k) {
    const ImageLayer& in = layers[k];
    PlacedLayer l{fmt::format("layer {}", k + 1), in.x, in.y, in.image->width, in.image->height};
    if (in.mask && (in.mask->width != l.width || in.mask->height != l.height))
      throw InputError(fmt::format("{}: mask is {}x{} but the image is {}x{}", l.name, in.mask->width,
                                   in.mask->height, l.width, l.height));
    channels.push_back(in.image->channels);
    plan.layers.push_back(l);
    plan.images.push_back(in);
  }
  finish(plan, options, channels);
  return plan;
}

void set_default_blend_sweeps(SampleType output, const BlendOptions& options, SolverOptions& solver) {
  const SolverOptions standard;
  const bool pinned = options.anchor >= 0 || !options.pinned.empty() || !options.weights.empty() || options.fidelity.any();
  const bool one_cycle = solver.tolerance <= 0.0 && solver.vcycles == 1;
  const bool cheaper = output == SampleType::UInt8 && options.correction == nullptr && !pinned && one_cycle;
  solver.sweeps = cheaper ? 2 : standard.sweeps;  // one pre-sweep less: post-sweeps lower the error more
  solver.post_sweeps = standard.post_sweeps;
}

std::optional<FramePlacement> frame_placement(const BlendPlan& plan) {
  const CanvasRect& c = plan.canvas;
  const CanvasRect f = plan.frame.value_or(c);
  const auto fits = [](const CanvasRect& r) {
    return r.x >= INT32_MIN && r.y >= INT32_MIN && r.x + r.width - 1 <= INT32_MAX && r.y + r.height - 1 <= INT32_MAX;
  };
  if (!fits(c) || !fits(f)) return std::nullopt;
  return FramePlacement{static_cast<int>(c.x), static_cast<int>(c.y), static_cast<int>(f.x), static_cast<int>(f.y), f.width, f.height};
}

}  // namespace gdp
