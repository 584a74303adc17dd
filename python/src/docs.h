// Docstrings of the gdp Python module (docs/python.md has the long form).
#pragma once

namespace gdp::python::docs {

#define GDP_SOLVER_KEYWORDS                                                                                        \
  "\n\nSolver keywords (the gdp CLI's flags): iters=3 (Gauss-Seidel sweeps per level), vcycles=1, tolerance=0 "   \
  "(> 0: V-cycles until the relative residual is below it), threads (default: all cores), coarsest=64, "          \
  "domain='planar'|'cylindrical'|'spherical', sphere=False (a 2:1 equirectangular input is resampled to PQ, "      \
  "solved there and resampled back; a 4:1 PQ input is solved in place), pq_height=0, double=False, "              \
  "in_core=False, incore_bytes=8 MiB, bands=0, temp=None (scratch directory), scratch='float' ('narrow': the CLI's default), half_scratch=False, "  \
  "memory=bytes (scratch kept in memory by the process while it fits; default a quarter of physical memory, "  \
  "with stores of 64 MiB or more in O_DIRECT files; 0: files), "                                                   \
  "verbose=False (residuals per level and V-cycle on sys.stderr), residuals=False (measure the relative "          \
  "residual before and after every V-cycle: stats' relative_residuals, else None; verbose, log and tolerance "      \
  "measure them too), log=callable(line), "                                                                        \
  "progress=callable(fraction) (called with increasing fractions up to 1.0; raising in it stops the solve), "      \
  "stats=dict (filled with sizes, residuals and times).\n\nThe GIL is released while gdp solves; Ctrl-C stops it. " \
  "Errors raise gdp.InputError, gdp.UsageError or gdp.OutputError with the CLI's messages."

#define GDP_ARRAYS                                                                                                 \
  "\n\nImages are numpy arrays of shape (height, width) or (height, width, channels): uint8 and uint16 values "   \
  "are read as k/255 and k/65535 (as gdp reads 8/16-bit files), floats as they are. Returns a float32 array of " \
  "the main input's shape."

#define GDP_FILES                                                                                                  \
  "\n\nFiles are streamed row by row (any size, little memory), as the gdp CLI does; a name with {rank} reads "   \
  "vertical strips. Write keywords: depth='8'|'16'|'half'|'float' (default: the input's), quality=95 (JPEG), "    \
  "tiled=False, compression=''. The output appears only when complete. Returns the solve's summary as a dict."

inline constexpr const char* kStitch =
    "stitch(composite, labels, **keywords) -> array\n\nSeamless stitching (gdp stitch): the composite's gradients, "
    "cut where the label map's colour changes (labels compared exactly; pure white = unknown). Keywords: "
    "unknown='harmonic'|'black'|'label', deramp=False, space='values'|'log'|'lab', zero_start=False, "
    "weights=array (per-pixel value weight), pin=array (pixels above 0.5 keep their values)." GDP_ARRAYS
        GDP_SOLVER_KEYWORDS;
inline constexpr const char* kStitchFile =
    "stitch_file(composite, labels, output, **keywords) -> dict\n\ngdp stitch on files: the keywords of "
    "gdp.stitch (weights and pin are file names)." GDP_FILES GDP_SOLVER_KEYWORDS;

#define GDP_SHARPEN_KEYWORDS                                                                                       \
  "Keywords: beta (gradient scale; any value >= 0, 1 returns the image), alpha (value weight) or "              \
  "scale=16 (alpha = 1/scale^2: detail finer than about scale pixels changes), scale_at (scale is in pixels of " \
  "an image whose long side is this many pixels), scale_deg (degrees of arc, spherical images), low=image "    \
  "(values from it, gradients from the image), weights=image, pin=image."

inline constexpr const char* kSharpen =
    "sharpen(image, **keywords) -> array\n\nGradient-domain sharpening (gdp sharpen): fit gradients beta * grad(I) "
    "and values I with weight alpha; beta=2 by default. " GDP_SHARPEN_KEYWORDS GDP_ARRAYS GDP_SOLVER_KEYWORDS;
inline constexpr const char* kSharpenFile =
    "sharpen_file(image, output, **keywords) -> dict\n\ngdp sharpen on files; keywords as gdp.sharpen (images as "
    "file names)." GDP_FILES GDP_SOLVER_KEYWORDS;
inline constexpr const char* kSmooth =
    "smooth(image, **keywords) -> array\n\nGradient-domain smoothing (gdp smooth): gdp.sharpen with beta=0.5 by "
    "default. " GDP_SHARPEN_KEYWORDS GDP_ARRAYS GDP_SOLVER_KEYWORDS;
inline constexpr const char* kSmoothFile =
    "smooth_file(image, output, **keywords) -> dict\n\ngdp smooth on files; keywords as gdp.smooth (images as "
    "file names)." GDP_FILES GDP_SOLVER_KEYWORDS;

inline constexpr const char* kClone =
    "clone(target, source, mask, **keywords) -> array\n\nSeamless cloning (gdp clone): the source's pixel (x, y) "
    "lands on the target's (x + dx, y + dy); inside the mask (source's size, first channel > 0.5) the result takes "
    "the source's gradients, outside it keeps the target. Keywords: offset=(dx, dy), mixed=False (keep the "
    "target's gradient where it is stronger). Iterates to tolerance=1e-5 unless vcycles or tolerance is given. "
    "Returns the target's size." GDP_ARRAYS GDP_SOLVER_KEYWORDS;
inline constexpr const char* kCloneFile =
    "clone_file(target, source, mask, output, **keywords) -> dict\n\ngdp clone on files; keywords as gdp.clone."
    GDP_FILES GDP_SOLVER_KEYWORDS;

inline constexpr const char* kTonemap =
    "tonemap(image, **keywords) -> array\n\nGradient-domain dynamic-range compression (gdp tonemap; Fattal et al. "
    "2002) of linear RGB to display values in [0, 1]. Keywords: alpha=0.1, beta=0.9, scales=0, resolution=2048, "
    "saturation=0.6, gamma=1.8, low=1.0, high=99.5 (percentiles mapped to 0 and 1); vcycles=2 by default."
    GDP_ARRAYS GDP_SOLVER_KEYWORDS;
inline constexpr const char* kTonemapFile =
    "tonemap_file(image, output, **keywords) -> dict\n\ngdp tonemap on files; keywords as gdp.tonemap (default "
    "depth: the output format's own, 8-bit PNG, float EXR)." GDP_FILES GDP_SOLVER_KEYWORDS;

inline constexpr const char* kReconstruct =
    "reconstruct(image, **keywords) -> (array, rms_error, max_error)\n\nRebuilds the image from its own gradients "
    "from a zero start, keeping its mean (gdp reconstruct: a self-test of the solver on real data); the errors "
    "are against the input, per value. sphere=True needs a PQ image." GDP_ARRAYS GDP_SOLVER_KEYWORDS;
inline constexpr const char* kReconstructFile =
    "reconstruct_file(image, output=None, **keywords) -> dict\n\ngdp reconstruct on files (read whole): the "
    "summary holds rms_error and max_error; the result is written to output when given." GDP_SOLVER_KEYWORDS;

#define GDP_RESAMPLE_KEYWORDS                                                                                      \
  " Keywords: map='toast'|'octahedral' (the PQ image's sphere-to-square map), nearest=False (copy values, never " \
  "blend: label maps), sky=False (equirectangular longitude increases to the left), threads=0 (all cores)."

inline constexpr const char* kToPq =
    "to_pq(image, **keywords) -> array\n\nResamples an equirectangular (2:1) or cube-strip (1:6) image to the "
    "periodic-quincuncial layout (4H x H) that gdp solves spherical images on (gdp sphere to-pq). height=0: about "
    "the input's pixel count." GDP_RESAMPLE_KEYWORDS GDP_ARRAYS;
inline constexpr const char* kToPqFile =
    "to_pq_file(input, output, **keywords) -> dict\n\ngdp sphere to-pq on files; keywords as gdp.to_pq plus "
    "depth, quality, tiled, compression. Returns the output's width, height and channels.";
inline constexpr const char* kFromPq =
    "from_pq(image, **keywords) -> array\n\nResamples a PQ image (4H x H) to equirectangular (format='equirect', "
    "width W gives W x W/2) or a cube strip (format='cube', width = face size) (gdp sphere from-pq). width=0: "
    "about the input's pixel count." GDP_RESAMPLE_KEYWORDS GDP_ARRAYS;
inline constexpr const char* kFromPqFile =
    "from_pq_file(input, output, **keywords) -> dict\n\ngdp sphere from-pq on files; keywords as gdp.from_pq plus "
    "depth, quality, tiled, compression. Returns the output's width, height and channels.";

inline constexpr const char* kReadImage =
    "read_image(path) -> array\n\nReads a whole image file as gdp does (PNG/TIFF/JPEG by gdp's codecs, others "
    "through OpenImageIO): a float32 array (height, width, channels), 8/16-bit samples as k/255, k/65535.";
inline constexpr const char* kWriteImage =
    "write_image(path, image, **keywords)\n\nWrites an array as gdp writes its outputs (atomically: the file "
    "appears only when complete). Keywords: depth='8'|'16'|'half'|'float' (default: 8/16 bits for uint8/uint16 "
    "arrays, else the format's own), quality=95, tiled=False, compression=''. Integer outputs are clamped to [0, 1].";

#undef GDP_SOLVER_KEYWORDS
#undef GDP_ARRAYS
#undef GDP_FILES
#undef GDP_SHARPEN_KEYWORDS
#undef GDP_RESAMPLE_KEYWORDS

}  // namespace gdp::python::docs
