// The OpenImageIO module's one exported symbol: its Backend, used by io/oiio_module_loader.cc.
#include "io/oiio_backend.h"
#include "oiio_module/oiio_module.h"

namespace gdp::io {
namespace {

class OiioBackend final : public Backend {
 public:
  std::unique_ptr<Decoder> open_decoder(const std::string& path) override { return open_oiio_decoder(path); }
  std::unique_ptr<Encoder> create_encoder(const std::string& path) override { return create_oiio_encoder(path); }
};

}  // namespace
}  // namespace gdp::io

extern "C" __attribute__((visibility("default"))) gdp::io::Backend* gdp_oiio_backend_v1() {
  static gdp::io::OiioBackend backend;
  return &backend;
}
