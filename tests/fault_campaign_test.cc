// The fault campaign on the gdp tool (small images): bad inputs and options, every codec's files cut
// at many offsets, signals at random moments, full disks. Each case: exit status, one line naming
// the file or option, no output or temporary left. Seeded, so every run tries the same cases.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "cli_fixture.h"
#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/image_stream.h"
#include "gdp/size_check.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace gdp {
namespace {

class FaultCampaign : public test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    write_image(path("in.png"), test::random_image(96, 64, 3, 7), {});
    write_image(path("in.tif"), test::random_image(96, 64, 3, 7), {});
    Image labels(96, 64, 1);
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 96; ++x) labels.at(0, x, y) = x < 48 ? 0.0f : 0.5f;
    write_image(path("labels.png"), labels, {});
  }
  void TearDown() override {
    std::printf("[ campaign ] %s: %d cases\n",
                ::testing::UnitTest::GetInstance()->current_test_info()->name(), cases_);
    CliFixture::TearDown();
  }
  void fail(const std::string& args, const std::string& mention) {
    SCOPED_TRACE(args);
    ++cases_;
    expect_failure(args, mention);
  }
  int cases_ = 0;
};

// Everything the README promises one clear line for.
TEST_F(FaultCampaign, BadInputsAndOptions) {
  const std::string in = path("in.png"), out = " -o " + path("out.png");
  const std::string stitch = "stitch -c " + in + " -l " + path("labels.png") + out;
  fs::create_directory(path("dir.png"));
  std::ofstream(path("empty.png"));
  std::ofstream(path("text.jpg")) << "not a JPEG at all\n";
  write_image(path("five.tif"), Image(8, 8, 5), {});
  write_image(path("small.png"), Image(10, 10, 1), {});
  write_image(path("white.png"), Image(96, 64, 1, 1.0f), {});
  write_image(path("gray.png"), Image(96, 64, 1, 0.5f), {});
  std::ofstream(path("afile")) << "x";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"sharpen " + path("missing.png") + out, "missing.png"},
      {"sharpen " + path("dir.png") + out, "dir.png"},
      {"sharpen " + path("empty.png") + out, "empty.png"},
      {"sharpen " + path("text.jpg") + out, "text.jpg"},
      {"smooth " + path("five.tif") + out, "five.tif"},
      {"stitch -c " + in + " -l " + path("small.png") + out, "small.png"},
      {"stitch -c " + in + " -l " + path("white.png") + out, "white.png"},
      {"sharpen " + in + out + " --weights " + path("small.png"), "small.png"},
      {"sharpen " + in + out + " --pin " + path("small.png"), "small.png"},
      {"sharpen " + in + out + " --low " + path("small.png"), "small.png"},
      {"sharpen " + in + " -o " + path("nowhere/out.png"), "nowhere"},
      {"sharpen " + in + " -o " + path("afile/out.png"), "afile"},
      {"sharpen " + in + out + " --temp " + path("nowhere"), "nowhere"},
      {"sharpen " + in + out + " --temp " + path("afile"), "afile"},
      {"sharpen " + in + out + " --stats " + path("nowhere/s.json"), "nowhere"},
      {"sharpen " + in + out + " --frobnicate", "frobnicate"},
      {"frobnicate " + in + out, "frobnicate"},
      {"sharpen " + in + out + " --iters -1", "--iters"},
      {"sharpen " + in + out + " --vcycles 0", "--vcycles"},
      {"sharpen " + in + out + " --tolerance nan", "--tolerance"},
      {"sharpen " + in + out + " --threads 0", "--threads"},
      {"sharpen " + in + out + " --bands 0", "--bands"},
      {"sharpen " + in + out + " --bands 2 --in-core", "--bands"},
      {"sharpen " + in + out + " --incore-bytes -1", "--incore-bytes"},
      {"sharpen " + in + out + " --depth 12", "--depth"},
      {"sharpen " + in + out + " --quality 0", "--quality"},
      {"sharpen " + in + out + " --domain sphere", "sphere"},
      {"sharpen " + in + out + " --half-scratch --double", "half"},
      {"sharpen " + in + out + " --compression zip", "--compression"},
      {"sharpen " + in + " -o " + path("out.tif") + " --compression bogus", "bogus"},
      {"sharpen " + in + out + " --alpha 0", "--alpha"},
      {"sharpen " + in + out + " --alpha inf", "--alpha"},
      {"sharpen " + in + out + " --beta inf", "--beta"},
      {"sharpen " + in + out + " --beta 0.5", "--beta"},
      {"smooth " + in + out + " --beta 2", "--beta"},
      {"sharpen " + in + out + " --scale 1e-30", "--scale"},
      {"sharpen " + in + out + " --scale-deg 10", "--scale-deg"},
      {"sharpen " + in + out + " --max-pixels 100", in},
      {"sharpen --sphere " + in + out, in},
      {"sharpen --sphere " + in + out + " --pq-height 3", "--pq-height"},
      {"sphere to-pq " + in + " -o " + path("pq.png"), in},
      {"sphere from-pq " + in + " -o " + path("eq.png") + " --format equirect", in},
      {"tonemap " + in + out + " --gamma 0", "--gamma"},
      {"clone -s " + in + " -t " + in + " -m " + path("missing.png") + " --offset 0,0" + out, "missing.png"},
      {stitch + " --unknown purple", "--unknown"},
      {"stitch -c " + path("gray.png") + " -l " + path("labels.png") + out + " --space lab", "--space lab"},
  };
  for (const auto& [args, mention] : cases) fail(args, mention);
}

// Every codec's files cut at many offsets: an error naming the file, never a partial success.
TEST_F(FaultCampaign, TruncatedFilesOfEveryCodec) {
  const Image image = test::random_image(96, 64, 3, 9);
  write_image(path("a.png"), image, {});
  write_image(path("a.jpg"), image, {});
  write_image(path("strips.tif"), image, WriteOptions{SampleType::UInt8, 95, false, "zip", 256});
  write_image(path("tiles.tif"), image, WriteOptions{SampleType::UInt16, 95, true, "lzw", 16});
  write_image(path("float.tif"), image, WriteOptions{SampleType::Float, 95, false, "none", 256});
  for (const char* name : {"a.png", "a.jpg", "strips.tif", "tiles.tif", "float.tif"}) {
    std::ifstream f(path(name), std::ios::binary);
    const std::string whole(std::istreambuf_iterator<char>(f), {});
    // PNG: the last 12 bytes are IEND, which gdp never needs; JPEG: the last 2, its end marker.
    const std::size_t spare = std::string(name) == "a.png" ? 12 : std::string(name) == "a.jpg" ? 2 : 0;
    const std::string cut = path(std::string("cut_") + name);
    std::vector<std::size_t> offsets = {0, 1, 4, 8, 16, 33, 100};
    for (int k = 1; k < 30; ++k) offsets.push_back(whole.size() * k / 30);
    offsets.push_back(whole.size() - spare - 1);
    for (std::size_t at : offsets) {
      if (at >= whole.size() - spare) continue;
      std::ofstream(cut, std::ios::binary) << whole.substr(0, at);
      fail("convert " + cut + " -o " + path("out.tif"), cut);
    }
    fs::remove(cut);
  }
}

// SIGINT, SIGTERM, SIGHUP and SIGQUIT at random moments of a run: it dies of the signal (or
// finished), and leaves no output, temporary or scratch file.
TEST_F(FaultCampaign, SignalsAtRandomMoments) {
  write_image(path("big.tif"), test::random_image(400, 300, 3, 2), {});
  const std::set<std::string> before = files();
  std::mt19937 random(11);
  for (int i = 0; i < 8; ++i) {
    const int sig = std::vector<int>{SIGINT, SIGTERM, SIGHUP, SIGQUIT}[i % 4];
    const int ms = static_cast<int>(random() % 700);
    const std::string cmd = "set -m; " + std::string(GDP_CLI_PATH) + " sharpen " + path("big.tif") + " -o " +
                            path("out.tif") + " --vcycles 100 --temp " + dir_.string() + " -q & pid=$!; sleep " +
                            std::to_string(ms / 1000.0) + "; kill -" + std::to_string(sig) + " $pid; wait $pid";
    const int status = std::system(("bash -c '" + cmd + "' 2>/dev/null").c_str());
    SCOPED_TRACE("signal " + std::to_string(sig) + " after " + std::to_string(ms) + " ms");
    ++cases_;
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    EXPECT_EQ(files(), before) << "no output, temporary or scratch file may remain";
  }
}

// A full disk (a file-size limit) for the output and for the scratch files, at several sizes.
TEST_F(FaultCampaign, FullDisks) {
  write_image(path("big.tif"), test::random_image(1200, 700, 3, 2), WriteOptions{SampleType::UInt8, 95, false, "none", 256});
  const std::set<std::string> before = files();
  for (int kb : {1, 8, 64, 512}) {
    for (const std::string& run : {"convert " + path("big.tif") + " -o " + path("out.tif"),
                                   "sharpen " + path("big.tif") + " -o " + path("out.png") + " --temp " + dir_.string(),
                                   "stitch -c " + path("big.tif") + " -l " + path("big.tif") + " -o " + path("out.jpg") +
                                       " --temp " + dir_.string() + " --unknown label"}) {
      SCOPED_TRACE(std::to_string(kb) + " KB: " + run);
      ++cases_;
      const test::CliRun r = gdp_shell("ulimit -f " + std::to_string(kb) + "; exec " + GDP_CLI_PATH + " " + run);
      EXPECT_EQ(r.code, 2) << r.err;
      EXPECT_TRUE(r.err.find(dir_.string()) != std::string::npos) << "names the file or directory: " << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
      EXPECT_EQ(files(), before);
    }
  }
}

// A seeded mutation loop over every decoder (bit flips, byte runs, cuts, duplicated and deleted
// spans of a valid file), for GDP_FUZZ_SECONDS per codec (default 1): each mutant reads whole or
// is an InputError naming the file; never another exception, a crash or a hang.
TEST_F(FaultCampaign, DecoderFuzz) {
  const char* env = std::getenv("GDP_FUZZ_SECONDS");
  const double seconds = env ? std::atof(env) : 1.0;
  const Image image = test::random_image(40, 24, 3, 9);
  const std::vector<std::pair<std::string, WriteOptions>> seeds = {
      {"f.png", {}},
      {"f.jpg", {}},
      {"f.tif", WriteOptions{SampleType::UInt8, 95, false, "zip", 256}},
      {"t.tif", WriteOptions{SampleType::UInt16, 95, true, "lzw", 16}},
      {"p.tif", WriteOptions{SampleType::Float, 95, false, "packbits", 256}}};
  set_size_check([](long long w, long long h, int) {  // what the gdp tool does, smaller
    if (w * h > 1 << 20) throw std::length_error("too many pixels");
  });
  std::mt19937 random(5);
  for (const auto& [name, options] : seeds) {
    write_image(path(name), image, options);
    std::ifstream f(path(name), std::ios::binary);
    const std::string whole(std::istreambuf_iterator<char>(f), {});
    const std::string mutant_path = path("mutant_" + name);
    int runs = 0, read_whole = 0;
    const auto start = std::chrono::steady_clock::now();
    while (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < seconds) {
      std::string m = whole;
      for (int edits = 1 + random() % 4; edits > 0; --edits) {
        const std::size_t at = random() % m.size(), span = 1 + random() % 16;
        switch (random() % 5) {
          case 0: m[at] ^= static_cast<char>(1 << (random() % 8)); break;
          case 1: m.replace(at, std::min(span, m.size() - at), span, static_cast<char>(random())); break;
          case 2: m.resize(std::max<std::size_t>(1, at)); break;
          case 3: m.insert(at, m.substr(at, span)); break;
          default: m.erase(at, std::min(span, m.size() - at - (at + 1 < m.size() ? 0 : 1)));
        }
        if (m.empty()) m = "x";
      }
      std::ofstream(mutant_path, std::ios::binary) << m;
      ++runs;
      try {
        ImageFileReader reader(mutant_path, runs % 2 == 0);
        std::vector<float> row(static_cast<std::size_t>(reader.width()) * reader.channels());
        for (int y = 0; y < reader.height(); ++y) reader.read_row(y, row);
        ++read_whole;
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(mutant_path + ": ", 0), 0u) << e.what();
      } catch (const std::exception& e) {
        ADD_FAILURE() << name << " mutant " << runs << ": not an InputError: " << e.what();
      }
    }
    cases_ += runs;
    std::printf("[ campaign ] fuzz %s: %d mutants, %d read whole\n", name.c_str(), runs, read_whole);
  }
  set_size_check(nullptr);
}

}  // namespace
}  // namespace gdp
