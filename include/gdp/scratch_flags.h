// The scratch precision an application (the CLI, the Python module) asks for from its flags.
#pragma once

#include <string>

#include "gdp/solver.h"

namespace gdp {

// `scratch` is --scratch ("float", "narrow" or empty), `half_scratch` --half-scratch (the same as
// narrow), `double_precision` --double. Applications writing images default to narrow; double
// precision to float (docs/how-streaming-works.md). UsageError naming the flags that conflict.
ScratchPrecision app_scratch_precision(const std::string& scratch, bool half_scratch, bool double_precision);

}  // namespace gdp
