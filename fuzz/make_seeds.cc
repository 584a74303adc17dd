// Writes the fuzz targets' seed corpora: small valid files of each codec (tests/tools/codec_samples.h) into DIR/CODEC/.
#include <cstdio>
#include <exception>
#include <filesystem>

#include "tools/codec_samples.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  try {
    for (const std::string& codec : gdp::test::sample_codecs()) {
      const std::filesystem::path dir = std::filesystem::path(argv[1]) / codec;
      std::filesystem::create_directories(dir);
      gdp::test::write_codec_samples(dir, codec);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
    return 1;
  }
  return 0;
}
