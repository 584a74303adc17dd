// Seamless mosaics from N aligned layers (gdp blend; docs/blend.md): seams by depth, then stitching.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gdp/apps.h"
#include "gdp/image.h"
#include "gdp/image_io.h"
#include "gdp/rows.h"
#include "gdp/solver.h"

namespace gdp {

// One input file: every page of a multi-page TIFF is a layer of its own. Coverage: the alpha
// channel (2 or 4 channels: the last) and the mask's first channel, each at least 0.5, and
// finite colour. Placement: `x, y` when `placed`, else the TIFF's XPOSITION/YPOSITION, else 0, 0.
// A smooth background taken off a layer's colour as it is read (gdp sky --projected): at the
// layer's own pixel centre (x + 1/2, y + 1/2), u = (x + 1/2 - cx) / scale, v = (y + 1/2 - cy) / scale,
// constant + slope_u u + slope_v v + radial (u^2 + v^2).
struct LayerBackground {
  double cx = 0.0, cy = 0.0, scale = 1.0;
  double constant = 0.0, slope_u = 0.0, slope_v = 0.0, radial = 0.0;
  bool active() const { return constant != 0.0 || slope_u != 0.0 || slope_v != 0.0 || radial != 0.0; }
};

struct LayerSource {
  std::string image;
  std::string mask = "";  // optional: a separate coverage image of the image's size
  bool placed = false;
  long long x = 0, y = 0;
  float offset = 0.0f;      // added to the colour as it is read (gdp sky --projected: each image's level)
  float mask_scale = 1.0f;  // the mask's samples times this are tested (area images: 1 / the largest area)
  LayerBackground background{};  // subtracted from the colour as it is read (after `offset` is added)
};

// An in-memory layer (tests, library users): colour channels plus optional alpha as above.
struct ImageLayer {
  const Image* image = nullptr;
  const Image* mask = nullptr;
  long long x = 0, y = 0;
};

// A rectangle of the layers' coordinate plane.
struct CanvasRect {
  long long x = 0, y = 0;
  int width = 0, height = 0;
};

// Topology of the canvas: none, horizontal (a 360-degree panorama: left and right edges meet,
// the cylindrical domain), both (a full equirectangular sphere, 2:1, solved on the sphere).
enum class Wrap { None, Horizontal, Both };

// Guidance across a seam between two layers: zero (the paper, DMG), or the mean of both layers'
// gradients where both cover the seam's pixels (docs/blend.md measures both).
enum class SeamGuidance { Zero, Mean };

// Where seams run: each pixel takes the layer it lies deepest inside (depth), or those seams
// moved through the overlaps to where the layers agree best (graphcut; docs/blend.md).
enum class SeamMethod { Depth, Graphcut };

// Photometric calibration (docs/blend.md, "Photometric calibration"): layer k's values v are read as
// (v - offset[c]) / (gain * V(t)), V(t) = 1 + a1 t + a2 t^2 + ..., t = (r / radius)^2, r the
// distance from the layer's vignetting centre (cx, cy), in the layer's own pixels (0, 0 = its
// first pixel's centre).
struct LayerPhotometry {
  double gain = 1.0;
  double offset[3] = {0.0, 0.0, 0.0};
  double cx = 0.0, cy = 0.0, radius = 1.0;
};
struct Photometry {
  std::vector<double> vignetting;       // a1, a2, ...: one falloff for all layers (one camera)
  std::vector<LayerPhotometry> layers;  // empty: the layers are read as they are
};

// Where a layer's optical centre lies, in its own pixels, and the radius r is measured in
// (radius <= 0: half the layer's diagonal). Default: the layer's own centre (layers cut from one
// photo; nona's cropped layers: the centre of the remapped photo's bounding box).
struct VignettingCentre {
  double x = 0.0, y = 0.0, radius = 0.0;
};

// Fit the calibration on the layers' overlaps before blending (robust least squares on sampled
// pixel pairs; one decimated pass over the layers).
struct PhotometricOptions {
  bool enabled = false;
  int vignetting_terms = 3;               // 0 to 3: a1 r^2 + a2 r^4 + a3 r^6
  std::vector<VignettingCentre> centres;  // empty, or one per layer
  int grid_points = 1 << 18;              // the canvas is sampled on a grid of about this many points
};

struct BlendOptions {
  std::optional<CanvasRect> canvas;  // enblend's -f; else the union of the layers and their canvas tags
  Wrap wrap = Wrap::None;
  SeamGuidance seam_guidance = SeamGuidance::Mean;
  SeamMethod seams = SeamMethod::Depth;
  BlendSpace space;
  // >= 0: the pixels that take this layer (0 = the first) keep its values exactly (pinned) and
  // the others level to it; the V-cycles then converge more slowly (use a tolerance).
  int anchor = -1;
  // Fidelity as gdp stitch's --pin and --weights (docs/weights.md), by layer: the pixels that take
  // a layer of `pinned` (0 = the first) keep its values, as `anchor`'s; `weights` (empty, or one
  // per layer, finite and >= 0) pulls the pixels that take each layer towards its values with that
  // weight (layers differing by constants level to their weighted mean). `fidelity`'s images, of
  // the canvas's size, add per-pixel weights and pins to these (weights summed).
  std::vector<int> pinned;
  std::vector<double> weights;
  Fidelity fidelity;
  // Optional: also receives the additive correction, output minus the composite of the layers
  // (colour channels, 0 where no layer covers a pixel; committed with the output). The layers
  // are read once more for it.
  RowWriter* correction = nullptr;
  // Seams in files (blending/seam_files.h): the label plane written as a grey image of layer
  // numbers (1 = the first, 0 = none), or read from one instead of computed.
  std::string save_seams, load_seams;
  bool alpha = true;  // write the alpha channel (false: colour only, e.g. for JPEG; uncovered pixels 0)
  int pq_height = 0;  // Wrap::Both: PQ height (0: sphere::default_pq_height)
  PhotometricOptions photometric;
  // Progress of the seam pass, 0 to 1 (the solve reports through SolverOptions::progress).
  std::function<void(double)> progress;
};

// A layer placed on the canvas.
struct PlacedLayer {
  std::string name;  // the file, with its page for multi-page TIFFs
  long long x = 0, y = 0;
  int width = 0, height = 0;
};

// What the layers make: read from every layer's header, no pixels.
struct BlendPlan {
  CanvasRect canvas;
  int colour_channels = 0;       // the layers' (1 to 3); the output adds alpha
  SampleType sample_type = SampleType::UInt8;  // the widest of the layers'
  std::vector<PlacedLayer> layers;
  std::vector<std::string> notes;  // mixed sample types
  std::optional<GeoReference> geo;  // GeoTIFF layers: the canvas's georeference (write it with the output)
  // The frame the layers' files name: TIFF canvas tags (PIXAR_IMAGEFULLWIDTH/LENGTH, at 0, 0) or
  // OpenEXR display windows (their union); none when no file names one.
  std::optional<CanvasRect> frame;
  Photometry photometry;  // applied to every layer as it is read (blend() fills it with options.photometric)
  // Internal: how each layer is opened.
  std::vector<LayerSource> sources;
  std::vector<ImageLayer> images;
  std::vector<int> pages;
};

// Throws InputError naming the file: unreadable, different colour channel counts, a mask of
// another size, a layer wholly outside the canvas; UsageError for no layers.
BlendPlan plan_blend(const std::vector<LayerSource>& sources, const BlendOptions& options);
BlendPlan plan_blend(const std::vector<ImageLayer>& layers, const BlendOptions& options);

// The blend's Gauss-Seidel sweeps when the user names none (the CLI's --iters): 2/3 for the plain
// one-V-cycle blend whose every output is 8-bit (`output` UInt8, no correction field), where the
// solve's remaining error stays well under half a level and the rounding to 1/255 hides it
// (docs/blend.md, "The solver's sweeps" measures it); else the solver's 3/3, which meets the
// stitching accuracy target (docs/reproduce.md) and gains more per CPU second over several
// V-cycles (--vcycles, --tolerance; docs/multigrid.md). Pins, weights and an anchor (not measured) keep 3/3.
void set_default_blend_sweeps(SampleType output, const BlendOptions& options, SolverOptions& solver);

// Where the canvas lies in the layers' frame (the canvas itself when they name none), for an
// OpenEXR output's data and display windows; nullopt where OpenEXR's 32-bit coordinates cannot hold it.
std::optional<FramePlacement> frame_placement(const BlendPlan& plan);

struct BlendReport {
  std::vector<std::string> isolated;  // layers that overlap no other: placed as they are
  double seconds_seams = 0.0, seconds_solve = 0.0;
  std::size_t scratch_bytes = 0;  // distance and label planes
  // The layers the seams read and the columns they were found for: all, unless this process
  // solves only some columns (mpirun), when only the layers meeting them are read.
  int seam_layers_read = 0;
  std::pair<int, int> seam_columns{0, 0};
  double seam_cost_depth = 0, seam_cost = 0;  // SeamMethod::Graphcut: the depth seams' cost and the result's
  SolveSummary solve;
  // options.photometric: the fitted calibration, the overlap samples it used and their robust RMS
  // disagreement (values, 0..1) before and after it.
  Photometry photometry;
  int photometric_points = 0;
  double photometric_rms_before = 0.0, photometric_rms_after = 0.0, seconds_photometry = 0.0;
};

// Output rows: the canvas, colour channels plus alpha (0 where no layer covers the pixel; the
// colour there is 0), committed at the end. The solver's domain follows options.wrap.
void blend(const BlendPlan& plan, const BlendOptions& options, const SolverOptions& solver, RowWriter& out,
           BlendReport* report = nullptr);
Image blend(const std::vector<ImageLayer>& layers, const BlendOptions& options, const SolverOptions& solver,
            BlendReport* report = nullptr);

}  // namespace gdp
