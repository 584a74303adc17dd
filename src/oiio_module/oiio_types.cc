// Mapping between gdp's sample types and OpenImageIO's TypeDesc.
#include "oiio_module/oiio_types.h"

namespace gdp::io {

SampleType sample_type_of(OIIO::TypeDesc type) {
  switch (type.basetype) {
    case OIIO::TypeDesc::UINT8: return SampleType::UInt8;
    case OIIO::TypeDesc::UINT16: return SampleType::UInt16;
    case OIIO::TypeDesc::HALF: return SampleType::Half;
    case OIIO::TypeDesc::FLOAT: return SampleType::Float;
    case OIIO::TypeDesc::DOUBLE: return SampleType::Double;
    default: return type.is_floating_point() ? SampleType::Float : SampleType::UInt16;
  }
}

OIIO::TypeDesc type_desc_of(SampleType type) {
  switch (type) {
    case SampleType::UInt8: return OIIO::TypeDesc::UINT8;
    case SampleType::UInt16: return OIIO::TypeDesc::UINT16;
    case SampleType::Half: return OIIO::TypeDesc::HALF;
    case SampleType::Float: return OIIO::TypeDesc::FLOAT;
    case SampleType::Double: return OIIO::TypeDesc::DOUBLE;
  }
  return OIIO::TypeDesc::FLOAT;
}

OIIO::TypeDesc native_integer_type(const OIIO::ImageSpec& spec) {
  const bool integer = spec.format == OIIO::TypeDesc::UINT8 || spec.format == OIIO::TypeDesc::UINT16;
  return integer && spec.channelformats.empty() ? spec.format : OIIO::TypeDesc::UNKNOWN;
}

SampleType band_type_of(const OIIO::ImageSpec& spec) {
  const OIIO::TypeDesc native = native_integer_type(spec);
  return native == OIIO::TypeDesc::UNKNOWN ? SampleType::Float : sample_type_of(native);
}

}  // namespace gdp::io
