// --memory: the scratch budget's default and how its sizes are written.
#include <unistd.h>

#include <cctype>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "gdp/solver.h"

namespace gdp {

std::size_t default_scratch_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return std::size_t{1} << 30;  // unknown: 1 GiB
  return static_cast<std::size_t>(pages) / 4 * static_cast<std::size_t>(page);
}

std::size_t parse_memory_size(const std::string& text) {
  if (text == "files") return 0;
  const auto bad = [&] {
    return UsageError(fmt::format("'{}' is not a size (bytes, or a number with K, M, G or T: 512M, 4G; "
                                  "0 or 'files' for scratch always in files)", text));
  };
  std::size_t end = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &end);
  } catch (const std::exception&) {
    throw bad();
  }
  if (!std::isdigit(static_cast<unsigned char>(text[0])) || !std::isfinite(value) || value < 0.0) throw bad();
  std::string unit = text.substr(end);
  if (!unit.empty() && (unit.back() == 'B' || unit.back() == 'b')) unit.pop_back();
  if (unit.size() > 1) throw bad();
  const std::string units = "KMGT";
  const std::size_t found = unit.empty() ? 0 : units.find(static_cast<char>(std::toupper(unit[0])));
  if (found == std::string::npos) throw bad();
  const std::size_t power = unit.empty() ? 0 : found + 1;
  const double bytes = std::ldexp(value, 10 * static_cast<int>(power));
  if (bytes >= 1.8e19) throw bad();
  return static_cast<std::size_t>(bytes);
}

}  // namespace gdp
