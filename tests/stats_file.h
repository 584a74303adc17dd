// Numbers read back from a --stats JSON file.
#pragma once

#include <fstream>
#include <iterator>
#include <string>

namespace gdp::test {

// A number from a --stats file ("key": N), -1 when absent.
inline double stat_of(const std::string& file, const std::string& key) {
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto at = text.find("\"" + key + "\": ");
  return at == std::string::npos ? -1 : std::stod(text.substr(at + key.size() + 4));
}

}  // namespace gdp::test
