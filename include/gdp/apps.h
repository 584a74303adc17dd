// Gradient-domain applications: each builds guidance for the one solver.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "gdp/image.h"
#include "gdp/rows.h"
#include "gdp/solver.h"

namespace gdp {

// What to do with pixels whose label is the reserved "unknown" colour (all channels 1.0, white).
enum class UnknownMode {
  Black,     // fill smoothly for the solve, then output black there
  Harmonic,  // no gradients into or inside them: a smooth (harmonic) fill
  Label,     // white is an ordinary label
  Extend,    // the composite's own differences into and inside them, as if part of every neighbouring
             // label: the correction field runs on smoothly through them, and labels on either side of
             // a gap keep their relative levels (gdp blend: pixels no layer covers)
};

// "black" | "harmonic" | "label"; anything else throws UsageError.
UnknownMode parse_unknown_mode(std::string_view name);

// Per-pixel fidelity (docs/weights.md): images of the input's size read row by row beside it
// (first channel used). The values held are the application's own: the composite, the image
// (or the low image), the target.
struct Fidelity {
  RowReader* weights = nullptr;  // per-pixel weight of the value term, added to alpha (finite, >= 0)
  RowReader* pins = nullptr;     // pixels above 0.5 keep their values (within 1e-4 of the range)
  std::string weights_name = "weight image", pins_name = "pin mask";  // for error messages
  bool any() const { return weights || pins; }
};

// The space the solve blends in (gdp stitch --space): the stored values, their logarithm
// (exposure differences become offsets: seams of multiplicative gain vanish exactly), or CIE
// L*a*b* (perceptual: lightness and colour seams weighted as seen). The result is converted back.
struct BlendSpace {
  enum class Kind { Values, Log, Lab } kind = Kind::Values;
  double log_offset = 1e-3;   // Log: log(max(v, 0) + offset), so zeros stay finite
  bool srgb_encoded = false;  // Lab: values are sRGB-encoded (8/16-bit files) rather than linear
};

// "values" | "log" | "lab"; anything else throws UsageError.
BlendSpace::Kind parse_blend_space(std::string_view name);

struct StitchOptions {
  UnknownMode unknown = UnknownMode::Harmonic;
  bool deramp = false;            // subtract each label's mean gradient (removes linear ramps)
  bool start_from_composite = true;  // initial guess: the composite (else zero)
  BlendSpace space;
  // Optional: at each pixel next to a label change, the value there of the source across it: the
  // composite's size and twice its channels, the first ones for the source its left and right
  // neighbours carry, the next for the one its upper and lower neighbours carry (so that where
  // three sources meet each edge finds its own); non-finite where unknown or where both
  // neighbours of a pair carry different other sources. Gradients across a label change are then
  // the mean of the composite's and this image's differences (of the edge's direction) where both
  // ends have finite values (the mean of both sources' gradients), the one source's gradient that
  // is known where only one end has (that source covers both pixels), zero where neither has
  // (gdp blend).
  RowReader* across = nullptr;
  std::string labels_name = "the label map";  // in messages
  std::string composite_name;                 // in messages (a file's name; empty: none)
};

// InputError naming both inputs when the label map's size is not the composite's (what stitch
// checks first; the CLI checks it before opening its output).
void check_stitch_inputs(const RowReader& composite, const RowReader& labels, const StitchOptions& options);

// Every application comes in two forms: rows in and rows out (RowReader / RowWriter: files
// streamed through in a few rows of memory, whatever the image size; commit() is left to the
// caller), and in-memory images. Non-finite input samples (FITS blanks) carry no guidance and
// come out as NaN again.

// Seamless stitching: gradients of the composite, zero across label changes; the output's mean
// over known pixels is the composite's (up to what the last sweeps move it, ~1e-5). Labels are
// compared exactly, any channel count. The composite is read twice with `deramp`. A label map
// that is all white (unknown) gives no pixel a source: an InputError naming `labels_name` after
// the solve (nothing is committed), unless white is a label (UnknownMode::Label). (Under mpirun a
// rank sees only its columns: there the check is left out.)
void stitch(RowReader& composite, RowReader& labels, const StitchOptions& options, const SolverOptions& solver,
            RowWriter& out, SolveSummary* summary = nullptr, const Fidelity& fidelity = {});
Image stitch(const Image& composite, const Image& labels, const StitchOptions& options,
             const SolverOptions& solver, SolveSummary* summary = nullptr);

// Gradient-domain sharpening (beta > 1) or smoothing (beta < 1): fit gradients beta * grad(I)
// and values I with weight alpha. alpha = 1 / s^2 changes detail finer than about s pixels.
// UsageError unless 0 < alpha <= 1e6 and 0 <= beta <= 1e6 (beyond, floats overflow).
void sharpen(RowReader& image, double alpha, double beta, const SolverOptions& solver, RowWriter& out,
             SolveSummary* summary = nullptr, const Fidelity& fidelity = {});
Image sharpen(const Image& image, double alpha, double beta, const SolverOptions& solver,
              SolveSummary* summary = nullptr);
// alpha from a scale in pixels or degrees (gdp sharpen/smooth --scale, --scale-at, --scale-deg).
struct SharpenScale {
  double pixels = 16.0;             // detail finer than about this many pixels is scaled
  std::optional<int> at;            // `pixels` is in pixels of an image whose long side is this many pixels
  std::optional<double> degrees;    // instead: the scale in degrees of arc (spherical domains only)
  // Throws UsageError naming the first invalid value (by the CLI's flag).
  void validate(Domain domain) const;
  // alpha = 1 / s^2 for an input of in_width x in_height solved on a solved_width x solved_height
  // grid (the PQ resampling of an equirectangular input, else the input's own): s in pixels of
  // the solved grid. Validates first.
  double alpha(Domain domain, int in_width, int in_height, int solved_width, int solved_height) const;
};

// High/low compositing (sharpen/smooth --low): gradients beta * grad(high), values (and the
// starting guess) from `low` with weight alpha, e.g. the detail of one exposure on the tones of
// another. Same size and channels (InputError otherwise).
void sharpen(RowReader& high, RowReader& low, double alpha, double beta, const SolverOptions& solver, RowWriter& out,
             SolveSummary* summary = nullptr, const Fidelity& fidelity = {});

// Seamless cloning (Perez, Gangnet and Blake 2003; gdp clone): the source's pixel (x, y) lands
// on the target's (x + offset_x, y + offset_y); inside the mask (first channel > 0.5, source's
// size) the result takes the source's gradients, outside it keeps the target's values exactly
// (pinned). With `mixed`, an edge keeps the target's gradient where it is stronger than the
// source's (transparent objects, text on texture). Output: the target's size and channels (the
// source's first channels; it needs at least as many). The problem has pinned pixels, so each
// V-cycle converges more slowly than plain stitching: gdp clone defaults to a tolerance.
inline constexpr double kCloneTolerance = 1e-5;  // gdp clone's tolerance unless V-cycles or one are given
struct CloneOptions {
  int offset_x = 0, offset_y = 0;
  bool mixed = false;
  // The input files' names, in messages (empty: not a file; the message names the role alone).
  std::string target_name, source_name, mask_name;
};
// InputError naming the files when the mask's size is not the source's or the source has fewer
// channels than the target (what clone checks first; the CLI checks it before opening its output).
void check_clone_inputs(const RowReader& target, const RowReader& source, const RowReader& mask,
                        const CloneOptions& options);
void clone(RowReader& target, RowReader& source, RowReader& mask, const CloneOptions& options,
           const SolverOptions& solver, RowWriter& out, SolveSummary* summary = nullptr);
Image clone(const Image& target, const Image& source, const Image& mask, const CloneOptions& options,
            const SolverOptions& solver, SolveSummary* summary = nullptr);

// Rebuilds an image from its own gradients from a zero start, keeping its mean (a self-test
// on real data).
void reconstruct(RowReader& image, const SolverOptions& solver, RowWriter& out, SolveSummary* summary = nullptr);

struct ReconstructResult {
  Image image;
  double rms_error = 0.0;  // against the input, per value
  double max_error = 0.0;
};
ReconstructResult reconstruct(const Image& image, const SolverOptions& solver, SolveSummary* summary = nullptr);

// ---- Dynamic-range compression (gdp tonemap; docs/tonemap.md) ----

// Gradient-domain tone mapping (Fattal, Lischinski and Werman 2002): the gradients of the log
// luminance are scaled by a multi-scale attenuation that shrinks large ones and keeps small
// ones, the Poisson equation (alpha = 0) gives the output log luminance, colour is restored
// with `saturation`, and the result is mapped to display values in [0, 1].
struct TonemapOptions {
  double alpha = 0.1;        // gradients above alpha * (mean gradient magnitude of a level) shrink
  double beta = 0.9;         // the attenuation exponent: 1 leaves gradients alone, smaller compresses more
  int scales = 0;            // pyramid levels (1: full resolution only); 0: down to ~32 pixels on the short side
  // Attenuate only at levels whose long side is at most this many pixels (finer levels pass
  // their gradients on, scaled by the coarser levels' attenuation), so that an image and its
  // preview at this size or larger get the same compression. 0: every level, as in the paper.
  int resolution = 2048;
  double saturation = 0.6;   // C_out = (C_in / L_in)^saturation * L_out
  double gamma = 1.8;        // display value = linear^(1 / gamma)
  double low_percentile = 1.0;    // output luminance at this percentile maps to 0 (0: black stays 0)
  double high_percentile = 99.5;  // ... and at this one to 1; brighter pixels clip
  // Throws UsageError naming the first invalid option.
  void validate() const;
};

// Reads `in` three times (rewind()): pyramid, guidance, colour. The first three channels are
// linear RGB (one or two channels: the first is the luminance); further channels pass through.
// Non-finite or negative samples count as zero. Output rows have the input's channel count.
void tonemap(RowReader& in, const TonemapOptions& options, const SolverOptions& solver, RowWriter& out,
             SolveSummary* summary = nullptr);
Image tonemap(const Image& image, const TonemapOptions& options, const SolverOptions& solver,
              SolveSummary* summary = nullptr);

}  // namespace gdp
