// FITS header cards as text: Montage-style templates read, keyword values looked up, target headers made.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

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

// One 80-character card "KEY     = value" (value formatted by the caller).
std::string card(const std::string& key, const std::string& value);

}  // namespace gdp::sky
