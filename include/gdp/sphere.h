// Spherical images: sphere <-> square maps (TOAST, equal-area octahedral), the periodic-quincuncial
// (PQ) layout, equirectangular and cube-map conventions, resampling between them, TOAST tiles.
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "gdp/image.h"
#include "gdp/image_io.h"
#include "gdp/rows.h"

namespace gdp::sphere {

// A direction in 3D. Frame: z = north pole, x = longitude 0 on the equator, y = longitude 90.
struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;
};

// A point in a plane: square coordinates (s, t) or continuous pixel coordinates (x, y).
struct Point2 {
  double x = 0.0, y = 0.0;
};

// ---- Sphere <-> square maps -------------------------------------------------------------------
// The square is (s, t) in [-1, 1]^2, s to the right, t up (an image of the square has
// s = 2u - 1, t = 1 - 2v for u, v in [0, 1], v down). North pole at the centre, south pole at the
// four corners, equator on the diamond |s| + |t| = 1; longitude 0 at the right-edge midpoint,
// 90 at the top, 180 left, 270 bottom. Inverses accept any non-zero vector (not only unit ones).
enum class SquareMap { Toast, Octahedral };

// "toast" | "octahedral"; anything else throws UsageError.
SquareMap parse_square_map(const std::string& name);

// Exact recursive TOAST map (limit of midpoint subdivision of the octahedron's octants).
Vec3 toast_to_sphere(double s, double t);
// Its inverse: descends `depth` subdivision levels on the sphere, then inverts the last triangle's
// normalised barycentric map. 30 levels reach double precision; fewer (the resampler uses the
// square's pixel level + 3) are faster and differ by less than (pi/2 / 2^depth)^2 radians.
Point2 toast_from_sphere(const Vec3& p, int depth = 30);

// Equal-area octahedral map: every region keeps its area (density pi per unit of square area).
Vec3 octahedral_to_sphere(double s, double t);
Point2 octahedral_from_sphere(const Vec3& p);

Vec3 square_to_sphere(SquareMap map, double s, double t);
Point2 square_from_sphere(SquareMap map, const Vec3& p);

// Directions of the pixel centres of row `row` (top-down) of an n x n image of the square
// (pixel (c, r) centred at s = (2c + 1)/n - 1, t = 1 - (2r + 1)/n), out.size() == n. For TOAST
// this subdivides rows of the octant lattices instead of recursing per pixel: exact when n is a
// power of two, otherwise within 2e-3 / n^2 radians of toast_to_sphere (a ten-thousandth of a pixel).
void square_row(SquareMap map, int n, int row, std::span<Vec3> out);

// ---- Periodic-quincuncial layout ----------------------------------------------------------------
// A PQ image is W x H with W = 4H. With a square image of side N = 2H: the left half is the bottom
// half of the square unchanged, PQ(i, j) = SQ(i, j + H); the right half is the top half rotated
// by 180 degrees, PQ(i, j) = SQ(W - 1 - i, H - 1 - j). Pixel (i, j) covers [i, i+1) x [j, j+1).

// The pixel that a PQ stencil reaching outside the image reads (NUMERICS.md section 4): periodic
// in i, reflected about the top edge and twice reflected about the bottom edge, as often as it
// takes (the solver's own index map, so resampling and solving agree on the folds).
std::array<int, 2> pq_wrap(int height, int i, int j);

// Square pixel (column, row) of an N = 2H square that PQ pixel (i, j) is.
std::array<int, 2> pq_to_square_pixel(int height, int i, int j);

Vec3 pq_pixel_direction(SquareMap map, int height, int i, int j);
// Continuous PQ coordinates of a direction (x in [0, W), y in [0, H)).
Point2 pq_from_direction(SquareMap map, int height, const Vec3& p, int toast_depth = 30);
// Directions of all pixel centres of PQ row j (out.size() == 4H); j in [-1, H] reads the
// wrapped rows just outside the image. Fast (rows of square_row).
void pq_row(SquareMap map, int height, int j, std::span<Vec3> out);

// The PQ height used when none is given: about as many pixels as the source (4H^2 = source
// pixels), rounded to H = m * 2^k with 8 <= m <= 16 (so k multigrid levels halve it evenly);
// small sources (H <= 16) to the nearest even H >= 2.
int default_pq_height(long long source_pixels);

// ---- Equirectangular (plate carree) ------------------------------------------------------------
// W x H (normally 2:1). Row 0 touches latitude +90, row H-1 latitude -90. Default (geographic /
// panorama convention): column 0 starts at longitude -180, longitude increases to the right, so
// longitude 0 is the centre. `sky` (astronomical convention, toasty's plate_carree_sampler):
// column 0 starts at +180 and longitude increases to the left.
Vec3 equirect_direction(int width, int height, double x, double y, bool sky = false);
Point2 equirect_from_direction(int width, int height, const Vec3& p, bool sky = false);

// ---- Cube maps ---------------------------------------------------------------------------------
// One image, a vertical strip of six F x F faces (F wide, 6F high) in the order +X, -X, +Y, -Y,
// +Z, -Z, each face oriented as in OpenEXR's ENVMAP_CUBE (ImfEnvmap.h), whose frame is y up and
// latitude-longitude centre +Z. Our frame maps to it as (X, Y, Z) = (-y, z, x), so converting an
// equirectangular image to a cube gives the same faces as OpenEXR's tools give for it.
Vec3 cube_direction(int face_size, double x, double y);  // (x, y): continuous strip coordinates
Point2 cube_from_direction(int face_size, const Vec3& p);

// ---- Resampling ----------------------------------------------------------------------------------
enum class Layout { Equirect, Pq, Cube };

struct Projection {
  Layout layout = Layout::Equirect;
  SquareMap map = SquareMap::Toast;  // Pq only
  bool sky = false;                  // Equirect only: longitude increases to the left
};

struct ResampleOptions {
  // Nearest neighbour (for label maps: values are copied, never blended). Otherwise Lanczos-3
  // interpolation when the output is as fine as the source or finer, and the average of n x n
  // interpolated samples spread over the output pixel when it is coarser (n per axis: the output
  // pixel's extent from the map's Jacobian over the source pixel, rounded, at most 8), so
  // shrinking does not alias and enlarging does not blur.
  bool nearest = false;
  // Row-major 3x3: an output direction d is looked up in the source at rotation * d (changes of
  // celestial frame, say). Identity by default.
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};
  int threads = 0;  // 0: all cores
};

// Size of an output image of a layout for a given size parameter: Equirect: width (height =
// width / 2); Pq: height (width = 4 * height); Cube: face size (F x 6F).
std::array<int, 2> layout_size(Layout layout, int size);
// The size parameter (as layout_size takes it) of a resampling to `layout` that keeps about the
// source's pixel count: Pq, default_pq_height; Equirect, an even width; Cube, the face size.
int default_size(Layout layout, long long source_pixels);
// gdp sphere to-pq / from-pq: the output's width and height for a `width` x `height` source of
// `channels` named `name` in errors; `size` as layout_size takes it (0: default_size). to-pq sets
// `other` to the source's layout (from its shape); from-pq resamples to `other`. InputError when
// the source is PQ already (to-pq), is not PQ (from-pq) or has no layout's shape; UsageError
// naming the flag (--height or --width) when the output's size fails check_image_size.
std::array<int, 2> plan_resampling(bool to_pq, Layout& other, int size, int width, int height, int channels,
                                   const std::string& name);
// The layout of a source image from its shape: 2:1 equirect, 1:4 PQ... throws InputError if none.
Layout guess_layout(int width, int height);

// Resamples a whole image. Throws UsageError on sizes that do not fit the layouts.
Image resample(const Image& source, const Projection& from, const Projection& to, int out_width, int out_height,
               const ResampleOptions& options = {});

// Row interface (what a streaming implementation replaces): today it reads the source into
// memory, then writes the output row by row; see docs/sphere.md for the streaming design. As
// with the applications, commit() is left to the caller.
void resample(RowReader& source, const Projection& from, RowWriter& out, const Projection& to, int out_width,
              int out_height, const ResampleOptions& options = {});

// ---- WorldWideTelescope TOAST tiles -------------------------------------------------------------
struct ToastPyramidOptions {
  int levels = -1;          // deepest level written (-1: the level of the PQ height, H = 128 * 2^n)
  std::string name = "gdp";  // data set name in the WTML file
  WriteOptions write;       // tile PNG options
};

// Writes `dir`/{level}/{y}/{y}_{x}.png (256 x 256 tiles) and `dir`/toast.wtml from a TOAST PQ image of
// height 128 * 2^n: level n tiles are copies or 180-degree rotations of PQ blocks, coarser levels
// 2x2 averages. The directory is built under a temporary name and renamed into place. Throws
// UsageError for other heights or a non-empty `dir`, OutputError when writing fails.
void write_toast_pyramid(const Image& pq, const std::filesystem::path& dir, const ToastPyramidOptions& options = {});

// Square row y (0 .. 2H-1) of a PQ image of height H is one half of PQ row square_row_source(H, y):
// for y >= H the left half of row y - H, else the right half of row H - 1 - y reversed.
int square_row_source(int height, int y);
// Square row y (2H values) from that PQ row (4H values), one channel.
void square_row_from_pq(int height, int y, std::span<const float> pq_row, std::span<float> out);

// Row y (0 .. 2H-1) of the 2H x 2H TOAST square, channel-major (channels x 2H floats): one half
// row of the PQ image (pq_to_square_pixel), read as the pyramid writer needs it.
using ToastSquareRows = std::function<void(int y, std::span<float> row)>;

// The same pyramid (the same files, bit for bit) from square rows read once, top to bottom: it
// holds a strip of 256 rows per level (256 x 2^(n - levels) rows at the finest), so memory grows
// with the PQ width, not its area.
void write_toast_pyramid(int height, int channels, const ToastSquareRows& rows, const std::filesystem::path& dir,
                         const ToastPyramidOptions& options = {});

// The N x N TOAST square image (N = 2H) that a PQ image lays out (no resampling).
Image pq_to_square(const Image& pq);

}  // namespace gdp::sphere
