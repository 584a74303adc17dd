// The band schedule across MPI ranks: `mpirun -np N gdp sharpen --bands T` against one process.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include "cli_fixture.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace gdp {
namespace {

// mpirun as these tests start it; `timeout` turns a hang into a failure (exit status 124).
const std::string kMpirun = "timeout 60 mpirun --oversubscribe --allow-run-as-root";

bool mpirun_works() {
  static const bool works =
      std::system((kMpirun + " -np 2 true > /dev/null 2>&1").c_str()) == 0;
  return works;
}

class MpiBands : public test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    if (!mpirun_works()) GTEST_SKIP() << "mpirun cannot start 2 processes here: MPI tests skipped";
    // A stitching-like problem: smooth content with offsets between regions, and some noise.
    Image im = test::cosine_image(320, 96, 2, 1);
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) im.at(0, x, y) = 0.5f + 0.3f * im.at(0, x, y) + (x > 150 ? 0.1f : 0.0f);
    const Image noise = test::random_image(320, 96, 1, 5);
    for (std::size_t i = 0; i < im.data.size(); ++i) im.data[i] += 0.05f * noise.data[i];
    write_image(path("in.tif"), im, {});
  }

  // gdp sharpen on in.tif into `out` (float TIFF), one process or under mpirun with `ranks`.
  test::CliRun sharpen(const std::string& out, int bands, int ranks = 0, const std::string& extra = "") const {
    const std::string args = "sharpen " + path("in.tif") + " -o " + path(out) + " --depth float -q --bands " +
                             std::to_string(bands) + " " + extra;
    if (ranks == 0) return gdp(args);
    return mpi("-np " + std::to_string(ranks) + " " + GDP_CLI_PATH + " " + args);
  }

  test::CliRun mpi(const std::string& rest) const { return gdp_raw(kMpirun + " " + rest); }

  test::CliRun gdp_raw(const std::string& cmd) const {
    test::CliRun r;
    const int status = std::system((cmd + " 2> " + path("stderr.txt") + " > /dev/null").c_str());
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream f(path("stderr.txt"));
    r.err.assign(std::istreambuf_iterator<char>(f), {});
    return r;
  }

  Image result(const std::string& name) const { return read_image(path(name)).image; }

  static double range(const Image& a) {
    const auto [lo, hi] = std::minmax_element(a.data.begin(), a.data.end());
    return *hi - *lo;
  }
};

TEST_F(MpiBands, RanksGiveTheThreadResultAndAgreeWithOneBand) {
  ASSERT_EQ(sharpen("one.tif", 1).code, 0);
  const Image one = result("one.tif");
  for (const auto& [ranks, bands] : {std::pair{2, 1}, std::pair{3, 1}, std::pair{2, 2}}) {
    SCOPED_TRACE(std::to_string(ranks) + " ranks x " + std::to_string(bands) + " bands");
    const test::CliRun r = sharpen("mpi.tif", bands, ranks);
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_EQ(sharpen("threads.tif", ranks * bands).code, 0);
    const Image m = result("mpi.tif");
    // The same bands on ranks as on threads: the same schedule, the same bits.
    EXPECT_EQ(test::max_difference(m, result("threads.tif")), 0.0);
    EXPECT_LE(test::max_difference(m, one), 1e-4 * range(one));
  }
}

// bench/mpi_delay (the latency injector) delays messages, in both of its modes, without changing
// them or their order: the same bits as without it, and no hang.
TEST_F(MpiBands, DelayedMessagesGiveTheSameBits) {
  const std::string lib = GDP_MPI_DELAY_LIB;
  if (lib.empty()) GTEST_SKIP() << "bench/mpi_delay is not built (GDP_BUILD_BENCH=OFF)";
  ASSERT_EQ(sharpen("threads.tif", 2).code, 0);
  const std::string run = std::string(GDP_CLI_PATH) + " sharpen " + path("in.tif") + " -o " + path("delayed.tif") +
                          " --depth float -q --bands 1";
  for (const std::string from : {"receive", "arrival"}) {
    SCOPED_TRACE(from);
    const test::CliRun r =
        mpi("-np 2 -x LD_PRELOAD=" + lib + " -x GDP_MPI_DELAY_US=300 -x GDP_MPI_DELAY_FROM=" + from + " " + run);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(test::max_difference(result("delayed.tif"), result("threads.tif")), 0.0);
  }
}

TEST_F(MpiBands, SameBitsRunToRun) {
  ASSERT_EQ(sharpen("a.tif", 1, 3).code, 0);
  ASSERT_EQ(sharpen("b.tif", 1, 3).code, 0);
  EXPECT_EQ(test::max_difference(result("a.tif"), result("b.tif")), 0.0);
}

TEST_F(MpiBands, MissingInputOnOneRankStopsEveryRank) {
  const std::string good = std::string(GDP_CLI_PATH) + " sharpen " + path("in.tif");
  const std::string bad = std::string(GDP_CLI_PATH) + " sharpen " + path("missing.tif");
  const std::string tail = " -o " + path("out.tif") + " --depth float -q --bands 1";
  const test::CliRun r = mpi("-np 1 " + good + tail + " : -np 1 " + bad + tail);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.code, 124) << "timed out: a rank hung";
  EXPECT_NE(r.err.find("missing.tif"), std::string::npos) << r.err;
  EXPECT_EQ(files(), std::set<std::string>{"in.tif"}) << "no output, not even a temporary file";
}

TEST_F(MpiBands, RanksThatDisagreeStopTogether) {
  const std::string run = std::string(GDP_CLI_PATH) + " sharpen " + path("in.tif") + " -o " + path("out.tif") +
                          " --depth float -q --bands 1";
  const test::CliRun r = mpi("-np 1 " + run + " : -np 1 " + run + " --iters 2");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("disagree"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path("out.tif")));
}

TEST_F(MpiBands, CommandsThatDoNotGatherAreRefused) {
  const test::CliRun r = mpi("-np 2 " + std::string(GDP_CLI_PATH) + " reconstruct " + path("in.tif") + " --bands 1");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.code, 124);
  EXPECT_NE(r.err.find("only stitch"), std::string::npos) << r.err;
  const test::CliRun s = sharpen("out.tif", 0, 2);
  EXPECT_NE(s.code, 0);
  EXPECT_NE(s.err.find("--bands"), std::string::npos) << s.err;
}

}  // namespace
}  // namespace gdp
