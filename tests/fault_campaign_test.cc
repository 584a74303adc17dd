// The fault campaign on the gdp tool (small images): bad inputs and options, every codec's files cut
// at many offsets, signals at random moments, full disks, a rank killed under mpirun (decoder
// mutations: decoder_mutation_test.cc). Each case: exit status, one line naming the file or option,
// no output or temporary left. Seeded, so every run tries the same cases.
#include <gtest/gtest.h>
#include <sys/wait.h>

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
#include "gdp/image_io.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace gdp {
namespace {

class FaultCampaign : public test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    write_stitch_inputs("in.png", "labels.png", 96, 64, 7, [](int x, int) { return x < 48 ? 0.0f : 0.5f; });
    write_image(path("in.tif"), test::random_image(96, 64, 3, 7), {});
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
      {"sharpen " + in + out + " --iters 2/x", "--iters"},
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
  write_image(path("a.exr"), image, {});
  write_image(path("tiles.exr"), image, WriteOptions{SampleType::Half, 95, true, "zip", 16});
  for (const char* name : {"a.png", "a.jpg", "strips.tif", "tiles.tif", "float.tif", "a.exr", "tiles.exr"}) {
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

// Every byte of each codec's signature set to other values: read (when the
// format still is what it was) or one line naming the file, nothing left. (OpenImageIO's libpng
// printed "libpng error: ..." on stderr besides gdp's line for a PNG signature damaged in byte 7.)
TEST_F(FaultCampaign, DamagedSignatures) {
  const Image image = test::random_image(16, 8, 3, 9);
  for (const char* name : {"s.png", "s.jpg", "s.tif"}) {
    write_image(path(name), image, {});
    std::ifstream f(path(name), std::ios::binary);
    const std::string whole(std::istreambuf_iterator<char>(f), {});
    fs::remove(path(name));
    const std::string bad = path(std::string("bad_") + name);
    for (std::size_t at = 0; at < 8; ++at) {  // (other formats go to OpenImageIO: 0.3 s a run)
      for (int v : {0, 13}) {
        if (static_cast<unsigned char>(whole[at]) == v) continue;
        std::string m = whole;
        m[at] = static_cast<char>(v);
        std::ofstream(bad, std::ios::binary) << m;
        const std::string args = "convert " + bad + " -o " + path("out.tif");
        ++cases_;
        const test::CliRun r = gdp(args);
        if (r.code == 0) {
          fs::remove(path("out.tif"));
          continue;
        }
        SCOPED_TRACE(args + " (byte " + std::to_string(at) + " = " + std::to_string(v) + ")");
        EXPECT_EQ(r.code, 2) << r.err;
        EXPECT_EQ(r.err.rfind("gdp: " + bad + ": ", 0), 0u) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(path("out.tif")));
      }
    }
    fs::remove(bad);
  }
}

// SIGINT, SIGTERM, SIGHUP and SIGQUIT at random moments of a run: it dies of the signal and leaves
// no output, temporary or scratch file. The run must outlast the latest signal (700 ms) on a fast
// machine: 500 V-cycles of 400x300 take about 1.7 s on a 2024 EPYC core (100 took 0.42 s there, and
// a signal after the output's rename found a complete output, as it should).
TEST_F(FaultCampaign, SignalsAtRandomMoments) {
  write_image(path("big.tif"), test::random_image(400, 300, 3, 2), {});
  const std::set<std::string> before = files();
  std::mt19937 random(11);
  for (int i = 0; i < 8; ++i) {
    const int sig = std::vector<int>{SIGINT, SIGTERM, SIGHUP, SIGQUIT}[i % 4];
    const int ms = static_cast<int>(random() % 700);
    const std::string cmd = "set -m; " + std::string(GDP_CLI_PATH) + " sharpen " + path("big.tif") + " -o " +
                            path("out.tif") + " --vcycles 500 --temp " + dir_.string() + " -q & pid=$!; sleep " +
                            std::to_string(ms / 1000.0) + "; kill -" + std::to_string(sig) + " $pid; wait $pid";
    const int status = std::system(("bash -c '" + cmd + "' 2>/dev/null").c_str());
    SCOPED_TRACE("signal " + std::to_string(sig) + " after " + std::to_string(ms) + " ms");
    ++cases_;
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    EXPECT_EQ(files(), before) << "no output, temporary or scratch file may remain";
  }
}

// A full disk (a file-size limit) for the output and for the scratch files (--memory 0: every
// store a file), at several sizes.
TEST_F(FaultCampaign, FullDisks) {
  write_image(path("big.tif"), test::random_image(1200, 700, 3, 2), WriteOptions{SampleType::UInt8, 95, false, "none", 256});
  const std::set<std::string> before = files();
  for (int kb : {1, 8, 64, 512}) {
    for (const std::string& run : {"convert " + path("big.tif") + " -o " + path("out.tif"),
                                   "sharpen " + path("big.tif") + " -o " + path("out.png") + " --memory 0 --temp " + dir_.string(),
                                   "stitch -c " + path("big.tif") + " -l " + path("big.tif") + " -o " + path("out.jpg") +
                                       " --memory 0 --temp " + dir_.string() + " --unknown label"}) {
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

// SIGKILL to one rank of `mpirun -np 2 gdp sharpen` at seeded random moments of its solve: the job
// ends (no hang: mpirun runs under `timeout`) with a non-zero status and Open MPI's line naming the
// rank and the signal, and leaves no output, temporary or scratch file. For rank 0, which writes
// the output, the next run writing it also succeeds and leaves nothing (a temporary a SIGKILL
// leaves while it writes goes with that run: TempOutput.KilledRunsTemporaryGoesWithTheNextRun).
// The clock starts once the victim has its signal handlers (SIGHUP and SIGQUIT in /proc's SigCgt),
// which gdp installs after the ranks' agreement, so after every rank's MPI_Init: a SIGKILL inside
// MPI_Init's connection to mpirun hangs Open MPI 4.1's mpirun itself (docs/faults.md, "Rank death").
TEST_F(FaultCampaign, RankDeathUnderMpirun) {
  if (!test::mpirun_works()) GTEST_SKIP() << "mpirun cannot start 2 processes here: rank death not tried";
  write_image(path("big.tif"), test::random_image(400, 300, 3, 2), {});
  const fs::path ctl = fs::temp_directory_path() / ("gdp_rank_death_" + std::to_string(::getpid()));
  fs::create_directories(ctl);
  const std::string run = std::string(GDP_CLI_PATH) + " sharpen " + path("big.tif") + " -o " + path("out.tif") +
                          " --bands 1 --vcycles 400 -q --temp " + dir_.string();
  const std::string pid_file = (ctl / "rank.pid").string();
  // The victim rank says its PID, then becomes gdp (exec keeps the PID).
  std::ofstream(ctl / "victim.sh") << "echo $$ > " << pid_file << "\nexec " << run << "\n";
  const std::set<std::string> before = files();
  std::mt19937 random(23);
  for (int i = 0; i < 4; ++i) {
    const int rank = i == 3 ? 0 : 1;
    const double seconds = 0.2 + (random() % 600) / 1000.0;
    const std::string victim = "-np 1 sh " + (ctl / "victim.sh").string(), other = "-np 1 " + run;
    std::ofstream(ctl / "kill.sh")
        << "rm -f " << pid_file << "\n"
        << test::kMpirun << " " << (rank == 0 ? victim + " : " + other : other + " : " + victim) << " & job=$!\n"
        << "for i in $(seq 6000); do [ -s " << pid_file << " ] && break; sleep 0.01; done\n"
        << "pid=$(cat " << pid_file << ")\n"
        << "for i in $(seq 6000); do c=0; while read -r k v; do case $k in SigCgt:) c=$v;; esac; done 2>/dev/null"
        << " < /proc/$pid/status || break; [ $((0x$c & 5)) = 5 ] && break; sleep 0.01; done\n"
        << "sleep " << seconds << "; kill -KILL $pid\nwait $job\n";
    SCOPED_TRACE("rank " + std::to_string(rank) + " killed " + std::to_string(seconds) + " s after its handlers were in place");
    ++cases_;
    const test::CliRun r = run_capturing_stderr("bash " + (ctl / "kill.sh").string());
    EXPECT_NE(r.code, 0) << r.err;
    EXPECT_FALSE(test::timed_out(r)) << "the job hung after a rank died\n" << r.err;
    EXPECT_NE(r.err.find("rank " + std::to_string(rank)), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("signal 9"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("out.tif")));
    if (rank == 0) {  // the next run writing out.tif
      write_image(path("small.tif"), test::random_image(16, 16, 1, 3), {});
      const test::CliRun next = gdp("convert " + path("small.tif") + " -o " + path("out.tif"));
      EXPECT_EQ(next.code, 0) << next.err;
      fs::remove(path("out.tif"));
      fs::remove(path("small.tif"));
    }
    EXPECT_EQ(files(), before) << "no output, temporary or scratch file may remain";
  }
  fs::remove_all(ctl);
}

}  // namespace
}  // namespace gdp
