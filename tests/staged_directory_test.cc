// Staged output directories (HiPS, TOAST): one left by a SIGKILLed run goes with the next run writing the same output.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <fstream>
#include <set>
#include <string>

#include "cli_fixture.h"
#include "gdp/errors.h"
#include "io/staged_directory.h"

namespace fs = std::filesystem;

namespace gdp {
namespace {

class StagedDirectory : public test::CliFixture {
 protected:
  // Writes `name` in a staged directory "out" in a child process that SIGKILLs itself before the
  // rename, as a kill -9 during gdp sky --hips would; true when it died of that signal.
  bool killed_while_writing(const std::string& name) const {
    const fs::path out = dir_ / "out";
    const pid_t child = ::fork();
    if (child == 0) {
      io::write_staged_directory(out, [&](const fs::path& temp) {
        fs::create_directories(temp / "Norder0");
        std::ofstream(temp / "Norder0" / name) << "partial";
        std::raise(SIGKILL);
      });
      ::_exit(0);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    return WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
  }
};

TEST_F(StagedDirectory, KilledRunsDirectoryGoesWithTheNextRun) {
  ASSERT_TRUE(killed_while_writing("Npix1.fits"));
  const std::set<std::string> left = files();
  ASSERT_EQ(left.size(), 1u);
  const std::string hidden = *left.begin();
  EXPECT_EQ(hidden.rfind(".out.tmp-", 0), 0u) << hidden;
  EXPECT_TRUE(fs::exists(dir_ / hidden / "Norder0" / "Npix1.fits")) << "SIGKILL cannot be caught: the tree stays";

  // A running process's staging directory (this one's: its PID is alive) and another output's stay.
  const std::string live = ".out.tmp-" + std::to_string(::getppid()) + "-0badf00d";
  const std::string other = ".other.tmp-" + hidden.substr(9);
  fs::create_directories(dir_ / live / "Norder0");
  fs::create_directories(dir_ / other);
  io::write_staged_directory(dir_ / "out", [](const fs::path& temp) { std::ofstream(temp / "properties") << "done"; });
  EXPECT_EQ(files(), (std::set<std::string>{"out", live, other})) << "the dead run's " << hidden << " is removed";
  EXPECT_TRUE(fs::exists(dir_ / "out" / "properties"));
}

TEST_F(StagedDirectory, ErrorsRemoveTheDirectory) {
  EXPECT_THROW(io::write_staged_directory(dir_ / "out",
                                          [](const fs::path& temp) {
                                            std::ofstream(temp / "tile") << "partial";
                                            throw OutputError("disk full");
                                          }),
               OutputError);
  EXPECT_TRUE(files().empty());
}

}  // namespace
}  // namespace gdp
