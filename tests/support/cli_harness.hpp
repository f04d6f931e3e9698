#pragma once
// Runs the mlce command line as an analyst would and captures its status, stdout and stderr.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace mlce::testing {

struct CliRun {
  int status = -1;
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A fresh temporary directory per test, removed afterwards.
class CliFixture : public ::testing::Test {
 protected:
  std::filesystem::path dir;
  void SetUp() override {
    dir = std::filesystem::temp_directory_path() /
          ("mlce_cli_" + std::to_string(::getpid()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir);
  }
  void TearDown() override { std::filesystem::remove_all(dir); }

  std::filesystem::path write(const std::string& name, const std::string& content) {
    std::filesystem::path p = dir / name;
    std::ofstream(p, std::ios::binary) << content;
    return p;
  }
  /// `env`: variable assignments put before the command (e.g. "PATH=/nonexistent"); `input`: the
  /// file its standard input reads.
  CliRun run(const std::string& args, const std::string& env = "", const std::string& input = "/dev/null") {
    const std::string cmd = (env.empty() ? "" : "env " + env + " ") + std::string(MLCE_CLI) + " " + args + " >" +
                            (dir / "out").string() + " 2>" +
                            (dir / "err").string() + " <" + input;
    const int rc = std::system(cmd.c_str());
    CliRun r;
    r.status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
    r.out = slurp(dir / "out");
    r.err = slurp(dir / "err");
    return r;
  }
};

/// One line on stderr, containing `what`, exit status `status`, nothing on stdout.
inline void expect_one_line_error(const CliRun& r, const std::string& what, int status = 1) {
  EXPECT_EQ(r.status, status) << r.err;
  EXPECT_NE(r.err.find(what), std::string::npos) << "stderr: " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

}  // namespace mlce::testing
