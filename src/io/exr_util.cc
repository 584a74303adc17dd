// OpenImageIO's OpenEXR channel order, gdp's channel names and OpenEXR's thread pool.
#include "io/exr_util.h"

#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfThreading.h>

#include <algorithm>
#include <cctype>
#include <mutex>
#include <string_view>

namespace gdp::io {
namespace {

bool same_ignoring_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

// Position of `suffix` among the names sorted first (case ignored); past them: 1000.
template <std::size_t N>
int rank(std::string_view suffix, const std::string_view (&first)[N]) {
  for (std::size_t i = 0; i < N; ++i)
    if (same_ignoring_case(suffix, first[i])) return static_cast<int>(i);
  return 1000;
}

constexpr std::string_view kUsual[] = {"R",  "Red", "G",  "Green", "B",  "Blue",  "Y",
                                                     "real", "imag", "A", "Alpha", "AR", "RA",  "AG",
                                                     "GA", "AB",  "BA", "Z",     "Depth", "Zback"};
constexpr std::string_view kPositions[] = {"R",  "Red",  "G",     "Green", "B",  "Blue", "X",
                                                         "Y",  "Z",    "real",  "imag",  "A",  "Alpha", "AR",
                                                         "RA", "AG",   "GA",    "AB",    "BA", "Depth", "Zback"};

struct Channel {
  std::string_view layer, suffix;  // "diffuse." and "R" of "diffuse.R"; "" and "R" of "R"
  int rank = 0, index = 0;
};

}  // namespace

std::vector<int> exr_channel_order(const std::vector<std::string>& names) {
  std::vector<Channel> channels;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string_view name = names[i];
    const std::size_t dot = name.rfind('.');
    const std::size_t cut = dot == std::string_view::npos ? 0 : dot + 1;
    channels.push_back({name.substr(0, cut), name.substr(cut), 0, static_cast<int>(i)});
  }
  for (Channel& c : channels) {
    auto in_layer = [&](std::string_view suffix) {
      return std::any_of(channels.begin(), channels.end(),
                         [&](const Channel& o) { return o.layer == c.layer && same_ignoring_case(o.suffix, suffix); });
    };
    const bool positions = in_layer("X") && (in_layer("Y") || in_layer("Z"));
    c.rank = positions ? rank(c.suffix, kPositions) : rank(c.suffix, kUsual);
  }
  std::sort(channels.begin(), channels.end(), [](const Channel& a, const Channel& b) {
    if (a.layer != b.layer) return a.layer < b.layer;
    if (a.rank != b.rank) return a.rank < b.rank;
    return a.suffix < b.suffix;
  });
  std::vector<int> order;
  for (const Channel& c : channels) order.push_back(c.index);
  return order;
}

std::vector<std::string> exr_channel_names(int channels) {
  if (channels == 1) return {"Y"};
  if (channels == 2) return {"Y", "A"};
  std::vector<std::string> names = {"R", "G", "B", "A"};
  names.resize(std::min(channels, 4));
  for (int c = 4; c < channels; ++c) names.push_back("channel" + std::to_string(c));
  return names;
}

int exr_threads(bool tiled) {
  constexpr int kThreads = 2;
  static std::once_flag once;
  std::call_once(once, [] {
    if (Imf::globalThreadCount() < kThreads) Imf::setGlobalThreadCount(kThreads);
  });
  return tiled ? kThreads : 0;
}

ExrHeader read_exr_header(const std::string& path) {
  Imf::StdIFStream stream(path.c_str());
  char start[8];  // magic number, version and flags
  stream.read(start, 8);
  ExrHeader h;
  h.version = static_cast<unsigned char>(start[4]) | static_cast<unsigned char>(start[5]) << 8 |
              static_cast<unsigned char>(start[6]) << 16 | static_cast<unsigned char>(start[7]) << 24;
  h.header.readFrom(stream, h.version);
  return h;
}

}  // namespace gdp::io
