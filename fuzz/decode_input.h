// What every fuzz target does: one input decoded through gdp's public reading API, with a small pixel limit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string_view>

namespace gdp::fuzz {

// Decodes `data` as a file (every row, then a column window; for TIFF also its pages and their
// GeoTIFF tags) when it starts with one of `signatures`. gdp's typed errors are the expected outcome of
// bad input; anything else escapes to libFuzzer as a finding. Returns -1 (not worth keeping in
// the corpus) for inputs without one, else 0.
int decode_input(const std::uint8_t* data, std::size_t size, std::initializer_list<std::string_view> signatures,
                 bool pages = false);

}  // namespace gdp::fuzz
