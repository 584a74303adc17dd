// Interrupted runs leave no tracked file behind.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>

#include "gdp/cleanup.h"

namespace fs = std::filesystem;

namespace gdp {
namespace {

fs::path make_file(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / (name + std::to_string(::getpid()));
  std::ofstream(p) << "partial";
  return p;
}

TEST(Cleanup, RemoveTrackedDeletesOnlyTrackedFiles) {
  const fs::path a = make_file("gdp_cleanup_a"), b = make_file("gdp_cleanup_b");
  const int h = cleanup::track(a.string());
  ASSERT_GE(h, 0);
  cleanup::remove_tracked();
  cleanup::untrack(h);
  EXPECT_FALSE(fs::exists(a));
  EXPECT_TRUE(fs::exists(b));
  fs::remove(b);
}

TEST(Cleanup, UntrackedFilesSurvive) {
  const fs::path a = make_file("gdp_cleanup_c");
  cleanup::untrack(cleanup::track(a.string()));
  cleanup::remove_tracked();
  EXPECT_TRUE(fs::exists(a));
  fs::remove(a);
}

TEST(Cleanup, SignalDeletesTrackedFilesAndKillsTheProcess) {
  const fs::path a = make_file("gdp_cleanup_d");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    cleanup::install_signal_handlers();
    cleanup::track(a.string());
    std::raise(SIGINT);
    ::_exit(0);  // not reached
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(WTERMSIG(status), SIGINT);
  EXPECT_FALSE(fs::exists(a));
  fs::remove(a);
}

}  // namespace
}  // namespace gdp
