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

}  // namespace
}  // namespace gdp
