// --checkpoint and --resume: checkpointed runs, runs killed at every unit of work and resumed, and refusals.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_fixture.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace gdp {
namespace {

using test::CliRun;

// A 96x80 composite of three labels (two streamed levels with --incore-bytes 4000), float output.
class Resume : public test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    write_stitch_inputs("comp.tif", "labels.tif", 96, 80, 11,
                        [](int x, int y) { return x < 30 ? 0.0f : y < 40 ? 0.25f : 0.5f; });
  }
  std::string stitch(const std::string& out, const std::string& more) const {
    return "stitch -c " + path("comp.tif") + " -l " + path("labels.tif") + " -o " + path(out) +
           " --depth float --incore-bytes 4000 --coarsest 8 -q " + more;
  }
  // `gdp ARGS` with environment settings before it (the test hooks).
  CliRun gdp_env(const std::string& env, const std::string& args) const {
    return run_capturing_stderr(env + " " + GDP_CLI_PATH + " " + args);
  }
  // Bitwise equality of two float images.
  static void expect_same_bits(const std::string& a, const std::string& b) {
    const Image x = read_image(a).image, y = read_image(b).image;
    ASSERT_EQ(x.data.size(), y.data.size());
    EXPECT_EQ(std::memcmp(x.data.data(), y.data.data(), x.data.size() * sizeof(float)), 0) << a << " vs " << b;
  }
  // Kills a checkpointed run after its n-th save (false: it finished before), then resumes it.
  bool kill_and_resume(int n, const std::string& options) {
    const std::string env = "GDP_CHECKPOINT_ROWS=8 GDP_CHECKPOINT_KILL_AFTER=" + std::to_string(n);
    const CliRun killed = gdp_env(env, stitch("r.tif", "--checkpoint " + path("cp") + " " + options));
    if (killed.code == 0) {  // finished: no save left to kill at
      fs::remove(path("r.tif"));
      return false;
    }
    EXPECT_EQ(killed.code, 128 + 9) << "save " << n << ": " << killed.err;
    EXPECT_FALSE(fs::exists(path("r.tif")));
    const CliRun resumed = gdp(stitch("r.tif", "--resume " + path("cp") + " " + options));
    EXPECT_EQ(resumed.code, 0) << "save " << n << ": " << resumed.err;
    expect_same_bits(path("plain.tif"), path("r.tif"));
    EXPECT_FALSE(fs::exists(path("cp"))) << "a successful run removes its checkpoint";
    fs::remove(path("r.tif"));
    return true;
  }
};

TEST_F(Resume, CheckpointedRunEqualsPlainAndInCoreRuns) {
  for (const std::string options : {"--threads 1", "--threads 5 --vcycles 3"}) {
    ASSERT_EQ(gdp(stitch("plain.tif", options)).code, 0);
    ASSERT_EQ(gdp(stitch("incore.tif", options + " --in-core")).code, 0);
    const CliRun r = gdp(stitch("cp.tif", options + " --checkpoint " + path("cp")));
    ASSERT_EQ(r.code, 0) << r.err;
    expect_same_bits(path("plain.tif"), path("cp.tif"));
    expect_same_bits(path("plain.tif"), path("incore.tif"));
    EXPECT_FALSE(fs::exists(path("cp"))) << options;
  }
}

TEST_F(Resume, KilledAtEveryUnitThenResumedGivesTheSameBits) {
  // One lane: a kill after every save, i.e. in every unit (9 blocks of 8 rows of the first pass,
  // a tail per cycle, a cycle) and then in the output pass.
  const std::string one = "--threads 1 --vcycles 2";
  ASSERT_EQ(gdp(stitch("plain.tif", one)).code, 0);
  int killed = 0;
  for (int n = 1; n < 100 && kill_and_resume(n, one); ++n) ++killed;
  EXPECT_EQ(killed, 12);
  // Three lanes save independently, so a kill catches them at different units.
  const std::string three = "--threads 5 --vcycles 2";
  ASSERT_EQ(gdp(stitch("plain.tif", three)).code, 0);
  for (int n : {2, 9, 16, 23, 30, 35}) EXPECT_TRUE(kill_and_resume(n, three)) << n;
}

TEST_F(Resume, ResumedRunsCanBeKilledAndResumedAgain) {
  const std::string options = "--threads 5 --tolerance 1e-4";
  ASSERT_EQ(gdp(stitch("plain.tif", options)).code, 0);
  const std::string env = "GDP_CHECKPOINT_ROWS=8 GDP_CHECKPOINT_KILL_AFTER=4";
  ASSERT_EQ(gdp_env(env, stitch("r.tif", "--checkpoint " + path("cp") + " " + options)).code, 137);
  int kills = 1;
  for (; kills < 100; ++kills) {
    const CliRun r = gdp_env(env, stitch("r.tif", "--resume " + path("cp") + " " + options));
    if (r.code == 0) break;
    ASSERT_EQ(r.code, 137) << r.err;
  }
  EXPECT_GT(kills, 3);
  expect_same_bits(path("plain.tif"), path("r.tif"));
}

TEST_F(Resume, RefusesChangedInputsAndOptions) {
  const std::string env = "GDP_CHECKPOINT_ROWS=8 GDP_CHECKPOINT_KILL_AFTER=3";
  ASSERT_EQ(gdp_env(env, stitch("r.tif", "--checkpoint " + path("cp"))).code, 137);
  expect_failure(stitch("r.tif", "--resume " + path("cp") + " --iters 4"), "--iters");
  expect_failure(stitch("r.tif", "--resume " + path("cp") + " --deramp"), "--deramp");
  expect_failure(stitch("other.tif", "--resume " + path("cp")), "--output");
  write_image(path("comp.tif"), test::random_image(96, 80, 3, 12), {});
  expect_failure(stitch("r.tif", "--resume " + path("cp")), "comp.tif changed");
}

TEST_F(Resume, EmptyMissingOrCorruptDirectoriesAreRefused) {
  fs::create_directories(path("empty"));
  expect_failure(stitch("r.tif", "--resume " + path("empty")), "no checkpoint");
  expect_failure(stitch("r.tif", "--resume " + path("missing")), "no such directory");
  const std::string env = "GDP_CHECKPOINT_ROWS=8 GDP_CHECKPOINT_KILL_AFTER=3";
  ASSERT_EQ(gdp_env(env, stitch("r.tif", "--checkpoint " + path("cp") + " --threads 1")).code, 137);
  // A state of an older layout version (the first int after the header line; 2: before the rings
  // of 2(G + k) + 10 rows) is refused as such, naming the directory, not as corrupt.
  const auto set_version = [&](int version) {
    std::fstream f(path("cp/lane0.1.state"), std::ios::in | std::ios::out | std::ios::binary);
    std::string head;
    std::getline(f, head);
    f.seekp(static_cast<std::streamoff>(head.size() + 1));
    f.write(reinterpret_cast<const char*>(&version), sizeof version);
  };
  set_version(2);
  expect_failure(stitch("r.tif", "--resume " + path("cp")),
                 "--resume " + path("cp") + ": saved by an older gdp (state version 2, this one reads 3): run again without --resume");
  set_version(1);
  expect_failure(stitch("r.tif", "--resume " + path("cp")), "saved by an older gdp (state version 1");
  set_version(4);
  expect_failure(stitch("r.tif", "--resume " + path("cp")), "saved by another gdp (state version 4");
  set_version(3);
  fs::resize_file(path("cp/lane0.1.state"), 100);  // the third save's (states alternate between two files)
  expect_failure(stitch("r.tif", "--resume " + path("cp")), "lane0.1.state is corrupt");
  std::ofstream(path("cp/manifest")) << "gdp checkpoint 1\nsizes\n";
  expect_failure(stitch("r.tif", "--resume " + path("cp")), "manifest is corrupt");
  std::ofstream(path("cp/manifest")) << "something else\n";
  expect_failure(stitch("r.tif", "--resume " + path("cp")), "not a gdp checkpoint");
}

// Bands checkpoint too: every band saves at the same rows and waits for the others before going on
// (StreamedVCycle::saved), so a kill between two bands' saves resumes from the newest save both
// made, with the same bits. Another band count is refused, naming it.
TEST_F(Resume, BandsKilledAndResumedGiveTheSameBits) {
  const std::string two = "--bands 2 --vcycles 2";
  ASSERT_EQ(gdp(stitch("plain.tif", two)).code, 0);
  int killed = 0;
  for (int n = 1; n < 100 && kill_and_resume(n, two); n += 3) ++killed;
  EXPECT_GE(killed, 6);
  const std::string env = "GDP_CHECKPOINT_ROWS=8 GDP_CHECKPOINT_KILL_AFTER=5";
  ASSERT_EQ(gdp_env(env, stitch("r.tif", "--checkpoint " + path("cp") + " " + two)).code, 137);
  expect_failure(stitch("r.tif", "--resume " + path("cp") + " --bands 3 --vcycles 2"), "--bands");
  expect_failure(stitch("r.tif", "--resume " + path("cp") + " --vcycles 2"), "--bands");
  ASSERT_EQ(gdp(stitch("r.tif", "--resume " + path("cp") + " " + two)).code, 0);
  expect_same_bits(path("plain.tif"), path("r.tif"));
}

TEST_F(Resume, InCoreDoesNotCheckpoint) {
  expect_failure(stitch("r.tif", "--checkpoint " + path("cp") + " --in-core"), "--in-core");
  expect_failure(stitch("r.tif", "--checkpoint " + path("cp") + " --resume " + path("cq")), "one directory");
}

}  // namespace
}  // namespace gdp
