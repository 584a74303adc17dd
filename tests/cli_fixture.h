// A scratch directory per test and runs of the gdp tool in it: exit code, stderr, files left behind.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "gdp/image_io.h"
#include "test_util.h"

namespace gdp::test {

// mpirun as the tests start it; `timeout` turns a hang into a failure (timed_out below). The KILL
// 30 s after the TERM: an mpirun stuck in its own PMIx finalize never handles a TERM (docs/faults.md,
// "Rank death"), and without it the test would wait for ctest's limit and leave mpirun behind.
inline const std::string kMpirun = "timeout -v -k 30 60 mpirun --oversubscribe --allow-run-as-root";

// True when mpirun can start 2 processes here (MPI tests skip otherwise).
inline bool mpirun_works() {
  static const bool works = std::system((kMpirun + " -np 2 true > /dev/null 2>&1").c_str()) == 0;
  return works;
}

struct CliRun {
  int code = -1;
  std::string err;
};

// Whether kMpirun's `timeout` had to end the job: status 124 after a TERM, 137 after the KILL
// (also what mpirun returns for a rank killed by signal 9), so `-v`'s line is what tells.
inline bool timed_out(const CliRun& r) {
  return r.code == 124 || r.err.find("timeout: sending signal") != std::string::npos;
}

class CliFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("gdp_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name() + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // gdp stitch's inputs in the scratch directory: a random w x h RGB composite `comp` (from
  // `seed`) and its label map `labels`, label(x, y) in each of its `label_channels` channels.
  template <class Label>
  void write_stitch_inputs(const std::string& comp, const std::string& labels, int w, int h, unsigned seed,
                           Label label, int label_channels = 1) const {
    Image map(w, h, label_channels);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < label_channels; ++c) map.at(c, x, y) = label(x, y);
    write_image(path(comp), random_image(w, h, 3, seed), {});
    write_image(path(labels), map, {});
  }

  // Runs gdp with the arguments, capturing stderr.
  CliRun gdp(const std::string& args) const { return run_capturing_stderr(std::string(GDP_CLI_PATH) + " " + args); }

  // Runs a bash command line (ulimit and the like before gdp), capturing stderr.
  CliRun gdp_shell(const std::string& command) const { return run_capturing_stderr("bash -c '" + command + "'"); }

  // Runs a shell command line with stdout discarded; its exit code and stderr.
  CliRun run_capturing_stderr(const std::string& command) const {
    const std::string err_file = path("stderr.txt");
    CliRun r;
    const int status = std::system((command + " 2> " + err_file + " > /dev/null").c_str());
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream f(err_file);
    r.err.assign(std::istreambuf_iterator<char>(f), {});
    return r;
  }

  // The files in the scratch directory (but stderr.txt).
  std::set<std::string> files() const {
    std::set<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(dir_)) out.insert(e.path().filename().string());
    out.erase("stderr.txt");
    return out;
  }

  // A failing run: exit code 2, one line on stderr mentioning `mention`, no new file.
  void expect_failure(const std::string& args, const std::string& mention) {
    const std::set<std::string> before = files();
    const CliRun r = gdp(args);
    std::vector<std::string> leftovers;
    for (const std::string& f : files())
      if (!before.count(f)) leftovers.push_back(f);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(mention), std::string::npos) << "stderr should mention '" << mention << "': " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1 + (r.err.find("--help") != std::string::npos))
        << "one-line message: " << r.err;
    EXPECT_TRUE(leftovers.empty()) << "left behind: " << leftovers.front();
  }

  std::filesystem::path dir_;
};

}  // namespace gdp::test
