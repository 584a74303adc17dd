// Integer settings read from the environment (test and tuning knobs such as GDP_CHECKPOINT_ROWS).
#pragma once

#include <cstdlib>

namespace gdp::util {

// The value of environment variable `name` as an integer, or `fallback` where it is not set.
inline int env_int(const char* name, int fallback = 0) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : fallback;
}

}  // namespace gdp::util
