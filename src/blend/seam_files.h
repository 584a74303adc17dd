// Seams kept in files: the label plane saved as gdp's grey label map or multiblend's palette PNG, and loaded back (--save-seams, --load-seams).
#pragma once

#include <filesystem>
#include <string>

#include "blend/seams.h"
#include "gdp/blend.h"

namespace gdp::blending {

// A path ending in .png: multiblend's format, an 8-bit palette PNG whose value is the layer index
// (0 = the first; 255 = none; at most 255 layers: seam_png.h). Other paths: gdp's own label map.
// Writes the labels as a one-channel image of the canvas's size: each pixel the number of the
// layer it takes (1 = the first), 0 where none covers it; 8-bit samples for up to 255 layers,
// else 16-bit (a TIFF, ...: any lossless format gdp writes).
void save_seams(const LabelPlane& labels, int layers, const std::string& path);

// Reads a palette PNG as multiblend's format, any other image as gdp's label map:
// reads such an image (8- or 16-bit: the sample values; float: the values themselves) as the
// label plane. A pixel labelled with a layer that does not cover it takes the first layer that
// does (0 where none); pixels labelled 0 that a layer covers take the first such layer too.
// InputError naming the file for another size or a label past the layer count.
SeamResult load_seams(const BlendPlan& plan, const std::string& path, const std::filesystem::path& temp_dir);

}  // namespace gdp::blending
