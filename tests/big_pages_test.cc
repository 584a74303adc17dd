// util/big_pages.h: large buffers on 2 MiB boundaries, zeroed, advised as huge pages; small ones as before.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "multigrid/plane.h"
#include "util/big_pages.h"

namespace gdp {
namespace {

using util::kBigBuffer;
using util::kHugePage;

bool all_zero(const unsigned char* p, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k)
    if (p[k] != 0) return false;
  return true;
}

std::uintptr_t address(const void* p) { return reinterpret_cast<std::uintptr_t>(p); }

// The kernel's THP mode ("always", "madvise" or "never"; empty where the file is missing).
std::string thp_mode() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string line;
  std::getline(in, line);
  const auto open = line.find('['), close = line.find(']');
  return open == std::string::npos || close == std::string::npos ? "" : line.substr(open + 1, close - open - 1);
}

// /proc/self/smaps' THPeligible for the mapping holding p (-1: not found).
int thp_eligible(const void* p) {
  std::ifstream in("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    std::uintptr_t begin = 0, end = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> begin >> dash >> end && dash == '-') {
      inside = address(p) >= begin && address(p) < end;
    } else if (inside && line.rfind("THPeligible:", 0) == 0) {
      return std::stoi(line.substr(12));
    }
  }
  return -1;
}

TEST(BigPages, LargeBuffersStartOnHugePagesAndAreZeroedWholePages) {
  const std::size_t bytes = kBigBuffer + kHugePage / 2 + 3;  // 5 MiB and a bit: 6 MiB mapped
  auto* p = static_cast<unsigned char*>(util::map_big(bytes));
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(address(p) % kHugePage, 0u);
  const std::size_t whole = 3 * kHugePage;
  EXPECT_TRUE(all_zero(p, whole));  // every byte up to the last whole huge page is there, zeroed
  std::memset(p, 0xab, whole);
  EXPECT_EQ(p[whole - 1], 0xab);
  util::unmap_big(p, bytes);
  auto* q = static_cast<unsigned char*>(util::map_big(bytes));
  EXPECT_TRUE(all_zero(q, bytes));  // fresh memory again, whatever was there before
  util::unmap_big(q, bytes);
}

TEST(BigPages, LargeBuffersAreAdvisedAsHugePagesWhereTheKernelHasThem) {
  const std::string mode = thp_mode();
  if (mode != "always" && mode != "madvise") GTEST_SKIP() << "transparent huge pages: " << (mode.empty() ? "absent" : mode);
  void* p = util::map_big(kBigBuffer);
  const int eligible = thp_eligible(p);
  util::unmap_big(p, kBigBuffer);
  if (eligible < 0) GTEST_SKIP() << "no THPeligible in /proc/self/smaps";
  EXPECT_EQ(eligible, 1);
}

TEST(BigPages, SmallBuffersAreZeroedToo) {
  for (std::size_t bytes : {std::size_t{1}, std::size_t{4096}, kBigBuffer - 1}) {
    auto* p = static_cast<unsigned char*>(util::map_big(bytes));
    ASSERT_NE(p, nullptr);
    EXPECT_TRUE(all_zero(p, bytes));
    p[bytes - 1] = 1;
    util::unmap_big(p, bytes);
  }
  EXPECT_EQ(util::map_big(0), nullptr);
}

TEST(BigPages, PopulateKeepsWhatIsWritten) {
  const std::size_t bytes = 2 * kBigBuffer;
  auto* p = static_cast<unsigned char*>(util::map_big(bytes));
  for (std::size_t k = 0; k < kBigBuffer; ++k) p[k] = static_cast<unsigned char>(k * 7 + 1);
  util::populate(p + 100, bytes - 200);  // not page-aligned, over written and unwritten pages
  bool same = true;
  for (std::size_t k = 0; k < kBigBuffer; ++k) same = same && p[k] == static_cast<unsigned char>(k * 7 + 1);
  EXPECT_TRUE(same);
  EXPECT_TRUE(all_zero(p + kBigBuffer, kBigBuffer));
  util::unmap_big(p, bytes);
}

TEST(BigPages, PlanesOfAnySizeBehaveAsVectors) {
  multigrid::Plane<float> big(1024, 1025), small(3, 2);  // 4.0 MiB and a row; 24 bytes
  EXPECT_EQ(address(big.data.data()) % kHugePage, 0u);
  EXPECT_EQ(big.at(1023, 1024), 0.0f);
  big.at(5, 7) = 2.5f;
  small.at(2, 1) = 1.5f;
  multigrid::Plane<float> copy = big;
  EXPECT_EQ(copy.at(5, 7), 2.5f);
  std::swap(copy, small);
  EXPECT_EQ(small.at(5, 7), 2.5f);
  EXPECT_EQ(copy.at(2, 1), 1.5f);
  copy.data.resize(big.data.size());  // grows from the heap into a big buffer, keeping its values
  EXPECT_EQ(copy.data[5], 1.5f);
  EXPECT_EQ(copy.data.back(), 0.0f);
}

}  // namespace
}  // namespace gdp
