// The entry point of OpenImageIO's module (libgdp_oiio.so), which gdp loads with dlopen() when a file needs it.
#pragma once

#include <memory>
#include <string>

#include "io/codec.h"

namespace gdp::io {

// The formats gdp does not decode itself (Radiance HDR, FITS, WebP, BMP, ...), through
// OpenImageIO. Errors are std::exception's whose what() is the problem, as for every codec.
class Backend {
 public:
  virtual ~Backend() = default;
  virtual std::unique_ptr<Decoder> open_decoder(const std::string& path) = 0;
  // Throws when no OpenImageIO writer matches the extension.
  virtual std::unique_ptr<Encoder> create_encoder(const std::string& path) = 0;
};

// The module exports this one C function; the version in its name changes with Backend.
inline constexpr const char* kOiioEntryPoint = "gdp_oiio_backend_v1";
using OiioEntryPoint = Backend* (*)();

// File name of the module, and the variable that overrides where it is looked for.
inline constexpr const char* kOiioModuleName = "libgdp_oiio.so";
inline constexpr const char* kOiioModuleVariable = "GDP_OIIO_MODULE";

// The module's backend, loaded on first use (thread-safe). Looked for at $GDP_OIIO_MODULE, then
// where it is installed (lib/gdp/ beside libgdp.so), then where the build tree puts it. Throws
// CodecError ("needs OpenImageIO's module (libgdp_oiio.so): not found at ...") when none loads.
Backend& oiio_backend();


}  // namespace gdp::io
