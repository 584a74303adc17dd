// Header cards as text: Montage templates to 80-character cards, numeric look-ups, target headers.
#include "sky/header.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp::sky {

std::string card(const std::string& key, const std::string& value) {
  std::string c = fmt::format("{:<8}= {}", key, value);
  c.resize(80, ' ');
  return c;
}

std::string cards_from_text(const std::string& text, const std::string& name) {
  std::istringstream in(text);
  std::string line, cards;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty()) continue;
    const std::size_t eq = line.find('=');
    std::string key = line.substr(0, std::min(eq, std::size_t{8}));
    while (!key.empty() && key.back() == ' ') key.pop_back();
    if (key == "END") break;
    if (key == "COMMENT" || key == "HISTORY") continue;
    if (eq == std::string::npos || eq > 8)
      throw InputError(fmt::format("{}: line {} is not a 'KEY = value' card: {}", name, number, line));
    std::string value = line.substr(eq + 1);
    while (!value.empty() && value.front() == ' ') value.erase(0, 1);
    if (key.empty() || value.empty())
      throw InputError(fmt::format("{}: line {} is not a 'KEY = value' card: {}", name, number, line));
    cards += card(key, value);
  }
  if (cards.empty()) throw InputError(fmt::format("{}: no header cards", name));
  return cards;
}

std::string read_header_template(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open the header template", path.string()));
  std::stringstream text;
  text << in.rdbuf();
  return cards_from_text(text.str(), path.string());
}

std::optional<double> header_number(const std::string& cards, const std::string& key) {
  const std::string want = fmt::format("{:<8}=", key);
  for (std::size_t at = 0; at + 80 <= cards.size(); at += 80) {
    if (cards.compare(at, 9, want) != 0) continue;
    const std::string value = cards.substr(at + 10, 70);
    const char* begin = value.c_str();
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin) return std::nullopt;
    return v;
  }
  return std::nullopt;
}

std::string target_header(const SkyTarget& s) {
  const auto number = [](double v) { return fmt::format("{:.15g}", v); };
  std::string h;
  h += card("NAXIS1", std::to_string(s.width));
  h += card("NAXIS2", std::to_string(s.height));
  h += card("CTYPE1", fmt::format("'RA---{}'", s.projection));
  h += card("CTYPE2", fmt::format("'DEC--{}'", s.projection));
  h += card("CRVAL1", number(s.lon));
  h += card("CRVAL2", number(s.lat));
  // The centre of the image: FITS pixel (N + 1) / 2.
  h += card("CRPIX1", number((s.width + 1) / 2.0));
  h += card("CRPIX2", number((s.height + 1) / 2.0));
  h += card("CDELT1", number(-s.scale));
  h += card("CDELT2", number(s.scale));
  h += card("CUNIT1", "'deg'");
  h += card("CUNIT2", "'deg'");
  h += card("RADESYS", "'ICRS'");
  return h;
}

int hpx_order_for_scale(double scale) {
  // HEALPix pixels of order k are sqrt(pi / 3) / 2^k radians on a side (58.6 degrees at order 0).
  const double base = std::sqrt(M_PI / 3.0) * 180.0 / M_PI;
  int order = 0;
  while (order < 13 && base / std::ldexp(1.0, order) > scale) ++order;
  return order;
}

std::pair<std::string, std::string> hpx_ctypes(const std::string& longitude) {
  const char* latitude = longitude == "RA" ? "DEC" : longitude == "GLON" ? "GLAT" : longitude == "ELON" ? "ELAT" : nullptr;
  if (!latitude) throw UsageError(fmt::format("HPX: a longitude axis RA, GLON or ELON, not {}", longitude));
  const auto axis = [](std::string name) {  // "RA" -> "RA---HPX"
    name.resize(4, '-');
    return name + "-HPX";
  };
  return {axis(longitude), axis(latitude)};
}

std::string hpx_grid_header(int order, const std::string& longitude) {
  const auto [ctype1, ctype2] = hpx_ctypes(longitude);
  if (order < 0 || order > 13) throw UsageError(fmt::format("an HPX grid of HEALPix order {}: 0 to 13", order));
  const long long n = 1LL << order;
  const auto number = [](double v) { return fmt::format("{:.17g}", v); };
  // The pixel grid turned by 45 degrees: CD = (90 / N) PC with PC = (1/2, 1/2; -1/2, 1/2) and
  // CDELT = (-90 / N, 90 / N), so a pixel is a HEALPix pixel (a diamond of diagonal 90 / N
  // degrees in the HPX plane); the image's centre (5N + 1) / 2 is base pixel 4's centre (0, 0).
  const double cd = 45.0 / double(n);
  std::string h;
  h += card("NAXIS1", std::to_string(5 * n));
  h += card("NAXIS2", std::to_string(5 * n));
  h += card("CTYPE1", "'" + ctype1 + "'");
  h += card("CTYPE2", "'" + ctype2 + "'");
  h += card("CRPIX1", number((5.0 * double(n) + 1.0) / 2.0));
  h += card("CRPIX2", number((5.0 * double(n) + 1.0) / 2.0));
  h += card("CRVAL1", "0.0");
  h += card("CRVAL2", "0.0");
  h += card("CD1_1", number(-cd));
  h += card("CD1_2", number(-cd));
  h += card("CD2_1", number(-cd));
  h += card("CD2_2", number(cd));
  h += card("PV2_1", "4");
  h += card("PV2_2", "3");
  h += card("CUNIT1", "'deg'");
  h += card("CUNIT2", "'deg'");
  if (longitude == "RA") h += card("RADESYS", "'ICRS'");
  return h;
}

}  // namespace gdp::sky
