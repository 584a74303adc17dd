// The OpenImageIO module's decoder and encoder factories.
#pragma once

#include <memory>
#include <string>

#include "io/codec.h"

namespace gdp::io {

std::unique_ptr<Decoder> open_oiio_decoder(const std::string& path);
std::unique_ptr<Encoder> create_oiio_encoder(const std::string& path);

}  // namespace gdp::io
