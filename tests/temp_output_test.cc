// The hidden temporary output file: gone after every signal gdp can catch, a file-size limit, and
// (left by SIGKILL) on the next run writing the same output; its name fits NAME_MAX.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "cli_fixture.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace gdp {
namespace {

class TempOutput : public test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    write_image(path("big.tif"), test::random_image(800, 800, 3, 2), {});
  }

  // A long stitch of big.tif into out.tif, sent `sig` after 1.5 s; the shell's exit status.
  int interrupted(int sig) const {
    const std::string cmd = std::string(GDP_CLI_PATH) + " sharpen " + path("big.tif") + " -o " + path("out.tif") +
                            " --vcycles 200 --temp " + dir_.string() + " -q & pid=$!; sleep 1.5; kill -" +
                            std::to_string(sig) + " $pid; wait $pid";
    const int status = std::system(("bash -c '" + cmd + "' 2>/dev/null").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  // The PID of a process that has ended.
  static pid_t dead_pid() {
    const pid_t child = ::fork();
    if (child == 0) ::_exit(0);
    ::waitpid(child, nullptr, 0);
    return child;
  }
};

TEST_F(TempOutput, CaughtSignalsLeaveNothing) {
  const std::set<std::string> before = files();
  for (int sig : {SIGTERM, SIGHUP, SIGQUIT}) {
    EXPECT_EQ(interrupted(sig), 128 + sig) << "signal " << sig << ": the run should have been stopped";
    EXPECT_EQ(files(), before) << "signal " << sig << ": no output, temporary or scratch file may remain";
  }
}

TEST_F(TempOutput, FileSizeLimitIsAnOutputErrorLeavingNothing) {
  const std::set<std::string> before = files();
  const std::string cmd = "ulimit -f 200; exec " + std::string(GDP_CLI_PATH) + " convert " + path("big.tif") +
                          " -o " + path("out.tif") + " --compression none";
  const test::CliRun r = gdp_shell(cmd);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(path("out.tif") + ": cannot write: File too large"), std::string::npos) << r.err;
  EXPECT_EQ(files(), before);
}

TEST_F(TempOutput, StaleTemporariesOfEndedRunsAreRemoved) {
  write_image(path("small.png"), test::random_image(8, 8, 1, 2), {});
  const std::string stale = ".out.tmp-" + std::to_string(dead_pid()) + "-0badf00d.png";
  const std::string live = ".out.tmp-" + std::to_string(::getpid()) + "-0badf00d.png";
  const std::string other = ".other.tmp-" + std::to_string(dead_pid()) + "-0badf00d.png";
  for (const std::string& f : {stale, live, other}) std::ofstream(path(f)) << "partial";
  const test::CliRun r = gdp("convert " + path("small.png") + " -o " + path("out.png"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(path(stale))) << "left by a process that has ended";
  EXPECT_TRUE(fs::exists(path(live))) << "a running process's";
  EXPECT_TRUE(fs::exists(path(other))) << "another output's";
}

TEST_F(TempOutput, KilledRunsTemporaryGoesWithTheNextRun) {
  const std::set<std::string> before = files();
  EXPECT_EQ(interrupted(SIGKILL), 128 + SIGKILL);
  EXPECT_NE(files(), before) << "SIGKILL cannot be caught: the temporary stays, until...";
  const test::CliRun r = gdp("convert " + path("big.tif") + " -o " + path("out.tif"));
  ASSERT_EQ(r.code, 0) << r.err;
  std::set<std::string> after = before;
  after.insert("out.tif");
  EXPECT_EQ(files(), after);
}

// 248 bytes (plus the directory) is a legal name: the temporary beside it must fit NAME_MAX too.
TEST_F(TempOutput, LongestOutputNamesWork) {
  write_image(path("small.png"), test::random_image(8, 8, 1, 2), {});
  for (const std::string& name : {std::string(251, 'a') + ".png", std::string(248, 'b') + ".png"}) {
    const test::CliRun r = gdp("convert " + path("small.png") + " -o " + path(name));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::exists(path(name)));
  }
}

}  // namespace
}  // namespace gdp
