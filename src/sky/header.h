// FITS header cards as text: Montage-style templates read, keyword values looked up, target headers made.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include "gdp/sky.h"

namespace gdp::sky {

// A header template as Montage's mMakeHdr writes it (and people by hand): one card per line,
// "KEY = value / comment", up to END. Returns 80-character cards (keywords padded to 8
// characters, "= " in columns 9-10). Throws InputError naming the file and line.
std::string read_header_template(const std::filesystem::path& path);
std::string cards_from_text(const std::string& text, const std::string& name);

// The value of `key` in 80-character cards as a number (nullopt when absent or not a number).
std::optional<double> header_number(const std::string& cards, const std::string& key);

// Cards for a target grid given by centre, size, scale and projection (SkyTarget without a
// template): CRPIX at the image's centre, CDELT1 = -scale (RA to the left), CDELT2 = scale.
std::string target_header(const SkyTarget& spec);

// The whole sky on the HEALPix pixels of `order` (N = 2^order pixels a base-pixel side), as an
// HPX image of 5N x 5N pixels (Calabretta & Roukema 2007, the layout of wcslib's HPXcvt): the 12
// base pixels as N x N squares along the diagonal, base pixel 4 at the centre, base pixel 6 halved
// at two corners, each image pixel one HEALPix pixel. `longitude`: the frame's longitude axis
// ("RA", "GLON", "ELON"). Throws UsageError for other frames or an order above 13.
std::string hpx_grid_header(int order, const std::string& longitude);

// CTYPE1 and CTYPE2 of an HPX image in the frame of longitude axis `longitude` ("RA" ->
// "RA---HPX", "DEC--HPX"; "GLON", "ELON" likewise). Throws UsageError for other frames.
std::pair<std::string, std::string> hpx_ctypes(const std::string& longitude);

// The HEALPix order of an HPX grid whose pixels are at most `scale` degrees (the coarsest).
int hpx_order_for_scale(double scale);

// One 80-character card "KEY     = value" (value formatted by the caller).
std::string card(const std::string& key, const std::string& value);

}  // namespace gdp::sky
