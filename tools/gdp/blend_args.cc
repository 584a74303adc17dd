// Translating enblend's options (as Hugin passes them) into gdp blend's, and gdp-blend's argv[0] dispatch.
#include "blend_args.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp::cli {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool starts(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

// enblend-only options: those taking a value (given after '=' or as the next argument), and
// those taking none or an optional '=VALUE'.
const std::set<std::string> kIgnoredWithValue = {
    "--levels", "--blend-colorspace", "--fallback-profile", "--layer-selector", "--parameter",
    "--primary-seam-generator", "--image-difference", "--optimizer-weights", "--mask-vectorize", "--anneal",
    "--dijkstra", "-l", "-b", "-m"};
const std::set<std::string> kIgnoredFlags = {
    "--fine-mask", "--coarse-mask", "--optimize", "--no-optimize", "--save-masks", "--load-masks", "--visualize",
    "--ciecam", "--no-ciecam", "--pre-assemble", "--no-pre-assemble", "--gpu", "-a", "-x", "-c", "-g"};

std::string depth(const std::string& v) {
  const std::string d = lower(v);
  if (d == "8" || d == "16") return d;
  if (d == "32" || d == "r32" || d == "r64" || d == "float" || d == "half") return d == "half" ? d : "float";
  throw UsageError(fmt::format("--depth: '{}' is not one of 8, 16, 32, r32, r64", v));
}

std::string compression(const std::string& v) {
  const std::string c = lower(v);
  if (!c.empty() && std::all_of(c.begin(), c.end(), [](unsigned char ch) { return std::isdigit(ch); }))
    return "--quality=" + c;
  if (c == "deflate") return "--compression=zip";
  if (starts(c, "jpeg")) return "--compression=jpeg";
  return "--compression=" + c;
}

}  // namespace

std::vector<std::string> read_listfile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw UsageError(fmt::format("{}: cannot read the list file", path));
  std::vector<std::string> entries;
  for (std::string line; std::getline(in, line);) {
    const auto b = line.find_first_not_of(" \t\r"), e = line.find_last_not_of(" \t\r");
    if (b == std::string::npos || line[b] == '#') continue;
    entries.push_back(line.substr(b, e - b + 1));
  }
  return entries;
}

std::vector<std::string> from_enblend(const std::vector<std::string>& args, std::vector<std::string>& ignored) {
  std::vector<std::string> out;
  bool positional = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const auto value = [&](const std::string& name) -> std::string {  // "--name=V", "-nV" or "-n V"
      if (a.size() > name.size() && a[name.size()] == '=') return a.substr(name.size() + 1);
      if (a.size() > name.size() && name.size() == 2) return a.substr(2);
      if (i + 1 >= args.size()) throw UsageError(fmt::format("{} needs a value", name));
      return args[++i];
    };
    const std::string key = a.substr(0, a.find('='));
    if (positional || a.empty() || a[0] != '-' || a == "-") {
      if (!a.empty() && a[0] == '@') {
        for (const std::string& f : read_listfile(a.substr(1))) out.push_back(f);
      } else {
        out.push_back(a);
      }
    } else if (a == "--") {
      positional = true;
      out.push_back(a);
    } else if (key == "--wrap" || starts(a, "-w")) {
      const std::string mode = key == "--wrap" ? (a.size() > 6 ? a.substr(7) : "") : a.substr(2);
      out.push_back("--wrap=" + (mode.empty() ? std::string("horizontal") : lower(mode)));
    } else if (starts(a, "-f")) {
      out.push_back("--canvas=" + value("-f"));
    } else if (key == "--depth" || starts(a, "-d")) {
      out.push_back("--depth=" + depth(value(key == "--depth" ? "--depth" : "-d")));
    } else if (key == "--compression") {
      out.push_back(compression(value("--compression")));
    } else if (key == "--output" || (starts(a, "-o") && a.size() > 2)) {
      out.push_back("-o");
      out.push_back(value(key == "--output" ? "--output" : "-o"));
    } else if (a == "-V") {
      out.push_back("--version");
    } else if (key == "--verbose" || starts(a, "-v")) {
      out.push_back("--verbose");
    } else if (kIgnoredWithValue.count(key) || (a.size() > 2 && kIgnoredWithValue.count(a.substr(0, 2)))) {
      const bool short_glued = a.size() > 2 && a[1] != '-';
      ignored.push_back(short_glued || a.find('=') != std::string::npos || i + 1 >= args.size() ? a
                                                                                              : a + " " + args[++i]);
    } else if (kIgnoredFlags.count(key)) {
      ignored.push_back(a);
    } else {
      out.push_back(a);
    }
  }
  return out;
}

std::vector<std::string> command_line(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  const std::string program = argc > 0 ? std::filesystem::path(argv[0]).filename().string() : "";
  if (program == "gdp-blend") args.insert(args.begin(), "blend");
  if (args.empty() || args[0] != "blend") return args;
  std::vector<std::string> ignored;
  std::vector<std::string> rest = from_enblend({args.begin() + 1, args.end()}, ignored);
  rest.insert(rest.begin(), "blend");
  const bool quiet = std::find_if(rest.begin(), rest.end(), [](const std::string& a) {
                       return a == "-q" || a == "--quiet";
                     }) != rest.end();
  if (!ignored.empty() && !quiet) {
    std::string list;
    for (const std::string& s : ignored) list += (list.empty() ? "" : ", ") + s;
    std::fprintf(stderr, "gdp blend: ignoring enblend-only option(s) %s (gdp blends in the gradient domain)\n",
                 list.c_str());
  }
  return rest;
}

}  // namespace gdp::cli
