// The size check every image decoder applies to a file's header before it allocates anything.
#pragma once

#include <functional>
#include <string>

namespace gdp {

// Throws (an exception derived from std::exception whose what() is one line; the reader puts the
// file's name in front) when an image of this size must not be opened.
using SizeCheck = std::function<void(long long width, long long height, int channels)>;

// The process-wide check, installed before images are opened (the gdp tool installs one from
// --max-pixels or the free disk and memory); none by default.
void set_size_check(SizeCheck check);

// What decoders call with a header's size: first gdp's own bounds (sides of 1 to 2^31 - 1 pixels,
// rows of at most 2^30 samples, so that no row, stride or level size overflows an int), then
// the installed check. std::length_error on a size outside gdp's bounds.
void check_image_size(long long width, long long height, int channels);

// An image size derived from options (`what`, e.g. "--pq-height 100000": its PQ grid), checked
// like a file's header; UsageError "what: problem". Sides are given as long long so that a
// product computed from an option cannot have overflowed already.
void check_derived_size(const std::string& what, long long width, long long height, int channels);

}  // namespace gdp
