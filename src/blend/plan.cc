// Planning a blend from the layers' headers: pages, placement, canvas, channels and sample type.
#include <algorithm>
#include <cmath>
#include <optional>
#include <memory>

#include <fmt/format.h>

#include "blend/layer_rows.h"
#include "gdp/blend.h"
#include "gdp/errors.h"
#include "gdp/image_stream.h"
#include "io/tiff_pages.h"

namespace gdp {
namespace {

int colour_of(int channels) { return channels == 2 || channels == 4 ? channels - 1 : channels; }

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
void finish(BlendPlan& plan, const BlendOptions& options, const std::vector<int>& channels, int full_w, int full_h) {
  if (plan.layers.empty()) throw UsageError("no layers to blend");
  plan.colour_channels = colour_of(channels[0]);
  for (std::size_t k = 1; k < plan.layers.size(); ++k)
    if (colour_of(channels[k]) != plan.colour_channels)
      throw InputError(fmt::format("{}: {} colour channel(s), but {} has {}; layers must agree (grey and RGB are "
                                   "not mixed)",
                                   plan.layers[k].name, colour_of(channels[k]), plan.layers[0].name,
                                   plan.colour_channels));
  if (options.canvas) {
    plan.canvas = *options.canvas;
    if (plan.canvas.width < 1 || plan.canvas.height < 1)
      throw UsageError(fmt::format("canvas {}x{} is empty", plan.canvas.width, plan.canvas.height));
  } else {
    long long x0 = 0, y0 = 0, x1 = full_w, y1 = full_h;
    bool first = full_w == 0 || full_h == 0;
    for (const PlacedLayer& l : plan.layers) {
      x0 = first ? l.x : std::min(x0, l.x);
      y0 = first ? l.y : std::min(y0, l.y);
      x1 = first ? l.x + l.width : std::max(x1, l.x + l.width);
      y1 = first ? l.y + l.height : std::max(y1, l.y + l.height);
      first = false;
    }
    if (x1 - x0 > (1LL << 31) - 1 || y1 - y0 > (1LL << 31) - 1)
      throw InputError(fmt::format("the layers span {}x{} pixels, more than a canvas can hold", x1 - x0, y1 - y0));
    plan.canvas = {x0, y0, static_cast<int>(x1 - x0), static_cast<int>(y1 - y0)};
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
  int full_w = 0, full_h = 0;
  for (const LayerSource& s : sources) {
    std::vector<io::TiffPage> pages;
    try {
      pages = io::tiff_pages(s.image);
    } catch (const std::exception& e) {
      throw InputError(fmt::format("{}: {}", s.image, e.what()));
    }
    const int count = std::max<int>(1, static_cast<int>(pages.size()));
    for (int p = 0; p < count; ++p) {
      const ImageFileReader reader(s.image, false, ColumnRange{}, p);
      PlacedLayer l;
      l.name = count > 1 ? fmt::format("{} (page {})", s.image, p + 1) : s.image;
      l.width = reader.width();
      l.height = reader.height();
      if (s.placed) {
        l.x = s.x;
        l.y = s.y;
      } else if (p < static_cast<int>(pages.size()) && pages[p].positioned) {
        l.x = pages[p].x;
        l.y = pages[p].y;
      }
      if (p < static_cast<int>(pages.size())) {
        full_w = std::max(full_w, pages[p].full_width);
        full_h = std::max(full_h, pages[p].full_height);
      }
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
      geo.push_back(p < static_cast<int>(pages.size()) ? pages[p].geo : std::nullopt);
      plan.layers.push_back(l);
      plan.sources.push_back(s);
      plan.pages.push_back(p);
    }
  }
  place_geo(plan, geo);
  finish(plan, options, channels, full_w, full_h);
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
  finish(plan, options, channels, 0, 0);
  return plan;
}

}  // namespace gdp
