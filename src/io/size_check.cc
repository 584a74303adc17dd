// The process-wide image size check: gdp's own bounds, then the installed one.
#include "gdp/size_check.h"

#include <climits>
#include <mutex>
#include <stdexcept>

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp {
namespace {

std::mutex mutex;
SizeCheck installed;

}  // namespace

void set_size_check(SizeCheck check) {
  std::lock_guard lock(mutex);
  installed = std::move(check);
}

void check_image_size(long long width, long long height, int channels) {
  if (width <= 0 || height <= 0 || channels <= 0)
    throw std::length_error(fmt::format("image of {}x{} with {} channel(s) is empty", width, height, channels));
  if (width > INT_MAX || height > INT_MAX)
    throw std::length_error(fmt::format("image of {}x{} is beyond gdp's largest side, {} pixels", width, height,
                                        INT_MAX));
  constexpr long long kMaxRowSamples = 1LL << 30;
  if (width * channels > kMaxRowSamples)
    throw std::length_error(fmt::format("image of {}x{} with {} channel(s) has rows beyond gdp's largest, {} samples",
                                        width, height, channels, kMaxRowSamples));
  SizeCheck check;
  {
    std::lock_guard lock(mutex);
    check = installed;
  }
  if (check) check(width, height, channels);
}

void check_derived_size(const std::string& what, long long width, long long height, int channels) {
  try {
    check_image_size(width, height, channels);
  } catch (const std::exception& e) {
    throw UsageError(fmt::format("{}: {}", what, e.what()));
  }
}

}  // namespace gdp
