// Sample types between gdp and OpenImageIO, for the OpenImageIO module.
#pragma once

#include <OpenImageIO/imageio.h>

#include "gdp/image_io.h"

namespace gdp::io {

SampleType sample_type_of(OIIO::TypeDesc type);
OIIO::TypeDesc type_desc_of(SampleType type);

// UINT8 or UINT16 when every channel of `spec` is stored so, else UNKNOWN. gdp converts such
// samples to and from float itself (io/codec_util.h): OpenImageIO 2.4 converts a few scanlines
// per task on its thread pool, which made writing a 256-pixel-wide 8-bit image 7x slower than the
// encoding itself, and reading 8-bit files some 30% slower.
OIIO::TypeDesc native_integer_type(const OIIO::ImageSpec& spec);

// The band sample type (UInt8, UInt16 or Float) for a spec.
SampleType band_type_of(const OIIO::ImageSpec& spec);

}  // namespace gdp::io
