// enblend's command line as gdp blend understands it: the translation Hugin's makefiles need.
#pragma once

#include <string>
#include <vector>

namespace gdp::cli {

// The arguments after `blend` in enblend's syntax, rewritten for gdp blend's parser: @listfiles
// expanded (one file a line, # comments), -w/--wrap[=MODE] -> --wrap=MODE, -fWxH[+X+Y] ->
// --canvas=..., -d/--depth 8|16|32|r32|r64 -> --depth=8|16|float, --compression=90 ->
// --quality=90 (words lower-cased, deflate -> zip), -oFILE -> -o FILE; enblend-only tuning
// options are dropped and named in `ignored`. Throws UsageError for an unreadable listfile.
std::vector<std::string> from_enblend(const std::vector<std::string>& args, std::vector<std::string>& ignored);

// Reads a response file: one entry a line, blank lines and lines starting with # skipped.
std::vector<std::string> read_listfile(const std::string& path);

// The command line as gdp's parser takes it (program name dropped): a program called gdp-blend
// runs `gdp blend`, and `blend`'s arguments go through from_enblend (its ignored options noted
// on stderr unless -q/--quiet).
std::vector<std::string> command_line(int argc, char** argv);

}  // namespace gdp::cli
