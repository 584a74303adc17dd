// The band schedule across MPI ranks: `mpirun -np N gdp sharpen --bands T` against one process.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <thread>
#include <tuple>
#include <vector>

#include "cli_fixture.h"
#include "image_compare.h"
#include "gdp/image_io.h"
#include "mpi/stored_samples.h"
#include "test_util.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

using test::kMpirun;

class MpiBands : public test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    if (!test::mpirun_works()) GTEST_SKIP() << "mpirun cannot start 2 processes here: MPI tests skipped";
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

  // A w x h RGB image of waves, an offset in the right half and noise, to `name`; and a label map
  // of slanted stripes (regions of w/6 columns) to labels.png.
  void write_waves(const std::string& name, int w, int h) const {
    Image im(w, h, 3), labels(w, h, 1);
    const Image noise = test::random_image(w, h, 3, 7);
    for (int c = 0; c < 3; ++c) {
      const Image wave = test::cosine_image(w, h, 2 + c, 3 - c);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          im.at(c, x, y) = 0.5f + 0.3f * wave.at(0, x, y) + (x > w / 2 ? 0.1f : 0.0f) + 0.05f * noise.at(c, x, y);
          labels.at(0, x, y) = static_cast<float>((x + y / 2) / (w / 6 + 1) % 6 + 1) / 8.0f;
        }
    }
    write_image(path(name), im, {});
    write_image(path("labels.png"), labels, {});
  }

  static double range(const Image& a) {
    const auto [lo, hi] = std::minmax_element(a.data.begin(), a.data.end());
    return *hi - *lo;
  }
};

// Float scratch: the bands' own ordering against one band's, without half floats' rounding flips
// (narrow adds up to 1.13e-4 of the range here; ScheduleConformance covers narrow bands).
TEST_F(MpiBands, RanksGiveTheThreadResultAndAgreeWithOneBand) {
  const std::string exact = "--scratch float";
  ASSERT_EQ(sharpen("one.tif", 1, 0, exact).code, 0);
  const Image one = result("one.tif");
  for (const auto& [ranks, bands] : {std::pair{2, 1}, std::pair{3, 1}, std::pair{2, 2}}) {
    SCOPED_TRACE(std::to_string(ranks) + " ranks x " + std::to_string(bands) + " bands");
    const test::CliRun r = sharpen("mpi.tif", bands, ranks, exact);
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_EQ(sharpen("threads.tif", ranks * bands, 0, exact).code, 0);
    const Image m = result("mpi.tif");
    // The same bands on ranks as on threads: the same schedule, the same bits.
    EXPECT_EQ(test::max_difference(m, result("threads.tif")), 0.0);
    EXPECT_LE(test::max_difference(m, one), 1e-4 * range(one));
  }
}

// Without --bands, mpirun runs one band per rank: the two-band result.
TEST_F(MpiBands, RanksDefaultToOneBandEach) {
  const std::string args = "sharpen " + path("in.tif") + " -o " + path("mpi.tif") + " --depth float -q";
  const test::CliRun r = mpi("-np 2 " + std::string(GDP_CLI_PATH) + " " + args);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(sharpen("threads.tif", 2).code, 0);
  EXPECT_EQ(test::max_difference(result("mpi.tif"), result("threads.tif")), 0.0);
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

// Waiting ranks never give their core away with sched_yield (mpi/wait.h): on a core shared with
// busy threads each yield waited a time slice of every one of them, and band solves under load
// took minutes (docs/how-bands-work.md, 2026-11-26). The preload counts the yields made from libgdp
// and Open MPI in each rank; every band count finishes (kMpirun's timeout) with the thread result.
TEST_F(MpiBands, WaitingRanksNeverYieldTheirCore) {
  const std::string lib = GDP_YIELD_COUNT_LIB;
  ASSERT_EQ(sharpen("one.tif", 1, 0, "--scratch float").code, 0);
  const Image one = result("one.tif");
  for (const int bands : {2, 3, 4}) {
    SCOPED_TRACE(std::to_string(bands) + " bands a rank");
    const test::CliRun r = mpi("-np 2 -x LD_PRELOAD=" + lib + " " + GDP_CLI_PATH + " sharpen " + path("in.tif") +
                               " -o " + path("mpi.tif") + " --depth float -q --scratch float --bands " +
                               std::to_string(bands));
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string none = "sched_yield calls from gdp or MPI: 0\n";
    const std::size_t first = r.err.find(none);
    EXPECT_TRUE(first != std::string::npos && r.err.find(none, first + 1) != std::string::npos) << r.err;
    ASSERT_EQ(sharpen("threads.tif", 2 * bands, 0, "--scratch float").code, 0);
    EXPECT_EQ(test::max_difference(result("mpi.tif"), result("threads.tif")), 0.0);
    EXPECT_LE(test::max_difference(result("mpi.tif"), one), 1e-4 * range(one));
  }
}

// The smallest result ring (GDP_RESULT_ROWS=1: a worker runs ahead of the writing by one row
// unless a worker of its group has not put the row to write) on a tall problem with bands of 28
// columns and a wide, low one, with two V-cycles and three channels (channel groups on threads): on
// threads with 1-4 bands and under mpirun with 2 and 3 ranks every run finishes (a hang fails by
// its timeout) with the in-core result (one band: its bits; more: 1e-4 of the range) and, on ranks,
// the threads' bits. A ring of a fixed 16 rows hung under mpirun (docs/how-bands-work.md, "Why a
// streamed solve cannot hang"); 1 row hangs at once without that rule.
TEST_F(MpiBands, SmallestResultRingNeverHangs) {
  for (const auto& [w, h] : {std::pair{170, 700}, std::pair{1000, 40}}) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
    write_waves("s.tif", w, h);
    const auto run = [&](const std::string& out, const std::string& how, int ranks = 0) {
      const std::string cli = std::string(GDP_CLI_PATH) + " sharpen " + path("s.tif") + " -o " + path(out) +
                              " --depth float -q --scratch float --vcycles 2 --incore-bytes 4096 --threads 14 " + how;
      const test::CliRun r = ranks ? mpi("-np " + std::to_string(ranks) + " -x GDP_RESULT_ROWS=1 " + cli)
                                   : gdp_raw("GDP_RESULT_ROWS=1 timeout 60 " + cli);
      EXPECT_EQ(r.code, 0) << how << " on " << ranks << " ranks: " << r.err;
      return r.code == 0 ? result(out) : Image();
    };
    const Image in_core = run("in_core.tif", "--in-core");
    ASSERT_FALSE(in_core.data.empty());
    std::vector<Image> threads(7);
    for (int bands = 1; bands <= 6; bands += bands < 4 ? 1 : 2) {
      threads[bands] = run("threads.tif", "--bands " + std::to_string(bands));
      ASSERT_FALSE(threads[bands].data.empty());
      EXPECT_LE(test::max_difference(threads[bands], in_core), bands == 1 ? 0.0 : 1e-4 * range(in_core)) << bands;
    }
    for (const auto& [ranks, bands] : {std::pair{2, 1}, std::pair{3, 2}, std::pair{2, 2}}) {
      const Image m = run("mpi.tif", "--bands " + std::to_string(bands), ranks);
      ASSERT_FALSE(m.data.empty());
      EXPECT_EQ(test::max_difference(m, threads[ranks * bands]), 0.0) << ranks << " ranks x " << bands << " bands";
    }
  }
}

// The smallest input rings (GDP_INPUT_ROWS=1: the fewest slots InputRing takes, 5 for a unit's rows
// and 11 for the decoded rows; with GDP_RESULT_ROWS=1) on a sharpen (one unit for all bands) and a
// stitch (a unit per band, one decoded ring), the tall and the wide problem, two V-cycles, three
// channel groups, on threads with 1-4 and 6 bands and under mpirun with 2 and 3 ranks: every run
// finishes (a hang fails by its timeout) with the bits of 16 slots (docs/how-bands-work.md, "Why a
// streamed solve cannot hang": fewer slots than these hang).
TEST_F(MpiBands, SmallestInputRingNeverHangs) {
  for (const auto& [w, h] : {std::pair{170, 700}, std::pair{1000, 40}})
    for (const std::string& app : {"sharpen " + path("s.tif"), "stitch -c " + path("s.tif") + " -l " + path("labels.png")}) {
      SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + " " + app.substr(0, 7));
      write_waves("s.tif", w, h);
      const auto run = [&](bool tiny, int bands, int ranks = 0) {  // under mpirun: tiny rings
        const std::string cli = std::string(GDP_CLI_PATH) + " " + app + " -o " + path("out.tif") +
                                " --depth float -q --scratch float --vcycles 2 --incore-bytes 4096 --threads 14 --bands " +
                                std::to_string(bands);
        const test::CliRun r =
            ranks ? mpi("-np " + std::to_string(ranks) + " -x GDP_INPUT_ROWS=1 -x GDP_RESULT_ROWS=1 " + cli)
                  : gdp_raw(std::string(tiny ? "GDP_INPUT_ROWS=1 GDP_RESULT_ROWS=1 " : "") + "timeout 60 " + cli);
        EXPECT_EQ(r.code, 0) << (tiny ? "tiny rings, " : "") << bands << " bands on " << ranks << " ranks: " << r.err;
        return r.code == 0 ? result("out.tif") : Image();
      };
      std::vector<Image> slots16(7);
      for (int bands = 1; bands <= 6; bands += bands < 4 ? 1 : 2) {
        slots16[bands] = run(false, bands);
        const Image one = run(true, bands);
        ASSERT_FALSE(one.data.empty() || slots16[bands].data.empty());
        EXPECT_EQ(test::max_difference(one, slots16[bands]), 0.0) << bands << " bands";
      }
      for (const auto& [ranks, bands] : {std::pair{2, 1}, std::pair{3, 2}, std::pair{2, 2}}) {
        const Image m = run(true, bands, ranks);
        ASSERT_FALSE(m.data.empty());
        EXPECT_EQ(test::max_difference(m, slots16[ranks * bands]), 0.0) << ranks << " ranks x " << bands << " bands";
      }
    }
}

// A stitch (a pure gradient problem: the kept mean needs every rank's input sums), every rank
// writing its own columns to its own file and keeping its scratch in its own directory.
TEST_F(MpiBands, RankFilesHoldTheColumnsOfTheSharedResult) {
  const Image wave = test::cosine_image(300, 80, 3, 2);
  Image comp(300, 80, 3), labels(300, 80, 1);
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 300; ++x) {
      const int region = (x + y / 2) / 70;
      labels.at(0, x, y) = static_cast<float>(region) / 8.0f;
      for (int c = 0; c < 3; ++c)
        comp.at(c, x, y) = 0.4f + 0.2f * wave.at(0, x, y) + 0.05f * static_cast<float>(region * (c + 1));
    }
  write_image(path("comp.tif"), comp, {});
  write_image(path("labels.png"), labels, {});
  std::filesystem::create_directory(path("tmp_0"));
  std::filesystem::create_directory(path("tmp_1"));
  const std::string stitch = std::string(GDP_CLI_PATH) + " stitch -c " + path("comp.tif") + " -l " +
                             path("labels.png") + " --depth float ";
  const test::CliRun r =
      mpi("-np 2 " + stitch + "--bands 1 -o " + path("out_{rank}.tif") + " --temp " + path("tmp_{rank}"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("rank 1 wrote columns"), std::string::npos) << r.err;
  ASSERT_EQ(gdp_raw(stitch + "-q --bands 2 -o " + path("threads.tif")).code, 0);
  const Image left = result("out_0.tif"), right = result("out_1.tif"), whole = result("threads.tif");
  ASSERT_EQ(left.width + right.width, whole.width);
  ASSERT_GT(left.width, 0);
  ASSERT_GT(right.width, 0);
  double diff = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < whole.height; ++y)
      for (int x = 0; x < whole.width; ++x) {
        const float v = x < left.width ? left.at(c, x, y) : right.at(c, x - left.width, y);
        diff = std::max(diff, static_cast<double>(std::abs(v - whole.at(c, x, y))));
      }
  EXPECT_EQ(diff, 0.0) << "two rank files side by side are the two-band result";
  // And gathered into one file by rank 0.
  ASSERT_EQ(mpi("-np 2 " + stitch + "--bands 1 -q -o " + path("gathered.tif")).code, 0);
  EXPECT_EQ(test::max_difference(result("gathered.tif"), whole), 0.0);
  // From per-band input files: the composite as three strips (each rank decodes the ones its
  // columns touch), the same result.
  for (const auto& [i, x0, w] : {std::tuple{0, 0, 100}, std::tuple{1, 100, 120}, std::tuple{2, 220, 80}}) {
    Image strip(w, 80, 3);
    for (int c = 0; c < 3; ++c)
      for (int y = 0; y < 80; ++y)
        for (int x = 0; x < w; ++x) strip.at(c, x, y) = comp.at(c, x0 + x, y);
    write_image(path("comp_" + std::to_string(i) + ".tif"), strip, {});
  }
  const std::string from_strips = std::string(GDP_CLI_PATH) + " stitch -c " + path("comp_{rank}.tif") + " -l " +
                                  path("labels.png") + " --depth float --bands 1 -q -o " + path("strips.tif");
  ASSERT_EQ(mpi("-np 2 " + from_strips).code, 0);
  EXPECT_EQ(test::max_difference(result("strips.tif"), whole), 0.0);

  // One rank's scratch directory missing: every rank stops, naming it.
  std::filesystem::remove(path("tmp_1"));
  const test::CliRun bad = mpi("-np 2 " + stitch + "--bands 1 -q -o " + path("x.tif") + " --temp " + path("tmp_{rank}"));
  EXPECT_NE(bad.code, 0);
  EXPECT_FALSE(test::timed_out(bad)) << "a rank hung: " << bad.err;
  EXPECT_NE(bad.err.find("tmp_1"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(path("x.tif")));
}

// Each rank computes labels, kept edges and output fixups for its own columns only: label
// stripes (black among them) whose seams cross the rank boundary, unknown (white) blobs and blank
// (NaN) composite samples on both sides of it give the bits of two bands on threads, blanks and
// blacked-out pixels where they were.
TEST_F(MpiBands, StitchSeamsAcrossTheRankBoundaryGiveTheThreadResult) {
  constexpr int w = 300, h = 80;
  const Image wave = test::cosine_image(w, h, 3, 2);
  Image comp(w, h, 3), labels(w, h, 1);
  const auto unknown = [](int x, int y) { return (x - 150) * (x - 150) + (y - 40) * (y - 40) < 64 || (x > 60 && x < 66); };
  const auto blank = [](int x, int y) { return y % 9 == 4 && x % 37 == 11; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int region = (x + y / 2) / 23 % 5;  // region 0 is black
      labels.at(0, x, y) = unknown(x, y) ? 1.0f : static_cast<float>(region) / 8.0f;
      for (int c = 0; c < 3; ++c)
        comp.at(c, x, y) = blank(x, y) && c == 1 ? std::nanf("")
                                                 : 0.4f + 0.2f * wave.at(0, x, y) + 0.05f * static_cast<float>(region * (c + 1));
    }
  write_image(path("comp.tif"), comp, {});
  write_image(path("labels.png"), labels, {});
  const std::string stitch = std::string(GDP_CLI_PATH) + " stitch -c " + path("comp.tif") + " -l " +
                             path("labels.png") + " --depth float -q ";
  for (const std::string mode : {"--unknown black", "--unknown extend --deramp"}) {
    SCOPED_TRACE(mode);
    const test::CliRun r = mpi("-np 2 " + stitch + mode + " -o " + path("mpi.tif"));
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_EQ(gdp_raw(stitch + mode + " --bands 2 -o " + path("threads.tif")).code, 0);
    const Image m = result("mpi.tif");
    EXPECT_TRUE(test::same_bits(m, result("threads.tif")));
    int blanks = 0, unknowns = 0, black = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        blanks += blank(x, y) && std::isnan(m.at(1, x, y)) && !std::isnan(m.at(0, x, y));
        unknowns += unknown(x, y);
        black += unknown(x, y) && m.at(0, x, y) == 0.0f && m.at(2, x, y) == 0.0f;
      }
    EXPECT_EQ(blanks, 9 * 8) << "blank samples (channel 1) come out blank, and only those channels";
    if (mode == "--unknown black") {
      EXPECT_EQ(black, unknowns) << "unknown pixels come out black";
    }
  }
}

// Seamless cloning (pinned pixels outside the mask, V-cycles to a tolerance) on ranks.
TEST_F(MpiBands, CloneOnRanksGivesTheThreadResult) {
  Image mask(120, 60, 1);
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 120; ++x) mask.at(0, x, y) = (x - 60) * (x - 60) + 4 * (y - 30) * (y - 30) < 50 * 50 ? 1.0f : 0.0f;
  write_image(path("source.tif"), test::random_image(120, 60, 1, 3), {});
  write_image(path("mask.png"), mask, {});
  const std::string clone = std::string(GDP_CLI_PATH) + " clone -t " + path("in.tif") + " -s " + path("source.tif") +
                            " -m " + path("mask.png") + " --offset 150,20 --depth float -q ";
  const test::CliRun r = mpi("-np 2 " + clone + "--bands 1 -o " + path("mpi.tif"));
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(gdp_raw(clone + "--bands 2 -o " + path("threads.tif")).code, 0);
  EXPECT_EQ(test::max_difference(result("mpi.tif"), result("threads.tif")), 0.0);
}

// A spherical (PQ) image: the rows by the poles read rows across the fold, at columns of other
// ranks' bands; ranks give the thread result and agree with one band.
TEST_F(MpiBands, SphereOnRanksGivesTheThreadResult) {
  Image pq = test::cosine_image(320, 80, 2, 4);
  const Image noise = test::random_image(320, 80, 2, 6);
  for (std::size_t i = 0; i < pq.data.size(); ++i) pq.data[i] = 0.5f + 0.3f * pq.data[i] + 0.05f * noise.data[i];
  write_image(path("pq.tif"), pq, {});
  const std::string sharpen = std::string(GDP_CLI_PATH) + " sharpen " + path("pq.tif") +
                              " --domain spherical --beta 2 --depth float -q ";
  ASSERT_EQ(gdp_raw(sharpen + "--bands 1 -o " + path("one.tif")).code, 0);
  const Image one = result("one.tif");
  for (int ranks : {2, 3}) {
    SCOPED_TRACE(std::to_string(ranks) + " ranks");
    const test::CliRun r = mpi("-np " + std::to_string(ranks) + " " + sharpen + "--bands 1 -o " + path("mpi.tif"));
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_EQ(gdp_raw(sharpen + "--bands " + std::to_string(ranks) + " -o " + path("threads.tif")).code, 0);
    EXPECT_EQ(test::max_difference(result("mpi.tif"), result("threads.tif")), 0.0);
    // One band is plain streaming (whole rows, forward); 3 bands on this 320-wide sphere differ
    // from it by 1.02e-4 of the range (the band orderings among themselves: within 1e-4).
    EXPECT_LE(test::max_difference(result("mpi.tif"), one), 1.5e-4 * range(one));
  }
}

// A cylindrical image: the bands at both ends of the rows are neighbours across the wrap, on
// other ranks; ranks give the thread result.
TEST_F(MpiBands, CylinderOnRanksGivesTheThreadResult) {
  const test::CliRun r = sharpen("mpi.tif", 1, 2, "--domain cylindrical");
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(sharpen("threads.tif", 2, 0, "--domain cylindrical").code, 0);
  EXPECT_EQ(test::max_difference(result("mpi.tif"), result("threads.tif")), 0.0);
}

// 4 ranks whose bands grow too narrow for the coarser levels: they merge in pairs across ranks
// (4 -> 2 -> 1 bands on levels 0-1, 2, 3) down to a small in-core level, with the bits of the
// same bands on threads.
TEST_F(MpiBands, MergedStagesOnRanksGiveTheThreadResult) {
  const std::string small = "--incore-bytes 512 --coarsest 8 --scratch float";  // as above
  const std::string extra = small + " --stats " + path("stats.json");
  const test::CliRun r = sharpen("mpi.tif", 1, 4, extra);
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream f(path("stats.json"));
  const std::string stats((std::istreambuf_iterator<char>(f)), {});
  // 4 bands of 80 columns are 20 wide on level 2 (28 at least): without merging 2 levels streamed.
  EXPECT_NE(stats.find("\"streamed_levels\": 4"), std::string::npos) << stats;
  ASSERT_EQ(sharpen("threads.tif", 4, 0, small).code, 0);
  EXPECT_EQ(test::max_difference(result("mpi.tif"), result("threads.tif")), 0.0);
  ASSERT_EQ(sharpen("one.tif", 1, 0, small).code, 0);
  EXPECT_LE(test::max_difference(result("mpi.tif"), result("one.tif")), 1e-4 * range(result("one.tif")));
}

// A rank bound to one core (Open MPI's default with up to 2 ranks) runs its band and its reading
// and writing threads on that core: rank 0 says so, and how to unbind.
TEST_F(MpiBands, RankBoundToOneCoreIsNoted) {
  if (std::thread::hardware_concurrency() < 2) GTEST_SKIP() << "one core: nothing to unbind";
  const std::string run = std::string(GDP_CLI_PATH) + " sharpen " + path("in.tif") + " -o " + path("o.tif") +
                          " --bands 1";
  const test::CliRun bound = mpi("--bind-to core -np 2 " + run);
  ASSERT_EQ(bound.code, 0) << bound.err;
  EXPECT_NE(bound.err.find("--bind-to none"), std::string::npos) << bound.err;
  const test::CliRun free = mpi("--bind-to none -np 2 " + run);
  ASSERT_EQ(free.code, 0) << free.err;
  EXPECT_EQ(free.err.find("core(s) only"), std::string::npos) << free.err;
}

TEST_F(MpiBands, MissingInputOnOneRankStopsEveryRank) {
  const std::string good = std::string(GDP_CLI_PATH) + " sharpen " + path("in.tif");
  const std::string bad = std::string(GDP_CLI_PATH) + " sharpen " + path("missing.tif");
  const std::string tail = " -o " + path("out.tif") + " --depth float -q --bands 1";
  const test::CliRun r = mpi("-np 1 " + good + tail + " : -np 1 " + bad + tail);
  EXPECT_NE(r.code, 0);
  EXPECT_FALSE(test::timed_out(r)) << "a rank hung: " << r.err;
  EXPECT_NE(r.err.find("missing.tif"), std::string::npos) << r.err;
  EXPECT_EQ(files(), std::set<std::string>{"in.tif"}) << "no output, not even a temporary file";
}

// Rank 0 itself failing (here its output disk full: a file-size limit on rank 0 alone) ends every
// rank, and its temporary output file goes too.
TEST_F(MpiBands, FullOutputDiskOnRankZeroLeavesNoTemporary) {
  // Rows are written while the ranks still solve (more than one band of rows). Not through Open
  // MPI's shared memory (btl vader): rank 0's file-size limit also fails the ftruncate of its
  // segment file in MPI_Init, and Open MPI's error paths after that are what went wrong under
  // load (docs/faults.md, "Rank death"). The limit (1 MiB) holds each scratch store (a memfd, a
  // file to the limit too: 500 x 400 floats and a halo) but not the 1.6 MB output.
  write_image(path("in.tif"), test::random_image(1000, 400, 1, 3), {});
  const std::string run = std::string(GDP_CLI_PATH) + " sharpen " + path("in.tif") + " -o " + path("out.tif") +
                          " --depth float -q --bands 1";
  const test::CliRun r =
      mpi("--mca btl ^vader -np 1 sh -c \"trap '' XFSZ; ulimit -f 1024; exec " + run + "\" : -np 1 " + run);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("out.tif"), std::string::npos) << r.err;
  EXPECT_EQ(files(), std::set<std::string>{"in.tif"}) << "no output, not even a temporary file";
}

// On one node gdp picks Open MPI's shared-memory transport before MPI_Init (gdp::MpiRun), but a
// transport the user names stays: with only the loopback BTL (`self`) two ranks cannot reach each
// other, so MPI_Init fails on every rank and the job ends without an output. Had gdp replaced the
// setting with its own (self,vader), the solve would have run.
TEST_F(MpiBands, AUsersTransportChoiceStays) {
  const std::string run = std::string(GDP_CLI_PATH) + " sharpen " + path("in.tif") + " -o " + path("out.tif") +
                          " --depth float -q";
  const test::CliRun r = mpi("-x OMPI_MCA_btl=self -np 2 " + run);
  EXPECT_FALSE(test::timed_out(r)) << "a rank hung: " << r.err;
  EXPECT_NE(r.code, 0) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path("out.tif")));
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
  EXPECT_FALSE(test::timed_out(r)) << r.err;
  EXPECT_NE(r.err.find("only stitch"), std::string::npos) << r.err;
  const test::CliRun s = mpi("-np 2 " + std::string(GDP_CLI_PATH) + " sharpen " + path("in.tif") + " -o " +
                             path("out.tif") + " --in-core");
  EXPECT_EQ(s.code, 2) << s.err;
  EXPECT_NE(s.err.find("--in-core"), std::string::npos) << s.err;
  // Every rank sees it: said once, by rank 0, without MPI_Abort's banner.
  EXPECT_EQ(s.err.find("--in-core"), s.err.rfind("--in-core")) << s.err;
  EXPECT_EQ(s.err.find("MPI_ABORT"), std::string::npos) << s.err;
}

// Each rank checkpoints its own bands in the shared directory (docs/resume.md): killed on every
// rank after a save, the resumed run gives the bits of the same bands on threads; resuming with
// another rank count is refused, naming the counts.
TEST_F(MpiBands, RanksCheckpointAndResume) {
  ASSERT_EQ(sharpen("threads.tif", 2, 0, "--vcycles 2").code, 0);
  const std::string env = "env GDP_CHECKPOINT_ROWS=16 GDP_CHECKPOINT_KILL_AFTER=";
  const std::string args = std::string(GDP_CLI_PATH) + " sharpen " + path("in.tif") + " -o " + path("mpi.tif") +
                           " --depth float -q --vcycles 2 ";
  for (int n : {2, 5, 7}) {
    SCOPED_TRACE("killed after save " + std::to_string(n));
    const test::CliRun killed =
        gdp_raw(env + std::to_string(n) + " " + kMpirun + " -np 2 " + args + "--checkpoint " + path("cp"));
    ASSERT_NE(killed.code, 0) << killed.err;
    EXPECT_FALSE(fs::exists(path("mpi.tif")));
    std::ifstream manifest(path("cp/manifest.rank1"));  // rank 1's own, saved mid-pass
    const std::string text(std::istreambuf_iterator<char>(manifest), {});
    EXPECT_NE(text.find("V-cycle 1"), std::string::npos) << text;
    if (n == 7) {
      const test::CliRun other = mpi("-np 3 " + args + "--resume " + path("cp"));
      EXPECT_NE(other.code, 0);
      EXPECT_NE(other.err.find("2 bands on 2 ranks"), std::string::npos) << other.err;
    }
    const test::CliRun r = mpi("-np 2 " + args + "--resume " + path("cp"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(test::max_difference(result("mpi.tif"), result("threads.tif")), 0.0);
    EXPECT_FALSE(fs::exists(path("cp"))) << "a successful run removes its checkpoint";
    fs::remove(path("mpi.tif"));
  }
}

// Under mpirun the other ranks send 8- or 16-bit samples when the file stores them: the files of
// two ranks and of two bands on threads are the same bytes, sharpening overshoots clamped alike.
TEST_F(MpiBands, IntegerOutputsGatheredNarrowAreTheSameBytes) {
  const auto bytes = [&](const std::string& name) {
    std::ifstream f(path(name), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  for (const auto& [depth, name] : {std::pair{"8", "out.tif"}, std::pair{"16", "out.png"}}) {
    const std::string args = " sharpen " + path("in.tif") + " --beta 4 -q --depth " + std::string(depth) + " -o ";
    ASSERT_EQ(gdp_raw(std::string(GDP_CLI_PATH) + args + path("threads_" + std::string(name)) + " --bands 2").code, 0);
    const test::CliRun r = mpi("-np 2 " + std::string(GDP_CLI_PATH) + args + path(name));
    ASSERT_EQ(r.code, 0) << r.err;
    const Image out = result(name);
    const auto [lo, hi] = std::minmax_element(out.data.begin(), out.data.end());
    EXPECT_TRUE(*lo == 0.0f && *hi == 1.0f) << "no sample clamped: " << *lo << ".." << *hi;
    EXPECT_TRUE(bytes(name) == bytes("threads_" + std::string(name))) << depth << "-bit " << name;
  }
}

// The floats rank 0 makes of 8- and 16-bit samples store as those integers again; floats pass as they are.
TEST(StoredSamples, IntegersComeBackThroughTheirFloats) {
  for (int levels : {255, 65535}) {
    ASSERT_EQ(mpi::sent_bytes(levels), levels == 255 ? 1u : 2u);
    for (int q = 0; q <= levels; ++q) {
      unsigned char sent[2];
      if (levels == 255) sent[0] = static_cast<unsigned char>(q);
      else *reinterpret_cast<std::uint16_t*>(sent) = static_cast<std::uint16_t>(q);
      float f = -1.0f;
      mpi::unpack(sent, 1, levels, &f);
      unsigned char again[2] = {0, 0};
      mpi::pack(&f, 1, levels, again);
      ASSERT_EQ(std::memcmp(sent, again, mpi::sent_bytes(levels)), 0) << q << " of " << levels;
    }
  }
  const float odd[] = {-0.5f, 1.5f, std::numeric_limits<float>::quiet_NaN(), 0.123456f};
  float back[4];
  unsigned char sent[sizeof(odd)];
  mpi::pack(odd, 4, 0, sent);
  mpi::unpack(sent, 4, 0, back);
  EXPECT_EQ(std::memcmp(odd, back, sizeof(odd)), 0);
}

}  // namespace
}  // namespace gdp
