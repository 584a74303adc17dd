// The part of the PQ sphere that a set of plates covers: a rectangle solved as a planar image when it meets no fold.
#pragma once

#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "sky/plate.h"

namespace gdp::sky {

// Columns [i0, i0 + width) and rows [j0, j0 + rows) of a PQ image of height `height` (4H x H).
struct PqWindow {
  int height = 0;
  int i0 = 0, j0 = 0, width = 0, rows = 0;
  bool whole() const { return i0 == 0 && j0 == 0 && width == 4 * height && rows == height; }
};

inline PqWindow whole_pq(int height) { return {height, 0, 0, 4 * height, height}; }

// The TOAST recursion depth that resolves a PQ image of height `height` to a fraction of a pixel.
inline int toast_depth(int height) { return static_cast<int>(std::ceil(std::log2(2.0 * height))) + 3; }

// The rectangle holding every plate with its extension (`extension` times its size beyond its
// edges) and a margin of 4 pixels, found from points along the extended borders. nullopt when it
// would meet the PQ's top or bottom edge (where the sphere folds), wrap across its left and
// right edges, or cover more than a quarter of the PQ image (no gain then): the whole sphere is
// solved instead.
std::optional<PqWindow> plate_window(const std::vector<Plate>& plates, int height, double extension);

// The rows of `window` (first, last) that the plate with its extension may reach: from a 65 x 65
// grid of points over the extended plate, widened by one and a half grid cells (TOAST pixels vary
// 1.45x in size) and 4 rows, clipped to the window; every row when a point has no sky position.
std::array<int, 2> plate_rows(const Plate& plate, const PqWindow& window, double extension);
// The same for the window's columns (first, last); every column on the whole sphere (its rows wrap).
std::array<int, 2> plate_columns(const Plate& plate, const PqWindow& window, double extension);

// Which of `ranks` equal shares of the window's columns holds each plate's centre: the rank that
// runs that plate's part of the passes before the solve under mpirun (plate_passes.h).
std::vector<int> plate_owners(const std::vector<Plate>& plates, const PqWindow& window, int ranks);

}  // namespace gdp::sky
