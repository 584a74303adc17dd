// Seeded mutations of small valid files of every codec (truncations, bit flips, header fields, spans):
// each mutant reads whole or is an InputError naming the file; never another exception, crash or hang.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "gdp/errors.h"
#include "gdp/image_stream.h"
#include "gdp/size_check.h"
#include "io/codecs.h"
#include "io/tiff_pages.h"
#include "tools/codec_samples.h"

namespace fs = std::filesystem;

namespace gdp {
namespace {

constexpr int kMutantsPerFile = 160;

// Aborts the test binary, naming the mutant, when one decode takes longer than `limit`: a hang
// fails at once instead of stalling the suite until CTest's timeout.
class HangGuard {
 public:
  explicit HangGuard(std::chrono::seconds limit) : limit_(limit), thread_([this] { watch(); }) {}
  ~HangGuard() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  void begin(const std::string& what) {
    std::lock_guard lock(mutex_);
    what_ = what;
    started_ = std::chrono::steady_clock::now();
    busy_ = true;
  }
  void end() {
    std::lock_guard lock(mutex_);
    busy_ = false;
  }

 private:
  void watch() {
    std::unique_lock lock(mutex_);
    while (!stop_) {
      wake_.wait_for(lock, std::chrono::milliseconds(200));
      if (busy_ && std::chrono::steady_clock::now() - started_ > limit_) {
        std::fprintf(stderr, "decoder hang: %s still decoding after %lld s\n", what_.c_str(),
                     static_cast<long long>(limit_.count()));
        std::abort();
      }
    }
  }
  std::chrono::seconds limit_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::string what_;
  std::chrono::steady_clock::time_point started_;
  bool busy_ = false, stop_ = false;
  std::thread thread_;
};

struct Mutant {
  std::string bytes;
  std::string what;  // how it was made, for messages
};

// A FITS header card's value (columns 11 to 30) replaced; other formats: a binary field.
void mutate_fits_card(std::string& m, std::mt19937& random, std::string& what) {
  static const char* keys[] = {"BITPIX  =", "NAXIS   =", "NAXIS1  =", "NAXIS2  =", "NAXIS3  =", "BZERO   =", "BSCALE  ="};
  static const char* values[] = {"0", "-1", "1", "3", "4", "99999999", "2147483648", "-32", "-64", "8", "16", "64",
                                 "1E300", "NAN", "'text'", ""};
  const std::string key = keys[random() % std::size(keys)], value = values[random() % std::size(values)];
  const std::size_t at = m.find(key);
  if (at == std::string::npos || at % 80 != 0 || at + 30 > m.size()) return;
  std::string field(20, ' ');
  field.replace(20 - value.size(), value.size(), value);
  m.replace(at + 10, 20, field);
  what += " card " + key + " " + value;
}

// A 1-, 2- or 4-byte field in the first 512 bytes set to a boundary value, either byte order.
void mutate_binary_field(std::string& m, std::mt19937& random, std::string& what) {
  static const unsigned long long values[] = {0, 1, 2, 0x7f, 0x80, 0xff, 0x100, 0x7fff, 0x8000, 0xffff,
                                              0x10000, 0x7fffffff, 0x80000000, 0xffffffff};
  const int bytes = std::vector<int>{1, 2, 4}[random() % 3];
  const unsigned long long v = values[random() % std::size(values)];
  const std::size_t at = random() % std::min<std::size_t>(m.size(), 512);
  const bool big_endian = random() % 2;
  for (int k = 0; k < bytes && at + k < m.size(); ++k)
    m[at + k] = static_cast<char>(v >> (8 * (big_endian ? bytes - 1 - k : k)));
  what += " field at " + std::to_string(at) + " = " + std::to_string(v) + " (" + std::to_string(bytes) + " bytes)";
}

Mutant mutate(const std::string& whole, bool fits, int i, std::mt19937& random) {
  Mutant mu{whole, "mutant " + std::to_string(i) + ":"};
  std::string& m = mu.bytes;
  switch (i % 4) {
    case 0: {  // a cut: the first 64 offsets one by one, then anywhere
      const std::size_t at = i / 4 < 64 ? i / 4 : random() % m.size();
      m.resize(std::min(at, m.size() - 1));
      mu.what += " cut at " + std::to_string(m.size());
      break;
    }
    case 1:  // bit flips, half of them in the header
      for (int k = 1 + random() % 3; k > 0; --k) {
        const std::size_t at = random() % (random() % 2 ? std::min<std::size_t>(m.size(), 256) : m.size());
        m[at] ^= static_cast<char>(1 << (random() % 8));
        mu.what += " flip at " + std::to_string(at);
      }
      break;
    case 2:
      if (fits) mutate_fits_card(m, random, mu.what);
      else mutate_binary_field(m, random, mu.what);
      break;
    default: {  // a span overwritten, duplicated or deleted
      const std::size_t at = random() % m.size(), span = 1 + random() % 64;
      const int kind = random() % 3;
      if (kind == 0) m.replace(at, std::min(span, m.size() - at), span, static_cast<char>(random()));
      if (kind == 1) m.insert(at, m.substr(at, span));
      if (kind == 2 && at > 0) m.erase(at, span);
      mu.what += std::string(kind == 0 ? " overwrite " : kind == 1 ? " duplicate " : " erase ") +
                 std::to_string(span) + " at " + std::to_string(at);
    }
  }
  return mu;
}

// Every row of the file (page 0), a column window of it, and its other TIFF pages (up to 4);
// prefetch on a thread or not. Throws what gdp's readers throw.
void read_everything(const std::string& path, bool prefetch) {
  int pages = 1;
  if (io::is_tiff_file(path)) {
    try {
      pages = std::max<int>(1, static_cast<int>(io::tiff_pages(path).size()));
    } catch (const std::exception& e) {
      throw InputError(path + ": " + e.what());  // as gdp blend reports it
    }
  }
  for (int page = 0; page < std::min(pages, 4); ++page) {
    ImageFileReader whole(path, prefetch, ColumnRange{}, page);
    const int w = whole.width();
    std::vector<float> row(static_cast<std::size_t>(w) * whole.channels());
    for (int y = 0; y < whole.height(); ++y) whole.read_row(y, row);
    ImageFileReader window(path, prefetch, ColumnRange{w / 3, w / 3 + (w + 1) / 2}, page);
    for (int y = 0; y < window.height(); ++y) window.read_row(y, row);
  }
}

class DecoderMutations : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("gdp_mutations_" + std::to_string(::getpid()) + "_" + GetParam());
    fs::create_directories(dir_);
    set_size_check([](long long w, long long h, int) {  // as --max-pixels does, small
      if (w * h > 1 << 18) throw std::length_error("too many pixels for this test");
    });
  }
  void TearDown() override {
    set_size_check(nullptr);
    fs::remove_all(dir_);
  }
  fs::path dir_;
};

TEST_P(DecoderMutations, ReadWholeOrInputErrorNamingTheFile) {
  const std::string codec = GetParam();
  const bool fits = codec == "fits";
  HangGuard guard(std::chrono::seconds(60));
  int cases = 0, read_whole = 0, errors = 0;
  const std::vector<fs::path> samples = test::write_codec_samples(dir_, codec);
  for (std::size_t s = 0; s < samples.size(); ++s) {
    std::ifstream f(samples[s], std::ios::binary);
    const std::string whole(std::istreambuf_iterator<char>(f), {});
    ASSERT_NO_THROW(read_everything(samples[s].string(), false)) << samples[s] << " itself must read";
    const std::string path = (dir_ / ("mutant_" + samples[s].filename().string())).string();
    std::mt19937 random(1900 + static_cast<unsigned>(s));
    for (int i = 0; i < kMutantsPerFile; ++i) {
      const Mutant mu = mutate(whole, fits, i, random);
      std::ofstream(path, std::ios::binary | std::ios::trunc) << mu.bytes;
      const std::string what = samples[s].filename().string() + " " + mu.what;
      ++cases;
      guard.begin(what);
      try {
        read_everything(path, i % 2 == 1);
        ++read_whole;
      } catch (const InputError& e) {
        ++errors;
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << what << ": " << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << what << ": " << message;
      } catch (const std::exception& e) {
        ADD_FAILURE() << what << ": not an InputError: " << e.what();
      }
      guard.end();
    }
  }
  EXPECT_GT(errors, cases / 10) << "the mutations should break many files";
  std::printf("[ campaign ] DecoderMutations %s: %d cases (%d read whole, %d InputError)\n", codec.c_str(), cases,
              read_whole, errors);
}

INSTANTIATE_TEST_SUITE_P(Codecs, DecoderMutations, ::testing::ValuesIn(test::sample_codecs()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace gdp
